//! Linux evdev recordings in the text format `evemu-record` writes (`# EVEMU 1.3`).
//!
//! A recording is a header and events:
//!
//! ```text
//! # EVEMU 1.3
//! N: Wacom Intuos Pro M Pen                  device name
//! I: 0003 056a 0357 0110                     bus, vendor, product, version (hex)
//! P: / B: / L: / S: / R:                     properties, event bits, ...: not needed, skipped
//! A: 00 0 44800 4 0 200                      axis (hex code): min max fuzz flat resolution
//! E: 0.008000 0003 0000 10010                event: sec.usec, type and code (hex), value
//! ```
//!
//! Events are grouped into frames ended by `SYN_REPORT` (type 0, code 0). Axis values persist:
//! an axis absent from a frame keeps its previous value (evdev only reports changes). A stroke
//! is a `BTN_TOUCH` down…up run: every frame ending with the pen touching gives one sample
//! (the frame that lifts the pen gives none). Strokes drawn while `BTN_TOOL_RUBBER` is the
//! active tool are kept and marked in [`EvemuStats::eraser`].
//!
//! - **Positions**: `ABS_X`/`ABS_Y` divided by their resolution (units per mm, per the kernel's
//!   `input_absinfo`), giving [`Units::Mm`]; [`Units::Device`] counts when either resolution
//!   is 0 or the axis is not declared.
//! - **Time**: seconds since the recording's first event.
//! - **Pressure**: `(v - min) / (max - min)` of the `ABS_PRESSURE` axis. A value outside the
//!   declared range is clamped and counted in [`EvemuStats::out_of_range`].
//! - **Tilt**: `ABS_TILT_X`/`ABS_TILT_Y` in degrees. The kernel documents their resolution in
//!   units per radian, so `degrees = (v / resolution).to_degrees()`; with resolution 0 the raw
//!   value is taken as degrees (Wacom tablets report about one unit per degree, and their
//!   drivers declare 57 units/rad ≈ 1 unit/degree).
//!
//! Nothing in a recording panics the reader: lines that do not parse, values beyond 32 bits and
//! events this reader does not use are skipped and counted in [`EvemuStats`]. A truncated
//! recording reads up to its last complete frame; a stroke still touching at the end is kept.

use std::collections::HashMap;

use serde_json::json;
use thiserror::Error;

use crate::stroke::{Sample, Stroke, StrokeError, StrokeFile, Units};

/// `EV_SYN`: frame markers.
pub const EV_SYN: u16 = 0x00;
/// `EV_KEY`: buttons and tools.
pub const EV_KEY: u16 = 0x01;
/// `EV_ABS`: absolute axes.
pub const EV_ABS: u16 = 0x03;
/// `SYN_REPORT`: ends a frame.
pub const SYN_REPORT: u16 = 0x00;
/// `SYN_DROPPED`: the kernel's buffer overran; the current frame is incomplete.
pub const SYN_DROPPED: u16 = 0x03;
/// `BTN_TOOL_PEN`: the pen tip is in proximity.
pub const BTN_TOOL_PEN: u16 = 0x140;
/// `BTN_TOOL_RUBBER`: the eraser end is in proximity.
pub const BTN_TOOL_RUBBER: u16 = 0x141;
/// `BTN_TOUCH`: contact with the surface.
pub const BTN_TOUCH: u16 = 0x14a;
/// `ABS_X`.
pub const ABS_X: u16 = 0x00;
/// `ABS_Y`.
pub const ABS_Y: u16 = 0x01;
/// `ABS_PRESSURE`.
pub const ABS_PRESSURE: u16 = 0x18;
/// `ABS_TILT_X`.
pub const ABS_TILT_X: u16 = 0x1a;
/// `ABS_TILT_Y`.
pub const ABS_TILT_Y: u16 = 0x1b;

/// The header's first line starts with this.
const HEADER: &str = "# EVEMU ";
/// The format major version read: evemu 1.x (1.0 to 1.3 differ only in optional lines).
const SUPPORTED_MAJOR: &str = "1";
/// Microseconds per second, for the `sec.usec` timestamps.
const MICROS_PER_SECOND: i64 = 1_000_000;

/// Why a recording could not be read at all.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum EvemuError {
    /// The text is empty or only white space.
    #[error("the recording is empty")]
    Empty,
    /// The first line is not an `# EVEMU` header.
    #[error("not an evemu recording: the first line is {0:?}, expected \"# EVEMU 1.x\"")]
    NotEvemu(String),
    /// An evemu format version this reader does not know.
    #[error("evemu format version {0:?} is not supported (1.x is)")]
    UnsupportedVersion(String),
    /// A stroke breaks the stroke rules (time going backwards, coordinates beyond range).
    #[error("stroke {stroke}: {source}")]
    Invalid {
        /// Stroke index among the strokes kept.
        stroke: usize,
        /// The rule broken.
        source: StrokeError,
    },
}

/// What the reader met besides the strokes, and which strokes were drawn with the eraser.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EvemuStats {
    /// The header's format version, e.g. `1.3`.
    pub version: String,
    /// Parallel to the file's strokes: `true` for a stroke drawn with the eraser end
    /// (`BTN_TOOL_RUBBER`).
    pub eraser: Vec<bool>,
    /// `E:` lines read.
    pub events: usize,
    /// Frames (`SYN_REPORT`s).
    pub frames: usize,
    /// Lines that did not parse (unknown prefixes, malformed or truncated `A:`/`E:` lines,
    /// values beyond 32 bits, timestamps that are not `sec.usec`).
    pub garbage_lines: usize,
    /// Well-formed events this reader does not use (other types, codes, axes not declared).
    pub ignored_events: usize,
    /// Axis values outside their declared min..max (pressure is clamped, others kept).
    pub out_of_range: usize,
    /// `SYN_DROPPED` markers; the incomplete frame before each, and the events after it up to
    /// and including the next `SYN_REPORT`, are discarded.
    pub dropped_frames: usize,
    /// Events after the last `SYN_REPORT` (a truncated recording): discarded.
    pub trailing_events: usize,
    /// Whether the pen was still touching at the end of the recording (its stroke is kept).
    pub unterminated_stroke: bool,
    /// Touching frames before any `ABS_X`/`ABS_Y` value was known: no sample.
    pub samples_without_position: usize,
    /// Strokes with fewer than two distinct positions (taps): dropped.
    pub short_strokes: usize,
}

/// An axis as the `A:` line declares it.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Axis {
    min: i64,
    max: i64,
    resolution: i64,
}

/// Axis values and buttons as the device reported them so far.
#[derive(Clone, Copy, Debug, Default)]
struct PenState {
    x: Option<i64>,
    y: Option<i64>,
    pressure: Option<i64>,
    tilt_x: Option<i64>,
    tilt_y: Option<i64>,
    touch: bool,
    rubber: bool,
}

/// One parsed `E:` line.
struct Event {
    micros: i64,
    kind: u16,
    code: u16,
    value: i64,
}

fn parse_event(rest: &str) -> Option<Event> {
    let mut fields = rest.split_whitespace();
    let (stamp, kind, code, value) = (
        fields.next()?,
        fields.next()?,
        fields.next()?,
        fields.next()?,
    );
    let (sec, usec) = stamp.split_once('.')?;
    // evemu writes %06u microseconds; other widths are not its output.
    if usec.len() != 6 || !sec.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let sec: i64 = sec.parse().ok()?;
    let usec: i64 = usec.parse().ok()?;
    let micros = sec.checked_mul(MICROS_PER_SECOND)?.checked_add(usec)?;
    Some(Event {
        micros,
        kind: u16::from_str_radix(kind, 16).ok()?,
        code: u16::from_str_radix(code, 16).ok()?,
        // evdev values are 32-bit signed.
        value: i64::from(value.parse::<i32>().ok()?),
    })
}

fn parse_axis(rest: &str) -> Option<(u16, Axis)> {
    let mut fields = rest.split_whitespace();
    let code = u16::from_str_radix(fields.next()?, 16).ok()?;
    let mut next = || -> Option<i64> { fields.next()?.parse::<i32>().ok().map(i64::from) };
    let (min, max, _fuzz, _flat) = (next()?, next()?, next()?, next()?);
    // Recordings older than evemu 1.1 have no resolution column.
    let resolution = next().unwrap_or(0);
    Some((
        code,
        Axis {
            min,
            max,
            resolution,
        },
    ))
}

/// The device description: `I:` fields (hex).
fn parse_ids(rest: &str) -> Option<[u32; 4]> {
    let mut fields = rest.split_whitespace();
    let mut next = || u32::from_str_radix(fields.next()?, 16).ok();
    Some([next()?, next()?, next()?, next()?])
}

/// A stroke being recorded.
struct Open {
    samples: Vec<Sample>,
    eraser: bool,
}

/// Reads an `evemu-record` recording. See the [module documentation](self).
pub fn read(text: &str) -> Result<(StrokeFile, EvemuStats), EvemuError> {
    let mut lines = text.lines();
    let first = loop {
        match lines.next() {
            None => return Err(EvemuError::Empty),
            Some(l) if l.trim().is_empty() => {}
            Some(l) => break l.trim(),
        }
    };
    let Some(version) = first.strip_prefix(HEADER) else {
        return Err(EvemuError::NotEvemu(first.to_owned()));
    };
    let version = version.trim();
    if version.split('.').next() != Some(SUPPORTED_MAJOR) {
        return Err(EvemuError::UnsupportedVersion(version.to_owned()));
    }
    let mut stats = EvemuStats {
        version: version.to_owned(),
        ..EvemuStats::default()
    };

    let mut name: Option<String> = None;
    let mut ids: Option<[u32; 4]> = None;
    let mut axes: HashMap<u16, Axis> = HashMap::new();
    let mut state = PenState::default();
    let mut frame = PenState::default();
    let mut pending = 0usize;
    // After SYN_DROPPED, events up to and including the next SYN_REPORT are discarded
    // (kernel Documentation/input/event-codes.rst).
    let mut dropping = false;
    let mut t0: Option<i64> = None;
    let mut open: Option<Open> = None;
    let mut finished: Vec<Open> = Vec::new();

    for line in lines {
        // evemu-record comments every event after a '#'.
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let Some((prefix, rest)) = line.split_once(':') else {
            stats.garbage_lines += 1;
            continue;
        };
        match prefix {
            "N" => name = Some(rest.trim().to_owned()),
            "I" => match parse_ids(rest) {
                Some(v) => ids = Some(v),
                None => stats.garbage_lines += 1,
            },
            "A" => match parse_axis(rest) {
                Some((code, axis)) => {
                    axes.insert(code, axis);
                }
                None => stats.garbage_lines += 1,
            },
            "P" | "B" | "L" | "S" | "R" => {}
            "E" => {
                let Some(event) = parse_event(rest) else {
                    stats.garbage_lines += 1;
                    continue;
                };
                stats.events += 1;
                let start = *t0.get_or_insert(event.micros);
                if dropping {
                    if (event.kind, event.code) == (EV_SYN, SYN_REPORT) {
                        dropping = false;
                    }
                    continue;
                }
                if pending == 0 {
                    frame = state;
                }
                pending += 1;
                match (event.kind, event.code) {
                    (EV_SYN, SYN_REPORT) => {
                        pending = 0;
                        stats.frames += 1;
                        let was_touching = state.touch;
                        state = frame;
                        if state.touch && !was_touching {
                            if let Some(stroke) = open.take() {
                                finished.push(stroke);
                            }
                            open = Some(Open {
                                samples: Vec::new(),
                                eraser: state.rubber,
                            });
                        }
                        if !state.touch {
                            if let Some(stroke) = open.take() {
                                finished.push(stroke);
                            }
                            continue;
                        }
                        let t = (event.micros - start) as f64 / MICROS_PER_SECOND as f64;
                        match sample(&state, &axes, t) {
                            Some(s) => {
                                if let Some(stroke) = open.as_mut() {
                                    stroke.samples.push(s);
                                }
                            }
                            None => stats.samples_without_position += 1,
                        }
                    }
                    (EV_SYN, SYN_DROPPED) => {
                        pending = 0;
                        dropping = true;
                        stats.dropped_frames += 1;
                    }
                    (EV_SYN, _) => {}
                    (EV_KEY, BTN_TOUCH) => frame.touch = event.value != 0,
                    (EV_KEY, BTN_TOOL_RUBBER) => frame.rubber = event.value != 0,
                    (EV_KEY, BTN_TOOL_PEN) => {
                        if event.value != 0 {
                            frame.rubber = false;
                        }
                    }
                    (EV_ABS, code) => {
                        let slot = match code {
                            ABS_X => &mut frame.x,
                            ABS_Y => &mut frame.y,
                            ABS_PRESSURE => &mut frame.pressure,
                            ABS_TILT_X => &mut frame.tilt_x,
                            ABS_TILT_Y => &mut frame.tilt_y,
                            _ => {
                                stats.ignored_events += 1;
                                continue;
                            }
                        };
                        match axes.get(&code) {
                            Some(axis) => {
                                if event.value < axis.min || event.value > axis.max {
                                    stats.out_of_range += 1;
                                }
                                *slot = Some(event.value);
                            }
                            // Pressure and tilt cannot be normalised without their range.
                            None if code == ABS_X || code == ABS_Y => *slot = Some(event.value),
                            None => stats.ignored_events += 1,
                        }
                    }
                    _ => stats.ignored_events += 1,
                }
            }
            _ => stats.garbage_lines += 1,
        }
    }
    stats.trailing_events = pending;
    if let Some(stroke) = open.take() {
        stats.unterminated_stroke = true;
        finished.push(stroke);
    }

    let resolution = |code: u16| axes.get(&code).map_or(0, |a| a.resolution);
    let units = if resolution(ABS_X) > 0 && resolution(ABS_Y) > 0 {
        Units::Mm
    } else {
        Units::Device
    };
    let mut strokes = Vec::new();
    for stroke in finished {
        let samples = stroke
            .samples
            .into_iter()
            .map(|mut s| {
                if units == Units::Mm {
                    s.x /= resolution(ABS_X) as f64;
                    s.y /= resolution(ABS_Y) as f64;
                }
                s
            })
            .collect();
        let candidate = Stroke::new(samples);
        match candidate.validate(strokes.len()) {
            Ok(()) => {
                strokes.push(candidate);
                stats.eraser.push(stroke.eraser);
            }
            Err(StrokeError::TooFewSamples { .. }) => stats.short_strokes += 1,
            Err(source) => {
                return Err(EvemuError::Invalid {
                    stroke: strokes.len(),
                    source,
                });
            }
        }
    }

    let mut file = StrokeFile::new(units, strokes);
    file.source = Some(format!("evemu recording (EVEMU {version})"));
    let axis_json = |code: u16| {
        axes.get(&code)
            .map(|a| json!({"min": a.min, "max": a.max, "resolution": a.resolution}))
    };
    file.device = Some(json!({
        "name": name,
        "bus": ids.map(|i| i[0]),
        "vendor": ids.map(|i| i[1]),
        "product": ids.map(|i| i[2]),
        "version": ids.map(|i| i[3]),
        "abs_x": axis_json(ABS_X),
        "abs_y": axis_json(ABS_Y),
        "abs_pressure": axis_json(ABS_PRESSURE),
    }));
    Ok((file, stats))
}

/// The sample of a touching frame, in raw position counts (scaled to mm later), or `None`
/// when no position is known yet.
fn sample(state: &PenState, axes: &HashMap<u16, Axis>, t: f64) -> Option<Sample> {
    let (x, y) = (state.x?, state.y?);
    let mut s = Sample::new(x as f64, y as f64).with_t(t);
    if let (Some(p), Some(axis)) = (state.pressure, axes.get(&ABS_PRESSURE))
        && axis.max > axis.min
    {
        let clamped = p.clamp(axis.min, axis.max);
        s.pressure = Some((clamped - axis.min) as f64 / (axis.max - axis.min) as f64);
    }
    let tilt = |v: Option<i64>, code: u16| {
        let (v, axis) = (v?, axes.get(&code)?);
        Some(if axis.resolution > 0 {
            (v as f64 / axis.resolution as f64).to_degrees()
        } else {
            v as f64
        })
    };
    s.tilt_x = tilt(state.tilt_x, ABS_TILT_X);
    s.tilt_y = tilt(state.tilt_y, ABS_TILT_Y);
    Some(s)
}
