//! Capture: pen input from recordings of real devices and from other ink formats, turned into
//! [`crate::stroke`] files. Everything here is a pure function of the bytes it reads: live input
//! (hidapi, evdev) feeds the same decoders, so every recording is a test of the live path.
//!
//! - [`hid`]: a pen's HID report descriptor located into a [`hid::PenLayout`], and input reports
//!   decoded into [`hid::PenReport`]s (millimetres, pressure 0..1, tilt in degrees).
//! - [`recorder`]: the hid-recorder text format (`R:` descriptor, `N:`/`I:` header, `E:` reports).
//! - [`stroke_builder`]: a stream of timed pen reports cut into strokes, one per contact run.
//! - [`replay`]: a recording through the decoder and the builder into a `kansei-stroke` file.
//! - [`evemu`]: Linux evdev recordings in the `evemu-record` text format.
//! - [`inkml`]: W3C InkML (read, with the compact difference encodings; and write).
//! - [`quickdraw`]: Google QuickDraw drawings (`.ndjson`).
//! - [`source`]: the [`source::PenSource`] trait (live devices and recordings alike), device
//!   descriptions, permission errors with the udev rules.
//! - [`session`]: the capture loop, each stroke written as it ends.
//! - [`writer`]: the crash-safe `kansei-stroke` writer and the hid-recorder raw writer.
//! - [`evdev_frames`]: evdev events framed into pen reports: the one evdev decoder, fed by the
//!   live evdev source and by evemu replay alike.
//! - [`paced`]: a source replayed in real time (a recording standing in for a live tablet).
//! - `live_hid`, `live_evdev` (feature `live`): tablets through `/dev/hidraw*` (hidapi) and
//!   `/dev/input/event*` (evdev); `open` (feature `live`): a tablet opened by its node name.

pub mod evdev_frames;
pub mod evemu;
pub mod hid;
pub mod inkml;
#[cfg(feature = "live")]
pub mod live_evdev;
#[cfg(feature = "live")]
pub mod live_hid;
#[cfg(feature = "live")]
pub mod open;
pub mod paced;
pub mod quickdraw;
pub mod recorder;
pub mod replay;
pub mod session;
pub mod source;
pub mod stroke_builder;
pub mod writer;
