//! The live capture path without hardware: the hid-recorder fixture through
//! [`RecordingSource`] and the capture loop ([`run_capture`]) must give exactly the strokes that
//! replay gives, with the output file valid and complete after every stroke; interruptions (a
//! failing source, the stop flag, the duration) keep the stroke in progress; the raw file
//! replays to the same strokes; evdev frames give the strokes the evemu reader gives; and the
//! `kansei capture` / `kansei devices` commands end to end.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicBool, Ordering};

use kansei::capture::evdev_frames::{AbsAxis, EvdevAxes, EvdevPen};
use kansei::capture::recorder::Recording;
use kansei::capture::replay::replay_text;
use kansei::capture::session::{CaptureLimits, EndReason, run_capture};
use kansei::capture::source::{RecordingSource, SourceError, UDEV_RULE_HIDRAW, UDEV_RULE_INPUT};
use kansei::capture::stroke_builder::StrokeBuilder;
use kansei::capture::writer::{RawWriter, StrokeWriter};
use kansei::stroke::{Stroke, StrokeFile};

const FIXTURE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/fixtures/hid/pen-three-vertical-strokes.hid"
);
const EVEMU: &str = include_str!("../fixtures/evemu/pen-two-strokes.evemu");

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("capture_live");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let path = dir.join(name);
    let _ = std::fs::remove_file(&path);
    path
}

fn fixture_text() -> String {
    std::fs::read_to_string(FIXTURE).expect("fixture")
}

fn source() -> RecordingSource {
    let recording = Recording::parse(&fixture_text()).expect("parse");
    RecordingSource::new(recording, "fixture").expect("pen descriptor")
}

/// The strokes replay gives (the reference).
fn replayed() -> Vec<Stroke> {
    replay_text(&fixture_text()).expect("replay").0.strokes
}

fn read_file(path: &Path) -> StrokeFile {
    let text = std::fs::read_to_string(path).expect("output exists");
    StrokeFile::from_json(&text).expect("output is a valid kansei-stroke file")
}

/// The index in the recording of the report that gave `stroke`'s sample `sample`.
fn report_index_of(stroke: &Stroke, sample: usize) -> usize {
    let t = stroke.samples[sample].t.expect("timed");
    let recording = Recording::parse(&fixture_text()).expect("parse");
    recording
        .reports
        .iter()
        .position(|(rt, _)| *rt == t)
        .expect("sample time is a report time")
}

#[test]
fn capture_from_recording_writes_each_stroke_as_it_ends() {
    let reference = replayed();
    assert_eq!(reference.len(), 3);
    let out = scratch("each-stroke.json");
    let mut src = source();
    let info = kansei::capture::source::PenSource::info(&src).clone();
    let mut writer = StrokeWriter::create(&out, &info, "test").expect("create");
    assert_eq!(read_file(&out).strokes.len(), 0, "written at once, empty");
    let stop = AtomicBool::new(false);
    let mut seen = Vec::new();
    let summary = run_capture(
        &mut src,
        &mut writer,
        None,
        &stop,
        CaptureLimits::default(),
        |i, stroke| {
            // Called as stroke i ends, before it is written: the file holds strokes 0..i.
            let on_disk = read_file(&out);
            assert_eq!(on_disk.strokes, reference[..i], "file before stroke {i}");
            seen.push(stroke.clone());
        },
    )
    .expect("capture");
    assert!(matches!(summary.end, EndReason::SourceEnded));
    assert!(!summary.partial_saved);
    assert_eq!(summary.strokes, 3);
    assert_eq!(summary.reports, 843);
    assert_eq!(seen, reference);
    let file = read_file(&out);
    assert_eq!(file.strokes, reference);
    let device = file.device.expect("device");
    assert_eq!(device["vendor_id"], "056a");
    assert_eq!(device["width_mm"], 224.0);
    assert_eq!(device["pressure_levels"], 8192);
    assert!(!Path::new(&format!("{}.tmp", out.display())).exists());
}

#[test]
fn source_failure_mid_stroke_keeps_the_partial_stroke() {
    let reference = replayed();
    let middle = reference[1].samples.len() / 2;
    let failing_at = report_index_of(&reference[1], middle) + 1;
    let out = scratch("failure.json");
    let mut src = source().fail_after(failing_at);
    let info = kansei::capture::source::PenSource::info(&src).clone();
    let mut writer = StrokeWriter::create(&out, &info, "test").expect("create");
    let summary = run_capture(
        &mut src,
        &mut writer,
        None,
        &AtomicBool::new(false),
        CaptureLimits::default(),
        |_, _| {},
    )
    .expect("capture");
    assert!(matches!(
        summary.end,
        EndReason::SourceError(SourceError::Read { .. })
    ));
    assert!(summary.partial_saved);
    assert_eq!(summary.reports, failing_at);
    let file = read_file(&out);
    assert_eq!(file.strokes.len(), 2);
    assert_eq!(file.strokes[0], reference[0]);
    assert_eq!(file.strokes[1].samples, reference[1].samples[..=middle]);
}

#[test]
fn stop_flag_ends_the_capture_after_the_current_report() {
    let reference = replayed();
    let out = scratch("stop.json");
    let mut src = source();
    let info = kansei::capture::source::PenSource::info(&src).clone();
    let mut writer = StrokeWriter::create(&out, &info, "test").expect("create");
    let stop = AtomicBool::new(false);
    let summary = run_capture(
        &mut src,
        &mut writer,
        None,
        &stop,
        CaptureLimits::default(),
        |_, _| stop.store(true, Ordering::Relaxed),
    )
    .expect("capture");
    assert!(matches!(summary.end, EndReason::Interrupted));
    // The stop came at the report that ended stroke 0: nothing was in progress.
    assert!(!summary.partial_saved);
    assert_eq!(read_file(&out).strokes, reference[..1]);
}

#[test]
fn duration_mid_stroke_keeps_the_partial_stroke() {
    let reference = replayed();
    let middle = reference[2].samples.len() / 2;
    let t_cut = reference[2].samples[middle].t.expect("timed");
    let out = scratch("duration.json");
    let mut src = source();
    let info = kansei::capture::source::PenSource::info(&src).clone();
    let mut writer = StrokeWriter::create(&out, &info, "test").expect("create");
    let summary = run_capture(
        &mut src,
        &mut writer,
        None,
        &AtomicBool::new(false),
        CaptureLimits {
            duration: Some(t_cut),
        },
        |_, _| {},
    )
    .expect("capture");
    assert!(matches!(summary.end, EndReason::Duration));
    assert!(summary.partial_saved);
    let file = read_file(&out);
    assert_eq!(file.strokes[..2], reference[..2]);
    // Reports at t >= duration are not taken.
    assert_eq!(file.strokes[2].samples, reference[2].samples[..middle]);
}

#[test]
fn raw_file_replays_to_the_same_strokes() {
    let out = scratch("raw.json");
    let raw_path = scratch("raw.hid");
    let mut src = source();
    let info = kansei::capture::source::PenSource::info(&src).clone();
    let descriptor = kansei::capture::source::PenSource::descriptor(&src)
        .expect("HID source")
        .to_vec();
    let mut writer = StrokeWriter::create(&out, &info, "test").expect("create");
    let mut raw = RawWriter::create(&raw_path, &descriptor, &info).expect("raw");
    run_capture(
        &mut src,
        &mut writer,
        Some(&mut raw),
        &AtomicBool::new(false),
        CaptureLimits::default(),
        |_, _| {},
    )
    .expect("capture");
    drop(raw);
    let raw_text = std::fs::read_to_string(&raw_path).expect("raw file");
    let original = Recording::parse(&fixture_text()).expect("parse");
    let again = Recording::parse(&raw_text).expect("raw file parses");
    assert_eq!(again.descriptor, original.descriptor);
    assert_eq!(again.name, original.name);
    assert_eq!(again.id, original.id);
    assert_eq!(again.warning_count, 0);
    assert_eq!(again.reports.len(), original.reports.len());
    for ((t0, b0), (t1, b1)) in original.reports.iter().zip(&again.reports) {
        assert_eq!(b0, b1);
        assert!((t0 - t1).abs() <= 5e-7, "time {t0} written as {t1}");
    }
    assert_eq!(
        replay_text(&raw_text).expect("replay raw").0.strokes,
        read_file(&out).strokes
    );
}

#[test]
fn permission_error_names_node_errno_and_rules() {
    let e = std::io::Error::from_raw_os_error(13);
    let err = SourceError::from_open("/dev/hidraw7", &e, Some(0x256c));
    let text = err.to_string();
    assert!(text.contains("/dev/hidraw7"), "{text}");
    assert!(text.contains("errno 13"), "{text}");
    assert!(
        text.contains(&UDEV_RULE_HIDRAW.replace("056a", "256c")),
        "{text}"
    );
    assert!(text.contains(UDEV_RULE_INPUT), "{text}");
    let other = SourceError::from_open("/dev/hidraw7", &std::io::Error::from_raw_os_error(2), None);
    assert!(matches!(other, SourceError::Open { .. }));
}

/// The evemu fixture's events through [`EvdevPen`] and the stroke builder give the strokes the
/// evemu reader gives (same frames, same conversions).
#[test]
fn evdev_frames_match_the_evemu_reader() {
    let (expected, _) = kansei::capture::evemu::read(EVEMU).expect("evemu");
    let mut axes = EvdevAxes::default();
    let mut events = Vec::new();
    for line in EVEMU.lines() {
        let line = line.split('#').next().unwrap_or("").trim();
        if let Some(rest) = line.strip_prefix("A:") {
            let f: Vec<&str> = rest.split_whitespace().collect();
            let code = u16::from_str_radix(f[0], 16).expect("code");
            let n = |i: usize| f[i].parse::<i32>().expect("number");
            let a = AbsAxis {
                min: n(1),
                max: n(2),
                resolution: n(5),
            };
            match code {
                0x00 => axes.x = a,
                0x01 => axes.y = a,
                0x18 => axes.pressure = Some(a),
                0x1a => axes.tilt_x = Some(a),
                0x1b => axes.tilt_y = Some(a),
                _ => {}
            }
        } else if let Some(rest) = line.strip_prefix("E:") {
            let f: Vec<&str> = rest.split_whitespace().collect();
            let t: f64 = f[0].parse().expect("time");
            let kind = u16::from_str_radix(f[1], 16).expect("type");
            let code = u16::from_str_radix(f[2], 16).expect("code");
            let value: i32 = f[3].parse().expect("value");
            events.push((t, kind, code, value));
        }
    }
    let t0 = events[0].0;
    let mut pen = EvdevPen::new(axes);
    let mut builder = StrokeBuilder::new();
    for (t, kind, code, value) in events {
        if let Some(report) = pen.event(kind, code, value) {
            builder.push(t - t0, &report);
        }
    }
    let (built, _) = builder.finish();
    assert_eq!(built.len(), expected.strokes.len());
    assert_eq!(built.len(), 2);
    for (b, e) in built.iter().zip(&expected.strokes) {
        assert_eq!(b.stroke.samples.len(), e.samples.len());
        for (s, r) in b.stroke.samples.iter().zip(&e.samples) {
            assert_eq!((s.x, s.y), (r.x, r.y));
            assert_eq!(s.pressure, r.pressure);
            assert_eq!((s.tilt_x, s.tilt_y), (r.tilt_x, r.tilt_y));
            let (ts, tr) = (s.t.expect("t"), r.t.expect("t"));
            assert!((ts - tr).abs() < 1e-9, "{ts} vs {tr}");
        }
    }
}

fn kansei(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_kansei"))
        .args(args)
        .output()
        .expect("run kansei")
}

#[test]
fn capture_command_end_to_end() {
    let out = scratch("cli.json");
    let raw = scratch("cli.hid");
    let o = kansei(&[
        "capture",
        "--from-recording",
        FIXTURE,
        "--out",
        out.to_str().expect("utf-8"),
        "--raw",
        raw.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("3 strokes from 843 reports"), "{stdout}");
    let reference = replayed();
    assert_eq!(read_file(&out).strokes, reference);
    let replayed_raw = kansei(&["replay", raw.to_str().expect("utf-8"), "--out", "/dev/null"]);
    assert!(replayed_raw.status.success());
    // Written in place, not renamed over: the device node survives (as root the rename replaced
    // it with a regular file).
    {
        use std::os::unix::fs::FileTypeExt;
        let kind = std::fs::metadata("/dev/null")
            .expect("/dev/null")
            .file_type();
        assert!(kind.is_char_device(), "/dev/null is no longer a device");
    }
    assert_eq!(
        replay_text(&std::fs::read_to_string(&raw).expect("raw"))
            .expect("replay")
            .0
            .strokes,
        reference
    );
}

#[test]
fn capture_command_saves_partial_stroke_on_failure() {
    let reference = replayed();
    let middle = reference[0].samples.len() / 2;
    let n = report_index_of(&reference[0], middle) + 1;
    let out = scratch("cli-fail.json");
    let o = kansei(&[
        "capture",
        "--from-recording",
        FIXTURE,
        "--out",
        out.to_str().expect("utf-8"),
        "--fail-after-reports",
        &n.to_string(),
    ]);
    assert!(!o.status.success());
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.contains("strokes so far are saved"), "{stderr}");
    let file = read_file(&out);
    assert_eq!(file.strokes.len(), 1);
    assert_eq!(file.strokes[0].samples, reference[0].samples[..=middle]);
}

#[test]
fn capture_command_rejects_bad_duration() {
    let out = scratch("cli-bad.json");
    let o = kansei(&[
        "capture",
        "--from-recording",
        FIXTURE,
        "--out",
        out.to_str().expect("utf-8"),
        "--duration",
        "0",
    ]);
    assert!(!o.status.success());
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.contains("--duration must be a positive"), "{stderr}");
    assert!(!out.exists());
}

/// With or without tablets (this test machine has none), `devices` succeeds and says something.
#[test]
fn devices_command_succeeds() {
    let o = kansei(&["devices"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(!stdout.trim().is_empty());
}

/// Pace for the SIGTERM test: half the recorded speed, so the second stroke lasts long enough
/// for the signal to land inside it on a loaded machine.
const SIGTERM_PACE: f64 = 0.5;

/// SIGTERM (`kill`, a service stop) during `kansei capture` ends it like Ctrl-C: the handler
/// (ctrlc's `termination` feature) stops the loop, the finished stroke and the stroke in
/// progress are written, and the exit is normal. Without the feature SIGTERM kills the process
/// and the stroke in progress is lost.
#[cfg(feature = "live")]
#[test]
fn sigterm_mid_stroke_saves_the_stroke_in_progress() {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    use std::time::Duration;

    let reference = replayed();
    let end_of_first = reference[0]
        .samples
        .last()
        .and_then(|s| s.t)
        .expect("timed");
    let second = &reference[1].samples;
    let (start, end) = (
        second[0].t.expect("timed"),
        second[second.len() - 1].t.expect("timed"),
    );
    // From the message that stroke 1 ended to the middle of stroke 2, on the wall clock.
    let delay = ((start + end) / 2.0 - end_of_first) / SIGTERM_PACE;
    let out = scratch("cli-sigterm.json");
    let mut child = Command::new(env!("CARGO_BIN_EXE_kansei"))
        .args(["capture", "--from-recording", FIXTURE, "--out"])
        .arg(&out)
        .args(["--pace", &SIGTERM_PACE.to_string()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn kansei");
    let stderr = child.stderr.take().expect("piped");
    let mut lines = BufReader::new(stderr).lines();
    let first = lines.next().expect("a line").expect("utf-8");
    assert!(first.starts_with("stroke 1:"), "{first}");
    std::thread::sleep(Duration::from_secs_f64(delay));
    let killed = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .expect("kill");
    assert!(killed.success());
    let rest: Vec<String> = lines.map_while(Result::ok).collect();
    let o = child.wait_with_output().expect("exits");
    assert!(o.status.success(), "{:?}: {rest:?}", o.status);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("2 strokes (the last one interrupted)"),
        "{stdout}"
    );
    let file = read_file(&out);
    assert_eq!(file.strokes.len(), 2);
    assert_eq!(file.strokes[0], reference[0]);
    let partial = &file.strokes[1].samples;
    assert!(
        partial.len() > 1 && partial.len() < second.len(),
        "{}",
        partial.len()
    );
    assert_eq!(partial[..], second[..partial.len()]);
}
