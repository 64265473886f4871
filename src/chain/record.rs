//! The records a chain's stages hand each other: what the fit works from ([`ChainInput`]), how
//! it is asked ([`ChainOptions`], [`Continuity`]), and what it answers ([`Chain`] of
//! [`ChainSegment`]s with their [`JointKind`]s, or a [`ChainError`]).

use serde::{Deserialize, Serialize};

use super::alpha_evidence::{AlphaBound, AlphaSource, UNDETERMINED_ALPHA};
use crate::bspline::BSpline;
use crate::geom::Point;
use crate::lac::{AlphaChoice, AlphaSearch, LacError, LacSegment};
use crate::split::{Spans, SplitKind};

/// Options of [`fit_chain`](super::fit_chain).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainOptions {
    /// α allowed per segment. Default: the range [−3, 3] ([`AlphaChoice::default`]).
    pub alpha: AlphaChoice,
    /// Rounds of subdividing the segments that miss the tolerance. Default 6 (a segment can be
    /// cut into 64): beyond that, what remains is the data's, not the curve family's.
    pub max_depth: usize,
    /// Merge neighbours that one segment covers within the tolerance. Default true.
    pub merge: bool,
    /// Refine joints and α by Levenberg–Marquardt. Default true.
    pub refine: bool,
    /// Iteration budget of each refinement. Default 30.
    pub refine_iterations: usize,
    /// Continuity at the smooth joints. Default [`Continuity::G2`]. With G2 or C3 the G1
    /// chain is refitted with one curvature per joint (see [`super::smooth`]); where that
    /// cannot hold the tolerance the G1 chain is kept.
    pub continuity: Continuity,
}

impl Default for ChainOptions {
    fn default() -> Self {
        ChainOptions {
            alpha: AlphaChoice::default(),
            max_depth: 6,
            merge: true,
            refine: true,
            refine_iterations: 30,
            continuity: Continuity::G2,
        }
    }
}

/// What a joint between segments (or an end of the chain) is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JointKind {
    /// The start of the piece.
    Start,
    /// The end of the piece.
    End,
    /// A corner shared with the neighbouring piece.
    Corner,
    /// An inflection of the B-spline.
    Inflection,
    /// A curvature extremum of the B-spline.
    CurvatureExtremum,
    /// A joint added to meet the tolerance.
    Subdivision,
    /// Where a closed chain's last segment meets its first ([`ChainInput::seam`]): the first
    /// segment's start and the last one's end. Both sides hold the seam's point and tangent
    /// (the G1 chain), and its curvature (the smooth fit), so the chain closes as smoothly as
    /// its other joints meet.
    Seam,
}

impl JointKind {
    /// Whether the tangent on either side of the joint is its segment's own (G0): a start, an
    /// end or a corner (a seam's tangent is the seam's, on both sides).
    pub fn tangent_free(self) -> bool {
        matches!(self, JointKind::Start | JointKind::End | JointKind::Corner)
    }

    /// Whether the joint's point is fixed: a corner (shared with the neighbouring piece) or a
    /// closed chain's seam.
    pub fn fixed_point(self) -> bool {
        matches!(self, JointKind::Corner | JointKind::Seam)
    }
}

impl From<SplitKind> for JointKind {
    fn from(k: SplitKind) -> Self {
        match k {
            SplitKind::Start => JointKind::Start,
            SplitKind::End => JointKind::End,
            SplitKind::Corner => JointKind::Corner,
            SplitKind::Seam => JointKind::Seam,
            SplitKind::Inflection => JointKind::Inflection,
            SplitKind::CurvatureExtremum => JointKind::CurvatureExtremum,
        }
    }
}

/// One segment of the chain.
#[derive(Clone, Debug)]
pub struct ChainSegment {
    /// The log-aesthetic segment.
    pub segment: LacSegment,
    /// Inclusive range of the stroke's sample indices it represents.
    pub samples: (usize, usize),
    /// Largest distance from those samples to the segment.
    pub max_deviation: f64,
    /// Root mean square of those distances.
    pub rms_deviation: f64,
    /// The α search that started it (the final α may differ after refinement).
    pub search: AlphaSearch,
    /// What chose its α (`None`: no α, an arc or a line).
    pub alpha_source: Option<AlphaSource>,
    /// What its start joint is.
    pub start: JointKind,
    /// What its end joint is.
    pub end: JointKind,
    /// The B-spline parameter interval its samples' foot points span (`None` without samples):
    /// where to compare it with the B-spline.
    pub params: Option<(f64, f64)>,
    /// The end of the allowed α range its α sits on (`None`: an interior α, no α, or a fixed
    /// one): a search stopped there found a wall, not a minimum.
    pub alpha_bound: Option<AlphaBound>,
    /// The standard error of its α given its joints' positions and tangents
    /// ([`super::alpha_evidence`]); `None` where α is absent or fixed, or the probes could not
    /// be built; +∞ where the samples do not move with α at all.
    pub alpha_uncertainty: Option<f64>,
}

impl ChainSegment {
    /// Whether the samples determine its α: an α with an uncertainty of at most
    /// [`UNDETERMINED_ALPHA`], not on the range's end. False for an arc or a line (no α), a
    /// fixed α (the user's), an α without an estimate and one on the bound (the search found a
    /// wall, not a minimum).
    pub fn alpha_determined(&self) -> bool {
        self.alpha_bound.is_none()
            && self
                .alpha_uncertainty
                .is_some_and(|u| u <= UNDETERMINED_ALPHA)
    }
}

/// The chain of one piece.
#[derive(Clone, Debug)]
pub struct Chain {
    /// The segments, in order.
    pub segments: Vec<ChainSegment>,
    /// Largest sample distance over all segments.
    pub max_deviation: f64,
    /// Whether every sample is within the tolerance.
    pub within_tolerance: bool,
    /// Whether Levenberg–Marquardt refinement ran.
    pub refined: bool,
    /// The continuity its smooth joints hold.
    pub continuity: Continuity,
}

/// Why a chain could not be built.
#[derive(Debug, thiserror::Error)]
pub enum ChainError {
    /// The input is inconsistent (lengths differ, no spans).
    #[error("inconsistent chain input: {0}")]
    Input(&'static str),
    /// No segment, not even a biarc, could join a span's G1 data.
    #[error("span u = {u0}..{u1}: {source}")]
    Span {
        /// Start parameter.
        u0: f64,
        /// End parameter.
        u1: f64,
        /// The cause.
        source: LacError,
    },
}

/// What [`fit_chain`](super::fit_chain) works from.
#[derive(Clone, Copy, Debug)]
pub struct ChainInput<'a> {
    /// Distinct sample positions, in stroke order.
    pub points: &'a [Point],
    /// Each point's B-spline parameter (its foot point).
    pub params: &'a [f64],
    /// Each point's original sample index.
    pub indices: &'a [usize],
    /// The inclusive original sample range of the piece.
    pub samples: (usize, usize),
    /// The B-spline.
    pub curve: &'a BSpline,
    /// Its spans.
    pub spans: &'a Spans,
    /// Where the piece closes on itself (its first span starts, or its last ends, at a
    /// [`SplitKind::Seam`]): the seam's pose and curvature, which the smooth fit holds on both
    /// sides. `None` for an open piece.
    pub seam: Option<SeamPose>,
}

/// The pose of a closed stroke's seam: where its chain closes, the tangent there and the
/// curvature, estimated from the samples on both sides of the seam (see
/// [`crate::closure`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeamPose {
    /// The seam's point.
    pub point: Point,
    /// The tangent angle there, in the stroke's direction of travel (radians).
    pub theta: f64,
    /// The signed curvature there (left turns positive).
    pub kappa: f64,
}

/// Continuity at the smooth (non-corner) joints of a chain.
///
/// Ordered from the weakest: `G1 < G2 < C3`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Continuity {
    /// Position and tangent (the seed paper's chains).
    G1,
    /// Position, tangent and curvature: the default (a curve the smooth fit cannot hold within
    /// its tolerance stays G1 and says so).
    #[default]
    G2,
    /// Position, tangent, curvature and its arc-length derivative dκ/ds: a continuous
    /// logarithmic curvature graph across the joint (compound rhythm).
    C3,
}

impl Continuity {
    /// Every mode's name, as the CLI, the service and the documents spell it.
    pub const NAMES: [&'static str; 3] = ["g1", "g2", "c3"];

    /// The mode's name (`g1`, `g2`, `c3`).
    pub fn name(self) -> &'static str {
        match self {
            Continuity::G1 => "g1",
            Continuity::G2 => "g2",
            Continuity::C3 => "c3",
        }
    }
}

impl std::str::FromStr for Continuity {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "g1" => Ok(Continuity::G1),
            "g2" => Ok(Continuity::G2),
            "c3" => Ok(Continuity::C3),
            _ => Err(format!(
                "continuity must be one of {}, got {s:?}",
                Continuity::NAMES.join(", ")
            )),
        }
    }
}

impl std::fmt::Display for Continuity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
