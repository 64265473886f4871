//! The split's result: split points and the monotonic-curvature spans between them.

use crate::geom::{ParamBez, Point};
use serde::{Deserialize, Serialize};

/// Why the curve is split at a point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SplitKind {
    /// The start of the curve.
    Start,
    /// The end of the curve.
    End,
    /// The curvature changes sign here.
    Inflection,
    /// `|κ|` has a local maximum or minimum here (including a minimum near zero between two
    /// spans of the same sign, e.g. where an insignificant opposite-sign wiggle was dropped).
    CurvatureExtremum,
    /// A tangent discontinuity. Never produced by [`split_spans`](super::split_spans) (strokes
    /// are split at corners upstream); part of the vocabulary shared with later stages.
    Corner,
    /// Where a closed stroke's curve meets itself (its first span's start and its last span's
    /// end). Never produced by [`split_spans`](super::split_spans): the pipeline marks a closed
    /// piece's ends so.
    Seam,
}

/// One split point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SplitPoint {
    /// Why the curve is split here.
    pub kind: SplitKind,
    /// Global B-spline parameter.
    pub u: f64,
    /// The point on the curve.
    pub point: Point,
    /// Signed curvature there (positive: turning counter-clockwise in a y-up frame). At an
    /// [`SplitKind::Inflection`] it is ≈ 0: within rounding for an exact inflection, within the
    /// straight threshold where a sign change was moved by noise suppression.
    pub curvature: f64,
}

/// The sign of the curvature over a span.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CurvatureSign {
    /// Turning counter-clockwise (y-up frame).
    Positive,
    /// Turning clockwise (y-up frame).
    Negative,
    /// Straight: `|κ|` stays below [`Spans::straight_curvature`] over the whole span.
    Zero,
}

/// A maximal piece of the curve with one curvature sign and monotonic `|κ|` (up to the
/// thresholds of [`SplitOptions`](super::SplitOptions)).
#[derive(Clone, Debug, PartialEq)]
pub struct Span {
    /// Global parameter at the start.
    pub u0: f64,
    /// Global parameter at the end.
    pub u1: f64,
    /// Sub-Béziers covering exactly `[u0, u1]`, in order, subdivided from the input pieces (an
    /// input piece lying wholly inside the span is passed through unchanged). Consecutive
    /// sub-Béziers meet at the input's joints.
    pub pieces: Vec<ParamBez>,
    /// The curvature sign over the span.
    pub sign: CurvatureSign,
    /// Kind of the split point at `u0`.
    pub start: SplitKind,
    /// Kind of the split point at `u1`.
    pub end: SplitKind,
}

/// The result of [`split_spans`](super::split_spans).
#[derive(Clone, Debug, PartialEq)]
pub struct Spans {
    /// Split points in increasing `u`; the first is [`SplitKind::Start`], the last
    /// [`SplitKind::End`].
    pub splits: Vec<SplitPoint>,
    /// The spans between consecutive split points: `spans[i]` runs from `splits[i]` to
    /// `splits[i + 1]`.
    pub spans: Vec<Span>,
    /// The curvature magnitude treated as zero for this curve (`κ_straight` of
    /// [`SplitOptions`](super::SplitOptions)), in inverse stroke units. Spans whose `|κ|` stays
    /// below it are [`CurvatureSign::Zero`].
    pub straight_curvature: f64,
}
