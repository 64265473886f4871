//! Split candidates: every point where `|κ|` can stop being monotonic or κ can change sign.

use kurbo::{ParamCurve, ParamCurveArclen};

use super::curvature::PieceCurvature;
use super::poly::MAX_DEGREE;
use crate::geom::ParamBez;

/// Relative accuracy of the arc lengths carried by the nodes. They only feed the geometric
/// significance test (a bump's effect on the curve, compared with the tolerance), for which a
/// part in a million is far finer than needed.
const ARCLEN_RELATIVE_ACCURACY: f64 = 1e-12;

/// Arc length of `piece` from local parameter 0 to `t`.
fn arclen_to(piece: &ParamBez, t: f64) -> f64 {
    let sub = piece.bez.subsegment(0.0..t);
    let scale = (sub.p3 - sub.p0).hypot() + (sub.p1 - sub.p0).hypot() + (sub.p2 - sub.p1).hypot();
    sub.arclen(ARCLEN_RELATIVE_ACCURACY * scale.max(f64::MIN_POSITIVE))
}

/// A split candidate (and, after simplification, a split point).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Node {
    /// Global parameter.
    pub u: f64,
    /// Index of the piece the node is evaluated on.
    pub piece: usize,
    /// Local parameter on that piece (`0` only for the curve's start; a joint is `t = 1` of the
    /// earlier piece).
    pub t: f64,
    /// Signed curvature there.
    pub kappa: f64,
    /// Arc length from the chain's start.
    pub s: f64,
}

impl Node {
    /// `|κ|`.
    pub(crate) fn magnitude(&self) -> f64 {
        self.kappa.abs()
    }
}

/// The candidates of the whole chain, in increasing `u`: the start, every sign-changing root of
/// `γ` (inflections) and of `h` (curvature extrema) strictly inside each piece, every joint, and
/// the end.
///
/// Between two consecutive candidates κ has one sign and `|κ|` is monotonic (no root of `γ` or `h`
/// lies between them), so whether a candidate is an extremum of `|κ|` is decided by comparing its
/// `|κ|` with its neighbours'. In particular a joint is a curvature extremum exactly when
/// `d|κ|/du` changes sign across it, even though a C2 spline's `dκ/du` may jump there, and no
/// derivative at the joint is needed.
///
/// Roots within `u_tolerance` of a joint (or of the ends) are merged into it, and roots within
/// `u_tolerance` of the previous candidate into that one, so a root found at `t ≈ 1` of one piece
/// and `t ≈ 0` of the next yields one split. At a joint κ is the mean of the two one-sided values
/// (equal up to rounding for a C2 spline).
pub(crate) fn candidates(
    pieces: &[ParamBez],
    curvatures: &[PieceCurvature],
    u_tolerance: f64,
) -> Vec<Node> {
    let mut nodes = Vec::with_capacity(pieces.len() * (MAX_DEGREE + 2) + 1);
    let mut s0 = 0.0;
    for (i, (piece, curvature)) in pieces.iter().zip(curvatures).enumerate() {
        if i == 0 {
            nodes.push(Node {
                u: piece.u0,
                piece: 0,
                t: 0.0,
                kappa: curvature.kappa(0.0),
                s: 0.0,
            });
        }
        let du = piece.u1 - piece.u0;
        let inflections = curvature.inflections();
        let extrema = curvature.extrema();
        let (mut a, mut b) = (
            inflections.crossings().peekable(),
            extrema.crossings().peekable(),
        );
        // Merge the two ascending lists.
        loop {
            // (t, whether it is a root of γ: an inflection, where κ is exactly 0)
            let next = match (a.peek(), b.peek()) {
                (Some(&x), Some(&y)) if x <= y => a.next().map(|t| (t, true)),
                (Some(_), Some(_)) => b.next().map(|t| (t, false)),
                (Some(_), None) => a.next().map(|t| (t, true)),
                (None, Some(_)) => b.next().map(|t| (t, false)),
                (None, None) => None,
            };
            let Some((t, inflection)) = next else { break };
            let near_start = t * du <= u_tolerance;
            let near_end = (1.0 - t) * du <= u_tolerance;
            let u = piece.global(t);
            let near_previous = nodes.last().is_some_and(|n: &Node| u - n.u <= u_tolerance);
            if !(near_start || near_end || near_previous) {
                nodes.push(Node {
                    u,
                    piece: i,
                    t,
                    // At a root of γ the curvature is 0 by definition; evaluating it would
                    // give ±1e-20 of rounding, whose sign and size must not decide anything.
                    kappa: if inflection { 0.0 } else { curvature.kappa(t) },
                    s: s0 + arclen_to(piece, t),
                });
            }
        }
        let kappa = match curvatures.get(i + 1) {
            Some(next) => 0.5 * (curvature.kappa(1.0) + next.kappa(0.0)),
            None => curvature.kappa(1.0),
        };
        s0 += arclen_to(piece, 1.0);
        nodes.push(Node {
            u: piece.u1,
            piece: i,
            t: 1.0,
            kappa,
            s: s0,
        });
    }
    nodes
}
