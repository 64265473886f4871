//! Cancellation-free elementary helpers shared by the LAC formulas.
//!
//! Every LAC quantity is a limit-continuous function of α: the α = 0 and α = 1 special cases of
//! the textbook formulas are removable singularities of the general one. Written with
//! `exprel(x) = (eˣ − 1)/x` and `lnrel(y) = ln(1 + y)/y` (both → 1 as the argument → 0, computed
//! from `exp_m1`/`ln_1p`), one formula covers every α with full relative accuracy, including α
//! near but not equal to 0 or 1, and the circle limit Λ → 0.
//!
//! Complex numbers are carried as [`Vec2`] (`x` = real part, `y` = imaginary part).

use crate::geom::Vec2;

/// Below this |x|, `exprel` and `lnrel` use a two-term Taylor series instead of the quotient.
/// The quotient `exp_m1(x)/x` is itself accurate for any x ≠ 0 (exp_m1 is relatively accurate);
/// the series only avoids 0/0 at x = 0 and subnormal quotients. The neglected term is x³/24
/// (resp. x³/4) < 1e-24 relative, far below f64 resolution.
const RELATIVE_SERIES_BELOW: f64 = 1e-8;

/// Below this |x|, `sinc` uses its Taylor series 1 − x²/6 + x⁴/120; the neglected x⁶/5040 term is
/// < 2e-28 there, while `sin(x)/x` would be exact anyway: the series only avoids 0/0.
const SINC_SERIES_BELOW: f64 = 1e-4;

/// Terms of a convergent power series smaller than this (relative to the leading term, which is
/// O(1) wherever the series are used) are dropped: 1e-18 is below half an ulp of 1.
pub(crate) const SERIES_TERM_EPS: f64 = 1e-18;

/// Safety cap on the number of terms of the power series used here. Every series is only used
/// where its argument is ≤ 1 in magnitude, where 25 terms already reach 1/25! ≈ 6e-26.
pub(crate) const SERIES_MAX_TERMS: usize = 40;

/// `exprel(x) = (eˣ − 1)/x`, continuous at 0 with value 1; `exprel(−∞) = 0`.
pub(crate) fn exprel(x: f64) -> f64 {
    if x.abs() < RELATIVE_SERIES_BELOW {
        1.0 + x * (0.5 + x / 6.0)
    } else {
        x.exp_m1() / x
    }
}

/// `lnrel(y) = ln(1 + y)/y`, continuous at 0 with value 1; `+∞` at y = −1.
pub(crate) fn lnrel(y: f64) -> f64 {
    if y.abs() < RELATIVE_SERIES_BELOW {
        1.0 + y * (-0.5 + y / 3.0)
    } else {
        y.ln_1p() / y
    }
}

/// `sinc(x) = sin(x)/x`, continuous at 0 with value 1.
pub(crate) fn sinc(x: f64) -> f64 {
    if x.abs() < SINC_SERIES_BELOW {
        let x2 = x * x;
        1.0 - x2 / 6.0 * (1.0 - x2 / 20.0)
    } else {
        x.sin() / x
    }
}

/// The unit complex number `e^{iθ}`.
pub(crate) fn cis(theta: f64) -> Vec2 {
    let (s, c) = theta.sin_cos();
    Vec2::new(c, s)
}

/// Largest |δ| for which [`cis_small`] sums its series; beyond it, `sin_cos`.
pub(crate) const CIS_SERIES_MAX: f64 = 1.0;

/// 1/(2k)! for k = 0..=10: cos δ = Σ (−1)^k·δ^{2k}/(2k)!; at |δ| ≤ 1 the first term left out,
/// δ^{22}/22!, is below 1e-21.
const COS_SERIES: [f64; 11] = [
    1.0,
    1.0 / 2.0,
    1.0 / 24.0,
    1.0 / 720.0,
    1.0 / 40_320.0,
    1.0 / 3_628_800.0,
    1.0 / 479_001_600.0,
    1.0 / 87_178_291_200.0,
    1.0 / 20_922_789_888_000.0,
    1.0 / 6_402_373_705_728_000.0,
    1.0 / 2_432_902_008_176_640_000.0,
];

/// 1/(2k+1)! for k = 0..=10: sin δ = δ·Σ (−1)^k·δ^{2k}/(2k+1)!.
const SIN_SERIES: [f64; 11] = [
    1.0,
    1.0 / 6.0,
    1.0 / 120.0,
    1.0 / 5_040.0,
    1.0 / 362_880.0,
    1.0 / 39_916_800.0,
    1.0 / 6_227_020_800.0,
    1.0 / 1_307_674_368_000.0,
    1.0 / 355_687_428_096_000.0,
    1.0 / 121_645_100_408_832_000.0,
    1.0 / 51_090_942_171_709_440_000.0,
];

/// `e^{iδ}` for a small angle: the Taylor series of cos and sin in δ² by Horner (|δ| ≤
/// [`CIS_SERIES_MAX`]; `sin_cos` beyond), within an ulp or two of `sin_cos` at a third of its
/// cost. Quadratures turn a node's e^{iθ} into e^{iθ_mid}·e^{iδ} with δ the phase from the
/// panel's middle.
pub(crate) fn cis_small(delta: f64) -> Vec2 {
    if delta.abs() > CIS_SERIES_MAX || delta.is_nan() {
        return cis(delta);
    }
    // Terms needed: the first left out, |δ|^{2K}/(2K)!, below 1e-19 (K = 5 at 1/20, 7 at 1/4,
    // 9 at 1/2). The quadratures' nodes sit within 1/20 of their panel's middle: a step turning
    // at most `deviation::POLISH_STEP_TURN` puts its outer nodes 0.039 from it.
    let a = delta.abs();
    let terms = if a <= 0.05 {
        5
    } else if a <= 0.25 {
        7
    } else if a <= 0.5 {
        9
    } else {
        COS_SERIES.len()
    };
    let z = -delta * delta;
    let (mut c, mut s) = (0.0, 0.0);
    for k in (0..terms).rev() {
        c = c * z + COS_SERIES[k];
        s = s * z + SIN_SERIES[k];
    }
    Vec2::new(c, s * delta)
}

/// Complex product `a·b`.
pub(crate) fn cmul(a: Vec2, b: Vec2) -> Vec2 {
    Vec2::new(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x)
}

/// Complex quotient `a/b` (b ≠ 0).
pub(crate) fn cdiv(a: Vec2, b: Vec2) -> Vec2 {
    let d = b.hypot2();
    Vec2::new((a.x * b.x + a.y * b.y) / d, (a.y * b.x - a.x * b.y) / d)
}

/// Complex conjugate.
pub(crate) fn conj(a: Vec2) -> Vec2 {
    Vec2::new(a.x, -a.y)
}

/// `e^{a + ib} − 1` without cancellation for small |a + ib|:
/// real part `expm1(a)·cos b − 2 sin²(b/2)`, imaginary part `eᵃ·sin b`.
pub(crate) fn cexpm1(a: f64, b: f64) -> Vec2 {
    let (sb, cb) = b.sin_cos();
    let h = (0.5 * b).sin();
    Vec2::new(a.exp_m1() * cb - 2.0 * h * h, a.exp() * sb)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_functions_are_continuous_at_zero() {
        for x in [1e-7, 1e-9, -1e-9, 1e-300, 0.0] {
            assert!((exprel(x) - 1.0).abs() < 1e-6);
            assert!((lnrel(x) - 1.0).abs() < 1e-6);
            assert!((sinc(x) - 1.0).abs() < 1e-12);
        }
        // Just below the thresholds the series equal the quotients they replace (to 2 ulp).
        let t = RELATIVE_SERIES_BELOW * 0.999;
        assert!((exprel(t) - t.exp_m1() / t).abs() < 5e-16);
        assert!((lnrel(t) - t.ln_1p() / t).abs() < 5e-16);
        let t = SINC_SERIES_BELOW * 0.999;
        assert!((sinc(t) - t.sin() / t).abs() < 5e-16);
        assert_eq!(exprel(f64::NEG_INFINITY), 0.0);
        assert_eq!(lnrel(-1.0), f64::INFINITY);
    }

    #[test]
    fn small_angle_cis_matches_sin_cos() {
        let mut worst = 0.0f64;
        for i in -2000..=2000 {
            let delta = i as f64 * 1.2e-3; // to ±2.4: the series up to 1, sin_cos beyond
            let (s, c) = delta.sin_cos();
            let e = cis_small(delta);
            worst = worst.max((e.x - c).abs()).max((e.y - s).abs());
        }
        assert!(worst <= 4.5e-16, "{worst:e}");
        assert_eq!(cis_small(0.0), Vec2::new(1.0, 0.0));
    }

    #[test]
    fn complex_expm1_matches_direct_form() {
        let z = cexpm1(0.3, -1.2);
        let d = cis(-1.2) * 0.3f64.exp() - Vec2::new(1.0, 0.0);
        assert!((z - d).hypot() < 1e-15);
        let w = cdiv(cmul(z, Vec2::new(2.0, 1.0)), Vec2::new(2.0, 1.0));
        assert!((w - z).hypot() < 1e-15);
    }
}
