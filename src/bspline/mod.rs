//! Least-squares cubic B-spline fitting.
