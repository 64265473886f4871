//! The `kansei-curve` v1 format: what `kansei fit` writes.
//!
//! ```json
//! {"format": "kansei-curve", "version": 1, "units": "mm", "tolerance": 0.05,
//!  "curves": [{"stroke": 0, "samples": [0, 311],
//!     "bspline": {"degree": 3, "knots": [], "control_points": [[0.0, 0.0]],
//!                 "max_deviation": 0.031, "rms_deviation": 0.01, "within_tolerance": true,
//!                 "fairing": 1e-9},
//!     "splits": [{"kind": "inflection", "point": [1.0, 2.0], "t": 0.42, "curvature": 0.0}],
//!     "lac": {"max_deviation": 0.04, "within_tolerance": true, "refined": true},
//!     "segments": [{"start": [0.0, 0.0], "theta0": 0.1, "length": 12.5, "alpha": -1.02,
//!                   "kappa0": 0.08, "kappa1": 0.01, "end": [12.1, 2.3], "theta1": 0.52,
//!                   "samples": [0, 120], "max_deviation": 0.04, "rms_deviation": 0.015,
//!                   "start_joint": "start", "end_joint": "curvature_extremum",
//!                   "alpha_search": {"range": [-3.0, 3.0], "alpha": -1.01, "rms": 0.015,
//!                                    "evaluations": 24, "grid": [[-3.0, 0.2]]}}]}]}
//! ```
//! Numbers are written with serde_json's shortest round-trip formatting, so reading a file back
//! gives bit-identical values.

use serde::{Deserialize, Serialize};

use crate::chain::{Chain, ChainSegment};
use crate::geom::{ParamBez, ParamCurve};
use crate::lac::{
    LacError, LacSegment, LacSegmentRecord, lcg_of_bezier_span, lcg_of_segment, lcg_slope,
};
use crate::pipeline::{CurveFit, FitOutput};
use crate::split::SplitKind;
use crate::stroke::Units;

/// The `format` value of a `kansei-curve` file.
pub const CURVE_FORMAT_NAME: &str = "kansei-curve";
/// The `kansei-curve` version written by this library.
pub const CURVE_FORMAT_VERSION: u64 = 1;

/// Points per logarithmic curvature graph written with `--lcg`.
pub const LCG_POINTS: usize = 32;

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
    /// Strokes fitted as one point (taps), in stroke order; absent when empty.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub dots: Vec<DotRecord>,
    /// Strokes that could not be fitted, in stroke order; absent when empty.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub errors: Vec<ErrorRecord>,
}

/// A stroke fitted as one point ([`crate::pipeline::DotFit`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DotRecord {
    /// Index of the stroke in the input.
    pub stroke: usize,
    /// Inclusive range of the stroke's sample indices: all of them.
    pub samples: [usize; 2],
    /// The dot `[x, y]`: the centre of the samples' bounding box.
    pub point: [f64; 2],
    /// Largest distance from a sample to `point` (at most the tolerance).
    pub max_deviation: f64,
}

/// A stroke that could not be fitted ([`crate::pipeline::StrokeFailure`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ErrorRecord {
    /// Index of the stroke in the input.
    pub stroke: usize,
    /// Whether the stroke's data broke a rule (`input`) or the fitter failed (`fit`).
    pub kind: crate::pipeline::FailureKind,
    /// What went wrong.
    pub message: String,
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
    /// How the log-aesthetic chain fits (absent when the LAC stage did not run).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lac: Option<ChainRecord>,
    /// The log-aesthetic chain's segments, in order; consecutive segments share end point and
    /// tangent (G1). Empty when the LAC stage did not run.
    pub segments: Vec<SegmentRecord>,
    /// The chain's joints with their measured continuity, one more than `segments` (absent
    /// when there are none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joints: Vec<JointRecord>,
    /// The tolerance this piece was fitted to, when it differs from the file's `tolerance` (the
    /// app fits each stroke with its own settings); its `within_tolerance` flags refer to it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    /// The stroke's estimated noise: its coordinate grid, the noise across the curve (σ) and
    /// the tolerance floor they support (absent when it was not estimated).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise: Option<crate::stroke::NoiseFloor>,
    /// Whether the curve is closed: its chain's last segment ends where its first starts
    /// (absent when false).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub closed: bool,
    /// On a closed stroke's last curve: how the stroke closes ([`crate::closure`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub closure: Option<crate::closure::ClosureRecord>,
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

/// What a joint of a chain is, for its continuity ([`JointRecord`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JointContinuity {
    /// Where the drawn run starts.
    Start,
    /// Where it ends.
    End,
    /// A corner: a G0 joint with the neighbouring piece of the stroke.
    Corner,
    /// Between two segments of the chain.
    Smooth,
    /// Where a closed chain's last segment meets its first: both the first joint and the last
    /// say so, each with the continuity measured across the seam.
    Seam,
}

/// A joint of a chain and its measured continuity: the curvature and its arc-length derivative
/// on each side, and their relative jumps at a smooth joint.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointRecord {
    /// What the joint is.
    pub kind: JointContinuity,
    /// Where it is `[x, y]`.
    pub point: [f64; 2],
    /// Signed curvature of the segment before and after (none at the piece's ends).
    pub kappa: [Option<f64>; 2],
    /// At a smooth joint, |κ_before − κ_after| / max(|κ_before|, |κ_after|) (0 when both are 0).
    pub curvature_jump: Option<f64>,
    /// dκ/ds of the segment before and after (none at the ends, or where infinite).
    pub dkappa_ds: [Option<f64>; 2],
    /// At a smooth joint, the relative jump of dκ/ds, as for `curvature_jump`.
    pub dkappa_ds_jump: Option<f64>,
}

/// |a − b| / max(|a|, |b|), 0 when both are 0; `None` unless both are finite.
pub fn relative_jump(a: f64, b: f64) -> Option<f64> {
    if !(a.is_finite() && b.is_finite()) {
        return None;
    }
    let scale = a.abs().max(b.abs());
    Some(if scale == 0.0 {
        0.0
    } else {
        (a - b).abs() / scale
    })
}

impl JointRecord {
    /// The joints of a chain of `segments`: its start (or a corner), one smooth joint between
    /// each two segments, its end (or a corner).
    pub fn of_chain(segments: &[ChainSegment]) -> Vec<JointRecord> {
        let (Some(first), Some(last)) = (segments.first(), segments.last()) else {
            return Vec::new();
        };
        let finite = |v: f64| v.is_finite().then_some(v);
        let end_kind = |k: crate::chain::JointKind, fallback| {
            if k == crate::chain::JointKind::Corner {
                JointContinuity::Corner
            } else {
                fallback
            }
        };
        let p = |q: crate::geom::Point| [q.x, q.y];
        // A closed chain's seam: the last segment's end meets the first's start.
        let seam = first.start == crate::chain::JointKind::Seam
            && last.end == crate::chain::JointKind::Seam;
        let seam_joint = |point| {
            let (a, b) = (&last.segment, &first.segment);
            let (da, db) = (a.dkappa_ds(a.length()), b.dkappa_ds(0.0));
            JointRecord {
                kind: JointContinuity::Seam,
                point,
                kappa: [Some(a.kappa1()), Some(b.kappa0())],
                curvature_jump: relative_jump(a.kappa1(), b.kappa0()),
                dkappa_ds: [finite(da), finite(db)],
                dkappa_ds_jump: relative_jump(da, db),
            }
        };
        let mut joints = vec![if seam {
            seam_joint(p(first.segment.start()))
        } else {
            JointRecord {
                kind: end_kind(first.start, JointContinuity::Start),
                point: p(first.segment.start()),
                kappa: [None, Some(first.segment.kappa0())],
                curvature_jump: None,
                dkappa_ds: [None, finite(first.segment.dkappa_ds(0.0))],
                dkappa_ds_jump: None,
            }
        }];
        for w in segments.windows(2) {
            let (a, b) = (&w[0].segment, &w[1].segment);
            let (da, db) = (a.dkappa_ds(a.length()), b.dkappa_ds(0.0));
            // A corner inside a chain (where a smooth chain met a bend its samples do not
            // resolve) is not a smooth joint: no jumps are measured there.
            let smooth = w[0].end != crate::chain::JointKind::Corner;
            joints.push(JointRecord {
                kind: if smooth {
                    JointContinuity::Smooth
                } else {
                    JointContinuity::Corner
                },
                point: p(b.start()),
                kappa: [Some(a.kappa1()), Some(b.kappa0())],
                curvature_jump: relative_jump(a.kappa1(), b.kappa0()).filter(|_| smooth),
                dkappa_ds: [finite(da), finite(db)],
                dkappa_ds_jump: relative_jump(da, db).filter(|_| smooth),
            });
        }
        let l = &last.segment;
        joints.push(if seam {
            seam_joint(p(l.end()))
        } else {
            JointRecord {
                kind: end_kind(last.end, JointContinuity::End),
                point: p(l.end()),
                kappa: [Some(l.kappa1()), None],
                curvature_jump: None,
                dkappa_ds: [finite(l.dkappa_ds(l.length())), None],
                dkappa_ds_jump: None,
            }
        });
        joints
    }
}

/// The chain's figures.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ChainRecord {
    /// Largest distance from a sample to its segment.
    pub max_deviation: f64,
    /// Whether that is within the tolerance.
    pub within_tolerance: bool,
    /// Whether joints and α were refined by Levenberg–Marquardt.
    pub refined: bool,
    /// The continuity the chain holds at its smooth joints (`g1`, or the `g2`/`c3` asked for
    /// where the smooth fit held the tolerance); absent in documents written before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub continuity: Option<crate::chain::Continuity>,
}

/// One log-aesthetic segment: the canonical record (`start` … `theta1`) and its fit.
///
/// The canonical fields are spelled out rather than `#[serde(flatten)]`ing a
/// [`LacSegmentRecord`]: that record denies unknown fields, which serde cannot combine with
/// flattening, and reading a document back must work. [`SegmentRecord::segment`] converts.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SegmentRecord {
    /// Start point [x, y].
    pub start: [f64; 2],
    /// Tangent angle at the start (radians).
    pub theta0: f64,
    /// Arc length.
    pub length: f64,
    /// Slope of the logarithmic curvature graph; null for a circular arc or a line.
    pub alpha: Option<f64>,
    /// Signed curvature at the start.
    pub kappa0: f64,
    /// Signed curvature at the end.
    pub kappa1: f64,
    /// End point [x, y] (follows from the parameters).
    pub end: [f64; 2],
    /// Tangent angle at the end (follows from the parameters).
    pub theta1: f64,
    /// Inclusive range of the stroke's sample indices the segment represents.
    pub samples: [usize; 2],
    /// Largest distance from those samples to the segment.
    pub max_deviation: f64,
    /// Root mean square of those distances.
    pub rms_deviation: f64,
    /// What the segment's start joint is (`start`, `corner`, `inflection`,
    /// `curvature_extremum`, `subdivision`).
    pub start_joint: crate::chain::JointKind,
    /// What its end joint is.
    pub end_joint: crate::chain::JointKind,
    /// The α search that started the segment (refinement may have moved α since).
    pub alpha_search: crate::lac::AlphaSearch,
    /// What chose α (`search`, `refinement`, `smooth`, `fixed`); absent where α is null.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_source: Option<crate::chain::AlphaSource>,
    /// The end of the allowed α range that α sits on (`min`, `max`; absent for an interior α):
    /// the search met the range's wall there, not a minimum.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_bound: Option<crate::chain::AlphaBound>,
    /// The standard error of α given the segment's joints' positions and tangents (absent where
    /// α is null or fixed, where it could not be estimated, and where the samples do not move
    /// with α at all).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_uncertainty: Option<f64>,
    /// Whether the samples determine α (an uncertainty of at most 0.5, the distance between
    /// the family's special values being 1); absent where α is null or fixed. False where α is
    /// on a bound or its uncertainty could not be estimated (fewer than two samples): α is then
    /// its source's pick among near-equals (a near arc, a near line, too few samples).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_determined: Option<bool>,
    /// The logarithmic curvature graphs, when asked for.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lcg: Option<LcgRecord>,
}

/// The logarithmic curvature graphs of a segment and of the B-spline over its samples: points
/// `[log ρ, log(ρ·ds/dρ)]`; the LAC's lie on a line of slope α.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LcgRecord {
    /// The segment's graph (empty for an arc or a line).
    pub lac: Vec<[f64; 2]>,
    /// The B-spline's graph over the segment's samples.
    pub bspline: Vec<[f64; 2]>,
    /// Least-squares slope of the B-spline's graph (the B-spline's "α").
    pub bspline_slope: Option<f64>,
}

impl SegmentRecord {
    /// The segment the record describes (validated; `end`/`theta1` checked to 1e-9).
    pub fn segment(&self) -> Result<LacSegment, LacError> {
        LacSegment::try_from(LacSegmentRecord {
            start: self.start,
            theta0: self.theta0,
            length: self.length,
            alpha: self.alpha,
            kappa0: self.kappa0,
            kappa1: self.kappa1,
            end: Some(self.end),
            theta1: Some(self.theta1),
        })
    }

    fn from_chain(seg: &ChainSegment, lcg: Option<LcgRecord>) -> Self {
        let r = LacSegmentRecord::from(seg.segment);
        let end = r.end.unwrap_or([seg.segment.end().x, seg.segment.end().y]);
        SegmentRecord {
            start: r.start,
            theta0: r.theta0,
            length: r.length,
            alpha: r.alpha,
            kappa0: r.kappa0,
            kappa1: r.kappa1,
            end,
            theta1: r.theta1.unwrap_or(seg.segment.theta1()),
            samples: [seg.samples.0, seg.samples.1],
            max_deviation: seg.max_deviation,
            rms_deviation: seg.rms_deviation,
            start_joint: seg.start,
            end_joint: seg.end,
            alpha_search: seg.search.clone(),
            alpha_source: seg.alpha_source,
            alpha_bound: seg.alpha_bound,
            alpha_uncertainty: seg.alpha_uncertainty.filter(|u| u.is_finite()),
            alpha_determined: seg
                .segment
                .alpha()
                .filter(|_| seg.alpha_source != Some(crate::chain::AlphaSource::Fixed))
                .map(|_| seg.alpha_determined()),
            lcg,
        }
    }
}

/// What to include beyond the curves themselves.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ExportOptions {
    /// Include each segment's logarithmic curvature graphs. Default false.
    pub lcg: bool,
}

impl CurveFile {
    /// The document for a pipeline result.
    pub fn from_output(output: &FitOutput) -> Self {
        Self::from_output_with(output, &ExportOptions::default())
    }

    /// The document for a pipeline result, with extras.
    pub fn from_output_with(output: &FitOutput, options: &ExportOptions) -> Self {
        CurveFile {
            format: CURVE_FORMAT_NAME.to_owned(),
            version: CURVE_FORMAT_VERSION,
            units: output.units,
            tolerance: output.tolerance,
            curves: output
                .curves
                .iter()
                .map(|c| {
                    let mut entry = CurveEntry::from_fit_with(c, options);
                    entry.tolerance = (c.tolerance != output.tolerance).then_some(c.tolerance);
                    entry
                })
                .collect(),
            dots: output
                .dots
                .iter()
                .map(|d| DotRecord {
                    stroke: d.stroke,
                    samples: [d.samples.0, d.samples.1],
                    point: [d.point.x, d.point.y],
                    max_deviation: d.max_deviation,
                })
                .collect(),
            errors: output
                .failures
                .iter()
                .map(|f| ErrorRecord {
                    stroke: f.stroke,
                    kind: f.kind,
                    message: f.message.clone(),
                })
                .collect(),
        }
    }

    /// Pretty-printed JSON.
    pub fn to_json(&self) -> String {
        // Plain data with string keys: serialising into a String cannot fail.
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// Parses a document: reads `format` and `version` first, then the body with the reader of
    /// that version ([`SUPPORTED_CURVE_VERSIONS`]).
    ///
    /// Versioning: each version has its own reader, and every reader produces the newest
    /// in-memory form ([`CurveFile`]). Today that is v1, read directly. When a v2 comes, the
    /// v1 structs move to a `v1` module and gain a conversion into the v2 structs, and this
    /// dispatch gains a `2 =>` arm; v1 files stay readable.
    pub fn from_json(text: &str) -> Result<Self, CurveFormatError> {
        let header: CurveHeader = serde_json::from_str(text).map_err(CurveFormatError::Json)?;
        match header.format.as_deref() {
            Some(CURVE_FORMAT_NAME) => {}
            other => {
                return Err(CurveFormatError::WrongFormat {
                    found: other.map(str::to_owned),
                });
            }
        }
        match header.version {
            Some(1) => {
                let file: CurveFile = serde_json::from_str(text).map_err(CurveFormatError::Json)?;
                Ok(file)
            }
            found => Err(CurveFormatError::UnknownVersion { found }),
        }
    }
}

/// The `kansei-curve` versions [`CurveFile::from_json`] reads.
pub const SUPPORTED_CURVE_VERSIONS: &[u64] = &[1];

/// Just enough of a document to tell its format and version before reading the rest.
#[derive(Deserialize)]
struct CurveHeader {
    format: Option<String>,
    version: Option<u64>,
}

/// Why a `kansei-curve` document was refused.
#[derive(Debug, thiserror::Error)]
pub enum CurveFormatError {
    /// Not JSON, or a field has the wrong type or is missing.
    #[error("not a valid kansei-curve document: {0}")]
    Json(serde_json::Error),
    /// The `format` field is missing or names another format.
    #[error("not a kansei-curve document (format {found:?})")]
    WrongFormat {
        /// The `format` found, if any.
        found: Option<String>,
    },
    /// The `version` is missing or not one this library reads.
    #[error(
        "kansei-curve version {} is not supported (this build reads versions {SUPPORTED_CURVE_VERSIONS:?}); a newer kansei may read it",
        found.map_or_else(|| "(missing)".to_owned(), |v| v.to_string())
    )]
    UnknownVersion {
        /// The `version` found, if any.
        found: Option<u64>,
    },
}

impl CurveEntry {
    /// The entry for one fitted piece.
    pub fn from_fit(fit: &CurveFit) -> Self {
        Self::from_fit_with(fit, &ExportOptions::default())
    }

    /// The entry for one fitted piece, with extras.
    pub fn from_fit_with(fit: &CurveFit, options: &ExportOptions) -> Self {
        let b = &fit.bspline;
        let beziers = b.curve.to_beziers();
        let lcg = |seg: &ChainSegment| -> Option<LcgRecord> {
            if !options.lcg {
                return None;
            }
            let to_pairs = |v: Vec<crate::lac::LcgPoint>| -> Vec<[f64; 2]> {
                v.iter().map(|p| [p.log_rho, p.log_rho_ds_drho]).collect()
            };
            let span = seg
                .params
                .map(|(u0, u1)| pieces_between(&beziers, u0, u1))
                .unwrap_or_default();
            let bspline = lcg_of_bezier_span(&span, LCG_POINTS);
            Some(LcgRecord {
                lac: to_pairs(lcg_of_segment(&seg.segment, LCG_POINTS)),
                bspline_slope: lcg_slope(&bspline),
                bspline: to_pairs(bspline),
            })
        };
        let chain: Option<&Chain> = fit.chain.as_ref();
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
            lac: chain.map(|c| ChainRecord {
                max_deviation: c.max_deviation,
                within_tolerance: c.within_tolerance,
                refined: c.refined,
                continuity: Some(c.continuity),
            }),
            segments: chain
                .map(|c| {
                    c.segments
                        .iter()
                        .map(|s| SegmentRecord::from_chain(s, lcg(s)))
                        .collect()
                })
                .unwrap_or_default(),
            joints: chain
                .map(|c| JointRecord::of_chain(&c.segments))
                .unwrap_or_default(),
            // Set by the document, which knows the file's tolerance.
            tolerance: None,
            noise: fit.noise,
            closed: fit.closure.is_some_and(|c| c.whole),
            closure: fit.closure,
        }
    }
}

/// The parts of a chain of Bézier pieces between global parameters `u0 < u1`.
pub fn pieces_between(pieces: &[ParamBez], u0: f64, u1: f64) -> Vec<ParamBez> {
    pieces
        .iter()
        .filter(|p| p.u1 > u0 && p.u0 < u1)
        .map(|p| {
            let (t0, t1) = (p.local(u0.max(p.u0)), p.local(u1.min(p.u1)));
            ParamBez {
                bez: p.bez.subsegment(t0..t1),
                u0: u0.max(p.u0),
                u1: u1.min(p.u1),
            }
        })
        .filter(|p| p.u1 > p.u0)
        .collect()
}
