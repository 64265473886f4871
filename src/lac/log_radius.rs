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
//!
//! ## The settling tail (α < 0)
//! For α < 0 (β < 0) the phase settles: θ(u) = θ_∞ − ε(u) with θ_∞ = c/|β| and
//! ε(u) = θ_∞·e^{βu}, the turning still to come. From a point u₀ where ε₀ = ε(u₀) is at most
//! [`SERIES_MAX_TURNING`], e^{−iε} is expanded in its power series and every term integrates in
//! closed form, ε(u)^m = ε₀^m·e^{mβ(u−u₀)}:
//!
//! ∫_{u₀}^U e^{αu}·e^{iθ} du = e^{iθ_∞}·e^{αu₀}·Σ_m ((−iε₀)^m/m!)·E_m,
//! E_m = ∫₀^{U−u₀} e^{k_m t} dt = expm1(k_m(U − u₀))/k_m (1/|k_m| for U = ∞), k_m = α + mβ < 0,
//!
//! and J's tail is θ_∞ times I's minus the same series with ε₀^{m+1}·E_{m+1}. The terms fall
//! like ε₀^m/m! (below 1e-17 of the sum after about twenty at ε₀ = 1) and the phase moves by at
//! most ε₀ over the tail, so the sum cannot cancel. A κ = 0 end (U = ∞), whose tail Gauss–Legendre
//! panels had to follow for tens of e-folds of the slowly decaying amplitude (a dozen panels of
//! up to 16 nodes at α near 0), is then a few panels at most, none where the whole span turns
//! less than a radian.

use super::quadrature::Panel;
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

/// For α < 0: the rest of the integral is summed as the settling tail's series (module
/// documentation) once the turning still to come is at most this many radians: its terms then
/// fall from the first, at least as fast as 1/m!.
pub const SERIES_MAX_TURNING: f64 = 1.0;

/// The settling tail's series stops once a term is below this fraction of the sum (half an ulp).
const TAIL_TERM_EPS: f64 = 1e-17;

/// Most terms of the settling tail's series: at ε₀ = 1 the m-th term is at most 1/m!, below
/// 1e-17 from m = 19 on.
const SERIES_MAX_TERMS: usize = 30;

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
            // β < α < 0: the phase settles towards θ_∞ = c/|β|.
            let to_come = c / -beta * (beta * lo).exp();
            if to_come <= SERIES_MAX_TURNING {
                let (tail, tail_moment) =
                    settling_tail(alpha, c, lo, upper - lo, shift, to_come, with_moment);
                acc += tail;
                moment += tail_moment;
                break;
            }
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
        let Panel { mid, half } = Panel::over(lo, hi);
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

/// The settling tail of [`integrals`] for α < 0 (module documentation): e^{−shift} times
/// ∫_{u₀}^{u₀+T} e^{αu}·e^{iθ(u)} du and, with `with_moment`, the same with the extra factor θ(u),
/// for T ∈ (0, ∞] and ε₀ = θ_∞ − θ(u₀) ∈ [0, [`SERIES_MAX_TURNING`]].
fn settling_tail(
    alpha: f64,
    c: f64,
    u0: f64,
    span: f64,
    shift: f64,
    eps0: f64,
    with_moment: bool,
) -> (Vec2, Vec2) {
    let beta = alpha - 1.0;
    let theta_inf = c / -beta;
    // E_m = ∫₀^T e^{k_m t} dt, k_m = α + mβ < 0.
    let e_m = |m: usize| {
        let k = alpha + m as f64 * beta;
        if span.is_finite() {
            (k * span).exp_m1() / k
        } else {
            1.0 / -k
        }
    };
    // Σ_m ((−iε₀)^m/m!)·E_{m+offset}, offset 0 for I and 1 for the moment.
    let series = |offset: usize| {
        let mut sum = Vec2::ZERO;
        // (−i)^m·ε₀^m/m! as a complex number.
        let mut power = Vec2::new(1.0, 0.0);
        for m in 0..SERIES_MAX_TERMS {
            let term = power * e_m(m + offset);
            sum += term;
            if term.hypot() <= TAIL_TERM_EPS * sum.hypot() {
                break;
            }
            power = Vec2::new(power.y, -power.x) * (eps0 / (m + 1) as f64);
        }
        sum
    };
    let front = cis(theta_inf) * (alpha * u0 - shift).exp();
    let tail = cmul(front, series(0));
    let moment = if with_moment {
        tail * theta_inf - cmul(front, series(1)) * eps0
    } else {
        Vec2::ZERO
    };
    (tail, moment)
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
    fn the_moment_is_the_derivative_in_c() {
        // ∂I/∂c = (i/c)·J (see [`integrals`]), through the settling tail and without it.
        for alpha in [-3.0, -1.0, -0.3, -0.01, 0.5, 1.5] {
            for c in [0.05, 0.4, 1.0, 3.0] {
                for upper in [0.3, 2.0, 9.0, f64::INFINITY] {
                    if alpha >= 0.0 && !upper.is_finite() {
                        continue;
                    }
                    let shift = if alpha > 0.0 { alpha * upper } else { 0.0 };
                    let (i, j) = integrals(alpha, c, upper, shift, true);
                    let h = 1e-6 * c;
                    let d = (integrals(alpha, c + h, upper, shift, false).0
                        - integrals(alpha, c - h, upper, shift, false).0)
                        / (2.0 * h);
                    let expected = Vec2::new(-j.y, j.x) / c;
                    let err = (d - expected).hypot();
                    assert!(
                        err <= 1e-7 * (expected.hypot() + i.hypot() / c),
                        "α {alpha} c {c} U {upper}: {d:?} vs {expected:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_settling_tail_agrees_with_panels() {
        // The series alone over the whole span (ε₀ = θ_∞, every span here turns at most a
        // radian in all) against an independent fine composite rule.
        for alpha in [-3.0, -1.0, -0.3, -0.01] {
            for c in [0.1, 0.6, 1.0] {
                let beta = alpha - 1.0;
                for upper in [0.5, 4.0, 30.0, f64::INFINITY] {
                    let (tail, _) = settling_tail(alpha, c, 0.0, upper, 0.0, c / -beta, false);
                    let reference = quadrature_reference(alpha, c, upper);
                    let err = (tail - reference).hypot();
                    assert!(
                        err <= 1e-14 * reference.hypot(),
                        "α {alpha} c {c} U {upper}: {tail:?} vs {reference:?} ({err:e})"
                    );
                }
            }
        }
    }

    /// I(α, c, U) by 16-node composite Gauss–Legendre panels of width 1/16 (U = ∞ cut where the
    /// amplitude falls below 1e-18): an independent reference for the series.
    fn quadrature_reference(alpha: f64, c: f64, upper: f64) -> Vec2 {
        let beta = alpha - 1.0;
        let end = if upper.is_finite() {
            upper
        } else {
            (1e-18f64).ln() / alpha
        };
        let panels = (end * 16.0).ceil().max(1.0) as usize;
        let width = end / panels as f64;
        // Thousands of panels: summed with Neumaier's compensation, or the reference's own
        // rounding (1e-13 of the sum) would exceed the error measured.
        let (mut sum, mut carry) = ([0.0f64; 2], [0.0f64; 2]);
        for p in 0..panels {
            let (lo, hi) = (p as f64 * width, (p + 1) as f64 * width);
            let mut panel = Vec2::ZERO;
            for &(w, x) in GAUSS_LEGENDRE_COEFFS_16 {
                let u = 0.5 * (lo + hi) + 0.5 * (hi - lo) * x;
                let theta = c * (beta * u).exp_m1() / beta;
                panel += cis(theta) * (w * 0.5 * (hi - lo) * (alpha * u).exp());
            }
            for (k, v) in [panel.x, panel.y].into_iter().enumerate() {
                let t = sum[k] + v;
                carry[k] += if sum[k].abs() >= v.abs() {
                    (sum[k] - t) + v
                } else {
                    (v - t) + sum[k]
                };
                sum[k] = t;
            }
        }
        Vec2::new(sum[0] + carry[0], sum[1] + carry[1])
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
