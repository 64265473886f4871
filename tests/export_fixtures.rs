//! Every fixture through every export: the SVG's paths, parsed back, and the DXF's splines, read
//! back with the `dxf` crate, lie within the stated accuracy of the exact LAC chain (measured
//! independently of the library's own measure); the DXF files pass ezdxf's audit, and ezdxf's own
//! evaluation of their splines lies within the accuracy of the chain both ways; the SVG
//! files render with librsvg; the stroke
//! files and the fit outputs validate against the checked-in JSON Schemas; curve JSON round
//! trips byte for byte and every f64 bit for bit; the readers dispatch on the version.

mod common;

use std::sync::OnceLock;

use common::export::{
    Piece, group, numbers, parse_attr, parse_xml, two_sided_distance, view_box, written_pieces,
};
use kansei::export::{
    CURVE_SCHEMA_V1, CurveFile, CurveFormatError, DxfOptions, ExportOptions, STROKE_SCHEMA_V1,
    SVG_METADATA_NAMESPACE, SvgOptions, dxf_drawing, lac_spacing, svg_document,
};
use kansei::lac::LacSegment;
use kansei::pipeline::{FitOutput, PipelineOptions, fit_file};
use kansei::stroke::{StrokeFile, Units};
use kurbo::CubicBez;

/// Every fixture: its name, the stroke file's text, the file, and its fit at the default
/// tolerance (fitted once for all the tests of this file).
fn fixtures() -> &'static [(String, String, StrokeFile, FitOutput)] {
    static FITS: OnceLock<Vec<(String, String, StrokeFile, FitOutput)>> = OnceLock::new();
    FITS.get_or_init(|| {
        common::fixture_names()
            .into_iter()
            .map(|name| {
                let path = format!(
                    "{}/fixtures/strokes/{name}.json",
                    env!("CARGO_MANIFEST_DIR")
                );
                let text = std::fs::read_to_string(&path).expect("fixture");
                let file = StrokeFile::from_json(&text).expect("fixture parses");
                let out = fit_file(&file, &PipelineOptions::default()).expect("fit");
                (name, text, file, out)
            })
            .collect()
    })
}

/// The chain segments of a fit, piece by piece (pieces without a chain left out).
fn chains(out: &FitOutput) -> Vec<Vec<LacSegment>> {
    out.curves
        .iter()
        .filter_map(|c| c.chain.as_ref())
        .map(|ch| ch.segments.iter().map(|s| s.segment).collect())
        .collect()
}

/// Figures over a set of segments written as cubics.
#[derive(Default)]
struct Tally {
    spiral_segments: usize,
    cubics: usize,
    max_cubics: usize,
    worst_ratio: f64,
    arcs: usize,
    lines: usize,
    paths: usize,
    pieces: usize,
    continued: usize,
    c2_splines: usize,
}

impl Tally {
    fn summary(&self) -> String {
        format!(
            "{} spiral segments, {} cubics ({:.2} per spiral segment, at most {} for one \
             segment), {} arcs, {} lines; {} paths of {} pieces ({} continuing the previous \
             piece's subpath); {} C2 splines; largest measured error {:.3} × the accuracy",
            self.spiral_segments,
            self.cubics,
            self.cubics as f64 / self.spiral_segments.max(1) as f64,
            self.max_cubics,
            self.arcs,
            self.lines,
            self.paths,
            self.pieces,
            self.continued,
            self.c2_splines,
            self.worst_ratio
        )
    }
}

#[test]
fn svg_paths_lie_within_the_accuracy_of_the_chain() {
    let mut tally = Tally::default();
    for (name, _, file, out) in fixtures() {
        let export = svg_document(out, Some(file), &SvgOptions::for_units(file.units));
        let accuracy = 0.1 * out.tolerance;
        assert_eq!(export.accuracy, accuracy);
        let elements = parse_xml(&export.svg).unwrap_or_else(|e| panic!("{name}: {e}"));
        // A full XML parser (with namespaces) agrees: the metadata is in kansei's namespace.
        let doc = roxmltree::Document::parse(&export.svg).unwrap_or_else(|e| panic!("{name}: {e}"));
        let segments = doc
            .descendants()
            .filter(|n| n.tag_name().name() == "segment")
            .inspect(|n| assert_eq!(n.tag_name().namespace(), Some(SVG_METADATA_NAMESPACE)))
            .count();
        assert_eq!(segments, chains(out).iter().map(Vec::len).sum::<usize>());
        let [_, _, w, h] = view_box(&elements);
        if file.units == Units::Mm {
            assert_eq!(elements[0].attr("width"), Some(format!("{w}mm").as_str()));
            assert_eq!(elements[0].attr("height"), Some(format!("{h}mm").as_str()));
        }
        // One <path> per stroke with a chain, in stroke order, saying which stroke it draws.
        let paths = group(&elements, "curves").1;
        let mut strokes: Vec<usize> = out
            .curves
            .iter()
            .filter(|c| c.chain.is_some())
            .map(|c| c.stroke)
            .collect();
        strokes.dedup();
        assert_eq!(paths.len(), strokes.len(), "{name}: one path per stroke");
        assert_eq!(export.paths.len(), strokes.len());
        let mut pieces_seen = 0;
        for ((path, &stroke), report) in paths.iter().zip(&strokes).zip(&export.paths) {
            assert_eq!(parse_attr(path, "data-stroke") as usize, stroke, "{name}");
            assert_eq!(path.attr("id"), Some(format!("stroke-{stroke}").as_str()));
            assert_eq!(report.stroke, stroke);
            let written = written_pieces(&elements, path);
            assert_eq!(parse_attr(path, "data-pieces") as usize, written.len());
            assert_eq!(written.len(), report.pieces.len(), "{name}");
            let range = numbers(path.attr("data-samples").expect("data-samples"));
            let mut last_end: Option<kurbo::Point> = None;
            for (w, r) in written.iter().zip(&report.pieces) {
                assert_eq!((w.piece, w.move_to), (r.piece, r.move_to), "{name}");
                let fit = &out.curves[w.piece];
                assert_eq!(
                    fit.stroke, stroke,
                    "{name}: piece {} in the wrong path",
                    w.piece
                );
                assert!(range[0] as usize <= fit.samples.0 && fit.samples.1 <= range[1] as usize);
                let chain: Vec<LacSegment> = fit
                    .chain
                    .as_ref()
                    .expect("a chain")
                    .segments
                    .iter()
                    .map(|s| s.segment)
                    .collect();
                assert_eq!(w.segments.len(), chain.len(), "{name}");
                // A piece continues the subpath only from its own exact start.
                if !w.move_to {
                    tally.continued += 1;
                    assert_eq!(last_end, Some(chain[0].start()), "{name}");
                }
                last_end = chain.last().map(LacSegment::end);
                pieces_seen += 1;
                for (i, (seg, (e, mine))) in chain.iter().zip(&w.segments).enumerate() {
                    assert_eq!(parse_attr(e, "index") as usize, i);
                    let n = mine.len();
                    let error = two_sided_distance(seg, mine);
                    let letter = e.attr("element").expect("element");
                    assert!(mine.iter().all(|p| letter.starts_with(p.letter())));
                    match letter {
                        "C" => {
                            assert!(
                                error <= accuracy,
                                "{name}: {seg:?} {n} cubics: {error} > {accuracy}"
                            );
                            assert!(parse_attr(e, "error") <= accuracy);
                            tally.spiral_segments += 1;
                            tally.cubics += n;
                            tally.max_cubics = tally.max_cubics.max(n);
                            tally.worst_ratio = tally.worst_ratio.max(error / accuracy);
                        }
                        _ => {
                            // Exact, up to the rounding of the written numbers.
                            // (An arc within a thousandth of the accuracy of its chord is
                            // written as that chord, and says so.)
                            let stated = parse_attr(e, "error");
                            assert!(stated <= 1e-3 * accuracy);
                            // A command starts where the one before it ended: where the
                            // chain's joint has a gap (two parts of a smooth chain meet at a
                            // corner to the joint equations' tolerance, 1e-10 of the extent;
                            // up to 2e-9 px on the painting) the line moves by the gap, and the
                            // arc of the segment's radius through the moved start by up to the
                            // gap times 1 + 2r/d (its centre moves across the chord d).
                            let gap = mine
                                .first()
                                .map_or(0.0, |p| p.start().distance(seg.start()));
                            let lever = match seg.kappa0().abs() {
                                k if letter == "A" && k > 0.0 => {
                                    1.0 + 2.0 / (k * seg.start().distance(seg.end()))
                                }
                                _ => 1.0,
                            };
                            assert!(
                                error <= stated + 1e-9 * seg.length().max(1.0) + gap * lever,
                                "{name}: {letter} {error} (gap {gap}) {seg:?} {mine:?}"
                            );
                            if letter == "A" {
                                tally.arcs += 1;
                            } else {
                                tally.lines += 1;
                            }
                        }
                    }
                }
            }
        }
        // Every piece with a chain is in some path.
        assert_eq!(pieces_seen, chains(out).len(), "{name}");
        tally.paths += paths.len();
        tally.pieces += pieces_seen;
    }
    assert!(tally.spiral_segments > 50, "{}", tally.summary());
    println!(
        "SVG, every fixture at a tenth of its tolerance: {}",
        tally.summary()
    );
}

/// The two-sided distance between a chain and `pieces` drawn along all of it: each segment's
/// projection grid to the nearest piece, and 24 points inside each piece to the nearest segment.
fn chain_to_pieces_distance(chain: &[LacSegment], pieces: &[Piece]) -> f64 {
    let grids: Vec<_> = chain.iter().map(common::export::grid_of).collect();
    let steps: Vec<f64> = grids
        .iter()
        .map(|grid| grid.windows(2).map(|w| w[1].0 - w[0].0).fold(0.0, f64::max))
        .collect();
    let mut worst: f64 = 0.0;
    for grid in &grids {
        for (_, p) in grid {
            let d = pieces
                .iter()
                .map(|x| x.distance(*p))
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
    }
    const INSIDE: usize = 24;
    for piece in pieces {
        for i in 0..=INSIDE + 1 {
            let q = piece.eval(i as f64 / (INSIDE + 1) as f64);
            // Projected onto every segment that can hold the nearest point: one whose nearest
            // grid point is no farther than the nearest of all plus its grid's largest step
            // (every point of a segment lies within a step of its grid).
            let near: Vec<f64> = grids
                .iter()
                .map(|grid| {
                    grid.iter()
                        .map(|(_, p)| p.distance(q))
                        .fold(f64::INFINITY, f64::min)
                })
                .collect();
            let best = near.iter().copied().fold(f64::INFINITY, f64::min);
            let d = (0..chain.len())
                .filter(|&k| near[k] - steps[k] <= best)
                .map(|k| common::export::project(&chain[k], &grids[k], q).1)
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
    }
    worst
}

/// The cubics of a clamped cubic B-spline whose interior knots all have multiplicity 3.
fn bezier_form(knots: &[f64], points: &[kurbo::Point]) -> Vec<CubicBez> {
    assert_eq!(knots.len(), points.len() + 4);
    assert_eq!((points.len() - 1) % 3, 0);
    let n = (points.len() - 1) / 3;
    assert!(knots[..4].iter().all(|&k| k == knots[0]));
    assert!(
        knots[knots.len() - 4..]
            .iter()
            .all(|&k| k == knots[knots.len() - 1])
    );
    for i in 0..n.saturating_sub(1) {
        let triple = &knots[4 + 3 * i..7 + 3 * i];
        assert!(triple.iter().all(|&k| k == triple[0]), "{knots:?}");
        let previous = if i == 0 { knots[0] } else { knots[3 + 3 * i] };
        assert!(triple[0] > previous, "knots not increasing: {knots:?}");
    }
    (0..n)
        .map(|i| {
            CubicBez::new(
                points[3 * i],
                points[3 * i + 1],
                points[3 * i + 2],
                points[3 * i + 3],
            )
        })
        .collect()
}

/// The directory the DXF files of every fixture are written to.
fn dxf_dir() -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("export-fixtures-dxf");
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

#[test]
fn dxf_splines_read_back_lie_within_the_accuracy_of_the_chain() {
    let mut tally = Tally::default();
    for (name, _, _, out) in fixtures() {
        let export = dxf_drawing(out, &DxfOptions::default());
        let accuracy = 0.1 * out.tolerance;
        assert_eq!(export.accuracy, accuracy);
        let bytes = export.to_bytes().expect("writes");
        std::fs::write(dxf_dir().join(format!("{name}.dxf")), &bytes).expect("write");
        let drawing = dxf::Drawing::load(&mut bytes.as_slice()).expect("reads back");
        let expected_units = match out.units {
            Units::Mm => dxf::enums::Units::Millimeters,
            Units::Px | Units::Device => dxf::enums::Units::Unitless,
        };
        assert_eq!(
            drawing.header.default_drawing_units, expected_units,
            "{name}"
        );
        let splines = common::export::dxf_splines(&drawing);
        let chains = chains(out);
        assert_eq!(splines.len(), chains.len(), "{name}");
        assert_eq!(export.splines.len(), chains.len());
        for ((spline, chain), report) in splines.iter().zip(&chains).zip(&export.splines) {
            assert_eq!(spline.degree_of_curve, 3);
            assert!(spline.weight_values.is_empty(), "not rational");
            let points: Vec<kurbo::Point> = spline
                .control_points
                .iter()
                .map(|p| {
                    assert_eq!(p.z, 0.0);
                    kurbo::Point::new(p.x, p.y)
                })
                .collect();
            if report.form == kansei::export::SplineForm::C2 {
                // A smooth chain's C2 spline (simple knots): the whole spline against the whole
                // chain, both ways.
                let spline = kansei::bspline::BSpline::new(spline.knot_values.clone(), points)
                    .expect("a valid spline");
                let pieces: Vec<Piece> = spline
                    .to_beziers()
                    .iter()
                    .map(|p| Piece::Cubic(p.bez))
                    .collect();
                let error = chain_to_pieces_distance(chain, &pieces);
                assert!(error <= accuracy, "{name}: C2 spline {error} > {accuracy}");
                tally.c2_splines += 1;
                tally.worst_ratio = tally.worst_ratio.max(error / accuracy);
                continue;
            }
            let cubics = bezier_form(&spline.knot_values, &points);
            assert_eq!(cubics.len(), report.cubics.iter().sum::<usize>(), "{name}");
            let mut at = 0;
            for (seg, &n) in chain.iter().zip(&report.cubics) {
                let mine: Vec<Piece> = cubics[at..at + n]
                    .iter()
                    .map(|c| Piece::Cubic(*c))
                    .collect();
                at += n;
                let error = two_sided_distance(seg, &mine);
                assert!(
                    error <= accuracy,
                    "{name}: {seg:?} {n} cubics: {error} > {accuracy}"
                );
                match (seg.kappa0(), seg.kappa1()) {
                    (a, b) if a == 0.0 && b == 0.0 => tally.lines += 1,
                    (a, b) if a == b => tally.arcs += 1,
                    _ => {
                        tally.spiral_segments += 1;
                        tally.cubics += n;
                        tally.max_cubics = tally.max_cubics.max(n);
                    }
                }
                tally.worst_ratio = tally.worst_ratio.max(error / accuracy);
            }
        }
    }
    println!(
        "DXF, every fixture at a tenth of its tolerance (all segments as cubics): {}",
        tally.summary()
    );
}

/// A Python interpreter that imports ezdxf: `$KANSEI_PYTHON`, Debian's `/usr/bin/python3`
/// (where `apt-get install python3-ezdxf` puts it), or `python3` on the path.
fn python_with_ezdxf() -> Option<String> {
    let candidates = std::env::var("KANSEI_PYTHON")
        .ok()
        .into_iter()
        .chain(["/usr/bin/python3".to_owned(), "python3".to_owned()]);
    candidates.into_iter().find(|python| {
        std::process::Command::new(python)
            .args(["-c", "import ezdxf"])
            .stdin(std::process::Stdio::null())
            .output()
            .is_ok_and(|o| o.status.success())
    })
}

/// The reference polylines of the ezdxf check lie within this fraction of the export accuracy
/// of the exact LAC chain (their chord error); the script adds it to the accuracy it checks
/// against. A twentieth keeps the check within 5 % of the accuracy while a fixture's polyline
/// stays at a few thousand points.
const EZDXF_REFERENCE_CHORD_FRACTION: f64 = 0.05;

/// The exact LAC chain of each spline of `out`'s DXF, as a JSON reference for
/// `tests/dxf_audit.py`: the accuracy, the chord error of the polylines, and per spline (one per
/// piece with a chain, in order) the points of its chain's segments, each sampled by
/// [`LacSegment::samples`] at [`lac_spacing`] for that chord error. The chord error written is
/// the largest bound κ_max·h²/8 over the spacings h actually used, never below the one asked.
fn dxf_reference(out: &FitOutput, accuracy: f64) -> serde_json::Value {
    let asked = EZDXF_REFERENCE_CHORD_FRACTION * accuracy;
    let mut chord_error: f64 = asked;
    let mut splines = Vec::new();
    for chain in chains(out) {
        let mut points: Vec<f64> = Vec::new();
        for seg in &chain {
            let spacing = lac_spacing(seg, asked);
            let steps = (seg.length() / spacing).ceil().max(1.0);
            let h = seg.length() / steps;
            let kappa = seg.kappa0().abs().max(seg.kappa1().abs());
            chord_error = chord_error.max(kappa * h * h / 8.0);
            // Consecutive segments share their joint: write it once.
            let skip = usize::from(!points.is_empty());
            for sample in seg.samples(spacing).skip(skip) {
                points.extend([sample.point.x, sample.point.y]);
            }
        }
        splines.push(serde_json::Value::from(points));
    }
    serde_json::json!({
        "accuracy": accuracy,
        "chord_error": chord_error,
        "splines": splines,
    })
}

/// Every fixture's DXF (and a planted spiral's in mm) read by ezdxf, the reference Python DXF
/// library, through `tests/dxf_audit.py`: the file loads, passes `doc.audit()` without errors,
/// states its `$INSUNITS`, and holds one degree-3 SPLINE per piece with knots = control points +
/// 4; and, beside each file, a reference of the exact LAC chain ([`dxf_reference`]) against
/// which every SPLINE, evaluated by ezdxf's own B-spline evaluator
/// (`construction_tool().points(...)`), lies within the stated accuracy both ways: every point of
/// the spline's dense polyline to the reference polyline, every reference point to the spline's
/// polyline (plus both polylines' chord errors, stated in the output).
///
/// ezdxf's audit reports 7 fixes per file, all of one kind: "Fixed invalid table head handle in
/// table VPORT" (and LTYPE, LAYER, STYLE, APPID, DIMSTYLE, BLOCK_RECORD; audit code 110,
/// `INVALID_TABLE_HANDLE`). The `dxf` crate writes the `TABLE` header of each of the seven symbol
/// tables without a handle (group code 5), which R2000 expects; ezdxf gives each a new handle
/// in memory. The entities themselves need no fix, and the script fails on any fix of another
/// kind.
#[test]
fn every_fixture_dxf_passes_the_ezdxf_audit_and_its_splines_lie_on_the_chain() {
    let Some(python) = python_with_ezdxf() else {
        // .ci/run installs python3-ezdxf and sets KANSEI_REQUIRE_EZDXF=1 when it can.
        if std::env::var_os("KANSEI_REQUIRE_EZDXF").is_some() {
            panic!("KANSEI_REQUIRE_EZDXF is set but no python3 imports ezdxf");
        }
        eprintln!("skipped: no python3 with ezdxf (install Debian's python3-ezdxf; .ci/run does)");
        return;
    };
    let dir = dxf_dir();
    let mut args = vec![format!("{}/tests/dxf_audit.py", env!("CARGO_MANIFEST_DIR"))];
    // The fixtures (px) and a planted spiral drawn in millimetres ($INSUNITS 4).
    let segment = common::lac::planted_segment(-1.0, 60.0, 0.2, 1.5);
    let stroke = common::lac::pen_stroke(&segment, 300, 0, 0.02, 7);
    let mm = StrokeFile::new(Units::Mm, vec![stroke]);
    let mm = fit_file(&mm, &PipelineOptions::default()).expect("fit");
    let outputs = fixtures()
        .iter()
        .map(|(name, _, _, out)| (name.as_str(), out))
        .chain([("planted-mm", &mm)]);
    for (name, out) in outputs {
        let export = dxf_drawing(out, &DxfOptions::default());
        // One spline per piece with a chain, so the reference's splines pair with the file's.
        assert_eq!(export.splines.len(), chains(out).len(), "{name}");
        let path = dir.join(format!("{name}.audit.dxf"));
        std::fs::write(&path, export.to_bytes().expect("writes")).expect("write");
        let reference = dir.join(format!("{name}.audit.reference.json"));
        let json = dxf_reference(out, export.accuracy);
        std::fs::write(&reference, json.to_string()).expect("write");
        let units = if out.units == Units::Mm { 4 } else { 0 };
        args.push(format!(
            "{}={},{units},{}",
            path.display(),
            export.splines.len(),
            reference.display()
        ));
    }
    let run = std::process::Command::new(&python)
        .args(&args)
        .stdin(std::process::Stdio::null())
        .output()
        .expect("python runs");
    let report = String::from_utf8_lossy(&run.stdout);
    println!("{report}{}", String::from_utf8_lossy(&run.stderr));
    assert!(run.status.success(), "ezdxf check failed:\n{report}");
    let files = fixtures().len() + 1;
    let count = |needle: &str| report.lines().filter(|l| l.contains(needle)).count();
    assert_eq!(count(" 0 audit errors"), files);
    assert_eq!(count("7 fixes (table head handles)"), files);
    assert_eq!(count("within the accuracy both ways"), files);

    // The geometric check does fail: the planted spiral's chain moved by three accuracies.
    let export = dxf_drawing(&mm, &DxfOptions::default());
    let mut moved = dxf_reference(&mm, export.accuracy);
    for spline in moved["splines"].as_array_mut().expect("splines") {
        for (i, v) in spline
            .as_array_mut()
            .expect("points")
            .iter_mut()
            .enumerate()
        {
            if i % 2 == 0 {
                *v = (v.as_f64().expect("x") + 3.0 * export.accuracy).into();
            }
        }
    }
    let reference = dir.join("planted-mm.moved.reference.json");
    std::fs::write(&reference, moved.to_string()).expect("write");
    let run = std::process::Command::new(&python)
        .arg(&args[0])
        .arg(format!(
            "{}=1,4,{}",
            dir.join("planted-mm.audit.dxf").display(),
            reference.display()
        ))
        .stdin(std::process::Stdio::null())
        .output()
        .expect("python runs");
    let report = String::from_utf8_lossy(&run.stdout);
    assert!(!run.status.success(), "a moved chain passed:\n{report}");
    assert!(report.contains("NOT within the accuracy"), "{report}");
}

#[test]
fn every_fixture_svg_renders_with_librsvg() {
    let available = std::process::Command::new("rsvg-convert")
        .arg("--version")
        .stdin(std::process::Stdio::null())
        .output()
        .is_ok_and(|o| o.status.success());
    if !available {
        // .ci/run installs librsvg2-bin and sets KANSEI_REQUIRE_RSVG=1 when it can.
        if std::env::var_os("KANSEI_REQUIRE_RSVG").is_some() {
            panic!("KANSEI_REQUIRE_RSVG is set but rsvg-convert does not run");
        }
        eprintln!("skipped: no rsvg-convert (install Debian's librsvg2-bin; .ci/run does)");
        return;
    }
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("export-fixtures-svg");
    std::fs::create_dir_all(&dir).expect("temp dir");
    for (name, _, file, out) in fixtures() {
        let options = SvgOptions::for_units(file.units).with_layers(true, true, true, true);
        let svg = dir.join(format!("{name}.svg"));
        let png = dir.join(format!("{name}.png"));
        std::fs::write(&svg, svg_document(out, Some(file), &options).svg).expect("write");
        let run = std::process::Command::new("rsvg-convert")
            .args(["--width", "800", "--output"])
            .arg(&png)
            .arg(&svg)
            .stdin(std::process::Stdio::null())
            .output()
            .expect("rsvg-convert runs");
        assert!(
            run.status.success() && run.stderr.is_empty(),
            "{name}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        let image = std::fs::read(&png).expect("png written");
        assert!(image.starts_with(b"\x89PNG\r\n\x1a\n"), "{name}: not a PNG");
        // The IHDR chunk: the requested width.
        assert_eq!(
            u32::from_be_bytes([image[16], image[17], image[18], image[19]]),
            800
        );
    }
}

fn validator(schema: &str) -> jsonschema::Validator {
    let schema: serde_json::Value = serde_json::from_str(schema).expect("schema is JSON");
    jsonschema::meta::validate(&schema).expect("a valid JSON Schema");
    jsonschema::validator_for(&schema).expect("schema compiles")
}

fn errors(v: &jsonschema::Validator, doc: &serde_json::Value) -> Vec<String> {
    v.iter_errors(doc)
        .map(|e| format!("{} at {}", e, e.instance_path()))
        .collect()
}

#[test]
fn stroke_files_and_fit_outputs_validate_against_the_schemas() {
    let strokes = validator(STROKE_SCHEMA_V1);
    let curves = validator(CURVE_SCHEMA_V1);
    for (name, text, file, out) in fixtures() {
        let doc: serde_json::Value = serde_json::from_str(text).expect("json");
        let e = errors(&strokes, &doc);
        assert!(e.is_empty(), "{name}: {e:?}");
        // What we write validates too.
        let written: serde_json::Value = serde_json::from_str(&file.to_json()).expect("json");
        assert!(errors(&strokes, &written).is_empty(), "{name} as written");
        for lcg in [false, true] {
            let curve = CurveFile::from_output_with(out, &ExportOptions { lcg });
            let doc: serde_json::Value = serde_json::from_str(&curve.to_json()).expect("json");
            let e = errors(&curves, &doc);
            assert!(e.is_empty(), "{name} (lcg {lcg}): {e:?}");
        }
    }
    // The schemas do reject: a wrong version, a missing field, an undocumented field, a bad
    // enum value, pressure out of range.
    let (_, text, _, out) = &fixtures()[0];
    let stroke: serde_json::Value = serde_json::from_str(text).expect("json");
    let mut bad = stroke.clone();
    bad["version"] = 2.into();
    assert!(!strokes.is_valid(&bad));
    let mut bad = stroke.clone();
    bad["strokes"][0]["samples"][0]["pressure"] = 1.5.into();
    assert!(!strokes.is_valid(&bad));
    let curve: serde_json::Value =
        serde_json::from_str(&CurveFile::from_output(out).to_json()).expect("json");
    let mut bad = curve.clone();
    bad["curves"][0]
        .as_object_mut()
        .expect("object")
        .remove("bspline");
    assert!(!curves.is_valid(&bad));
    let mut bad = curve.clone();
    bad["curves"][0]["segments"][0]["colour"] = "red".into();
    assert!(!curves.is_valid(&bad));
    let mut bad = curve.clone();
    bad["curves"][0]["splits"][0]["kind"] = "wiggle".into();
    assert!(!curves.is_valid(&bad));
}

/// What a written segment says of its α (issue 18's honest α), on every fixture segment at the
/// defaults (a searched range, G2): no α, no claims about one; an α says what chose it and
/// whether the samples determine it; "determined" only with an uncertainty of at most 0.5 off
/// the range's bound.
#[test]
fn every_written_alpha_says_what_chose_it_and_whether_the_samples_determine_it() {
    let mut sources = std::collections::BTreeMap::new();
    for (name, _, _, out) in fixtures() {
        let doc: serde_json::Value =
            serde_json::from_str(&CurveFile::from_output(out).to_json()).expect("json");
        for (c, curve) in doc["curves"].as_array().expect("curves").iter().enumerate() {
            for (k, seg) in curve["segments"]
                .as_array()
                .expect("segments")
                .iter()
                .enumerate()
            {
                let here = format!("{name} curve {c} segment {k}");
                let source = seg.get("alpha_source").and_then(|v| v.as_str());
                let determined = seg.get("alpha_determined").and_then(|v| v.as_bool());
                if seg["alpha"].is_null() {
                    assert_eq!((source, determined), (None, None), "{here}");
                    assert!(seg.get("alpha_uncertainty").is_none(), "{here}");
                    continue;
                }
                let source = source.unwrap_or_else(|| panic!("{here}: an α without a source"));
                *sources.entry(source.to_string()).or_insert(0usize) += 1;
                assert!(
                    ["search", "refinement", "smooth"].contains(&source),
                    "{here}: {source}"
                );
                let determined =
                    determined.unwrap_or_else(|| panic!("{here}: an α without alpha_determined"));
                if determined {
                    let u = seg["alpha_uncertainty"].as_f64().expect("an estimate");
                    assert!(u <= kansei::chain::UNDETERMINED_ALPHA, "{here}: ± {u}");
                    assert!(seg.get("alpha_bound").is_none(), "{here}");
                }
                if seg.get("alpha_bound").is_some() || seg.get("alpha_uncertainty").is_none() {
                    assert!(!determined, "{here}");
                }
            }
        }
    }
    // The default fits the recorded strokes smooth: most α are the smooth fit's, and a piece of
    // one segment (no joint to smooth) keeps its G1 search's or refinement's.
    assert!(
        sources.get("smooth").copied().unwrap_or(0) > 0,
        "{sources:?}"
    );
    assert!(
        sources.get("search").copied().unwrap_or(0) > 0,
        "{sources:?}"
    );
}

/// Every number of `a` and `b` (same shape) has the same bits.
fn same_bits(a: &serde_json::Value, b: &serde_json::Value, at: &str, count: &mut usize) {
    use serde_json::Value;
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            if x.is_f64() || y.is_f64() {
                let (x, y) = (x.as_f64().expect("f64"), y.as_f64().expect("f64"));
                assert_eq!(x.to_bits(), y.to_bits(), "{at}: {x} vs {y}");
                *count += 1;
            } else {
                assert_eq!(x, y, "{at}");
            }
        }
        (Value::Array(x), Value::Array(y)) => {
            assert_eq!(x.len(), y.len(), "{at}");
            for (i, (x, y)) in x.iter().zip(y).enumerate() {
                same_bits(x, y, &format!("{at}/{i}"), count);
            }
        }
        (Value::Object(x), Value::Object(y)) => {
            assert_eq!(x.len(), y.len(), "{at}");
            for (k, v) in x {
                same_bits(v, &y[k], &format!("{at}/{k}"), count);
            }
        }
        _ => assert_eq!(a, b, "{at}"),
    }
}

#[test]
fn curve_json_round_trips_byte_for_byte_and_bit_for_bit() {
    let mut floats = 0;
    for (name, _, file, out) in fixtures() {
        for lcg in [false, true] {
            let doc = CurveFile::from_output_with(out, &ExportOptions { lcg });
            let text = doc.to_json();
            let back = CurveFile::from_json(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(back.to_json(), text, "{name}: not byte-identical");
            assert_eq!(back, doc);
            // The structs' own numbers (not the text's) compared bit for bit.
            let (a, b) = (
                serde_json::to_value(&doc).expect("value"),
                serde_json::to_value(&back).expect("value"),
            );
            same_bits(&a, &b, name, &mut floats);
            // Compact output reads back the same too.
            let compact = serde_json::to_string(&doc).expect("json");
            assert_eq!(CurveFile::from_json(&compact).expect("reads"), doc);
        }
        // Stroke files: written, read, written again: the same bytes and bits.
        let text = file.to_json();
        let back = StrokeFile::from_json(&text).expect("reads");
        assert_eq!(
            back.to_json(),
            text,
            "{name}: stroke file not byte-identical"
        );
        let mut n = 0;
        same_bits(
            &serde_json::to_value(file).expect("value"),
            &serde_json::to_value(&back).expect("value"),
            name,
            &mut n,
        );
        floats += n;
    }
    assert!(floats > 100_000, "only {floats} numbers compared");
    println!("{floats} f64 values round-tripped bit for bit");
}

#[test]
fn the_curve_reader_dispatches_on_format_and_version() {
    let (_, _, _, out) = &fixtures()[0];
    let doc: serde_json::Value =
        serde_json::from_str(&CurveFile::from_output(out).to_json()).expect("json");
    let with = |key: &str, value: serde_json::Value| {
        let mut d = doc.clone();
        d[key] = value;
        d.to_string()
    };
    match CurveFile::from_json(&with("version", 2.into())) {
        Err(e @ CurveFormatError::UnknownVersion { found: Some(2) }) => {
            let message = e.to_string();
            assert!(
                message.contains("version 2") && message.contains("[1]"),
                "{message}"
            );
        }
        other => panic!("{other:?}"),
    }
    let mut no_version = doc.clone();
    no_version
        .as_object_mut()
        .expect("object")
        .remove("version");
    assert!(matches!(
        CurveFile::from_json(&no_version.to_string()),
        Err(CurveFormatError::UnknownVersion { found: None })
    ));
    assert!(matches!(
        CurveFile::from_json(&with("format", "kansei-stroke".into())),
        Err(CurveFormatError::WrongFormat { .. })
    ));
    // A v2 document's body is not read by the v1 reader: the version decides, even if the body
    // would parse.
    assert!(CurveFile::from_json(&with("version", 1.into())).is_ok());
    assert!(matches!(
        CurveFile::from_json("{\"format\": \"kansei-curve\", \"version\": 1}"),
        Err(CurveFormatError::Json(_))
    ));
    assert!(matches!(
        CurveFile::from_json("not json"),
        Err(CurveFormatError::Json(_))
    ));
}

#[test]
fn a_piece_fitted_to_its_own_tolerance_says_so_and_validates() {
    // Two fits of a fixture at different tolerances in one output (as the app exports strokes
    // with their own settings): the file states the smaller, the other pieces carry theirs, and
    // the document validates and round trips.
    let (_, _, file, _) = &fixtures()[0];
    let fine = 0.5 * file.units.default_tolerance();
    let coarse = 2.0 * file.units.default_tolerance();
    let at = |tolerance: f64| {
        fit_file(file, &PipelineOptions::default().with_tolerance(tolerance)).expect("fit")
    };
    let (a, b) = (at(fine), at(coarse));
    let output = FitOutput::with_curves(
        file.units,
        fine,
        a.curves.iter().chain(&b.curves).cloned().collect(),
    );
    let doc = CurveFile::from_output(&output);
    assert_eq!(doc.tolerance, fine);
    let (first, second) = doc.curves.split_at(a.curves.len());
    assert!(first.iter().all(|c| c.tolerance.is_none()));
    assert!(second.iter().all(|c| c.tolerance == Some(coarse)));
    let json: serde_json::Value = serde_json::from_str(&doc.to_json()).expect("JSON");
    let problems = errors(&validator(CURVE_SCHEMA_V1), &json);
    assert!(problems.is_empty(), "{problems:?}");
    assert_eq!(CurveFile::from_json(&doc.to_json()).expect("reads"), doc);
}

/// Smallest window, as a fraction of the segment's length, over which the joint test below
/// differences a curvature: below it the step nears the rounding of the arc length.
const FD_MIN_SCALE: f64 = 1e-6;

/// The joint records measure the written segments: one more joint than segments, each smooth
/// joint's curvatures and dκ/ds those of the segments it joins (dκ/ds checked against central
/// differences of the record's own curvature), the jumps recomputed from them, the end kinds
/// those of the piece's ends.
#[test]
fn joint_records_measure_the_continuity_of_the_written_segments() {
    use kansei::export::{JointContinuity, relative_jump};
    let mut jumps = Vec::new();
    for (name, _, _, out) in fixtures() {
        let doc = CurveFile::from_output(out);
        for (c, fit) in doc.curves.iter().zip(&out.curves) {
            assert_eq!(c.joints.len(), c.segments.len() + 1, "{name}");
            let ends = [fit.spans.splits.first(), fit.spans.splits.last()]
                .map(|s| s.is_some_and(|s| s.kind == kansei::split::SplitKind::Corner));
            let expect = |corner: bool, other| {
                if corner {
                    JointContinuity::Corner
                } else {
                    other
                }
            };
            assert_eq!(c.joints[0].kind, expect(ends[0], JointContinuity::Start));
            assert_eq!(
                c.joints[c.segments.len()].kind,
                expect(ends[1], JointContinuity::End)
            );
            for (i, w) in c.segments.windows(2).enumerate() {
                let j = &c.joints[i + 1];
                assert_eq!(j.point, w[1].start);
                // A smooth chain turns a joint the samples bend through tighter than it may
                // (a hook) into a corner inside the piece: no curvature to compare there.
                if j.kind == JointContinuity::Corner {
                    continue;
                }
                assert_eq!(j.kind, JointContinuity::Smooth);
                assert_eq!(j.kappa, [Some(w[0].kappa1), Some(w[1].kappa0)]);
                assert_eq!(j.curvature_jump, relative_jump(w[0].kappa1, w[1].kappa0));
                jumps.push(j.curvature_jump.unwrap_or(0.0));
                let (a, b) = (
                    w[0].segment().expect("valid"),
                    w[1].segment().expect("valid"),
                );
                // Second-order one-sided differences over 1e-4 of the length over which the
                // curvature changes (the segment, or |κ/κ′| where shorter): truncation
                // ~(1e-4)² relative, rounding O(ε·κ/h), both far below the 1e-4 asked.
                for (seg, s, sign, got) in [
                    (&a, a.length(), -1.0, j.dkappa_ds[0]),
                    (&b, 0.0, 1.0, j.dkappa_ds[1]),
                ] {
                    let Some(got) = got else { continue };
                    let scale = seg.length().min((seg.kappa(s) / got).abs());
                    // At an inflection (κ = 0, α < 0) dκ/ds ∝ |κ|^(1+α) is the closed form's
                    // limit (0, constant or unbounded as α is above, at or below −1), which no
                    // difference approaches at a useful rate; nor one where the curvature changes
                    // by its whole size within a millionth of the segment (α < −1 near κ = 0: a
                    // G2 joint pressed onto the curvature's lower bound).
                    if seg.kappa(s) == 0.0 || scale < FD_MIN_SCALE * seg.length() {
                        continue;
                    }
                    let h = sign * 1e-4 * scale;
                    let k = |i: f64| seg.kappa(s + i * h);
                    let fd = (-3.0 * k(0.0) + 4.0 * k(1.0) - k(2.0)) / (2.0 * h);
                    assert!(
                        (fd - got).abs()
                            <= 1e-4
                                * got
                                    .abs()
                                    .max((seg.kappa1() - seg.kappa0()).abs() / seg.length())
                                + 1e-9 / seg.length().powi(2),
                        "{name}: dκ/ds {got} vs {fd}"
                    );
                }
            }
        }
    }
    jumps.sort_by(f64::total_cmp);
    let at = |q: f64| jumps[((jumps.len() - 1) as f64 * q) as usize];
    eprintln!(
        "curvature jump at {} smooth joints: median {:.3}, p90 {:.3}, max {:.3}",
        jumps.len(),
        at(0.5),
        at(0.9),
        at(1.0)
    );
    assert!(!jumps.is_empty());
}
