//! Adaptive-panel Gauss–Legendre quadrature of the unit tangent, P = ∫ e^{iθ(s)} ds, for the
//! standard form (see [`super::standard`]).
//!
//! ## Panels
//! Marching forward from the lower limit, each panel [a, b] obeys two rules (κ decreases along s,
//! so its maximum on the panel is κ(a) = 1/ρ(a)):
//!
//! 1. **Turning**: b − a ≤ [`PANEL_MAX_TURNING`]·ρ(a), so the panel turns by at most that angle.
//! 2. **Radius growth**: ln ρ(b) − ln ρ(a) ≤ D(α) = min([`PANEL_MAX_LOG_RHO`],
//!    [`PANEL_BRANCH_LOG`]/|α|), i.e. b − a = ρ(a)^α·D·exprel(αD)/Λ. The integrand has a branch
//!    point where 1 + αΛs = 0, at distance ρ(a)^α/(|α|Λ) from a (behind the panel for α > 0, ahead
//!    of it for α < 0); limiting ρ^α to a factor 3 per panel keeps that point at least half a panel
//!    length beyond the panel's end. For α → 0 the branch point recedes to infinity but e^{−Λs}
//!    still grows in the complex plane; the ln ρ cap bounds that.
//!
//! Both rules are scale-free in ρ, so a curvature ratio of 1e22 costs ≈ ln(1e22)/D panels
//! (≈ 50 for α = 0), not 1e22/(uniform step). With 16 nodes and these bounds, a panel's error is
//! below 1e-16 of its length (checked against the reference tables).
//!
//! ## The κ = 0 end (α < 0)
//! Near s_max the tangent angle behaves like θ_max − c·(s_max − s)^{(α−1)/α}, a branch point at the
//! very end of the interval. Once the remaining turning g = θ_max − θ(a) ≤ [`TAIL_MAX_TURNING`], the
//! rest of the interval is done exactly by a power series. With r = 1 + αΛs = 1 − s/s_max and
//! p = (α − 1)/α > 1, θ = θ_max(1 − r^p), so
//!
//! ∫ e^{iθ} ds = −s_max·e^{iθ_max} ∫ e^{−iθ_max r^p} dr,   F(r) := ∫₀ʳ e^{−iθ_max ρ^p} dρ
//! = r·Σ_{k≥0} (−i g(r))^k / (k!·(pk + 1)),   g(r) = θ_max r^p,
//!
//! which converges like g^k/k! (g ≤ 0.5: 17 terms for 1e-18).

use super::special::{SERIES_MAX_TERMS, SERIES_TERM_EPS, cis, cmul, exprel};
use super::standard::StandardLac;
use crate::geom::Vec2;
use kurbo::common::GAUSS_LEGENDRE_COEFFS_16;

/// Largest turning angle (radians) of one panel. With 16 nodes, a panel turning by φ integrates
/// e^{iθ} about as well as a degree-31 polynomial approximates e^{iφx/2} on [−1, 1]: error
/// ≈ (φ/2)^32/32! ≈ 1e-45 for φ = 1, so turning is never the binding limit at 1 rad.
pub const PANEL_MAX_TURNING: f64 = 1.0;

/// Largest growth of ln ρ over one panel (a factor e in the radius of curvature), the bound that
/// applies for α near 0 where the branch point is far away but κ = e^{−Λs} still varies.
pub const PANEL_MAX_LOG_RHO: f64 = 1.0;

/// |α|·(ln ρ growth) per panel: ρ^α changes by at most a factor 3 over a panel, which keeps the
/// branch point of (1 + αΛs)^{1/α} at least half a panel length outside it (Bernstein ellipse
/// parameter ≥ 2 + √3, so 16-node Gauss–Legendre converges like (2 + √3)^{−32} ≈ 5e-19).
pub const PANEL_BRANCH_LOG: f64 = 1.098_612_288_668_109_8; // ln 3

/// For α < 0: once at most this much turning remains before the κ = 0 point, the rest is summed
/// by the power series of the module documentation. Its terms fall like 0.5^k/k!, so 17 terms
/// reach 1e-18.
pub const TAIL_MAX_TURNING: f64 = 0.5;

/// The tail series computes ∫_a^b as (r_a − r_b) (exact, from b − a) plus the difference of the
/// k ≥ 1 terms, whose rounding error is ≈ 1e-16·g(a)·(s_max − a). It is only used when
/// g(a)·(s_max − a) ≤ this factor times (b − a), keeping that error below 1e-15 of the
/// integration length; otherwise the graded panels (just as accurate, but more of them) are used.
/// Weighting by g matters for α → 0⁻, where ρ grows so fast near the κ = 0 end that graded panels
/// would need ~1/|α| of them, while the turning left (hence g) is tiny.
pub const TAIL_REACH: f64 = 4.0;

/// ∫_a^b e^{iθ(s)} ds (as a complex number) on the standard form by adaptive panels, for
/// 0 ≤ a ≤ b ≤ s_max. Always numerical, whatever α: [`StandardLac::point`] dispatches to the
/// closed forms for α = 1, 2; this entry point exists to cross-check them.
pub fn integrate(lac: &StandardLac, a: f64, b: f64) -> Vec2 {
    let s_max = lac.s_max();
    let b = s_max.map_or(b, |sm| b.min(sm));
    let mut acc = Vec2::ZERO;
    let mut lo = a;
    while lo < b {
        if let (Some(sm), Some(g)) = (s_max, lac.remaining_turning(lo))
            && g <= TAIL_MAX_TURNING
            && g * (sm - lo) <= TAIL_REACH * (b - lo)
        {
            acc += tail(lac, sm, lo, b);
            break;
        }
        let mut hi = (lo + panel_width(lac, lo)).min(b);
        if hi <= lo {
            // The panel is below the resolution of `lo` (only for absurd turning): finish.
            hi = b;
        }
        acc += gauss_legendre(lac, lo, hi);
        lo = hi;
    }
    acc
}

/// Width of the panel starting at `a` (rules 1 and 2 of the module documentation).
fn panel_width(lac: &StandardLac, a: f64) -> f64 {
    let ln_rho = lac.ln_rho(a);
    let by_turning = PANEL_MAX_TURNING * ln_rho.exp();
    let alpha = lac.alpha();
    let lambda = lac.lambda();
    if lambda == 0.0 {
        return by_turning;
    }
    let d = if alpha == 0.0 {
        PANEL_MAX_LOG_RHO
    } else {
        PANEL_MAX_LOG_RHO.min(PANEL_BRANCH_LOG / alpha.abs())
    };
    // ρ(a)^α = e^{α ln ρ(a)}; Δs = ρ(a)^α (e^{αD} − 1)/(αΛ).
    let by_growth = (alpha * ln_rho).exp() * d * exprel(alpha * d) / lambda;
    by_turning.min(by_growth)
}

/// 16-node Gauss–Legendre rule for ∫_a^b e^{iθ(s)} ds.
fn gauss_legendre(lac: &StandardLac, a: f64, b: f64) -> Vec2 {
    let half = 0.5 * (b - a);
    let mid = 0.5 * (a + b);
    let mut sum = Vec2::ZERO;
    for &(w, x) in GAUSS_LEGENDRE_COEFFS_16 {
        sum += cis(lac.theta(mid + half * x)) * w;
    }
    sum * half
}

/// ∫_a^b e^{iθ} ds by the κ = 0 tail series (α < 0, `s_max` = the κ = 0 point).
fn tail(lac: &StandardLac, s_max: f64, a: f64, b: f64) -> Vec2 {
    let alpha = lac.alpha();
    let p = (alpha - 1.0) / alpha;
    let theta_max = 1.0 / ((1.0 - alpha) * lac.lambda());
    // r = 1 + αΛs = ρ^α, from ln ρ to stay exact (r = 0) at the κ = 0 end.
    let r = |s: f64| (alpha * lac.ln_rho(s)).exp();
    // F(r) − r = r·Σ_{k≥1} (−i g)^k / (k!(pk + 1)), g = θ_max r^p.
    let f1 = |r: f64| -> Vec2 {
        if r <= 0.0 {
            return Vec2::ZERO;
        }
        let g = theta_max * r.powf(p);
        let step = Vec2::new(0.0, -g);
        let mut power = Vec2::new(1.0, 0.0); // (−ig)^k / k!
        let mut sum = Vec2::ZERO;
        for k in 1..SERIES_MAX_TERMS {
            power = cmul(power, step) * (1.0 / k as f64);
            let term = power * (1.0 / (p * k as f64 + 1.0));
            sum += term;
            if term.hypot() < SERIES_TERM_EPS {
                break;
            }
        }
        sum * r
    };
    // ds = −s_max dr: ∫_a^b ds = s_max ∫_{r_b}^{r_a} dr, and s_max·(r_a − r_b) = b − a exactly.
    let leading = Vec2::new(b - a, 0.0);
    cmul(cis(theta_max), leading + (f1(r(a)) - f1(r(b))) * s_max)
}
