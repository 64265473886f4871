//! Strokes: the samples a pen produced, and the `kansei-stroke` v1 file format.
//!
//! A [`Stroke`] is one pen-down run of [`Sample`]s. A [`StrokeFile`] is what `kansei-stroke` JSON
//! holds: units, optional provenance, and the strokes. Everything entering the library passes
//! [`StrokeFile::validate`] (or [`Stroke::validate`]): finite numbers, non-decreasing time,
//! coordinates within [`crate::geom::MAX_COORDINATE`], at least two distinct samples. Past that
//! boundary the stages trust their input.

mod error;
mod file;
mod locate;
mod sample;

pub use error::StrokeError;
pub use file::{FORMAT_NAME, FORMAT_VERSION, StrokeFile};
pub use locate::{JsonPlace, place_at};
pub use sample::{Sample, Stroke, Units};
