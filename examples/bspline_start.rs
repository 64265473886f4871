//! Whether a curvature-continuous chain can be had without iterating on the samples' distances:
//! every G2 chain the pipeline makes within the tolerance (fixture strokes up to 600 samples, each
//! at its own tolerance, pieces of two segments or more) is rebuilt at its own joints from what
//! the B-spline, which holds the same samples within the same tolerance, says there, and laid out
//! forward from the chain's start pose, as a fit in the turning angle against arc length would
//! lay it out; then each sample's distance to the nearest point of the rebuilt chain is measured,
//! in tolerances.
//!
//! Rebuilt segment by segment, each the log-aesthetic segment with the given end curvatures and
//! length whose turning is the B-spline's between the joints' foot points (α by bisection over the
//! range the segment allows; the nearest end of it where no α turns that far):
//!
//! 1. the B-spline's curvature at the joints and its arc length between them;
//! 2. the chain's own curvatures, the B-spline's arc length;
//! 3. the chain's own curvatures and lengths: only the turning is the B-spline's.
//!
//! `cargo run --release --example bspline_start` (docs/performance.md, "What the targets would
//! take").

#[path = "../tests/common/mod.rs"]
mod common;

use common::{fixture, fixture_names};
use kansei::bspline::project::Pieces;
use kansei::chain::smooth::ZERO_END_ALPHA;
use kansei::geom::{Point, distance_to_segment, wrap_angle};
use kansei::lac::deviation::trace;
use kansei::lac::segment::LacSegment;
use kansei::pipeline::{PipelineOptions, fit_stroke};

/// Midpoint-rule panels for the B-spline's arc length between two joints (its speed is smooth
/// on a span between splits: far below a tolerance's worth of length).
const ARC_PANELS: usize = 64;

/// Bisection steps on α (to 6/2⁶⁰ of the range: rounding).
const ALPHA_STEPS: usize = 60;

/// The α range the pipeline searches by default (`--alpha-range -3:3`).
const ALPHA_RANGE: (f64, f64) = (-3.0, 3.0);

/// A curvature a hair off zero on the chain's side, where the B-spline turns the other way at a
/// joint the chain does not hold at κ = 0 (a segment cannot change sign): far below any drawn
/// curvature, far above underflow in ρ^α.
const HAIR: f64 = 1e-150;

/// Chord error of the traced chains, in tolerances: far below what is measured.
const TRACE_CHORD: f64 = 1e-3;

/// Signed curvature and tangent angle of the B-spline at parameter `u`.
fn kappa_theta(pieces: &Pieces, u: f64) -> (f64, f64) {
    let (_, d1, d2) = pieces.eval_derivs(u);
    (d1.cross(d2) / d1.hypot().powi(3), d1.y.atan2(d1.x))
}

fn arc_length(pieces: &Pieces, u0: f64, u1: f64) -> f64 {
    let h = (u1 - u0) / ARC_PANELS as f64;
    (0..ARC_PANELS)
        .map(|i| pieces.eval_derivs(u0 + h * (i as f64 + 0.5)).1.hypot() * h)
        .sum()
}

/// The segment from `(start, theta0)` with end curvatures `k0`, `k1` and length `length` whose
/// turning is nearest `turn`.
fn turning_to(
    start: Point,
    theta0: f64,
    length: f64,
    (k0, k1): (f64, f64),
    turn: f64,
) -> Option<LacSegment> {
    if k0 == k1 {
        return LacSegment::new(start, theta0, length, None, k0, k1).ok();
    }
    let top = if k0 == 0.0 || k1 == 0.0 {
        ZERO_END_ALPHA
    } else {
        ALPHA_RANGE.1
    };
    let miss = |a: f64| {
        LacSegment::new(start, theta0, length, Some(a), k0, k1)
            .ok()
            .map(|s| s.theta1() - theta0 - turn)
    };
    let (mut lo, mut hi) = (ALPHA_RANGE.0, top);
    let (at_lo, at_hi) = (miss(lo)?, miss(hi)?);
    let alpha = if at_lo.signum() != at_hi.signum() {
        for _ in 0..ALPHA_STEPS {
            let mid = 0.5 * (lo + hi);
            if miss(mid)?.signum() == at_lo.signum() {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    } else if at_lo.abs() < at_hi.abs() {
        lo
    } else {
        hi
    };
    LacSegment::new(start, theta0, length, Some(alpha), k0, k1).ok()
}

/// Largest distance from a sample to the nearest point of the chain, in tolerances.
fn worst(points: &[Point], chain: &[LacSegment], tolerance: f64) -> f64 {
    let polyline: Vec<Point> = chain
        .iter()
        .flat_map(|s| {
            trace(s, TRACE_CHORD * tolerance)
                .into_iter()
                .map(|(_, p)| p)
        })
        .collect();
    points
        .iter()
        .map(|q| {
            polyline
                .windows(2)
                .map(|w| distance_to_segment(*q, w[0], w[1]))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
        / tolerance
}

fn main() {
    // Per piece: the chain's own worst distance, then each rebuild's (NaN: not buildable).
    let mut rows: Vec<[f64; 4]> = Vec::new();
    for name in fixture_names() {
        let file = fixture(&name);
        for (i, stroke) in file.strokes.iter().enumerate() {
            if stroke.samples.len() > 600 {
                continue;
            }
            let options = PipelineOptions::default();
            let tolerance = options.stroke_tolerance(stroke, file.units).tolerance;
            let options = options.with_tolerance(tolerance);
            let Ok(curves) = fit_stroke(stroke, i, tolerance, &options) else {
                continue;
            };
            for curve in curves {
                let Some(chain) = curve.chain.as_ref().filter(|c| c.segments.len() > 1) else {
                    continue;
                };
                let pieces = Pieces::new(curve.bspline.curve.to_beziers());
                let own: Vec<LacSegment> = chain.segments.iter().map(|s| s.segment).collect();
                let mut row = [f64::NAN; 4];
                row[0] = worst(&curve.points, &own, tolerance);
                for (variant, slot) in row.iter_mut().enumerate().skip(1) {
                    let (mut start, mut theta0) = (own[0].start(), own[0].theta0());
                    let mut rebuilt = Vec::new();
                    for part in &chain.segments {
                        let s = &part.segment;
                        let Some((ua, ub)) = part.params else { break };
                        let a = pieces.project_local(s.start(), ua).u;
                        let b = pieces.project_local(s.end(), ub).u;
                        let ((ka, ta), (kb, tb)) =
                            (kappa_theta(&pieces, a), kappa_theta(&pieces, b));
                        // The B-spline's curvature where the chain's is on the same side (zero
                        // where the chain holds an inflection, a hair off zero where the
                        // B-spline turns the other way there).
                        let side = |k: f64, own: f64| {
                            if own == 0.0 {
                                0.0
                            } else if k.signum() != own.signum() {
                                own.signum() * HAIR
                            } else {
                                k
                            }
                        };
                        let ends = if variant == 1 {
                            (side(ka, s.kappa0()), side(kb, s.kappa1()))
                        } else {
                            (s.kappa0(), s.kappa1())
                        };
                        let length = if variant == 3 {
                            s.length()
                        } else {
                            arc_length(&pieces, a, b)
                        };
                        let Some(next) =
                            turning_to(start, theta0, length, ends, wrap_angle(tb - ta))
                        else {
                            break;
                        };
                        (start, theta0) = (next.end(), next.theta1());
                        rebuilt.push(next);
                    }
                    if rebuilt.len() == own.len() {
                        *slot = worst(&curve.points, &rebuilt, tolerance);
                    }
                }
                rows.push(row);
            }
        }
    }
    println!("largest sample distance to the chain, in tolerances, over pieces of 2+ segments");
    println!("| chain | pieces | median | quarter | within 1 | within 2 | most |");
    println!("|---|---|---|---|---|---|---|");
    for (v, name) in [
        "the pipeline's (fitted on the samples' distances)",
        "1. the B-spline's curvature, length and turning",
        "2. the chain's curvatures, the B-spline's length and turning",
        "3. the chain's curvatures and lengths, the B-spline's turning",
    ]
    .iter()
    .enumerate()
    {
        let mut r: Vec<f64> = rows
            .iter()
            .map(|r| r[v])
            .filter(|x| x.is_finite())
            .collect();
        r.sort_by(f64::total_cmp);
        let Some(&most) = r.last() else { continue };
        println!(
            "| {name} | {} | {:.2} | {:.2} | {} | {} | {:.2} |",
            r.len(),
            r[r.len() / 2],
            r[r.len() / 4],
            r.iter().filter(|&&x| x <= 1.0).count(),
            r.iter().filter(|&&x| x <= 2.0).count(),
            most
        );
    }
}
