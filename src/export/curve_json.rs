//! The `kansei-curve` v1 format: what `kansei fit` writes.
//!
//! ```json
//! {"format": "kansei-curve", "version": 1, "units": "mm", "tolerance": 0.05,
//!  "curves": [{"stroke": 0, "samples": [0, 311],
//!     "bspline": {"degree": 3, "knots": [], "control_points": [[0.0, 0.0]],
//!                 "max_deviation": 0.031, "rms_deviation": 0.01, "within_tolerance": true},
//!     "splits": [{"kind": "inflection", "point": [1.0, 2.0], "t": 0.42, "curvature": 0.0}],
//!     "segments": []}]}
//! ```
//! Numbers are written with serde_json's shortest round-trip formatting, so reading a file back
//! gives bit-identical values.

use serde::{Deserialize, Serialize};

use crate::pipeline::{CurveFit, FitOutput};
use crate::split::SplitKind;
use crate::stroke::Units;

/// The `format` value of a `kansei-curve` file.
pub const CURVE_FORMAT_NAME: &str = "kansei-curve";
/// The `kansei-curve` version written by this library.
pub const CURVE_FORMAT_VERSION: u64 = 1;

/// A `kansei-curve` document.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CurveFile {
    /// Always [`CURVE_FORMAT_NAME`].
    pub format: String,
    /// Always [`CURVE_FORMAT_VERSION`].
    pub version: u64,
    /// Units of every coordinate (those of the input strokes).
    pub units: Units,
    /// The fitting tolerance used, in `units`.
    pub tolerance: f64,
    /// One entry per fitted piece of stroke (strokes are cut at corners).
    pub curves: Vec<CurveEntry>,
}

/// One fitted piece of a stroke.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CurveEntry {
    /// Index of the stroke in the input.
    pub stroke: usize,
    /// Inclusive range of the stroke's sample indices this entry represents. Samples of a
    /// dropped hook lie outside every range.
    pub samples: [usize; 2],
    /// The least-squares B-spline.
    pub bspline: BSplineRecord,
    /// Split points in order: `start` (or `corner`), inflections and curvature extrema, `end`
    /// (or `corner`).
    pub splits: Vec<SplitRecord>,
    /// Log-aesthetic curve segments, one per span between consecutive splits (filled by the LAC
    /// stage; empty until then).
    pub segments: Vec<serde_json::Value>,
}

/// A clamped cubic B-spline and its fit figures.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BSplineRecord {
    /// Always 3.
    pub degree: usize,
    /// The full clamped knot vector on [0, 1] (`control_points.len() + 4` entries).
    pub knots: Vec<f64>,
    /// Control points `[x, y]`.
    pub control_points: Vec<[f64; 2]>,
    /// Largest distance from a sample in `samples` to the curve.
    pub max_deviation: f64,
    /// Root mean square of those distances.
    pub rms_deviation: f64,
    /// Whether `max_deviation ≤ tolerance`.
    pub within_tolerance: bool,
    /// The fairing weight λ the curve was fitted with (0: plain least squares); see
    /// [`crate::bspline::BSplineFit::fairing`].
    pub fairing: f64,
}

/// A point where the curve is split.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SplitRecord {
    /// Why the curve is split here.
    pub kind: SplitKind,
    /// The split point `[x, y]`.
    pub point: [f64; 2],
    /// The B-spline parameter of the point, in [0, 1].
    pub t: f64,
    /// Signed curvature of the B-spline there (positive turns left in a y-up frame).
    pub curvature: f64,
}

impl CurveFile {
    /// The document for a pipeline result.
    pub fn from_output(output: &FitOutput) -> Self {
        CurveFile {
            format: CURVE_FORMAT_NAME.to_owned(),
            version: CURVE_FORMAT_VERSION,
            units: output.units,
            tolerance: output.tolerance,
            curves: output.curves.iter().map(CurveEntry::from_fit).collect(),
        }
    }

    /// Pretty-printed JSON.
    pub fn to_json(&self) -> String {
        // Plain data with string keys: serialising into a String cannot fail.
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// Parses a document (checking format and version).
    pub fn from_json(text: &str) -> Result<Self, serde_json::Error> {
        let file: CurveFile = serde_json::from_str(text)?;
        if file.format != CURVE_FORMAT_NAME || file.version != CURVE_FORMAT_VERSION {
            return Err(serde::de::Error::custom(format!(
                "not a kansei-curve v{CURVE_FORMAT_VERSION} document (format {:?}, version {})",
                file.format, file.version
            )));
        }
        Ok(file)
    }
}

impl CurveEntry {
    /// The entry for one fitted piece.
    pub fn from_fit(fit: &CurveFit) -> Self {
        let b = &fit.bspline;
        CurveEntry {
            stroke: fit.stroke,
            samples: [fit.samples.0, fit.samples.1],
            bspline: BSplineRecord {
                degree: crate::bspline::DEGREE,
                knots: b.curve.knots().to_vec(),
                control_points: b
                    .curve
                    .control_points()
                    .iter()
                    .map(|p| [p.x, p.y])
                    .collect(),
                max_deviation: b.max_deviation,
                rms_deviation: b.rms_deviation,
                within_tolerance: b.within_tolerance,
                fairing: b.fairing,
            },
            splits: fit
                .spans
                .splits
                .iter()
                .map(|s| SplitRecord {
                    kind: s.kind,
                    point: [s.point.x, s.point.y],
                    t: s.u,
                    curvature: s.curvature,
                })
                .collect(),
            segments: Vec::new(),
        }
    }
}
