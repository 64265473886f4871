//! evemu recordings: the synthetic two-stroke Wacom recording (pen, then eraser) to planted
//! values, and every kind of damaged input.

use kansei::capture::evdev_frames::OutOfRange;
use kansei::capture::evemu::{self, EvemuError, EvemuProblem, EvemuWarning};
use kansei::capture::replay::replay_text;
use kansei::stroke::StrokeFile;
use kansei::stroke::{StrokeError, Units};

const RECORDING: &str = include_str!("../fixtures/evemu/pen-two-strokes.evemu");

/// The fixture's axes: 200 counts per mm, pressure 0..8191, tilt 57 units per radian.
const COUNTS_PER_MM: f64 = 200.0;
const PRESSURE_MAX: f64 = 8191.0;
const TILT_PER_RADIAN: f64 = 57.0;

fn deg(v: f64) -> f64 {
    (v / TILT_PER_RADIAN).to_degrees()
}

#[test]
fn two_strokes_in_mm_with_carried_forward_axes_and_the_eraser_marked() {
    let (file, stats) = evemu::read(RECORDING).expect("reads");
    assert_eq!(file.units, Units::Mm);
    assert_eq!(file.strokes.len(), 2);
    assert_eq!(stats.eraser, [false, true]);
    // (t ms, X, Y counts, pressure, tilt_x counts): X, Y, pressure and tilt carry forward.
    let pen: [(f64, f64, f64, f64, f64); 6] = [
        (8.0, 10010.0, 8000.0, 1000.0, 10.0),
        (16.0, 10200.0, 8100.0, 2500.0, 10.0),
        (24.0, 10400.0, 8100.0, 2500.0, 10.0), // only X reported
        (32.0, 10400.0, 8300.0, 2500.0, 12.0), // only Y and tilt
        (40.0, 10400.0, 8300.0, 3000.0, 12.0), // only pressure
        (48.0, 10600.0, 8400.0, 1200.0, 12.0),
    ];
    let eraser: [(f64, f64, f64, f64, f64); 3] = [
        (508.0, 20000.0, 15000.0, 4096.0, 12.0),
        (516.0, 19800.0, 15000.0, 4096.0, 12.0),
        (524.0, 19600.0, 14800.0, 8191.0, 12.0),
    ];
    for (stroke, expected) in file.strokes.iter().zip([&pen[..], &eraser[..]]) {
        assert_eq!(stroke.samples.len(), expected.len());
        for (s, &(t, x, y, p, tx)) in stroke.samples.iter().zip(expected) {
            assert_eq!(s.x, x / COUNTS_PER_MM, "{s:?}");
            assert_eq!(s.y, y / COUNTS_PER_MM, "{s:?}");
            assert!((s.t.expect("present") - t / 1000.0).abs() < 1e-12, "{s:?}");
            assert_eq!(s.pressure, Some(p / PRESSURE_MAX), "{s:?}");
            assert_eq!(s.tilt_x, Some(deg(tx)), "{s:?}");
            assert_eq!(s.tilt_y, Some(deg(-5.0)), "{s:?}");
        }
    }
    assert_eq!(file.strokes[1].samples[2].pressure, Some(1.0));
    assert_eq!(stats.version, "1.3");
    assert_eq!((stats.events, stats.frames), (55, 15));
    // Not used: 5 ABS_DISTANCE and 2 MSC_SERIAL events.
    assert_eq!(stats.ignored_events, 7);
    assert_eq!(
        (
            stats.garbage_lines,
            stats.out_of_range,
            stats.trailing_events
        ),
        (0, 0, 0)
    );
    assert!(!stats.unterminated_stroke);
    assert!(file.validate().is_ok());
    let device = file.device.expect("present");
    assert_eq!(device["name"], "Wacom Intuos Pro M Pen");
    assert_eq!(device["vendor"], 0x56a);
    assert_eq!(device["abs_x"]["resolution"], 200);
}

/// The fixture's header (everything before the first event).
fn header() -> &'static str {
    let end = RECORDING.find("\nE: ").expect("in the fixture") + 1;
    &RECORDING[..end]
}

#[test]
fn truncated_recording_keeps_complete_frames_and_the_open_stroke() {
    // Cut in the middle of the line after the frame at 24 ms.
    let cut = RECORDING
        .find("E: 0.032000 0003 0001")
        .expect("in the fixture")
        + 14;
    let (file, stats) = evemu::read(&RECORDING[..cut]).expect("reads");
    assert_eq!(file.strokes.len(), 1);
    assert_eq!(file.strokes[0].samples.len(), 3);
    assert!(stats.unterminated_stroke);
    assert_eq!(stats.garbage_lines, 1);
    // Cut after a complete event but before its SYN_REPORT.
    let cut = RECORDING
        .find("E: 0.032000 0003 001a")
        .expect("in the fixture");
    let (file, stats) = evemu::read(&RECORDING[..cut]).expect("reads");
    assert_eq!(file.strokes[0].samples.len(), 3);
    assert_eq!((stats.trailing_events, stats.garbage_lines), (1, 0));
    // Only the header: no strokes, no error.
    let (file, stats) = evemu::read(header()).expect("reads");
    assert!(file.strokes.is_empty() && stats.events == 0);
}

#[test]
fn garbage_unknown_codes_and_huge_values_are_counted_not_fatal() {
    let body = "\
hello world
E: 0.000000 0001 014a
E: zero 0003 0000 5
E: 0.0 0003 0000 5
E: 0.000000 0003 0000 99999999999
E: 0.000000 00zz 0000 1
A: 2f nope
Q: 1 2 3
E: 0.000000 0001 014a 0001
E: 0.000000 0003 0000 100
E: 0.000000 0003 0001 100
E: 0.000000 0003 0018 9000
E: 0.000000 0003 0030 7
E: 0.000000 0015 0001 1
E: 0.000000 0000 0000 0000
E: 0.005000 0003 0000 200
E: 0.005000 0003 0018 4000
E: 0.005000 0000 0000 0000
E: 0.010000 0003 0000 2147483647
E: 0.010000 0003 0018 -4
E: 0.010000 0000 0000 0000
E: 0.015000 0003 0001 300
E: 0.015000 0000 0000 0000
E: 0.020000 0001 014a 0000
E: 0.020000 0000 0000 0000
";
    let (file, stats) = evemu::read(&format!("{}{body}", header())).expect("reads");
    assert_eq!(stats.garbage_lines, 8);
    // ABS_MT_TOUCH_MAJOR (0x30) and the unknown type 0x15.
    assert_eq!(stats.ignored_events, 2);
    // Pressure 9000 > 8191, X 2147483647 > 44800, pressure -4 < 0: not used, and the two
    // frames holding them give no sample.
    assert_eq!((stats.out_of_range, stats.rejected_frames), (3, 2));
    let s = &file.strokes[0].samples;
    assert_eq!(s.len(), 2);
    // X keeps 200 (not 2147483647) and pressure 4000 through the rejected frame.
    assert_eq!(
        (s[0].x, s[0].y),
        (200.0 / COUNTS_PER_MM, 100.0 / COUNTS_PER_MM)
    );
    assert_eq!(
        (s[1].x, s[1].y),
        (200.0 / COUNTS_PER_MM, 300.0 / COUNTS_PER_MM)
    );
    assert_eq!(s[1].t, Some(0.015));
    let p = Some(4000.0 / PRESSURE_MAX);
    assert_eq!((s[0].pressure, s[1].pressure), (p, p));
    assert_eq!(stats.eraser, [false]);
    // Every skipped line and value, in order, with its line number.
    let first = header().lines().count() + 1;
    let lines: Vec<usize> = stats.warnings.iter().map(|w| w.line).collect();
    let expected: Vec<usize> = [0, 1, 2, 3, 4, 5, 6, 7, 11, 18, 19]
        .iter()
        .map(|i| first + i)
        .collect();
    assert_eq!(lines, expected);
    assert!(
        stats.warnings[..8]
            .iter()
            .all(|w| w.problem == EvemuProblem::Garbage)
    );
    assert_eq!(
        stats.warnings[9].problem,
        EvemuProblem::OutOfRange(OutOfRange {
            axis: "ABS_X",
            value: i32::MAX,
            min: 0,
            max: 44800
        })
    );
    let message = stats.warnings[10].problem.to_string();
    assert!(message.contains("ABS_PRESSURE = -4"), "{message}");
}

#[test]
fn dropped_frames_are_discarded_up_to_the_next_report() {
    let body = "\
E: 0.000000 0001 014a 0001
E: 0.000000 0003 0000 100
E: 0.000000 0003 0001 100
E: 0.000000 0000 0000 0000
E: 0.010000 0003 0000 5000
E: 0.010000 0000 0003 0000
E: 0.010000 0003 0001 5000
E: 0.010000 0000 0000 0000
E: 0.020000 0003 0001 300
E: 0.020000 0000 0000 0000
";
    let (file, stats) = evemu::read(&format!("{}{body}", header())).expect("reads");
    assert_eq!(stats.dropped_frames, 1);
    let dropped_line = header().lines().count() + 6;
    assert_eq!(
        stats.warnings,
        [EvemuWarning {
            line: dropped_line,
            problem: EvemuProblem::Dropped
        }]
    );
    let s = &file.strokes[0].samples;
    assert_eq!(s.len(), 2);
    assert_eq!((s[1].x, s[1].y), (0.5, 1.5));
}

#[test]
fn without_resolution_units_are_device_counts_and_tilt_degrees() {
    let text = "# EVEMU 1.3
N: Some Pen
A: 00 0 1000 0 0 0
A: 01 0 1000 0 0 0
A: 1a -60 60 0 0 0
E: 5.000000 0001 014a 0001
E: 5.000000 0003 0000 10
E: 5.000000 0003 0001 20
E: 5.000000 0003 001a -30
E: 5.000000 0000 0000 0000
E: 5.250000 0003 0000 30
E: 5.250000 0000 0000 0000
";
    let (file, stats) = evemu::read(text).expect("reads");
    assert_eq!(file.units, Units::Device);
    let s = &file.strokes[0].samples;
    assert_eq!((s[1].x, s[1].y, s[1].t), (30.0, 20.0, Some(0.25)));
    assert_eq!(
        (s[0].tilt_x, s[0].tilt_y, s[0].pressure),
        (Some(-30.0), None, None)
    );
    assert!(stats.unterminated_stroke);
}

#[test]
fn taps_and_positionless_frames_are_counted() {
    let body = "\
E: 0.000000 0001 014a 0001
E: 0.000000 0000 0000 0000
E: 0.010000 0003 0000 100
E: 0.010000 0003 0001 100
E: 0.010000 0000 0000 0000
E: 0.020000 0001 014a 0000
E: 0.020000 0000 0000 0000
";
    let (file, stats) = evemu::read(&format!("{}{body}", header())).expect("reads");
    assert!(file.strokes.is_empty());
    assert_eq!(
        (stats.samples_without_position, stats.short_strokes),
        (1, 1)
    );
    assert!(stats.eraser.is_empty());
}

#[test]
fn bad_recordings_are_refused_with_clear_errors() {
    assert_eq!(evemu::read(""), Err(EvemuError::Empty));
    assert_eq!(evemu::read(" \n\n"), Err(EvemuError::Empty));
    assert_eq!(
        evemu::read("N: pen\nE: 0.000000 0000 0000 0000\n"),
        Err(EvemuError::NotEvemu("N: pen".to_owned()))
    );
    assert_eq!(
        evemu::read("# EVEMU 2.0\n"),
        Err(EvemuError::UnsupportedVersion("2.0".to_owned()))
    );
    // Time going backwards within a stroke.
    let body = "\
E: 1.000000 0001 014a 0001
E: 1.000000 0003 0000 100
E: 1.000000 0003 0001 100
E: 1.000000 0000 0000 0000
E: 0.500000 0003 0000 200
E: 0.500000 0000 0000 0000
";
    let err = evemu::read(&format!("{}{body}", header())).expect_err("refused");
    assert!(matches!(
        err,
        EvemuError::Invalid {
            stroke: 0,
            source: StrokeError::TimeBackwards { sample: 1, .. }
        }
    ));
    assert!(err.to_string().starts_with("stroke 0: "), "{err}");
}

/// Characters that matter to the evemu line grammar.
const MUTATIONS: &[u8] = b"0123456789abcdef-:. #\nEAx";

#[test]
fn mutated_and_truncated_recording_never_panics_and_what_is_accepted_is_valid() {
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = move |n: usize| {
        // xorshift64: a fixed, dependency-free sequence.
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n as u64) as usize
    };
    let mut accepted = 0;
    for round in 0..1500 {
        let mut text = RECORDING.as_bytes().to_vec();
        let at = next(text.len());
        if round % 3 == 0 {
            text.truncate(at);
        } else if text[at].is_ascii() {
            text[at] = MUTATIONS[next(MUTATIONS.len())];
        }
        let Ok(text) = String::from_utf8(text) else {
            continue;
        };
        if let Ok((file, stats)) = evemu::read(&text) {
            assert!(file.validate().is_ok());
            assert_eq!(stats.eraser.len(), file.strokes.len());
            accepted += 1;
        }
    }
    assert!(accepted > 1000, "{accepted}");
}

/// evemu replay marks eraser strokes in `device.eraser_strokes` as HID replay does, and the
/// mark survives the kansei-stroke JSON round trip.
#[test]
fn eraser_strokes_are_marked_in_the_device_object_like_hid_replay() {
    let (file, stats) = evemu::read(RECORDING).expect("reads");
    assert_eq!(stats.eraser, [false, true]);
    let device = file.device.as_ref().expect("present");
    assert_eq!(device["eraser_strokes"], serde_json::json!([1]));
    let back = StrokeFile::from_json(&file.to_json()).expect("round trip");
    assert_eq!(
        back.device.expect("present")["eraser_strokes"],
        serde_json::json!([1])
    );
    // The same key HID replay writes (here: no eraser strokes).
    let hid = include_str!("../fixtures/hid/pen-three-vertical-strokes.hid");
    let (hid_file, _) = replay_text(hid).expect("replays");
    assert_eq!(
        hid_file.device.expect("present")["eraser_strokes"],
        serde_json::json!([])
    );
}

/// The same recording split as old evemu recordings are kept (fixtures/evemu/README.md): a
/// `.desc` device description and a header-less `.events` file.
const DESCRIPTION: &str = include_str!("../fixtures/evemu/pen-two-strokes.desc");
const EVENTS: &str = include_str!("../fixtures/evemu/pen-two-strokes.events");

#[test]
fn a_description_and_a_headerless_events_file_read_as_the_combined_recording() {
    use kansei::capture::evemu::EvemuRecording;
    let (combined, combined_stats) = evemu::read(RECORDING).expect("reads");
    // The events alone are not a recording: no header.
    assert!(matches!(evemu::read(EVENTS), Err(EvemuError::NotEvemu(_))));
    let rec = EvemuRecording::parse_description(DESCRIPTION)
        .expect("a description")
        .with_events(EVENTS, "pen-two-strokes.desc")
        .expect("events");
    let (split, stats) = evemu::replay(&rec).expect("replays");
    assert_eq!(split.strokes, combined.strokes);
    assert_eq!(split.units, combined.units);
    assert_eq!(split.device, combined.device);
    assert_eq!(stats.eraser, combined_stats.eraser);
    assert_eq!(
        (stats.events, stats.frames, stats.garbage_lines),
        (55, combined_stats.frames, 0)
    );
    assert!(
        split
            .source
            .as_deref()
            .is_some_and(|s| s.contains("pen-two-strokes.desc")),
        "{:?}",
        split.source
    );
    // A description without its `# EVEMU` line (format 1.0 assumed) describes the same device.
    let bare: String = DESCRIPTION
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| format!("{l}\n"))
        .collect();
    let rec = EvemuRecording::parse_description(&bare)
        .expect("a description")
        .with_events(EVENTS, "bare.desc")
        .expect("events");
    assert_eq!(rec.version, "1.0");
    assert_eq!(
        evemu::replay(&rec).expect("replays").0.strokes,
        combined.strokes
    );
}

#[test]
fn a_bad_description_is_refused_with_its_line() {
    use kansei::capture::evemu::EvemuRecording;
    assert_eq!(
        EvemuRecording::parse_description("N: pen\nA: 00 0 100\n"),
        Err(EvemuError::BadDescription(2))
    );
    assert_eq!(
        EvemuRecording::parse_description("# only a comment\n"),
        Err(EvemuError::NoDescription)
    );
    assert_eq!(
        EvemuRecording::parse_description(DESCRIPTION)
            .expect("a description")
            .with_events(" \n", "x.desc"),
        Err(EvemuError::Empty)
    );
}
