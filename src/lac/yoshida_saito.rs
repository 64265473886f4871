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
//! φ(q) = θ_big is solved with kurbo's ITP method (bracketing, safeguarded, superlinear on smooth
//! functions). θ_big beyond the reachable range is outside the drawable region. Then scale by |AB|/|P(s_T)|, rotate, and undo the mirror;
//! when the high-curvature end is B, the record simply has |κ| increasing along travel.

use super::error::LacError;
use super::segment::LacSegment;
use super::special::exprel;
use crate::geom::{Point, Vec2};
use kurbo::common::solve_itp;
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

/// Absolute tolerance on q for the ITP root finder. dφ/dq ≤ O(1), so the end-angle error this
/// leaves is ≲ 1e-13 rad, and the curvature ratio is off by ≲ 1e-13 relative.
pub const LOG_RATIO_TOLERANCE: f64 = 1e-13;

/// Angle wrapped to (−π, π].
fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(2.0 * PI);
    if w > PI { w - 2.0 * PI } else { w }
}

/// The standard-form span with total turning `theta_t` and log curvature ratio `q` (`None`: the
/// κ = 0 edge, α < 0), as a record starting at the origin along +x with κ0 = 1.
fn standard_span(alpha: f64, theta_t: f64, q: Option<f64>) -> Result<LacSegment, LacError> {
    let (length, kappa1) = match q {
        // s_max = (1 − α)θ_T/(−α) at Λ = Λ_max.
        None => (theta_t * (alpha - 1.0) / alpha, 0.0),
        Some(q) => (
            theta_t * exprel(alpha * q) / exprel((alpha - 1.0) * q),
            (-q).exp(),
        ),
    };
    if !length.is_finite() {
        // exprel(αq) overflows: s_T/ρ0 = (ρ_T^α − 1)/(αΛ) beyond f64.
        return Err(LacError::CurvatureRatioOutOfRange {
            ratio: q.map_or(f64::INFINITY, f64::exp),
            alpha,
        });
    }
    LacSegment::new(Point::ORIGIN, 0.0, length, Some(alpha), 1.0, kappa1)
}

/// Chord angle of [`standard_span`].
fn chord_angle(span: &LacSegment) -> f64 {
    let e = span.end();
    e.y.atan2(e.x)
}

/// The LAC segment of slope `alpha` from `a` (unit tangent direction `ta`) to `b` (direction `tb`).
///
/// The tangents need not be normalised, only nonzero. Errors: [`LacError::CoincidentEndPoints`],
/// [`LacError::NotFinite`], and [`LacError::OutsideDrawableRegion`] when the tangents turn in
/// opposite senses relative to the chord (an inflection), or the end angles are too unequal for
/// this α (beyond φ_∞ of the module documentation: for α < 0 the κ = 0 edge, otherwise needing a
/// curvature ratio above e^[`MAX_LOG_CURVATURE_RATIO`]).
pub fn fit_g1(a: Point, ta: Vec2, b: Point, tb: Vec2, alpha: f64) -> Result<LacSegment, LacError> {
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

    let target = |span: &LacSegment| chord_angle(span) - big;
    let q = if alpha < 0.0 {
        let edge = standard_span(alpha, theta_t, None)?;
        let f_edge = target(&edge);
        if f_edge < -DRAWABLE_EDGE_TOLERANCE {
            return Err(outside());
        }
        if f_edge <= 0.0 {
            None
        } else {
            solve_q(alpha, theta_t, big)?
        }
    } else {
        Some(solve_q(alpha, theta_t, big)?.ok_or_else(outside)?)
    };
    let span = standard_span(alpha, theta_t, q)?;
    let end = span.end();
    let scale = c / end.to_vec2().hypot();
    let kappa_hi = sigma / scale;
    let kappa_lo = sigma * span.kappa1() / scale;
    let length = scale * span.length();
    let (kappa0, kappa1) = if ea > eb {
        (kappa_hi, kappa_lo)
    } else {
        (kappa_lo, kappa_hi)
    };
    LacSegment::new(a, angle_a, length, Some(alpha), kappa0, kappa1)
}

/// Solves φ(q) = `big` for q by ITP, after bracketing: φ(0) = θ_T/2 < big, and q is doubled from 1
/// until φ(q) ≥ big. `None` when that needs q > [`MAX_LOG_CURVATURE_RATIO`] (or a q at which
/// ρ^α or the length overflows f64): for α ≥ 0 the data
/// is then outside the drawable region; for α < 0 (where the caller has checked big < φ_∞) it is
/// within e^{−600} of the κ = 0 edge, which is the answer.
fn solve_q(alpha: f64, theta_t: f64, big: f64) -> Result<Option<f64>, LacError> {
    let f = |q: f64| -> Result<f64, LacError> {
        Ok(chord_angle(&standard_span(alpha, theta_t, Some(q))?) - big)
    };
    let (mut lo, mut f_lo) = (0.0, 0.5 * theta_t - big);
    let mut hi = 1.0;
    let mut f_hi = f(hi)?;
    while f_hi < 0.0 {
        if hi >= MAX_LOG_CURVATURE_RATIO {
            return Ok(None);
        }
        (lo, f_lo) = (hi, f_hi);
        hi = (2.0 * hi).min(MAX_LOG_CURVATURE_RATIO);
        f_hi = match f(hi) {
            // ρ_T^α (or s_T) overflows f64 before φ reaches the target: not representable.
            Err(LacError::CurvatureRatioOutOfRange { .. }) => return Ok(None),
            other => other?,
        };
    }
    if f_hi == 0.0 {
        return Ok(Some(hi));
    }
    // φ is continuous and increasing in q; every evaluation inside the bracket is valid because the
    // bracket ends were.
    let mut failure = None;
    let q = solve_itp(
        |q| match f(q) {
            Ok(v) => v,
            Err(e) => {
                failure = Some(e);
                0.0
            }
        },
        lo,
        hi,
        LOG_RATIO_TOLERANCE,
        1,
        0.2 / (hi - lo),
        f_lo,
        f_hi,
    );
    match failure {
        Some(e) => Err(e),
        None => Ok(Some(q)),
    }
}
