//! The Yoshida–Saito construction: the LAC segment of a given α joining two points with given
//! tangents (G1 Hermite data), after Yoshida & Saito (2006), table 2.2 of the seed notes.
//!
//! ## Normalisation
//! With chord AB at angle ψ, θ_A = ψ − arg t_A and θ_B = arg t_B − ψ (wrapped to (−π, π]) are the
//! angles between chord and tangents; θ_T = θ_A + θ_B is the total turning. Mirror so that θ_T ≥ 0
//! (left turn). A monotone-curvature arc turning one way has both angles positive, and by Vogt's
//! theorem the larger one sits at the high-curvature end, equal ones only for a circular arc:
//!
//! * θ_A = θ_B (within [`SYMMETRIC_TOLERANCE`]): circular arc, or a line when both are 0;
//! * otherwise the standard form starts at the end with the larger angle θ_big.
//!
//! ## Solving for the shape
//! The unknown is q = ln(κ_hi/κ_lo) ∈ (0, ∞), the log curvature ratio; it fixes Λ through the
//! turning, ρ_T^{α−1} = 1 + Λ(α−1)θ_T, i.e. Λ = q·exprel((α−1)q)/θ_T, and the standard-form length
//! s_T = s(θ_T) = θ_T·exprel(αq)/exprel((α−1)q). (For α < 1 this sweeps Λ over (0, Λ_max),
//! Λ_max = 1/((1 − α)θ_T), the bound of table 2.1; for α ≥ 1 over (0, ∞).) The chord angle
//! φ(q) = arg P(s_T) rises from θ_T/2 (q → 0, the circle) towards a limit φ_∞:
//!
//! * α < 0: the chord angle of the curve that ends where κ = 0 (q = ∞, Λ = Λ_max), reached;
//! * 0 ≤ α ≤ 1: θ_T (the curve's length, weighted towards the low-curvature end, grows without
//!   bound), approached only as q → ∞;
//! * α > 1: arg ∫₀^{θ_T} θ^{1/(α−1)} e^{iθ} dθ < θ_T (for large Λ, ds = ρ dθ ∝ θ^{1/(α−1)} dθ),
//!   approached only as q → ∞: the drawable region is bounded here too.
//!
//! φ(q) and dφ/dq come from one quadrature in the log radius of curvature
//! ([`super::log_radius`]), and φ(q) = θ_big is solved by Newton's method safeguarded by a
//! bracket (see `solve_q`), warm-started when the caller knows a nearby solution
//! ([`fit_g1_near`]). θ_big beyond the reachable range is outside the drawable region. Then
//! scale by |AB|/|P(s_T)|, rotate, and undo the mirror; when the high-curvature end is B, the
//! record simply has |κ| increasing along travel.

use super::error::LacError;
use super::log_radius::{integrals, log_radius_integral};
use super::segment::LacSegment;
use super::special::cis;
use super::special::exprel;
use crate::geom::{Point, Vec2};
use std::f64::consts::PI;

/// End angles equal to within this (radians) give a circular arc. Snapping moves each end tangent
/// by at most half of it; 1e-12 rad is far below any pen data and keeps the root finder away from
/// q → 0, where φ(q) − θ_T/2 vanishes and the LAC is a circle anyway.
pub const SYMMETRIC_TOLERANCE: f64 = 1e-12;

/// For α < 0, a target chord angle beyond the κ = 0 edge φ_∞ by at most this (radians) is taken
/// as exactly on the edge (a κ = 0 end). Data printed to 16 digits, or produced by this crate's
/// own evaluation, lands on the edge only to ~1e-15; anything farther out is genuinely outside.
pub const DRAWABLE_EDGE_TOLERANCE: f64 = 1e-12;

/// End points closer than this, relative to the larger coordinate magnitude (or absolutely below
/// 1e-300), coincide: the chord direction is then rounding noise.
pub const COINCIDENT_RELATIVE: f64 = 1e-14;

/// Largest log curvature ratio q the solver will consider: e^{600} ≈ 1e260, so that the far-end
/// curvature e^{−q}/scale stays a normal f64 for any chord up to ~1e40 times ρ at the near end.
/// Data needing more is within ~e^{−q} (for α > 1; α < 0 never gets here) or ~θ_T/q (α = 1,
/// slower still for 0 ≤ α < 1) of the limit φ_∞ that only an infinitely long curve reaches: it is
/// reported as outside the drawable region, since the record could not hold its far-end curvature.
pub const MAX_LOG_CURVATURE_RATIO: f64 = 600.0;

/// Most Newton/bisection steps of the q solve: bisection alone would reach the tolerance on
/// [0, 600] in 53; Newton converges quadratically in a handful.
const MAX_SOLVE_STEPS: usize = 200;

/// A Newton step at most this fraction of the one before shows the iteration in its quadratic
/// regime, where the next error can be predicted from the two steps (see `solve_q`).
const NEWTON_SETTLED_RATIO: f64 = 0.01;

/// Absolute tolerance on q for the root finder. dφ/dq ≤ O(1), so the end-angle error this
/// leaves is ≲ 1e-13 rad, and the curvature ratio is off by ≲ 1e-13 relative.
pub const LOG_RATIO_TOLERANCE: f64 = 1e-13;

/// Angle wrapped to (−π, π].
fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(2.0 * PI);
    if w > PI { w - 2.0 * PI } else { w }
}

/// The standard-form span with total turning θ_T and log curvature ratio q (`None`: the κ = 0
/// edge, α < 0): ρ(0) = 1, start at the origin along +x.
#[derive(Clone, Copy, Debug)]
struct StandardShape {
    /// c = 1/Λ, the phase rate of [`log_radius_integral`] at u = 0.
    inv_lambda: f64,
    /// U = ln ρ at the end (q, or ∞ at the κ = 0 edge).
    upper: f64,
    /// Arc length s_T.
    length: f64,
    /// Curvature at the end, e^{−q} (0 at the edge).
    kappa1: f64,
}

impl StandardShape {
    fn new(alpha: f64, theta_t: f64, q: Option<f64>) -> Result<Self, LacError> {
        let shape = match q {
            // Λ_max = 1/((1 − α)θ_T); s_max = (1 − α)θ_T/(−α).
            None => StandardShape {
                inv_lambda: (1.0 - alpha) * theta_t,
                upper: f64::INFINITY,
                length: theta_t * (alpha - 1.0) / alpha,
                kappa1: 0.0,
            },
            // Λ = q·exprel((α−1)q)/θ_T, s_T = θ_T·exprel(αq)/exprel((α−1)q).
            Some(q) => {
                let e = exprel((alpha - 1.0) * q);
                StandardShape {
                    inv_lambda: theta_t / (q * e),
                    upper: q,
                    length: theta_t * exprel(alpha * q) / e,
                    kappa1: (-q).exp(),
                }
            }
        };
        if !(shape.length.is_finite() && shape.inv_lambda.is_finite()) {
            // exprel(αq) overflows: s_T/ρ0 = (ρ_T^α − 1)/(αΛ) beyond f64.
            return Err(LacError::CurvatureRatioOutOfRange {
                ratio: q.map_or(f64::INFINITY, f64::exp),
                alpha,
            });
        }
        Ok(shape)
    }

    /// e^{−shift}·P(s_T) with the shift (0, or αU for α > 0) that keeps it of order one.
    fn scaled_end(&self, alpha: f64) -> (Vec2, f64) {
        let shift = if alpha > 0.0 { alpha * self.upper } else { 0.0 };
        let integral = log_radius_integral(alpha, self.inv_lambda, self.upper, shift);
        (integral * self.inv_lambda, shift)
    }

    /// The chord angle φ = arg P(s_T).
    fn chord_angle(&self, alpha: f64) -> f64 {
        let (p, _) = self.scaled_end(alpha);
        p.y.atan2(p.x)
    }
}

/// The chord angle φ(q) of the standard span with log curvature ratio q > 0 and its derivative
/// dφ/dq.
///
/// P ∝ I(q) = ∫₀^q e^{αu}·e^{iθ(u)} du with θ(u) = c·u·exprel((α−1)u), c = θ_T/(q·exprel((α−1)q))
/// ([`super::log_radius`]), so
///
/// I′(q) = e^{αq}·e^{iθ_T} + i·(c′/c)·J,   J = ∫₀^q e^{αu}·e^{iθ(u)}·θ(u) du,
/// c′/c = −1/(q·exprel(−(α−1)q)),
///
/// (the first term from the moving upper limit, where θ(q) = θ_T), and dφ/dq = Im(Ī·I′)/|I|².
/// Both integrals share one pass over the nodes; the common factor e^{−shift} cancels.
fn chord_angle_and_slope(alpha: f64, theta_t: f64, q: f64) -> Result<(f64, f64), LacError> {
    let shape = StandardShape::new(alpha, theta_t, Some(q))?;
    let shift = if alpha > 0.0 { alpha * q } else { 0.0 };
    let (i, j) = integrals(alpha, shape.inv_lambda, q, shift, true);
    let log_rate = -1.0 / (q * exprel(-(alpha - 1.0) * q));
    let boundary = cis(theta_t) * (alpha * q - shift).exp();
    let di = boundary + Vec2::new(-j.y, j.x) * log_rate;
    let norm2 = i.hypot2();
    Ok((i.y.atan2(i.x), (i.x * di.y - i.y * di.x) / norm2))
}

/// The LAC segment of slope `alpha` from `a` (unit tangent direction `ta`) to `b` (direction `tb`).
///
/// The tangents need not be normalised, only nonzero. Errors: [`LacError::CoincidentEndPoints`],
/// [`LacError::NotFinite`], and [`LacError::OutsideDrawableRegion`] when the tangents turn in
/// opposite senses relative to the chord (an inflection), or the end angles are too unequal for
/// this α (beyond φ_∞ of the module documentation: for α < 0 the κ = 0 edge, otherwise needing a
/// curvature ratio above e^[`MAX_LOG_CURVATURE_RATIO`]).
pub fn fit_g1(a: Point, ta: Vec2, b: Point, tb: Vec2, alpha: f64) -> Result<LacSegment, LacError> {
    fit_g1_near(a, ta, b, tb, alpha, None)
}

/// [`fit_g1`], warm-started from `near`, a segment for nearby data (the previous iterate of a
/// refinement, or the same span at a neighbouring α): its log curvature ratio starts the solve,
/// which then typically converges in two or three steps. The result does not depend on `near`
/// beyond the solver's tolerance.
pub fn fit_g1_near(
    a: Point,
    ta: Vec2,
    b: Point,
    tb: Vec2,
    alpha: f64,
    near: Option<&LacSegment>,
) -> Result<LacSegment, LacError> {
    let hint = near.and_then(|n| {
        let (k0, k1) = (n.kappa0().abs(), n.kappa1().abs());
        let (hi, lo) = if k0 >= k1 { (k0, k1) } else { (k1, k0) };
        let q = (hi / lo).ln();
        (q.is_finite() && q > 0.0).then_some(q)
    });
    for (field, v) in [
        ("a.x", a.x),
        ("a.y", a.y),
        ("b.x", b.x),
        ("b.y", b.y),
        ("ta.x", ta.x),
        ("ta.y", ta.y),
        ("tb.x", tb.x),
        ("tb.y", tb.y),
        ("alpha", alpha),
    ] {
        if !v.is_finite() {
            return Err(LacError::NotFinite { field });
        }
    }
    if ta.hypot2() == 0.0 || tb.hypot2() == 0.0 {
        return Err(LacError::NotFinite {
            field: "tangent direction (zero vector)",
        });
    }
    let chord = b - a;
    let c = chord.hypot();
    let magnitude = a.x.abs().max(a.y.abs()).max(b.x.abs()).max(b.y.abs());
    if c <= COINCIDENT_RELATIVE * magnitude || c < 1e-300 {
        return Err(LacError::CoincidentEndPoints);
    }
    let psi = chord.atan2();
    let angle_a = ta.atan2();
    let theta_a = wrap(psi - angle_a);
    let theta_b = wrap(tb.atan2() - psi);
    let outside = || LacError::OutsideDrawableRegion {
        theta_a,
        theta_b,
        alpha,
    };

    let sigma = if theta_a + theta_b >= 0.0 { 1.0 } else { -1.0 };
    let (ea, eb) = (sigma * theta_a, sigma * theta_b);
    let theta_t = ea + eb;

    if (ea - eb).abs() <= SYMMETRIC_TOLERANCE {
        // Circular arc (line when θ_T = 0): κ = 2 sin(θ_T/2)/c, S = c/sinc(θ_T/2).
        let half = 0.5 * theta_t;
        let kappa = sigma * 2.0 * half.sin() / c;
        let length = if half == 0.0 {
            c
        } else {
            c * half / half.sin()
        };
        return LacSegment::new(a, angle_a, length, None, kappa, kappa);
    }
    let (big, small) = if ea > eb { (ea, eb) } else { (eb, ea) };
    if small <= 0.0 {
        return Err(outside());
    }

    let q = if alpha < 0.0 {
        let f_edge = StandardShape::new(alpha, theta_t, None)?.chord_angle(alpha) - big;
        if f_edge < -DRAWABLE_EDGE_TOLERANCE {
            return Err(outside());
        }
        if f_edge <= 0.0 {
            None
        } else {
            // Beyond q = 600 the far-end curvature is not representable. For α well below 0 the
            // chord angle there is within rounding of the edge's, which is then the answer; near
            // α = 0⁻ it approaches the edge only like e^{αq}, the data lies between q = 600 and
            // the edge, and no record can hold it.
            match solve_q(alpha, theta_t, big, hint)? {
                Some(q) => Some(q),
                None if f_edge <= DRAWABLE_EDGE_TOLERANCE => None,
                None => {
                    return Err(LacError::CurvatureRatioOutOfRange {
                        ratio: f64::INFINITY,
                        alpha,
                    });
                }
            }
        }
    } else {
        Some(solve_q(alpha, theta_t, big, hint)?.ok_or_else(outside)?)
    };
    let shape = StandardShape::new(alpha, theta_t, q)?;
    let (end, shift) = shape.scaled_end(alpha);
    // |AB| = scale·|P(s_T)| = scale·e^{shift}·|end|.
    let scale = c / end.hypot() * (-shift).exp();
    let kappa_hi = sigma / scale;
    let kappa_lo = sigma * shape.kappa1 / scale;
    let length = scale * shape.length;
    let (kappa0, kappa1) = if ea > eb {
        (kappa_hi, kappa_lo)
    } else {
        (kappa_lo, kappa_hi)
    };
    LacSegment::new(a, angle_a, length, Some(alpha), kappa0, kappa1)
}

/// Solves φ(q) = `big` for q by Newton's method on φ(q) − big with the analytic slope of
/// [`chord_angle_and_slope`], safeguarded by a bracket: φ(0) = θ_T/2 < big and φ increases with q,
/// so every evaluation moves one end of [lo, hi]; a Newton step that leaves the bracket is replaced
/// by bisection (or, while no upper end is known, by at most quadrupling q). Starts from `hint`
/// (a nearby solution, e.g. the previous iterate of a chain refinement) or q = 1.
///
/// `None` when φ stays below `big` up to q = [`MAX_LOG_CURVATURE_RATIO`] (or a q at which ρ^α or the
/// length overflows f64): for α ≥ 0 the data is then outside the drawable region; for α < 0 (where
/// the caller has checked big < φ_∞) it is within e^{−600} of the κ = 0 edge, which is the answer.
fn solve_q(alpha: f64, theta_t: f64, big: f64, hint: Option<f64>) -> Result<Option<f64>, LacError> {
    let (mut lo, mut hi) = (0.0_f64, f64::INFINITY);
    // Whether φ(hi) ≥ big was seen (hi may also be a q at which the shape overflows).
    let mut bracketed = false;
    // The last Newton step taken, while Newton steps follow each other.
    let mut previous_step: Option<f64> = None;
    let mut q = hint
        .filter(|&h| h > 0.0 && h <= MAX_LOG_CURVATURE_RATIO)
        .unwrap_or(1.0);
    for _ in 0..MAX_SOLVE_STEPS {
        let (phi, slope) = match chord_angle_and_slope(alpha, theta_t, q) {
            Ok(v) => v,
            // ρ_T^α (or s_T) overflows f64 here: the root, if any, lies below q.
            Err(LacError::CurvatureRatioOutOfRange { .. }) if q > lo && !bracketed => {
                hi = hi.min(q);
                if hi - lo <= LOG_RATIO_TOLERANCE {
                    return Ok(None);
                }
                q = 0.5 * (lo + hi);
                continue;
            }
            Err(e) => return Err(e),
        };
        let f = phi - big;
        if f == 0.0 {
            return Ok(Some(q));
        }
        if f < 0.0 {
            lo = q;
        } else {
            hi = q;
            bracketed = true;
        }
        let newton = q - f / slope;
        let newton_ok = newton > lo
            && newton < hi
            && newton <= MAX_LOG_CURVATURE_RATIO
            && (hi.is_finite() || newton <= 4.0 * q);
        if newton_ok {
            let step = (newton - q).abs();
            // Quadratic convergence: the error after this step is ≈ C·step² with
            // C ≈ step/previous², so step³/previous² bounds it once the iteration has settled
            // (two successive Newton steps, the second much smaller than the first).
            let settled = previous_step.is_some_and(|p: f64| {
                step <= NEWTON_SETTLED_RATIO * p
                    && step * step * step <= LOG_RATIO_TOLERANCE * p * p
            });
            if step <= LOG_RATIO_TOLERANCE || settled {
                return Ok(Some(newton));
            }
            previous_step = Some(step);
        } else {
            previous_step = None;
        }
        let next = if newton_ok {
            newton
        } else if hi.is_finite() {
            0.5 * (lo + hi)
        } else {
            if q >= MAX_LOG_CURVATURE_RATIO {
                return Ok(None);
            }
            (4.0 * q).min(MAX_LOG_CURVATURE_RATIO)
        };
        if hi - lo <= LOG_RATIO_TOLERANCE {
            // Without a sign change the bracket closed on the overflow bound: no representable root.
            return Ok(bracketed.then_some(next));
        }
        q = next;
    }
    // Not reached in practice: bisection alone shrinks [0, 600] below the tolerance in 53 steps.
    Ok(bracketed.then_some(0.5 * (lo + hi)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chord_angle_slope_matches_central_differences() {
        for alpha in [-2.5, -1.0, -0.2, 0.0, 0.4, 1.0, 1.7, 3.0] {
            for theta_t in [0.2, 1.0, 2.5] {
                for q in [0.05, 0.7, 2.0, 6.0] {
                    let (_, slope) = chord_angle_and_slope(alpha, theta_t, q).expect("valid");
                    let h = 1e-5 * q;
                    let angle = |q| {
                        StandardShape::new(alpha, theta_t, Some(q))
                            .expect("valid")
                            .chord_angle(alpha)
                    };
                    let fd = (angle(q + h) - angle(q - h)) / (2.0 * h);
                    assert!(
                        (slope - fd).abs() <= 1e-7 * (1.0 + fd.abs()),
                        "α {alpha} θ_T {theta_t} q {q}: {slope} vs {fd}"
                    );
                }
            }
        }
    }

    #[test]
    fn warm_start_gives_the_same_segment() {
        let (a, b) = (Point::ORIGIN, Point::new(2.0, 0.5));
        let (ta, tb) = (Vec2::new(1.0, -0.4), Vec2::new(0.3, 1.0));
        for alpha in [-1.5, -0.5, 0.0, 0.5, 1.5, 2.5] {
            let Ok(cold) = fit_g1(a, ta, b, tb, alpha) else {
                continue;
            };
            // Hints from a neighbouring α, from the answer itself, and from a far-off segment.
            let near = fit_g1(a, ta, b, tb, alpha + 0.1).ok();
            let far =
                LacSegment::new(Point::ORIGIN, 0.0, 1.0, Some(1.0), 1.0, 1e-100).expect("valid");
            for hint in [near.as_ref(), Some(&cold), Some(&far)] {
                let warm = fit_g1_near(a, ta, b, tb, alpha, hint).expect("drawable");
                assert!((warm.kappa1() - cold.kappa1()).abs() <= 1e-10 * cold.kappa1().abs());
                assert!((warm.end() - b).hypot() < 1e-12);
            }
        }
    }
}
