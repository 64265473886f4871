//! Capture: pen input from recordings of real devices, turned into [`crate::stroke`] files.
//!
//! - [`hid`]: a pen's HID report descriptor located into a [`hid::PenLayout`], and input reports
//!   decoded into [`hid::PenReport`]s (millimetres, pressure 0..1, tilt in degrees). Pure: no I/O.
//! - [`recorder`]: the hid-recorder text format (`R:` descriptor, `N:`/`I:` header, `E:` reports).
//! - [`stroke_builder`]: a stream of timed pen reports cut into strokes, one per contact run.
//! - [`replay`]: a recording through the decoder and the builder into a `kansei-stroke` file.

pub mod hid;
pub mod recorder;
pub mod replay;
pub mod stroke_builder;
