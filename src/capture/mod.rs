//! Capture: pen input from recordings of real devices and from other ink formats, turned into
//! [`crate::stroke`] files. Everything here is a pure function of the bytes it reads: live input
//! (hidapi, evdev) will feed the same decoders, so every recording is a test of the live path.
//!
//! - [`hid`]: a pen's HID report descriptor located into a [`hid::PenLayout`], and input reports
//!   decoded into [`hid::PenReport`]s (millimetres, pressure 0..1, tilt in degrees).
//! - [`recorder`]: the hid-recorder text format (`R:` descriptor, `N:`/`I:` header, `E:` reports).
//! - [`stroke_builder`]: a stream of timed pen reports cut into strokes, one per contact run.
//! - [`replay`]: a recording through the decoder and the builder into a `kansei-stroke` file.
//! - [`evemu`]: Linux evdev recordings in the `evemu-record` text format.
//! - [`inkml`]: W3C InkML (read, with the compact difference encodings; and write).
//! - [`quickdraw`]: Google QuickDraw drawings (`.ndjson`).

pub mod evemu;
pub mod hid;
pub mod inkml;
pub mod quickdraw;
pub mod recorder;
pub mod replay;
pub mod stroke_builder;
