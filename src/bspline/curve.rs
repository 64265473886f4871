//! The clamped cubic B-spline, its evaluation and its decomposition into Bézier pieces.

use crate::geom::{CubicBez, ParamBez, Point};

/// Degree of every B-spline in kansei.
pub const DEGREE: usize = 3;

/// A clamped cubic B-spline on the parameter domain `[knots[3], knots[n]]` (kansei's fits use
/// `[0, 1]`).
///
/// With `n` control points the knot vector has `n + 4` entries, the first four and the last four
/// equal (clamped: the curve starts at the first control point and ends at the last), interior
/// knots non-decreasing. The curve is
/// C(u) = Σⱼ Nⱼ,₃(u) Pⱼ with the Cox–de Boor basis Nⱼ,₃.
#[derive(Clone, Debug, PartialEq)]
pub struct BSpline {
    knots: Vec<f64>,
    control_points: Vec<Point>,
}

/// Why a knot vector and control points do not make a clamped cubic B-spline.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BSplineError {
    /// `knots.len()` must be `control_points.len() + 4`, with at least 4 control points.
    #[error("{knots} knots do not fit {control_points} control points (need n + 4, n ≥ 4)")]
    Shape {
        /// Number of knots given.
        knots: usize,
        /// Number of control points given.
        control_points: usize,
    },
    /// Knots decrease, are non-finite, the domain is empty, or the ends are not clamped.
    #[error("the knot vector is not clamped, finite and non-decreasing with a non-empty domain")]
    Knots,
    /// A control point is not finite.
    #[error("control point {0} is not finite")]
    ControlPoint(usize),
}

impl BSpline {
    /// A B-spline from its knots and control points, checked.
    pub fn new(knots: Vec<f64>, control_points: Vec<Point>) -> Result<Self, BSplineError> {
        let n = control_points.len();
        if n < DEGREE + 1 || knots.len() != n + DEGREE + 1 {
            return Err(BSplineError::Shape {
                knots: knots.len(),
                control_points: n,
            });
        }
        let sorted = knots.windows(2).all(|w| w[0] <= w[1]);
        let finite = knots.iter().all(|k| k.is_finite());
        let clamped = knots[..=DEGREE].iter().all(|&k| k == knots[0])
            && knots[n..].iter().all(|&k| k == knots[n + DEGREE]);
        if !sorted || !finite || !clamped || knots[DEGREE] >= knots[n] {
            return Err(BSplineError::Knots);
        }
        if let Some(i) = control_points
            .iter()
            .position(|p| !(p.x.is_finite() && p.y.is_finite()))
        {
            return Err(BSplineError::ControlPoint(i));
        }
        Ok(BSpline {
            knots,
            control_points,
        })
    }

    /// The clamped knot vector on `[0, 1]` with `segments` equal spans.
    pub fn uniform_knots(segments: usize) -> Vec<f64> {
        let segments = segments.max(1);
        let mut knots = vec![0.0; DEGREE + 1];
        knots.extend((1..segments).map(|i| i as f64 / segments as f64));
        knots.extend([1.0; DEGREE + 1]);
        knots
    }

    /// The knot vector.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// The control points.
    pub fn control_points(&self) -> &[Point] {
        &self.control_points
    }

    /// The parameter domain `(u_min, u_max)`.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[DEGREE], self.knots[self.control_points.len()])
    }

    /// Number of non-empty knot spans (polynomial segments).
    pub fn segment_count(&self) -> usize {
        let n = self.control_points.len();
        (DEGREE..n)
            .filter(|&k| self.knots[k] < self.knots[k + 1])
            .count()
    }

    /// Index `k` of the knot span holding `u`: `knots[k] ≤ u < knots[k + 1]`, with the domain's
    /// right end assigned to the last non-empty span. `u` is clamped to the domain.
    pub fn find_span(&self, u: f64) -> usize {
        let n = self.control_points.len();
        let (lo, hi) = self.domain();
        let u = u.clamp(lo, hi);
        if u >= hi {
            // Last non-empty span.
            let mut k = n - 1;
            while k > DEGREE && self.knots[k] >= self.knots[k + 1] {
                k -= 1;
            }
            return k;
        }
        // Largest k in [DEGREE, n-1] with knots[k] <= u.
        let idx = self.knots[DEGREE..n].partition_point(|&k| k <= u);
        DEGREE + idx.saturating_sub(1)
    }

    /// The four non-zero cubic basis functions at `u` in span `k` (Cox–de Boor, Piegl & Tiller
    /// algorithm A2.2): `N[k−3..=k]`.
    pub fn basis(&self, k: usize, u: f64) -> [f64; 4] {
        basis_functions(&self.knots, k, u)
    }

    /// The point at parameter `u`.
    pub fn eval(&self, u: f64) -> Point {
        let k = self.find_span(u);
        self.blossom(k, [u, u, u])
    }

    /// The blossom (polar form) of span `k`'s polynomial at the three arguments: de Boor's
    /// algorithm with a different argument at each level. `blossom(k, [u, u, u])` is the point at
    /// `u`; `blossom(k, [a, a, b])` with `[a, b]` the span is its second Bézier control point.
    pub fn blossom(&self, k: usize, args: [f64; 3]) -> Point {
        let t = &self.knots;
        let mut d = [
            self.control_points[k - 3],
            self.control_points[k - 2],
            self.control_points[k - 1],
            self.control_points[k],
        ];
        for r in 1..=DEGREE {
            let x = args[r - 1];
            for j in (r..=DEGREE).rev() {
                let left = t[j + k - DEGREE];
                let right = t[j + 1 + k - r];
                let a = if right > left {
                    (x - left) / (right - left)
                } else {
                    0.0
                };
                d[j] = d[j - 1].lerp(d[j], a);
            }
        }
        d[DEGREE]
    }

    /// The curve as one cubic Bézier per non-empty knot span, in order.
    ///
    /// The Bézier control points of span `[a, b]` are the blossom values at (a,a,a), (a,a,b),
    /// (a,b,b), (b,b,b) (Ramshaw's polar forms), so the decomposition is exact up to rounding.
    pub fn to_beziers(&self) -> Vec<ParamBez> {
        let n = self.control_points.len();
        (DEGREE..n)
            .filter(|&k| self.knots[k] < self.knots[k + 1])
            .map(|k| {
                let (a, b) = (self.knots[k], self.knots[k + 1]);
                ParamBez {
                    bez: CubicBez::new(
                        self.blossom(k, [a, a, a]),
                        self.blossom(k, [a, a, b]),
                        self.blossom(k, [a, b, b]),
                        self.blossom(k, [b, b, b]),
                    ),
                    u0: a,
                    u1: b,
                }
            })
            .collect()
    }
}

/// The four non-zero cubic basis functions at `u` in knot span `k` of `knots`
/// (Piegl & Tiller, *The NURBS Book*, algorithm A2.2).
pub(crate) fn basis_functions(knots: &[f64], k: usize, u: f64) -> [f64; 4] {
    let mut n = [0.0; 4];
    let mut left = [0.0; 4];
    let mut right = [0.0; 4];
    n[0] = 1.0;
    for j in 1..=DEGREE {
        left[j] = u - knots[k + 1 - j];
        right[j] = knots[k + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            let denom = right[r + 1] + left[j - r];
            let temp = if denom != 0.0 { n[r] / denom } else { 0.0 };
            n[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        n[j] = saved;
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::ParamCurve;

    fn sample_spline() -> BSpline {
        let knots = vec![0.0, 0.0, 0.0, 0.0, 0.2, 0.5, 0.5, 0.9, 1.0, 1.0, 1.0, 1.0];
        let pts = [
            (0.0, 0.0),
            (1.0, 2.0),
            (3.0, 3.0),
            (4.0, 0.0),
            (6.0, -1.0),
            (7.0, 2.0),
            (9.0, 2.5),
            (10.0, 0.0),
        ];
        BSpline::new(knots, pts.iter().map(|&(x, y)| Point::new(x, y)).collect())
            .expect("valid spline")
    }

    #[test]
    fn basis_is_a_partition_of_unity() {
        let s = sample_spline();
        for i in 0..=100 {
            let u = i as f64 / 100.0;
            let k = s.find_span(u);
            let sum: f64 = s.basis(k, u).iter().sum();
            assert!((sum - 1.0).abs() < 1e-14, "u = {u}: sum {sum}");
            assert!(s.basis(k, u).iter().all(|&b| b >= -1e-15));
        }
    }

    #[test]
    fn clamped_ends_interpolate_the_end_control_points() {
        let s = sample_spline();
        assert!(s.eval(0.0).distance(Point::new(0.0, 0.0)) < 1e-14);
        assert!(s.eval(1.0).distance(Point::new(10.0, 0.0)) < 1e-14);
    }

    #[test]
    fn beziers_match_the_spline_everywhere() {
        let s = sample_spline();
        let beziers = s.to_beziers();
        // Spans [0,.2], [.2,.5], [.5,.9], [.9,1]: the double knot at 0.5 leaves no empty piece.
        assert_eq!(beziers.len(), 4);
        assert_eq!(s.segment_count(), 4);
        for pb in &beziers {
            for i in 0..=20 {
                let t = i as f64 / 20.0;
                let u = pb.global(t);
                let d = pb.bez.eval(t).distance(s.eval(u));
                assert!(d < 1e-12, "u = {u}: {d}");
            }
        }
        for w in beziers.windows(2) {
            assert_eq!(w[0].u1, w[1].u0);
            assert!(w[0].bez.p3.distance(w[1].bez.p0) < 1e-12);
        }
    }

    #[test]
    fn basis_evaluation_matches_de_boor() {
        let s = sample_spline();
        for i in 0..=50 {
            let u = i as f64 / 50.0;
            let k = s.find_span(u);
            let b = s.basis(k, u);
            let p = (0..4).fold(Point::ZERO, |acc, j| {
                acc + s.control_points()[k - 3 + j].to_vec2() * b[j]
            });
            assert!(p.distance(s.eval(u)) < 1e-12);
        }
    }

    #[test]
    fn bad_shapes_are_refused() {
        let p = vec![Point::ZERO; 4];
        assert!(BSpline::new(vec![0.0; 7], p.clone()).is_err());
        assert!(BSpline::new(vec![0.0; 8], p.clone()).is_err());
        let mut k = BSpline::uniform_knots(1);
        k[4] = f64::NAN;
        assert!(BSpline::new(k, p.clone()).is_err());
        let mut q = p;
        q[2] = Point::new(f64::INFINITY, 0.0);
        assert_eq!(
            BSpline::new(BSpline::uniform_knots(1), q),
            Err(BSplineError::ControlPoint(2))
        );
    }
}
