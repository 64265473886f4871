//! How a Yoshida–Saito segment moves when the tangent at one of its ends turns or its α changes,
//! both end points held: the derivatives of its points, for the chain refinement's Jacobian
//! ([`crate::chain`]). One pass along the segment gives all three, where differences need a
//! construction and a pass per unknown.
//!
//! ## The segment in the log radius
//! Let H be the segment's high-curvature end and L the other, w = ln(ρ/ρ_H) ∈ [0, q] the log
//! radius from H (q = ln(κ_H/κ_L)), θ_T the total turning and
//! g(w) = (e^{(α−1)w} − 1)/(α − 1) = w·exprel((α − 1)w). In the standard form (ρ^α = 1 + αΛu,
//! ρ(0) = 1) dθ = e^{(α−1)w}·dw/Λ and du = e^{αw}·dw/Λ, so θ(w) = θ_T·g(w)/g(q) and
//!
//! P(w) = H + (L − H)·m(F(w)/F(q)),   F(w) = ∫₀ʷ e^{iθ(v) + αv} dv,
//!
//! m the identity where the standard form, travelled from H, turns left and complex conjugation
//! where it turns right (the 1/Λ cancels in the ratio). The shape is fixed by (q, θ_T, α), and q
//! by the chord angle at H, φ = arg F(q), which the construction matches to the data.
//!
//! ## Derivatives
//! The tangent at H has the angle arg(L − H) − σφ and the one at L the angle
//! arg(L − H) + σ(θ_T − φ), σ = ±1 the turning sign of m (travelling the other way adds π to
//! both, a constant). With the ends held, turning the tangent at H by dτ_H and the one at L by
//! dτ_L therefore asks for dφ = −σ·dτ_H and dθ_T = σ(dτ_L − dτ_H); q follows from
//! φ(q, θ_T, α) = φ by the implicit-function theorem,
//!
//! dq = (dφ − φ_T·dθ_T − φ_α·dα)/φ_q,   φ_x = Im(∂_x F(q)/F(q)),
//!
//! and at a fixed w, with R = F(w)/F(q),
//!
//! dP(w) = (L − H)·m((dF(w) − R·dF(q))/F(q)),
//! ∂_x F(w) = ∫₀ʷ e^{iθ + αv}·(i·∂_x θ + [x = α]·v) dv,
//!
//! ∂_{θ_T} θ = g(w)/g(q), ∂_q θ = −θ(w)·e^{(α−1)q}/g(q),
//! ∂_α θ = θ_T·(∂_β g(w) − (g(w)/g(q))·∂_β g(q))/g(q), ∂_β g(w) = w²·h((α − 1)w),
//! h(z) = (z·e^z − e^z + 1)/z², and ∂_q F(q) gains the end term e^{iθ_T + αq}. Holding w rather
//! than the arc length moves a point only along the curve, which a residual measured along the
//! normal does not see.
//!
//! All the integrals come from one pass of 3-point Gauss–Legendre panels from w = 0 to q, through
//! the feet in order of w, each panel turning at most [`PANEL_TURN`] (and changing e^{αw} by at
//! most that exponent): about 1e-8 relative, far more than a Gauss–Newton step needs.

use super::quadrature::{GAUSS_LEGENDRE_2, GAUSS_LEGENDRE_3, Panel, add_nodes, panel_count};
use super::segment::LacSegment;
use super::special::{SERIES_TERM_EPS, cdiv, cis, cmul, conj, exprel};
use crate::geom::Vec2;

/// Largest phase change (radians), and largest change of the exponent αw, over one panel of the
/// pass: the 3-point rule's relative error on e^{iθ} over a panel turning τ is about τ⁶/2·10⁶,
/// 8e-9 at 0.5.
const PANEL_TURN: f64 = 0.5;

/// Stretches whose phase and exponent change by at most this are integrated by one 2-point
/// Gauss–Legendre panel: its relative error on e^{iτt}, about (τ/2)⁴/135, is 3e-9 at 0.05 (many
/// stretches between neighbouring feet are this short). At 0.2 (7e-7 per stretch) the
/// implicit derivative of q, a quotient by the small φ_q near the drawable region's limit,
/// magnified the errors to 5e-3 at α = 3 (see the tests).
const GL2_MAX_SPREAD: f64 = 0.05;

/// Most panels of one pass: a segment needing more (an extreme curvature ratio at a large |α|)
/// is left to the caller's differences.
const MAX_PANELS: usize = 512;

/// Log curvature ratios below this are left to the caller: near the circle, φ_q → 0 and the
/// implicit derivative of q is a quotient of two small, cancelling quantities.
const MIN_LOG_RATIO: f64 = 1e-3;

/// Log curvature ratios above this are left to the caller too: e^{αq} and the panel count grow
/// without bound, and pen data never gets near (e^{40} ≈ 2e17).
const MAX_LOG_RATIO: f64 = 40.0;

/// Below this |z|, h(z) = (z·e^z − e^z + 1)/z² is summed as its series Σ_{m≥2} (m − 1)z^{m−2}/m!
/// (the closed form loses about 1e-16/|z| relative); at 0.1 twelve terms reach rounding.
const H_SERIES_BELOW: f64 = 0.1;

/// Terms of the h series summed at most.
const H_SERIES_TERMS: usize = 16;

/// The derivatives of one point of a segment (at a fixed foot, see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Sensitivity {
    /// ∂P/∂τ_start: the start tangent turning (radians, counter-clockwise).
    pub start_angle: Vec2,
    /// ∂P/∂τ_end: the end tangent turning.
    pub end_angle: Vec2,
    /// ∂P/∂α.
    pub alpha: Vec2,
}

/// exprel(z) = (e^z − 1)/z and h(z) = (z·e^z − e^z + 1)/z² (h(0) = 1/2), from one `exp_m1`.
fn exprel_and_h(z: f64) -> (f64, f64) {
    if z.abs() < H_SERIES_BELOW {
        // Σ_{m≥2} (m − 1)·z^{m−2}/m!: the power z^{m−2}/m! is carried from term to term.
        let (mut sum, mut power) = (0.0, 0.5);
        for m in 2..2 + H_SERIES_TERMS {
            let term = (m - 1) as f64 * power;
            sum += term;
            if term.abs() <= SERIES_TERM_EPS {
                break;
            }
            power *= z / (m + 1) as f64;
        }
        (exprel(z), sum)
    } else {
        let em1 = z.exp_m1();
        (em1 / z, (z * (1.0 + em1) - em1) / (z * z))
    }
}

/// The shape of a segment in the log radius (see the module documentation).
struct LogRadiusShape {
    alpha: f64,
    theta_t: f64,
    /// g(q).
    g_q: f64,
    /// e^{(α−1)q}.
    e_q: f64,
    /// ∂_β g(q).
    dg_q: f64,
}

/// The integrands of F, ∂_{θ_T}F, ∂_qF and ∂_αF at one w.
type Integrands = [Vec2; 4];

impl LogRadiusShape {
    fn integrands(&self, w: f64) -> Integrands {
        let z = (self.alpha - 1.0) * w;
        let (rel, h) = exprel_and_h(z);
        let g = w * rel;
        let ratio = g / self.g_q;
        let theta = self.theta_t * ratio;
        let f = cis(theta) * (self.alpha * w).exp();
        let d_theta_q = -theta * self.e_q / self.g_q;
        let d_theta_alpha = self.theta_t * (w * w * h - ratio * self.dg_q) / self.g_q;
        // i·x·f.
        let i_times = |x: f64| Vec2::new(-f.y * x, f.x * x);
        [
            f,
            i_times(ratio),
            i_times(d_theta_q),
            i_times(d_theta_alpha) + f * w,
        ]
    }

    /// ∫ over [a, b] of the integrands, in panels (see [`PANEL_TURN`]); `None` beyond
    /// [`MAX_PANELS`].
    fn integrate(&self, a: f64, b: f64, panels: &mut usize) -> Option<Integrands> {
        // dθ/dw = θ_T·e^{(α−1)w}/g(q) is monotonic: its larger end value bounds it.
        let beta = self.alpha - 1.0;
        let rate = self.theta_t * (beta * a).exp().max((beta * b).exp()) / self.g_q;
        let spread = rate.max(self.alpha.abs()) * (b - a);
        let n = panel_count(spread, PANEL_TURN);
        *panels += n;
        if *panels > MAX_PANELS {
            return None;
        }
        let mut sum = [Vec2::ZERO; 4];
        // Each node's four integrands, weighted by its weight times the half width.
        let mut add_panel = |rule: &[(f64, f64)], panel: Panel| {
            add_nodes(&mut sum, rule, panel, |w, weight| {
                self.integrands(w).map(|v| v * (weight * panel.half))
            });
        };
        if spread <= GL2_MAX_SPREAD {
            add_panel(&GAUSS_LEGENDRE_2, Panel::over(a, b));
        } else {
            for panel in Panel::equal(a, b, n) {
                add_panel(&GAUSS_LEGENDRE_3, panel);
            }
        }
        Some(sum)
    }
}

/// The derivatives of `segment`'s points at the arc lengths `feet` with respect to its start and
/// end tangent angles and its α, both end points held (see the module documentation); zero at
/// feet on or beyond an end (the end points are held). Circular arcs by [`arc_sensitivities`].
/// `None` where the log-radius form does not apply or is ill-conditioned (lines, a κ = 0 end, log
/// curvature ratios outside [[`MIN_LOG_RATIO`], [`MAX_LOG_RATIO`]]): the caller then differences
/// constructions.
pub(crate) fn sensitivities(segment: &LacSegment, feet: &[f64]) -> Option<Vec<Sensitivity>> {
    let Some(alpha) = segment.alpha() else {
        return arc_sensitivities(segment, feet);
    };
    let (k0, k1) = (segment.kappa0().abs(), segment.kappa1().abs());
    let curling = k1 > k0;
    let (k_high, k_low) = if curling { (k1, k0) } else { (k0, k1) };
    if !(k_low > 0.0) {
        return None;
    }
    let q = (k_high / k_low).ln();
    if !(MIN_LOG_RATIO..=MAX_LOG_RATIO).contains(&q) {
        return None;
    }
    let theta_t = (segment.theta1() - segment.theta0()).abs();
    let beta = alpha - 1.0;
    let shape = LogRadiusShape {
        alpha,
        theta_t,

        g_q: q * exprel(beta * q),
        e_q: (beta * q).exp(),
        dg_q: q * q * exprel_and_h(beta * q).1,
    };
    // The standard form's turning sign: the travel's, reversed when it is travelled from L.
    let travel_sign = (segment.kappa0() + segment.kappa1()).signum();
    let sigma = if curling { -travel_sign } else { travel_sign };
    let (high, low) = if curling {
        (segment.end(), segment.start())
    } else {
        (segment.start(), segment.end())
    };
    let length = segment.length();
    // Interior feet by w.
    let mut panels = 0;
    let (at, end) = integrals_at_feet(
        feet,
        length,
        |s| (k_high / segment.kappa(s).abs()).ln().clamp(0.0, q),
        q,
        |a, b| shape.integrate(a, b, &mut panels),
    )?;
    let [f_q, f_theta_t, mut f_q_q, f_alpha] = end;
    f_q_q += cis(theta_t) * (alpha * q).exp();
    let slope = |d: Vec2| cdiv(d, f_q).y;
    let (phi_t, phi_q, phi_alpha) = (slope(f_theta_t), slope(f_q_q), slope(f_alpha));
    if !(phi_q.abs() > 0.0 && phi_q.is_finite()) {
        return None;
    }
    let chord = low - high;
    // dP at every foot for the change (dφ, dθ_T, dα).
    let column = |d_phi: f64, d_theta_t: f64, d_alpha: f64| -> Vec<Vec2> {
        let dq = (d_phi - phi_t * d_theta_t - phi_alpha * d_alpha) / phi_q;
        let d_end = f_q_q * dq + f_theta_t * d_theta_t + f_alpha * d_alpha;
        feet.iter()
            .zip(&at)
            .map(|(&s, [f, f_t, f_qw, f_a])| {
                if !(s > 0.0 && s < length) {
                    return Vec2::ZERO;
                }
                let ratio = cdiv(*f, f_q);
                let d_f = *f_qw * dq + *f_t * d_theta_t + *f_a * d_alpha;
                let d_ratio = cdiv(d_f - cmul(ratio, d_end), f_q);
                cmul(chord, if sigma > 0.0 { d_ratio } else { conj(d_ratio) })
            })
            .collect()
    };
    // Turning the tangent at H by 1: dφ = −σ, dθ_T = −σ; at L: dθ_T = σ.
    let at_high = column(-sigma, -sigma, 0.0);
    let at_low = column(0.0, sigma, 0.0);
    let by_alpha = column(0.0, 0.0, 1.0);
    let (at_start, at_end) = if curling {
        (at_low, at_high)
    } else {
        (at_high, at_low)
    };
    let out: Vec<Sensitivity> = at_start
        .into_iter()
        .zip(at_end)
        .zip(by_alpha)
        .map(|((start_angle, end_angle), alpha)| Sensitivity {
            start_angle,
            end_angle,
            alpha,
        })
        .collect();
    out.iter()
        .all(|d| {
            [d.start_angle, d.end_angle, d.alpha]
                .iter()
                .all(|v| v.x.is_finite() && v.y.is_finite())
        })
        .then_some(out)
}

/// Integrals from 0 to each interior foot (`at`, zero for feet on or beyond an end) and to `top`
/// (`end`), in one pass through the feet in order of their variable `position(s)`;
/// `integrate(a, b)` gives the integrals over [a, b] (`None` ends the pass).
fn integrals_at_feet<const N: usize>(
    feet: &[f64],
    length: f64,
    position: impl Fn(f64) -> f64,
    top: f64,
    mut integrate: impl FnMut(f64, f64) -> Option<[Vec2; N]>,
) -> Option<(Vec<[Vec2; N]>, [Vec2; N])> {
    let mut interior: Vec<(f64, usize)> = feet
        .iter()
        .enumerate()
        .filter(|&(_, &s)| s > 0.0 && s < length)
        .map(|(i, &s)| (position(s), i))
        .collect();
    interior.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut at = vec![[Vec2::ZERO; N]; feet.len()];
    let mut sum = [Vec2::ZERO; N];
    let mut from = 0.0;
    for &(x, i) in &interior {
        for (s, p) in sum.iter_mut().zip(integrate(from, x)?) {
            *s += p;
        }
        at[i] = sum;
        from = x;
    }
    for (s, p) in sum.iter_mut().zip(integrate(from, top)?) {
        *s += p;
    }
    Some((at, sum))
}

/// [`sensitivities`] for a circular arc (κ0 = κ1 ≠ 0, no α).
///
/// Every α draws the arc, so ∂P/∂α = 0. Turning an end tangent makes the data slightly
/// asymmetric, and the segment a spiral with a small log curvature ratio; to first order in it,
/// ln κ is linear in the arc length whatever α is (ρ^α linear in s gives
/// ln ρ = ln ρ0 + q·s/S + O(q²)). So, with x = s/S ∈ [0, 1], θ(x) = θ0 + θ_T·x on the arc, the
/// turned segment has
///
/// dθ(x) = dτ_A + u·x − v·(x² − x),   u = dτ_B − dτ_A,
///
/// (u the change of the turning, v that of the curvature's slope) and length S + dS. (A line has
/// no such family: turning one of its tangents asks for an inflection, which no LAC draws, and
/// the caller's probes then see no segment at all.) Holding the
/// end, with I_k = J_k(1) and J_k(x) = ∫₀ˣ t^k·e^{iθ(t)} dt,
///
/// dS·I₀ + i·S·(dτ_A·I₀ + u·I₁ − v·(I₂ − I₁)) = 0,
///
/// two real equations for dS and v (their determinant tends to S²/6 as θ_T → 0), and at a fixed x
///
/// dP(x) = dS·J₀(x) + i·S·(dτ_A·J₀(x) + u·J₁(x) − v·(J₂(x) − J₁(x))).
///
/// The moments come from one pass of 3-point Gauss–Legendre panels through the feet in order,
/// each turning at most [`PANEL_TURN`]. `None` for a line, a segment without length or a
/// singular system.
fn arc_sensitivities(segment: &LacSegment, feet: &[f64]) -> Option<Vec<Sensitivity>> {
    let length = segment.length();
    if !(length > 0.0 && segment.kappa0() != 0.0) {
        return None;
    }
    let theta0 = segment.theta0();
    let turn = segment.theta1() - theta0;
    let mut panels = 0;
    // [J₀, J₁, J₂] over [a, b].
    let mut moments = |a: f64, b: f64| -> Option<[Vec2; 3]> {
        let n = panel_count(turn.abs() * (b - a), PANEL_TURN);
        panels += n;
        if panels > MAX_PANELS {
            return None;
        }
        let mut sum = [Vec2::ZERO; 3];
        for panel in Panel::equal(a, b, n) {
            add_nodes(&mut sum, &GAUSS_LEGENDRE_3, panel, |x, w| {
                let e = cis(theta0 + turn * x) * (w * panel.half);
                [e, e * x, e * (x * x)]
            });
        }
        Some(sum)
    };
    let (at, [i0, i1, i2]) = integrals_at_feet(feet, length, |s| s / length, 1.0, &mut moments)?;
    let times_i = |v: Vec2| Vec2::new(-v.y, v.x);
    // dS·I₀ + v·W = R, W = −i·S·(I₂ − I₁), R = −i·S·(dτ_A·I₀ + u·I₁), by Cramer's rule.
    let w = times_i(i2 - i1) * -length;
    let det = i0.x * w.y - i0.y * w.x;
    if !(det.abs() > 0.0 && det.is_finite()) {
        return None;
    }
    let column = |d_start: f64, d_end: f64| -> Vec<Vec2> {
        let u = d_end - d_start;
        let r = times_i(i0 * d_start + i1 * u) * -length;
        let ds = (r.x * w.y - r.y * w.x) / det;
        let v = (i0.x * r.y - i0.y * r.x) / det;
        feet.iter()
            .zip(&at)
            .map(|(&s, [j0, j1, j2])| {
                if !(s > 0.0 && s < length) {
                    return Vec2::ZERO;
                }
                *j0 * ds + times_i(*j0 * d_start + *j1 * u - (*j2 - *j1) * v) * length
            })
            .collect()
    };
    let out: Vec<Sensitivity> = column(1.0, 0.0)
        .into_iter()
        .zip(column(0.0, 1.0))
        .map(|(start_angle, end_angle)| Sensitivity {
            start_angle,
            end_angle,
            alpha: Vec2::ZERO,
        })
        .collect();
    out.iter()
        .all(|d| {
            [d.start_angle, d.end_angle]
                .iter()
                .all(|v| v.x.is_finite() && v.y.is_finite())
        })
        .then_some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Point;
    use crate::lac::fit_g1;

    /// Against central differences of full constructions, at a fixed fraction of the arc length
    /// and projected on the normal (the tangential part depends on which parameter is held).
    #[test]
    fn sensitivities_match_differences_of_constructions() {
        let cases = [
            (Some(0.5), 0.09, 0.03),
            (Some(-1.0), 0.02, 0.05),
            (Some(1.0), 0.1, 0.02),
            (Some(0.0), 0.04, 0.08),
            (Some(2.0), 0.12, 0.05),
            (Some(-2.2), 0.03, 0.01),
            (Some(3.0), 0.15, 0.01),
        ];
        for (alpha, kappa0, kappa1) in cases {
            for sign in [1.0, -1.0] {
                let segment = LacSegment::new(
                    Point::new(3.0, 1.0),
                    0.4,
                    25.0,
                    alpha,
                    sign * kappa0,
                    sign * kappa1,
                )
                .expect("segment");
                check(&segment);
            }
        }
    }

    #[test]
    fn arc_sensitivities_match_differences_of_constructions() {
        // Every α draws an arc; the turned data's first-order shape is the same for all of them
        // (checked with the differences of three α), turning 0.25 to 2.5 rad either way.
        for kappa in [0.05, -0.05, 0.1, -0.01] {
            let segment =
                LacSegment::new(Point::new(3.0, 1.0), 0.4, 25.0, None, kappa, kappa).expect("arc");
            for alpha in [-1.0, 0.5, 2.0] {
                check_with(&segment, alpha);
            }
        }
        // A line has no first-order family (see `arc_sensitivities`): left to the caller.
        let line = LacSegment::new(Point::new(3.0, 1.0), 0.4, 25.0, None, 0.0, 0.0).expect("line");
        assert!(sensitivities(&line, &[5.0, 12.0]).is_none());
    }

    fn check(segment: &LacSegment) {
        check_with(segment, segment.alpha().expect("spiral"));
    }

    /// [`check`] with the constructions of `alpha`.
    fn check_with(segment: &LacSegment, alpha: f64) {
        let length = segment.length();
        let feet: Vec<f64> = (0..=10).map(|i| length * i as f64 / 10.0).collect();
        let got = sensitivities(segment, &feet).expect("applies");
        let (a, b) = (segment.start(), segment.end());
        let build = |ta: f64, tb: f64, alpha: f64| {
            fit_g1(
                a,
                Vec2::new(ta.cos(), ta.sin()),
                b,
                Vec2::new(tb.cos(), tb.sin()),
                alpha,
            )
            .expect("builds")
        };
        let (t0, t1) = (segment.theta0(), segment.theta1());
        // Large enough that the constructions' rounding (~1e-12 of the length, more at α = 3)
        // stays far below the difference; the central difference's own error is O(h²).
        let h = 1e-5;
        for (which, plus, minus) in [
            (0, build(t0 + h, t1, alpha), build(t0 - h, t1, alpha)),
            (1, build(t0, t1 + h, alpha), build(t0, t1 - h, alpha)),
            (2, build(t0, t1, alpha + h), build(t0, t1, alpha - h)),
        ] {
            for (i, &s) in feet.iter().enumerate() {
                let theta = segment.theta(s);
                let normal = Vec2::new(-theta.sin(), theta.cos());
                let t = s / length;
                let difference = (plus.point(t * plus.length()) - minus.point(t * minus.length()))
                    .dot(normal)
                    / (2.0 * h);
                let d = [got[i].start_angle, got[i].end_angle, got[i].alpha][which];
                assert!(
                    (d.dot(normal) - difference).abs() <= 1e-5 * length,
                    "α {alpha:?} κ {} → {}, unknown {which}, foot {i}: {} vs {difference}",
                    segment.kappa0(),
                    segment.kappa1(),
                    d.dot(normal)
                );
            }
        }
    }
}
