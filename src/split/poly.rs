//! Low-degree power-basis polynomials and exact real-root isolation on an interval.
//!
//! # Method: isolation by the derivative chain (Rolle's theorem)
//!
//! Between two consecutive real roots of `p′` the polynomial `p` is monotonic, so it has at most
//! one root there, and it has one exactly when its values at the two ends have opposite signs.
//! Starting from the linear derivative `p^{(n−1)}` (whose single root is explicit) and working back
//! up the chain `p^{(n−2)}, …, p′, p`, the roots of each level are the breakpoints that split the
//! interval into monotonic pieces for the level above. Every bracket found this way contains
//! exactly one root and `p` is monotonic on it, so the root is polished by the safeguarded ITP
//! solver ([`kurbo::common::solve_itp`]), which never leaves the bracket. No grid, no starting
//! guesses: no root can be missed because two of them fell into one grid cell.
//!
//! # Signs near zero
//!
//! A value is treated as zero when it is within the a-priori rounding bound of Horner's rule,
//! `|p(x)| ≤ SIGN_ULPS · ε · Σ |c_i| |x|^i`. A breakpoint (a root of `p′`) whose value is "zero"
//! is a multiple root of `p`: it is reported once, as [`Root::crossing`] when the signs of `p` on
//! its two sides differ (odd multiplicity) and as a touching root otherwise (even multiplicity,
//! e.g. a double root). Two simple roots closer than about `sqrt(ε)` relative to the polynomial's
//! scale are indistinguishable from a double root in `f64`; they are reported as one touching
//! root, which is the right answer for every caller here (a sign change that cannot be resolved
//! in `f64` carries no geometric information).

use kurbo::common::solve_itp;

/// Largest degree a [`Poly`] can hold. The split stage needs degree ≤ 5 (the curvature-extremum
/// polynomial of a cubic Bézier); 6 leaves room for the degree the paper states.
pub(crate) const MAX_DEGREE: usize = 6;

/// Number of coefficients of a polynomial of degree [`MAX_DEGREE`].
const CAPACITY: usize = MAX_DEGREE + 1;

/// Multiple of `f64::EPSILON · Σ|c_i||x|^i` below which a computed value's sign is not trusted.
/// Horner's rule alone is within `2n·(ε/2) = 6ε` for degree 6; the coefficients of the curvature
/// polynomials are themselves sums of products of rounded cross/dot products, which costs another
/// few ε each. 64 covers both with margin while still resolving simple roots about 1e-6 apart
/// (for coefficients of order one; see the clustered-roots tests).
const SIGN_ULPS: f64 = 64.0;

/// Absolute tolerance on a root's parameter, handed to ITP. Roots live in `[0, 1]`, where one ulp
/// is at most 1.1e-16; 1e-15 is ~10 ulps, below which the rounding of `p` itself decides the
/// answer anyway. (ITP needs `ε > 2⁻⁶³ · (b − a)`, true for any bracket inside `[0, 1]`.)
const ROOT_TOLERANCE: f64 = 1e-15;

/// ITP's `n0`: 1 lets the secant step engage on these smooth functions at the cost of at most one
/// iteration over bisection in the worst case (kurbo's recommendation).
const ITP_N0: usize = 1;

/// ITP's `k1 · (b − a)`: 0.2 is the value from the ITP paper that kurbo confirms works well.
const ITP_K1_TIMES_WIDTH: f64 = 0.2;

/// A real polynomial `Σ c_i tⁱ` of degree ≤ [`MAX_DEGREE`] in the power basis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Poly {
    /// `c[i]` multiplies `tⁱ`; entries above the degree are zero.
    c: [f64; CAPACITY],
}

impl Poly {
    /// The zero polynomial.
    pub(crate) const ZERO: Poly = Poly { c: [0.0; CAPACITY] };

    /// The polynomial with coefficients `coeffs` (constant term first). `N ≤ CAPACITY` is checked
    /// at compile time.
    pub(crate) fn new<const N: usize>(coeffs: [f64; N]) -> Poly {
        const { assert!(N <= CAPACITY, "polynomial degree exceeds MAX_DEGREE") };
        let mut c = [0.0; CAPACITY];
        c[..N].copy_from_slice(&coeffs);
        Poly { c }
    }

    /// The product of two coefficient arrays (constant term first). The product's degree
    /// `A + B − 2 ≤ MAX_DEGREE` is checked at compile time.
    pub(crate) fn product<const A: usize, const B: usize>(a: &[f64; A], b: &[f64; B]) -> Poly {
        const {
            assert!(
                A >= 1 && B >= 1 && A + B - 1 <= CAPACITY,
                "product degree exceeds MAX_DEGREE"
            )
        };
        let mut c = [0.0; CAPACITY];
        for (i, &ai) in a.iter().enumerate() {
            for (j, &bj) in b.iter().enumerate() {
                c[i + j] += ai * bj;
            }
        }
        Poly { c }
    }

    /// `self + k · other`.
    pub(crate) fn add_scaled(&self, k: f64, other: &Poly) -> Poly {
        let mut c = self.c;
        for (ci, oi) in c.iter_mut().zip(other.c.iter()) {
            *ci += k * oi;
        }
        Poly { c }
    }

    /// The coefficients, constant term first (`MAX_DEGREE + 1` of them, zero-padded).
    #[cfg(test)]
    pub(crate) fn coeffs(&self) -> &[f64; CAPACITY] {
        &self.c
    }

    /// Degree, i.e. index of the highest non-zero coefficient; `None` for the zero polynomial.
    pub(crate) fn degree(&self) -> Option<usize> {
        self.c.iter().rposition(|&ci| ci != 0.0)
    }

    /// The derivative `Σ i·c_i tⁱ⁻¹`.
    pub(crate) fn derivative(&self) -> Poly {
        let mut c = [0.0; CAPACITY];
        for i in 1..CAPACITY {
            c[i - 1] = i as f64 * self.c[i];
        }
        Poly { c }
    }

    /// Value at `t` by Horner's rule.
    pub(crate) fn eval(&self, t: f64) -> f64 {
        self.c.iter().rev().fold(0.0, |acc, &ci| acc * t + ci)
    }

    /// Value at `t` together with the bound below which its sign is not trusted
    /// (`SIGN_ULPS · ε · Σ|c_i||t|^i`).
    fn eval_with_bound(&self, t: f64) -> (f64, f64) {
        let at = t.abs();
        let (v, m) = self.c.iter().rev().fold((0.0f64, 0.0f64), |(v, m), &ci| {
            (v * t + ci, m * at + ci.abs())
        });
        (v, SIGN_ULPS * f64::EPSILON * m)
    }

    /// Sign of the value at `t`: `-1`, `+1`, or `0` when within the rounding bound.
    fn sign_at(&self, t: f64) -> i8 {
        let (v, bound) = self.eval_with_bound(t);
        if v.abs() <= bound {
            0
        } else if v > 0.0 {
            1
        } else {
            -1
        }
    }
}

/// One real root found by [`roots_in`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Root {
    /// The root's location.
    pub t: f64,
    /// Whether the polynomial changes sign there (odd multiplicity). `false` for a root where it
    /// only touches zero (even multiplicity).
    pub crossing: bool,
}

/// A fixed-capacity, ascending list of roots (a polynomial of degree ≤ [`MAX_DEGREE`] has at most
/// that many).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Roots {
    items: [Root; MAX_DEGREE],
    len: usize,
}

impl Roots {
    /// An empty list.
    pub(crate) const fn new() -> Roots {
        Roots {
            items: [Root {
                t: 0.0,
                crossing: false,
            }; MAX_DEGREE],
            len: 0,
        }
    }

    /// Appends `root`; returns `false` (and drops it) when full, which the isolation below never
    /// causes because it finds at most one root per monotonic interval.
    pub(crate) fn push(&mut self, root: Root) -> bool {
        match self.items.get_mut(self.len) {
            Some(slot) => {
                *slot = root;
                self.len += 1;
                true
            }
            None => false,
        }
    }

    /// The roots, ascending.
    pub(crate) fn as_slice(&self) -> &[Root] {
        &self.items[..self.len]
    }

    /// Iterator over the sign-changing roots' locations.
    pub(crate) fn crossings(&self) -> impl Iterator<Item = f64> + '_ {
        self.as_slice().iter().filter(|r| r.crossing).map(|r| r.t)
    }
}

impl Default for Roots {
    fn default() -> Self {
        Roots::new()
    }
}

/// All real roots of `p` in the open interval `(lo, hi)`, ascending, each flagged with whether
/// `p` changes sign there. Roots within rounding of `lo` or `hi` are not reported (the callers
/// treat the interval ends separately). The zero polynomial and non-zero constants have none.
///
/// Allocation-free: the derivative chain and every list live on the stack.
pub(crate) fn roots_in(p: &Poly, lo: f64, hi: f64) -> Roots {
    let Some(degree) = p.degree() else {
        return Roots::new();
    };
    if degree == 0 || lo.is_nan() || hi.is_nan() || lo >= hi {
        return Roots::new();
    }
    // chain[k] = p^{(k)}; chain[degree − 1] is linear with a non-zero slope.
    let mut chain = [Poly::ZERO; CAPACITY];
    chain[0] = *p;
    for k in 1..degree {
        chain[k] = chain[k - 1].derivative();
    }
    // The breakpoints of the linear level are none (its derivative is a non-zero constant); each
    // level's roots (crossing or touching) are the next level's breakpoints.
    let mut breakpoints = Roots::new();
    for level in chain[..degree].iter().rev() {
        breakpoints = isolate_between(level, lo, hi, &breakpoints);
    }
    breakpoints
}

/// Roots of `p` in `(lo, hi)` given `critical`, an ascending list that contains every root of `p′`
/// in `(lo, hi)` (so `p` is monotonic between consecutive breakpoints).
fn isolate_between(p: &Poly, lo: f64, hi: f64, critical: &Roots) -> Roots {
    // Breakpoints: lo, the critical points strictly inside, hi.
    let mut xs = [0.0; CAPACITY + 1];
    let mut n = 0;
    xs[n] = lo;
    n += 1;
    for r in critical.as_slice() {
        if r.t > xs[n - 1] && r.t < hi && n < xs.len() - 1 {
            xs[n] = r.t;
            n += 1;
        }
    }
    xs[n] = hi;
    n += 1;
    let mut signs = [0i8; CAPACITY + 1];
    for (s, &x) in signs.iter_mut().zip(&xs[..n]) {
        *s = p.sign_at(x);
    }

    let mut out = Roots::new();
    let mut j = 0;
    while j < n {
        if signs[j] == 0 {
            // A maximal run of "zero" breakpoints is one multiple root. Runs touching an end of
            // the interval are roots at (or within rounding of) that end: not reported.
            let start = j;
            while j + 1 < n && signs[j + 1] == 0 {
                j += 1;
            }
            let end = j;
            if start > 0 && end + 1 < n {
                let t = xs[start..=end]
                    .iter()
                    .copied()
                    .fold((xs[start], f64::INFINITY), |best, x| {
                        let v = p.eval(x).abs();
                        if v < best.1 { (x, v) } else { best }
                    })
                    .0;
                out.push(Root {
                    t,
                    crossing: signs[start - 1] != signs[end + 1],
                });
            }
        } else if j + 1 < n && signs[j + 1] != 0 && signs[j + 1] != signs[j] {
            out.push(Root {
                t: polish(p, xs[j], xs[j + 1], signs[j]),
                crossing: true,
            });
        }
        j += 1;
    }
    out
}

/// The root of `p` in `(a, b)`, where `p` is monotonic and `sign(p(a)) = sign_a = −sign(p(b))`.
fn polish(p: &Poly, a: f64, b: f64, sign_a: i8) -> f64 {
    // ITP wants f(a) < 0 < f(b): flip the polynomial when it decreases.
    let flip = if sign_a < 0 { 1.0 } else { -1.0 };
    let f = |t: f64| flip * p.eval(t);
    let (ya, yb) = (f(a), f(b));
    let t = solve_itp(
        f,
        a,
        b,
        ROOT_TOLERANCE,
        ITP_N0,
        ITP_K1_TIMES_WIDTH / (b - a),
        ya,
        yb,
    );
    t.clamp(a, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Power-basis coefficients of `Π (t − r_i)`.
    fn from_roots(roots: &[f64]) -> Poly {
        let mut c = [0.0; CAPACITY];
        c[0] = 1.0;
        for (k, &r) in roots.iter().enumerate() {
            // Multiply by (t − r): new c_i = c_{i−1} − r c_i.
            for i in (0..=k + 1).rev() {
                let prev = if i > 0 { c[i - 1] } else { 0.0 };
                c[i] = prev - r * c[i];
            }
        }
        Poly { c }
    }

    fn located(roots: &Roots) -> Vec<(f64, bool)> {
        roots.as_slice().iter().map(|r| (r.t, r.crossing)).collect()
    }

    fn assert_roots(p: &Poly, expected: &[(f64, bool)], tol: f64) {
        let got = located(&roots_in(p, 0.0, 1.0));
        assert_eq!(
            got.len(),
            expected.len(),
            "got {got:?}, expected {expected:?}"
        );
        for (g, e) in got.iter().zip(expected) {
            assert!(
                (g.0 - e.0).abs() <= tol,
                "got {got:?}, expected {expected:?}"
            );
            assert_eq!(
                g.1, e.1,
                "crossing flag: got {got:?}, expected {expected:?}"
            );
        }
    }

    #[test]
    fn from_roots_builds_the_right_polynomial() {
        let p = from_roots(&[0.5, 2.0]);
        // (t − 0.5)(t − 2) = t² − 2.5t + 1
        assert_eq!(p.coeffs()[..3], [1.0, -2.5, 1.0]);
        assert_eq!(p.degree(), Some(2));
        assert_eq!(p.derivative().coeffs()[..2], [-2.5, 2.0]);
    }

    #[test]
    fn simple_roots_of_every_degree() {
        let planted = [0.1, 0.3, 0.45, 0.6, 0.75, 0.9];
        for n in 1..=MAX_DEGREE {
            let p = from_roots(&planted[..n]);
            let expected: Vec<_> = planted[..n].iter().map(|&r| (r, true)).collect();
            assert_roots(&p, &expected, 1e-13);
        }
    }

    #[test]
    fn roots_outside_the_interval_are_ignored() {
        let p = from_roots(&[-0.5, 0.25, 1.5, 3.0]);
        assert_roots(&p, &[(0.25, true)], 1e-14);
        let none = from_roots(&[-2.0, 1.25]);
        assert_roots(&none, &[], 0.0);
    }

    #[test]
    fn double_root_is_one_touching_root() {
        let p = from_roots(&[0.4, 0.4, 0.8]);
        assert_roots(&p, &[(0.4, false), (0.8, true)], 1e-7);
        // The same with a positive-definite factor (no real root elsewhere).
        let q = Poly::product(&[0.16, -0.8, 1.0], &[2.0, 0.0, 1.0]); // (t − 0.4)² (t² + 2)
        assert_roots(&q, &[(0.4, false)], 1e-7);
    }

    #[test]
    fn triple_root_crosses() {
        let p = from_roots(&[0.5, 0.5, 0.5]);
        assert_roots(&p, &[(0.5, true)], 1e-5);
        let q = from_roots(&[0.2, 0.6, 0.6, 0.6, 0.9]);
        assert_roots(&q, &[(0.2, true), (0.6, true), (0.9, true)], 1e-4);
    }

    #[test]
    fn clustered_simple_roots_are_separated() {
        let p = from_roots(&[0.2, 0.5, 0.5 + 1e-5, 0.7]);
        assert_roots(
            &p,
            &[(0.2, true), (0.5, true), (0.5 + 1e-5, true), (0.7, true)],
            1e-9,
        );
        let q = from_roots(&[0.3, 0.3 + 1e-4, 0.3 + 2e-4]);
        assert_roots(
            &q,
            &[(0.3, true), (0.3 + 1e-4, true), (0.3 + 2e-4, true)],
            1e-9,
        );
    }

    #[test]
    fn unresolvable_cluster_degrades_to_one_root() {
        // Two roots 1e-10 apart cannot be told from a double root in f64: one touching root.
        let p = from_roots(&[0.5, 0.5 + 1e-10]);
        let got = located(&roots_in(&p, 0.0, 1.0));
        assert_eq!(got.len(), 1, "{got:?}");
        assert!((got[0].0 - 0.5).abs() < 1e-7);
        assert!(!got[0].1);
    }

    #[test]
    fn roots_at_the_ends_are_not_reported() {
        let p = from_roots(&[0.0, 0.5, 1.0]);
        assert_roots(&p, &[(0.5, true)], 1e-14);
    }

    #[test]
    fn degenerate_polynomials() {
        assert_roots(&Poly::ZERO, &[], 0.0);
        assert_roots(&Poly::new([3.0]), &[], 0.0);
        assert_roots(&Poly::new([-0.25, 1.0]), &[(0.25, true)], 0.0);
        // A leading coefficient 1e-20 times the rest: the near-linear root is still found exactly.
        let p = Poly::new([-0.25, 1.0, 1e-20]);
        assert_roots(&p, &[(0.25, true)], 1e-15);
    }

    #[test]
    fn other_intervals_and_scaling() {
        let p = from_roots(&[-1.5, 0.5, 2.5]);
        let got = located(&roots_in(&p, -2.0, 3.0));
        assert_eq!(got.len(), 3);
        for (g, e) in got.iter().zip([-1.5, 0.5, 2.5]) {
            assert!((g.0 - e).abs() < 1e-13 && g.1);
        }
        // Scaling every coefficient by 1e-200 or 1e200 changes nothing.
        for k in [1e-200, 1e200] {
            let scaled = Poly::ZERO.add_scaled(k, &from_roots(&[0.3, 0.7]));
            assert_roots(&scaled, &[(0.3, true), (0.7, true)], 1e-14);
        }
    }
}
