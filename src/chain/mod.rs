//! The log-aesthetic chain: LAC segments over the spans of monotonic curvature, G1 throughout.
//!
//! In: a fitted piece of stroke ([`crate::pipeline::CurveFit`]: its samples, their B-spline
//! parameters, the spans) and the tolerance. Out: a [`Chain`] of [`ChainSegment`]s, each the
//! Yoshida–Saito segment ([`crate::lac::fit_g1`]) through its ends' positions and tangents with
//! the α that fits its samples best ([`crate::lac::fit_span`]). Consecutive segments share the
//! joint's position and tangent, so the chain is G1 by construction. The first segments are one
//! per run of spans holding at least three samples (most spans hold one sample or none: their
//! extrema are the noise's); a Levenberg–Marquardt refinement then moves joints and α together,
//! and after every later change only where the chain changed.
//!
//! Tolerance: a segment whose samples are not all within the tolerance is subdivided between its
//! two middle samples (the new joint taken on the B-spline, still G1) and refitted, up to
//! [`ChainOptions::max_depth`] times. Then runs that a straight line holds within the tolerance
//! become one line segment, and neighbours are merged where one segment covers both within the
//! tolerance: across a curvature extremum, a subdivision joint or an inflection (the data decide:
//! a real inflection cannot be absorbed by one single-signed segment), never across a corner
//! (which separates pieces).
//! Fewer segments are better, as the seed paper's future work asks.

pub mod alpha_evidence;
mod band;
mod band_lu;
mod fit;
mod polyline;
mod refine;
pub mod smooth;
mod state;
pub mod stray;
mod unhook;

pub use alpha_evidence::{
    ALPHA_BOUND_TOLERANCE, ALPHA_DIFFERENCE_STEP, AlphaBound, AlphaSource, UNDETERMINED_ALPHA,
    alpha_uncertainty,
};
pub use fit::{Chain, ChainError, ChainInput, ChainOptions, ChainSegment, JointKind, fit_chain};
pub use smooth::Continuity;
