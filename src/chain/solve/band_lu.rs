//! A general square band matrix and its solve by Gaussian elimination with partial pivoting
//! confined to the band: O(n·l·(l + u)) for n unknowns, l sub- and u super-diagonals, where a
//! dense LU costs O(n³). For the smooth fit's KKT systems (symmetric but indefinite, so
//! [`super::band::Band`]'s Cholesky does not apply), whose unknowns and constraints ordered
//! along the chain couple only neighbouring segments.
//!
//! Row swaps move entries of a pivot row at most l places further right, so each row keeps
//! room for l + u super-diagonals (LAPACK's `gbtrf` layout, stored by rows).

/// A square band matrix: entry (i, j) for −l ≤ j − i ≤ u (zero outside), with room for the
/// elimination's fill up to j − i ≤ l + u.
#[derive(Clone, Debug)]
pub(crate) struct BandMatrix {
    n: usize,
    lower: usize,
    upper: usize,
    /// Row i holds columns i − l ..= i + l + u at `rows[i * width + (j + l − i)]`.
    rows: Vec<f64>,
}

impl BandMatrix {
    /// The zero n × n matrix with `lower` sub- and `upper` super-diagonals.
    pub fn zeros(n: usize, lower: usize, upper: usize) -> Self {
        BandMatrix {
            n,
            lower,
            upper,
            rows: vec![0.0; n * (2 * lower + upper + 1)],
        }
    }

    fn width(&self) -> usize {
        2 * self.lower + self.upper + 1
    }

    /// Where entry (i, j) sits, `None` outside the storage.
    fn at(&self, i: usize, j: usize) -> Option<usize> {
        let offset = (j + self.lower).checked_sub(i)?;
        (i < self.n && j < self.n && offset < self.width()).then(|| i * self.width() + offset)
    }

    /// Adds `value` to entry (i, j); `false` (nothing added) where (i, j) lies outside the band.
    pub fn add(&mut self, i: usize, j: usize, value: f64) -> bool {
        if j + self.lower < i || j > i + self.upper {
            return false;
        }
        match self.at(i, j) {
            Some(k) => {
                self.rows[k] += value;
                true
            }
            None => false,
        }
    }

    /// Solves A·x = b (`b` of length n); `None` where a pivot is zero or not finite (A singular
    /// to working precision, or NaN in it) or `b` has the wrong length.
    pub fn solve(mut self, b: &[f64]) -> Option<Vec<f64>> {
        let (n, l) = (self.n, self.lower);
        if b.len() != n {
            return None;
        }
        let w = self.width();
        let reach = l + self.upper;
        let mut x = b.to_vec();
        for j in 0..n {
            let last_row = (j + l).min(n.saturating_sub(1));
            let last_col = (j + reach).min(n - 1);
            let mut pivot_row = j;
            let mut best = self.rows[j * w + l].abs();
            for i in j + 1..=last_row {
                let v = self.rows[i * w + (j + l - i)].abs();
                if v > best {
                    best = v;
                    pivot_row = i;
                }
            }
            if !(best > 0.0 && best.is_finite()) {
                return None;
            }
            if pivot_row != j {
                // Row j's entries from column j on, and the pivot row's: the pivot row lies
                // below, so its storage follows row j's.
                let len = last_col + 1 - j;
                let (upper_rows, lower_rows) = self.rows.split_at_mut(pivot_row * w);
                let row_j = &mut upper_rows[j * w + l..j * w + l + len];
                let start = j + l - pivot_row;
                let row_p = &mut lower_rows[start..start + len];
                row_j.swap_with_slice(row_p);
                x.swap(j, pivot_row);
            }
            let pivot = self.rows[j * w + l];
            // Columns j + 1 ..= last_col of row j, subtracted from each row below it: row i's
            // storage lies wholly after row j's (i > j), so the two are disjoint slices and
            // the loop runs without index checks.
            let len = last_col - j;
            for i in j + 1..=last_row {
                let (upper_rows, lower_rows) = self.rows.split_at_mut(i * w);
                let below = &mut lower_rows[..w];
                let factor = below[j + l - i] / pivot;
                if factor == 0.0 {
                    continue;
                }
                let source = &upper_rows[j * w + l + 1..j * w + l + 1 + len];
                let start = j + 1 + l - i;
                for (d, &u) in below[start..start + len].iter_mut().zip(source) {
                    *d -= factor * u;
                }
                x[i] -= factor * x[j];
            }
        }
        for j in (0..n).rev() {
            let last_col = (j + reach).min(n - 1);
            let row = &self.rows[j * w + l..j * w + l + (last_col + 1 - j)];
            let mut sum = x[j];
            for (&a, &v) in row[1..].iter().zip(&x[j + 1..=last_col]) {
                sum -= a * v;
            }
            x[j] = sum / row[0];
        }
        x.iter().all(|v| v.is_finite()).then_some(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    /// An indefinite band matrix (a KKT-like saddle with zero diagonal entries that need
    /// pivoting) against nalgebra's dense LU.
    #[test]
    fn agrees_with_a_dense_lu_where_pivoting_is_needed() {
        let (n, lower, upper) = (31, 3, 5);
        let mut band = BandMatrix::zeros(n, lower, upper);
        let mut dense = DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            for j in i.saturating_sub(lower)..(i + upper + 1).min(n) {
                let v = if i == j {
                    if i % 3 == 0 {
                        0.0
                    } else {
                        2.0 + i as f64 * 0.1
                    }
                } else {
                    ((i * 7 + j * 3) % 11) as f64 * 0.4 - 2.0
                };
                assert!(band.add(i, j, v));
                dense[(i, j)] = v;
            }
        }
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).cos()).collect();
        let x = band.solve(&b).expect("nonsingular");
        let y = dense
            .lu()
            .solve(&DVector::from_vec(b))
            .expect("nonsingular");
        for i in 0..n {
            assert!(
                (x[i] - y[i]).abs() < 1e-10 * y.amax().max(1.0),
                "{i}: {} {}",
                x[i],
                y[i]
            );
        }
    }

    #[test]
    fn refuses_entries_outside_the_band_and_singular_matrices() {
        let mut band = BandMatrix::zeros(4, 1, 1);
        assert!(!band.add(3, 0, 1.0));
        assert!(!band.add(0, 2, 1.0));
        assert!(band.add(0, 0, 1.0));
        assert!(band.add(1, 0, 1.0));
        // Rows 2 and 3 are zero: singular.
        assert!(band.clone().solve(&[1.0, 1.0, 1.0, 1.0]).is_none());
        assert!(band.solve(&[1.0]).is_none());
    }
}
