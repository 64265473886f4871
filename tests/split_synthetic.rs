//! Splits on synthetic strokes with known inflections and curvature extrema.

mod common;

use common::*;
use kansei::geom::Point;
use kansei::pipeline::{CurveFit, PipelineOptions, fit_stroke};
use kansei::split::SplitKind;

fn fit_one(stroke: &kansei::stroke::Stroke, tol: f64) -> CurveFit {
    let mut fits = fit_stroke(stroke, 0, tol, &PipelineOptions::splits_only()).expect("fit");
    assert_eq!(fits.len(), 1, "no corners expected");
    fits.remove(0)
}

fn splits_of(fit: &CurveFit, kind: SplitKind) -> Vec<Point> {
    fit.spans
        .splits
        .iter()
        .filter(|s| s.kind == kind)
        .map(|s| s.point)
        .collect()
}

fn polyline_length(stroke: &kansei::stroke::Stroke) -> f64 {
    stroke
        .points()
        .windows(2)
        .map(|w| w[0].distance(w[1]))
        .sum()
}

#[test]
fn an_s_curve_has_exactly_one_inflection_in_the_right_place() {
    for (sigma, seed) in [(0.0, 1), (0.01, 2), (0.02, 3)] {
        let stroke = sample_curve(s_curve, -48.0, 48.0, 600, sigma, seed);
        let fit = fit_one(&stroke, 0.1);
        let infl = splits_of(&fit, SplitKind::Inflection);
        assert_eq!(infl.len(), 1, "sigma {sigma}: inflections {infl:?}");
        assert!(
            splits_of(&fit, SplitKind::CurvatureExtremum).is_empty(),
            "sigma {sigma}: {:?}",
            fit.spans.splits
        );
        let length = polyline_length(&sample_curve(s_curve, -48.0, 48.0, 600, 0.0, 0));
        let err = infl[0].distance(Point::ZERO);
        assert!(
            err < 0.005 * length,
            "sigma {sigma}: inflection {:?}, off by {err}",
            infl[0]
        );
    }
}

#[test]
fn an_ellipse_arc_has_exactly_one_curvature_extremum_at_the_vertex() {
    for (sigma, seed) in [(0.0, 1), (0.01, 2), (0.02, 3)] {
        let stroke = sample_curve(ellipse, -1.0, 1.0, 600, sigma, seed);
        let fit = fit_one(&stroke, 0.1);
        let ext = splits_of(&fit, SplitKind::CurvatureExtremum);
        assert_eq!(ext.len(), 1, "sigma {sigma}: {:?}", fit.spans.splits);
        assert!(splits_of(&fit, SplitKind::Inflection).is_empty());
        let length = polyline_length(&sample_curve(ellipse, -1.0, 1.0, 600, 0.0, 0));
        let err = ext[0].distance(Point::new(50.0, 0.0));
        assert!(
            err < 0.005 * length,
            "sigma {sigma}: extremum {:?}, off by {err}",
            ext[0]
        );
    }
}

#[test]
fn spans_have_one_curvature_sign_and_monotonic_curvature() {
    use kansei::geom::{ParamCurve, ParamCurveDeriv, curvature_from_derivs};
    let tolerance = 0.5;
    let file = fixture("google-ink-spring");
    let fits = fit_stroke(
        &file.strokes[0],
        0,
        tolerance,
        &PipelineOptions::splits_only(),
    )
    .expect("fit");
    for fit in &fits {
        let first = fit.spans.splits.first().expect("splits");
        let last = fit.spans.splits.last().expect("splits");
        assert!(matches!(first.kind, SplitKind::Start | SplitKind::Corner));
        assert!(matches!(last.kind, SplitKind::End | SplitKind::Corner));
        assert_eq!(fit.spans.spans.len() + 1, fit.spans.splits.len());
        let count = fit.spans.spans.len();
        for (k, span) in fit.spans.spans.iter().enumerate() {
            // Curvature and arc length along the span.
            let (mut kappas, mut arc) = (Vec::new(), Vec::new());
            let mut s = 0.0;
            let mut previous = None;
            for pb in &span.pieces {
                let d1 = pb.bez.deriv();
                let d2 = d1.deriv();
                for i in 0..=200 {
                    let t = i as f64 / 200.0;
                    let p = pb.bez.eval(t);
                    if let Some(q) = previous {
                        s += p.distance(q);
                    }
                    previous = Some(p);
                    kappas.push(curvature_from_derivs(
                        d1.eval(t).to_vec2(),
                        d2.eval(t).to_vec2(),
                    ));
                    arc.push(s);
                }
            }
            let max = kappas.iter().fold(0.0f64, |m, k| m.max(k.abs()));
            // One sign, up to rounding near a zero-curvature end,
            let sign = |k: f64| {
                if k > 1e-9 * max {
                    1
                } else if k < -1e-9 * max {
                    -1
                } else {
                    0
                }
            };
            let pos = kappas.iter().filter(|k| sign(**k) > 0).count();
            let neg = kappas.iter().filter(|k| sign(**k) < 0).count();
            if pos == 0 || neg == 0 {
                continue;
            }
            // or, next to a free end of the stroke, a stretch of the other sign that bends by
            // less than the tolerance (κ·ℓ²/8, the sagitta of its bend): its sign is the
            // noise's, and the split cancelled the inflection it made (SplitOptions::free_ends).
            let signs: Vec<(usize, i32)> = (0..kappas.len())
                .map(|i| (i, sign(kappas[i])))
                .filter(|(_, g)| *g != 0)
                .collect();
            let changes: Vec<usize> = signs
                .windows(2)
                .filter(|w| w[0].1 != w[1].1)
                .map(|w| w[1].0)
                .collect();
            assert_eq!(
                changes.len(),
                1,
                "span {:?}..{:?} changes sign twice",
                span.u0,
                span.u1
            );
            let stretch = if k == 0 && first.kind == SplitKind::Start {
                0..changes[0]
            } else if k + 1 == count && last.kind == SplitKind::End {
                changes[0]..kappas.len()
            } else {
                panic!(
                    "span {:?}..{:?} changes sign away from a free end",
                    span.u0, span.u1
                );
            };
            let ell = arc[stretch.end - 1] - arc[stretch.start];
            let bend = stretch.fold(0.0f64, |m, i| m.max(kappas[i].abs()));
            assert!(
                bend * ell * ell / 8.0 < tolerance,
                "span {:?}..{:?}: the stretch at the free end bends by {}",
                span.u0,
                span.u1,
                bend * ell * ell / 8.0
            );
        }
    }
}
