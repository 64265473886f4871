//! The logarithmic curvature graph: straight lines of slope α for LAC segments (closed form,
//! checked against finite differences of the evaluator), the same slope from a dense cubic
//! approximation of the curve, independence of travel direction, scaling, and the degenerate
//! cases.

use kansei::geom::{CubicBez, ParamBez, Point, Vec2};
use kansei::lac::{LacSegment, LcgPoint, lcg_line, lcg_of_bezier_span, lcg_of_segment, lcg_slope};

/// The α sweep of the brief: negative, the exponential form α = 0, the log spiral α = 1, the
/// involute α = 2 and beyond.
const ALPHAS: [f64; 9] = [-2.0, -1.0, -0.5, 0.0, 0.5, 1.0, 1.5, 2.0, 3.0];

/// The LCG of a segment is a line of slope α to this (absolute, in ln units); the closed form
/// only rounds, so 1e-9 leaves a wide margin over the ~5e-15 seen.
const LINE_TOL: f64 = 1e-9;

fn seg(alpha: Option<f64>, k0: f64, k1: f64, length: f64) -> LacSegment {
    LacSegment::new(Point::new(1.5, -0.7), 0.3, length, alpha, k0, k1)
        .unwrap_or_else(|e| panic!("{alpha:?} {k0} {k1} {length}: {e}"))
}

/// Segments per α: uncurling and curling, both turning senses, a large curvature ratio, and a
/// κ = 0 end where α < 0 allows one.
fn segments(alpha: f64) -> Vec<LacSegment> {
    let mut v = vec![
        seg(Some(alpha), 2.0, 0.5, 3.0),
        seg(Some(alpha), 0.5, 2.0, 3.0),
        seg(Some(alpha), -0.1, -0.01, 40.0),
        seg(Some(alpha), 1.0, 1e-6, 50.0),
    ];
    if alpha < 0.0 {
        v.push(seg(Some(alpha), 0.4, 0.0, 2.0));
        v.push(seg(Some(alpha), 0.0, -0.4, 2.0));
    }
    v
}

#[test]
fn segment_lcg_is_a_line_of_slope_alpha() {
    for alpha in ALPHAS {
        for s in segments(alpha) {
            let points = lcg_of_segment(&s, 64);
            assert_eq!(points.len(), 64, "α = {alpha}: no point skipped inside");
            let line = lcg_line(&points).expect("64 distinct ln ρ");
            assert!(
                (line.slope - alpha).abs() <= LINE_TOL,
                "α = {alpha}, {s:?}: slope {}",
                line.slope
            );
            assert!(line.max_residual <= LINE_TOL, "α = {alpha}: {line:?}");
            let slope = lcg_slope(&points).expect("a slope");
            assert!((slope - alpha).abs() <= LINE_TOL);
            // Every consecutive pair lies on the line too (not just on average).
            for w in points.windows(2) {
                let dx = w[1].log_rho - w[0].log_rho;
                let dy = w[1].log_rho_ds_drho - w[0].log_rho_ds_drho;
                assert!((dy - alpha * dx).abs() <= LINE_TOL, "α = {alpha}: {w:?}");
            }
        }
    }
}

/// The closed-form y against ρ·|Δs/Δρ| from central differences of the evaluator's κ(s).
/// Step h = 1e-5·S: truncation O(h²·ρ‴/ρ′) ≤ 1e-8 relative even near the fast-growing ρ of a
/// low-curvature end, rounding ≈ 1e-16/1e-5 = 1e-11, so y (a log, i.e. relative) agrees to 1e-6.
#[test]
fn segment_lcg_matches_finite_differences() {
    const FD_TOL: f64 = 1e-6;
    for alpha in ALPHAS {
        for s in segments(alpha) {
            let h = 1e-5 * s.length();
            for p in lcg_of_segment(&s, 16) {
                let rho = |s_: f64| 1.0 / s.kappa(s_).abs();
                let drho_ds = (rho(p.s + h) - rho(p.s - h)) / (2.0 * h);
                let y = (rho(p.s) / drho_ds.abs()).ln();
                assert!(
                    (y - p.log_rho_ds_drho).abs() <= FD_TOL,
                    "α = {alpha}, s = {}: {y} vs {}",
                    p.s,
                    p.log_rho_ds_drho
                );
                assert!((p.log_rho - rho(p.s).ln()).abs() <= 1e-15 * p.log_rho.abs().max(1.0));
            }
        }
    }
}

#[test]
fn segment_lcg_points_are_cell_midpoints() {
    let s = seg(Some(1.0), 2.0, 0.5, 3.0);
    let points = lcg_of_segment(&s, 3);
    let expected = [0.5, 1.5, 2.5];
    assert_eq!(points.len(), 3);
    for (p, e) in points.iter().zip(expected) {
        assert!((p.s - e).abs() <= 1e-15);
    }
    assert!(lcg_of_segment(&s, 0).is_empty());
}

#[test]
fn arcs_and_lines_have_no_lcg() {
    assert!(lcg_of_segment(&seg(None, 0.7, 0.7, 2.0), 50).is_empty());
    assert!(lcg_of_segment(&seg(None, 0.0, 0.0, 2.0), 50).is_empty());
    // A straight cubic has κ = 0 everywhere, so no LCG either. (A cubic approximating a circular
    // arc does have one: its κ′ is small but not 0.)
    let line = CubicBez::new((0.0, 0.0), (1.0, 1.0), (2.0, 2.0), (3.0, 3.0));
    assert!(lcg_of_bezier_span(&[piece(line)], 50).is_empty());
}

#[test]
fn direction_of_travel_does_not_change_the_slope() {
    for alpha in ALPHAS {
        let down = lcg_of_segment(&seg(Some(alpha), 2.0, 0.5, 3.0), 40);
        let up = lcg_of_segment(&seg(Some(alpha), 0.5, 2.0, 3.0), 40);
        let (a, b) = (
            lcg_slope(&down).expect("slope"),
            lcg_slope(&up).expect("slope"),
        );
        assert!((a - b).abs() <= LINE_TOL, "α = {alpha}: {a} vs {b}");
        // Same graph, travelled backwards: point i of one is point n − 1 − i of the other.
        for (p, q) in down.iter().zip(up.iter().rev()) {
            assert!((p.log_rho - q.log_rho).abs() <= LINE_TOL);
            assert!((p.log_rho_ds_drho - q.log_rho_ds_drho).abs() <= LINE_TOL);
        }
    }
}

fn piece(bez: CubicBez) -> ParamBez {
    ParamBez {
        bez,
        u0: 0.0,
        u1: 1.0,
    }
}

/// The C1 cubic Hermite interpolant of `segment` on `n` equal arc-length steps h: each piece
/// runs from P(s_i) to P(s_i + h) with control points P ± (h/3)·(cos θ, sin θ), so its velocity
/// at both ends is the curve's unit tangent (the arc-length parameterisation).
fn hermite_span(segment: &LacSegment, n: usize) -> Vec<ParamBez> {
    let h = segment.length() / n as f64;
    let samples: Vec<_> = (0..=n).map(|i| segment.sample(i as f64 * h)).collect();
    samples
        .windows(2)
        .enumerate()
        .map(|(i, w)| {
            let t0 = Vec2::from_angle(w[0].theta) * (h / 3.0);
            let t1 = Vec2::from_angle(w[1].theta) * (h / 3.0);
            ParamBez {
                bez: CubicBez::new(w[0].point, w[0].point + t0, w[1].point - t1, w[1].point),
                u0: i as f64,
                u1: (i + 1) as f64,
            }
        })
        .collect()
}

/// Reverses a span: pieces in reverse order, each travelled backwards.
fn reversed(span: &[ParamBez]) -> Vec<ParamBez> {
    span.iter()
        .rev()
        .map(|p| ParamBez {
            bez: CubicBez::new(p.bez.p3, p.bez.p2, p.bez.p1, p.bez.p0),
            u0: -p.u1,
            u1: -p.u0,
        })
        .collect()
}

/// A cubic Hermite interpolant on steps h matches the curve's third derivative (hence κ′) to
/// O(h²) at each piece's midpoint (O(h) elsewhere), so sampling the LCG once per piece, at the
/// cell midpoints (which are the piece midpoints up to the pieces' O(h⁵) arc-length deviation
/// from h), gives a slope error O(h²): ≤ 4.8e-4 seen at 128 pieces over a curvature ratio of 4,
/// 1e-3 asserted; and doubling the pieces must divide the error by at least 3 (second order: 4).
#[test]
fn dense_bezier_span_of_a_lac_has_slope_alpha() {
    const SPAN_TOL: f64 = 1e-3;
    for alpha in ALPHAS {
        for s in [
            seg(Some(alpha), 2.0, 0.5, 3.0),
            seg(Some(alpha), -0.5, -2.0, 3.0),
        ] {
            let err = |n: usize| {
                let points = lcg_of_bezier_span(&hermite_span(&s, n), n);
                assert_eq!(points.len(), n, "α = {alpha}");
                (lcg_slope(&points).expect("slope") - alpha).abs()
            };
            let (e_coarse, e_fine) = (err(64), err(128));
            assert!(e_fine <= SPAN_TOL, "α = {alpha}: slope error {e_fine}");
            assert!(
                e_coarse >= 3.0 * e_fine,
                "α = {alpha}: not second order: {e_coarse} → {e_fine}"
            );
            // Travelling the span backwards gives the same graph, points in reverse order.
            let span = hermite_span(&s, 128);
            let forward = lcg_of_bezier_span(&span, 128);
            let back = lcg_of_bezier_span(&reversed(&span), 128);
            assert_eq!(back.len(), forward.len());
            for (p, q) in forward.iter().zip(back.iter().rev()) {
                assert!((p.log_rho - q.log_rho).abs() <= 1e-9, "{p:?} {q:?}");
                assert!((p.log_rho_ds_drho - q.log_rho_ds_drho).abs() <= 1e-9);
            }
        }
    }
}

/// The analytic κ′ of a single cubic against central differences of κ over arc length.
#[test]
fn bezier_lcg_matches_finite_differences() {
    let bez = CubicBez::new((0.0, 0.0), (1.0, 0.2), (2.0, 1.5), (2.2, 3.0));
    let points = lcg_of_bezier_span(&[piece(bez)], 20);
    assert_eq!(points.len(), 20);
    // κ(s) from kurbo's curvature at the parameter reached by arc length.
    use kurbo::{ParamCurveArclen, ParamCurveCurvature};
    let kappa_at = |s: f64| bez.curvature(bez.inv_arclen(s, 1e-13));
    let h = 1e-4;
    for p in &points {
        let k = kappa_at(p.s).abs();
        let dk = ((kappa_at(p.s + h).abs() - kappa_at(p.s - h).abs()) / (2.0 * h)).abs();
        assert!((p.log_rho + k.ln()).abs() <= 1e-9, "{p:?}");
        assert!(
            (p.log_rho_ds_drho - (k / dk).ln()).abs() <= 1e-6,
            "{p:?} vs {}",
            (k / dk).ln()
        );
    }
}

/// Scaling a curve by k moves each LCG point by (ln k, ln k); the slope stays.
#[test]
fn scaling_shifts_the_graph_diagonally() {
    let s = seg(Some(1.5), 2.0, 0.5, 3.0);
    let span = hermite_span(&s, 64);
    let k = 7.5_f64;
    let sc = |q: Point| Point::new(k * q.x, k * q.y);
    let scaled: Vec<ParamBez> = span
        .iter()
        .map(|p| ParamBez {
            bez: CubicBez::new(sc(p.bez.p0), sc(p.bez.p1), sc(p.bez.p2), sc(p.bez.p3)),
            ..*p
        })
        .collect();
    let a = lcg_of_bezier_span(&span, 50);
    let b = lcg_of_bezier_span(&scaled, 50);
    assert_eq!(a.len(), b.len());
    for (p, q) in a.iter().zip(&b) {
        assert!((q.s - k * p.s).abs() <= 1e-8 * q.s);
        assert!(
            (q.log_rho - p.log_rho - k.ln()).abs() <= 1e-7,
            "{p:?} {q:?}"
        );
        assert!((q.log_rho_ds_drho - p.log_rho_ds_drho - k.ln()).abs() <= 1e-7);
    }
}

#[test]
fn slope_needs_two_distinct_x() {
    let p = |x: f64, y: f64| LcgPoint {
        s: 0.0,
        log_rho: x,
        log_rho_ds_drho: y,
    };
    assert_eq!(lcg_slope(&[]), None);
    assert_eq!(lcg_slope(&[p(1.0, 2.0)]), None);
    assert_eq!(lcg_slope(&[p(1.0, 2.0), p(1.0, 3.0), p(1.0, 4.0)]), None);
    let slope = lcg_slope(&[p(1.0, 2.0), p(3.0, 8.0), p(f64::NAN, 0.0)]).expect("two points");
    assert!((slope - 3.0).abs() <= 1e-15);
    let line = lcg_line(&[p(0.0, 1.0), p(1.0, 2.0), p(2.0, 3.5)]).expect("line");
    assert_eq!(line.count, 3);
    assert!((line.slope - 1.25).abs() <= 1e-15);
    assert!(line.max_residual > 0.0 && line.rms_residual <= line.max_residual);
}
