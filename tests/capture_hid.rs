//! The HID decoder against hid-tools' own decode of every report in the real Wacom Intuos Pro M
//! recordings (`fixtures/hid/oracle/`, copied whole from whot/wacom-recordings): each `E:` line there is preceded by a
//! `# ReportID: .. / Tip Switch: .. | X: .. | ...` line, parsed here independently of the library.
//! Also: stroke counts and contact-run lengths per recording, unit conversions, and the curated
//! fixture through replay into a valid `kansei-stroke` file and the fitting pipeline.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use kansei::capture::hid::PenLayout;
use kansei::capture::recorder::Recording;
use kansei::capture::replay::replay_text;
use kansei::capture::stroke_builder::Tool;
use kansei::stroke::{StrokeFile, Units};

const ORACLE_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/hid/oracle/");
const FIXTURE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/fixtures/hid/pen-three-vertical-strokes.hid"
);

/// The Intuos Pro M's pen report (SOURCE.md, and the descriptor: X 0..44800 ↔ 0..22400 × 10⁻³ cm).
const PEN_REPORT_ID: u8 = 0x10;
const MM_PER_X_UNIT: f64 = 224.0 / 44800.0;
const MM_PER_Y_UNIT: f64 = 148.0 / 29600.0;
const PRESSURE_MAX: f64 = 8191.0;
/// Conversions are one multiply and divide in f64: a few ulps of values up to ~224.
const CONVERSION_TOL: f64 = 1e-12;

/// Pen strokes (tip-down runs) each recording holds, from its name and header comment.
/// The eraser and two-horizontal files of the upstream set are listed for when they are added.
fn expected_strokes(file: &str) -> Option<(usize, Tool)> {
    Some(match file {
        "pen.battery-reporting.hid" => (0, Tool::Pen),
        "pen.pen-ccw-circle.hid"
        | "pen.pen-light-horizontal.hid"
        | "pen.pen-strong-vertical.hid" => (1, Tool::Pen),
        "pen.pen-two-horizontal-strokes.hid" => (2, Tool::Pen),
        "pen.pen-three-vertical-strokes.hid" => (3, Tool::Pen),
        "pen.eraser-ccw-circle.hid" => (1, Tool::Eraser),
        _ => return None,
    })
}

/// hid-tools' decode: report ID and `name -> value` for every named field.
struct Oracle {
    report_id: u8,
    fields: BTreeMap<String, i64>,
}

impl Oracle {
    fn get(&self, name: &str, line: usize) -> i64 {
        *self
            .fields
            .get(name)
            .unwrap_or_else(|| panic!("line {line}: oracle has no {name:?}"))
    }
}

/// `# ReportID: 16 / Tip Switch: 0 | ... | # | X:      6057 | ...`
fn parse_oracle(line: &str) -> Option<Oracle> {
    let rest = line.strip_prefix("# ReportID:")?;
    let (id, fields_text) = rest.split_once('/')?;
    let report_id = id.trim().parse().ok()?;
    let mut fields = BTreeMap::new();
    for part in fields_text.split('|') {
        if let Some((name, value)) = part.split_once(':')
            && let Ok(v) = value.trim().parse::<i64>()
        {
            fields.insert(name.trim().to_owned(), v);
        }
    }
    Some(Oracle { report_id, fields })
}

fn oracle_recordings() -> Vec<PathBuf> {
    let dir = Path::new(ORACLE_DIR);
    assert!(
        dir.is_dir(),
        "the recorded-oracle test needs the Wacom recordings at {ORACLE_DIR}; the folder is missing"
    );
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{ORACLE_DIR}: {e}"))
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "hid"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no .hid recordings in {ORACLE_DIR}");
    files
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every report of every recording decodes to exactly hid-tools' values.
#[test]
fn decoder_agrees_with_hid_tools_on_every_recorded_report() {
    for path in oracle_recordings() {
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or("?")
            .to_owned();
        let text = read(&path);
        let rec = Recording::parse(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(rec.warning_count, 0, "{name}: {:?}", rec.warnings);
        let layout =
            PenLayout::from_descriptor(&rec.descriptor).unwrap_or_else(|e| panic!("{name}: {e}"));
        let lines: Vec<&str> = text.lines().collect();
        let (mut checked_pen, mut checked_other) = (0usize, 0usize);
        for ((_, bytes), &line_no) in rec.reports.iter().zip(&rec.report_lines) {
            let oracle_line = lines[line_no - 2];
            let oracle = parse_oracle(oracle_line).unwrap_or_else(|| {
                panic!("{name}:{}: no oracle line before the report", line_no - 1)
            });
            assert_eq!(bytes[0], oracle.report_id, "{name}:{line_no}");
            let decoded = layout
                .decode(bytes)
                .unwrap_or_else(|e| panic!("{name}:{line_no}: {e}"));
            let Some(r) = decoded else {
                assert_ne!(
                    oracle.report_id, PEN_REPORT_ID,
                    "{name}:{line_no}: pen report not decoded"
                );
                checked_other += 1;
                continue;
            };
            let at = format!("{name}:{line_no}");
            assert_eq!(r.report_id, oracle.report_id, "{at}");
            assert_eq!(r.raw_x, oracle.get("X", line_no), "{at}: X");
            assert_eq!(r.raw_y, oracle.get("Y", line_no), "{at}: Y");
            assert_eq!(
                r.raw_pressure,
                Some(oracle.get("Tip Pressure", line_no)),
                "{at}: pressure"
            );
            assert_eq!(
                r.raw_tilt_x,
                Some(oracle.get("X Tilt", line_no)),
                "{at}: X tilt"
            );
            assert_eq!(
                r.raw_tilt_y,
                Some(oracle.get("Y Tilt", line_no)),
                "{at}: Y tilt"
            );
            let flag = |n: &str| oracle.get(n, line_no) != 0;
            assert_eq!(r.tip, flag("Tip Switch"), "{at}: Tip Switch");
            assert_eq!(r.in_range, flag("In Range"), "{at}: In Range");
            assert_eq!(
                r.barrel,
                [flag("Barrel Switch"), flag("Secondary Barrel Switch")],
                "{at}: barrels"
            );
            assert_eq!(r.eraser, flag("Eraser"), "{at}: Eraser");
            assert_eq!(r.invert, flag("Invert"), "{at}: Invert");
            // The physical values follow from the raw ones by the descriptor's ranges.
            assert!(
                (r.x_mm - r.raw_x as f64 * MM_PER_X_UNIT).abs() < CONVERSION_TOL,
                "{at}: x_mm {}",
                r.x_mm
            );
            assert!(
                (r.y_mm - r.raw_y as f64 * MM_PER_Y_UNIT).abs() < CONVERSION_TOL,
                "{at}: y_mm {}",
                r.y_mm
            );
            let p = r.pressure.expect("pressure");
            assert!(
                (p - r.raw_pressure.expect("raw") as f64 / PRESSURE_MAX).abs() < CONVERSION_TOL,
                "{at}"
            );
            // Tilt: logical −64..63 ↔ physical −64..63 degrees.
            assert_eq!(r.tilt_x_deg, r.raw_tilt_x.map(|v| v as f64), "{at}");
            assert_eq!(r.tilt_y_deg, r.raw_tilt_y.map(|v| v as f64), "{at}");
            checked_pen += 1;
        }
        let oracle_lines = lines
            .iter()
            .filter(|l| l.starts_with("# ReportID:"))
            .count();
        assert_eq!(
            checked_pen + checked_other,
            oracle_lines,
            "{name}: every oracle line checked"
        );
        assert_eq!(
            rec.reports.len(),
            lines.iter().filter(|l| l.starts_with("E:")).count(),
            "{name}"
        );
        eprintln!(
            "{name}: {checked_pen} pen reports and {checked_other} other reports agree with hid-tools"
        );
    }
}

/// Tip-down runs per recording, computed from the oracle lines alone.
fn oracle_contact_runs(text: &str) -> Vec<usize> {
    let mut runs = Vec::new();
    let mut current = 0usize;
    for o in text
        .lines()
        .filter_map(parse_oracle)
        .filter(|o| o.report_id == PEN_REPORT_ID)
    {
        let contact = o.fields.get("Tip Switch") == Some(&1) || o.fields.get("Eraser") == Some(&1);
        if contact {
            current += 1;
        } else if current > 0 {
            runs.push(current);
            current = 0;
        }
    }
    if current > 0 {
        runs.push(current);
    }
    runs
}

/// Each recording replays to the strokes its name announces, one per contact run, every report
/// of the run a sample, and the file validates.
#[test]
fn stroke_counts_match_each_recording() {
    for path in oracle_recordings() {
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or("?")
            .to_owned();
        let (count, tool) = expected_strokes(&name).unwrap_or_else(|| {
            panic!("{name}: new recording; add its stroke count to expected_strokes")
        });
        let text = read(&path);
        let (file, stats) = replay_text(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
        file.validate().expect("valid");
        assert_eq!(file.units, Units::Mm);
        assert_eq!(file.strokes.len(), count, "{name}: strokes");
        assert!(
            stats.tools.iter().all(|&t| t == tool),
            "{name}: tools {:?}",
            stats.tools
        );
        assert_eq!(stats.warnings(), 0, "{name}: {stats:?}");
        let runs = oracle_contact_runs(&text);
        let samples: Vec<usize> = file.strokes.iter().map(|s| s.samples.len()).collect();
        assert_eq!(
            samples, runs,
            "{name}: samples per stroke = oracle contact runs"
        );
        eprintln!(
            "{name}: {count} stroke(s), samples {samples:?}, {} pen reports",
            stats.pen_reports
        );
    }
}

/// The published contact-run lengths (SOURCE.md) and the device block.
#[test]
fn three_vertical_strokes_from_the_oracle_recording() {
    let text = read(&Path::new(ORACLE_DIR).join("pen.pen-three-vertical-strokes.hid"));
    let (file, stats) = replay_text(&text).expect("replays");
    let samples: Vec<usize> = file.strokes.iter().map(|s| s.samples.len()).collect();
    assert_eq!(samples, [118, 103, 94]);
    assert_eq!(
        (stats.reports, stats.pen_reports, stats.other_reports),
        (843, 838, 5)
    );
    let device = file.device.expect("device");
    assert_eq!(device["width_mm"], 224.0);
    assert_eq!(device["height_mm"], 148.0);
    assert_eq!(device["pressure_levels"], 8192);
    assert_eq!(device["tilt"], true);
    assert_eq!(device["vendor_id"], "056a");
    assert_eq!(device["product_id"], "0357");
    assert_eq!(device["name"], "Wacom Co.,Ltd. Wacom Intuos Pro M");
}

/// The curated fixture in the repository replays to the same three strokes, vertical, with
/// non-decreasing time, and survives a JSON round trip and the fitting pipeline (splits only).
#[test]
fn fixture_replays_to_kansei_stroke_and_fits() {
    let text = read(Path::new(FIXTURE));
    let (file, stats) = replay_text(&text).expect("replays");
    assert_eq!(file.strokes.len(), 3);
    assert_eq!(stats.tools, [Tool::Pen; 3]);
    for (i, s) in file.strokes.iter().enumerate() {
        let first = s.samples.first().expect("sample");
        let last = s.samples.last().expect("sample");
        // Vertical: far more travel in y than in x (the header sketch; y grows downwards).
        let (dx, dy) = ((last.x - first.x).abs(), (last.y - first.y).abs());
        assert!(dy > 20.0 && dy > 5.0 * dx, "stroke {i}: dx {dx} dy {dy}");
        assert!(
            s.samples
                .iter()
                .all(|p| p.pressure.is_some_and(|v| v > 0.0 && v <= 1.0))
        );
    }
    let back = StrokeFile::from_json(&file.to_json()).expect("round trip");
    assert_eq!(back.strokes, file.strokes);
    let out = kansei::pipeline::fit_file(&file, &kansei::pipeline::PipelineOptions::splits_only())
        .expect("fits");
    assert!(out.curves.len() >= 3, "{} curves", out.curves.len());
}
