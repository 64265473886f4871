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
    let (mut a, mut b) = if a <= b { (a, b) } else { (b, a) };
    let mut x = a + GOLDEN * (b - a);
    let (mut w, mut v) = (x, x);
    let mut fx = f(x);
    let (mut fw, mut fv) = (fx, fx);
    let mut evaluations = 1;
    let (mut d, mut e) = (0.0f64, 0.0f64);
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
    fn a_minimum_at_the_boundary_is_approached() {
        let m = brent(|x| x, 0.0, 1.0, 1e-9, 200);
        assert!(m.x < 1e-6);
    }
}
