//! The `kansei` binary: outputs, exit codes and error messages.

mod common;

use common::run_ok;

use std::process::Command;

fn kansei() -> Command {
    Command::new(env!("CARGO_BIN_EXE_kansei"))
}

fn fixture(name: &str) -> String {
    format!(
        "{}/fixtures/strokes/{name}.json",
        env!("CARGO_MANIFEST_DIR")
    )
}

#[test]
fn fit_writes_a_kansei_curve_document() {
    let out = run_ok(kansei().args(["fit", &fixture("google-ink-spring")]));
    let doc = kansei::export::CurveFile::from_json(&String::from_utf8_lossy(&out.stdout))
        .expect("valid document");
    assert_eq!(doc.units, kansei::stroke::Units::Px);
    assert_eq!(doc.tolerance, 0.5);
    assert!(!doc.curves.is_empty());
    for c in &doc.curves {
        // Without --tolerance each stroke is fitted to the unit's default raised to its noise
        // floor, which the curve states.
        let noise = c.noise.expect("the stroke's noise");
        let tolerance = c.tolerance.unwrap_or(doc.tolerance);
        assert_eq!(tolerance, noise.floor.max(0.5));
        assert_eq!(c.bspline.degree, 3);
        assert_eq!(c.bspline.knots.len(), c.bspline.control_points.len() + 4);
        assert!(c.bspline.max_deviation <= tolerance);
        let lac = c.lac.as_ref().expect("chain figures");
        assert!(lac.within_tolerance && lac.max_deviation <= tolerance);
        assert!(!c.segments.is_empty());
        // Every record is a valid segment whose written end and end tangent follow from its
        // parameters, and consecutive segments join G1.
        let segments: Vec<_> = c
            .segments
            .iter()
            .map(|s| s.segment().expect("valid record"))
            .collect();
        for w in segments.windows(2) {
            assert!(w[0].end().distance(w[1].start()) <= 1e-9 * w[0].length().max(w[1].length()));
        }
        for s in &c.segments {
            assert!(s.max_deviation <= tolerance);
            assert!(s.samples[0] <= s.samples[1]);
        }
    }
    // The document round-trips exactly.
    let again = kansei::export::CurveFile::from_json(&doc.to_json()).expect("reads back");
    assert_eq!(again, doc);
}

#[test]
fn alpha_can_be_fixed_or_limited_and_svg_and_dxf_written() {
    let dir = std::env::temp_dir().join(format!("kansei-cli-alpha-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let svg = dir.join("spring.svg");
    let dxf = dir.join("spring.dxf");
    let out = run_ok(
        kansei()
            .args([
                "fit",
                &fixture("perfect-freehand-waves"),
                "--alpha",
                "-1",
                "--svg-layers",
                "samples,alpha",
                "--export-accuracy",
                "0.02",
                "--svg",
            ])
            .arg(&svg)
            .arg("--dxf")
            .arg(&dxf),
    );
    let doc =
        kansei::export::CurveFile::from_json(&String::from_utf8_lossy(&out.stdout)).expect("valid");
    // The joints stay by the samples: within the samples' bounding box grown by its diagonal (a
    // refinement step once sent one 1.8e12 away through loops that each met one sample).
    let file = kansei::stroke::StrokeFile::from_json(
        &std::fs::read_to_string(fixture("perfect-freehand-waves")).expect("fixture"),
    )
    .expect("valid");
    let samples = file.strokes.iter().flat_map(|s| &s.samples);
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in samples {
        (lo[0], lo[1]) = (lo[0].min(p.x), lo[1].min(p.y));
        (hi[0], hi[1]) = (hi[0].max(p.x), hi[1].max(p.y));
    }
    let margin = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    for s in doc.curves.iter().flat_map(|c| &c.segments) {
        // Clothoids only (null α: a circular arc or line, which any α reproduces).
        assert!(s.alpha.is_none_or(|a| a == -1.0), "alpha {:?}", s.alpha);
        for [x, y] in [s.start, s.end] {
            assert!(
                x >= lo[0] - margin
                    && x <= hi[0] + margin
                    && y >= lo[1] - margin
                    && y <= hi[1] + margin,
                "a joint at ({x}, {y}) far from the samples"
            );
        }
    }
    let text = std::fs::read_to_string(&svg).expect("svg written");
    assert!(text.starts_with("<?xml") || text.starts_with("<svg"));
    assert!(text.contains("id=\"curves\""));
    assert!(text.contains("id=\"samples\"") && text.contains("id=\"alpha\""));
    assert!(!text.contains("id=\"bspline\""));
    assert!(text.contains("accuracy=\"0.02\""));
    let drawing = dxf::Drawing::load_file(&dxf).expect("dxf written");
    assert_eq!(drawing.entities().count(), doc.curves.len());
    // A bad accuracy is refused.
    let out = kansei()
        .args([
            "fit",
            &fixture("perfect-freehand-waves"),
            "--export-accuracy",
            "-1",
        ])
        .output()
        .expect("runs");
    assert!(!out.status.success());
    let out = kansei()
        .args([
            "fit",
            &fixture("perfect-freehand-waves"),
            "--alpha-range=-0.5:0.5",
        ])
        .output()
        .expect("runs");
    assert!(out.status.success());
    let doc =
        kansei::export::CurveFile::from_json(&String::from_utf8_lossy(&out.stdout)).expect("valid");
    for s in doc.curves.iter().flat_map(|c| &c.segments) {
        assert!(
            s.alpha.is_none_or(|a| (-0.5..=0.5).contains(&a)),
            "alpha {:?}",
            s.alpha
        );
    }
    for bad in ["--alpha-range=1:x", "--alpha-range=2:1", "--alpha=nan"] {
        let out = kansei()
            .args(["fit", &fixture("perfect-freehand-waves"), bad])
            .output()
            .expect("runs");
        assert!(!out.status.success(), "{bad} accepted");
        assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn an_export_that_misses_its_accuracy_says_so_and_states_what_holds() {
    // A hook segment asked for 1e-9 px: beyond the exporter's work bound per segment (the hook
    // exports to about 1e-7 px within it), so the SVG is written with the error it has, the CLI
    // warns, and the file's comment states a bound that holds (the larger of the accuracy and
    // the measured error).
    let dir = std::env::temp_dir().join(format!("kansei-cli-accuracy-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let svg = dir.join("hey.svg");
    let out = run_ok(kansei().args([
        "fit",
        &fixture("perfect-freehand-hey"),
        "--export-accuracy",
        "1e-9",
        "--json",
        dir.join("hey.json").to_str().expect("utf-8"),
        "--svg",
        svg.to_str().expect("utf-8"),
    ]));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("exceeds the accuracy 1.0000e-9"),
        "{stderr}"
    );
    let text = std::fs::read_to_string(&svg).expect("the SVG is written");
    let number = |after: &str, until: char| -> f64 {
        let start = text.find(after).expect(after) + after.len();
        text[start..]
            .split(until)
            .next()
            .expect("a number")
            .parse()
            .expect("a number")
    };
    let error = number("error=\"", '"');
    assert!(error > 1e-9, "{error}");
    assert_eq!(number("spirals are cubic Beziers within ", ' '), error);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn fit_writes_one_file_per_input_into_a_directory() {
    let dir = std::env::temp_dir().join(format!("kansei-cli-{}", std::process::id()));
    run_ok(
        kansei()
            .args([
                "fit",
                &fixture("perfect-freehand-waves"),
                &fixture("google-ink-straight-line"),
                "--tolerance",
                "1.5",
                "--json",
            ])
            .arg(&dir),
    );
    for stem in ["perfect-freehand-waves", "google-ink-straight-line"] {
        let text =
            std::fs::read_to_string(dir.join(format!("{stem}.curve.json"))).expect("written");
        let doc = kansei::export::CurveFile::from_json(&text).expect("valid");
        assert_eq!(doc.tolerance, 1.5);
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// An output that would replace an input, or another output, is refused before anything is
/// written (exit 2): the input stays byte for byte, and no other output appears.
#[test]
fn no_output_replaces_an_input_or_another_output() {
    let dir = std::env::temp_dir().join(format!("kansei-cli-clobber-{}", std::process::id()));
    let (a, b) = (dir.join("a"), dir.join("b"));
    std::fs::create_dir_all(&a).expect("dir a");
    std::fs::create_dir_all(&b).expect("dir b");
    let original = std::fs::read(fixture("perfect-freehand-waves")).expect("fixture");
    let input = a.join("x.json");
    std::fs::write(&input, &original).expect("copied");
    std::fs::copy(fixture("google-ink-straight-line"), b.join("x.json")).expect("copied");
    // The input as its own output, by the same path and by another spelling of it.
    for output in [input.clone(), a.join(".").join("x.json")] {
        let run = kansei()
            .args(["fit"])
            .arg(&input)
            .arg("--svg")
            .arg(dir.join("x.svg"))
            .arg("--json")
            .arg(&output)
            .output()
            .expect("runs");
        assert_eq!(run.status.code(), Some(2), "{run:?}");
        assert!(String::from_utf8_lossy(&run.stderr).contains("would replace the input"));
        assert_eq!(std::fs::read(&input).expect("still there"), original);
        assert!(!dir.join("x.svg").exists(), "nothing written");
    }
    // Two inputs named alike into one directory.
    let out = dir.join("out");
    let run = kansei()
        .args(["fit"])
        .arg(&input)
        .arg(b.join("x.json"))
        .arg("--json")
        .arg(&out)
        .output()
        .expect("runs");
    assert_eq!(run.status.code(), Some(2), "{run:?}");
    assert!(String::from_utf8_lossy(&run.stderr).contains("would both be written"));
    assert!(!out.exists(), "nothing written, not even the directory");
    // Two formats to one path.
    let run = kansei()
        .args(["fit"])
        .arg(&input)
        .arg("--json")
        .arg(dir.join("same"))
        .arg("--svg")
        .arg(dir.join("same"))
        .output()
        .expect("runs");
    assert_eq!(run.status.code(), Some(2), "{run:?}");
    assert!(!dir.join("same").exists());
    let _ = std::fs::remove_dir_all(dir);
}

/// An input that cannot be read is named once on stderr (not once as it is met and again at
/// exit), the run exits 1 saying how many, and the readable input is still fitted.
#[test]
fn an_unreadable_input_is_named_once_and_costs_no_other() {
    let missing = "kansei-no-such-input.json";
    let run = kansei()
        .args(["fit", missing, &fixture("perfect-freehand-waves")])
        .output()
        .expect("runs");
    assert_eq!(run.status.code(), Some(1), "{run:?}");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(stderr.matches(missing).count(), 1, "{stderr}");
    assert!(
        stderr.contains("1 of 2 inputs could not be read"),
        "{stderr}"
    );
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert_eq!(
        stdout.lines().count(),
        1,
        "one document for the readable input"
    );
}

/// One input with an output naming a directory that exists: the directory receives
/// `<stem>.curve.json` (and `<stem>.svg`), as with several inputs.
#[test]
fn one_input_into_an_existing_directory_writes_there() {
    let dir = std::env::temp_dir().join(format!("kansei-cli-onedir-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    run_ok(
        kansei()
            .args(["fit", &fixture("perfect-freehand-waves"), "--json"])
            .arg(&dir)
            .arg("--svg")
            .arg(&dir),
    );
    let text = std::fs::read_to_string(dir.join("perfect-freehand-waves.curve.json"))
        .expect("written into the directory");
    kansei::export::CurveFile::from_json(&text).expect("valid");
    assert!(dir.join("perfect-freehand-waves.svg").exists());
    let _ = std::fs::remove_dir_all(dir);
}

/// A PNG size the render cannot draw is a bad option value: exit 2, as the README says, and no
/// file is written.
#[test]
fn a_png_size_out_of_range_is_a_usage_error() {
    for size in ["0x10", "10x0", "20000x10", "10000x10000"] {
        let png = std::env::temp_dir().join(format!("kansei-cli-size-{}.png", std::process::id()));
        let run = kansei()
            .args([
                "fit",
                &fixture("perfect-freehand-waves"),
                "--size",
                size,
                "--png",
            ])
            .arg(&png)
            .output()
            .expect("runs");
        assert_eq!(run.status.code(), Some(2), "{size}: {run:?}");
        assert!(!png.exists(), "{size}: nothing written");
    }
}

#[test]
fn exit_codes_say_what_happened_and_one_bad_stroke_costs_no_other() {
    use kansei::cli::{EXIT_FILE, EXIT_STROKES_FAILED, EXIT_USAGE};
    let dir = std::env::temp_dir().join(format!("kansei-cli-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("tmp");
    // A line, a tap (the dot of an "i"), a stroke whose time runs backwards, another line.
    let line = |y: i32| {
        (0..12)
            .map(|i| format!(r#"{{"x": {}, "y": {y}}}"#, 3 * i))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mixed = dir.join("mixed.json");
    let text = format!(
        r#"{{"format": "kansei-stroke", "version": 1, "units": "px", "strokes": [
            {{"samples": [{}]}},
            {{"samples": [{{"x": 5, "y": 9}}, {{"x": 5, "y": 9}}]}},
            {{"samples": [{{"x": 0, "y": 0, "t": 2}}, {{"x": 1, "y": 1, "t": 1}}]}},
            {{"samples": [{}]}}]}}"#,
        line(0),
        line(20)
    );
    std::fs::write(&mixed, text).expect("write");
    let json = dir.join("mixed.curve.json");
    let out = kansei()
        .arg("fit")
        .arg(&mixed)
        .arg("--json")
        .arg(&json)
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(i32::from(EXIT_STROKES_FAILED)));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("mixed.json: stroke 2, sample 1: time goes backwards"),
        "{err}"
    );
    assert!(err.contains("1 of 4 strokes could not be fitted"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    let doc =
        kansei::export::CurveFile::from_json(&std::fs::read_to_string(&json).expect("written"))
            .expect("valid");
    let mut fitted: Vec<usize> = doc.curves.iter().map(|c| c.stroke).collect();
    fitted.dedup();
    assert_eq!(fitted, [0, 3]);
    assert_eq!(doc.dots.len(), 1);
    assert_eq!((doc.dots[0].stroke, doc.dots[0].point), (1, [5.0, 9.0]));
    assert_eq!(doc.errors.len(), 1);
    assert_eq!(doc.errors[0].stroke, 2);
    assert_eq!(doc.errors[0].kind, kansei::pipeline::FailureKind::Input);
    // The document with dots and errors is valid against the published schema.
    let schema: serde_json::Value =
        serde_json::from_str(kansei::export::CURVE_SCHEMA_V1).expect("schema parses");
    let instance: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("written")).expect("json");
    let validator = jsonschema::validator_for(&schema).expect("schema compiles");
    let problems: Vec<String> = validator
        .iter_errors(&instance)
        .map(|e| format!("{e} at {}", e.instance_path()))
        .collect();
    assert!(problems.is_empty(), "{problems:?}");

    // A file that cannot be read at all: 1, naming it.
    let missing = dir.join("missing.json");
    let out = kansei().arg("fit").arg(&missing).output().expect("runs");
    assert_eq!(out.status.code(), Some(i32::from(EXIT_FILE)));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("missing.json"), "{err}");
    // An option value kansei refuses: 2, as clap's own usage errors.
    let out = kansei()
        .args(["fit", &fixture("google-ink-spring"), "--tolerance=-1"])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(i32::from(EXIT_USAGE)));
    let out = kansei()
        .args(["fit", &fixture("google-ink-spring"), "--no-such-option"])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(i32::from(EXIT_USAGE)));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_recording_replays_and_fits_end_to_end() {
    let recording = format!(
        "{}/fixtures/hid/pen-three-vertical-strokes.hid",
        env!("CARGO_MANIFEST_DIR")
    );
    let dir = std::env::temp_dir().join(format!("kansei-cli-replay-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let strokes = dir.join("strokes.json");
    run_ok(kansei().args(["replay", &recording, "--out"]).arg(&strokes));
    let file =
        kansei::stroke::StrokeFile::from_json(&std::fs::read_to_string(&strokes).expect("written"))
            .expect("valid");
    assert_eq!(file.units, kansei::stroke::Units::Mm);
    assert_eq!(file.strokes.len(), 3, "the recording holds three strokes");
    // The replayed file and the recording itself fit the same.
    let a = kansei().arg("fit").arg(&strokes).output().expect("runs");
    let b = kansei().args(["fit", &recording]).output().expect("runs");
    assert!(a.status.success() && b.status.success());
    let (a, b) = (
        String::from_utf8_lossy(&a.stdout),
        String::from_utf8_lossy(&b.stdout),
    );
    let a = kansei::export::CurveFile::from_json(&a).expect("valid");
    let b = kansei::export::CurveFile::from_json(&b).expect("valid");
    assert_eq!(a, b);
    assert!(
        a.curves
            .iter()
            .all(|c| c.lac.as_ref().is_some_and(|l| l.within_tolerance))
    );
    // A damaged recording: a clear error naming the file, no panic.
    let bad = dir.join("bad.hid");
    std::fs::write(&bad, "N: nothing\nE: 0.1 3 01 02\n").expect("write");
    let out = kansei().arg("fit").arg(&bad).output().expect("runs");
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.hid") && !err.contains("panicked"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn inkml_and_evemu_recordings_fit_directly() {
    for (name, units) in [
        ("inkml/reference.inkml", "mm"),
        ("evemu/pen-two-strokes.evemu", "mm"),
    ] {
        let path = format!("{}/fixtures/{name}", env!("CARGO_MANIFEST_DIR"));
        let out = kansei().args(["fit", &path]).output().expect("runs");
        assert!(
            out.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let doc = kansei::export::CurveFile::from_json(&String::from_utf8_lossy(&out.stdout))
            .expect("valid");
        assert_eq!(doc.units.name(), units);
        assert!(!doc.curves.is_empty(), "{name}");
        assert!(doc.curves.iter().all(|c| !c.segments.is_empty()), "{name}");
    }
}

/// A damaged evemu recording replays (exit 0) and stderr names each kind of skip with its count
/// and first line numbers; the eraser stroke is marked in the output's `device.eraser_strokes`.
/// A hid-recorder file's garbage lines and out-of-range reports are named by line too.
#[test]
fn replay_warnings_name_counts_and_lines() {
    let root = env!("CARGO_MANIFEST_DIR");
    let dir = std::env::temp_dir().join(format!("kansei-cli-warnings-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let text = std::fs::read_to_string(format!("{root}/fixtures/evemu/pen-two-strokes.evemu"))
        .expect("fixture");
    // After the header: a garbage line, a huge ABS_X in its own frame and a SYN_DROPPED.
    let at = text.find("\nE: ").expect("events") + 1;
    let header_lines = text[..at].lines().count();
    let damage = "hello\n\
                  E: 0.000000 0003 0000 2147483647\n\
                  E: 0.000000 0000 0000 0000\n\
                  E: 0.000000 0000 0003 0000\n\
                  E: 0.000000 0000 0000 0000\n";
    let evemu = dir.join("damaged.evemu");
    std::fs::write(&evemu, format!("{}{damage}{}", &text[..at], &text[at..])).expect("write");
    let out_json = dir.join("damaged.json");
    let out = kansei()
        .args(["replay"])
        .arg(&evemu)
        .arg("--out")
        .arg(&out_json)
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    for expected in [
        "1 lines that do not parse skipped".to_owned(),
        format!("line {}: line does not parse", header_lines + 1),
        "1 values out of their axis range skipped".to_owned(),
        format!("line {}: ABS_X = 2147483647", header_lines + 2),
        "1 frames dropped (SYN_DROPPED) skipped".to_owned(),
        format!("line {}: SYN_DROPPED", header_lines + 4),
        "1 eraser strokes".to_owned(),
    ] {
        assert!(err.contains(&expected), "{expected:?} not in {err}");
    }
    let file = kansei::stroke::StrokeFile::from_json(
        &std::fs::read_to_string(&out_json).expect("written"),
    )
    .expect("valid");
    assert_eq!(file.strokes.len(), 2);
    assert_eq!(
        file.device.expect("present")["eraser_strokes"],
        serde_json::json!([1])
    );

    let hid_text = std::fs::read_to_string(format!(
        "{root}/fixtures/hid/pen-three-vertical-strokes.hid"
    ))
    .expect("fixture");
    let hid_text = hid_text.replacen(
        "I: 3 056a 0357\n",
        "I: 3 056a 0357\nnonsense\nE: 0.0 27 10 61 ff ff ff f0 2c 00 ea 14 24 00 00 00 00 00 00 06 9c 36 80 23 02 08 11 00 02\n",
        1,
    );
    let garbage_line = hid_text.lines().position(|l| l == "nonsense").expect("in") + 1;
    let hid = dir.join("damaged.hid");
    std::fs::write(&hid, hid_text).expect("write");
    let out = kansei()
        .args(["replay"])
        .arg(&hid)
        .arg("--out")
        .arg(dir.join("hid.json"))
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("2 reports or lines skipped"), "{err}");
    assert!(err.contains(&format!("line {garbage_line}: ")), "{err}");
    assert!(
        err.contains(&format!("line {}: report 0x10, field X", garbage_line + 1))
            && err.contains("16777215"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// Numeric options take negative numbers as values, so that kansei's own checks answer (not
/// clap's advice to write `-- -1`), and `--alpha -1` and `--alpha-range -3:-1` work.
#[test]
fn negative_numbers_reach_kanseis_own_checks() {
    let waves = fixture("perfect-freehand-waves");
    for (args, expected) in [
        (
            vec!["fit", &waves, "--tolerance", "-1"],
            "--tolerance must be a positive number, got -1",
        ),
        (
            vec!["fit", &waves, "--export-accuracy", "-0.5"],
            "--export-accuracy must be a positive number, got -0.5",
        ),
        (
            vec!["bench", &waves, "--tolerance", "-1"],
            "--tolerance must be a positive number, got -1",
        ),
        (
            vec!["fit", &waves, "--corner-angle", "-5"],
            "the corner angle is in degrees from 0 to 180, got -5",
        ),
    ] {
        let out = kansei().args(&args).output().expect("runs");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?}");
        assert!(err.contains(expected), "{args:?}: {err}");
        assert!(!err.contains("use '--"), "{args:?}: {err}");
    }
    for args in [
        vec!["fit", &waves, "--alpha", "-1"],
        vec!["fit", &waves, "--alpha-range", "-3:-1"],
        vec!["fit", &waves, "--corner-angle", "100", "--tolerance", "0.8"],
    ] {
        let out = run_ok(kansei().args(&args));
        let doc = kansei::export::CurveFile::from_json(&String::from_utf8_lossy(&out.stdout))
            .expect("valid");
        assert!(!doc.curves.is_empty(), "{args:?}");
    }
}

/// An output in a directory that does not exist is an error naming the directory, and nothing
/// is written: not that output, not the others, no directory.
#[test]
fn an_output_in_a_missing_directory_fails_naming_it_and_writes_nothing() {
    let dir = std::env::temp_dir().join(format!("kansei-cli-nodir-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let waves = fixture("perfect-freehand-waves");
    assert!(!std::path::Path::new("/no-such-dir").exists());
    let out = kansei()
        .args(["fit", &waves, "--svg", "/no-such-dir/x.svg"])
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("/no-such-dir") && err.contains("does not exist"),
        "{err}"
    );
    assert!(!std::path::Path::new("/no-such-dir").exists());
    // The JSON's directory exists, the PNG's does not: neither is written.
    let json = dir.join("waves.curve.json");
    let png = dir.join("missing").join("waves.png");
    let out = kansei()
        .args(["fit", &waves, "--json"])
        .arg(&json)
        .arg("--png")
        .arg(&png)
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains(&dir.join("missing").display().to_string()),
        "{err}"
    );
    // Several inputs: the output directory is made, but only under a parent that exists.
    let out = kansei()
        .args(["fit", &waves, &fixture("google-ink-spring"), "--json"])
        .arg(dir.join("a").join("b"))
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("does not exist"), "{err}");
    let names: Vec<_> = std::fs::read_dir(&dir)
        .expect("dir")
        .filter_map(Result::ok)
        .map(|e| e.file_name())
        .collect();
    assert!(names.is_empty(), "{names:?}");
    // `kansei replay --out` and `kansei capture --out` follow the same rule.
    let out = kansei()
        .args(["replay", &waves, "--out"])
        .arg(dir.join("missing").join("x.json"))
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("does not exist"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Outputs go through a temporary file of their own: a file named like the old `OUT.tmp` is
/// the user's and stays, and no temporary file is left.
#[test]
fn an_output_never_touches_a_file_named_like_its_temporary() {
    let dir = std::env::temp_dir().join(format!("kansei-cli-tmp-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let json = dir.join("out.json");
    let tmp = dir.join("out.json.tmp");
    std::fs::write(&tmp, "mine").expect("write");
    for _ in 0..2 {
        run_ok(
            kansei()
                .args(["fit", &fixture("perfect-freehand-waves"), "--json"])
                .arg(&json),
        );
    }
    assert_eq!(std::fs::read_to_string(&tmp).expect("read"), "mine");
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .expect("dir")
        .filter_map(Result::ok)
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["out.json", "out.json.tmp"]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Old evemu recordings: a header-less `.events` file reads with its sibling `.desc` exactly as
/// the combined recording does; without the `.desc` the error names the file it looked for.
#[test]
fn a_headerless_evemu_events_file_reads_with_its_sibling_description() {
    let root = format!("{}/fixtures/evemu", env!("CARGO_MANIFEST_DIR"));
    let combined = run_ok(kansei().args(["fit", &format!("{root}/pen-two-strokes.evemu")]));
    let split = run_ok(kansei().args(["fit", &format!("{root}/pen-two-strokes.events")]));
    assert_eq!(
        String::from_utf8_lossy(&split.stdout),
        String::from_utf8_lossy(&combined.stdout)
    );
    let dir = std::env::temp_dir().join(format!("kansei-cli-evemu-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    // The collection's naming: NAME.DESC.events with NAME.desc.
    let events = dir.join("Pen.two-strokes.events");
    std::fs::copy(format!("{root}/pen-two-strokes.events"), &events).expect("copy");
    let out = kansei().arg("fit").arg(&events).output().expect("runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains(&dir.join("Pen.desc").display().to_string())
            && err.contains("does not exist")
            && !err.contains("panicked"),
        "{err}"
    );
    std::fs::copy(format!("{root}/pen-two-strokes.desc"), dir.join("Pen.desc")).expect("copy");
    let out = run_ok(kansei().arg("fit").arg(&events));
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&combined.stdout)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A batch is fitted on every core, and what it writes does not depend on how many: one file per
/// line in input order, the same bytes with one thread and with four.
#[test]
fn a_parallel_batch_writes_what_one_thread_writes_in_input_order() {
    let inputs: Vec<String> = [
        "perfect-freehand-waves",
        "google-ink-spring",
        "libmypaint-painting30sec",
        "wacom-intuos-pro-ccw-circle",
    ]
    .iter()
    .map(|n| fixture(n))
    .collect();
    let run = |jobs: &str| {
        let out = kansei()
            .arg("fit")
            .args(&inputs)
            .args(["--jobs", jobs])
            .output()
            .expect("runs");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        out.stdout
    };
    let one = run("1");
    assert_eq!(one, run("4"));
    let lines: Vec<&[u8]> = one
        .split(|&b| b == b'\n')
        .filter(|l| !l.is_empty())
        .collect();
    assert_eq!(lines.len(), inputs.len());
    let strokes: Vec<usize> = lines
        .iter()
        .map(|l| {
            let doc =
                kansei::export::CurveFile::from_json(&String::from_utf8_lossy(l)).expect("doc");
            doc.curves.iter().map(|c| c.stroke).max().unwrap_or(0) + 1
        })
        .collect();
    assert_eq!(
        strokes,
        [1, 1, 30, 1],
        "each line is its input's document, in order"
    );
    let out = kansei()
        .arg("fit")
        .arg(&inputs[0])
        .args(["--jobs", "0"])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn a_tolerance_below_the_noise_floor_is_honoured_with_a_warning() {
    // perfect-freehand-waves is a sparse mouse stroke whose samples sit well over 0.5 px from
    // any smooth curve: its floor is higher.
    let given = run_ok(kansei().args([
        "fit",
        &fixture("perfect-freehand-waves"),
        "--tolerance",
        "0.5",
    ]));
    let stderr = String::from_utf8_lossy(&given.stderr);
    assert!(stderr.contains("below the noise floor"), "{stderr}");
    let doc = kansei::export::CurveFile::from_json(&String::from_utf8_lossy(&given.stdout))
        .expect("valid document");
    for c in &doc.curves {
        // Honoured: fitted to 0.5, its floor stated above it.
        assert_eq!(c.tolerance, None);
        assert!(c.noise.expect("noise").floor > 0.5);
        assert!(c.lac.as_ref().expect("chain").max_deviation <= 0.5);
    }
    let default = run_ok(kansei().args(["fit", &fixture("perfect-freehand-waves")]));
    assert!(!String::from_utf8_lossy(&default.stderr).contains("noise floor"));
    let doc = kansei::export::CurveFile::from_json(&String::from_utf8_lossy(&default.stdout))
        .expect("valid document");
    for c in &doc.curves {
        let floor = c.noise.expect("noise").floor;
        assert_eq!(c.tolerance, Some(floor));
        assert!(c.lac.as_ref().expect("chain").max_deviation <= floor);
    }
}
