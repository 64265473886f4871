//! Strokes: the samples a pen produced, and the `kansei-stroke` v1 file format.
//!
//! A [`Stroke`] is one pen-down run of [`Sample`]s. A [`StrokeFile`] is what `kansei-stroke` JSON
//! holds: units, optional provenance, and the strokes. Everything entering the library passes
//! [`StrokeFile::validate`] (or [`Stroke::validate`]): finite numbers, non-decreasing time,
//! coordinates within [`crate::geom::MAX_COORDINATE`], pressure within 0..1, at least one sample.
//! Past that boundary the stages trust their input. A stroke whose samples all lie within the
//! tolerance of one point is a dot ([`Stroke::as_dot`]), not a curve; a stroke the pipeline fits as
//! a curve must also be resolvable in `f64` where it lies ([`Stroke::check_resolvable`]).

mod error;
mod file;
mod locate;
mod noise;
mod sample;

pub use error::StrokeError;
pub use file::{FORMAT_NAME, FORMAT_VERSION, StrokeFile};
pub use locate::{JsonPlace, place_at};
pub use noise::{
    GRID_DECORRELATION_STEPS, GRID_STAIRCASE_RATIO, GRID_TRIM_STEPS, JITTER_REVERSALS,
    NOISE_MULTIPLE, NoiseFloor, WINDOW as NOISE_WINDOW, noise_multiple,
};
pub use sample::{Sample, Stroke, Units};
