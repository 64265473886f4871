//! Capture: reading pen recordings from other formats into [`crate::stroke::StrokeFile`]s.
//!
//! - [`inkml`]: W3C InkML (read, with the compact difference encodings; and write).
//! - [`evemu`]: Linux evdev recordings in the `evemu-record` text format.

pub mod evemu;
pub mod inkml;
