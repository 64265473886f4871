//! Splitting a B-spline into spans of monotonic curvature: Bézier decomposition, inflections and
//! curvature extrema.
