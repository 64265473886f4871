//! The preparation stage through the whole pipeline: corners, hooks, dwell and duplicates.

mod common;

use common::*;
use kansei::geom::{Point, Vec2};
use kansei::pipeline::{PipelineOptions, fit_stroke};
use kansei::split::SplitKind;
use kansei::stroke::{Sample, Stroke};

/// A quarter circle of radius 30 mm from (30, 0) counter-clockwise, sampled every 0.3 mm, with
/// `dwell` extra samples piled at the end point with tremor of deviation `sigma` (the pen
/// resting before it lifts).
fn arc_with_dwell(dwell: usize, sigma: f64, seed: u64) -> Vec<Point> {
    let mut rng = Rng::new(seed);
    let n = (30.0 * std::f64::consts::FRAC_PI_2 / 0.3) as usize;
    let mut pts: Vec<Point> = (0..=n)
        .map(|i| {
            let a = std::f64::consts::FRAC_PI_2 * i as f64 / n as f64;
            Point::new(30.0 * a.cos(), 30.0 * a.sin())
        })
        .collect();
    let end = Point::new(0.0, 30.0);
    pts.extend((0..dwell).map(|_| end + Vec2::new(sigma * rng.normal(), sigma * rng.normal())));
    pts
}

/// The pipeline's single piece for a stroke of points.
fn fit_points(points: &[Point], options: &PipelineOptions) -> kansei::pipeline::CurveFit {
    let stroke = Stroke::from_points(points.iter().copied());
    let mut fits = fit_stroke(&stroke, 0, 0.1, options).expect("fit");
    assert_eq!(fits.len(), 1);
    fits.remove(0)
}

/// Angle (degrees) between a fit's end tangent and the true one, −x.
fn end_tangent_error(fit: &kansei::pipeline::CurveFit) -> f64 {
    let last = fit.bspline.curve.to_beziers().last().expect("pieces").bez;
    let d = last.p3 - last.p2;
    d.y.atan2(-d.x).to_degrees().abs()
}

#[test]
fn dwell_does_not_bias_the_end_tangent() {
    for seed in 0..5 {
        let pts = arc_with_dwell(40, 0.04, seed);
        let arc_end = pts.len() - 41;
        let fit = fit_points(&pts, &PipelineOptions::splits_only());
        // The dwell lies outside the curve's range, which ends where the pen arrived.
        assert!(
            fit.samples.1 <= arc_end && fit.samples.1 + 3 >= arc_end,
            "{:?}",
            fit.samples
        );
        // A tolerance-bound fit pins the end tangent only to about tol / (last span's length),
        // a degree or two here (the same arc without any dwell: 1–2°).
        let error = end_tangent_error(&fit);
        assert!(error < 3.0, "seed {seed}: end tangent off by {error}°");
        // Kept, the dwell wrecks the tangent: the curve must loop into the cloud (7°–175° when
        // this test was written).
        let kept = fit_points(
            &pts,
            &PipelineOptions {
                keep_hooks: true,
                ..PipelineOptions::splits_only()
            },
        );
        assert_eq!(kept.samples.1, pts.len() - 1);
        assert!(
            end_tangent_error(&kept) > 5.0,
            "seed {seed}: kept dwell did not bend the end"
        );
    }
}

/// Points every `step` along the polyline through `corners`.
fn polyline(corners: &[(f64, f64)], step: f64) -> Vec<Point> {
    let mut out = vec![Point::new(corners[0].0, corners[0].1)];
    for w in corners.windows(2) {
        let (a, b) = (Point::new(w[0].0, w[0].1), Point::new(w[1].0, w[1].1));
        let k = (a.distance(b) / step).ceil() as usize;
        out.extend((1..=k).map(|i| a.lerp(b, i as f64 / k as f64)));
    }
    out
}

#[test]
fn a_corner_cuts_the_stroke_into_two_curves_meeting_exactly() {
    let pts = polyline(&[(0.0, 0.0), (40.0, 0.0), (40.0, 30.0)], 0.3);
    let corner = pts
        .iter()
        .position(|p| p.distance(Point::new(40.0, 0.0)) < 1e-9)
        .expect("apex");
    let stroke = Stroke::from_points(pts.iter().copied());
    let fits = fit_stroke(&stroke, 0, 0.1, &PipelineOptions::splits_only()).expect("fit");
    assert_eq!(fits.len(), 2);
    assert_eq!(fits[0].samples, (0, corner));
    assert_eq!(fits[1].samples, (corner, pts.len() - 1));
    assert_eq!(
        fits[0].spans.splits.last().map(|s| s.kind),
        Some(SplitKind::Corner)
    );
    assert_eq!(
        fits[1].spans.splits.first().map(|s| s.kind),
        Some(SplitKind::Corner)
    );
    // G0: both curves pass exactly through the corner sample.
    let end = *fits[0]
        .bspline
        .curve
        .control_points()
        .last()
        .expect("points");
    let start = fits[1].bspline.curve.control_points()[0];
    assert_eq!(end, pts[corner]);
    assert_eq!(start, pts[corner]);
    // A larger corner angle keeps the stroke whole.
    let whole = PipelineOptions {
        corner_angle: 100.0,
        ..PipelineOptions::splits_only()
    };
    assert_eq!(fit_stroke(&stroke, 0, 0.1, &whole).expect("fit").len(), 1);
}

#[test]
fn a_landing_hook_is_dropped_unless_kept() {
    // A 1.5 mm hook, then a gentle 60 mm arc.
    let mut pts = polyline(&[(1.0, -1.2), (0.0, 0.0)], 0.25);
    let hook_end = pts.len() - 1;
    pts.extend((1..=200).map(|i| {
        let a = i as f64 / 200.0;
        Point::new(60.0 * a, 8.0 * (std::f64::consts::PI * a).sin())
    }));
    let stroke = Stroke::from_points(pts.iter().copied());
    let fits = fit_stroke(&stroke, 0, 0.1, &PipelineOptions::splits_only()).expect("fit");
    assert_eq!(fits.len(), 1);
    let first = fits[0].samples.0;
    assert!(
        first > 0 && first <= hook_end + 1,
        "range starts at {first}, hook ends at {hook_end}"
    );
    let kept = PipelineOptions {
        keep_hooks: true,
        ..PipelineOptions::splits_only()
    };
    let fits = fit_stroke(&stroke, 0, 0.1, &kept).expect("fit");
    assert_eq!(fits.first().map(|f| f.samples.0), Some(0));
}

#[test]
fn duplicate_samples_are_merged_without_changing_the_fit() {
    let stroke = sample_curve(s_curve, -48.0, 48.0, 300, 0.01, 9);
    let mut doubled = Vec::new();
    for (i, s) in stroke.samples.iter().enumerate() {
        doubled.push(*s);
        if i % 3 == 0 {
            doubled.push(*s);
            doubled.push(Sample {
                t: s.t.map(|t| t + 1e-4),
                ..*s
            });
        }
    }
    let a = fit_stroke(&stroke, 0, 0.1, &PipelineOptions::splits_only()).expect("fit");
    let b = fit_stroke(
        &Stroke::new(doubled.clone()),
        0,
        0.1,
        &PipelineOptions::splits_only(),
    )
    .expect("fit");
    assert_eq!(a.len(), 1);
    assert_eq!(b.len(), 1);
    assert_eq!(b[0].samples, (0, doubled.len() - 1));
    assert_eq!(
        a[0].bspline.curve.control_points(),
        b[0].bspline.curve.control_points()
    );
}
