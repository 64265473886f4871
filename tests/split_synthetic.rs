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
    let file = fixture("google-ink-spring");
    let fits = fit_stroke(&file.strokes[0], 0, 0.5, &PipelineOptions::splits_only()).expect("fit");
    for fit in &fits {
        let first = fit.spans.splits.first().expect("splits");
        let last = fit.spans.splits.last().expect("splits");
        assert!(matches!(first.kind, SplitKind::Start | SplitKind::Corner));
        assert!(matches!(last.kind, SplitKind::End | SplitKind::Corner));
        assert_eq!(fit.spans.spans.len() + 1, fit.spans.splits.len());
        for span in &fit.spans.spans {
            let mut kappas = Vec::new();
            for pb in &span.pieces {
                let d1 = pb.bez.deriv();
                let d2 = d1.deriv();
                for i in 0..=20 {
                    let t = i as f64 / 20.0;
                    kappas.push(curvature_from_derivs(
                        d1.eval(t).to_vec2(),
                        d2.eval(t).to_vec2(),
                    ));
                }
            }
            let max = kappas.iter().fold(0.0f64, |m, k| m.max(k.abs()));
            // One sign, up to rounding near a zero-curvature end.
            let pos = kappas.iter().filter(|k| **k > 1e-9 * max).count();
            let neg = kappas.iter().filter(|k| **k < -1e-9 * max).count();
            assert!(
                pos == 0 || neg == 0,
                "span {:?}..{:?} changes sign",
                span.u0,
                span.u1
            );
        }
    }
}
