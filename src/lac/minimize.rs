//! Scalar minimisation on an interval: Brent's method (golden-section search with parabolic
//! interpolation; R. P. Brent, *Algorithms for Minimization without Derivatives*, 1973, ch. 5).

/// The golden-section ratio (3 − √5)/2.
const GOLDEN: f64 = 0.381_966_011_250_105_1;

/// Result of [`brent`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Minimum {
    /// The abscissa of the minimum found.
    pub x: f64,
    /// The function value there.
    pub value: f64,
    /// Function evaluations used.
    pub evaluations: usize,
}

/// Minimises `f` on `[a, b]` to an absolute abscissa tolerance `tol` (at most `max_evaluations`
/// evaluations). `f` may return `+∞` where it is undefined; the search then behaves as golden
/// section there. For a unimodal `f` the result is the minimum to `tol`; otherwise a local one.
pub fn brent(
    mut f: impl FnMut(f64) -> f64,
    a: f64,
    b: f64,
    tol: f64,
    max_evaluations: usize,
) -> Minimum {
    let (a, b) = if a <= b { (a, b) } else { (b, a) };
    let x = a + GOLDEN * (b - a);
    let fx = f(x);
    brent_from(f, (a, b), (x, fx), &[], tol, max_evaluations)
}

/// [`brent`] started from what a coarse scan already knows: `best`, a point inside `[a, b]` with
/// its value, and up to two other evaluated points (the scan's neighbours of `best`, typically
/// `a` and `b` themselves). The first step is then the parabola through those three points
/// rather than a golden-section step from scratch, and none of them is evaluated again. Points
/// outside `[a, b]` or not above `best`'s value are ignored.
pub fn brent_from(
    mut f: impl FnMut(f64) -> f64,
    (a, b): (f64, f64),
    best: (f64, f64),
    known: &[(f64, f64)],
    tol: f64,
    max_evaluations: usize,
) -> Minimum {
    let (mut a, mut b) = if a <= b { (a, b) } else { (b, a) };
    let (mut x, mut fx) = best;
    // w: the second-best point, v: the third (Brent's names); both x when not known.
    let mut others: Vec<(f64, f64)> = known
        .iter()
        .copied()
        .filter(|&(p, fp)| p >= a && p <= b && p != x && fp >= fx)
        .collect();
    others.sort_by(|p, q| p.1.total_cmp(&q.1));
    let (mut w, mut fw) = others.first().copied().unwrap_or((x, fx));
    let (mut v, mut fv) = others.get(1).copied().unwrap_or((w, fw));
    let mut evaluations = 1;
    // With three known points, allow the first step to be parabolic (the step before last is
    // taken as the whole interval); otherwise start with a golden-section step.
    let (mut d, mut e) = if others.len() == 2 {
        (0.0f64, b - a)
    } else {
        (0.0f64, 0.0f64)
    };
    while evaluations < max_evaluations {
        let m = 0.5 * (a + b);
        let tol1 = tol + f64::EPSILON * x.abs();
        let tol2 = 2.0 * tol1;
        if (x - m).abs() <= tol2 - 0.5 * (b - a) {
            break;
        }
        let mut golden = true;
        if e.abs() > tol1 && fx.is_finite() && fw.is_finite() && fv.is_finite() {
            // Parabola through (v, fv), (w, fw), (x, fx).
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            }
            q = q.abs();
            let e_prev = e;
            e = d;
            if p.abs() < (0.5 * q * e_prev).abs() && p > q * (a - x) && p < q * (b - x) {
                d = p / q;
                let u = x + d;
                if u - a < tol2 || b - u < tol2 {
                    d = if x < m { tol1 } else { -tol1 };
                }
                golden = false;
            }
        }
        if golden {
            e = if x < m { b - x } else { a - x };
            d = GOLDEN * e;
        }
        let u = if d.abs() >= tol1 {
            x + d
        } else if d > 0.0 {
            x + tol1
        } else {
            x - tol1
        };
        let fu = f(u);
        evaluations += 1;
        if fu <= fx {
            if u < x {
                b = x;
            } else {
                a = x;
            }
            (v, fv) = (w, fw);
            (w, fw) = (x, fx);
            (x, fx) = (u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv) = (w, fw);
                (w, fw) = (u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    Minimum {
        x,
        value: fx,
        evaluations,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_minimum_of_smooth_functions() {
        // Tolerances below √ε·|x| ≈ 1e-8 cannot be resolved: there f(x) is flat in f64.
        let m = brent(|x| (x - 0.7).powi(2) + 1.0, -3.0, 3.0, 1e-6, 100);
        assert!((m.x - 0.7).abs() < 1e-6 && (m.value - 1.0).abs() < 1e-12);
        assert!(m.evaluations < 15, "{}", m.evaluations);
        let m = brent(|x: f64| x.cosh() + 0.3 * x, -2.0, 2.0, 1e-7, 100);
        assert!((m.x - (-0.3f64).asinh()).abs() < 1e-6);
        assert!(m.evaluations < 20, "{}", m.evaluations);
    }

    #[test]
    fn tolerates_an_undefined_region() {
        let m = brent(
            |x| {
                if x < -1.0 {
                    f64::INFINITY
                } else {
                    (x + 0.5).powi(2)
                }
            },
            -3.0,
            3.0,
            1e-9,
            200,
        );
        assert!((m.x + 0.5).abs() < 1e-6, "{}", m.x);
    }

    #[test]
    fn a_seeded_search_finds_the_minimum_in_fewer_evaluations() {
        let f = |x: f64| x.cosh() + 0.3 * x;
        let cold = brent(f, -2.0, 2.0, 1e-7, 100);
        // A coarse scan at −2, −1, 0, 1, 2 knows the minimum lies between −1 and 1, nearest 0.
        let seeded = brent_from(
            f,
            (-1.0, 1.0),
            (0.0, f(0.0)),
            &[(-1.0, f(-1.0)), (1.0, f(1.0))],
            1e-7,
            100,
        );
        let exact = (-0.3f64).asinh();
        assert!((seeded.x - exact).abs() < 1e-6, "{}", seeded.x);
        assert!(
            seeded.evaluations < cold.evaluations,
            "{} vs {}",
            seeded.evaluations,
            cold.evaluations
        );
        // Known points that are not worse than the best, or lie outside, are ignored.
        let odd = brent_from(
            f,
            (-1.0, 1.0),
            (0.0, f(0.0)),
            &[(-5.0, 100.0), (0.5, -10.0)],
            1e-7,
            100,
        );
        assert!((odd.x - exact).abs() < 1e-6, "{}", odd.x);
    }

    #[test]
    fn a_minimum_at_the_boundary_is_approached() {
        let m = brent(|x| x, 0.0, 1.0, 1e-9, 200);
        assert!(m.x < 1e-6);
    }
}
