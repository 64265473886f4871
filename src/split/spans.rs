//! [`split_spans`]: input checks, candidates, simplification, and assembly of the spans.

use super::candidates::{Node, candidates};
use super::curvature::PieceCurvature;
use super::scale::straight_curvature;
use super::simplify::{Significance, simplify};
use super::{CurvatureSign, Span, Spans, SplitError, SplitKind, SplitOptions, SplitPoint};
use crate::geom::{ParamBez, ParamCurve, Point};

/// Largest distance between the end of one piece and the start of the next, relative to the
/// bounding-box diagonal of all control points. A B-spline's Bézier pieces share their joint
/// points up to the rounding of the knot-insertion arithmetic (~1e-16 relative); 1e-9 is far
/// above that and far below anything visible (0.3 nm on a 300 mm stroke).
const POSITION_GAP_RELATIVE: f64 = 1e-9;

/// Splits a chain of cubic Bézier pieces (the knot spans of a cubic B-spline, in order) at its
/// inflections and curvature extrema into spans with one curvature sign and monotonic `|κ|`.
///
/// Steps: check the input; compute each piece's curvature polynomials; collect the candidates
/// (all inflections, curvature extrema and joints, see the [module docs](super)); drop
/// insignificant extrema as set by `options`; cut the pieces at the surviving points with
/// [`CubicBez::subsegment`](kurbo::ParamCurve::subsegment).
///
/// The input is expected to be C2 (a cubic B-spline with simple knots). With weaker continuity the
/// result is still well formed, but a curvature jump at a joint is only seen through the mean of
/// its one-sided values.
///
/// # Errors
///
/// [`SplitError::InvalidOption`] for options out of range; [`SplitError::Empty`],
/// [`SplitError::NonFinite`], [`SplitError::EmptyParameterRange`], [`SplitError::ParameterGap`],
/// [`SplitError::PositionGap`] for malformed input; [`SplitError::Singular`] for a piece whose
/// speed vanishes.
pub fn split_spans(pieces: &[ParamBez], options: &SplitOptions) -> Result<Spans, SplitError> {
    options.validate()?;
    let u_tolerance = check_pieces(pieces, options)?;
    let curvatures = pieces
        .iter()
        .enumerate()
        .map(|(piece, p)| PieceCurvature::new(&p.bez).ok_or(SplitError::Singular { piece }))
        .collect::<Result<Vec<_>, _>>()?;
    let straight = straight_curvature(pieces, &curvatures, options);
    let mut nodes = candidates(pieces, &curvatures, u_tolerance);
    simplify(
        &mut nodes,
        &Significance {
            relative: options.extremum_relative,
            floor: straight,
            tolerance: options.tolerance,
            free_ends: options.free_ends,
        },
    );
    Ok(assemble(pieces, &nodes, straight))
}

/// Validates the chain; returns the absolute parameter tolerance
/// `joint_tolerance · (u_end − u_start)`.
fn check_pieces(pieces: &[ParamBez], options: &SplitOptions) -> Result<f64, SplitError> {
    let (Some(first), Some(last)) = (pieces.first(), pieces.last()) else {
        return Err(SplitError::Empty);
    };
    let mut min = Point::new(f64::INFINITY, f64::INFINITY);
    let mut max = Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
    for (piece, p) in pieces.iter().enumerate() {
        let points = [p.bez.p0, p.bez.p1, p.bez.p2, p.bez.p3];
        if !(points.iter().all(|q| q.is_finite()) && p.u0.is_finite() && p.u1.is_finite()) {
            return Err(SplitError::NonFinite { piece });
        }
        if p.u1 <= p.u0 {
            return Err(SplitError::EmptyParameterRange {
                piece,
                u0: p.u0,
                u1: p.u1,
            });
        }
        for q in points {
            min = Point::new(min.x.min(q.x), min.y.min(q.y));
            max = Point::new(max.x.max(q.x), max.y.max(q.y));
        }
    }
    let u_tolerance = options.joint_tolerance * (last.u1 - first.u0);
    let position_tolerance = POSITION_GAP_RELATIVE * (max - min).hypot();
    for (i, pair) in pieces.windows(2).enumerate() {
        let (a, b) = (&pair[0], &pair[1]);
        if (b.u0 - a.u1).abs() > u_tolerance {
            return Err(SplitError::ParameterGap {
                piece: i + 1,
                previous_u1: a.u1,
                u0: b.u0,
            });
        }
        let distance = (b.bez.p0 - a.bez.p3).hypot();
        if distance > position_tolerance {
            return Err(SplitError::PositionGap {
                piece: i + 1,
                distance,
            });
        }
    }
    Ok(u_tolerance)
}

/// Sign of a span from its end nodes: `|κ|` is monotonic over the span, so its largest value is at
/// an end; the sign there is the span's, unless even that is below the straight threshold.
fn span_sign(a: &Node, b: &Node, straight: f64) -> CurvatureSign {
    let larger = if a.magnitude() >= b.magnitude() {
        a.kappa
    } else {
        b.kappa
    };
    if larger.abs() <= straight {
        CurvatureSign::Zero
    } else if larger > 0.0 {
        CurvatureSign::Positive
    } else {
        CurvatureSign::Negative
    }
}

/// Builds the split points and spans from the surviving nodes (first and last are the ends).
fn assemble(pieces: &[ParamBez], nodes: &[Node], straight: f64) -> Spans {
    let signs: Vec<CurvatureSign> = nodes
        .windows(2)
        .map(|w| span_sign(&w[0], &w[1], straight))
        .collect();
    let last = nodes.len().saturating_sub(1);
    let splits: Vec<SplitPoint> = nodes
        .iter()
        .enumerate()
        .map(|(i, node)| {
            let kind = if i == 0 {
                SplitKind::Start
            } else if i == last {
                SplitKind::End
            } else {
                match (signs[i - 1], signs[i]) {
                    (CurvatureSign::Positive, CurvatureSign::Negative)
                    | (CurvatureSign::Negative, CurvatureSign::Positive) => SplitKind::Inflection,
                    _ => SplitKind::CurvatureExtremum,
                }
            };
            SplitPoint {
                kind,
                u: node.u,
                point: pieces[node.piece].bez.eval(node.t),
                curvature: node.kappa,
            }
        })
        .collect();
    let spans = nodes
        .windows(2)
        .zip(splits.windows(2))
        .zip(&signs)
        .map(|((n, s), &sign)| Span {
            u0: n[0].u,
            u1: n[1].u,
            pieces: cut(pieces, &n[0], &n[1]),
            sign,
            start: s[0].kind,
            end: s[1].kind,
        })
        .collect();
    Spans {
        splits,
        spans,
        straight_curvature: straight,
    }
}

/// The sub-Béziers of `pieces` between nodes `a` and `b`.
fn cut(pieces: &[ParamBez], a: &Node, b: &Node) -> Vec<ParamBez> {
    // A node at t = 1 of a piece is t = 0 of the next.
    let (first, t_first) = if a.t >= 1.0 && a.piece + 1 < pieces.len() {
        (a.piece + 1, 0.0)
    } else {
        (a.piece, a.t)
    };
    let mut out = Vec::with_capacity(b.piece + 1 - first.min(b.piece + 1));
    for (k, piece) in pieces.iter().enumerate().take(b.piece + 1).skip(first) {
        let t0 = if k == first { t_first } else { 0.0 };
        let t1 = if k == b.piece { b.t } else { 1.0 };
        if t1 <= t0 {
            continue;
        }
        let bez = if t0 == 0.0 && t1 == 1.0 {
            piece.bez
        } else {
            piece.bez.subsegment(t0..t1)
        };
        let u0 = if k == first { a.u } else { piece.u0 };
        let u1 = if k == b.piece { b.u } else { piece.u1 };
        out.push(ParamBez { bez, u0, u1 });
    }
    out
}
