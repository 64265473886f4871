//! Least-squares cubic B-spline fitting (Miura et al., §3.3).
//!
//! In: a stroke's sample positions (finite, consecutive duplicates merged) and a distance
//! tolerance. Out: a clamped cubic [`BSpline`] on `[0, 1]` with the fewest segments the search
//! found such that every sample's foot-point distance to the curve is within the tolerance
//! ([`BSplineFit`]), and its decomposition into Bézier pieces ([`BSpline::to_beziers`]).
//!
//! The least squares is solved by Givens rotations on the banded observation matrix ([`lsq`]),
//! distances are exact foot-point distances ([`project`]).

mod curve;
mod fit;
pub mod lsq;
pub mod project;

pub use curve::{BSpline, BSplineError, DEGREE};
pub use fit::{
    BSplineFit, FitError, FitOptions, SegmentSearch, Weighting, fit_bspline, least_squares,
};
