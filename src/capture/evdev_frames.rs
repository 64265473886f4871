//! Linux input events turned into [`PenReport`]s, one per frame, so that evdev tablets go
//! through the same [`StrokeBuilder`](crate::capture::stroke_builder::StrokeBuilder) as HID
//! ones: [`EvdevPen`]. Pure (no device access): the live evdev source feeds it.
//!
//! The rules are those of [`crate::capture::evemu`]: events are grouped into frames ended by
//! `SYN_REPORT`; axis values persist between frames; `BTN_TOUCH` is contact; `BTN_TOOL_RUBBER`
//! marks the eraser (cleared by `BTN_TOOL_PEN`); after `SYN_DROPPED` the events up to and
//! including the next `SYN_REPORT` are discarded. Each `SYN_REPORT` with X and Y known gives one
//! report:
//!
//! - position: `ABS_X`/`ABS_Y` divided by their resolution (units/mm), or raw counts when a
//!   resolution is 0 ([`EvdevAxes::units`] is then [`Units::Device`]);
//! - pressure: `(v - min) / (max - min)`, clamped to 0..1;
//! - tilt: `(v / resolution).to_degrees()` (the kernel gives tilt resolution in units/radian),
//!   or `v` as degrees with resolution 0.
//!
//! The report's `tip` and `contact` are `BTN_TOUCH`; `invert` and `eraser` are the rubber tool
//! (`eraser` only while touching); `in_range` is either tool in proximity.

use crate::capture::evemu::{
    ABS_PRESSURE, ABS_TILT_X, ABS_TILT_Y, ABS_X, ABS_Y, BTN_TOOL_PEN, BTN_TOOL_RUBBER, BTN_TOUCH,
    EV_ABS, EV_KEY, EV_SYN, SYN_DROPPED, SYN_REPORT,
};
use crate::capture::hid::PenReport;
use crate::stroke::Units;

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
}

/// Frames of evdev events into pen reports; see the module documentation.
#[derive(Clone, Debug)]
pub struct EvdevPen {
    axes: EvdevAxes,
    state: State,
    frame: State,
    dropping: bool,
}

impl EvdevPen {
    /// A decoder for a device with these axes.
    pub fn new(axes: EvdevAxes) -> Self {
        EvdevPen {
            axes,
            state: State::default(),
            frame: State::default(),
            dropping: false,
        }
    }

    /// Feeds one event (`type`, `code`, `value`); a report when it ends a frame with a known
    /// position.
    pub fn event(&mut self, kind: u16, code: u16, value: i32) -> Option<PenReport> {
        if self.dropping {
            if (kind, code) == (EV_SYN, SYN_REPORT) {
                self.dropping = false;
                self.frame = self.state;
            }
            return None;
        }
        match (kind, code) {
            (EV_SYN, SYN_REPORT) => {
                self.state = self.frame;
                return self.report();
            }
            (EV_SYN, SYN_DROPPED) => {
                self.dropping = true;
                self.frame = self.state;
            }
            (EV_KEY, BTN_TOUCH) => self.frame.touch = value != 0,
            (EV_KEY, BTN_TOOL_RUBBER) => self.frame.rubber = value != 0,
            (EV_KEY, BTN_TOOL_PEN) => {
                self.frame.pen = value != 0;
                if value != 0 {
                    self.frame.rubber = false;
                }
            }
            (EV_ABS, ABS_X) => self.frame.x = Some(value),
            (EV_ABS, ABS_Y) => self.frame.y = Some(value),
            (EV_ABS, ABS_PRESSURE) => self.frame.pressure = Some(value),
            (EV_ABS, ABS_TILT_X) => self.frame.tilt_x = Some(value),
            (EV_ABS, ABS_TILT_Y) => self.frame.tilt_y = Some(value),
            _ => {}
        }
        None
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
            barrel: [false; 2],
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
