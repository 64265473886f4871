//! The DXF export on a millimetre stroke and on hand-made Bézier chains: `$INSUNITS`, the
//! spline's Bézier form (clamped, triple interior knots at arc lengths, shared end control
//! points), and the splines read back within the accuracy of the chain. Every fixture is checked
//! in `tests/export_fixtures.rs`.

mod common;

use common::export::{Piece, two_sided_distance};
use kansei::chain::Continuity;
use kansei::export::{DxfOptions, SplineForm, bezier_chain_spline, dxf_drawing, dxf_units};
use kansei::pipeline::{PipelineOptions, fit_file};
use kansei::stroke::{StrokeFile, Units};
use kurbo::ParamCurve;
use kurbo::{CubicBez, ParamCurveArclen, Point};

#[test]
fn a_chain_of_cubics_is_one_spline_in_bezier_form() {
    let a = CubicBez::new((0.0, 0.0), (1.0, 1.0), (2.0, 1.0), (3.0, 0.0));
    let b = CubicBez::new((3.0, 0.0), (4.0, -1.0), (5.0, -1.0), (6.0, 0.0));
    let dot = CubicBez::new((6.0, 0.0), (6.0, 0.0), (6.0, 0.0), (6.0, 0.0));
    let (knots, points) = bezier_chain_spline(&[a, dot, b]).expect("a spline");
    // The zero-length cubic is dropped: 2 cubics, 7 control points, 11 knots.
    assert_eq!(points.len(), 7);
    assert_eq!(knots.len(), points.len() + 4);
    assert_eq!(&points[..4], &[a.p0, a.p1, a.p2, a.p3]);
    assert_eq!(&points[3..], &[b.p0, b.p1, b.p2, b.p3]);
    let (la, lb) = (a.arclen(1e-12), b.arclen(1e-12));
    let expected = [
        0.0,
        0.0,
        0.0,
        0.0,
        la,
        la,
        la,
        la + lb,
        la + lb,
        la + lb,
        la + lb,
    ];
    for (k, e) in knots.iter().zip(expected) {
        assert!((k - e).abs() <= 1e-8, "{knots:?}");
    }
    assert_eq!(bezier_chain_spline(&[dot]), None);
    assert_eq!(bezier_chain_spline(&[]), None);
}

#[test]
fn millimetre_strokes_say_millimetres_and_read_back_within_the_accuracy() {
    assert_eq!(dxf_units(Units::Mm), dxf::enums::Units::Millimeters);
    assert_eq!(dxf_units(Units::Px), dxf::enums::Units::Unitless);
    assert_eq!(dxf_units(Units::Device), dxf::enums::Units::Unitless);
    let segment = common::lac::planted_segment(-1.0, 60.0, 0.2, 1.5);
    let stroke = common::lac::pen_stroke(&segment, 300, 0, 0.02, 7);
    let file = StrokeFile::new(Units::Mm, vec![stroke]);
    // A G1 chain: its Bézier form, segment by segment (a G2 chain's C2 spline is the next test's).
    let mut options = PipelineOptions::default();
    options.chain.continuity = Continuity::G1;
    let out = fit_file(&file, &options).expect("fit");
    for accuracy in [None, Some(0.001)] {
        let export = dxf_drawing(&out, &DxfOptions { accuracy });
        let expected = accuracy.unwrap_or(0.1 * out.tolerance);
        assert_eq!(export.accuracy, expected);
        let bytes = export.to_bytes().expect("writes");
        let text = String::from_utf8_lossy(&bytes);
        assert!(text.contains("$INSUNITS") && text.contains("AC1015"));
        let drawing = dxf::Drawing::load(&mut bytes.as_slice()).expect("reads back");
        assert_eq!(
            drawing.header.default_drawing_units,
            dxf::enums::Units::Millimeters
        );
        let splines = common::export::dxf_splines(&drawing);
        let chain = out.curves[0].chain.as_ref().expect("chain");
        assert_eq!(splines.len(), 1);
        let s = splines[0];
        assert_eq!(s.degree_of_curve, 3);
        assert!(s.is_planar());
        let points: Vec<Point> = s
            .control_points
            .iter()
            .map(|p| Point::new(p.x, p.y))
            .collect();
        assert_eq!(s.knot_values.len(), points.len() + 4);
        // The dxf crate writes 12 decimals: 5e-13 at most off, far below any accuracy.
        assert!(points[0].distance(chain.segments[0].segment.start()) <= 1e-12);
        let cubics: Vec<CubicBez> = (0..(points.len() - 1) / 3)
            .map(|i| {
                CubicBez::new(
                    points[3 * i],
                    points[3 * i + 1],
                    points[3 * i + 2],
                    points[3 * i + 3],
                )
            })
            .collect();
        let mut at = 0;
        for (cs, &n) in chain.segments.iter().zip(&export.splines[0].cubics) {
            let mine: Vec<Piece> = cubics[at..at + n]
                .iter()
                .map(|c| Piece::Cubic(*c))
                .collect();
            at += n;
            let error = two_sided_distance(&cs.segment, &mine);
            assert!(error <= expected, "{error} > {expected}");
        }
        assert_eq!(at, cubics.len());
        assert!(export.splines[0].error <= expected);
    }
}

/// A planted G2 chain in millimetres (a C rising then falling), drawn with a pen's noise.
fn planted_g2_file() -> (StrokeFile, Vec<kansei::lac::LacSegment>) {
    let truth =
        common::planted::planted(0.016, &[(37.5, Some(0.5), 0.08), (30.0, Some(-1.0), 0.024)]);
    let stroke = common::planted::jittered(&truth, 300, 0.01, 3);
    (StrokeFile::new(Units::Mm, vec![stroke]), truth)
}

#[test]
fn a_g2_chain_is_written_as_a_c2_spline_within_the_accuracy_and_a_g1_chain_in_bezier_form() {
    let (file, _) = planted_g2_file();
    for continuity in [Continuity::G1, Continuity::G2] {
        let mut options = PipelineOptions::default();
        options.chain.continuity = continuity;
        let out = fit_file(&file, &options).expect("fit");
        let chain = out.curves[0].chain.as_ref().expect("chain");
        assert_eq!(chain.continuity, continuity, "the smooth fit held");
        let export = dxf_drawing(&out, &DxfOptions::default());
        let accuracy = export.accuracy;
        let expected = if continuity == Continuity::G1 {
            SplineForm::Bezier
        } else {
            SplineForm::C2
        };
        assert_eq!(export.splines[0].form, expected);
        let bytes = export.to_bytes().expect("writes");
        let drawing = dxf::Drawing::load(&mut bytes.as_slice()).expect("reads back");
        let s = common::export::dxf_splines(&drawing)[0];
        let knots = s.knot_values.clone();
        let points: Vec<Point> = s
            .control_points
            .iter()
            .map(|p| Point::new(p.x, p.y))
            .collect();
        // The interior knots: simple for the C2 spline (each span joins its neighbours with
        // continuous second derivative), triple for the Bézier form.
        let interior = &knots[4..knots.len() - 4];
        let simple = interior.windows(2).all(|w| w[1] > w[0]);
        assert_eq!(
            simple,
            expected == SplineForm::C2,
            "{continuity:?}: {interior:?}"
        );
        if expected != SplineForm::C2 {
            continue;
        }
        // Measured here, independently of the exporter: the spline read back against the exact
        // chain, both ways.
        let spline = kansei::bspline::BSpline::new(knots, points).expect("a valid spline");
        let on_spline: Vec<Point> = spline
            .to_beziers()
            .iter()
            .flat_map(|p| (0..=40).map(move |i| p.bez.eval(i as f64 / 40.0)))
            .collect();
        let on_chain: Vec<Point> = chain
            .segments
            .iter()
            .flat_map(|c| c.segment.samples(0.01).map(|p| p.point).collect::<Vec<_>>())
            .collect();
        let nearest = |q: Point, set: &[Point]| {
            set.windows(2)
                .map(|w| {
                    let ab = w[1] - w[0];
                    let t =
                        ((q - w[0]).dot(ab) / ab.hypot2().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
                    q.distance(w[0] + ab * t)
                })
                .fold(f64::INFINITY, f64::min)
        };
        let there = on_chain
            .iter()
            .map(|q| nearest(*q, &on_spline))
            .fold(0.0, f64::max);
        let back = on_spline
            .iter()
            .map(|q| nearest(*q, &on_chain))
            .fold(0.0, f64::max);
        // The polylines' own chord errors (κ ≤ 0.08, steps ≤ 0.01 mm on the chain) are far below.
        assert!(
            there <= accuracy && back <= accuracy,
            "{there} / {back} > {accuracy}"
        );
        assert!(export.splines[0].error <= accuracy);
    }
}

/// A smooth chain with a corner inside (a hook the smooth fit left G0) is written in Bézier form,
/// which keeps the corner (a C2 spline would follow it within the accuracy by a tight bend).
#[test]
fn a_smooth_chain_with_a_corner_inside_is_written_in_bezier_form() {
    let file = common::fixture("google-ink-spring");
    let out = fit_file(&file, &PipelineOptions::default()).expect("fit");
    let cornered: Vec<bool> = out
        .curves
        .iter()
        .filter_map(|c| c.chain.as_ref())
        .map(|ch| {
            ch.segments
                .iter()
                .skip(1)
                .any(|s| s.start == kansei::chain::JointKind::Corner)
        })
        .collect();
    assert!(
        cornered.iter().any(|&c| c),
        "the spring's smooth chain has a corner inside"
    );
    let export = dxf_drawing(&out, &DxfOptions::default());
    assert_eq!(export.splines.len(), cornered.len());
    for (report, &corner) in export.splines.iter().zip(&cornered) {
        if corner {
            assert_eq!(report.form, SplineForm::Bezier);
        }
    }
    assert!(
        export.splines.iter().any(|r| r.form == SplineForm::C2),
        "a chain without a corner is still C2"
    );
}
