//! Linux input events turned into [`PenReport`]s, one per frame, so that evdev tablets go
//! through the same [`StrokeBuilder`](crate::capture::stroke_builder::StrokeBuilder) as HID
//! ones: [`EvdevPen`]. Pure (no device access): the live evdev source feeds it.
//!
//! This is the one evdev decoder: the live source ([`crate::capture::live_evdev`], feature
//! `live`) and the evemu reader ([`crate::capture::evemu`]) both feed it, so every evemu
//! recording is a test of the live path. Events are grouped into frames ended by `SYN_REPORT`;
//! axis values persist between frames (evdev reports changes only); `BTN_TOUCH` is contact;
//! `BTN_TOOL_RUBBER` marks the eraser (cleared by `BTN_TOOL_PEN`); `BTN_STYLUS` and
//! `BTN_STYLUS2` are the barrel buttons; after `SYN_DROPPED` the events up to and including the
//! next `SYN_REPORT` are discarded. An axis value outside the range the device declares
//! (`min..=max`, when `max > min`) is not taken: the axis keeps its previous value and the frame
//! gives no report ([`FrameEnd::Rejected`]); its buttons still apply. Each other `SYN_REPORT`
//! with X and Y known gives one report:
//!
//! - position: `ABS_X`/`ABS_Y` divided by their resolution (units/mm), or raw counts when a
//!   resolution is 0 ([`EvdevAxes::units`] is then [`Units::Device`]);
//! - pressure: `(v - min) / (max - min)`, in 0..1 (the range is checked);
//! - tilt: `(v / resolution).to_degrees()` (the kernel gives tilt resolution in units/radian),
//!   or `v` as degrees with resolution 0.
//!
//! The report's `tip` and `contact` are `BTN_TOUCH`; `invert` and `eraser` are the rubber tool
//! (`eraser` only while touching); `in_range` is either tool in proximity; `barrel` is
//! (`BTN_STYLUS`, `BTN_STYLUS2`). Every event's [`EvdevOutcome`] says what became of it, and
//! [`EvdevStats`] counts them, so that a reader can name the lines it skipped.

use thiserror::Error;

use crate::capture::hid::PenReport;
use crate::stroke::Units;

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
/// `BTN_STYLUS`: the first barrel button.
pub const BTN_STYLUS: u16 = 0x14b;
/// `BTN_STYLUS2`: the second barrel button.
pub const BTN_STYLUS2: u16 = 0x14c;
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

/// An absolute axis as the kernel declares it (`input_absinfo`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AbsAxis {
    /// Minimum value.
    pub min: i32,
    /// Maximum value.
    pub max: i32,
    /// Resolution: units per mm for X/Y, units per radian for tilt.
    pub resolution: i32,
}

/// The pen axes of an evdev device.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EvdevAxes {
    /// `ABS_X`.
    pub x: AbsAxis,
    /// `ABS_Y`.
    pub y: AbsAxis,
    /// `ABS_PRESSURE`, if the device has it.
    pub pressure: Option<AbsAxis>,
    /// `ABS_TILT_X`.
    pub tilt_x: Option<AbsAxis>,
    /// `ABS_TILT_Y`.
    pub tilt_y: Option<AbsAxis>,
}

impl AbsAxis {
    /// Whether `value` keeps to the declared range; always, when the range is empty
    /// (`max <= min`: an axis not declared, or declared without a range).
    pub fn admits(&self, value: i32) -> bool {
        self.max <= self.min || (self.min..=self.max).contains(&value)
    }
}

impl EvdevAxes {
    /// [`Units::Mm`] when both X and Y have a resolution, else [`Units::Device`].
    pub fn units(&self) -> Units {
        if self.x.resolution > 0 && self.y.resolution > 0 {
            Units::Mm
        } else {
            Units::Device
        }
    }

    /// Active area (width, height) in mm, when the resolutions are known.
    pub fn size_mm(&self) -> Option<(f64, f64)> {
        (self.units() == Units::Mm).then(|| {
            let mm = |a: &AbsAxis| f64::from(a.max - a.min) / f64::from(a.resolution);
            (mm(&self.x), mm(&self.y))
        })
    }
}

/// An axis value outside the range the device declares.
#[derive(Clone, Copy, Debug, Error, PartialEq, Eq)]
#[error("{axis} = {value} is outside the declared range {min}..={max}")]
pub struct OutOfRange {
    /// The axis name (`ABS_X`, `ABS_PRESSURE`, ...).
    pub axis: &'static str,
    /// The value read.
    pub value: i32,
    /// The declared minimum.
    pub min: i32,
    /// The declared maximum.
    pub max: i32,
}

/// How a `SYN_REPORT` ended a frame.
#[derive(Clone, Debug, PartialEq)]
pub enum FrameEnd {
    /// The pen's state after the frame.
    Report(PenReport),
    /// No `ABS_X`/`ABS_Y` value is known yet: no report. `touching` when `BTN_TOUCH` was down
    /// (a sample lost, counted in [`EvdevStats::touching_without_position`]).
    NoPosition {
        /// Whether the pen touched.
        touching: bool,
    },
    /// The frame had a value out of range: no report (the frame's buttons still apply).
    Rejected,
}

/// What became of one event fed to [`EvdevPen::feed`].
#[derive(Clone, Debug, PartialEq)]
pub enum EvdevOutcome {
    /// Taken into the frame being assembled.
    Pending,
    /// A well-formed event the decoder does not use: other types and codes, or pressure and
    /// tilt on a device that does not declare those axes (they cannot be scaled).
    Ignored,
    /// An axis value outside its declared range: not taken, and the frame gives no report.
    OutOfRange(OutOfRange),
    /// `SYN_DROPPED`: the frame so far is discarded, and so are the events after it up to and
    /// including the next `SYN_REPORT`.
    Dropped,
    /// An event discarded after a `SYN_DROPPED`.
    Discarded,
    /// A `SYN_REPORT` ended a frame.
    Frame(FrameEnd),
}

/// What [`EvdevPen`] has seen so far.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EvdevStats {
    /// Frames ended by `SYN_REPORT` (those discarded after a `SYN_DROPPED` not counted).
    pub frames: usize,
    /// `SYN_DROPPED` markers.
    pub dropped_frames: usize,
    /// Axis values outside their declared range.
    pub out_of_range: usize,
    /// Frames that gave no report because of an out-of-range value.
    pub rejected_frames: usize,
    /// Events not used ([`EvdevOutcome::Ignored`]).
    pub ignored_events: usize,
    /// Frames with `BTN_TOUCH` down before any X/Y value was known.
    pub touching_without_position: usize,
}

#[derive(Clone, Copy, Debug, Default)]
struct State {
    x: Option<i32>,
    y: Option<i32>,
    pressure: Option<i32>,
    tilt_x: Option<i32>,
    tilt_y: Option<i32>,
    touch: bool,
    pen: bool,
    rubber: bool,
    stylus: bool,
    stylus2: bool,
}

/// Frames of evdev events into pen reports; see the module documentation.
#[derive(Clone, Debug)]
pub struct EvdevPen {
    axes: EvdevAxes,
    state: State,
    frame: State,
    dropping: bool,
    /// The frame being assembled holds an out-of-range value.
    rejected: bool,
    /// Events in the frame being assembled.
    pending: usize,
    stats: EvdevStats,
}

impl EvdevPen {
    /// A decoder for a device with these axes.
    pub fn new(axes: EvdevAxes) -> Self {
        EvdevPen {
            axes,
            state: State::default(),
            frame: State::default(),
            dropping: false,
            rejected: false,
            pending: 0,
            stats: EvdevStats::default(),
        }
    }

    /// Feeds one event (`type`, `code`, `value`); a report when it ends a frame with a known
    /// position and no value out of range. [`EvdevPen::feed`] says what became of every event.
    pub fn event(&mut self, kind: u16, code: u16, value: i32) -> Option<PenReport> {
        match self.feed(kind, code, value) {
            EvdevOutcome::Frame(FrameEnd::Report(report)) => Some(report),
            _ => None,
        }
    }

    /// Feeds one event (`type`, `code`, `value`) and says what became of it.
    pub fn feed(&mut self, kind: u16, code: u16, value: i32) -> EvdevOutcome {
        if self.dropping {
            if (kind, code) == (EV_SYN, SYN_REPORT) {
                self.dropping = false;
                self.frame = self.state;
            }
            return EvdevOutcome::Discarded;
        }
        let outcome = match (kind, code) {
            (EV_SYN, SYN_REPORT) => return EvdevOutcome::Frame(self.end_frame()),
            (EV_SYN, SYN_DROPPED) => {
                self.dropping = true;
                self.rejected = false;
                self.pending = 0;
                self.frame = self.state;
                self.stats.dropped_frames += 1;
                return EvdevOutcome::Dropped;
            }
            // Other SYN codes (SYN_CONFIG, SYN_MT_REPORT) carry nothing for a pen.
            (EV_SYN, _) => EvdevOutcome::Pending,
            (EV_KEY, BTN_TOUCH) => self.key(|s| &mut s.touch, value),
            (EV_KEY, BTN_STYLUS) => self.key(|s| &mut s.stylus, value),
            (EV_KEY, BTN_STYLUS2) => self.key(|s| &mut s.stylus2, value),
            (EV_KEY, BTN_TOOL_RUBBER) => self.key(|s| &mut s.rubber, value),
            (EV_KEY, BTN_TOOL_PEN) => {
                if value != 0 {
                    self.frame.rubber = false;
                }
                self.key(|s| &mut s.pen, value)
            }
            (EV_ABS, ABS_X) => self.axis("ABS_X", Some(self.axes.x), |s| &mut s.x, value),
            (EV_ABS, ABS_Y) => self.axis("ABS_Y", Some(self.axes.y), |s| &mut s.y, value),
            (EV_ABS, ABS_PRESSURE) => self.axis(
                "ABS_PRESSURE",
                self.axes.pressure,
                |s| &mut s.pressure,
                value,
            ),
            (EV_ABS, ABS_TILT_X) => {
                self.axis("ABS_TILT_X", self.axes.tilt_x, |s| &mut s.tilt_x, value)
            }
            (EV_ABS, ABS_TILT_Y) => {
                self.axis("ABS_TILT_Y", self.axes.tilt_y, |s| &mut s.tilt_y, value)
            }
            _ => EvdevOutcome::Ignored,
        };
        match &outcome {
            EvdevOutcome::Ignored => self.stats.ignored_events += 1,
            EvdevOutcome::OutOfRange(_) => {
                self.stats.out_of_range += 1;
                self.rejected = true;
            }
            _ => {}
        }
        self.pending += 1;
        outcome
    }

    fn key(&mut self, slot: impl Fn(&mut State) -> &mut bool, value: i32) -> EvdevOutcome {
        *slot(&mut self.frame) = value != 0;
        EvdevOutcome::Pending
    }

    fn axis(
        &mut self,
        name: &'static str,
        axis: Option<AbsAxis>,
        slot: impl Fn(&mut State) -> &mut Option<i32>,
        value: i32,
    ) -> EvdevOutcome {
        let Some(axis) = axis else {
            return EvdevOutcome::Ignored;
        };
        if !axis.admits(value) {
            return EvdevOutcome::OutOfRange(OutOfRange {
                axis: name,
                value,
                min: axis.min,
                max: axis.max,
            });
        }
        *slot(&mut self.frame) = Some(value);
        EvdevOutcome::Pending
    }

    fn end_frame(&mut self) -> FrameEnd {
        self.state = self.frame;
        self.pending = 0;
        self.stats.frames += 1;
        if std::mem::take(&mut self.rejected) {
            self.stats.rejected_frames += 1;
            return FrameEnd::Rejected;
        }
        match self.report() {
            Some(report) => FrameEnd::Report(report),
            None => {
                let touching = self.state.touch;
                if touching {
                    self.stats.touching_without_position += 1;
                }
                FrameEnd::NoPosition { touching }
            }
        }
    }

    /// What was seen so far.
    pub fn stats(&self) -> EvdevStats {
        self.stats
    }

    /// Events fed since the last frame ended (a recording cut mid-frame leaves some).
    pub fn pending_events(&self) -> usize {
        self.pending
    }

    /// Whether `BTN_TOUCH` was down after the last complete frame.
    pub fn touching(&self) -> bool {
        self.state.touch
    }

    /// The axes this decoder scales by.
    pub fn axes(&self) -> &EvdevAxes {
        &self.axes
    }

    fn report(&self) -> Option<PenReport> {
        let s = &self.state;
        let (x, y) = (s.x?, s.y?);
        let position = |v: i32, a: &AbsAxis| {
            if self.axes.units() == Units::Mm {
                f64::from(v) / f64::from(a.resolution)
            } else {
                f64::from(v)
            }
        };
        let pressure = self.axes.pressure.zip(s.pressure).map(|(a, v)| {
            let span = f64::from(a.max) - f64::from(a.min);
            if span > 0.0 {
                // In range (checked when taken), so 0..1; the clamp only guards rounding.
                ((f64::from(v) - f64::from(a.min)) / span).clamp(0.0, 1.0)
            } else {
                0.0
            }
        });
        let tilt = |a: Option<AbsAxis>, v: Option<i32>| {
            a.zip(v).map(|(a, v)| {
                if a.resolution > 0 {
                    (f64::from(v) / f64::from(a.resolution)).to_degrees()
                } else {
                    f64::from(v)
                }
            })
        };
        Some(PenReport {
            report_id: 0,
            in_range: s.pen || s.rubber,
            tip: s.touch,
            barrel: [s.stylus, s.stylus2],
            invert: s.rubber,
            eraser: s.rubber && s.touch,
            contact: s.touch,
            x_mm: position(x, &self.axes.x),
            y_mm: position(y, &self.axes.y),
            pressure,
            tilt_x_deg: tilt(self.axes.tilt_x, s.tilt_x),
            tilt_y_deg: tilt(self.axes.tilt_y, s.tilt_y),
            raw_x: i64::from(x),
            raw_y: i64::from(y),
            raw_pressure: s.pressure.map(i64::from),
            raw_tilt_x: s.tilt_x.map(i64::from),
            raw_tilt_y: s.tilt_y.map(i64::from),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An Intuos-like pen: 200 counts/mm over 0..44800 × 0..29600, pressure 0..8191.
    fn pen() -> EvdevPen {
        let position = |max| AbsAxis {
            min: 0,
            max,
            resolution: 200,
        };
        EvdevPen::new(EvdevAxes {
            x: position(44800),
            y: position(29600),
            pressure: Some(AbsAxis {
                min: 0,
                max: 8191,
                resolution: 0,
            }),
            tilt_x: None,
            tilt_y: None,
        })
    }

    /// Feeds `events` then a `SYN_REPORT`; the frame's end.
    fn frame(pen: &mut EvdevPen, events: &[(u16, u16, i32)]) -> FrameEnd {
        for &(kind, code, value) in events {
            let outcome = pen.feed(kind, code, value);
            assert!(!matches!(outcome, EvdevOutcome::Frame(_)), "{outcome:?}");
        }
        match pen.feed(EV_SYN, SYN_REPORT, 0) {
            EvdevOutcome::Frame(end) => end,
            other => panic!("{other:?}"),
        }
    }

    fn report(end: FrameEnd) -> PenReport {
        match end {
            FrameEnd::Report(r) => r,
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn barrel_buttons_are_decoded_and_carried_between_frames() {
        let mut pen = pen();
        let hover = [
            (EV_KEY, BTN_TOOL_PEN, 1),
            (EV_ABS, ABS_X, 2000),
            (EV_ABS, ABS_Y, 1000),
        ];
        let r = report(frame(&mut pen, &hover));
        assert_eq!(r.barrel, [false, false]);
        assert!(r.in_range && !r.contact);
        let r = report(frame(&mut pen, &[(EV_KEY, BTN_STYLUS, 1)]));
        assert_eq!(r.barrel, [true, false]);
        // Held across a frame that only moves the pen.
        let r = report(frame(&mut pen, &[(EV_ABS, ABS_X, 2200)]));
        assert_eq!((r.barrel, r.x_mm), ([true, false], 11.0));
        let r = report(frame(&mut pen, &[(EV_KEY, BTN_STYLUS2, 1)]));
        assert_eq!(r.barrel, [true, true]);
        let r = report(frame(&mut pen, &[(EV_KEY, BTN_STYLUS, 0)]));
        assert_eq!(r.barrel, [false, true]);
        // Buttons do not make contact or the eraser.
        assert!(!r.contact && !r.is_eraser());
        assert_eq!(pen.stats().ignored_events, 0);
    }

    #[test]
    fn out_of_range_values_are_not_taken_and_reject_their_frame() {
        let mut pen = pen();
        let down = [
            (EV_KEY, BTN_TOUCH, 1),
            (EV_ABS, ABS_X, 2000),
            (EV_ABS, ABS_Y, 1000),
            (EV_ABS, ABS_PRESSURE, 4095),
        ];
        let r = report(frame(&mut pen, &down));
        assert_eq!((r.x_mm, r.y_mm), (10.0, 5.0));
        assert_eq!(r.pressure, Some(4095.0 / 8191.0));
        assert_eq!(
            pen.feed(EV_ABS, ABS_X, i32::MAX),
            EvdevOutcome::OutOfRange(OutOfRange {
                axis: "ABS_X",
                value: i32::MAX,
                min: 0,
                max: 44800
            })
        );
        assert!(matches!(
            pen.feed(EV_ABS, ABS_PRESSURE, 8192),
            EvdevOutcome::OutOfRange(OutOfRange {
                axis: "ABS_PRESSURE",
                ..
            })
        ));
        // The frame's other events still apply: Y moves.
        assert_eq!(pen.feed(EV_ABS, ABS_Y, 1200), EvdevOutcome::Pending);
        assert_eq!(
            pen.feed(EV_SYN, SYN_REPORT, 0),
            EvdevOutcome::Frame(FrameEnd::Rejected)
        );
        // The next frame reports the values kept: X and pressure as before, the new Y.
        let r = report(frame(&mut pen, &[]));
        assert_eq!((r.raw_x, r.raw_y, r.raw_pressure), (2000, 1200, Some(4095)));
        // The range's ends are in range.
        let r = report(frame(
            &mut pen,
            &[(EV_ABS, ABS_X, 44800), (EV_ABS, ABS_PRESSURE, 0)],
        ));
        assert_eq!((r.x_mm, r.pressure), (224.0, Some(0.0)));
        let stats = pen.stats();
        assert_eq!(
            (stats.out_of_range, stats.rejected_frames, stats.frames),
            (2, 1, 4)
        );
    }

    #[test]
    fn undeclared_axes_are_not_range_checked() {
        let mut pen = EvdevPen::new(EvdevAxes::default());
        let r = report(frame(
            &mut pen,
            &[(EV_ABS, ABS_X, i32::MAX), (EV_ABS, ABS_Y, i32::MIN)],
        ));
        assert_eq!((r.x_mm, r.y_mm), (f64::from(i32::MAX), f64::from(i32::MIN)));
        // Pressure cannot be scaled without its range: ignored.
        assert_eq!(pen.feed(EV_ABS, ABS_PRESSURE, 5), EvdevOutcome::Ignored);
    }
}
