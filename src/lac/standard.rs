//! The normalised (standard) form of a log-aesthetic curve, after Yoshida & Saito (2006) and
//! Ziatdinov, Yoshida & Kim (2012).
//!
//! Start at the origin, tangent along +x, radius of curvature ρ(0) = 1, shape parameter Λ ≥ 0,
//! arc length `s ≥ 0`:
//!
//! * ρ(s)^α = 1 + αΛs (α ≠ 0), ρ(s) = e^{Λs} (α = 0); κ = 1/ρ decreases along s (the curve
//!   "uncurls"); Λ = 0 is the unit circle.
//! * θ(s) = ∫₀ˢ κ = ((1 + αΛs)^{(α−1)/α} − 1)/(Λ(α−1)), with the limits ln(1 + Λs)/Λ (α = 1) and
//!   (1 − e^{−Λs})/Λ (α = 0).
//! * s(θ) = ((1 + Λ(α−1)θ)^{α/(α−1)} − 1)/(αΛ), limits (e^{Λθ} − 1)/Λ (α = 1), −ln(1 − Λθ)/Λ (α = 0).
//! * For α < 1 the turning is bounded: θ < θ_max = 1/((1 − α)Λ); for α < 0 it is reached at
//!   s_max = −1/(αΛ), where κ = 0 (table 2.1 of the seed notes).
//! * P(s) = ∫₀ˢ e^{iθ(u)} du: closed forms for α = 1 (logarithmic spiral) and α = 2 (circle
//!   involute), adaptive Gauss–Legendre otherwise (see [`super::quadrature`]).
//!
//! ## One formula for every α
//! With ln ρ(s) = Λs·lnrel(αΛs) (`lnrel(y) = ln(1+y)/y`), the closed forms above become
//!
//! θ(s) = s·lnrel(αΛs)·exprel((α−1)·ln ρ(s)),   κ(s) = e^{−ln ρ(s)},
//! s(θ) = θ·lnrel(z)·exprel(α·ln ρ),   ln ρ = Λθ·lnrel(z),   z = Λ(α−1)θ,
//!
//! (`exprel(x) = (eˣ − 1)/x`), which are continuous in α and Λ: α = 0, α = 1 and Λ = 0 need no
//! special case and α near 0 or 1 suffers no cancellation.

use super::error::LacError;
use super::log_radius::log_radius_integral;
use super::quadrature;
use super::special::{SERIES_MAX_TERMS, SERIES_TERM_EPS, cdiv, cexpm1, cis, cmul, exprel, lnrel};
use crate::geom::{Point, Vec2};

/// Below this turning angle |θ| the circle-involute correction term G(θ) = e^{iθ}(1 − iθ) − 1
/// is summed as its power series Σ_{n≥2} (1 − n)(iθ)ⁿ/n! instead of evaluated directly: its
/// imaginary part sin θ − θ cos θ ≈ θ³/3 cancels catastrophically for small θ, while the series
/// (alternating, leading term dominant for |θ| ≤ 1) keeps full relative accuracy.
const INVOLUTE_SERIES_BELOW: f64 = 1.0;

/// Largest relative change ε of ρ^α over a step for which [`StandardLac::theta_around`] sums its
/// series (beyond it, the closed form): at a quarter the terms shrink at least fourfold once past
/// the first few, and steps of the deviation's integration (turning at most 0.1 rad) stay far
/// below it unless the curvature changes by a large factor within one.
const STEP_SERIES_MAX_EPS: f64 = 0.25;

/// 1/(m + 1) for the terms m of [`StandardLac::theta_around`]'s series.
const INVERSE_COUNTS: [f64; SERIES_MAX_TERMS] = {
    let mut table = [0.0; SERIES_MAX_TERMS];
    let mut m = 0;
    while m < SERIES_MAX_TERMS {
        table[m] = 1.0 / (m as f64 + 1.0);
        m += 1;
    }
    table
};

/// A log-aesthetic curve in the normalised standard form (see the module documentation).
///
/// Internally the linear function y(s) = αΛs is stored as y = m·(s/s_ref) so that a segment
/// ending exactly at the κ = 0 point of an α < 0 curve evaluates y = −1 (κ = 0) exactly there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StandardLac {
    alpha: f64,
    lambda: f64,
    /// Reference arc length s_ref (1 for [`StandardLac::new`], the segment length for spans).
    s_ref: f64,
    /// Λ·s_ref.
    l_ref: f64,
    /// α·Λ·s_ref (exactly −1 for an α < 0 span that ends where κ = 0).
    m_ref: f64,
}

impl StandardLac {
    /// The standard-form curve with slope `alpha` of the logarithmic curvature graph and shape
    /// parameter `lambda` = Λ ≥ 0 (Λ = 0: the unit circle).
    pub fn new(alpha: f64, lambda: f64) -> Result<Self, LacError> {
        if !alpha.is_finite() {
            return Err(LacError::NotFinite { field: "alpha" });
        }
        if !(lambda.is_finite() && lambda >= 0.0) {
            return Err(LacError::InvalidLambda { lambda });
        }
        Ok(Self {
            alpha,
            lambda,
            s_ref: 1.0,
            l_ref: lambda,
            m_ref: alpha * lambda,
        })
    }

    /// The standard form of a span of length `s_end` (in units of ρ at its high-curvature end)
    /// whose curvature falls by the factor e^{ln_ratio} from s = 0 to s = s_end;
    /// `ln_ratio = None` means it falls to exactly 0 (α < 0 only, checked by the caller).
    pub(crate) fn from_span(
        alpha: f64,
        s_end: f64,
        ln_ratio: Option<f64>,
    ) -> Result<Self, LacError> {
        let (l_ref, m_ref) = match ln_ratio {
            // ρ^α goes from 1 to 0: αΛs_end = −1.
            None => (-1.0 / alpha, -1.0),
            // ρ_end^α = e^{α·ln_ratio}: αΛs_end = expm1(α·ln_ratio), Λs_end = ln_ratio·exprel(α·ln_ratio).
            Some(lr) => {
                let m = if alpha == 0.0 {
                    0.0
                } else {
                    (alpha * lr).exp_m1()
                };
                (lr * exprel(alpha * lr), m)
            }
        };
        let lambda = l_ref / s_end;
        if !(l_ref.is_finite() && m_ref.is_finite() && lambda.is_finite()) {
            return Err(LacError::CurvatureRatioOutOfRange {
                ratio: ln_ratio.map_or(f64::INFINITY, f64::exp),
                alpha,
            });
        }
        Ok(Self {
            alpha,
            lambda,
            s_ref: s_end,
            l_ref,
            m_ref,
        })
    }

    /// The slope α of the logarithmic curvature graph.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// The shape parameter Λ (in units of 1/ρ(0)).
    pub fn lambda(&self) -> f64 {
        self.lambda
    }

    /// y(s) = αΛs, clamped to ≥ −1 (the κ = 0 point of an α < 0 curve).
    fn y(&self, s: f64) -> f64 {
        (self.m_ref * (s / self.s_ref)).max(-1.0)
    }

    /// ln ρ(s) = Λs·lnrel(αΛs); +∞ at the κ = 0 point of an α < 0 curve.
    pub(crate) fn ln_rho(&self, s: f64) -> f64 {
        let y = self.y(s);
        if y <= -1.0 {
            f64::INFINITY
        } else {
            self.l_ref * (s / self.s_ref) * lnrel(y)
        }
    }

    /// Curvature κ(s) = (1 + αΛs)^{−1/α} (e^{−Λs} for α = 0); 0 beyond s_max when α < 0.
    pub fn kappa(&self, s: f64) -> f64 {
        (-self.ln_rho(s)).exp()
    }

    /// Tangent angle θ(s) = ∫₀ˢ κ, in closed form (see the module documentation).
    pub fn theta(&self, s: f64) -> f64 {
        let y = self.y(s);
        if y <= -1.0 {
            // Only reachable for α < 0 with Λ > 0, where θ_max is finite.
            return 1.0 / ((1.0 - self.alpha) * self.lambda);
        }
        let lr = self.l_ref * (s / self.s_ref) * lnrel(y);
        s * lnrel(y) * exprel((self.alpha - 1.0) * lr)
    }

    /// θ(s) and κ(s) together: both take ln ρ(s), so one logarithm serves both.
    pub(crate) fn theta_kappa(&self, s: f64) -> (f64, f64) {
        let y = self.y(s);
        if y <= -1.0 {
            return (self.theta(s), 0.0);
        }
        let rel = lnrel(y);
        let ln_rho = self.l_ref * (s / self.s_ref) * rel;
        (
            s * rel * exprel((self.alpha - 1.0) * ln_rho),
            (-ln_rho).exp(),
        )
    }

    /// θ(s) and the increments θ(s ± d) − θ(s), the increments by a power series where the
    /// curvature changes little over ±d (`None` there otherwise, and at the κ = 0 point).
    ///
    /// With 1 + y the value of ρ^α at s (y = αΛs) and ρ^α linear in arc length,
    /// ρ(s + δ)^α = ρ(s)^α·(1 + ε), ε = αΛδ/(1 + y), and θ(s + δ) − θ(s) = κ(s)·δ·S(ε) with
    ///
    /// S = ((1 + ε)^p − 1)/(pε) = Σ_m c_m ε^m,  c_0 = 1,  c_m ε^m = c_{m−1} ε^{m−1}·(pε − mε)/(m + 1),
    ///
    /// p = (α − 1)/α: finite in the product pε = (α − 1)Λδ/(1 + y) for every α (α = 1 gives
    /// lnrel(ε), α = 0 exprel(−Λδ)), and the sign of δ only flips the odd terms. Where
    /// |ε| ≤ [`STEP_SERIES_MAX_EPS`] and |pε| ≤ 1 the terms fall at least fourfold from the
    /// fourth on: about fifteen terms reach rounding, a tenth of the logarithm and exponential of
    /// the closed form, and the increment keeps its full relative accuracy where the difference
    /// of two closed forms would cancel.
    pub(crate) fn theta_around(&self, s: f64, d: f64) -> (f64, Option<(f64, f64)>) {
        let y = self.y(s);
        if y <= -1.0 {
            return (self.theta(s), None);
        }
        let rel = lnrel(y);
        let ln_rho = self.l_ref * (s / self.s_ref) * rel;
        let theta = s * rel * exprel((self.alpha - 1.0) * ln_rho);
        let one_plus_y = 1.0 + y;
        let eps = self.m_ref * (d / self.s_ref) / one_plus_y;
        let p_eps = (self.alpha - 1.0) * self.l_ref * (d / self.s_ref) / one_plus_y;
        if !(eps.abs() <= STEP_SERIES_MAX_EPS && p_eps.abs() <= 1.0) {
            return (theta, None);
        }
        // Even and odd parts of S at +ε; S(−ε) = even − odd.
        let (mut even, mut odd) = (1.0, 0.0);
        let mut term = 1.0;
        for (m, inverse) in INVERSE_COUNTS.iter().enumerate().skip(1) {
            // 1/(m + 1) from the table: a product instead of a division per term.
            term *= (p_eps - m as f64 * eps) * inverse;
            if m % 2 == 0 {
                even += term;
            } else {
                odd += term;
            }
            if term.abs() <= SERIES_TERM_EPS {
                break;
            }
        }
        let step = (-ln_rho).exp() * d;
        (theta, Some((-step * (even - odd), step * (even + odd))))
    }

    /// The supremum of the turning angle, θ_max = 1/((1 − α)Λ), for α < 1 and Λ > 0 (reached at
    /// [`StandardLac::s_max`] when α < 0, approached as s → ∞ when 0 ≤ α < 1); `None` when the
    /// turning is unbounded (α ≥ 1 or Λ = 0).
    pub fn theta_max(&self) -> Option<f64> {
        (self.alpha < 1.0 && self.lambda > 0.0).then(|| 1.0 / ((1.0 - self.alpha) * self.lambda))
    }

    /// Arc length s_max = −1/(αΛ) of the κ = 0 point, for α < 0 and Λ > 0; `None` otherwise.
    pub fn s_max(&self) -> Option<f64> {
        (self.alpha < 0.0 && self.lambda > 0.0).then(|| -self.s_ref / self.m_ref)
    }

    /// Turning still to come from s to the κ = 0 point, θ_max − θ(s) = θ_max·ρ(s)^{α−1}, without
    /// cancellation (α < 0 only; `None` otherwise).
    pub(crate) fn remaining_turning(&self, s: f64) -> Option<f64> {
        let tm = self.theta_max()?;
        (self.alpha < 0.0).then(|| tm * ((self.alpha - 1.0) * self.ln_rho(s)).exp())
    }

    /// Arc length at turning angle θ ≥ 0, the inverse of [`StandardLac::theta`]; `None` when
    /// θ < 0 or θ is beyond the reachable turning (θ > θ_max, or θ = θ_max for 0 ≤ α < 1).
    pub fn s_of_theta(&self, theta: f64) -> Option<f64> {
        if theta.is_nan() || theta < 0.0 {
            return None;
        }
        if let Some(tm) = self.theta_max() {
            if theta > tm || (theta == tm && self.alpha >= 0.0) {
                return None;
            }
            if theta == tm {
                return self.s_max();
            }
        }
        let z = self.lambda * (self.alpha - 1.0) * theta;
        if z <= -1.0 {
            // Rounding right at θ_max.
            return if self.alpha < 0.0 { self.s_max() } else { None };
        }
        let ln_rho = self.lambda * theta * lnrel(z);
        Some(theta * lnrel(z) * exprel(self.alpha * ln_rho))
    }

    /// Point P(s) = ∫₀ˢ e^{iθ(u)} du (start at the origin, tangent +x). For α < 0, `s` is clamped
    /// to s_max.
    pub fn point(&self, s: f64) -> Point {
        self.tangent_integral(0.0, s).to_point()
    }

    /// ∫_{a}^{b} e^{iθ(u)} du for 0 ≤ a ≤ b (≤ s_max when α < 0), as a complex number: closed
    /// forms for α = 1 and α = 2, adaptive quadrature otherwise.
    pub(crate) fn tangent_integral(&self, a: f64, b: f64) -> Vec2 {
        let b = match self.s_max() {
            Some(sm) => b.min(sm),
            None => b,
        };
        if b <= a {
            return Vec2::ZERO;
        }
        if self.alpha == 1.0 || self.alpha == 2.0 {
            self.closed_form(b) - self.closed_form(a)
        } else if self.lambda == 0.0 {
            quadrature::integrate(self, a, b)
        } else {
            self.integral_in_log_radius(a, b)
        }
    }

    /// ∫_a^b e^{iθ} ds by the substitution w = ln ρ of [`super::log_radius`] (Λ > 0, a < b).
    ///
    /// With y_a = αΛa (ρ_a^α = 1 + y_a) and d = b − a, ρ_b^α = ρ_a^α + αΛd, so
    /// U = ln(ρ_b/ρ_a) = (Λd/(1 + y_a))·lnrel(αΛd/(1 + y_a)), without the cancellation of
    /// ln ρ_b − ln ρ_a when d is small; U = ∞ once b reaches the κ = 0 point.
    fn integral_in_log_radius(&self, a: f64, b: f64) -> Vec2 {
        let d = (b - a) / self.s_ref;
        let one_plus_ya = 1.0 + self.y(a);
        let upper = if self.y(b) <= -1.0 || one_plus_ya <= 0.0 {
            f64::INFINITY
        } else {
            let z = self.m_ref * d / one_plus_ya;
            self.l_ref * d / one_plus_ya * lnrel(z)
        };
        let w_a = self.ln_rho(a);
        let c = ((self.alpha - 1.0) * w_a).exp() / self.lambda;
        // For α > 0 the amplitude e^{αu} peaks at u = U: integrate relative to it.
        let shift = if self.alpha > 0.0 {
            self.alpha * upper
        } else {
            0.0
        };
        let integral = log_radius_integral(self.alpha, c, upper, shift);
        cmul(cis(self.theta(a)), integral) * ((self.alpha * w_a + shift).exp() / self.lambda)
    }

    /// Closed-form P(s) for α = 1 and α = 2 (only called for those).
    ///
    /// * α = 1, logarithmic spiral: P = ((1 + Λs)^{1 + i/Λ} − 1)/(Λ + i) = expm1(L + iθ)/(Λ + i)
    ///   with L = ln(1 + Λs) = Λθ.
    /// * α = 2, circle involute (w = ρ = √(1 + 2Λs), θ = (w − 1)/Λ):
    ///   P = −i(e^{iθ} − 1) + Λ·G(θ), G(θ) = e^{iθ}(1 − iθ) − 1, which is the reference
    ///   `e^{−ik}/Λ [F(w) − F(1)]`, F(w) = e^{ikw}(w/(ik) + 1/k²), k = 1/Λ, regrouped so that no
    ///   term cancels (G by its power series for small θ).
    fn closed_form(&self, s: f64) -> Vec2 {
        let theta = self.theta(s);
        if self.alpha == 1.0 {
            let l = self.ln_rho(s);
            cdiv(cexpm1(l, theta), Vec2::new(self.lambda, 1.0))
        } else {
            let e = cexpm1(0.0, theta);
            Vec2::new(e.y, -e.x) + involute_g(theta) * self.lambda
        }
    }
}

/// G(θ) = e^{iθ}(1 − iθ) − 1 = Σ_{n≥2} (1 − n)(iθ)ⁿ/n!.
pub(crate) fn involute_g(theta: f64) -> Vec2 {
    if theta.abs() >= INVOLUTE_SERIES_BELOW {
        involute_g_direct(theta)
    } else {
        involute_g_series(theta)
    }
}

/// G(θ) = e^{iθ}(1 − iθ) − 1 evaluated as written.
fn involute_g_direct(theta: f64) -> Vec2 {
    cmul(cis(theta), Vec2::new(1.0, -theta)) - Vec2::new(1.0, 0.0)
}

/// G(θ) = Σ_{n≥2} (1 − n)(iθ)ⁿ/n!, for |θ| ≤ 1.
fn involute_g_series(theta: f64) -> Vec2 {
    let it = Vec2::new(0.0, theta);
    let mut power = cmul(it, it) * 0.5; // (iθ)²/2!
    let mut sum = -power; // n = 2: (1 − 2)(iθ)²/2!
    for n in 3..SERIES_MAX_TERMS {
        power = cmul(power, it) * (1.0 / n as f64);
        let term = power * (1.0 - n as f64);
        sum += term;
        if term.hypot() < SERIES_TERM_EPS * sum.hypot() {
            break;
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn increments_around_a_point_are_the_closed_form_differences() {
        // Every α kind (0 and 1 included), a near-circle (Λ tiny), steps from tiny to beyond the
        // series' reach (the closed form then answers), and points up to the κ = 0 end.
        let (mut summed, mut closed) = (0, 0);
        for alpha in [-3.0, -1.0, -0.2, 0.0, 0.3, 1.0, 2.0, 3.0] {
            for lambda in [1e-9, 0.05, 0.8] {
                let lac = StandardLac::new(alpha, lambda).expect("valid");
                let end = lac.s_max().unwrap_or(4.0).min(4.0);
                for i in 1..40 {
                    let s = end * i as f64 / 40.0;
                    for d in [1e-6, 1e-3, 0.02, 0.3] {
                        let (theta, steps) = lac.theta_around(s, d);
                        assert_eq!(theta, lac.theta(s), "α {alpha} Λ {lambda} s {s}");
                        let Some((minus, plus)) = steps else {
                            closed += 1;
                            continue;
                        };
                        summed += 1;
                        let want = (lac.theta(s - d) - theta, lac.theta(s + d) - theta);
                        // Relative to the step's turning (the increments keep that accuracy),
                        // plus the closed-form difference's own rounding, a few ulps of θ.
                        let bound = 1e-13 * lac.kappa(s) * d + 8.0 * f64::EPSILON * theta.abs();
                        for (got, want) in [(minus, want.0), (plus, want.1)] {
                            assert!(
                                (got - want).abs() <= bound,
                                "α {alpha} Λ {lambda} s {s} d {d}: {got} against {want}"
                            );
                        }
                    }
                }
            }
        }
        assert!(
            summed > 3000 && closed > 50,
            "{summed} by series, {closed} closed"
        );
    }

    #[test]
    fn theta_and_inverse_agree_across_alpha() {
        for alpha in [
            -2.0,
            -1.0,
            -1e-12,
            0.0,
            1e-12,
            0.5,
            1.0 - 1e-12,
            1.0,
            1.0 + 1e-12,
            2.0,
            3.0,
        ] {
            for lambda in [0.0, 1e-9, 0.2, 1.0, 5.0] {
                let lac = StandardLac::new(alpha, lambda).expect("valid");
                let s_max = lac.s_max().unwrap_or(f64::INFINITY);
                for s in [0.0, 1e-6, 0.05, 0.07, 0.5, 0.09]
                    .into_iter()
                    .filter(|&s| s <= s_max)
                {
                    let th = lac.theta(s);
                    let back = lac.s_of_theta(th).expect("reachable");
                    assert!(
                        (back - s).abs() <= 1e-14 * (1.0 + s),
                        "{alpha} {lambda} {s}: {back}"
                    );
                }
            }
        }
    }

    #[test]
    fn involute_series_matches_direct_at_threshold() {
        for theta in [INVOLUTE_SERIES_BELOW, -INVOLUTE_SERIES_BELOW, 0.7] {
            let (a, b) = (involute_g_series(theta), involute_g_direct(theta));
            assert!((a - b).hypot() < 1e-15, "{theta}: {a:?} vs {b:?}");
        }
        // Small θ: G ≈ θ²/2 + iθ³/3 with full relative accuracy in both parts.
        let g = involute_g(1e-6);
        assert!((g.x / 5e-13 - 1.0).abs() < 1e-11 && (g.y / (1e-18 / 3.0) - 1.0).abs() < 1e-11);
    }
}
