//! # kansei: pen strokes to log-aesthetic curves
//!
//! The pipeline (Miura et al., "Input of log-aesthetic curves with a pen tablet"):
//! 1. [`stroke`]: samples (x, y, time, pressure, tilt), read from `kansei-stroke` JSON.
//! 2. [`bspline`]: least-squares cubic B-spline, segments added until the tolerance holds.
//! 3. [`split`]: Bézier pieces split at inflections and curvature extrema into monotonic spans.
//! 4. [`lac`]: one log-aesthetic curve segment per span, G1 chain.
//! 5. [`export`]: `kansei-curve` JSON.

pub mod bspline;
pub mod geom;
pub mod lac;
pub mod split;
pub mod stroke;
