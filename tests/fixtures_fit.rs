//! Every fixture stroke fits within its tolerance, checked independently of the fitter's own
//! distance code (kurbo's exact nearest point on every Bézier piece).

mod common;

use kansei::pipeline::{PipelineOptions, fit_file};
use kurbo::ParamCurveNearest;

#[test]
fn every_fixture_stroke_fits_within_its_tolerance() {
    let mut strokes = 0;
    for name in common::fixture_names() {
        let file = common::fixture(&name);
        for tol_factor in [1.0, 2.0] {
            let tol = file.units.default_tolerance() * tol_factor;
            let out =
                fit_file(&file, &PipelineOptions::splits_only().with_tolerance(tol)).expect("fit");
            for c in &out.curves {
                assert!(
                    c.bspline.within_tolerance,
                    "{name} stroke {} {:?}: {}",
                    c.stroke, c.samples, c.bspline.max_deviation
                );
                let beziers = c.bspline.curve.to_beziers();
                let samples = &file.strokes[c.stroke].samples[c.samples.0..=c.samples.1];
                let mut worst: f64 = 0.0;
                for s in samples {
                    let d = beziers
                        .iter()
                        .map(|b| b.bez.nearest(s.point(), 1e-12).distance_sq.sqrt())
                        .fold(f64::INFINITY, f64::min);
                    worst = worst.max(d);
                }
                assert!(
                    worst <= tol * (1.0 + 1e-9),
                    "{name} stroke {}: {worst} > {tol}",
                    c.stroke
                );
                assert!(
                    (worst - c.bspline.max_deviation).abs() <= 1e-9 * tol.max(1.0),
                    "{name}: reported {} vs {worst}",
                    c.bspline.max_deviation
                );
            }
            // Pieces of one stroke tile its kept samples: consecutive ranges share a corner or
            // are separated only by dropped hooks at the ends.
            for w in out.curves.windows(2) {
                if w[0].stroke == w[1].stroke {
                    assert_eq!(
                        w[0].samples.1, w[1].samples.0,
                        "{name}: pieces do not meet at a corner"
                    );
                }
            }
        }
        strokes += file.strokes.len();
    }
    assert!(strokes >= 30, "only {strokes} fixture strokes");
}

/// What is dropped at a stroke's ends is small: a hook (a flick no longer than
/// `hook_length` along the stroke) and a dwell (tremor within `radius` of a centroid the kept
/// end lies near), so every dropped sample lies within their sum plus a dwell's diameter of
/// the nearest kept end sample. The drawing itself is never dropped.
#[test]
fn only_hooks_and_dwell_are_dropped_at_the_ends() {
    use kansei::prepare::{CornerOptions, DwellOptions};
    let mut dropped = 0;
    for name in common::fixture_names() {
        let file = common::fixture(&name);
        let tol = file.units.default_tolerance();
        let reach = CornerOptions::for_tolerance(tol).hook_length
            + 3.0 * DwellOptions::for_tolerance(tol).radius;
        let out =
            fit_file(&file, &PipelineOptions::splits_only().with_tolerance(tol)).expect("fit");
        for (k, stroke) in file.strokes.iter().enumerate() {
            let pieces: Vec<_> = out.curves.iter().filter(|c| c.stroke == k).collect();
            let (Some(first), Some(last)) = (pieces.first(), pieces.last()) else {
                continue;
            };
            let (a, b) = (first.samples.0, last.samples.1);
            let ends = [stroke.samples[a].point(), stroke.samples[b].point()];
            for (i, s) in stroke.samples.iter().enumerate() {
                if i >= a && i <= b {
                    continue;
                }
                dropped += 1;
                let end = if i < a { ends[0] } else { ends[1] };
                let d = s.point().distance(end);
                assert!(
                    d <= reach,
                    "{name} stroke {k}: sample {i} dropped {d} from the kept end (samples {a}..={b})"
                );
            }
        }
    }
    assert!(
        dropped > 0,
        "no fixture drops anything: the check checks nothing"
    );
}
