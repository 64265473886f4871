//! The HID decoder and the hid-recorder reader on bad input: truncated and unknown reports,
//! descriptors cut mid-item or mutated at random, garbage lines and huge values. Each gives a
//! typed error naming the byte or line, or is skipped and counted; nothing panics. Also a
//! hand-built descriptor exercising what the Wacom recordings do not: no report IDs, inches,
//! tilt in radians, an eraser without Tip Switch, and contact by pressure alone.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use kansei::capture::hid::{HidError, PenLayout};
use kansei::capture::recorder::{RecorderError, Recording};
use kansei::capture::replay::{CaptureError, recording_to_strokes, replay_text};
use kansei::capture::stroke_builder::Tool;

const FIXTURE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/fixtures/hid/pen-three-vertical-strokes.hid"
);

/// A mid-stroke pen report of the fixture (SOURCE.md excerpt): report ID 0x10, 27 bytes.
const PEN_REPORT: [u8; 27] = [
    0x10, 0x61, 0xe6, 0x12, 0x00, 0xf0, 0x2c, 0x00, 0xea, 0x14, 0x24, 0x00, 0x00, 0x00, 0x00, 0x00,
    0x00, 0x06, 0x9c, 0x36, 0x80, 0x23, 0x02, 0x08, 0x11, 0x00, 0x02,
];
/// The last byte a pen field of the Intuos report occupies: Y Tilt, byte 11.
const LAST_PEN_FIELD_BYTE: usize = 11;

fn fixture() -> Recording {
    let text = std::fs::read_to_string(Path::new(FIXTURE)).expect("fixture");
    Recording::parse(&text).expect("parses")
}

fn wacom_layout() -> PenLayout {
    PenLayout::from_descriptor(&fixture().descriptor).expect("layout")
}

#[test]
fn the_excerpt_report_decodes() {
    let r = wacom_layout()
        .decode(&PEN_REPORT)
        .expect("ok")
        .expect("pen");
    assert_eq!(
        (r.raw_x, r.raw_y, r.raw_pressure),
        (4838, 11504, Some(5354))
    );
    assert!(r.tip && r.in_range && r.contact && !r.is_eraser());
    assert_eq!(r.tilt_x_deg, Some(36.0));
}

#[test]
fn truncated_reports_name_the_field_and_byte() {
    let layout = wacom_layout();
    for len in 1..=LAST_PEN_FIELD_BYTE {
        match layout.decode(&PEN_REPORT[..len]) {
            Err(HidError::ReportTruncated {
                report_id: 0x10,
                needed_byte,
                len: l,
                field,
            }) => {
                assert_eq!(l, len);
                assert!(
                    needed_byte >= len,
                    "{field} needs byte {needed_byte} of {len}"
                );
                let msg = layout
                    .decode(&PEN_REPORT[..len])
                    .expect_err("an error")
                    .to_string();
                assert!(msg.contains("truncated") && msg.contains(field), "{msg}");
            }
            other => panic!("{len} bytes: {other:?}"),
        }
    }
    // Bytes past the last pen field (twist, serial, ...) are not needed.
    for len in LAST_PEN_FIELD_BYTE + 1..=PEN_REPORT.len() {
        assert!(
            layout.decode(&PEN_REPORT[..len]).expect("ok").is_some(),
            "{len}"
        );
    }
    assert_eq!(layout.decode(&[]), Err(HidError::EmptyReport));
}

#[test]
fn unknown_report_ids_are_errors_and_declared_non_pen_reports_are_none() {
    let layout = wacom_layout();
    let mut report = PEN_REPORT;
    report[0] = 0x42;
    let err = layout.decode(&report).expect_err("an error");
    assert_eq!(err, HidError::UnknownReportId { report_id: 0x42 });
    assert!(err.to_string().contains("byte 0"), "{err}");
    // 0x13 is the battery report: declared, not a pen report.
    let battery = [0x13, 0x64, 0x80, 0, 0, 0, 0, 0, 0];
    assert_eq!(layout.decode(&battery), Ok(None));
}

/// The Intuos pen fields' logical ranges (its descriptor): X 0..=44800 (24 bits at byte 2),
/// Tip Pressure 0..=8191 (16 bits at byte 8), X Tilt -64..=63 (8 bits at byte 10).
const X_MAX: i64 = 44800;
const PRESSURE_MAX: i64 = 8191;
const TILT_MAX: i64 = 63;

#[test]
fn values_outside_the_logical_range_are_refused_naming_field_and_value() {
    let layout = wacom_layout();
    // (bytes to overwrite at, with, field, value read, byte, min, max)
    type Case = (usize, &'static [u8], &'static str, i64, usize, i64, i64);
    let cases: [Case; 4] = [
        (2, &[0xff, 0xff, 0xff], "X", 0xFF_FFFF, 2, 0, X_MAX),
        (2, &[0x01, 0xaf, 0x00], "X", X_MAX + 1, 2, 0, X_MAX),
        (8, &[0xff, 0xff], "Tip Pressure", 0xFFFF, 8, 0, PRESSURE_MAX),
        (10, &[0x7f], "X Tilt", 127, 10, -64, TILT_MAX),
    ];
    for (at, bytes, field, value, byte, min, max) in cases {
        let mut report = PEN_REPORT;
        report[at..at + bytes.len()].copy_from_slice(bytes);
        let err = layout.decode(&report).expect_err("refused");
        assert_eq!(
            err,
            HidError::OutOfRange {
                report_id: 0x10,
                field,
                byte,
                value,
                min,
                max
            }
        );
        let msg = err.to_string();
        assert!(
            msg.contains(field) && msg.contains(&value.to_string()),
            "{msg}"
        );
    }
    // The range's ends themselves decode.
    let mut report = PEN_REPORT;
    report[2..5].copy_from_slice(&[0x00, 0xaf, 0x00]);
    let r = layout.decode(&report).expect("ok").expect("pen");
    assert_eq!(r.raw_x, X_MAX);
}

#[test]
fn out_of_range_reports_in_a_recording_are_skipped_and_counted_with_line_numbers() {
    // The excerpt report with X = 0xFFFFFF, which once replayed as x = 83 886 mm.
    let huge_x = "E: 0.0 27 10 61 ff ff ff f0 2c 00 ea 14 24 00 00 00 00 00 00 06 9c 36 80 23 02 08 11 00 02\n";
    let text = fixture_with(huge_x);
    let line = text
        .lines()
        .position(|l| l == huge_x.trim_end())
        .expect("inserted")
        + 1;
    let (file, stats) = replay_text(&text).expect("replays");
    assert_eq!(file.strokes.len(), 3);
    assert_eq!(stats.decode_errors, 1);
    assert_eq!(
        stats.first_decode_errors,
        [(
            line,
            HidError::OutOfRange {
                report_id: 0x10,
                field: "X",
                byte: 2,
                value: 0xFF_FFFF,
                min: 0,
                max: X_MAX
            }
        )]
    );
    let widest = file
        .strokes
        .iter()
        .flat_map(|s| &s.samples)
        .map(|s| s.x)
        .fold(0.0, f64::max);
    assert!(widest <= 224.0, "{widest}");
}

#[test]
fn descriptor_cut_mid_item_names_the_item_offset() {
    let descriptor = fixture().descriptor;
    // Byte 102 is `0x47, 0x80, 0x57, 0x00, 0x00` (Physical Maximum 22400): keep 2 of its 4
    // data bytes.
    assert_eq!(descriptor[102], 0x47);
    let err = PenLayout::from_descriptor(&descriptor[..105]).expect_err("an error");
    assert_eq!(
        err,
        HidError::DescriptorTruncated {
            offset: 102,
            needed: 4,
            available: 2
        }
    );
    assert!(err.to_string().contains("byte 102"), "{err}");
}

#[test]
fn every_truncation_of_the_descriptor_is_an_error_or_a_layout_never_a_panic() {
    let descriptor = fixture().descriptor;
    let mut layouts = 0;
    for len in 0..descriptor.len() {
        let result = catch_unwind(|| PenLayout::from_descriptor(&descriptor[..len]));
        match result {
            Ok(Ok(_)) => layouts += 1,
            Ok(Err(_)) => {}
            Err(_) => panic!("panic on the descriptor cut to {len} bytes"),
        }
    }
    // Cut after the pen report's collection, the pen is found; cut before X, it is not.
    assert!(layouts > 0 && layouts < descriptor.len());
    assert_eq!(
        PenLayout::from_descriptor(&descriptor[..93]),
        Err(HidError::NoPenReport)
    );
}

/// A small deterministic generator (64-bit LCG, Knuth's MMIX constants).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 33
    }
}

/// Random byte mutations of the real descriptor, and of a report decoded with each layout that
/// survives: errors are fine, panics are not.
#[test]
fn mutated_descriptors_and_reports_never_panic() {
    let descriptor = fixture().descriptor;
    let mut rng = Lcg(0x6b61_6e73_6569);
    let (mut ok, mut err) = (0usize, 0usize);
    for round in 0..4000 {
        let mut d = descriptor.clone();
        for _ in 0..1 + rng.next() % 4 {
            let i = (rng.next() as usize) % d.len();
            d[i] = rng.next() as u8;
        }
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            let layout = PenLayout::from_descriptor(&d)?;
            let mut report = PEN_REPORT.to_vec();
            let j = (rng.next() as usize) % report.len();
            report[j] = rng.next() as u8;
            layout.decode(&report).map(|_| ())
        }));
        match outcome {
            Ok(Ok(())) => ok += 1,
            Ok(Err(_)) => err += 1,
            Err(_) => panic!("panic in round {round} on descriptor {d:02x?}"),
        }
    }
    assert!(ok > 0 && err > 0, "ok {ok}, err {err}");
}

#[test]
fn hostile_descriptors_are_refused_with_offsets() {
    // Usage before any Usage Page, then an Input: hidreport would panic; refused at the Input.
    let d = [0x09, 0x30, 0x75, 0x08, 0x95, 0x01, 0x81, 0x02];
    assert!(matches!(
        PenLayout::from_descriptor(&d),
        Err(HidError::DescriptorInvalid { offset: 6, .. })
    ));
    // A Report Count of 2^32 - 1.
    let d = [0x05, 0x0d, 0x97, 0xff, 0xff, 0xff, 0xff];
    let err = PenLayout::from_descriptor(&d).expect_err("an error");
    assert!(
        matches!(err, HidError::DescriptorInvalid { offset: 2, .. }),
        "{err}"
    );
    // A Usage Minimum..Maximum spanning four billion usages.
    let d = [
        0x1b, 0, 0, 0, 0, 0x2b, 0xff, 0xff, 0xff, 0xff, 0x75, 1, 0x95, 1, 0x81, 0x02,
    ];
    assert!(matches!(
        PenLayout::from_descriptor(&d),
        Err(HidError::DescriptorInvalid { offset: 14, .. })
    ));
    // Pop without Push; a long item cut short; empty; too long.
    assert!(matches!(
        PenLayout::from_descriptor(&[0xb4]),
        Err(HidError::DescriptorInvalid { offset: 0, .. })
    ));
    assert!(matches!(
        PenLayout::from_descriptor(&[0x05, 0x0d, 0xfe, 0x10, 0x01, 0x00]),
        Err(HidError::DescriptorTruncated { offset: 2, .. })
    ));
    assert_eq!(
        PenLayout::from_descriptor(&[]),
        Err(HidError::EmptyDescriptor)
    );
    assert!(matches!(
        PenLayout::from_descriptor(&vec![0x00; 5000]),
        Err(HidError::DescriptorTooLong { len: 5000, .. })
    ));
}

#[test]
fn a_mouse_has_no_pen() {
    // Report 1 of the Intuos descriptor alone: a relative-X/Y mouse.
    let descriptor = fixture().descriptor;
    assert_eq!(
        PenLayout::from_descriptor(&descriptor[..52]),
        Err(HidError::NoPenReport)
    );
}

/// The fixture's text with extra lines inserted after the `I:` line.
fn fixture_with(extra: &str) -> String {
    let text = std::fs::read_to_string(Path::new(FIXTURE)).expect("fixture");
    text.replacen("I: 3 056a 0357\n", &format!("I: 3 056a 0357\n{extra}"), 1)
}

#[test]
fn garbage_lines_are_skipped_and_counted_with_line_numbers() {
    let garbage = "\
hello world
E: abc 3 10 00 00
E: 0.5 99999999999999999999 10
E: 0.5 999999 10 61
E: 0.5 2 10 zz
E: 0.5 2 10 61
E: inf 1 10
E: 1e400 1 10
E: -1 1 10
Q: what
E:
";
    let text = fixture_with(garbage);
    let first = text
        .lines()
        .position(|l| l == "hello world")
        .expect("inserted")
        + 1;
    let rec = Recording::parse(&text).expect("parses");
    // Every line but `E: 0.5 2 10 61` (well-formed, but a truncated report) is skipped.
    assert_eq!(rec.warning_count, 10, "{:?}", rec.warnings);
    let lines: Vec<usize> = rec.warnings.iter().map(|w| w.line).collect();
    let expected: Vec<usize> = (0..11).filter(|&i| i != 5).map(|i| first + i).collect();
    assert_eq!(lines, expected);
    assert!(
        rec.warnings[2].message.contains("exceeds")
            || rec.warnings[2].message.contains("not a number")
    );
    assert!(
        rec.warnings[3].message.contains("limit"),
        "{}",
        rec.warnings[3].message
    );
    let (file, stats) = recording_to_strokes(&rec).expect("replays");
    assert_eq!(file.strokes.len(), 3);
    assert_eq!(stats.recorder_warnings, 10);
    assert_eq!(stats.decode_errors, 1);
    let (line, e) = &stats.first_decode_errors[0];
    assert_eq!(*line, first + 5);
    assert!(matches!(e, HidError::ReportTruncated { len: 2, .. }), "{e}");
}

#[test]
fn unknown_report_ids_in_a_recording_are_counted() {
    let text = fixture_with("E: 0.0 3 42 00 00\n");
    let (file, stats) = replay_text(&text).expect("replays");
    assert_eq!(file.strokes.len(), 3);
    assert_eq!(stats.decode_errors, 1);
    assert_eq!(
        stats.first_decode_errors[0].1,
        HidError::UnknownReportId { report_id: 0x42 }
    );
}

#[test]
fn descriptor_line_errors_name_the_line() {
    assert_eq!(
        Recording::parse("N: x\nE: 0.1 1 10\n"),
        Err(RecorderError::MissingDescriptor)
    );
    let bad = "# c\nR: 3 05 0d\n";
    assert!(matches!(
        Recording::parse(bad),
        Err(RecorderError::BadDescriptor { line: 2, .. })
    ));
    let huge = "R: 18446744073709551615 05\n";
    let err = Recording::parse(huge).expect_err("an error");
    assert!(err.to_string().starts_with("line 1:"), "{err}");
    let not_hex = "R: 2 05 0x\n";
    assert!(matches!(
        Recording::parse(not_hex),
        Err(RecorderError::BadDescriptor { line: 1, .. })
    ));
    let twice = fixture_with("R: 2 05 0d\n");
    assert!(matches!(
        Recording::parse(&twice),
        Err(RecorderError::DuplicateDescriptor { .. })
    ));
    // A descriptor that parses as text but has no pen: the replay says so.
    let mouse = "R: 2 05 01\nE: 0.1 1 10\n";
    assert!(matches!(
        replay_text(mouse),
        Err(CaptureError::Descriptor(HidError::NoPenReport))
    ));
}

#[test]
fn other_devices_lines_are_skipped() {
    let text = fixture_with("D: 1\nR: 2 05 01\nE: 0.1 1 10\nD: 0\n");
    let rec = Recording::parse(&text).expect("parses");
    assert_eq!(rec.warning_count, 2);
    assert_eq!(replay_text(&text).expect("replays").0.strokes.len(), 3);
}

/// A generic pen without report IDs: Digitizers page switches, X/Y in inches (10⁻³ in),
/// pressure 0..1023 with no unit, tilts ±127 ↔ ±0.99 rad. Report: flags, X, Y, pressure (16
/// bits each), X and Y tilt (8 bits each): 9 bytes.
const GENERIC_PEN: [u8; 70] = [
    0x05, 0x0d, // Usage Page (Digitizers)
    0x09, 0x02, // Usage (Pen)
    0xa1, 0x01, // Collection (Application)
    0x09, 0x20, // Usage (Stylus)
    0xa1, 0x00, // Collection (Physical)
    0x09, 0x42, 0x09, 0x44, 0x09, 0x5a, 0x09, 0x45, 0x09, 0x3c, 0x09, 0x32, // six switches
    0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x06, 0x81, 0x02, // 6 x 1 bit
    0x95, 0x02, 0x81, 0x03, // 2 bits padding
    0x05, 0x01, 0x09, 0x30, 0x09, 0x31, // X, Y
    0x65, 0x13, 0x55, 0x0d, // Unit inch, exponent -3
    0x35, 0x00, 0x46, 0x10, 0x27, 0x15, 0x00, 0x26, 0x10, 0x27, // 0..10000 both
    0x75, 0x10, 0x95, 0x02, 0x81, 0x02, // 2 x 16 bits
    0x05, 0x0d, 0x09, 0x30, // Tip Pressure
    0x65, 0x00, // Unit none
    0x55, 0x00, // exponent 0
];
const GENERIC_PEN_TAIL: [u8; 33] = [
    0x35, 0x00, 0x45, 0x00, // no physical range
    0x15, 0x00, 0x26, 0xff, 0x03, 0x95, 0x01, 0x81, 0x02, // 0..1023, 16 bits
    0x09, 0x3d, 0x09, 0x3e, 0x65, 0x12, 0x55, 0x0e, // tilts, radians, exponent -2
    0x35, 0x9d, 0x45, 0x63, 0x15, 0x81, 0x25, 0x7f, // -99..99, -127..127
    0x75, 0x08, 0x95, 0x02,
];
const GENERIC_PEN_END: [u8; 4] = [0x81, 0x02, 0xc0, 0xc0];

fn generic_descriptor() -> Vec<u8> {
    [
        &GENERIC_PEN[..],
        &GENERIC_PEN_TAIL[..],
        &GENERIC_PEN_END[..],
    ]
    .concat()
}

/// Flags bits: Tip, Barrel, Secondary Barrel, Eraser, Invert, In Range.
const TIP: u8 = 1;
const ERASER: u8 = 1 << 3;
const INVERT: u8 = 1 << 4;
const IN_RANGE: u8 = 1 << 5;

fn generic_report(flags: u8, x: u16, y: u16, p: u16, tx: i8, ty: i8) -> Vec<u8> {
    let mut r = vec![flags];
    r.extend(x.to_le_bytes());
    r.extend(y.to_le_bytes());
    r.extend(p.to_le_bytes());
    r.extend([tx as u8, ty as u8]);
    r
}

#[test]
fn generic_pen_without_report_ids_in_inches_and_radians() {
    let layout = PenLayout::from_descriptor(&generic_descriptor()).expect("layout");
    assert!(!layout.uses_report_ids());
    let r = layout
        .decode(&generic_report(TIP | IN_RANGE, 5000, 2500, 1023, 127, -127))
        .expect("ok")
        .expect("pen");
    // 5000 × 10⁻³ inch = 127 mm; 2500 → 63.5 mm.
    assert!((r.x_mm - 127.0).abs() < 1e-9, "{}", r.x_mm);
    assert!((r.y_mm - 63.5).abs() < 1e-9, "{}", r.y_mm);
    assert_eq!(r.pressure, Some(1.0));
    // ±127 ↔ ±0.99 rad = ±56.72°.
    let deg = 0.99f64.to_degrees();
    assert!((r.tilt_x_deg.expect("tilt") - deg).abs() < 1e-9);
    assert!((r.tilt_y_deg.expect("tilt") + deg).abs() < 1e-9);
    assert!(r.tip && r.contact && !r.is_eraser());
}

#[test]
fn an_eraser_without_tip_switch_makes_a_marked_eraser_stroke() {
    let layout = PenLayout::from_descriptor(&generic_descriptor()).expect("layout");
    let hover = layout
        .decode(&generic_report(INVERT | IN_RANGE, 100, 100, 0, 0, 0))
        .expect("ok")
        .expect("pen");
    assert!(hover.is_eraser() && !hover.contact);
    let touch = layout
        .decode(&generic_report(
            ERASER | INVERT | IN_RANGE,
            100,
            100,
            500,
            0,
            0,
        ))
        .expect("ok")
        .expect("pen");
    assert!(touch.eraser && !touch.tip && touch.contact);

    // As a recording: hover, eraser contact over 5 reports, hover, a pen stroke, a lone tap.
    let hex = |r: &[u8]| {
        r.iter()
            .map(|b| format!("{b:02x}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let d = generic_descriptor();
    let mut text = format!("R: {} {}\nN: generic pen\n", d.len(), hex(&d));
    let mut t = 0.0;
    let mut push = |r: Vec<u8>, text: &mut String| {
        t += 0.005;
        text.push_str(&format!("E: {t:.6} {} {}\n", r.len(), hex(&r)));
    };
    push(
        generic_report(INVERT | IN_RANGE, 100, 100, 0, 0, 0),
        &mut text,
    );
    for i in 0..5 {
        push(
            generic_report(ERASER | INVERT | IN_RANGE, 100 + 50 * i, 100, 500, 0, 0),
            &mut text,
        );
    }
    push(
        generic_report(INVERT | IN_RANGE, 400, 100, 0, 0, 0),
        &mut text,
    );
    push(generic_report(IN_RANGE, 400, 100, 0, 0, 0), &mut text);
    for i in 0..4 {
        push(
            generic_report(TIP | IN_RANGE, 400, 100 + 80 * i, 300, 0, 0),
            &mut text,
        );
    }
    push(generic_report(IN_RANGE, 400, 400, 0, 0, 0), &mut text);
    push(
        generic_report(TIP | IN_RANGE, 400, 400, 300, 0, 0),
        &mut text,
    );
    push(generic_report(0, 400, 400, 0, 0, 0), &mut text);
    let (file, stats) = replay_text(&text).expect("replays");
    assert_eq!(stats.tools, [Tool::Eraser, Tool::Pen]);
    assert_eq!(file.strokes[0].samples.len(), 5);
    assert_eq!(file.strokes[1].samples.len(), 4);
    assert_eq!(stats.short_runs_dropped, 1, "the one-report tap");
    assert_eq!(
        file.device.expect("device")["eraser_strokes"],
        serde_json::json!([0])
    );
}

#[test]
fn times_going_backwards_are_dropped_and_counted() {
    let d = generic_descriptor();
    let hex = |r: &[u8]| {
        r.iter()
            .map(|b| format!("{b:02x}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let mut text = format!("R: {} {}\n", d.len(), hex(&d));
    for (t, y) in [(0.01, 0), (0.02, 100), (0.015, 200), (0.03, 300)] {
        let r = generic_report(TIP | IN_RANGE, 0, y, 300, 0, 0);
        text.push_str(&format!("E: {t} {} {}\n", r.len(), hex(&r)));
    }
    let (file, stats) = replay_text(&text).expect("replays");
    assert_eq!(stats.backwards_samples_dropped, 1);
    let ts: Vec<f64> = file.strokes[0].samples.iter().filter_map(|s| s.t).collect();
    assert_eq!(ts, [0.01, 0.02, 0.03]);
}

#[test]
fn pressure_alone_is_contact_when_the_pen_has_no_switches() {
    // X, Y and Tip Pressure only (drop the switch and padding items).
    let d: Vec<u8> = [
        &GENERIC_PEN[..10],
        &GENERIC_PEN[36..],
        &GENERIC_PEN_TAIL[..13],
        &GENERIC_PEN_END[2..],
    ]
    .concat();
    let layout = PenLayout::from_descriptor(&d).expect("layout");
    let report = |x: u16, p: u16| {
        let mut r = x.to_le_bytes().to_vec();
        r.extend(10u16.to_le_bytes());
        r.extend(p.to_le_bytes());
        r
    };
    let up = layout.decode(&report(10, 0)).expect("ok").expect("pen");
    let down = layout.decode(&report(10, 1)).expect("ok").expect("pen");
    assert!(!up.contact && down.contact && down.in_range && !down.tip);
}

/// An unsigned 8-bit Logical Maximum written as one byte (`0x25, 0xff`) is 255, not -1.
#[test]
fn one_byte_logical_maximum_of_255_is_unsigned() {
    let mut d: Vec<u8> = [
        &GENERIC_PEN[..],
        &GENERIC_PEN_TAIL[..],
        &GENERIC_PEN_END[..],
    ]
    .concat();
    // Pressure: Logical Maximum 0x26 0xff 0x03 → 0x25 0xff, 16-bit field kept.
    let at = GENERIC_PEN.len() + 6;
    assert_eq!(&d[at..at + 3], &[0x26, 0xff, 0x03]);
    d.splice(at..at + 3, [0x25, 0xff]);
    let layout = PenLayout::from_descriptor(&d).expect("layout");
    let r = layout
        .decode(&generic_report(TIP | IN_RANGE, 0, 0, 255, 0, 0))
        .expect("ok")
        .expect("pen");
    assert_eq!(r.pressure, Some(1.0));
}
