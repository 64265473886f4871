//! Quadrature of the unit tangent in the log radius of curvature, w = ln ρ: the fast path for
//! P = ∫ e^{iθ} ds on the standard form (see [`super::standard`]).
//!
//! ## Why w
//! On the standard form ρ^α = 1 + αΛs, so ds = ρ^α dw/Λ = e^{αw} dw/Λ and
//! θ(w) = ∫ e^{−w} ds = (e^{(α−1)w} − 1)/((α−1)Λ). Hence, from s = a (w = w_a, θ = θ_a) on,
//!
//! ∫_a^b e^{iθ(s)} ds = e^{iθ_a}·e^{α w_a}/Λ · ∫₀^U e^{αu}·e^{i c·u·exprel(βu)} du,
//!
//! with u = w − w_a, U = w_b − w_a, β = α − 1 and c = e^{β w_a}/Λ (= ρ_a^α/(Λρ_a)). The integrand
//! is an **entire** function of u: the branch point that the arc-length integrand has where
//! 1 + αΛs = 0 is gone, so Gauss–Legendre panels may be as wide as the integrand's growth allows,
//! instead of staying clear of a singularity (compare [`super::quadrature`]). A typical pen span
//! (turning ≤ 2 rad, curvature ratio ≤ e³) needs one or two panels of 8 to 16 nodes.
//!
//! ## Panels
//! A panel [u₀, u₀ + h] obeys (its node count then follows from its size, [`rule_for`]),
//! 1. **growth**: |α|·h ≤ [`PANEL_MAX_GROWTH`] (the amplitude e^{αu} changes by at most e⁴);
//! 2. **turning**: c·e^{βu₀}·h·exprel(|β|h) ≤ [`PANEL_MAX_TURNING`] (the phase advance over the
//!    panel, taken with the faster of the two exponential rates so that it bounds the phase's
//!    variation in the complex neighbourhood of the panel that governs convergence).
//!
//! An entire integrand whose exponent varies by at most g over a panel is integrated by n-node
//! Gauss–Legendre with a relative error of order (g/2)^{2n} times a factor that falls
//! factorially in n ([`rule_for`] gives it); the node count is the smallest that keeps it below
//! 1e-19. The reference tables confirm 1e-15.
//!
//! ## Unbounded U (α < 0)
//! At the κ = 0 end of an α < 0 curve U = ∞, and far along a long α < 0 span it is large. The
//! amplitude e^{αu} then decays: once the mass still to come, e^{αu₀}/|α|, is below
//! [`NEGLIGIBLE_MASS`] of the integral so far, it is added with the phase of u₀ (its phase can
//! move by at most the remaining turning; the error is below that bound times the mass).
//! Symmetrically for α > 0, where the mass sits at the top end, the part of [0, U] more than
//! [`SKIP_DECADES`]/α below U carries less than e^{−40} of the total and is skipped.

use super::special::{cis, cis_small, cmul, exprel};
use crate::geom::Vec2;
use kurbo::common::{GAUSS_LEGENDRE_COEFFS_8, GAUSS_LEGENDRE_COEFFS_11, GAUSS_LEGENDRE_COEFFS_16};

/// Largest change of the exponent αu of the amplitude over one panel (rule 1).
pub const PANEL_MAX_GROWTH: f64 = 4.0;

/// Largest phase advance over one panel, radians (rule 2).
pub const PANEL_MAX_TURNING: f64 = 2.0;

/// For α < 0: the mass still to come is neglected once below this fraction of the integral so far
/// (half an ulp of the result).
pub const NEGLIGIBLE_MASS: f64 = 1e-17;

/// For α > 0: the stretch of u more than this many e-folds (divided by α) below U is skipped; its
/// share of the integral is below e^{−40} ≈ 4e-18.
pub const SKIP_DECADES: f64 = 40.0;

/// The paired node phases use e^{βv} = 1 + βv·exprel(βv) only while |βv| is at most this: below
/// it the sum cannot cancel (e^{−1} > 0.36); beyond, each node's θ is evaluated directly.
const PAIR_PHASE_MAX_EXPONENT: f64 = 1.0;

/// Safety cap on the number of panels (each at least halves nothing: rules 1 and 2 make panels of
/// width ≥ min(4/|α|, …) that grow geometrically where the turning rate decays). Reached only by
/// absurd inputs; the sum so far is returned.
const MAX_PANELS: usize = 100_000;

/// Largest panel size g (see [`rule_for`]) integrated with 8 nodes.
pub const GL8_MAX_SIZE: f64 = 1.5;

/// Largest panel size g integrated with 11 nodes (16 beyond).
pub const GL11_MAX_SIZE: f64 = 3.0;

/// The Gauss–Legendre rule for a panel over which the integrand's exponent varies by at most
/// `size` = g (the amplitude's growth |α|h plus the phase advance): the fewest nodes whose error
/// stays below 1e-19 of the panel's magnitude. For e^{zt} on t ∈ [−1, 1] the n-node error is
/// 2^{2n+1}(n!)⁴/((2n+1)((2n)!)³)·|z|^{2n}, with |z| = g/2: 8 nodes at g = 1.5 give 2e-20,
/// 11 nodes at g = 3 give 5e-24, 16 nodes at the panel limits (g = 6) 5e-30. Pen spans are
/// mostly one panel of g ≤ 1.5, so half the nodes of a fixed 16-node rule.
pub fn rule_for(size: f64) -> &'static [(f64, f64)] {
    if size <= GL8_MAX_SIZE {
        GAUSS_LEGENDRE_COEFFS_8
    } else if size <= GL11_MAX_SIZE {
        GAUSS_LEGENDRE_COEFFS_11
    } else {
        GAUSS_LEGENDRE_COEFFS_16
    }
}

/// e^{−shift}·I(α, c, U), where I(α, c, U) = ∫₀^U e^{αu}·e^{i c·u·exprel((α−1)u)} du for
/// U ∈ (0, ∞] (U = ∞ only when α < 0), c ≥ 0: the building block of the module documentation.
/// The factor e^{−shift} is applied inside the integrand, so that for α > 0 and large U the caller
/// can pass shift = αU and get a result of order 1 where I itself would overflow.
pub(crate) fn log_radius_integral(alpha: f64, c: f64, upper: f64, shift: f64) -> Vec2 {
    integrals(alpha, c, upper, shift, false).0
}

/// e^{−shift}·(I, J) with I as in [`log_radius_integral`] and
/// J = ∫₀^U e^{αu}·e^{iθ(u)}·θ(u) du, θ(u) = c·u·exprel((α−1)u), on the same nodes: J is what the
/// derivative of I with respect to c needs (∂I/∂c = (i/c)·J). J is only accumulated when
/// `with_moment` is set (it is zero otherwise).
pub(crate) fn integrals(
    alpha: f64,
    c: f64,
    upper: f64,
    shift: f64,
    with_moment: bool,
) -> (Vec2, Vec2) {
    let beta = alpha - 1.0;
    let theta = |u: f64| c * u * exprel(beta * u);
    let mut lo = if alpha > 0.0 && upper.is_finite() {
        (upper - SKIP_DECADES / alpha).max(0.0)
    } else {
        0.0
    };
    let mut acc = Vec2::ZERO;
    let mut moment = Vec2::ZERO;
    for _ in 0..MAX_PANELS {
        if lo >= upper {
            break;
        }
        if alpha < 0.0 {
            let mass = (alpha * lo - shift).exp() / -alpha;
            if lo > 0.0 && mass <= NEGLIGIBLE_MASS * acc.hypot() {
                // ∫_lo^U e^{αu} du ≈ mass (U = ∞) or mass·(1 − e^{α(U−lo)}).
                let rest = if upper.is_finite() {
                    mass * -(alpha * (upper - lo)).exp_m1()
                } else {
                    mass
                };
                let th = theta(lo);
                acc += cis(th) * rest;
                if with_moment {
                    moment += cis(th) * (rest * th);
                }
                break;
            }
        }
        let rate = c * (beta * lo).exp();
        let mut h = if alpha == 0.0 {
            f64::INFINITY
        } else {
            PANEL_MAX_GROWTH / alpha.abs()
        };
        if upper.is_finite() {
            h = h.min(upper - lo);
        }
        if !h.is_finite() {
            // α = 0 with U = ∞ cannot occur (U = ∞ needs α < 0); a finite start width otherwise.
            h = 1.0;
        }
        // Rule 2: shrink until the phase advance fits (each halving at least halves it).
        while rate * h * exprel(beta.abs() * h) > PANEL_MAX_TURNING && h > 0.0 {
            h *= 0.5;
        }
        let hi = if upper.is_finite() && lo + h >= upper {
            upper
        } else {
            lo + h
        };
        if hi <= lo {
            break;
        }
        let (half, mid) = (0.5 * (hi - lo), 0.5 * (hi + lo));
        let width = hi - lo;
        let size = alpha.abs() * width + rate * width * exprel(beta.abs() * width);
        // Nodes in ± pairs about the middle (the rules are symmetric): with r = c·e^{β·mid},
        // θ(mid ± v) = θ(mid) ± r·v·exprel(±βv), exprel(−βv) = exprel(βv)/e^{βv}, and
        // e^{α(mid ± v)} = e^{α·mid}·e^{±αv}: one expm1 and one exp per pair instead of two of
        // each per node, and e^{iθ} = e^{iθ(mid)}·e^{iδ} by the small-angle series.
        let theta_mid = theta(mid);
        let phase_mid = cis(theta_mid);
        let rate_mid = c * (beta * mid).exp();
        let amplitude_mid = (alpha * mid - shift).exp();
        let (mut sum, mut sum_moment) = (Vec2::ZERO, Vec2::ZERO);
        let mut add = |weight: f64, delta: f64, amplitude: f64| {
            let term = cmul(phase_mid, cis_small(delta)) * (weight * amplitude);
            sum += term;
            if with_moment {
                sum_moment += term * (theta_mid + delta);
            }
        };
        for &(weight, x) in rule_for(size) {
            if x < 0.0 {
                continue;
            }
            if x == 0.0 {
                add(weight, 0.0, amplitude_mid);
                continue;
            }
            let v = half * x;
            let (above, below) = if (beta * v).abs() <= PAIR_PHASE_MAX_EXPONENT {
                let rel = exprel(beta * v);
                let grow = 1.0 + beta * v * rel; // e^{βv}
                (rate_mid * v * rel, -rate_mid * v * rel / grow)
            } else {
                (theta(mid + v) - theta_mid, theta(mid - v) - theta_mid)
            };
            // |αv| ≤ PANEL_MAX_GROWTH/2: no overflow either way.
            let up = (alpha * v).exp();
            add(weight, above, amplitude_mid * up);
            add(weight, below, amplitude_mid / up);
        }
        acc += sum * half;
        moment += sum_moment * half;
        lo = hi;
    }
    (acc, moment)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lac::quadrature;
    use crate::lac::standard::StandardLac;

    /// ∫₀^s e^{iθ} ds on the standard form through the w substitution (a = 0, w_a = 0, θ_a = 0).
    fn via_log_radius(lac: &StandardLac, s: f64) -> Vec2 {
        let w = lac.ln_rho(s);
        log_radius_integral(lac.alpha(), 1.0 / lac.lambda(), w, 0.0) * (1.0 / lac.lambda())
    }

    #[test]
    fn agrees_with_arc_length_quadrature() {
        for alpha in [
            -3.0, -1.5, -1.0, -0.3, -1e-9, 0.0, 1e-9, 0.5, 0.999, 1.001, 1.5, 2.5, 3.0,
        ] {
            for lambda in [1e-6, 0.05, 0.3, 1.0, 4.0] {
                let lac = StandardLac::new(alpha, lambda).expect("valid");
                let s_max = lac.s_max().unwrap_or(f64::INFINITY);
                for s in [1e-3f64, 0.1, 0.7, 2.0, 6.0] {
                    let s = s.min(s_max);
                    let reference = quadrature::integrate(&lac, 0.0, s);
                    let fast = via_log_radius(&lac, s);
                    let err = (fast - reference).hypot();
                    assert!(
                        err <= 1e-14 * s.max(1e-300) + 1e-15 * reference.hypot(),
                        "α {alpha} Λ {lambda} s {s}: {fast:?} vs {reference:?} ({err:e})"
                    );
                }
            }
        }
    }

    #[test]
    fn the_rules_come_in_exact_pairs() {
        // `integrals` takes the nodes in ± pairs: every node but an exact 0 must have its mirror
        // with the same weight, or a pair would be counted twice or once.
        for rule in [
            GAUSS_LEGENDRE_COEFFS_8,
            GAUSS_LEGENDRE_COEFFS_11,
            GAUSS_LEGENDRE_COEFFS_16,
        ] {
            let weight: f64 = rule.iter().map(|&(w, _)| w).sum();
            assert!((weight - 2.0).abs() < 1e-14);
            for &(w, x) in rule.iter().filter(|&&(_, x)| x > 0.0) {
                assert!(rule.iter().any(|&(v, y)| y == -x && v == w), "{x}");
            }
            let zeros = rule.iter().filter(|&&(_, x)| x == 0.0).count();
            let positive = rule.iter().filter(|&&(_, x)| x > 0.0).count();
            assert_eq!(2 * positive + zeros, rule.len());
        }
    }

    #[test]
    fn zero_curvature_end_matches_arc_length_quadrature() {
        for alpha in [-3.0, -1.0, -0.2, -0.01, -0.004862580243074322] {
            for lambda in [0.1, 1.0, 3.0, 5.996762044496054] {
                let lac = StandardLac::new(alpha, lambda).expect("valid");
                let s_max = lac.s_max().expect("α < 0");
                let reference = quadrature::integrate(&lac, 0.0, s_max);
                let fast = log_radius_integral(alpha, 1.0 / lambda, f64::INFINITY, 0.0) / lambda;
                let err = (fast - reference).hypot();
                assert!(
                    err <= 1e-13 * s_max,
                    "α {alpha} Λ {lambda}: {fast:?} vs {reference:?} ({err:e})"
                );
            }
        }
    }
}
