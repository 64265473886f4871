use thiserror::Error;

use super::locate::JsonPlace;

/// "stroke i, sample j, field f: " for a known place, nothing otherwise.
fn prefix(place: &Option<JsonPlace>) -> String {
    place.as_ref().map(|p| format!("{p}: ")).unwrap_or_default()
}

/// Why a stroke or a `kansei-stroke` file was refused. Every variant names the stroke and, where
/// there is one, the sample index (both 0-based), so a user can find the offending line.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum StrokeError {
    /// The file was empty (zero bytes or only whitespace).
    #[error("the file is empty")]
    Empty,
    /// The JSON did not parse, or a field had the wrong type (a number beyond `f64`, such as
    /// `1e999`, is the JSON spelling of an infinity and lands here).
    #[error("{}invalid JSON at line {line}, column {column}: {message}", prefix(.place))]
    Json {
        /// 1-based line of the error.
        line: usize,
        /// 1-based column of the error.
        column: usize,
        /// What serde_json reported.
        message: String,
        /// The stroke, sample and field there, when the error lies inside `strokes`.
        place: Option<JsonPlace>,
    },
    /// The `format` field is not `kansei-stroke`.
    #[error("\"format\" is {found:?}, expected \"kansei-stroke\"")]
    WrongFormat {
        /// The value found.
        found: String,
    },
    /// The `version` is not one this library reads.
    #[error("\"version\" is {found}, this kansei reads version 1")]
    WrongVersion {
        /// The value found.
        found: u64,
    },
    /// A number is NaN or infinite.
    #[error("stroke {stroke}, sample {sample}: {field} is not a finite number ({value})")]
    NonFinite {
        /// Stroke index.
        stroke: usize,
        /// Sample index within the stroke.
        sample: usize,
        /// Field name (`x`, `y`, `t`, ...).
        field: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A coordinate's magnitude exceeds [`crate::geom::MAX_COORDINATE`].
    #[error(
        "stroke {stroke}, sample {sample}: {field} = {value} is beyond the accepted range ±{limit}"
    )]
    OutOfRange {
        /// Stroke index.
        stroke: usize,
        /// Sample index within the stroke.
        sample: usize,
        /// Field name.
        field: &'static str,
        /// The offending value.
        value: f64,
        /// The accepted magnitude.
        limit: f64,
    },
    /// Pressure outside 0..1.
    #[error("stroke {stroke}, sample {sample}: pressure {value} is outside 0..1")]
    Pressure {
        /// Stroke index.
        stroke: usize,
        /// Sample index within the stroke.
        sample: usize,
        /// The offending value.
        value: f64,
    },
    /// Time decreased from one sample to the next.
    #[error("stroke {stroke}, sample {sample}: time goes backwards ({t} s after {previous} s)")]
    TimeBackwards {
        /// Stroke index.
        stroke: usize,
        /// Sample index within the stroke.
        sample: usize,
        /// The sample's time.
        t: f64,
        /// The previous sample's time.
        previous: f64,
    },
    /// Some samples have a time and others do not.
    #[error("stroke {stroke}, sample {sample}: has no \"t\" while other samples of the stroke do")]
    MixedTime {
        /// Stroke index.
        stroke: usize,
        /// Sample index within the stroke.
        sample: usize,
    },
    /// The stroke has no samples at all. (A stroke whose samples all sit at one position is
    /// valid: a tap, fitted as a dot.)
    #[error("stroke {stroke}: has no samples")]
    NoSamples {
        /// Stroke index.
        stroke: usize,
    },
    /// The samples span so little beside the size of their coordinates that `f64` cannot
    /// resolve the stroke's shape there (see [`crate::geom::MIN_EXTENT_RELATIVE`]).
    #[error(
        "stroke {stroke}: its samples span {extent:e} at coordinates up to {magnitude:e}, too \
         little for f64 to resolve its shape there; move the drawing nearer the origin"
    )]
    Unresolvable {
        /// Stroke index.
        stroke: usize,
        /// The diagonal of the samples' bounding box.
        extent: f64,
        /// The largest coordinate magnitude among the samples.
        magnitude: f64,
    },
}
