//! The damped Gauss–Newton system of the smooth fit: JᵀJ held over where it can be nonzero
//! (a joint's unknowns reach the two segments meeting there), ordered along the chain so that
//! the KKT system is banded.

use super::jacobian::ResidualJacobian;
use super::layout::{Layout, Var};
use super::project::constraint_key;
use super::solver::{Evaluation, Solver};
use nalgebra::DVector;

/// Where JᵀJ of a solve's unknowns can be nonzero, fixed through the solve: column j holds the
/// rows `rows[j]`, the unknowns that share a segment with unknown j (ascending, and symmetric:
/// i is among j's rows where j is among i's), its entries stored column after column.
pub(super) struct NormalPattern {
    /// Per column j, the rows of its entries (ascending).
    pub(super) rows: Vec<Vec<usize>>,
    /// Where column j's entries start in the stored values; the last is their count.
    pub(super) offsets: Vec<usize>,
    /// Where each column's diagonal entry is stored.
    pub(super) diagonal: Vec<usize>,
    /// Per segment k with columns c (`reaching[k]`): entry (c[a], c[b]) stored at
    /// `slots[k][a·|c| + b]`.
    pub(super) slots: Vec<Vec<usize>>,
}

impl NormalPattern {
    /// The pattern of the unknowns reaching each segment (`reaching[k]`, ascending), each
    /// column holding its own diagonal; `None` where an index is out of range.
    pub(super) fn new(m: usize, reaching: &[Vec<usize>]) -> Option<Self> {
        let mut rows: Vec<Vec<usize>> = (0..m).map(|j| vec![j]).collect();
        for columns in reaching {
            for &j in columns {
                rows.get_mut(j)?.extend(columns);
            }
        }
        for r in &mut rows {
            r.sort_unstable();
            r.dedup();
        }
        let mut offsets = Vec::with_capacity(m + 1);
        let mut count = 0;
        for r in &rows {
            offsets.push(count);
            count += r.len();
        }
        offsets.push(count);
        let mut pattern = NormalPattern {
            rows,
            offsets,
            diagonal: Vec::new(),
            slots: Vec::new(),
        };
        pattern.diagonal = (0..m).map(|j| pattern.at(j, j)).collect::<Option<_>>()?;
        pattern.slots = reaching
            .iter()
            .map(|columns| {
                columns
                    .iter()
                    .flat_map(|&i| columns.iter().map(move |&j| (i, j)))
                    .map(|(i, j)| pattern.at(i, j))
                    .collect::<Option<_>>()
            })
            .collect::<Option<_>>()?;
        Some(pattern)
    }

    /// Where entry (i, j) is stored; `None` outside the pattern.
    pub(super) fn at(&self, i: usize, j: usize) -> Option<usize> {
        Some(self.offsets[j] + self.rows[j].binary_search(&i).ok()?)
    }
}

/// JᵀJ over a [`NormalPattern`]. Held dense, a part of 31 segments (186 unknowns) was
/// allocated and zeroed at every iteration, 34 596 entries for about 2 000 that can be nonzero,
/// and each unknown held on its bound or outside a local solve's window (see
/// [`Solver::window`]) swept its whole row and column.
pub(super) struct Normal<'p> {
    pub(super) pattern: &'p NormalPattern,
    /// The entries, column after column (see [`NormalPattern::offsets`]).
    pub(super) values: Vec<f64>,
}

impl<'p> Normal<'p> {
    pub(super) fn zeros(pattern: &'p NormalPattern) -> Self {
        Normal {
            values: vec![0.0; pattern.offsets.last().copied().unwrap_or(0)],
            pattern,
        }
    }

    /// Diagonal entry (j, j).
    pub(super) fn diagonal(&self, j: usize) -> f64 {
        self.values[self.pattern.diagonal[j]]
    }

    /// The number of entries stored (the pattern's size).
    pub(super) fn stored(&self) -> usize {
        self.values.len()
    }

    /// The largest diagonal entry (zero without unknowns).
    pub(super) fn max_diagonal(&self) -> f64 {
        (0..self.pattern.rows.len())
            .map(|j| self.diagonal(j))
            .reduce(|a, b| if b > a { b } else { a })
            .unwrap_or(0.0)
    }

    /// Adds wᵢ·rowᵀrow for one residual row of segment `k`, `row` over the segment's columns
    /// (those its slots were made for); a column whose weighted entry is zero adds nothing.
    pub(super) fn add_row(&mut self, k: usize, row: &[f64], w: f64) {
        let slots = &self.pattern.slots[k];
        let c = row.len();
        for (b, &jrj) in row.iter().enumerate() {
            let v = w * jrj;
            if v == 0.0 {
                continue;
            }
            for (i, &jri) in row.iter().enumerate() {
                self.values[slots[i * c + b]] += jri * v;
            }
        }
    }

    /// Row and column i set to zero, and the diagonal entry to `value`.
    pub(super) fn hold(&mut self, i: usize, value: f64) {
        let pattern = self.pattern;
        for &j in &pattern.rows[i] {
            if let Some(at) = pattern.at(i, j) {
                self.values[at] = 0.0;
            }
        }
        self.values[pattern.offsets[i]..pattern.offsets[i + 1]].fill(0.0);
        self.values[pattern.diagonal[i]] = value;
    }

    /// The nonzero entries of column j (and its diagonal, zero or not), as (row, value).
    pub(super) fn column(&self, j: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let p = self.pattern;
        p.rows[j]
            .iter()
            .zip(&self.values[p.offsets[j]..p.offsets[j + 1]])
            .filter(move |&(&i, &v)| v != 0.0 || i == j)
            .map(|(&i, &v)| (i, v))
    }

    /// The product with `x`, each row summed over its columns in ascending order as a dense
    /// product would (the entries outside the pattern are zero).
    pub(super) fn times(&self, x: &DVector<f64>) -> DVector<f64> {
        let p = self.pattern;
        let mut out = DVector::zeros(x.len());
        for (j, rows) in p.rows.iter().enumerate() {
            let values = &self.values[p.offsets[j]..p.offsets[j + 1]];
            for (&i, &v) in rows.iter().zip(values) {
                out[i] += v * x[j];
            }
        }
        out
    }
}

/// The normal equations JᵀJ (over `pattern`, that of the reaching sets `jr` holds) and Jᵀr
/// for the residuals of `e` with Jacobian `jr`: segment k's rows are nonzero only in its own
/// columns, so each row adds its few products instead of a dense product over every column.
pub(super) fn normal_equations<'p>(
    solver: &Solver,
    jr: &ResidualJacobian,
    pattern: &'p NormalPattern,
    e: &Evaluation,
    assign: &[Vec<usize>],
) -> (Normal<'p>, DVector<f64>) {
    let mut a = Normal::zeros(pattern);
    let mut g = DVector::zeros(pattern.rows.len());
    for (k, (residuals, list)) in e.residuals.iter().zip(assign).enumerate() {
        let (columns, rows) = jr.segment(k);
        for ((&r, &sample), row) in residuals.iter().zip(list).zip(rows) {
            let w = solver.weight(sample);
            for (&j, &jrj) in columns.iter().zip(row) {
                let v = w * jrj;
                if v != 0.0 {
                    g[j] += v * r;
                }
            }
            a.add_row(k, row, w);
        }
    }
    (a, g)
}

/// Where each row of the KKT system (the unknowns `vars`, then the `nc` constraints in the order
/// of [`Solver::constraints`] in the shooting form) goes so that the system is banded: along the
/// chain, a joint's curvature, its position and tangent equations (and C3's), the pose of the
/// segment it starts, that segment's length and α; the end point's equations last. A segment's
/// residuals and a joint's equations then involve rows of two neighbouring segments only, a
/// bandwidth of about fifteen whatever the chain's length.
pub(super) fn band_order(
    layout: &Layout,
    vars: &[Var],
    nc: usize,
    c3_joints: &[usize],
) -> Vec<usize> {
    let n = layout.n();
    let m = vars.len();
    let joint_rows = 3 * n.saturating_sub(1);
    let mut keys: Vec<(f64, usize)> = vars
        .iter()
        .enumerate()
        .map(|(i, &var)| {
            let key = match var {
                Var::Theta0 => -1.0,
                Var::StartShift => 0.0,
                Var::EndShift => n as f64,
                Var::Joint(j) => j as f64 - 0.2,
                Var::X(k) | Var::Y(k) | Var::Angle(k) => k as f64,
                Var::Length(k) | Var::Alpha(k) => k as f64 + 0.5,
            };
            (key, i)
        })
        .collect();
    keys.extend((0..nc).map(|r| (constraint_key(r, n, joint_rows, c3_joints), m + r)));
    positions(keys)
}

/// Each index's place when `keys` (a key per index, `(key, index)`) are sorted by key, ties in
/// index order.
pub(super) fn positions(mut keys: Vec<(f64, usize)>) -> Vec<usize> {
    keys.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)));
    let mut position = vec![0; keys.len()];
    for (p, &(_, i)) in keys.iter().enumerate() {
        position[i] = p;
    }
    position
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    /// The unknowns reaching each of four segments as a chain's do (a joint's unknowns reach
    /// the two segments meeting there), in ascending order.
    fn reaching() -> Vec<Vec<usize>> {
        vec![
            vec![0, 1, 2, 3],
            vec![2, 3, 4, 5, 6],
            vec![5, 6, 7],
            vec![7, 8, 9],
        ]
    }

    /// A deterministic entry for (segment, row, column).
    fn entry(k: usize, row: usize, j: usize) -> f64 {
        ((k * 31 + row * 7 + j * 13) % 17) as f64 / 8.0 - 1.0
    }

    /// JᵀJ accumulated over the pattern equals the dense product of the same rows, and a hold
    /// clears exactly its row and column.
    #[test]
    fn the_normal_matrix_over_its_pattern_is_the_dense_product() {
        let (m, reaching) = (10, reaching());
        let pattern = NormalPattern::new(m, &reaching).expect("a valid pattern");
        let mut normal = Normal::zeros(&pattern);
        let mut dense = DMatrix::<f64>::zeros(m, m);
        for (k, columns) in reaching.iter().enumerate() {
            for row in 0..3 {
                let values: Vec<f64> = columns.iter().map(|&j| entry(k, row, j)).collect();
                let w = 0.5 + row as f64;
                normal.add_row(k, &values, w);
                for (b, &j) in columns.iter().enumerate() {
                    for (a, &i) in columns.iter().enumerate() {
                        dense[(i, j)] += values[a] * (w * values[b]);
                    }
                }
            }
        }
        let x = DVector::from_iterator(m, (0..m).map(|i| (i as f64 * 0.37).sin()));
        let times = normal.times(&x);
        let expected = &dense * &x;
        for i in 0..m {
            assert!((times[i] - expected[i]).abs() <= 1e-12, "row {i}");
            assert_eq!(normal.diagonal(i), dense[(i, i)]);
            let column: Vec<(usize, f64)> = normal.column(i).collect();
            for r in 0..m {
                let stored = column.iter().find(|&&(row, _)| row == r).map(|&(_, v)| v);
                match stored {
                    Some(v) => assert_eq!(v, dense[(r, i)]),
                    None => assert_eq!(dense[(r, i)], 0.0, "({r}, {i}) left out"),
                }
            }
        }
        normal.hold(5, 2.5);
        for j in 0..m {
            let expect_row = if j == 5 { 2.5 } else { 0.0 };
            let row_entry = normal
                .column(j)
                .find(|&(r, _)| r == 5)
                .map_or(0.0, |(_, v)| v);
            assert_eq!(row_entry, expect_row, "(5, {j})");
            let col_entry = normal
                .column(5)
                .find(|&(r, _)| r == j)
                .map_or(0.0, |(_, v)| v);
            assert_eq!(col_entry, expect_row, "({j}, 5)");
        }
    }
}
