//! A symmetric positive definite band matrix and its Cholesky solve: O(n·p²) for n unknowns and
//! half-bandwidth p, where a dense solve costs O(n³).

/// A symmetric band matrix: entry (i, j) for |i − j| ≤ p, stored as the lower band.
#[derive(Clone, Debug)]
pub(crate) struct Band {
    n: usize,
    p: usize,
    /// `lower[i * (p + 1) + (i - j)]` is entry (i, j), j ≤ i.
    lower: Vec<f64>,
}

impl Band {
    /// The zero n × n matrix with half-bandwidth `p`.
    pub fn zeros(n: usize, p: usize) -> Self {
        Band {
            n,
            p,
            lower: vec![0.0; n * (p + 1)],
        }
    }

    /// Order.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Entry (i, j) (0 outside the band).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        if i - j > self.p {
            0.0
        } else {
            self.lower[i * (self.p + 1) + (i - j)]
        }
    }

    /// Adds `value` to entries (i, j) and (j, i); ignored outside the band.
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        if i - j <= self.p {
            self.lower[i * (self.p + 1) + (i - j)] += value;
        }
    }

    /// The Cholesky factor L (A = L·Lᵀ, L lower band of the same width); `None` unless A is
    /// positive definite.
    pub fn factor(&self) -> Option<BandCholesky> {
        let (n, p) = (self.n, self.p);
        let w = p + 1;
        let mut l = self.lower.clone();
        for i in 0..n {
            let j0 = i.saturating_sub(p);
            for j in j0..=i {
                // Σ_k L(i,k)·L(j,k) over the columns both rows share, k in [max(j0, j − p), j).
                let k0 = j0.max(j.saturating_sub(p));
                let row_i = &l[i * w..i * w + w];
                let row_j = &l[j * w..j * w + w];
                let mut sum = row_i[i - j];
                for k in k0..j {
                    sum -= row_i[i - k] * row_j[j - k];
                }
                if i == j {
                    if !(sum > 0.0) {
                        return None;
                    }
                    l[i * w] = sum.sqrt();
                } else {
                    l[i * w + (i - j)] = sum / l[j * w];
                }
            }
        }
        Some(BandCholesky { n, p, l })
    }

    /// Solves A·x = b; `None` unless A is positive definite.
    #[cfg(test)]
    pub fn solve(&self, b: &[f64]) -> Option<Vec<f64>> {
        Some(self.factor()?.solve(b))
    }
}

/// The Cholesky factor of a [`Band`]: factored once, it solves for any number of right-hand
/// sides at O(n·p) each.
#[derive(Clone, Debug)]
pub(crate) struct BandCholesky {
    n: usize,
    p: usize,
    /// L in the layout of [`Band::lower`].
    l: Vec<f64>,
}

impl BandCholesky {
    /// Solves L·Lᵀ·x = b (`b` of length n).
    pub fn solve(&self, b: &[f64]) -> Vec<f64> {
        let (n, p, l) = (self.n, self.p, &self.l);
        let w = p + 1;
        let mut y = b.to_vec();
        for i in 0..n {
            let mut sum = y[i];
            for k in i.saturating_sub(p)..i {
                sum -= l[i * w + (i - k)] * y[k];
            }
            y[i] = sum / l[i * w];
        }
        for i in (0..n).rev() {
            let mut sum = y[i];
            for k in i + 1..(i + p + 1).min(n) {
                sum -= l[k * w + (k - i)] * y[k];
            }
            y[i] = sum / l[i * w];
        }
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    #[test]
    fn agrees_with_a_dense_cholesky() {
        let (n, p) = (23, 4);
        let mut band = Band::zeros(n, p);
        let mut dense = DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            for j in i.saturating_sub(p)..=i {
                let v = if i == j {
                    10.0 + i as f64
                } else {
                    ((i * 7 + j * 3) % 5) as f64 * 0.3 - 0.6
                };
                band.add(i, j, v);
                dense[(i, j)] = v;
                dense[(j, i)] = v;
            }
        }
        let b: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let x = band.solve(&b).expect("positive definite");
        let y = dense
            .cholesky()
            .expect("positive definite")
            .solve(&DVector::from_vec(b));
        for i in 0..n {
            assert!((x[i] - y[i]).abs() < 1e-12);
        }
        assert_eq!(band.get(3, 9), 0.0);
        assert_eq!(band.get(5, 3), band.get(3, 5));
    }

    #[test]
    fn refuses_an_indefinite_matrix() {
        let mut band = Band::zeros(2, 1);
        band.add(0, 0, 1.0);
        band.add(1, 1, 1.0);
        band.add(1, 0, 2.0);
        assert!(band.solve(&[1.0, 1.0]).is_none());
    }
}
