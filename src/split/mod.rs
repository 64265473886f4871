//! Splitting a B-spline into spans of monotonic curvature: inflections and curvature extrema
//! (Miura et al., "Input of log-aesthetic curves with a pen tablet", §3.4–3.6).
//!
//! Input: the cubic B-spline as its cubic Bézier pieces ([`ParamBez`](crate::geom::ParamBez), one
//! per knot span, in order). Output ([`split_spans`]): split points and [`Span`]s, each with one
//! curvature sign and monotonic `|κ|`, carrying its own sub-Béziers — what a log-aesthetic curve
//! segment can fit.
//!
//! # Mathematics (per piece, local `t ∈ [0, 1]`)
//!
//! With `f = x′² + y′²` and `g = x′y″ − x″y′`, the signed curvature is `κ = g / f^{3/2}`.
//! For a cubic Bézier `g` is a **quadratic** (the paper says cubic; the `t³` terms cancel) and
//! `f` a quartic, so the extremum polynomial `h = 2g′f − 3gf′` (`dκ/dt = h / (2 f^{5/2})`) has
//! **degree ≤ 5** (the paper says 6). See `curvature.rs` for the explicit coefficients.
//!
//! * **Inflections** are the sign-changing roots of `g` in `(0, 1)`, in closed form
//!   ([`kurbo::common::solve_quadratic`]); double roots are discarded.
//! * **Curvature extrema** are the sign-changing roots of `h` in `(0, 1)`. They are isolated
//!   exactly, not by a grid: the roots of `h′, h″, …` (recursively) split `(0, 1)` into intervals
//!   where `h` is monotonic, each with at most one root, polished by the safeguarded ITP solver.
//!   See `poly.rs`.
//! * **Joints** between pieces: a C2 spline has continuous κ but not `dκ/du`. Every joint is a
//!   candidate; since `|κ|` is monotonic between consecutive candidates, a joint is an extremum
//!   exactly when `d|κ|/du` changes sign across it, which comparing `|κ|` with the neighbouring
//!   candidates decides. Roots within [`SplitOptions::joint_tolerance`] of a joint merge into it.
//!
//! # Noise
//!
//! A neighbouring max/min pair of `|κ|` whose magnitudes differ by less than
//! [`SplitOptions::extremum_relative`] of the larger one (default 5 %), or by less than the
//! straight threshold `κ_straight`, is dropped, smallest difference first (topological
//! persistence), so what remains is monotonic between split points up to that threshold.
//! `κ_straight = max(straight_relative · Θ, straight_turning) / L` (`L` arc length, `Θ` total
//! turning; see [`SplitOptions`]) makes wiggles of κ around zero on a near-straight stretch
//! vanish instead of producing a flood of inflections. The spans' signs and the split kinds are
//! decided after this simplification, so they are consistent with it: a split is an
//! [`SplitKind::Inflection`] exactly when the spans on its two sides have opposite signs.
//!
//! Corners are not detected here ([`SplitKind::Corner`] is vocabulary for later stages); pieces
//! whose speed vanishes are rejected with [`SplitError::Singular`].

mod candidates;
mod curvature;
mod error;
mod options;
mod output;
mod poly;
mod scale;
mod simplify;
mod spans;

pub use error::SplitError;
pub use options::SplitOptions;
pub use output::{CurvatureSign, Span, Spans, SplitKind, SplitPoint};
pub use spans::split_spans;
