//! The SVG export on synthetic chains with known answers: lines and arcs exact, spirals within
//! the stated accuracy (measured independently: golden-section projection onto the exact
//! segment, both ways), the per-segment metadata, the layers, the document's size and units.
//! Every fixture is checked in `tests/export_fixtures.rs`.

mod common;

use common::export::{
    Element, Piece, group, parse_attr, parse_path, parse_subpaths, parse_xml, two_sided_distance,
    view_box, written_pieces,
};
use kansei::export::{
    ALPHA_BLUE_RGB, ALPHA_RED_RGB, ALPHA_ZERO_RGB, LacCurve, MAX_ARC_TURNING, NO_ALPHA_RGB,
    SvgElement, SvgOptions, alpha_colour, chain_path_data, segment_beziers, svg_document,
};
use kansei::geom::Point;
use kansei::lac::LacSegment;
use kansei::pipeline::{PipelineOptions, fit_file};
use kansei::stroke::{StrokeFile, Units};
use kurbo::ParamCurveFit;

#[test]
fn the_checker_rejects_broken_xml() {
    assert!(parse_xml("<a><b/></a>").is_ok());
    for bad in [
        "<a><b></a>",
        "<a>",
        "<a></a><b/>",
        "<a x=\"1\"y=\"2\"/>",
        "<a x=1/>",
        "<a x=\"<\"/>",
        "<a>text</a>",
        "<!-- a -- b --><a/>",
        "<a x=\"1\" x=\"2\"/>",
    ] {
        assert!(parse_xml(bad).is_err(), "{bad} accepted");
    }
}

fn seg(start: Point, theta0: f64, length: f64, alpha: Option<f64>, k0: f64, k1: f64) -> LacSegment {
    LacSegment::new(start, theta0, length, alpha, k0, k1)
        .unwrap_or_else(|e| panic!("{alpha:?} {k0} {k1}: {e}"))
}

/// A G1 chain of LAC segments of several kinds (spirals of both senses, an arc, a line, a κ = 0
/// end) in millimetres, starting at (10, 20).
fn chain() -> Vec<LacSegment> {
    let specs = [
        (30.0, Some(-1.0), 0.0, 0.05),
        (25.0, Some(0.5), 0.05, 0.12),
        (20.0, None, 0.12, 0.12),
        (30.0, Some(2.0), 0.12, 0.01),
        (15.0, None, 0.0, 0.0),
        (40.0, Some(3.0), -0.01, -0.2),
        (10.0, Some(0.0), -0.2, -0.05),
    ];
    let mut v: Vec<LacSegment> = Vec::new();
    let (mut start, mut theta) = (Point::new(10.0, 20.0), 0.3);
    for (length, alpha, k0, k1) in specs {
        let s = seg(start, theta, length, alpha, k0, k1);
        (start, theta) = (s.end(), s.theta1());
        v.push(s);
    }
    v
}

/// Splits the parsed pieces of a chain's path by the reported command counts.
fn per_segment<T: Copy>(pieces: &[T], counts: &[usize]) -> Vec<Vec<T>> {
    assert_eq!(counts.iter().sum::<usize>(), pieces.len());
    let mut out = Vec::new();
    let mut at = 0;
    for &n in counts {
        out.push(pieces[at..at + n].to_vec());
        at += n;
    }
    out
}

#[test]
fn chain_within_the_accuracy_with_exact_lines_and_arcs() {
    let chain = chain();
    for accuracy in [0.1, 0.01, 0.001] {
        let (d, reports) = chain_path_data(&chain, accuracy);
        assert_eq!(reports.len(), chain.len());
        let pieces = parse_path(&d);
        let counts: Vec<usize> = reports.iter().map(|r| r.commands).collect();
        let mut cubics = Vec::new();
        for ((seg, report), pieces) in chain
            .iter()
            .zip(&reports)
            .zip(per_segment(&pieces, &counts))
        {
            let expected = match (seg.kappa0(), seg.kappa1()) {
                (a, b) if a == 0.0 && b == 0.0 => SvgElement::Line,
                (a, b) if a == b => SvgElement::Arc,
                _ => SvgElement::Cubic,
            };
            assert_eq!(report.element, expected);
            assert!(pieces.iter().all(|p| p.letter() == expected.letter()));
            let error = two_sided_distance(seg, &pieces);
            match expected {
                // Exact up to rounding of the written numbers.
                SvgElement::Line | SvgElement::Arc => {
                    assert!(error <= 1e-9 * seg.length(), "{expected:?}: {error}");
                    assert_eq!(report.error, 0.0);
                }
                SvgElement::Cubic => {
                    assert!(error <= accuracy, "{seg:?}: {error} > {accuracy}");
                    assert!(report.error <= accuracy, "reported {}", report.error);
                    cubics.push(report.commands);
                }
            }
        }
        // The path is continuous: each segment's commands start where the previous ended.
        let ends: Vec<Point> = chain.iter().map(|s| s.end()).collect();
        let last = parse_path(&d).last().map(|p| p.end()).expect("pieces");
        assert!(last.distance(ends[ends.len() - 1]) <= 1e-9);
        println!("accuracy {accuracy}: cubics per spiral segment {cubics:?}");
    }
}

#[test]
fn finer_accuracy_needs_no_fewer_cubics() {
    let chain = chain();
    for seg in chain.iter().filter(|s| s.alpha().is_some()) {
        let coarse = segment_beziers(seg, 0.1).cubics.len();
        let fine = segment_beziers(seg, 0.001).cubics.len();
        assert!(fine >= coarse, "{seg:?}: {fine} < {coarse}");
        // A cubic matches a curve to fourth/fifth order: 100× finer costs at most a few times
        // more cubics (kurbo's subdivision halves the parameter range).
        assert!(fine <= 8 * coarse.max(1), "{fine} vs {coarse}");
    }
}

#[test]
fn a_hook_that_fools_kurbo_is_subdivided_until_measured_within_the_accuracy() {
    // From a fixture (perfect-freehand-hey): curvature falls from 1.86 to 1e-243 per px, nearly
    // all of it within the first pixel of 18.
    let hook = seg(
        Point::new(658.48, 417.26),
        1.82832469543429,
        18.448114291424673,
        Some(-0.004510292272824147),
        -1.8595824788478208,
        -1.1222026544134617e-243,
    );
    let accuracy = 0.05;
    // kurbo alone accepts a single cubic far from the curve (its 20 samples miss the hook).
    let alone = kurbo::fit_to_bezpath(&LacCurve::new(&hook), accuracy);
    let alone: Vec<Piece> = alone
        .segments()
        .map(|s| Piece::Cubic(s.to_cubic()))
        .collect();
    assert!(two_sided_distance(&hook, &alone) > 100.0 * accuracy);
    // Measured and subdivided, it is within the accuracy.
    let fit = segment_beziers(&hook, accuracy);
    assert!(fit.error <= accuracy, "{}", fit.error);
    let pieces: Vec<Piece> = fit.cubics.iter().map(|c| Piece::Cubic(*c)).collect();
    let error = two_sided_distance(&hook, &pieces);
    assert!(error <= accuracy, "{error}");
    // The cubics join end to end, from the segment's start to its end.
    assert_eq!(fit.cubics[0].p0, hook.start());
    assert_eq!(fit.cubics[fit.cubics.len() - 1].p3, hook.end());
    for w in fit.cubics.windows(2) {
        assert_eq!(w[0].p3, w[1].p0);
    }
}

/// The distance from points spread along `segment` to the nearest of `cubics`: what a reader of
/// the cubics sees of the segment, measured without the exporter's own polyline.
fn worst_miss(segment: &LacSegment, cubics: &[kurbo::CubicBez]) -> f64 {
    use kurbo::ParamCurveNearest;
    const POINTS: f64 = 2000.0;
    segment
        .samples(segment.length() / POINTS)
        .map(|x| {
            cubics
                .iter()
                .map(|c| c.nearest(x.point, 1e-9).distance_sq)
                .fold(f64::INFINITY, f64::min)
                .sqrt()
        })
        .fold(0.0, f64::max)
}

#[test]
fn pathological_segments_end_with_bounded_work_and_an_honest_error() {
    use kansei::export::{MAX_FIT_STEPS_PER_SEGMENT, MAX_PARTS_PER_SEGMENT};
    let cases = [
        // A clothoid of 80 000 turns (κ 0 → 1000 over 1000 units) at a thousandth of a unit.
        (
            seg(Point::new(0.0, 0.0), 0.0, 1000.0, Some(-1.0), 0.0, 1000.0),
            1e-3,
        ),
        // A logarithmic spiral 10¹⁴ accuracies long, curling from radius 10⁸ to 10⁻⁴.
        (
            seg(Point::new(5.0, 5.0), 0.3, 1e11, Some(1.0), 1e-8, 1e4),
            1e-3,
        ),
        // A circle wound 1.6·10¹² times.
        (seg(Point::new(0.0, 1.0), 0.0, 1e13, None, 1.0, 1.0), 1e-3),
        // A gentle spiral far from the origin, asked for an accuracy finer than f64 places its
        // points there (their spacing is about 1e-7).
        (
            seg(Point::new(1e9, -1e9), 2.0, 50.0, Some(0.0), 0.01, 0.02),
            1e-12,
        ),
    ];
    // Every cubic ends a range of kurbo's or of the exporter's halving: one per step spent, one
    // more per range a step left unsplit, and one per part.
    let most_cubics = 3 * MAX_FIT_STEPS_PER_SEGMENT + MAX_PARTS_PER_SEGMENT;
    for (segment, accuracy) in cases {
        let fit = segment_beziers(&segment, accuracy);
        assert!(!fit.cubics.is_empty() && fit.cubics.len() <= most_cubics);
        assert!(fit.error.is_finite() && fit.error > 0.0);
        // Joined end to end from the exact start to the exact end.
        assert_eq!(fit.cubics[0].p0, segment.start());
        assert_eq!(fit.cubics[fit.cubics.len() - 1].p3, segment.end());
        for w in fit.cubics.windows(2) {
            assert_eq!(w[0].p3, w[1].p0);
        }
        // The stated error is honest: no point of the segment is farther from the cubics.
        let miss = worst_miss(&segment, &fit.cubics);
        assert!(
            miss <= fit.error * (1.0 + 1e-9),
            "{segment:?}: missed by {miss}, stated {}",
            fit.error
        );
    }
    // The accuracy beyond f64's reach is raised to what it can reach (256 ulps of 1.4e9), and
    // the spiral is fitted to that, not given up on.
    let far = cases[3].0;
    let fit = segment_beziers(&far, 1e-12);
    assert!(fit.error <= 256.0 * f64::EPSILON * 1.5e9, "{}", fit.error);
}

#[test]
fn long_arcs_are_cut_into_quarter_turns() {
    for turns in [0.1, 0.25, 0.26, 0.5, 0.99, 1.0, 1.7] {
        let kappa: f64 = -0.2;
        let length = turns * std::f64::consts::TAU / kappa.abs();
        let arc = seg(Point::new(3.0, -4.0), 1.0, length, None, kappa, kappa);
        let (d, reports) = chain_path_data(&[arc], 0.01);
        let n = (turns * std::f64::consts::TAU / MAX_ARC_TURNING).ceil() as usize;
        assert_eq!(reports[0].commands, n.max(1), "{turns} turns");
        let pieces = parse_path(&d);
        assert_eq!(pieces.len(), n.max(1));
        let error = two_sided_distance(&arc, &pieces);
        assert!(error <= 1e-9 * length, "{turns} turns: {error}");
    }
}

#[test]
fn an_arc_winding_many_times_is_one_circle_and_the_rest() {
    let kappa: f64 = 0.5;
    let (r, theta0, start) = (1.0 / kappa, 0.7_f64, Point::new(2.0, -1.0));
    let centre = start + kurbo::Vec2::new(-theta0.sin(), theta0.cos()) * r;
    for turns in [1.0, 1.25, 2.5, 3.0, 1e6 + 0.6, 1.6e12] {
        let length = turns * std::f64::consts::TAU / kappa;
        let arc = seg(start, theta0, length, None, kappa, kappa);
        let (d, reports) = chain_path_data(&[arc], 0.01);
        let rest = (turns - turns.floor()) * 4.0;
        let expected = 4 + if rest > 1e-9 { rest.ceil() as usize } else { 0 };
        assert_eq!(reports[0].commands, expected, "{turns} turns");
        assert!(reports[0].commands <= 8);
        let pieces = parse_path(&d);
        assert_eq!(pieces.len(), expected);
        // Every command is an arc of the segment's circle, and the path ends at its end; to the
        // rounding of the segment's own points, whose angle κ·s rounds by an ulp of the turning
        // (a thousandth of a radian at 10¹³ radians).
        let tolerance = (1e-9_f64).max(16.0 * f64::EPSILON * turns * std::f64::consts::TAU) * r;
        for piece in &pieces {
            for i in 0..=8 {
                let p = piece.eval(f64::from(i) / 8.0);
                assert!(
                    (p.distance(centre) - r).abs() <= tolerance,
                    "{turns}: {p:?}"
                );
            }
        }
        let last = pieces[pieces.len() - 1].eval(1.0);
        assert!(last.distance(arc.end()) <= tolerance);
    }
}

#[test]
fn the_adapter_samples_position_and_arc_length_derivative() {
    let s = seg(Point::new(1.0, 2.0), 0.4, 30.0, Some(-0.7), 0.3, 0.02);
    let curve = LacCurve::new(&s);
    for t in [0.0, 0.2, 0.5, 0.9, 1.0] {
        let (p, d) = curve.sample_pt_deriv(t);
        assert!(p.distance(s.point(t * s.length())) <= 1e-12);
        // |dP/dt| = S (arc-length parametrisation).
        assert!((d.hypot() - s.length()).abs() <= 1e-12 * s.length());
        // Central difference of the position agrees with the derivative.
        let h = 1e-6;
        if t > h && t < 1.0 - h {
            let fd = (curve.sample_pt_deriv(t + h).0 - curve.sample_pt_deriv(t - h).0) / (2.0 * h);
            assert!(
                (fd - d).hypot() <= 1e-5 * s.length(),
                "{t}: {fd:?} vs {d:?}"
            );
        }
        let sample = curve.sample_pt_tangent(t, 1.0);
        assert_eq!(sample.p, p);
        assert_eq!(sample.tangent, d);
    }
    assert_eq!(curve.break_cusp(0.0..1.0), None);
}

/// A fitted file: a planted spiral drawn by a pen, in mm.
fn fitted() -> (StrokeFile, kansei::pipeline::FitOutput) {
    let segment = common::lac::planted_segment(-1.0, 60.0, 0.2, 1.5);
    let stroke = common::lac::pen_stroke(&segment, 300, 0, 0.02, 7);
    let file = StrokeFile::new(Units::Mm, vec![stroke]);
    let out = fit_file(&file, &PipelineOptions::default()).expect("fit");
    (file, out)
}

fn curve_paths(elements: &[Element]) -> Vec<&Element> {
    group(elements, "curves").1
}

#[test]
fn document_structure_and_metadata() {
    let (file, out) = fitted();
    let options = SvgOptions::default().with_layers(true, true, true, true);
    let export = svg_document(&out, Some(&file), &options);
    let svg = &export.svg;
    assert!(svg.contains("y axis is not flipped"));
    for bad in ["NaN", "inf"] {
        assert!(!svg.contains(bad), "{bad} in output");
    }
    let elements = parse_xml(svg).unwrap_or_else(|e| panic!("{e}\n{svg}"));
    let root = &elements[0];
    assert_eq!(root.name, "svg");
    assert_eq!(root.attr("xmlns"), Some("http://www.w3.org/2000/svg"));
    let [x, y, w, h] = view_box(&elements);
    // Millimetre data: a physical size equal to the viewBox.
    assert_eq!(root.attr("width"), Some(format!("{w}mm").as_str()));
    assert_eq!(root.attr("height"), Some(format!("{h}mm").as_str()));
    // Every sample lies inside the view with the margin around it.
    for s in &file.strokes[0].samples {
        let m = options.margin;
        assert!(s.x - m >= x - 1e-9 && s.x + m <= x + w + 1e-9);
        assert!(s.y - m >= y - 1e-9 && s.y + m <= y + h + 1e-9);
    }
    // The document's metadata states the accuracy: a tenth of the tolerance by default.
    let export_meta = elements
        .iter()
        .find(|e| e.name == "kansei:export")
        .expect("export metadata");
    assert_eq!(parse_attr(export_meta, "accuracy"), 0.1 * out.tolerance);
    assert_eq!(parse_attr(export_meta, "tolerance"), out.tolerance);
    assert!(parse_attr(export_meta, "error") <= 0.1 * out.tolerance);

    let paths = curve_paths(&elements);
    let chains: Vec<_> = out.curves.iter().filter_map(|c| c.chain.as_ref()).collect();
    // One stroke: one path, holding every piece.
    assert_eq!(paths.len(), 1);
    assert_eq!(export.paths.len(), 1);
    assert_eq!(export.paths[0].pieces.len(), chains.len());
    for path in &paths {
        assert_eq!(path.name, "path");
        assert_eq!(path.attr("data-stroke"), Some("0"));
        let written = written_pieces(&elements, path);
        assert_eq!(written.len(), chains.len());
        for (w, chain) in written.iter().zip(&chains) {
            assert_eq!(w.segments.len(), chain.segments.len());
            for ((e, mine), cs) in w.segments.iter().zip(&chain.segments) {
                let s = &cs.segment;
                assert_eq!(e.name, "kansei:segment");
                match s.alpha() {
                    Some(a) => assert_eq!(parse_attr(e, "alpha"), a),
                    None => assert_eq!(e.attr("alpha"), Some("null")),
                }
                assert_eq!(parse_attr(e, "length"), s.length());
                assert_eq!(parse_attr(e, "kappa0"), s.kappa0());
                assert_eq!(parse_attr(e, "kappa1"), s.kappa1());
                assert_eq!(parse_attr(e, "max-deviation"), cs.max_deviation);
                assert!(parse_attr(e, "error") <= export.accuracy);
                // The commands the metadata announces lie within the accuracy of the segment
                // (measured here, independently).
                let error = two_sided_distance(s, mine);
                assert!(error <= export.accuracy, "{error} > {}", export.accuracy);
            }
        }
    }
    // Optional layers.
    assert_eq!(
        group(&elements, "samples").1.len(),
        file.strokes[0].samples.len()
    );
    assert_eq!(group(&elements, "bspline").1.len(), out.curves.len());
    let (_, alpha) = group(&elements, "alpha");
    assert_eq!(
        alpha.len(),
        chains.iter().map(|c| c.segments.len()).sum::<usize>()
    );
    for (e, cs) in alpha.iter().zip(chains.iter().flat_map(|c| &c.segments)) {
        let [r, g, b] = alpha_colour(cs.segment.alpha());
        assert_eq!(
            e.attr("stroke"),
            Some(format!("#{r:02x}{g:02x}{b:02x}").as_str())
        );
    }
    let splits: usize = out.curves.iter().map(|c| c.spans.splits.len()).sum();
    assert_eq!(group(&elements, "splits").1.len(), splits);
}

#[test]
fn layers_are_off_by_default_and_units_set_the_size() {
    let (file, out) = fitted();
    let svg = svg_document(&out, Some(&file), &SvgOptions::default()).svg;
    let elements = parse_xml(&svg).expect("well-formed");
    for id in ["samples", "bspline", "alpha", "splits"] {
        assert!(!elements.iter().any(|e| e.attr("id") == Some(id)), "{id}");
    }
    assert!(!curve_paths(&elements).is_empty());
    for (units, width) in [(Units::Px, true), (Units::Device, false)] {
        let mut o = out.clone();
        o.units = units;
        let svg = svg_document(&o, None, &SvgOptions::for_units(units)).svg;
        let elements = parse_xml(&svg).expect("well-formed");
        let [_, _, w, _] = view_box(&elements);
        match width {
            true => assert_eq!(elements[0].attr("width"), Some(format!("{w}").as_str())),
            false => assert_eq!(elements[0].attr("width"), None),
        }
    }
    // A chosen accuracy is honoured and stated.
    let fine = svg_document(&out, None, &SvgOptions::default().with_accuracy(0.0005));
    assert_eq!(fine.accuracy, 0.0005);
    assert!(fine.max_error() <= 0.0005);
    let cubics = |e: &kansei::export::SvgExport| -> usize {
        e.paths
            .iter()
            .flat_map(|p| &p.pieces)
            .flat_map(|p| &p.segments)
            .map(|s| s.commands)
            .sum()
    };
    let coarse = svg_document(&out, None, &SvgOptions::default());
    assert!(cubics(&fine) >= cubics(&coarse));
}

#[test]
fn colour_map() {
    assert_eq!(alpha_colour(None), NO_ALPHA_RGB);
    assert_eq!(alpha_colour(Some(f64::NAN)), NO_ALPHA_RGB);
    assert_eq!(alpha_colour(Some(0.0)), ALPHA_ZERO_RGB);
    assert_eq!(alpha_colour(Some(-2.0)), ALPHA_BLUE_RGB);
    assert_eq!(alpha_colour(Some(-7.0)), ALPHA_BLUE_RGB);
    assert_eq!(alpha_colour(Some(2.0)), ALPHA_RED_RGB);
    assert_eq!(alpha_colour(Some(5.0)), ALPHA_RED_RGB);
    // Monotonic between the ends: more blue below 0, more red above.
    let blue = |a: f64| alpha_colour(Some(a))[2];
    let red = |a: f64| alpha_colour(Some(a))[0];
    assert!(blue(-1.5) > blue(-0.5) && blue(-0.5) > blue(0.0));
    assert!(red(1.5) > red(0.5) && red(0.5) > red(0.0));
    // Halfway is the rounded midpoint.
    let mid = alpha_colour(Some(1.0));
    for i in 0..3 {
        let m = (f64::from(ALPHA_ZERO_RGB[i]) + f64::from(ALPHA_RED_RGB[i])) / 2.0;
        assert!((f64::from(mid[i]) - m).abs() <= 0.5);
    }
}

#[test]
fn one_path_per_stroke_with_its_pieces_as_subpaths() {
    // Three pieces of stroke 0 and one of stroke 1, built from the synthetic chain: pieces 0 and
    // 1 are its two halves (piece 1 starts exactly where piece 0 ends: it continues the
    // subpath), piece 2 is the chain's last segment moved away (a new `M`), piece 3 (stroke 1)
    // the first segment again.
    let (_, base) = fitted();
    let template = base.curves[0].clone();
    let proto = template.chain.as_ref().expect("a chain").segments[0].clone();
    let all = chain();
    let moved = {
        let s = all[all.len() - 1];
        seg(
            s.start() + kurbo::Vec2::new(5.0, -3.0),
            s.theta0(),
            s.length(),
            s.alpha(),
            s.kappa0(),
            s.kappa1(),
        )
    };
    let piece = |stroke: usize, segments: &[LacSegment]| {
        let mut c = template.clone();
        c.stroke = stroke;
        let chain = c.chain.as_mut().expect("a chain");
        chain.segments = segments
            .iter()
            .map(|s| kansei::chain::ChainSegment {
                segment: *s,
                ..proto.clone()
            })
            .collect();
        c
    };
    let output = kansei::pipeline::FitOutput::with_curves(
        Units::Mm,
        base.tolerance,
        vec![
            piece(0, &all[..3]),
            piece(0, &all[3..]),
            piece(0, &[moved]),
            piece(1, &all[..1]),
        ],
    );
    let options = SvgOptions::default().with_layers(false, false, true, false);
    let export = svg_document(&output, None, &options);
    let elements = parse_xml(&export.svg).unwrap_or_else(|e| panic!("{e}"));
    let paths = curve_paths(&elements);
    assert_eq!(paths.len(), 2, "one path per stroke");
    assert_eq!(
        export.paths.iter().map(|p| p.stroke).collect::<Vec<_>>(),
        [0, 1]
    );
    // Stroke 0: two subpaths (pieces 0 + 1, then piece 2), its segments tagged with their piece.
    let d = paths[0].attr("d").expect("d");
    let subpaths = parse_subpaths(d);
    assert_eq!(subpaths.len(), 2);
    assert_eq!(subpaths[0].start, all[0].start());
    assert_eq!(subpaths[1].start, moved.start());
    let written = written_pieces(&elements, paths[0]);
    let summary: Vec<(usize, bool, usize)> = written
        .iter()
        .map(|w| (w.piece, w.move_to, w.segments.len()))
        .collect();
    assert_eq!(
        summary,
        [(0, true, 3), (1, false, all.len() - 3), (2, true, 1)]
    );
    let reported: Vec<(usize, bool)> = export.paths[0]
        .pieces
        .iter()
        .map(|p| (p.piece, p.move_to))
        .collect();
    assert_eq!(reported, [(0, true), (1, false), (2, true)]);
    assert_eq!(paths[0].attr("data-pieces"), Some("3"));
    // Every segment of every piece is within the accuracy of its exact curve.
    let exact = [&all[..3], &all[3..], &[moved][..]];
    for (w, segments) in written.iter().zip(exact) {
        for ((_, mine), s) in w.segments.iter().zip(segments) {
            let error = two_sided_distance(s, mine);
            assert!(error <= export.accuracy, "{error} > {}", export.accuracy);
        }
    }
    // Stroke 1: one subpath, one piece (index 3 of the fit's curves).
    let written = written_pieces(&elements, paths[1]);
    assert_eq!(written.len(), 1);
    assert_eq!((written[0].piece, written[0].move_to), (3, true));
    assert_eq!(paths[1].attr("data-stroke"), Some("1"));
    // The α layer keeps one path per segment, naming stroke, piece and segment.
    let (_, alpha) = group(&elements, "alpha");
    assert_eq!(alpha.len(), all.len() + 2);
    assert_eq!(alpha[3].attr("data-piece"), Some("1"));
    assert_eq!(alpha[3].attr("data-stroke"), Some("0"));
    assert_eq!(alpha[alpha.len() - 1].attr("data-stroke"), Some("1"));
}
