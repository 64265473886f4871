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
//! Old recordings (evemu before 1.10, and most of the evemu-devices collection) keep the device
//! description (`N:`, `I:`, `P:`, `B:`, `A:` lines, as `evemu-describe` prints them) in a file
//! of its own, `NAME.desc`, and the events (`E:` lines only, no header) in `NAME.events` or
//! `NAME.DESC.events`: [`EvemuRecording::parse_description`] and
//! [`EvemuRecording::with_events`] put such a pair together, and
//! [`crate::io::read_strokes`] finds the `.desc` next to the events file.
//!
//! This module only parses the text ([`EvemuRecording::parse`]: the `A:` axis table and the
//! `E:` events as (line, time, type, code, value)). [`read`] then feeds the events through
//! [`EvdevPen`], the frame decoder the live evdev source uses, and the pen reports through the
//! [`StrokeBuilder`] every source uses: a recording replays exactly as the tablet would have
//! been captured live.
//!
//! Events are grouped into frames ended by `SYN_REPORT` (type 0, code 0). Axis values persist:
//! an axis absent from a frame keeps its previous value (evdev only reports changes). A stroke
//! is a `BTN_TOUCH` down…up run: every frame ending with the pen touching gives one sample
//! (the frame that lifts the pen gives none). Strokes drawn while `BTN_TOOL_RUBBER` is the
//! active tool are kept and marked, in [`EvemuStats::eraser`] and in the file's
//! `device.eraser_strokes` (stroke indices), as HID replay marks them.
//!
//! - **Positions**: `ABS_X`/`ABS_Y` divided by their resolution (units per mm, per the kernel's
//!   `input_absinfo`), giving [`Units::Mm`](crate::stroke::Units::Mm);
//!   [`Units::Device`](crate::stroke::Units::Device) counts when either resolution is 0 or the
//!   axis is not declared.
//! - **Time**: seconds since the recording's first event. Time going backwards within a
//!   stroke is an error ([`EvemuError::Invalid`]): a recording's clock is the kernel's.
//! - **Pressure**: `(v - min) / (max - min)` of the `ABS_PRESSURE` axis.
//! - **Out of range**: a value outside its axis's declared `min..=max` is not used; the frame
//!   holding it gives no sample ([`EvemuStats::rejected_frames`]) and the value is counted
//!   ([`EvemuStats::out_of_range`]) with its line ([`EvemuStats::warnings`]).
//! - **Tilt**: `ABS_TILT_X`/`ABS_TILT_Y` in degrees. The kernel documents their resolution in
//!   units per radian, so `degrees = (v / resolution).to_degrees()`; with resolution 0 the raw
//!   value is taken as degrees (Wacom tablets report about one unit per degree, and their
//!   drivers declare 57 units/rad ≈ 1 unit/degree).
//!
//! Nothing in a recording panics the reader: lines that do not parse, values beyond 32 bits and
//! events this reader does not use are skipped and counted in [`EvemuStats`], the first
//! [`MAX_KEPT_WARNINGS`] with their line numbers. A truncated recording reads up to its last
//! complete frame; a stroke still touching at the end is kept.

use std::collections::BTreeMap;

use serde_json::json;
use thiserror::Error;

pub use crate::capture::evdev_frames::{
    ABS_PRESSURE, ABS_TILT_X, ABS_TILT_Y, ABS_X, ABS_Y, BTN_STYLUS, BTN_STYLUS2, BTN_TOOL_PEN,
    BTN_TOOL_RUBBER, BTN_TOUCH, EV_ABS, EV_KEY, EV_SYN, SYN_DROPPED, SYN_REPORT,
};
use crate::capture::evdev_frames::{
    AbsAxis, EvdevAxes, EvdevOutcome, EvdevPen, FrameEnd, OutOfRange,
};
use crate::capture::stroke_builder::{BuiltStroke, StrokeBuilder, Tool};
use crate::stroke::{Stroke, StrokeError, StrokeFile};

/// The header's first line starts with this.
const HEADER: &str = "# EVEMU ";
/// The format major version read: evemu 1.x (1.0 to 1.3 differ only in optional lines).
const SUPPORTED_MAJOR: &str = "1";
/// The format version of a description without a header (evemu's rule).
const VERSION_WITHOUT_HEADER: &str = "1.0";
/// Microseconds per second, for the `sec.usec` timestamps.
const MICROS_PER_SECOND: i64 = 1_000_000;
/// Warnings kept with their line numbers; later ones are only counted (a damaged recording
/// can have one per line, and a user needs the first few to find the damage).
pub const MAX_KEPT_WARNINGS: usize = 100;

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
    /// A device description with a line that does not parse (a description is a few dozen
    /// lines written by `evemu-describe`: a damaged one is refused rather than guessed at).
    #[error("device description, line {0}: the line does not parse")]
    BadDescription(usize),
    /// A device description with no `N:`, `I:` or `A:` line: not a description.
    #[error("not an evemu device description: no N:, I: or A: lines")]
    NoDescription,
    /// A stroke breaks the stroke rules (time going backwards, coordinates beyond range).
    #[error("stroke {stroke}: {source}")]
    Invalid {
        /// Stroke index among the strokes kept.
        stroke: usize,
        /// The rule broken.
        source: StrokeError,
    },
}

/// Why a line or an event was skipped.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum EvemuProblem {
    /// The line does not parse (unknown prefix, malformed or truncated `A:`/`E:`/`I:` line,
    /// a value beyond 32 bits, a timestamp that is not `sec.usec`).
    #[error("line does not parse")]
    Garbage,
    /// An axis value outside its declared range: its frame gives no sample.
    #[error("{0}; the frame gives no sample")]
    OutOfRange(OutOfRange),
    /// `SYN_DROPPED`: the kernel's buffer overran; the frame is discarded.
    #[error("SYN_DROPPED: the frame is discarded")]
    Dropped,
}

/// A skipped line or event, with its 1-based line number.
#[derive(Clone, Debug, PartialEq)]
pub struct EvemuWarning {
    /// 1-based line number in the recording.
    pub line: usize,
    /// What was wrong.
    pub problem: EvemuProblem,
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
    /// Axis values outside their declared min..max: not used.
    pub out_of_range: usize,
    /// Frames that gave no sample because they held a value out of range.
    pub rejected_frames: usize,
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
    /// The first [`MAX_KEPT_WARNINGS`] garbage lines, out-of-range values and dropped frames,
    /// with their line numbers, in the order met.
    pub warnings: Vec<EvemuWarning>,
}

impl EvemuStats {
    /// Every skipped line, value and frame and every dropped stroke or sample.
    pub fn skipped(&self) -> usize {
        self.garbage_lines
            + self.out_of_range
            + self.dropped_frames
            + self.trailing_events
            + self.samples_without_position
            + self.short_strokes
    }

    fn warn(&mut self, line: usize, problem: EvemuProblem) {
        if self.warnings.len() < MAX_KEPT_WARNINGS {
            self.warnings.push(EvemuWarning { line, problem });
        }
    }
}

/// One `E:` line: an input event as the kernel delivered it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EvemuEvent {
    /// 1-based line number in the recording.
    pub line: usize,
    /// The timestamp, microseconds.
    pub micros: i64,
    /// Event type (`EV_SYN`, `EV_KEY`, `EV_ABS`, ...).
    pub kind: u16,
    /// Event code.
    pub code: u16,
    /// Value (evdev values are 32-bit signed).
    pub value: i32,
}

/// A parsed recording: the header and the events, not yet decoded.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EvemuRecording {
    /// The header's format version, e.g. `1.3`.
    pub version: String,
    /// The device name (`N:`).
    pub name: Option<String>,
    /// Bus, vendor, product, version (`I:`).
    pub ids: Option<[u32; 4]>,
    /// Every `A:` axis by code (the last line for a code wins).
    pub axes: BTreeMap<u16, AbsAxis>,
    /// Every well-formed `E:` line, in order.
    pub events: Vec<EvemuEvent>,
    /// 1-based numbers of the lines that did not parse.
    pub garbage_lines: Vec<usize>,
    /// The device description's file name, when it came from a file of its own
    /// ([`EvemuRecording::with_events`]).
    pub description: Option<String>,
}

fn parse_event(line: usize, rest: &str) -> Option<EvemuEvent> {
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
    Some(EvemuEvent {
        line,
        micros,
        kind: u16::from_str_radix(kind, 16).ok()?,
        code: u16::from_str_radix(code, 16).ok()?,
        value: value.parse::<i32>().ok()?,
    })
}

fn parse_axis(rest: &str) -> Option<(u16, AbsAxis)> {
    let mut fields = rest.split_whitespace();
    let code = u16::from_str_radix(fields.next()?, 16).ok()?;
    let mut next = || -> Option<i32> { fields.next()?.parse::<i32>().ok() };
    let (min, max, _fuzz, _flat) = (next()?, next()?, next()?, next()?);
    // Recordings older than evemu 1.1 have no resolution column.
    let resolution = next().unwrap_or(0);
    Some((
        code,
        AbsAxis {
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

impl EvemuRecording {
    /// Parses the header and the lines; errors only for a text that is not an evemu 1.x
    /// recording. Lines that do not parse are kept in [`EvemuRecording::garbage_lines`].
    pub fn parse(text: &str) -> Result<EvemuRecording, EvemuError> {
        let mut lines = text.lines().enumerate();
        let first = loop {
            match lines.next() {
                None => return Err(EvemuError::Empty),
                Some((_, l)) if l.trim().is_empty() => {}
                Some((_, l)) => break l.trim(),
            }
        };
        let Some(version) = first.strip_prefix(HEADER) else {
            return Err(EvemuError::NotEvemu(first.to_owned()));
        };
        let version = version.trim();
        if version.split('.').next() != Some(SUPPORTED_MAJOR) {
            return Err(EvemuError::UnsupportedVersion(version.to_owned()));
        }
        let mut rec = EvemuRecording {
            version: version.to_owned(),
            ..EvemuRecording::default()
        };
        rec.parse_lines(lines);
        Ok(rec)
    }

    /// Parses a device description as `evemu-describe` writes it (a `.desc` file): the
    /// `# EVEMU` header is optional (evemu assumes format 1.0 without it); `E:` lines, if any,
    /// are not kept. A line that does not parse, or no `N:`, `I:` or `A:` line at all, is an
    /// error: the description decides the units and ranges of everything after it.
    pub fn parse_description(text: &str) -> Result<EvemuRecording, EvemuError> {
        let first = text.lines().map(str::trim).find(|l| !l.is_empty());
        let mut rec = match first {
            Some(line) if line.starts_with(HEADER) => EvemuRecording::parse(text)?,
            _ => {
                let mut rec = EvemuRecording {
                    version: VERSION_WITHOUT_HEADER.to_owned(),
                    ..EvemuRecording::default()
                };
                rec.parse_lines(text.lines().enumerate());
                rec
            }
        };
        if let Some(&line) = rec.garbage_lines.first() {
            return Err(EvemuError::BadDescription(line));
        }
        if rec.name.is_none() && rec.ids.is_none() && rec.axes.is_empty() {
            return Err(EvemuError::NoDescription);
        }
        rec.events.clear();
        Ok(rec)
    }

    /// This description (from [`EvemuRecording::parse_description`], read from the file named
    /// `description`) with the events of a header-less events file (`E:` lines; their line
    /// numbers are the events file's). `N:`, `I:` and `A:` lines in the events file, if any,
    /// override the description's.
    pub fn with_events(
        mut self,
        events: &str,
        description: &str,
    ) -> Result<EvemuRecording, EvemuError> {
        if events.trim().is_empty() {
            return Err(EvemuError::Empty);
        }
        self.events.clear();
        self.garbage_lines.clear();
        self.parse_lines(events.lines().enumerate());
        self.description = Some(description.to_owned());
        Ok(self)
    }

    /// Parses `(index, line)` pairs (0-based indices) into the fields.
    fn parse_lines<'a>(&mut self, lines: impl Iterator<Item = (usize, &'a str)>) {
        let rec = self;
        for (i, line) in lines {
            let line_no = i + 1;
            // evemu-record comments every event after a '#'.
            let line = line.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let parsed = line
                .split_once(':')
                .and_then(|(prefix, rest)| match prefix {
                    "N" => {
                        rec.name = Some(rest.trim().to_owned());
                        Some(())
                    }
                    "I" => parse_ids(rest).map(|v| rec.ids = Some(v)),
                    "A" => parse_axis(rest).map(|(code, axis)| {
                        rec.axes.insert(code, axis);
                    }),
                    "P" | "B" | "L" | "S" | "R" => Some(()),
                    "E" => parse_event(line_no, rest).map(|e| rec.events.push(e)),
                    _ => None,
                });
            if parsed.is_none() {
                rec.garbage_lines.push(line_no);
            }
        }
    }

    /// The pen axes as the frame decoder takes them: X and Y default to an empty range with
    /// resolution 0 (device counts, not range-checked) when the recording does not declare them.
    pub fn pen_axes(&self) -> EvdevAxes {
        let axis = |code: u16| self.axes.get(&code).copied();
        EvdevAxes {
            x: axis(ABS_X).unwrap_or_default(),
            y: axis(ABS_Y).unwrap_or_default(),
            pressure: axis(ABS_PRESSURE),
            tilt_x: axis(ABS_TILT_X),
            tilt_y: axis(ABS_TILT_Y),
        }
    }
}

/// Reads an `evemu-record` recording. See the [module documentation](self).
pub fn read(text: &str) -> Result<(StrokeFile, EvemuStats), EvemuError> {
    replay(&EvemuRecording::parse(text)?)
}

/// A parsed recording through the live path's frame decoder ([`EvdevPen`]) and the
/// [`StrokeBuilder`] into a `kansei-stroke` file.
pub fn replay(rec: &EvemuRecording) -> Result<(StrokeFile, EvemuStats), EvemuError> {
    let mut stats = EvemuStats {
        version: rec.version.clone(),
        events: rec.events.len(),
        garbage_lines: rec.garbage_lines.len(),
        ..EvemuStats::default()
    };
    // Warnings in line order: garbage lines and event problems merged.
    let mut garbage = rec.garbage_lines.iter().copied().peekable();
    let mut warn_garbage_before = |stats: &mut EvemuStats, line: usize| {
        while let Some(g) = garbage.next_if(|&g| g < line) {
            stats.warn(g, EvemuProblem::Garbage);
        }
    };
    let axes = rec.pen_axes();
    let mut pen = EvdevPen::new(axes);
    let mut builder = StrokeBuilder::new();
    let mut finished: Vec<BuiltStroke> = Vec::new();
    let t0 = rec.events.first().map_or(0, |e| e.micros);
    for event in &rec.events {
        warn_garbage_before(&mut stats, event.line);
        match pen.feed(event.kind, event.code, event.value) {
            EvdevOutcome::OutOfRange(o) => stats.warn(event.line, EvemuProblem::OutOfRange(o)),
            EvdevOutcome::Dropped => stats.warn(event.line, EvemuProblem::Dropped),
            EvdevOutcome::Frame(FrameEnd::Report(report)) => {
                let t = (event.micros - t0) as f64 / MICROS_PER_SECOND as f64;
                let tool = if report.is_eraser() {
                    Tool::Eraser
                } else {
                    Tool::Pen
                };
                if report.contact
                    && let Some(run) = builder.current().filter(|run| run.tool == tool)
                    && let Some(previous) = run.stroke.samples.last().and_then(|s| s.t)
                    && t < previous
                {
                    // Finished strokes are taken after every push: this run is the next.
                    let stroke = finished.len();
                    return Err(EvemuError::Invalid {
                        stroke,
                        source: StrokeError::TimeBackwards {
                            stroke,
                            sample: run.stroke.samples.len(),
                            t,
                            previous,
                        },
                    });
                }
                builder.push(t, &report);
                finished.extend(builder.take_finished());
            }
            _ => {}
        }
    }
    warn_garbage_before(&mut stats, usize::MAX);
    let pen_stats = pen.stats();
    stats.frames = pen_stats.frames;
    stats.ignored_events = pen_stats.ignored_events;
    stats.out_of_range = pen_stats.out_of_range;
    stats.rejected_frames = pen_stats.rejected_frames;
    stats.dropped_frames = pen_stats.dropped_frames;
    stats.samples_without_position = pen_stats.touching_without_position;
    stats.trailing_events = pen.pending_events();
    stats.unterminated_stroke = pen.touching();
    let (rest, builder_stats) = builder.finish();
    finished.extend(rest);
    stats.short_strokes = builder_stats.short_runs_dropped;

    let mut strokes: Vec<Stroke> = Vec::with_capacity(finished.len());
    for built in finished {
        built
            .stroke
            .validate(strokes.len())
            .map_err(|source| EvemuError::Invalid {
                stroke: strokes.len(),
                source,
            })?;
        stats.eraser.push(built.tool == Tool::Eraser);
        strokes.push(built.stroke);
    }
    let eraser_strokes: Vec<usize> = (stats.eraser.iter().enumerate())
        .filter(|(_, eraser)| **eraser)
        .map(|(i, _)| i)
        .collect();

    let mut file = StrokeFile::new(axes.units(), strokes);
    file.source = Some(match &rec.description {
        None => format!("evemu recording (EVEMU {})", rec.version),
        Some(desc) => format!(
            "evemu recording (EVEMU {}, device description from {desc})",
            rec.version
        ),
    });
    let axis_json = |code: u16| {
        rec.axes
            .get(&code)
            .map(|a| json!({"min": a.min, "max": a.max, "resolution": a.resolution}))
    };
    let ids = rec.ids;
    file.device = Some(json!({
        "name": rec.name,
        "bus": ids.map(|i| i[0]),
        "vendor": ids.map(|i| i[1]),
        "product": ids.map(|i| i[2]),
        "version": ids.map(|i| i[3]),
        "abs_x": axis_json(ABS_X),
        "abs_y": axis_json(ABS_Y),
        "abs_pressure": axis_json(ABS_PRESSURE),
        "eraser_strokes": eraser_strokes,
    }));
    Ok((file, stats))
}
