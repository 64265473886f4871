//! Signed curvature of one cubic Bézier piece, and the polynomials whose roots are its inflections
//! and curvature extrema (Miura et al. §3.5–3.6).
//!
//! # Formulas
//!
//! Let `P0..P3` be the control points and `d_i = P_{i+1} − P_i` (i = 0, 1, 2) the control-polygon
//! legs, so `C′(t) = 3 q(t)` with the quadratic Bézier
//!
//! ```text
//! q(t) = (1−t)² d0 + 2t(1−t) d1 + t² d2 = d0 + 2e t + A t²,   e = d1 − d0,  A = d2 − 2 d1 + d0,
//! q′(t) = 2 (e + A t),   C″(t) = 3 q′(t).
//! ```
//!
//! With `a × b = a_x b_y − a_y b_x`, the paper's `g = x′y″ − x″y′ = C′ × C″ = 9 q × q′`, and
//! `q × q′ = 2 [d0×e + (d0×A) t + (e×A) t²]`: the `t³` terms cancel (`A × A = 0`), so **`g` is a
//! quadratic**, not a cubic. In Bernstein form it is strikingly simple:
//!
//! ```text
//! g(t) = 18 γ(t),   γ(t) = (1−t)² (d0×d1) + 2t(1−t) (½ d0×d2) + t² (d1×d2).
//! ```
//!
//! The paper's `f = x′² + y′² = 9 φ(t)` with the quartic `φ = |q|²`:
//!
//! ```text
//! φ = d0·d0 + 4(d0·e) t + (4 e·e + 2 d0·A) t² + 4(e·A) t³ + (A·A) t⁴.
//! ```
//!
//! Hence `κ = g / f^{3/2} = (2/3) γ / φ^{3/2}` and
//! `dκ/dt = (2/3)(γ′φ − (3/2)γφ′)/φ^{5/2} = h / (3 φ^{5/2})` with
//!
//! ```text
//! h(t) = 2 γ′ φ − 3 γ φ′,
//! ```
//!
//! the paper's equation (7) up to the positive factor 162. Degrees: `γ′` is linear and `φ` quartic,
//! `γ` quadratic and `φ′` cubic, so **`h` has degree ≤ 5** (leading coefficient
//! `−8 (e×A)(A·A)`), not 6. Finally `d|κ|/dt = sign(γ) · h / (3 φ^{5/2})`.
//!
//! Everything is computed from the legs `d_i`, which makes it exactly translation invariant, and
//! the legs are divided by their largest length `s` first, so the polynomial coefficients are
//! `O(1)` whatever the stroke's units (κ is then divided by `s`).

use super::poly::{Poly, Root, Roots, roots_in};
use crate::geom::{CubicBez, Vec2};
use kurbo::common::solve_quadratic;

/// Smallest speed `|C′(t)|`, relative to the piece's largest control-polygon leg (times 3), that
/// counts as a regular parametrisation. Below it the piece has a cusp or a stationary point where
/// κ blows up like `1/speed`: the curvature is meaningless there and the piece must be split at
/// a corner (or refitted) upstream. 1e-9 lets through anything a least-squares fit produces for a
/// real stroke (whose speed varies by a few orders of magnitude at most) while rejecting
/// coincident control points that only differ by rounding.
const DEGENERATE_SPEED_RELATIVE: f64 = 1e-9;

/// Sign-changing roots in `(0, 1)` of `c0 + c1 t + c2 t²`, ascending, by [`solve_quadratic`]. A
/// single root of a genuine quadratic is a double root (discriminant exactly zero, the polynomial
/// only touches zero) and is not returned; solve_quadratic's own test decides whether it treated
/// the equation as linear.
fn quadratic_crossings([c0, c1, c2]: [f64; 3]) -> Roots {
    let mut out = Roots::new();
    let found = solve_quadratic(c0, c1, c2);
    let genuinely_quadratic = (c0 / c2).is_finite() && (c1 / c2).is_finite();
    if found.len() == 1 && genuinely_quadratic {
        return out;
    }
    for &t in &found {
        if t > 0.0 && t < 1.0 {
            out.push(Root { t, crossing: true });
        }
    }
    out
}

/// Curvature data of one cubic Bézier, in its local parameter `t ∈ [0, 1]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PieceCurvature {
    /// Control-polygon legs divided by `scale`.
    legs: [Vec2; 3],
    /// The largest leg length `s` the legs were divided by.
    scale: f64,
    /// Bernstein coefficients of `γ` (normalised legs).
    gamma_bernstein: [f64; 3],
    /// `γ` in the power basis.
    gamma: [f64; 3],
    /// The extremum polynomial `h = 2γ′φ − 3γφ′`.
    h: Poly,
}

impl PieceCurvature {
    /// Curvature data of `bez`, or `None` when the piece is not regular (its speed `|C′|` falls
    /// below [`DEGENERATE_SPEED_RELATIVE`] somewhere on `[0, 1]`, including the all-points-equal
    /// piece) or its coordinates are not finite.
    pub(crate) fn new(bez: &CubicBez) -> Option<PieceCurvature> {
        let raw = [bez.p1 - bez.p0, bez.p2 - bez.p1, bez.p3 - bez.p2];
        let scale = raw.iter().map(|d| d.hypot()).fold(0.0, f64::max);
        if !(scale.is_finite() && scale > 0.0) {
            return None;
        }
        let legs = raw.map(|d| d / scale);
        let [d0, d1, d2] = legs;
        let e = d1 - d0;
        let a = (d2 - d1) - (d1 - d0);

        let gamma_bernstein = [d0.cross(d1), 0.5 * d0.cross(d2), d1.cross(d2)];
        let [b0, b1, b2] = gamma_bernstein;
        let gamma = [b0, 2.0 * (b1 - b0), (b0 - b1) + (b2 - b1)];

        let phi = [
            d0.dot(d0),
            4.0 * d0.dot(e),
            4.0 * e.dot(e) + 2.0 * d0.dot(a),
            4.0 * e.dot(a),
            a.dot(a),
        ];
        let dphi = [phi[1], 2.0 * phi[2], 3.0 * phi[3], 4.0 * phi[4]];
        let dgamma = [gamma[1], 2.0 * gamma[2]];
        let h = Poly::product(&[2.0 * dgamma[0], 2.0 * dgamma[1]], &phi)
            .add_scaled(-3.0, &Poly::product(&gamma, &dphi));

        // Regularity: the minimum of φ = |q|² on [0, 1] is at an end or at a root of φ′.
        let phi_poly = Poly::new(phi);
        let dphi_poly = Poly::new(dphi);
        let min_phi = roots_in(&dphi_poly, 0.0, 1.0)
            .as_slice()
            .iter()
            .map(|r| phi_poly.eval(r.t))
            .fold(phi_poly.eval(0.0).min(phi_poly.eval(1.0)), f64::min);
        if min_phi.is_nan() || min_phi < DEGENERATE_SPEED_RELATIVE * DEGENERATE_SPEED_RELATIVE {
            return None;
        }
        Some(PieceCurvature {
            legs,
            scale,
            gamma_bernstein,
            gamma,
            h,
        })
    }

    /// `q(t) = C′(t) / (3s)`: the tangent direction, in normalised units.
    pub(crate) fn tangent(&self, t: f64) -> Vec2 {
        let [d0, d1, d2] = self.legs;
        let mt = 1.0 - t;
        d0 * (mt * mt) + d1 * (2.0 * t * mt) + d2 * (t * t)
    }

    /// `γ(t)` (sign of the curvature), from the Bernstein form.
    fn gamma_at(&self, t: f64) -> f64 {
        let [b0, b1, b2] = self.gamma_bernstein;
        let mt = 1.0 - t;
        b0 * mt * mt + 2.0 * b1 * t * mt + b2 * t * t
    }

    /// Signed curvature `κ(t) = (2/3) γ(t) / (s · |q(t)|³)` (positive turning left, i.e.
    /// counter-clockwise in a y-up frame).
    pub(crate) fn kappa(&self, t: f64) -> f64 {
        let speed = self.tangent(t).hypot();
        (2.0 / 3.0) * self.gamma_at(t) / (self.scale * speed * speed * speed)
    }

    /// Inflections: the roots of the quadratic `γ` in `(0, 1)` where it changes sign, solved in
    /// closed form by [`solve_quadratic`] (which stays accurate for a vanishing leading
    /// coefficient by switching to the linear solution). A double root (κ touching zero) is not an
    /// inflection and is not returned; for a regular piece it only occurs when the piece is a
    /// straight line (γ = γ′ = 0 forces `q`, `q′`, `q″` parallel), where γ vanishes identically.
    pub(crate) fn inflections(&self) -> Roots {
        quadratic_crossings(self.gamma)
    }

    /// Curvature extrema: roots of `h` in `(0, 1)` where `h` changes sign. There `dκ/dt` changes
    /// sign; `γ` does not vanish (a simple root of `γ` has `h = 2γ′φ ≠ 0`), so `d|κ|/dt` changes
    /// sign too.
    pub(crate) fn extrema(&self) -> Roots {
        let all = roots_in(&self.h, 0.0, 1.0);
        let mut out = Roots::new();
        for r in all.as_slice().iter().filter(|r| r.crossing) {
            out.push(*r);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{ParamCurve, ParamCurveDeriv, Point, curvature_from_derivs};

    fn bez(p: [(f64, f64); 4]) -> CubicBez {
        CubicBez::new(p[0], p[1], p[2], p[3])
    }

    /// Curvature straight from kurbo's derivatives, independent of the polynomials above.
    fn reference_kappa(c: &CubicBez, t: f64) -> f64 {
        let d1 = c.deriv();
        let d2 = d1.deriv();
        curvature_from_derivs(d1.eval(t).to_vec2(), d2.eval(t).to_vec2())
    }

    /// The cubic that is the degree elevation of a quadratic Bézier.
    fn elevated(q0: Point, q1: Point, q2: Point) -> CubicBez {
        CubicBez::new(q0, q0.lerp(q1, 2.0 / 3.0), q2.lerp(q1, 2.0 / 3.0), q2)
    }

    #[test]
    fn kappa_matches_the_derivative_formula() {
        let c = bez([(0.0, 0.0), (1.0, 3.0), (4.0, -2.0), (6.0, 1.0)]);
        let k = PieceCurvature::new(&c).expect("regular piece");
        for i in 0..=20 {
            let t = i as f64 / 20.0;
            let (a, b) = (k.kappa(t), reference_kappa(&c, t));
            assert!(
                (a - b).abs() <= 1e-12 * b.abs().max(1.0),
                "t={t}: {a} vs {b}"
            );
        }
    }

    #[test]
    fn h_has_degree_five_and_gamma_degree_two() {
        let c = bez([(0.0, 0.0), (1.0, 3.0), (4.0, -2.0), (6.0, 1.0)]);
        let k = PieceCurvature::new(&c).expect("regular piece");
        assert_eq!(k.h.degree(), Some(5));
        // h is dκ/dt up to the positive factor 3 φ^{5/2}: check its sign against finite differences.
        let step = 1e-6;
        for i in 1..20 {
            let t = i as f64 / 20.0;
            let fd = (reference_kappa(&c, t + step) - reference_kappa(&c, t - step)) / (2.0 * step);
            let phi = k.tangent(t).hypot2();
            let predicted = k.h.eval(t) / (3.0 * phi.powf(2.5) * k.scale);
            assert!(
                (fd - predicted).abs() <= 1e-5 * fd.abs().max(1.0),
                "t={t}: {fd} vs {predicted}"
            );
        }
    }

    #[test]
    fn symmetric_s_has_its_inflection_at_one_half() {
        // Point-symmetric about (1.5, 0): the inflection is exactly at t = 1/2.
        let c = bez([(0.0, 0.0), (1.0, 1.0), (2.0, -1.0), (3.0, 0.0)]);
        let k = PieceCurvature::new(&c).expect("regular piece");
        let roots: Vec<f64> = k.inflections().crossings().collect();
        assert_eq!(roots.len(), 1);
        assert!((roots[0] - 0.5).abs() < 1e-15, "{roots:?}");
    }

    #[test]
    fn asymmetric_inflection_matches_the_closed_form() {
        // d0 = (1, 0), d1 = (0, 1), d2 = (1, −3/2): Bernstein coefficients of γ are
        // d0×d1 = 1, ½ d0×d2 = −3/4, d1×d2 = −1, i.e. γ = 1 − 7/2 t + 3/2 t² = (1 − 3t)(2 − t)/2:
        // the inflection is t = 1/3 (the other root, 2, is off the piece).
        let c = bez([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (2.0, -0.5)]);
        let k = PieceCurvature::new(&c).expect("regular piece");
        let roots: Vec<f64> = k.inflections().crossings().collect();
        assert_eq!(roots.len(), 1, "{roots:?}");
        assert!((roots[0] - 1.0 / 3.0).abs() < 1e-15, "{roots:?}");
        // And κ really changes sign there.
        assert!(
            reference_kappa(&c, 1.0 / 3.0 - 1e-6) * reference_kappa(&c, 1.0 / 3.0 + 1e-6) < 0.0
        );
    }

    #[test]
    fn touching_zero_is_not_an_inflection() {
        // For a regular, non-straight cubic γ cannot have a double root (γ = γ′ = 0 forces q, q′
        // and q″ to be parallel, i.e. a straight line), so the classification is tested on γ alone.
        assert_eq!(quadratic_crossings([1.0, -4.0, 4.0]).as_slice().len(), 0); // (1 − 2t)²
        let two: Vec<f64> = quadratic_crossings([0.18, -0.9, 1.0]).crossings().collect(); // (t−0.3)(t−0.6)
        assert_eq!(two.len(), 2);
        assert!(
            (two[0] - 0.3).abs() < 1e-15 && (two[1] - 0.6).abs() < 1e-15,
            "{two:?}"
        );
        let linear: Vec<f64> = quadratic_crossings([-0.25, 1.0, 0.0]).crossings().collect();
        assert_eq!(linear, vec![0.25]);
        // Leading coefficient 1e-300: effectively linear, the root is still found.
        let near: Vec<f64> = quadratic_crossings([-0.25, 1.0, 1e-300])
            .crossings()
            .collect();
        assert_eq!(near, vec![0.25]);
    }

    #[test]
    fn symmetric_arch_has_its_extremum_at_one_half() {
        let c = bez([(0.0, 0.0), (1.0, 2.0), (3.0, 2.0), (4.0, 0.0)]);
        let k = PieceCurvature::new(&c).expect("regular piece");
        let ext: Vec<f64> = k.extrema().crossings().collect();
        assert_eq!(ext.len(), 1, "{ext:?}");
        assert!((ext[0] - 0.5).abs() < 1e-14, "{ext:?}");
        assert_eq!(k.inflections().as_slice().len(), 0);
    }

    #[test]
    fn parabola_vertex_is_the_extremum() {
        // y = x² on x ∈ [−1, 3] as a quadratic Bézier (Q1 = (1, −3)), elevated to a cubic.
        // x(t) = −1 + 4t, so the vertex x = 0 is at t = 1/4, where κ = 2.
        let c = elevated(
            Point::new(-1.0, 1.0),
            Point::new(1.0, -3.0),
            Point::new(3.0, 9.0),
        );
        let k = PieceCurvature::new(&c).expect("regular piece");
        let ext: Vec<f64> = k.extrema().crossings().collect();
        assert_eq!(ext.len(), 1, "{ext:?}");
        assert!((ext[0] - 0.25).abs() < 1e-14, "{ext:?}");
        assert!((k.kappa(0.25) - 2.0).abs() < 1e-13);
        assert_eq!(k.inflections().as_slice().len(), 0);
        // A degree-elevated quadratic has A = 0 in exact arithmetic, so h's degree-4 and -5
        // coefficients are pure rounding noise here: the isolation copes with that.
    }

    #[test]
    fn irregular_pieces_are_rejected() {
        let p = (1.0, 1.0);
        assert!(PieceCurvature::new(&bez([p, p, p, p])).is_none());
        // A cusp: the speed vanishes at t = 1/2.
        let cusp = bez([(0.0, 0.0), (1.0, 1.0), (0.0, 1.0), (1.0, 0.0)]);
        assert!(PieceCurvature::new(&cusp).is_none());
        // Stationary end point (P0 = P1).
        let stationary = bez([(0.0, 0.0), (0.0, 0.0), (1.0, 1.0), (2.0, 0.0)]);
        assert!(PieceCurvature::new(&stationary).is_none());
        let nan = bez([(0.0, 0.0), (f64::NAN, 0.0), (1.0, 1.0), (2.0, 0.0)]);
        assert!(PieceCurvature::new(&nan).is_none());
    }
}
