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
use super::special::exprel;
use super::special::{SERIES_TERM_EPS, cdiv, cexpm1, cis, cmul};
use super::standard::involute_g;
use crate::geom::{Point, Vec2, wrap_angle_by_turns};

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

/// Terms of the φ_∞ series summed at most: a turning of 2π needs about 45 for 1e-18.
const LIMIT_SERIES_MAX_TERMS: usize = 80;

/// Data whose larger end angle exceeds the series value of φ_∞ by more than this (radians) is
/// rejected without solving; closer to the limit the solve (and, for α < 0, the exact edge test)
/// decides. Far above the series' rounding (≈ 1e-14 for turnings up to 2π).
const LIMIT_PRECHECK_MARGIN: f64 = 1e-9;

/// For α < 0, a target chord angle inside the κ = 0 edge by at most this (radians) is on the
/// edge too: the edge's chord angle and the data's (a segment ending at κ = 0, evaluated on
/// another path) agree only to rounding, a few 1e-16 rad, and inside by that much the solve
/// would return a finite ratio where φ(q) meets the data to rounding (e^{18} at α = −2: an end
/// curvature of 1e-8 of the other's instead of 0).
const EDGE_ROUNDING: f64 = 1e-14;

/// For α < 0, data whose larger end angle is within this of the series value of the edge's chord
/// angle (radians) goes straight to the exact edge test: far above the series' rounding, so no
/// data on the edge (within [`DRAWABLE_EDGE_TOLERANCE`]) is solved for a huge finite ratio instead
/// of getting its exact κ = 0 end.
const EDGE_NEAR: f64 = 1e-10;

/// For α < 0, the κ = 0 edge is only examined when no root lies below this log curvature ratio
/// (e^{40}): pen data is far inside, and the edge needs an integral over an unbounded range.
const EDGE_CHECK_RATIO: f64 = 40.0;

/// Most Newton/bisection steps of the q solve: bisection alone would reach the tolerance on
/// [0, 600] in 53; Newton converges quadratically in a handful.
const MAX_SOLVE_STEPS: usize = 200;

/// A Newton step at most this fraction of the one before shows the iteration in its quadratic
/// regime, where the next error can be predicted from the two steps (see `solve_q`).
const NEWTON_SETTLED_RATIO: f64 = 0.01;

/// Absolute tolerance on q for the root finder. dφ/dq ≤ O(1), so the end-angle error this
/// leaves is ≲ 1e-13 rad, and the curvature ratio is off by ≲ 1e-13 relative.
pub const LOG_RATIO_TOLERANCE: f64 = 1e-13;

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
    /// Total turning θ_T.
    theta_t: f64,
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
                theta_t,
            },
            // Λ = q·exprel((α−1)q)/θ_T, s_T = θ_T·exprel(αq)/exprel((α−1)q).
            Some(q) => {
                let e = exprel((alpha - 1.0) * q);
                StandardShape {
                    inv_lambda: theta_t / (q * e),
                    upper: q,
                    length: theta_t * exprel(alpha * q) / e,
                    kappa1: (-q).exp(),
                    theta_t,
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
        if let Some((p, _)) = closed_form_end(alpha, self.theta_t, self.upper) {
            return (p, 0.0);
        }
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

/// The chord angle φ(q) and dφ/dq (see [`span_end_and_rate`]).
#[cfg(test)]
fn chord_angle_and_slope(alpha: f64, theta_t: f64, q: f64) -> Result<(f64, f64), LacError> {
    let e = span_end_and_rate(alpha, theta_t, q)?;
    Ok((e.p.y.atan2(e.p.x), e.angle_slope()))
}

/// The standard span's end P(s_T) and dP/dq at one q, both scaled by e^{−shift}.
#[derive(Clone, Copy, Debug)]
struct SpanEnd {
    p: Vec2,
    dp: Vec2,
    shift: f64,
}

impl SpanEnd {
    /// dφ/dq = Im(P̄·P′)/|P|² (the scale cancels).
    fn angle_slope(&self) -> f64 {
        (self.p.x * self.dp.y - self.p.y * self.dp.x) / self.p.hypot2()
    }
}

/// [`SpanEnd`] at q > 0: closed forms for α = 1, 2 ([`closed_form_end`]); otherwise P = c·I with
///
/// I(q) = ∫₀^q e^{αu}·e^{iθ(u)} du with θ(u) = c·u·exprel((α−1)u), c = θ_T/(q·exprel((α−1)q))
/// ([`super::log_radius`]), so
///
/// I′(q) = e^{αq}·e^{iθ_T} + i·(c′/c)·J,   J = ∫₀^q e^{αu}·e^{iθ(u)}·θ(u) du,
/// c′/c = −1/(q·exprel(−(α−1)q)),
///
/// (the first term from the moving upper limit, where θ(q) = θ_T), so dP/dq = c·((c′/c)·I + I′)
/// and dφ/dq = Im(P̄·P′)/|P|². Both integrals share one pass over the nodes; the common factor
/// e^{−shift} cancels in φ and its slope.
fn span_end_and_rate(alpha: f64, theta_t: f64, q: f64) -> Result<SpanEnd, LacError> {
    let shape = StandardShape::new(alpha, theta_t, Some(q))?;
    if let Some((p, dp)) = closed_form_end(alpha, theta_t, q) {
        return Ok(SpanEnd { p, dp, shift: 0.0 });
    }
    let shift = if alpha > 0.0 { alpha * q } else { 0.0 };
    let (i, j) = integrals(alpha, shape.inv_lambda, q, shift, true);
    let log_rate = -1.0 / (q * exprel(-(alpha - 1.0) * q));
    let boundary = cis(theta_t) * (alpha * q - shift).exp();
    let di = boundary + Vec2::new(-j.y, j.x) * log_rate;
    Ok(SpanEnd {
        p: i * shape.inv_lambda,
        dp: (i * log_rate + di) * shape.inv_lambda,
        shift,
    })
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
/// refinement, or the same span at a neighbouring α): its log curvature ratio, moved to the new
/// data by the nearly-straight model (see `warm_start`), starts the solve, which then typically
/// converges in two or three steps. The result does not depend on `near` beyond the solver's
/// tolerance.
pub fn fit_g1_near(
    a: Point,
    ta: Vec2,
    b: Point,
    tb: Vec2,
    alpha: f64,
    near: Option<&LacSegment>,
) -> Result<LacSegment, LacError> {
    build(a, ta, b, tb, alpha, near, false)
}

/// [`fit_g1_near`] for data a tiny step away from `near`'s (a finite-difference probe): the
/// solve for q takes one Newton step from `near`'s ratio, with the end moved to first order. A
/// step of h in the data moves q by O(h), so the result is off by O(h²) (about 1e-14 for the
/// refinement's steps of 1e-7), far below what a forward difference resolves, for one
/// quadrature instead of the two or three that confirm convergence. Not for output.
pub(crate) fn fit_g1_probe(
    a: Point,
    ta: Vec2,
    b: Point,
    tb: Vec2,
    alpha: f64,
    near: &LacSegment,
) -> Result<LacSegment, LacError> {
    build(a, ta, b, tb, alpha, Some(near), true)
}

/// G1 data in the normalised frame of the module doc.
#[derive(Clone, Copy, Debug)]
struct Normalised {
    /// Direction of the start tangent.
    angle_a: f64,
    /// θ_A = ψ − arg t_A and θ_B = arg t_B − ψ, ψ the chord's direction, wrapped to (−π, π].
    theta_a: f64,
    theta_b: f64,
    /// The mirror that makes the turning non-negative (±1).
    sigma: f64,
    /// σ·θ_A and σ·θ_B.
    ea: f64,
    eb: f64,
    /// The total turning θ_T = ea + eb ≥ 0.
    theta_t: f64,
}

impl Normalised {
    /// [`Normalised::new`] for the chord from `a` to `b`; `None` for non-finite data, coincident
    /// end points or a zero tangent.
    fn checked(a: Point, ta: Vec2, b: Point, tb: Vec2) -> Option<Self> {
        let chord = b - a;
        let finite = [a.x, a.y, b.x, b.y, ta.x, ta.y, tb.x, tb.y]
            .iter()
            .all(|v| v.is_finite());
        (finite && chord.hypot2() > 0.0 && ta.hypot2() > 0.0 && tb.hypot2() > 0.0)
            .then(|| Normalised::new(chord, ta, tb))
    }

    /// The angles of tangents `ta`, `tb` to `chord` (non-zero vectors).
    fn new(chord: Vec2, ta: Vec2, tb: Vec2) -> Self {
        let psi = chord.atan2();
        let angle_a = ta.atan2();
        let theta_a = wrap_angle_by_turns(psi - angle_a);
        let theta_b = wrap_angle_by_turns(tb.atan2() - psi);
        let sigma = if theta_a + theta_b >= 0.0 { 1.0 } else { -1.0 };
        let (ea, eb) = (sigma * theta_a, sigma * theta_b);
        Normalised {
            angle_a,
            theta_a,
            theta_b,
            sigma,
            ea,
            eb,
            theta_t: ea + eb,
        }
    }
}

/// The body of [`fit_g1_near`] and [`fit_g1_probe`].
fn build(
    a: Point,
    ta: Vec2,
    b: Point,
    tb: Vec2,
    alpha: f64,
    near: Option<&LacSegment>,
    one_step: bool,
) -> Result<LacSegment, LacError> {
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
    let Normalised {
        angle_a,
        theta_a,
        theta_b,
        sigma,
        ea,
        eb,
        theta_t,
    } = Normalised::new(chord, ta, tb);
    let outside = || LacError::OutsideDrawableRegion {
        theta_a,
        theta_b,
        alpha,
    };

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
    let hint = near.and_then(|n| {
        if one_step {
            log_ratio(n)
        } else {
            warm_start(n, alpha, theta_t, big)
        }
    });

    // Far outside (beyond the limit φ_∞ by more than the series' accuracy): no solve needed.
    let limit = limit_chord_angle(alpha, theta_t);
    if limit.is_some_and(|limit| big > limit + LIMIT_PRECHECK_MARGIN) {
        return Err(outside());
    }
    // For α < 0: the exact κ = 0 edge test, then (inside it) the full-range solve.
    let edge_path = || -> Result<Option<(f64, Option<SpanEnd>)>, LacError> {
        let f_edge = StandardShape::new(alpha, theta_t, None)?.chord_angle(alpha) - big;
        if f_edge < -DRAWABLE_EDGE_TOLERANCE {
            return Err(outside());
        }
        if f_edge <= EDGE_ROUNDING {
            return Ok(None);
        }
        // Beyond q = 600 the far-end curvature is not representable. For α well below 0 the
        // chord angle there is within rounding of the edge's, which is then the answer; near
        // α = 0⁻ it approaches the edge only like e^{αq}, the data lies between q = 600 and the
        // edge, and no record can hold it.
        match solve_q(alpha, theta_t, big, hint, MAX_LOG_CURVATURE_RATIO, one_step)? {
            Some(solved) => Ok(Some(solved)),
            None if f_edge <= DRAWABLE_EDGE_TOLERANCE => Ok(None),
            None => Err(LacError::CurvatureRatioOutOfRange {
                ratio: f64::INFINITY,
                alpha,
            }),
        }
    };
    // (q, its end when the solve already has it); `None`: the κ = 0 edge.
    let solved: Option<(f64, Option<SpanEnd>)> = if alpha < 0.0 {
        if limit.is_some_and(|limit| big >= limit - EDGE_NEAR) {
            // On or next to the edge: decide exactly, so that edge data gets κ = 0 exactly.
            edge_path()?
        } else {
            // Most data lies well inside: look for the root below a moderate ratio first.
            match solve_q(alpha, theta_t, big, hint, EDGE_CHECK_RATIO, one_step)? {
                Some(solved) => Some(solved),
                None => edge_path()?,
            }
        }
    } else {
        Some(
            solve_q(alpha, theta_t, big, hint, MAX_LOG_CURVATURE_RATIO, one_step)?
                .ok_or_else(outside)?,
        )
    };
    let q = solved.map(|(q, _)| q);
    let shape = StandardShape::new(alpha, theta_t, q)?;
    let (end, shift) = match solved.and_then(|(_, end)| end) {
        Some(e) => (e.p, e.shift),
        None => shape.scaled_end(alpha),
    };
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
    // The segment ends at `b`: the solve matched the chord angle to LOG_RATIO_TOLERANCE·dφ/dq
    // (≲ 1e-13 rad) and the scale matched its length exactly, so b is its end to ~1e-13 of the
    // chord; integrating the end again would only repeat the quadrature that set the scale.
    LacSegment::with_known_end(a, angle_a, length, Some(alpha), kappa0, kappa1, b)
}

/// How far G1 data lies inside the drawable region of α, in radians: min(θ_small, φ_∞ − θ_big)
/// in the normalised frame of the module doc, with φ_∞ the limit chord angle (the κ = 0 edge for
/// α < 0, θ_T for 0 ≤ α ≤ 1, the series limit for α > 1). Positive inside, negative outside;
/// smooth in the data and α away from the symmetric (circular) case, so an optimiser can
/// linearise it to keep a step inside (see `chain::refine`). The series value is accurate to
/// ~1e-13 rad for turnings up to 2π (see `limit_chord_angle`); the construction itself decides
/// exactly. Symmetric data (a circular arc or a line, which every α draws) gets θ_T/2. `None` for
/// non-finite data or coincident end points.
pub(crate) fn drawable_margin(a: Point, ta: Vec2, b: Point, tb: Vec2, alpha: f64) -> Option<f64> {
    if !alpha.is_finite() {
        return None;
    }
    let Normalised {
        ea, eb, theta_t, ..
    } = Normalised::checked(a, ta, b, tb)?;
    if (ea - eb).abs() <= SYMMETRIC_TOLERANCE {
        // A circular arc or a line: any α draws it.
        return Some(0.5 * theta_t);
    }
    let (big, small) = if ea > eb { (ea, eb) } else { (eb, ea) };
    let limit = limit_chord_angle(alpha, theta_t).unwrap_or(theta_t);
    Some(small.min(limit - big))
}

/// The two edges of the drawable region of α that G1 data meets, in a mirror frame `sigma` (±1)
/// held fixed: [φ_∞(θ_T) − σθ_A, φ_∞(θ_T) − σθ_B] with θ_T = σ(θ_A + θ_B) and φ_∞ the limit
/// chord angle of [`drawable_margin`] (θ_T itself for 0 ≤ α ≤ 1, where the two reduce to σθ_B
/// and σθ_A). Data is drawable in that frame exactly when both are non-negative: their sum
/// 2φ_∞ − θ_T ≥ 0 forces θ_T ≥ 0 (φ_∞ lies between θ_T/2 and θ_T), and each bounds the larger
/// end angle, which also keeps the smaller one positive.
///
/// Unlike [`drawable_margin`], a minimum taken in the data's own mirror frame, both are smooth in
/// the data and α everywhere. That matters for a near-straight segment: its drawable region is
/// a wedge with its apex at θ_A = θ_B = 0, a step of the size of its turning crosses it, and the
/// linearised minimum sees only one side of the wedge and nothing of the apex, while the two
/// edges, held together, are the wedge (see `chain::refine`). Tested for turnings up to 3.4 rad;
/// at 4.2 rad the limit for α > 1 already reads symmetric data (an arc, which every α draws) as
/// outside, so a segment held there only takes more cautious steps. `None` for non-finite data
/// or coincident end points.
pub(crate) fn edge_margins(
    a: Point,
    ta: Vec2,
    b: Point,
    tb: Vec2,
    alpha: f64,
    sigma: f64,
) -> Option<[f64; 2]> {
    if !(alpha.is_finite() && sigma.is_finite()) {
        return None;
    }
    let n = Normalised::checked(a, ta, b, tb)?;
    let (ea, eb) = (sigma * n.theta_a, sigma * n.theta_b);
    let theta_t = ea + eb;
    let limit = limit_chord_angle(alpha, theta_t).unwrap_or(theta_t);
    Some([limit - ea, limit - eb])
}

/// The mirror (±1) that makes G1 data turn left in the normalised frame of the module doc (see
/// [`edge_margins`]); `None` for non-finite data or coincident end points.
pub(crate) fn mirror(a: Point, ta: Vec2, b: Point, tb: Vec2) -> Option<f64> {
    Some(Normalised::checked(a, ta, b, tb)?.sigma)
}

/// P(s_T) and dP/dq of the standard span in closed form, for α = 1 and α = 2 (`None` otherwise,
/// or at the κ = 0 edge). With ds = ρ dθ:
///
/// * α = 1 (logarithmic spiral): ρ = e^{Λθ}, Λ = q/θ_T, z = Λ + i, E = e^{zθ_T} = e^q·e^{iθ_T}:
///   P = (E − 1)/z and dP/dq = (E − P/θ_T)/z.
/// * α = 2 (circle involute): ρ = 1 + kθ, k = (e^q − 1)/θ_T:
///   P = −i(e^{iθ_T} − 1) + k·G(θ_T), G(θ) = e^{iθ}(1 − iθ) − 1, and dP/dq = (e^q/θ_T)·G(θ_T).
fn closed_form_end(alpha: f64, theta_t: f64, q: f64) -> Option<(Vec2, Vec2)> {
    if !q.is_finite() {
        return None;
    }
    if alpha == 1.0 {
        let z = Vec2::new(q / theta_t, 1.0);
        let e_minus_1 = cexpm1(q, theta_t);
        let p = cdiv(e_minus_1, z);
        let e = e_minus_1 + Vec2::new(1.0, 0.0);
        Some((p, cdiv(e - p / theta_t, z)))
    } else if alpha == 2.0 {
        let g = involute_g(theta_t);
        let e = cexpm1(0.0, theta_t);
        let p = Vec2::new(e.y, -e.x) + g * (q.exp_m1() / theta_t);
        Some((p, g * (q.exp() / theta_t)))
    } else {
        None
    }
}

/// The chord angle φ_∞ that the standard span approaches as q → ∞, by power series, for α < 0
/// (the κ = 0 edge) and α > 1; `None` for 0 ≤ α ≤ 1, where it is θ_T itself (never binding, since
/// the larger end angle is below the total turning). In the turning angle t = θ/θ_T:
///
/// * α < 0: ρ^{α−1} = 1 − t, so ρ = r^{−γ} with r = 1 − t and γ = 1/(1 − α) ∈ (0, 1), and
///   P = θ_T·e^{iθ_T}·∫₀¹ e^{−iθ_T r}·r^{−γ} dr = θ_T·e^{iθ_T}·Σ_k (−iθ_T)^k/(k!·(k + 1 − γ));
/// * α > 1 (q → ∞): ds = ρ dθ ∝ θ^p dθ with p = 1/(α − 1), and
///   ∫₀^{θ_T} θ^p e^{iθ} dθ = θ_T^{p+1}·Σ_k (iθ_T)^k/(k!·(k + p + 1)).
///
/// The terms fall like θ_T^k/k!; the sum stops when they are below [`SERIES_TERM_EPS`] of it. For a
/// turning of 2π the largest term is ≈ 85, so two digits are lost to cancellation: this is a
/// quick pre-check with a margin, not the edge test itself. The value is not wrapped: it may exceed
/// π, where no end angle (each in (−π, π]) can reach it.
fn limit_chord_angle(alpha: f64, theta_t: f64) -> Option<f64> {
    let (base, sign, offset) = if alpha < 0.0 {
        (theta_t, -1.0, 1.0 - 1.0 / (1.0 - alpha))
    } else if alpha > 1.0 {
        (0.0, 1.0, 1.0 + 1.0 / (alpha - 1.0))
    } else {
        return None;
    };
    let step = Vec2::new(0.0, sign * theta_t);
    let mut power = Vec2::new(1.0, 0.0); // (±iθ_T)^k/k!
    let mut sum = power * (1.0 / offset);
    for k in 1..LIMIT_SERIES_MAX_TERMS {
        power = cmul(power, step) * (1.0 / k as f64);
        let term = power * (1.0 / (k as f64 + offset));
        sum += term;
        if term.hypot() < SERIES_TERM_EPS * sum.hypot() {
            break;
        }
    }
    Some(base + sum.y.atan2(sum.x))
}

/// The log curvature ratio q = ln(κ_high/κ_low) of `segment`, when positive and finite.
fn log_ratio(segment: &LacSegment) -> Option<f64> {
    let (k0, k1) = (segment.kappa0().abs(), segment.kappa1().abs());
    let (hi, lo) = if k0 >= k1 { (k0, k1) } else { (k1, k0) };
    let q = (hi / lo).ln();
    (q.is_finite() && q > 0.0).then_some(q)
}

/// A start for the solve of data (α, θ_T, θ_big) from `near`, the segment of nearby data (the
/// previous iterate of a refinement, the same span at a neighbouring α): the nearly-straight
/// approximation [`flat_ratio_guess`] with its defect at `near` carried over. Its ratio
/// r = θ_big/θ_T is the data's less the flat model's error at `near`,
/// r_near − r_flat(α_near, q_near), which the approximation's own curvature and the data's step
/// change only to first order. The flat model carries the strong nonlinearity of q in the end
/// angles (for a short span, a step of a thousandth of a radian in one tangent can move q by a
/// whole unit); the defect carries the span's finite turning. Over the refinement's trials of
/// the fixture strokes up to 600 samples, q moved by a median of 0.4 from `near`'s, and its
/// solve took 4.2 quadratures on average from there, 2.5 from this start (two are the least
/// that confirm convergence). Falls back to `near`'s own q.
fn warm_start(near: &LacSegment, alpha: f64, theta_t: f64, big: f64) -> Option<f64> {
    let q_near = log_ratio(near)?;
    let corrected = || {
        let alpha_near = near.alpha()?;
        let n = Normalised::checked(
            near.start(),
            cis(near.theta0()),
            near.end(),
            cis(near.theta1()),
        )?;
        if !(n.theta_t > 0.0) {
            return None;
        }
        let defect = n.ea.max(n.eb) / n.theta_t - flat_ratio(alpha_near, q_near)?;
        flat_ratio_guess(alpha, big / theta_t - defect, Some(q_near))
    };
    corrected().or(Some(q_near))
}

/// Relative offset of the secant method's second point from its start in [`secant_from`]: the
/// warm starts lie within a few percent of the root, where the flat equation is nearly linear.
const SECANT_OFFSET: f64 = 1e-2;

/// Relative step at which [`secant_from`] stops: the guess only starts Newton's method on the
/// quadrature, whose first step then lands within about 1e-12 of the root.
const SECANT_TOLERANCE: f64 = 1e-6;

/// The root of the flat equation `f` (increasing in q) by the secant method from `q0` (and
/// q0·(1 + [`SECANT_OFFSET`])); `None` when an iterate leaves (0, [`EDGE_CHECK_RATIO`]] or a
/// value is not finite, for the caller's bracket to take over.
fn secant_from(f: &impl Fn(f64) -> f64, q0: f64) -> Option<f64> {
    if !(q0 > 0.0 && q0 <= EDGE_CHECK_RATIO) {
        return None;
    }
    let (mut a, mut f_a) = (q0, f(q0));
    let mut b = q0 * (1.0 + SECANT_OFFSET);
    let mut f_b = f(b);
    for _ in 0..FLAT_GUESS_STEPS {
        if !(f_a.is_finite() && f_b.is_finite()) || f_a == f_b {
            return None;
        }
        let c = b - f_b * (b - a) / (f_b - f_a);
        if !(c > 0.0 && c <= EDGE_CHECK_RATIO) {
            return None;
        }
        if (c - b).abs() <= SECANT_TOLERANCE * c {
            return Some(c);
        }
        (a, f_a) = (b, f_b);
        b = c;
        f_b = f(c);
    }
    None
}

/// The flat model's end-angle ratio r(q) of [`flat_ratio_guess`]; `None` at α = 1 and q = 0,
/// where its form is 0/0.
fn flat_ratio(alpha: f64, q: f64) -> Option<f64> {
    let r =
        (exprel((2.0 * alpha - 1.0) * q) / exprel(alpha * q) - 1.0) / ((alpha - 1.0) * q).exp_m1();
    r.is_finite().then_some(r)
}

/// Most regula falsi steps of [`flat_ratio_guess`]: a start for Newton needs no more.
const FLAT_GUESS_STEPS: usize = 12;

/// The log curvature ratio q at which a nearly straight span (θ_T → 0) has the end-angle ratio
/// `r` = θ_big/θ_T: there the chord runs along the mean tangent, φ/θ_T = ∫₀¹ θ(x) dx/θ_T over
/// the normalised length x, which for ρ^α linear in x from 1 to e^{αq} is
///
/// r(q) = (exprel((2α − 1)q)/exprel(αq) − 1)/expm1((α − 1)q),
///
/// rising from 1/2 (q → 0, the circle) towards r_∞ = (1 − α)/(1 − 2α) for α < 0 (2/3 for the
/// clothoid from κ = 0), 1 for 0 ≤ α ≤ 1, α/(2α − 1) for α > 1, which it approaches
/// exponentially in q. So the equation is solved for ln(r_∞ − r(q)), nearly linear in q, by
/// regula falsi (Illinois) on a bracket found by doubling q: a start for the full solve that pen
/// data's small turnings put within a few Newton steps of the root, instead of the doubling
/// search from q = 1. With `start` (a nearby root: see [`warm_start`]) the secant method from
/// there goes first ([`secant_from`]), three or four evaluations of r where the bracket takes
/// a dozen. `None` for r outside (1/2, r_∞), a root beyond [`EDGE_CHECK_RATIO`], or α = 1
/// (where the form is 0/0).
fn flat_ratio_guess(alpha: f64, r: f64, start: Option<f64>) -> Option<f64> {
    let limit = if alpha < 0.0 {
        (1.0 - alpha) / (1.0 - 2.0 * alpha)
    } else if alpha <= 1.0 {
        1.0
    } else {
        alpha / (2.0 * alpha - 1.0)
    };
    if alpha == 1.0 || !(r > 0.5 && r < limit) {
        return None;
    }
    let target = (limit - r).ln();
    // Increasing in q, zero at the root; +∞ once r(q) is within rounding of the limit.
    let f = |q: f64| {
        let gap = flat_ratio(alpha, q).map_or(0.0, |ratio| limit - ratio);
        if gap > 0.0 {
            target - gap.ln()
        } else {
            f64::INFINITY
        }
    };
    if let Some(q) = start.and_then(|q0| secant_from(&f, q0)) {
        return Some(q);
    }
    let (mut lo, mut f_lo) = (0.0, target - (limit - 0.5).ln());
    let mut hi = 1.0;
    let mut f_hi = f(hi);
    while f_hi < 0.0 {
        (lo, f_lo) = (hi, f_hi);
        hi *= 2.0;
        if hi > EDGE_CHECK_RATIO {
            return None;
        }
        f_hi = f(hi);
    }
    let mut side = 0;
    let mut q = hi;
    for _ in 0..FLAT_GUESS_STEPS {
        // Regula falsi where both ends are finite; bisection while the upper one is the rounding
        // wall (+∞).
        q = if f_hi.is_finite() {
            (lo * f_hi - hi * f_lo) / (f_hi - f_lo)
        } else {
            0.5 * (lo + hi)
        };
        let value = f(q);
        if value < 0.0 {
            (lo, f_lo) = (q, value);
            if side == -1 {
                f_hi *= 0.5;
            }
            side = -1;
        } else {
            (hi, f_hi) = (q, value);
            if side == 1 {
                f_lo *= 0.5;
            }
            side = 1;
        }
        if hi - lo <= 1e-9 * hi {
            break;
        }
    }
    q.is_finite().then_some(q)
}

/// Solves φ(q) = `big` for q by Newton's method on φ(q) − big with the analytic slope of
/// [`span_end_and_rate`], safeguarded by a bracket: φ(0) = θ_T/2 < big and φ increases with q,
/// so every evaluation moves one end of [lo, hi]; a Newton step that leaves the bracket is replaced
/// by bisection (or, while no upper end is known, by at most quadrupling q). Starts from `hint`
/// (a nearby solution, e.g. the previous iterate of a chain refinement), else from the
/// nearly-straight approximation ([`flat_ratio_guess`]: over the fixture strokes up to 600 samples,
/// a cold solve takes 3.0 Newton steps on average instead of 7.1 from q = 1), else from q = 1.
///
/// `None` when φ stays below `big` up to q = `q_max` (at most [`MAX_LOG_CURVATURE_RATIO`]; or a q at which ρ^α or the
/// length overflows f64): for α ≥ 0 the data is then outside the drawable region; for α < 0 (where
/// the caller has checked big < φ_∞) it is within e^{−600} of the κ = 0 edge, which is the answer.
fn solve_q(
    alpha: f64,
    theta_t: f64,
    big: f64,
    hint: Option<f64>,
    q_max: f64,
    one_step: bool,
) -> Result<Option<(f64, Option<SpanEnd>)>, LacError> {
    // One Newton step from the hint only (see `fit_g1_probe`).
    let one_step = one_step && hint.is_some_and(|h| h > 0.0 && h <= q_max);
    let (mut lo, mut hi) = (0.0_f64, f64::INFINITY);
    // Whether φ(hi) ≥ big was seen (hi may also be a q at which the shape overflows).
    let mut bracketed = false;
    // The last Newton step taken, while Newton steps follow each other.
    let mut previous_step: Option<f64> = None;
    let mut q = hint
        .filter(|&h| h > 0.0 && h <= q_max)
        .or_else(|| flat_ratio_guess(alpha, big / theta_t, None).map(|g| g.min(q_max)))
        .unwrap_or(1.0);
    for _ in 0..MAX_SOLVE_STEPS {
        let end = match span_end_and_rate(alpha, theta_t, q) {
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
        let (phi, slope) = (end.p.y.atan2(end.p.x), end.angle_slope());
        let f = phi - big;
        if f == 0.0 {
            return Ok(Some((q, Some(end))));
        }
        if f < 0.0 {
            lo = q;
        } else {
            hi = q;
            bracketed = true;
        }
        let newton = q - f / slope;
        let newton_ok =
            newton > lo && newton < hi && newton <= q_max && (hi.is_finite() || newton <= 4.0 * q);
        if newton_ok {
            let step = (newton - q).abs();
            // Quadratic convergence: the error after this step is ≈ C·step² with
            // C ≈ step/previous², so step³/previous² bounds it once the iteration has settled
            // (two successive Newton steps, the second much smaller than the first).
            let settled = previous_step.is_some_and(|p: f64| {
                step <= NEWTON_SETTLED_RATIO * p
                    && step * step * step <= LOG_RATIO_TOLERANCE * p * p
            });
            if step <= LOG_RATIO_TOLERANCE || settled || one_step {
                // The end at the new q to first order (its error ≈ |P″|·step², below the
                // solver's own tolerance once settled).
                let moved = SpanEnd {
                    p: end.p + end.dp * (newton - q),
                    ..end
                };
                return Ok(Some((newton, Some(moved))));
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
            if q >= q_max {
                return Ok(None);
            }
            (4.0 * q).min(q_max)
        };
        if hi - lo <= LOG_RATIO_TOLERANCE {
            // Without a sign change the bracket closed on the overflow bound: no representable root.
            return Ok(bracketed.then_some((next, None)));
        }
        q = next;
    }
    // Not reached in practice: bisection alone shrinks [0, 600] below the tolerance in 53 steps.
    Ok(bracketed.then_some((0.5 * (lo + hi), None)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chord_angle_slope_matches_central_differences() {
        for alpha in [-2.5, -1.0, -0.2, 0.0, 0.4, 1.0, 1.7, 2.0, 3.0] {
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
    fn limit_series_matches_the_edge_and_large_ratios() {
        for theta_t in [0.05, 0.8, 2.0, 4.0, 6.2] {
            for alpha in [-3.0, -1.0, -0.3, -0.01] {
                let edge = StandardShape::new(alpha, theta_t, None)
                    .expect("valid")
                    .chord_angle(alpha);
                let series = limit_chord_angle(alpha, theta_t).expect("α < 0");
                // atan2 wraps to (−π, π]; the series does not.
                assert!(
                    wrap_angle_by_turns(edge - series).abs() < 1e-12,
                    "α {alpha} θ_T {theta_t}: {edge} vs {series}"
                );
            }
            for alpha in [1.5, 2.0, 3.0] {
                // φ(q) rises to φ_∞ like e^{−(α−1)q}: q = 60 is within rounding of it.
                let far = chord_angle_and_slope(alpha, theta_t, 60.0)
                    .expect("valid")
                    .0;
                let series = limit_chord_angle(alpha, theta_t).expect("α > 1");
                assert!(
                    wrap_angle_by_turns(far - series).abs() < 1e-11,
                    "α {alpha} θ_T {theta_t}: {far} vs {series}"
                );
            }
            assert_eq!(limit_chord_angle(0.5, theta_t), None);
        }
    }

    /// Asserts that `margin` (of G1 data on the chord (0,0)→(1,0), with θ_A = −arg t_A and
    /// θ_B = arg t_B from −0.4 in 48 steps of `step`, and α) has the sign of constructibility:
    /// clearly inside (above 0.05 rad; closer, α ≥ 0 needs ratios beyond e^{600}) must build,
    /// outside must not.
    fn assert_sign_of_constructibility(
        step: f64,
        margin: impl Fn(Point, Vec2, Point, Vec2, f64) -> f64,
    ) {
        let (a, b) = (Point::new(0.0, 0.0), Point::new(1.0, 0.0));
        let (mut inside, mut outside) = (0, 0);
        for alpha in [
            -3.0, -1.5, -1.0, -0.5, -0.3, 0.0, 0.5, 1.0, 1.5, 1.7, 2.0, 3.0,
        ] {
            for i in 0..48 {
                for j in 0..48 {
                    let (theta_a, theta_b) = (-0.4 + step * i as f64, -0.4 + step * j as f64);
                    let ta = Vec2::new(theta_a.cos(), -theta_a.sin());
                    let tb = Vec2::new(theta_b.cos(), theta_b.sin());
                    let m = margin(a, ta, b, tb, alpha);
                    let built = fit_g1(a, ta, b, tb, alpha);
                    if m > 0.05 {
                        inside += 1;
                        assert!(built.is_ok(), "α {alpha} θ {theta_a} {theta_b}: {built:?}");
                    } else if m < -1e-9 {
                        outside += 1;
                        assert!(
                            matches!(built, Err(LacError::OutsideDrawableRegion { .. })),
                            "α {alpha} θ {theta_a} {theta_b} margin {m}: {built:?}"
                        );
                    }
                }
            }
        }
        assert!(
            inside > 1000 && outside > 1000,
            "{inside} inside, {outside} outside"
        );
    }

    #[test]
    fn the_drawable_margin_has_the_sign_of_constructibility() {
        assert_sign_of_constructibility(0.053, |a, ta, b, tb, alpha| {
            drawable_margin(a, ta, b, tb, alpha).expect("finite data")
        });
    }

    #[test]
    fn both_edges_bound_the_drawable_region() {
        // In the data's own mirror frame, both edges are non-negative exactly where the data is
        // drawable, for turnings up to 3.4 rad (see `edge_margins` for beyond).
        assert_sign_of_constructibility(0.045, |a, ta, b, tb, alpha| {
            let sigma = mirror(a, ta, b, tb).expect("finite data");
            let edges = edge_margins(a, ta, b, tb, alpha, sigma).expect("finite data");
            edges[0].min(edges[1])
        });
    }

    #[test]
    fn the_edges_of_a_near_straight_segment_are_a_wedge() {
        // Near-straight data: the region is a wedge with its apex at θ_A = θ_B = 0, and the two
        // edges are linear in the angles there (homogeneous of degree one), so that their
        // linearisation holds at any step size. Held in a frame, data turned the other way (a
        // step through the apex) is outside on at least one edge.
        let (a, b) = (Point::new(0.0, 0.0), Point::new(2.0, 1.0));
        let chord = (b - a).atan2();
        for alpha in [-3.0, -1.0, -0.5, 0.5, 2.0] {
            for (u, v) in [(1.0, 1.3), (1.0, 1.9), (2.5, 1.0)] {
                let data = |t: f64| {
                    let ta = Vec2::new((chord - t * u).cos(), (chord - t * u).sin());
                    let tb = Vec2::new((chord + t * v).cos(), (chord + t * v).sin());
                    (ta, tb)
                };
                let (ta, tb) = data(1e-6);
                let sigma = mirror(a, ta, b, tb).expect("finite data");
                let unit = edge_margins(a, ta, b, tb, alpha, sigma).expect("finite data");
                for t in [1e-5, 1e-4, 1e-3] {
                    let (ta, tb) = data(t);
                    let m = edge_margins(a, ta, b, tb, alpha, sigma).expect("finite data");
                    for e in 0..2 {
                        let scaled = unit[e] * t / 1e-6;
                        assert!(
                            (m[e] - scaled).abs() <= 1e-3 * t,
                            "α {alpha} ({u}, {v}) t {t} edge {e}: {} against {scaled}",
                            m[e]
                        );
                    }
                    let (ta, tb) = data(-t);
                    let flipped = edge_margins(a, ta, b, tb, alpha, sigma).expect("finite data");
                    // Their sum, 2φ_∞ − θ_T, has the sign of the turning θ_T.
                    assert!(flipped[0] + flipped[1] < 0.0, "α {alpha} ({u}, {v}) t {t}");
                }
            }
        }
    }

    #[test]
    fn the_flat_guess_is_the_ratio_of_a_nearly_straight_span() {
        // Build nearly straight spans (turning 1e-3 rad) for known q, read their end-angle ratio
        // back, and guess q from it: the guess is the small-turning limit, so it lands within a
        // small fraction of q wherever the ratio still moves with q (away from its limit).
        for alpha in [-2.0, -1.0, -0.3, 0.0, 0.5, 1.5, 2.0, 3.0] {
            for q in [0.3, 1.0, 3.0, 6.0] {
                let theta_t = 1e-3;
                let end = span_end_and_rate(alpha, theta_t, q).expect("representable");
                let ratio = end.p.y.atan2(end.p.x) / theta_t;
                let guess = flat_ratio_guess(alpha, ratio, None).expect("inside (1/2, limit)");
                assert!(
                    (guess - q).abs() <= 1e-3 * q,
                    "α {alpha} q {q}: guessed {guess} from ratio {ratio}"
                );
            }
        }
        assert_eq!(flat_ratio_guess(1.0, 0.7, None), None);
        assert_eq!(flat_ratio_guess(-1.0, 0.5, None), None);
        assert_eq!(flat_ratio_guess(-1.0, 0.9, None), None);
    }

    #[test]
    fn closed_forms_agree_with_log_radius_quadrature() {
        for alpha in [1.0, 2.0] {
            for theta_t in [0.01, 0.5, 2.0, 3.0] {
                for q in [1e-6, 0.3, 2.0, 8.0] {
                    let shape = StandardShape::new(alpha, theta_t, Some(q)).expect("valid");
                    let (closed, _) = closed_form_end(alpha, theta_t, q).expect("α = 1, 2");
                    let shift = alpha * q;
                    let quad = log_radius_integral(alpha, shape.inv_lambda, q, shift)
                        * (shape.inv_lambda * shift.exp());
                    assert!(
                        (closed - quad).hypot() <= 1e-13 * shape.length,
                        "α {alpha} θ_T {theta_t} q {q}: {closed:?} vs {quad:?}"
                    );
                }
            }
        }
    }

    /// G1 data: start, its tangent, end, its tangent.
    type G1Data = (Point, Vec2, Point, Vec2);

    /// G1 data of a left-turning spiral, and the segments of the α values for which it is
    /// drawable, each built cold.
    fn g1_data_and_segments() -> (G1Data, Vec<(f64, LacSegment)>) {
        let data = (
            Point::ORIGIN,
            Vec2::new(1.0, -0.4),
            Point::new(2.0, 0.5),
            Vec2::new(0.3, 1.0),
        );
        let (a, ta, b, tb) = data;
        let segments = [-1.5, -0.5, 0.0, 0.5, 1.5, 2.5]
            .into_iter()
            .filter_map(|alpha| fit_g1(a, ta, b, tb, alpha).ok().map(|s| (alpha, s)))
            .collect();
        (data, segments)
    }

    #[test]
    fn a_probe_one_step_away_matches_the_full_solve() {
        let ((a, ta, b, tb), segments) = g1_data_and_segments();
        for (alpha, base) in segments {
            // The refinement's probes: a tangent turned by 1e-7 rad, α moved by 1e-6.
            let turned = Vec2::new(
                tb.x * 1e-7f64.cos() - tb.y * 1e-7f64.sin(),
                tb.x * 1e-7f64.sin() + tb.y * 1e-7f64.cos(),
            );
            for (tb1, alpha1) in [(turned, alpha), (tb, alpha + 1e-6)] {
                let exact = fit_g1(a, ta, b, tb1, alpha1).expect("drawable");
                let probe = fit_g1_probe(a, ta, b, tb1, alpha1, &base).expect("drawable");
                // The probe's error is O(h²) (its constant grows towards the drawable region's
                // edge), the shape's response O(h): measured against the response (the relative
                // change of κ1), the error is below 0.1 % of it, so a difference quotient of the
                // probe is the full solve's to that.
                let response = (exact.kappa1() - base.kappa1()).abs() / base.kappa1().abs();
                assert!(response > 0.0, "α {alpha}: the probe changed nothing");
                for (x, y) in [
                    (probe.kappa0(), exact.kappa0()),
                    (probe.kappa1(), exact.kappa1()),
                    (probe.length(), exact.length()),
                ] {
                    let change = response * y.abs();
                    assert!(
                        (x - y).abs() <= 1e-3 * change,
                        "α {alpha}: {x} vs {y} (change {change:e})"
                    );
                }
            }
        }
    }

    #[test]
    fn warm_start_gives_the_same_segment() {
        let ((a, ta, b, tb), segments) = g1_data_and_segments();
        for (alpha, cold) in segments {
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

    #[test]
    fn the_warm_start_carries_the_flat_models_defect() {
        // The same span after a step (its end tangent turned, its α moved): the warm start from
        // the old segment lands closer to the new ratio than the old ratio does, by orders of
        // magnitude for a nearly straight span (where q is most sensitive to the angles).
        let rotate = |v: Vec2, by: f64| {
            Vec2::new(
                v.x * by.cos() - v.y * by.sin(),
                v.x * by.sin() + v.y * by.cos(),
            )
        };
        let (a, b) = (Point::ORIGIN, Point::new(2.0, 0.0));
        for (angle_a, angle_b) in [(-0.004, 0.007), (-0.3, 0.9), (-0.5, 1.3)] {
            let (ta, tb) = (
                rotate(Vec2::new(1.0, 0.0), angle_a),
                rotate(Vec2::new(1.0, 0.0), angle_b),
            );
            for alpha in [-1.5, -0.5, 0.0, 0.5, 1.5, 2.5] {
                let Ok(near) = fit_g1(a, ta, b, tb, alpha) else {
                    continue;
                };
                for (turn, d_alpha) in [(2e-4, 0.0), (0.0, 0.05), (1e-3, -0.02)] {
                    let (tb1, alpha1) = (rotate(tb, turn * (angle_b - angle_a)), alpha + d_alpha);
                    let Ok(exact) = fit_g1(a, ta, b, tb1, alpha1) else {
                        continue;
                    };
                    let n = Normalised::new(b - a, ta, tb1);
                    let q = log_ratio(&exact).expect("a spiral");
                    let q_near = log_ratio(&near).expect("a spiral");
                    let warm =
                        warm_start(&near, alpha1, n.theta_t, n.ea.max(n.eb)).expect("a start");
                    // Nearly straight: the flat model is the span to O(θ_T²) and the start within
                    // 1e-5 of the step's effect (seen: 6e-5 at most); turning: measured 0.001 to
                    // 0.6 (α near 1/2, where the model's α dependence is weakest).
                    let bound = if n.theta_t < 0.02 { 1e-4 } else { 0.75 };
                    assert!(
                        (warm - q).abs() <= bound * (q_near - q).abs(),
                        "turns {angle_a}, {angle_b}, α {alpha} → {alpha1}, turn {turn}: \
                         q {q}, near {q_near}, warm {warm}"
                    );
                }
            }
        }
    }
}
