//! Quadrature of the unit tangent, P(b) − P(a) = ∫_a^b e^{iθ(s)} ds: the Gauss–Legendre rules and
//! panels every integrator in [`super`] is written with, and the adaptive arc-length integrator
//! of the standard form ([`integrate`]).
//!
//! ## The vocabulary
//! An n-node Gauss–Legendre rule {(w_j, x_j)} on [−1, 1] integrates polynomials of degree
//! 2n − 1 exactly. On a panel with middle m and half width h,
//!
//! ∫_{m−h}^{m+h} f(s) ds ≈ h·Σ_j w_j·f(m + h·x_j),
//!
//! and for f = e^{iθ} with θ turning by φ over the panel the relative error falls like (φ/2)^{2n}
//! over a factorial in n (for θ linear in s, 2^{2n+1}(n!)⁴/((2n+1)((2n)!)³)·(φ/2)^{2n}; see
//! [`super::log_radius::rule_for`]): so every integrator bounds a panel's turning (and, where the
//! variable is ln ρ, the growth of the amplitude) and picks n from it. The pieces:
//!
//! * the rules: `GAUSS_LEGENDRE_2`, `GAUSS_LEGENDRE_3` (here, nodes in increasing order) and
//!   kurbo's 8-, 11- and 16-node tables;
//! * `Panel`: a panel as (middle, half width), `Panel::over` one panel, `Panel::equal` n
//!   equal ones, `panel_count` how many equal panels keep each below a turning;
//! * `add_nodes`: a rule's weighted node values on a panel added to a running sum, node by node
//!   in the rule's order (the value type is a [`Vec2`] or a fixed array of them, `Accumulate`).
//!
//! ## The integrators
//! | where | variable | rule and panels | accuracy | used for |
//! |---|---|---|---|---|
//! | [`super::log_radius`] | w = ln ρ | 8/11/16 nodes ([`super::log_radius::rule_for`]), adaptive panels, nodes paired about the middle; a series for the settling tail (α < 0) | 1e-15 | every point of a spiral ([`super::StandardLac::point`]), the Yoshida–Saito construction |
//! | [`integrate`] (here) | s | 16 nodes, adaptive panels graded in ln ρ; a series at the κ = 0 end (α < 0) | 1e-16 | the standard form with Λ = 0; the cross-check of the others |
//! | `deviation::integrate_within` | s | 3 nodes, equal panels turning ≤ `POLISH_STEP_TURN` (0.1), graded in \|κ\|, nodes from the middle's e^{iθ}; a series next to a curvature zero | 1e-12 (1e-8 where κ changes fast) | points at foot points, from one to the next (the foot polish) |
//! | `sensitivity` | w = ln ρ | 2 nodes on one panel (phase spread ≤ 0.05) or 3 nodes on equal panels turning ≤ 0.5, four integrands at once (the point and its three derivatives) | 1e-8 | the chain refinement's Jacobian |
//! | `sensitivity::arc_sensitivities` | s/S | 3 nodes on equal panels turning ≤ 0.5, with the moments ∫ x^k e^{iθ} (k ≤ 2) | 1e-8 | the same for circular arcs |
//!
//! Lines and circular arcs need no quadrature: [`super::LacSegment`] integrates them in closed
//! form (an arc's chord over arc length d from θ_a is d·e^{i(θ_a + κd/2)}·sinc(κd/2)), and so
//! does [`super::StandardLac`] for α = 1 and α = 2.
//!
//! They stay five because each is tuned to its accuracy and its cost: a fit evaluates points by
//! the hundred thousand, and each integrator sums its terms in an order the fits' outputs depend
//! on bit for bit. No two of them give the same bits for the same point: the foot polish's
//! points lie within its accuracy of the log-radius ones (up to about 1e-8 of the length where
//! the curvature changes fast, see `deviation::POLISH_STEP_TURN`), the arc-length reference
//! within rounding of them, but almost every point differs in its last bits, and with them would
//! move every fit: the Gauss–Newton steps, the α searches and the chain's decisions that follow
//! from them. What they share is written once here: the rules, the panels and the node sums.
//!
//! ## The arc-length integrator
//! [`integrate`] is the reference: 16 nodes everywhere, its panels kept clear of the branch
//! point of θ(s).
//!
//! ### Panels
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
//! ### The κ = 0 end (α < 0)
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

/// The 2-point Gauss–Legendre rule on [−1, 1] as (weight, abscissa): nodes ±1/√3, weights 1;
/// exact for cubics.
pub(crate) const GAUSS_LEGENDRE_2: [(f64, f64); 2] = [(1.0, -GL2_NODE), (1.0, GL2_NODE)];

/// 1/√3, the 2-point rule's abscissa.
const GL2_NODE: f64 = 0.577_350_269_189_625_8;

/// The 3-point Gauss–Legendre rule on [−1, 1] as (weight, abscissa), nodes in increasing order:
/// −√(3/5), 0, √(3/5) with weights 5/9, 8/9, 5/9; exact for quintics.
pub(crate) const GAUSS_LEGENDRE_3: [(f64, f64); 3] = [
    (5.0 / 9.0, -GL3_NODE),
    (8.0 / 9.0, 0.0),
    (5.0 / 9.0, GL3_NODE),
];

/// √(3/5), the 3-point rule's outer abscissa.
const GL3_NODE: f64 = 0.774_596_669_241_483_4;

/// One panel of a quadrature: [mid − half, mid + half].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Panel {
    /// The middle of the panel.
    pub mid: f64,
    /// Half its width (negative for a panel run backwards, b < a).
    pub half: f64,
}

impl Panel {
    /// The single panel [a, b]: middle (a + b)/2, half width (b − a)/2.
    pub fn over(a: f64, b: f64) -> Self {
        Self {
            mid: 0.5 * (a + b),
            half: 0.5 * (b - a),
        }
    }

    /// [a, b] cut into `n` equal panels, in order from a: with h = (b − a)/n, the k-th has middle
    /// a + (k + ½)·h and half width h/2.
    pub fn equal(a: f64, b: f64, n: usize) -> impl Iterator<Item = Self> {
        let step = (b - a) / n as f64;
        (0..n).map(move |k| Self {
            mid: a + step * (k as f64 + 0.5),
            half: 0.5 * step,
        })
    }

    /// The point of the panel at abscissa `x` ∈ [−1, 1] of a rule: mid + half·x.
    pub fn node(&self, x: f64) -> f64 {
        self.mid + self.half * x
    }
}

/// How many equal panels keep each one's `turning` (or whatever bounds the rule's error: a
/// phase change, an exponent's change) at most `max_per_panel`: ⌈turning/max_per_panel⌉, at
/// least 1 (also for a NaN turning).
pub(crate) fn panel_count(turning: f64, max_per_panel: f64) -> usize {
    ((turning / max_per_panel).ceil() as usize).max(1)
}

/// A sum a quadrature accumulates: one integrand ([`Vec2`], a complex number) or several
/// evaluated at the same nodes (`[Vec2; N]`, added component by component).
pub(crate) trait Accumulate: Copy {
    /// `self += value`.
    fn accumulate(&mut self, value: Self);
}

impl Accumulate for Vec2 {
    fn accumulate(&mut self, value: Self) {
        *self += value;
    }
}

impl<const N: usize> Accumulate for [Vec2; N] {
    fn accumulate(&mut self, value: Self) {
        for (s, v) in self.iter_mut().zip(value) {
            *s += v;
        }
    }
}

/// Adds `value(node, weight)` to `sum` for each (weight, abscissa) of `rule` on `panel`, in the
/// rule's order, node = [`Panel::node`] of the abscissa. The closure applies the weight (and
/// the half width, or the caller multiplies the panel's sum by it): Σ_j w_j·f(m + h·x_j), the
/// panel's integral over h.
pub(crate) fn add_nodes<T: Accumulate>(
    sum: &mut T,
    rule: &[(f64, f64)],
    panel: Panel,
    mut value: impl FnMut(f64, f64) -> T,
) {
    for &(weight, x) in rule {
        sum.accumulate(value(panel.node(x), weight));
    }
}

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
    let panel = Panel::over(a, b);
    let mut sum = Vec2::ZERO;
    add_nodes(&mut sum, GAUSS_LEGENDRE_COEFFS_16, panel, |s, w| {
        cis(lac.theta(s)) * w
    });
    sum * panel.half
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

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫_a^b e^{i(θ0 + κs)} ds in closed form, (e^{iθ(b)} − e^{iθ(a)})/(iκ), κ ≠ 0.
    fn linear_phase_integral(theta0: f64, kappa: f64, a: f64, b: f64) -> Vec2 {
        let d = cis(theta0 + kappa * b) - cis(theta0 + kappa * a);
        Vec2::new(d.y, -d.x) * (1.0 / kappa)
    }

    /// Σ over equal panels of the rule's nodes, the panel sums scaled by the half width.
    fn panels(rule: &[(f64, f64)], a: f64, b: f64, n: usize, f: impl Fn(f64) -> Vec2) -> Vec2 {
        let mut sum = Vec2::ZERO;
        for panel in Panel::equal(a, b, n) {
            add_nodes(&mut sum, rule, panel, |s, w| f(s) * (w * panel.half));
        }
        sum
    }

    #[test]
    fn the_rules_are_exact_to_their_degree_and_not_beyond() {
        // Σ w·x^k = ∫_{−1}^{1} x^k dx = 2/(k + 1) for even k, 0 for odd, up to degree 2n − 1.
        let moment = |rule: &[(f64, f64)], k: i32| rule.iter().map(|&(w, x)| w * x.powi(k)).sum();
        let exact = |k: i32| {
            if k % 2 == 0 {
                2.0 / f64::from(k + 1)
            } else {
                0.0
            }
        };
        for (rule, n) in [(&GAUSS_LEGENDRE_2[..], 2), (&GAUSS_LEGENDRE_3[..], 3)] {
            for k in 0..2 * n {
                let m: f64 = moment(rule, k);
                assert!((m - exact(k)).abs() < 1e-15, "n = {n}, x^{k}: {m}");
            }
            let m: f64 = moment(rule, 2 * n);
            assert!(
                (m - exact(2 * n)).abs() > 1e-3,
                "n = {n} exact at x^{}",
                2 * n
            );
            // Nodes in increasing order, symmetric about 0.
            assert!(rule.windows(2).all(|p| p[0].1 < p[1].1));
            assert!(
                rule.iter()
                    .zip(rule.iter().rev())
                    .all(|(l, r)| l.1 == -r.1 && l.0 == r.0)
            );
        }
    }

    #[test]
    fn equal_panels_tile_the_interval() {
        for (a, b, n) in [
            (0.0, 1.0, 1),
            (2.5, 9.0, 7),
            (9.0, 2.5, 3),
            (-1.0, 1e-3, 64),
        ] {
            let panels: Vec<Panel> = Panel::equal(a, b, n).collect();
            assert_eq!(panels.len(), n);
            let scale = a.abs().max(b.abs());
            assert!((panels[0].node(-1.0) - a).abs() <= 1e-15 * scale);
            assert!((panels[n - 1].node(1.0) - b).abs() <= 1e-15 * scale);
            for p in panels.windows(2) {
                assert!((p[0].node(1.0) - p[1].node(-1.0)).abs() <= 1e-15 * scale);
                assert_eq!(p[0].half, p[1].half);
            }
            let whole = Panel::over(a, b);
            assert!((whole.node(-1.0) - a).abs() <= 1e-15 * scale);
            assert!((whole.node(1.0) - b).abs() <= 1e-15 * scale);
        }
    }

    #[test]
    fn panel_count_is_the_ceiling_and_at_least_one() {
        assert_eq!(panel_count(0.0, 0.1), 1);
        assert_eq!(panel_count(0.05, 0.1), 1);
        assert_eq!(panel_count(0.25, 0.1), 3);
        assert_eq!(panel_count(2.0, 0.5), 4);
        assert_eq!(panel_count(f64::NAN, 0.5), 1);
    }

    #[test]
    fn a_linear_phase_is_integrated_to_the_rules_accuracy() {
        // θ linear in s: a circular arc, whose integral is known in closed form. Panels turning
        // at most φ = 0.1 rad by 3 nodes, error h·φ⁶/2 016 000 ≈ 5e-13 of the panel's length h;
        // at most 1 rad by 16 nodes, error far below rounding.
        for (theta0, kappa, a, b) in [
            (0.3, 0.02, 0.0, 40.0),
            (-2.0, -1.5, 1.0, 3.0),
            (1.0, 5e-4, 0.0, 1e3),
        ] {
            let exact = linear_phase_integral(theta0, kappa, a, b);
            let f = |s: f64| cis(theta0 + kappa * s);
            let turning = kappa.abs() * (b - a);
            let three = panels(&GAUSS_LEGENDRE_3, a, b, panel_count(turning, 0.1), f);
            assert!(
                (three - exact).hypot() < 1e-12 * (b - a),
                "{three:?} {exact:?}"
            );
            let sixteen = panels(GAUSS_LEGENDRE_COEFFS_16, a, b, panel_count(turning, 1.0), f);
            assert!(
                (sixteen - exact).hypot() < 1e-15 * (b - a),
                "{sixteen:?} {exact:?}"
            );
            // Two nodes on a panel turning 0.05 (the sensitivities' one-panel case): (τ/2)^4/135.
            let short = a + 0.05 / kappa.abs();
            let two = panels(&GAUSS_LEGENDRE_2, a, short, 1, f);
            let exact = linear_phase_integral(theta0, kappa, a, short);
            assert!((two - exact).hypot() < 4e-9 * (short - a));
        }
    }

    #[test]
    fn the_unit_circle_has_its_chord() {
        // Λ = 0 is the unit circle, integrated here whatever α: from s = 0 along s, the chord
        // has length 2·sin(s/2) and points along s/2.
        for alpha in [-1.0, 0.0, 0.5, 3.0] {
            let lac = StandardLac::new(alpha, 0.0).expect("circle");
            for s in [1e-3, 0.5, 2.0, 3.0, 6.0] {
                let chord = integrate(&lac, 0.0, s);
                assert!((chord.hypot() - 2.0 * (0.5 * s).sin()).abs() < 2e-15, "{s}");
                assert!((chord.atan2() - 0.5 * s).abs() < 2e-15, "{s}");
                // Split anywhere, the pieces add up.
                let split = integrate(&lac, 0.0, 0.3 * s) + integrate(&lac, 0.3 * s, s);
                assert!((split - chord).hypot() < 2e-15);
            }
        }
    }

    #[test]
    fn several_integrands_accumulate_component_by_component() {
        // ∫₀¹ [1, x, x²] dx = [1, 1/2, 1/3], by 3 nodes (exact for quintics) on 4 panels.
        let mut sum = [Vec2::ZERO; 3];
        for panel in Panel::equal(0.0, 1.0, 4) {
            add_nodes(&mut sum, &GAUSS_LEGENDRE_3, panel, |x, w| {
                let e = Vec2::new(w * panel.half, 0.0);
                [e, e * x, e * (x * x)]
            });
        }
        for (got, want) in sum.iter().zip([1.0, 0.5, 1.0 / 3.0]) {
            assert!((got.x - want).abs() < 1e-15 && got.y == 0.0, "{got:?}");
        }
    }
}
