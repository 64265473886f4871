//! Weighted least squares for B-spline control points with a fixed knot vector, by Givens
//! rotations on the banded observation matrix.
//!
//! Each sample `qᵢ` at parameter `uᵢ` with weight `wᵢ` contributes the row
//! `√wᵢ · [N_{k−3}(uᵢ) … N_k(uᵢ)]` (four non-zeros) and right-hand side `√wᵢ · qᵢ`. The rows are
//! rotated one at a time into an upper-triangular `R` of band width 4 (Dierckx, *Curve and Surface
//! Fitting with Splines*, §4.1), so the cost is O(m) for m samples, the memory O(n) for n control
//! points, and, unlike the normal equations `NᵀN`, the condition number is not squared.

use crate::geom::{Point, Vec2};

use super::curve::{DEGREE, basis_functions};

/// Band width of `R`: a cubic basis row has four non-zeros, a fairness row (the jump of C‴ at an
/// interior knot, which involves the basis functions of the two spans it joins) five.
const BAND: usize = DEGREE + 2;

/// A diagonal entry of `R` smaller than this fraction of the largest data row's norm means a
/// control point is (numerically) not determined: a knot span without samples. 1e-10 leaves ample
/// room above the rounding level (~1e-16 · √m) while flagging genuinely empty spans, whose
/// diagonal is exactly 0 or only rounding. It is measured against the data rows, not the largest
/// diagonal: strong fairness rows make some diagonals huge without making the others less
/// determined.
pub const RANK_RELATIVE: f64 = 1e-10;

/// Weight of the fairing rows added when the data leave control points undetermined, relative to
/// the mean sample weight. Small enough not to move a determined control point visibly (its
/// effect on a fit is of order 1e-8 of the local control-polygon bend), large enough to make every
/// diagonal of `R` non-zero.
pub const FAIRING_WEIGHT: f64 = 1e-8;

/// Why a least-squares solve failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LsqError {
    /// Some control point is not determined even with fairing (fewer than 4 control points'
    /// worth of distinct data).
    #[error("the samples do not determine control point {0}")]
    Underdetermined(usize),
}

/// An accumulating banded least-squares system for the control points of a cubic B-spline.
pub struct BandedLsq<'a> {
    knots: &'a [f64],
    /// `r[j][c]` is R(j, j + c).
    r: Vec<[f64; BAND]>,
    /// Rotated right-hand side, x and y together.
    z: Vec<Vec2>,
    /// Weighted squared residual left after the rotations (the least-squares objective).
    residual: f64,
    /// Largest norm of a data row (√w times the basis values), the scale of "determined".
    data_scale: f64,
    /// Control points held at given values (eliminated from the unknowns): the clamped ends,
    /// where the curve must pass exactly through a point (a corner shared with the neighbour).
    fixed: Vec<Option<Vec2>>,
}

impl<'a> BandedLsq<'a> {
    /// An empty system for the clamped cubic B-spline with these knots.
    pub fn new(knots: &'a [f64]) -> Self {
        let n = knots.len().saturating_sub(DEGREE + 1);
        BandedLsq {
            knots,
            r: vec![[0.0; BAND]; n],
            z: vec![Vec2::ZERO; n],
            residual: 0.0,
            data_scale: 0.0,
            fixed: vec![None; n],
        }
    }

    /// Holds control point `j` at `p`: every row added afterwards has its column `j` moved to
    /// the right-hand side. For a clamped spline, fixing control point 0 (or the last) makes
    /// the curve start (or end) exactly at `p`. Call before adding rows.
    pub fn fix(&mut self, j: usize, p: Point) {
        if let Some(f) = self.fixed.get_mut(j) {
            *f = Some(p.to_vec2());
        }
    }

    /// Number of control points (unknowns).
    pub fn unknowns(&self) -> usize {
        self.r.len()
    }

    /// Adds the observation "the curve at `u` is `q`" with weight `w` (> 0). `span` is the knot
    /// span holding `u` (see [`super::BSpline::find_span`]).
    pub fn add_sample(&mut self, span: usize, u: f64, q: Point, w: f64) {
        self.add_row(&Row::sample(self.knots, span, u, q, w), 0.0);
    }

    /// Adds a prepared row (see [`Row`]); a knot's jump row gets the weight `jump_weight`.
    pub(crate) fn add_row(&mut self, row: &Row, jump_weight: f64) {
        match *row {
            Row::Sample { first, row, rhs } => {
                let norm = row.iter().map(|x| x * x).sum::<f64>().sqrt();
                self.data_scale = self.data_scale.max(norm);
                self.rotate_in(first, row, rhs);
            }
            Row::Jump {
                first,
                left,
                right,
                width,
            } => {
                let scale = (jump_weight * 0.5 * width).sqrt();
                // Columns k−4..=k: the left span's basis covers k−4..=k−1, the right span's
                // k−3..=k.
                let mut row = [0.0; BAND];
                for j in 0..4 {
                    row[j] -= scale * left[j];
                    row[j + 1] += scale * right[j];
                }
                self.rotate_in(first, row, Vec2::ZERO);
            }
        }
    }

    /// Adds a row with non-zeros `row` in columns `first..first + BAND` and right-hand side `rhs`.
    ///
    /// The row is rotated against `R`'s rows `first, first + 1, …` in turn. Row `j` of `R`
    /// spans columns `j..j + BAND`, so each rotation can fill the incoming row one column further
    /// right: the window slides until it is all zero (for rows arriving in column order, as the
    /// samples and fairness rows do, that is after at most `BAND` steps; a row arriving out of
    /// order may slide to the last column).
    fn rotate_in(&mut self, first: usize, row: [f64; BAND], mut rhs: Vec2) {
        let n = self.r.len();
        let mut w = row;
        // Known columns go to the right-hand side.
        for (c, x) in w.iter_mut().enumerate() {
            if let Some(Some(p)) = self.fixed.get(first + c) {
                rhs -= *p * *x;
                *x = 0.0;
            }
        }
        let mut j = first;
        while j < n && w.iter().any(|&x| x != 0.0) {
            let piv = w[0];
            if piv != 0.0 {
                // Givens rotation zeroing `piv` against the diagonal R(j, j).
                let d = self.r[j][0];
                let h = d.hypot(piv);
                let (cos, sin) = (d / h, piv / h);
                self.r[j][0] = h;
                let zj = self.z[j];
                self.z[j] = zj * cos + rhs * sin;
                rhs = rhs * cos - zj * sin;
                for i in 1..BAND {
                    let a = self.r[j][i];
                    let b = w[i];
                    self.r[j][i] = cos * a + sin * b;
                    w[i] = cos * b - sin * a;
                }
            }
            w.rotate_left(1);
            w[BAND - 1] = 0.0;
            j += 1;
        }
        self.residual += rhs.hypot2();
    }

    /// Adds fairing rows `√w · (P_{j−1} − 2P_j + P_{j+1}) = 0` for every interior control point:
    /// the smallest bending of the control polygon decides what the data leave open.
    fn add_fairing(&mut self, w: f64) {
        let sw = w.sqrt();
        for j in 1..self.r.len().saturating_sub(1) {
            self.rotate_in(j - 1, [sw, -2.0 * sw, sw, 0.0, 0.0], Vec2::ZERO);
        }
    }

    /// Adds the fairness row of interior knot `k` (between spans `k − 1` and `k`):
    /// `√(weight·h) · (C‴(k⁺) − C‴(k⁻)) = 0` with `h` the mean length of the two spans.
    ///
    /// The jump of the third derivative is Dierckx's smoothing measure (*Curve and Surface
    /// Fitting with Splines*, §5.2): Σ h·‖jump‖² vanishes exactly for a single cubic, so the
    /// penalty removes wobbles between knots without pulling the curvature's slope towards zero
    /// (which ∫‖C‴‖² does, flattening the curvature at a stroke's high-curvature end).
    /// The row touches control points `k − 4..=k`; add it before the first sample of span `k`
    /// to keep the rows in column order.
    pub fn add_knot_jump_penalty(&mut self, k: usize, weight: f64) {
        if let Some(row) = Row::jump(self.knots, k) {
            self.add_row(&row, weight);
        }
    }

    /// Adds every interior knot's fairness row (see [`BandedLsq::add_knot_jump_penalty`]).
    pub fn add_jump_penalty(&mut self, weight: f64) {
        for k in DEGREE + 1..self.r.len() {
            self.add_knot_jump_penalty(k, weight);
        }
    }

    /// Whether every control point is determined (no tiny diagonal in `R`).
    fn determined(&self) -> Result<(), usize> {
        let scale = if self.data_scale > 0.0 {
            self.data_scale
        } else {
            self.r.iter().map(|r| r[0].abs()).fold(0.0, f64::max)
        };
        match self
            .r
            .iter()
            .zip(&self.fixed)
            .position(|(r, f)| f.is_none() && !(r[0].abs() > RANK_RELATIVE * scale))
        {
            Some(j) => Err(j),
            None => Ok(()),
        }
    }

    /// Back-substitution. If the data leave control points undetermined, fairing rows of weight
    /// [`FAIRING_WEIGHT`] × `mean_weight` are added first.
    pub fn solve(mut self, mean_weight: f64) -> Result<Solution, LsqError> {
        let mut faired = false;
        if self.determined().is_err() {
            self.add_fairing(FAIRING_WEIGHT * mean_weight);
            faired = true;
        }
        self.determined().map_err(LsqError::Underdetermined)?;
        let n = self.r.len();
        let mut x = vec![Vec2::ZERO; n];
        for j in (0..n).rev() {
            if let Some(p) = self.fixed[j] {
                x[j] = p;
                continue;
            }
            let mut acc = self.z[j];
            for c in 1..BAND {
                if j + c < n {
                    acc -= x[j + c] * self.r[j][c];
                }
            }
            x[j] = acc / self.r[j][0];
        }
        Ok(Solution {
            control_points: x.into_iter().map(|v| v.to_point()).collect(),
            residual: self.residual,
            faired,
        })
    }
}

/// One row of a [`BandedLsq`] system, prepared once for several solves with the same knots and
/// sample parameters (the fairing search solves one design at several weights): the basis values
/// and third derivatives are its cost, the rotation the system's.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Row {
    /// A sample's row √w·[N_{k−3}(u) … N_k(u)] from column `first`, right-hand side √w·q.
    Sample {
        first: usize,
        row: [f64; BAND],
        rhs: Vec2,
    },
    /// Interior knot k's C‴ jump (see [`BandedLsq::add_knot_jump_penalty`]) from column
    /// `first` = k − 4, before its weight: the third derivatives of the basis on the spans to its
    /// left and right, and the length of the two together (twice their mean).
    Jump {
        first: usize,
        left: [f64; 4],
        right: [f64; 4],
        width: f64,
    },
}

impl Row {
    /// The observation "the curve at `u` (in knot span `span`) is `q`", weight `w`.
    pub(crate) fn sample(knots: &[f64], span: usize, u: f64, q: Point, w: f64) -> Row {
        let sw = w.sqrt();
        let b = basis_functions(knots, span, u);
        Row::Sample {
            first: span - DEGREE,
            row: [b[0] * sw, b[1] * sw, b[2] * sw, b[3] * sw, 0.0],
            rhs: q.to_vec2() * sw,
        }
    }

    /// Interior knot `k`'s jump row; `None` for a knot that is not interior or joins an empty
    /// span (a multiple knot).
    pub(crate) fn jump(knots: &[f64], k: usize) -> Option<Row> {
        let controls = knots.len().saturating_sub(DEGREE + 1);
        if k < DEGREE + 1 || k >= controls {
            return None;
        }
        let (a, m, b) = (knots[k - 1], knots[k], knots[k + 1]);
        if !(a < m && m < b) {
            return None;
        }
        Some(Row::Jump {
            first: k - DEGREE - 1,
            left: third_derivatives(knots, k - 1),
            right: third_derivatives(knots, k),
            width: b - a,
        })
    }
}

/// The constant third derivatives `N‴_{k−3..=k}` of the four basis functions on the non-empty
/// knot span `k`: the third finite difference of the basis at four equally spaced points of the
/// span, divided by `h³` (exact for a cubic up to rounding).
fn third_derivatives(knots: &[f64], k: usize) -> [f64; 4] {
    let (a, b) = (knots[k], knots[k + 1]);
    let h = (b - a) / 3.0;
    let v: [[f64; 4]; 4] = std::array::from_fn(|i| basis_functions(knots, k, a + h * i as f64));
    std::array::from_fn(|j| (v[3][j] - 3.0 * v[2][j] + 3.0 * v[1][j] - v[0][j]) / (h * h * h))
}

/// The result of [`BandedLsq::solve`].
#[derive(Clone, Debug)]
pub struct Solution {
    /// The control points.
    pub control_points: Vec<Point>,
    /// The weighted sum of squared residuals.
    pub residual: f64,
    /// Whether fairing rows had to be added (some knot span had too little data).
    pub faired: bool,
}

#[cfg(test)]
mod tests {
    use nalgebra::{DMatrix, DVector};

    use super::*;
    use crate::bspline::BSpline;

    /// Knots with uneven spacing and a double knot.
    fn knots() -> Vec<f64> {
        vec![
            0.0, 0.0, 0.0, 0.0, 0.15, 0.4, 0.4, 0.7, 0.85, 1.0, 1.0, 1.0, 1.0,
        ]
    }

    #[test]
    fn recovers_a_planted_spline_from_exact_samples() {
        let k = knots();
        let planted: Vec<Point> = (0..9)
            .map(|i| {
                let a = i as f64 * 0.7;
                Point::new(10.0 * a.cos() + i as f64, 10.0 * a.sin() - 0.5 * i as f64)
            })
            .collect();
        let s = BSpline::new(k.clone(), planted.clone()).expect("valid");
        let mut lsq = BandedLsq::new(&k);
        for i in 0..=200 {
            let u = (i as f64 / 200.0).powf(1.3);
            lsq.add_sample(s.find_span(u), u, s.eval(u), 1.0 + (i % 3) as f64);
        }
        let sol = lsq.solve(1.0).expect("determined");
        assert!(!sol.faired);
        for (a, b) in sol.control_points.iter().zip(&planted) {
            assert!(a.distance(*b) < 1e-9, "{a:?} vs {b:?}");
        }
        assert!(sol.residual < 1e-18);
    }

    #[test]
    fn agrees_with_a_dense_weighted_solve() {
        let k = knots();
        let n = k.len() - 4;
        let s = BSpline::new(k.clone(), vec![Point::ZERO; n]).expect("valid");
        let m = 120;
        let mut a = DMatrix::<f64>::zeros(m, n);
        let mut bx = DVector::<f64>::zeros(m);
        let mut by = DVector::<f64>::zeros(m);
        let mut lsq = BandedLsq::new(&k);
        for i in 0..m {
            let u = i as f64 / (m - 1) as f64;
            let q = Point::new(
                (7.0 * u).sin() * 3.0 + u,
                (5.0 * u).cos() + 0.3 * (31.0 * u).sin(),
            );
            let w = 0.5 + u;
            let span = s.find_span(u);
            lsq.add_sample(span, u, q, w);
            let b = s.basis(span, u);
            for c in 0..4 {
                a[(i, span - 3 + c)] = b[c] * w.sqrt();
            }
            bx[i] = q.x * w.sqrt();
            by[i] = q.y * w.sqrt();
        }
        let sol = lsq.solve(1.0).expect("determined");
        let svd = a.clone().svd(true, true);
        let x = svd.solve(&bx, 1e-14).expect("svd solve");
        let y = svd.solve(&by, 1e-14).expect("svd solve");
        for j in 0..n {
            assert!((sol.control_points[j].x - x[j]).abs() < 1e-10);
            assert!((sol.control_points[j].y - y[j]).abs() < 1e-10);
        }
        let rx = &a * &x - &bx;
        let ry = &a * &y - &by;
        assert!((sol.residual - (rx.norm_squared() + ry.norm_squared())).abs() < 1e-10);
    }

    #[test]
    fn an_empty_span_is_faired_not_singular() {
        let k = BSpline::uniform_knots(8);
        let s = BSpline::new(k.clone(), vec![Point::ZERO; 11]).expect("valid");
        let mut lsq = BandedLsq::new(&k);
        // No samples in (0.2, 0.8): the middle control point is touched by no sample's basis.
        for i in 0..=40 {
            let u = i as f64 / 40.0;
            if u > 0.2 && u < 0.8 {
                continue;
            }
            lsq.add_sample(s.find_span(u), u, Point::new(u, 2.0 * u), 1.0);
        }
        let sol = lsq.solve(1.0).expect("faired");
        assert!(sol.faired);
        // Collinear data: fairing keeps the undetermined point on the line.
        for p in &sol.control_points {
            assert!((p.y - 2.0 * p.x).abs() < 1e-6, "{p:?}");
        }
    }

    /// Dense rows of the same system, for the SVD oracle: data rows then knot-jump rows, with
    /// N‴ obtained independently (a dense fit of each basis function's cubic on its span).
    fn dense_with_jumps(
        k: &[f64],
        samples: &[(f64, Point)],
        weight: f64,
    ) -> (DMatrix<f64>, DVector<f64>, DVector<f64>) {
        let n = k.len() - 4;
        let s = BSpline::new(k.to_vec(), vec![Point::ZERO; n]).expect("valid");
        let mut rows: Vec<(Vec<f64>, Point)> = Vec::new();
        for &(u, q) in samples {
            let span = s.find_span(u);
            let b = s.basis(span, u);
            let mut r = vec![0.0; n];
            r[span - 3..=span].copy_from_slice(&b);
            rows.push((r, q));
        }
        let third = |kk: usize| -> Vec<f64> {
            let (a, bb) = (k[kk], k[kk + 1]);
            let us: Vec<f64> = (0..4)
                .map(|i| a + (bb - a) * (0.1 + 0.25 * i as f64))
                .collect();
            let vander = DMatrix::from_fn(4, 4, |i, p| us[i].powi(p as i32));
            let mut d = vec![0.0; n];
            for j in 0..4 {
                let vals = DVector::from_fn(4, |i, _| s.basis(kk, us[i])[j]);
                let coef = vander.clone().lu().solve(&vals).expect("Vandermonde");
                d[kk - 3 + j] = 6.0 * coef[3];
            }
            d
        };
        for kk in 4..n {
            let (l, r) = (third(kk - 1), third(kk));
            let scale = (weight * 0.5 * (k[kk + 1] - k[kk - 1])).sqrt();
            rows.push(((0..n).map(|j| scale * (r[j] - l[j])).collect(), Point::ZERO));
        }
        let a = DMatrix::from_fn(rows.len(), n, |i, j| rows[i].0[j]);
        let bx = DVector::from_fn(rows.len(), |i, _| rows[i].1.x);
        let by = DVector::from_fn(rows.len(), |i, _| rows[i].1.y);
        (a, bx, by)
    }

    #[test]
    fn jump_penalty_agrees_with_a_dense_solve_and_is_translation_invariant() {
        let k = vec![
            0.0, 0.0, 0.0, 0.0, 0.15, 0.4, 0.55, 0.7, 0.85, 1.0, 1.0, 1.0, 1.0,
        ];
        let n = k.len() - 4;
        let s = BSpline::new(k.clone(), vec![Point::ZERO; n]).expect("valid");
        let weight = 1e-4;
        let mut previous: Option<Vec<Point>> = None;
        for shift in [0.0, 0.7, -1234.5] {
            let samples: Vec<(f64, Point)> = (0..60)
                .map(|i| {
                    let u = i as f64 / 59.0;
                    (
                        u,
                        Point::new((3.0 * u).sin() + shift, (2.0 * u).cos() - 0.5 * shift),
                    )
                })
                .collect();
            let mut lsq = BandedLsq::new(&k);
            for &(u, q) in &samples {
                lsq.add_sample(s.find_span(u), u, q, 1.0);
            }
            // Added after all the data: the out-of-order case.
            lsq.add_jump_penalty(weight);
            let sol = lsq.solve(1.0).expect("determined");
            let (a, bx, by) = dense_with_jumps(&k, &samples, weight);
            let svd = a.svd(true, true);
            let x = svd.solve(&bx, 1e-14).expect("svd");
            let y = svd.solve(&by, 1e-14).expect("svd");
            for j in 0..n {
                let p = sol.control_points[j];
                assert!(
                    (p.x - x[j]).abs() < 1e-8 && (p.y - y[j]).abs() < 1e-8,
                    "shift {shift}, P{j}"
                );
            }
            let unshifted: Vec<Point> = sol
                .control_points
                .iter()
                .map(|p| Point::new(p.x - shift, p.y + 0.5 * shift))
                .collect();
            if let Some(prev) = &previous {
                for (a, b) in prev.iter().zip(&unshifted) {
                    assert!(a.distance(*b) < 1e-9, "shift {shift}: {a:?} vs {b:?}");
                }
            }
            previous = Some(unshifted);
        }
    }

    #[test]
    fn a_strong_jump_penalty_leaves_a_single_cubic() {
        // Σ‖jump‖² vanishes exactly for one cubic: data on a cubic are fitted exactly whatever
        // the weight.
        let k = vec![0.0, 0.0, 0.0, 0.0, 0.2, 0.5, 0.8, 1.0, 1.0, 1.0, 1.0];
        let n = k.len() - 4;
        let s = BSpline::new(k.clone(), vec![Point::ZERO; n]).expect("valid");
        let cubic = |u: f64| Point::new(u + 2.0 * u * u * u, 3.0 * u * u - u * u * u);
        let mut lsq = BandedLsq::new(&k);
        for i in 0..50 {
            let u = i as f64 / 49.0;
            lsq.add_sample(s.find_span(u), u, cubic(u), 1.0);
        }
        lsq.add_jump_penalty(1e6);
        let control_points = lsq.solve(1.0).expect("determined").control_points;
        let fit = BSpline::new(k.clone(), control_points).expect("valid");
        for i in 0..=20 {
            let u = i as f64 / 20.0;
            assert!(fit.eval(u).distance(cubic(u)) < 1e-9);
        }
    }

    #[test]
    fn row_order_does_not_matter() {
        let k = knots();
        let n = k.len() - 4;
        let s = BSpline::new(k.clone(), vec![Point::ZERO; n]).expect("valid");
        let samples: Vec<(f64, Point)> = (0..80)
            .map(|i| {
                let u = i as f64 / 79.0;
                (
                    u,
                    Point::new((5.0 * u).sin(), u * u + 0.1 * (17.0 * u).cos()),
                )
            })
            .collect();
        let solve = |order: &[usize]| {
            let mut lsq = BandedLsq::new(&k);
            for &i in order {
                let (u, q) = samples[i];
                lsq.add_sample(s.find_span(u), u, q, 1.0);
            }
            lsq.solve(1.0).expect("determined").control_points
        };
        let sorted: Vec<usize> = (0..samples.len()).collect();
        let reversed: Vec<usize> = sorted.iter().rev().copied().collect();
        let shuffled: Vec<usize> = (0..samples.len())
            .map(|i| (i * 37) % samples.len())
            .collect();
        let a = solve(&sorted);
        for other in [solve(&reversed), solve(&shuffled)] {
            for (p, q) in a.iter().zip(&other) {
                assert!(p.distance(*q) < 1e-10, "{p:?} vs {q:?}");
            }
        }
    }

    #[test]
    fn fixed_ends_are_interpolated_and_the_rest_is_least_squares() {
        let k = vec![
            0.0, 0.0, 0.0, 0.0, 0.15, 0.4, 0.55, 0.7, 0.85, 1.0, 1.0, 1.0, 1.0,
        ];
        let n = k.len() - 4;
        let s = BSpline::new(k.clone(), vec![Point::ZERO; n]).expect("valid");
        let samples: Vec<(f64, Point)> = (0..80)
            .map(|i| {
                let u = i as f64 / 79.0;
                (
                    u,
                    Point::new(10.0 * u, (6.0 * u).sin() + 0.05 * (40.0 * u).cos()),
                )
            })
            .collect();
        let (a, b) = (Point::new(-0.3, 0.2), Point::new(10.2, -0.1));
        let mut lsq = BandedLsq::new(&k);
        lsq.fix(0, a);
        lsq.fix(n - 1, b);
        for &(u, q) in &samples {
            lsq.add_sample(s.find_span(u), u, q, 1.0);
        }
        lsq.add_jump_penalty(1e-6);
        let sol = lsq.solve(1.0).expect("determined");
        assert_eq!(sol.control_points[0], a);
        assert_eq!(sol.control_points[n - 1], b);
        // The free points are the dense least-squares solution with the fixed columns moved
        // to the right-hand side.
        let (m, bx, by) = dense_with_jumps(&k, &samples, 1e-6);
        let free = m.columns(1, n - 2).into_owned();
        let rx = &bx - m.column(0) * a.x - m.column(n - 1) * b.x;
        let ry = &by - m.column(0) * a.y - m.column(n - 1) * b.y;
        let svd = free.svd(true, true);
        let x = svd.solve(&rx, 1e-14).expect("svd");
        let y = svd.solve(&ry, 1e-14).expect("svd");
        for j in 1..n - 1 {
            let p = sol.control_points[j];
            assert!(
                (p.x - x[j - 1]).abs() < 1e-8 && (p.y - y[j - 1]).abs() < 1e-8,
                "P{j}"
            );
        }
    }
}
