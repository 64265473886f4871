//! The shared geometric vocabulary: points and vectors (from [`kurbo`]), a Bézier piece that knows
//! where it sits on its B-spline, and the named tolerances every stage uses.
//!
//! Coordinates are in the stroke's units (see [`crate::stroke::Units`]); all numerics are `f64`.

pub use kurbo::{CubicBez, ParamCurve, ParamCurveDeriv, Point, Rect, Vec2};

/// Two consecutive samples closer than this (relative to the stroke's bounding-box diagonal) are
/// duplicates and are merged. `1e-12` is far below any device resolution (a 300 mm tablet at
/// 1e-12 relative is 3e-10 mm) yet far above the rounding noise of coordinates near 1e6.
pub const DUPLICATE_RELATIVE: f64 = 1e-12;

/// Largest absolute coordinate accepted at the boundary. 1e9 in the stroke's units is 1000 km in
/// millimetres: anything beyond is a unit mistake or garbage, and squaring it in the normal
/// equations would start to lose every digit of a sub-millimetre tolerance.
pub const MAX_COORDINATE: f64 = 1e9;

/// Smallest extent of a stroke (the diagonal of its samples' box) relative to its largest
/// coordinate: 10⁻¹¹, a thousand times the relative distance at which the LAC construction
/// takes two end points for one ([`crate::lac::yoshida_saito::COINCIDENT_RELATIVE`], 10⁻¹⁴),
/// so a segment of a thousandth of the stroke is still resolved. At the largest accepted
/// coordinate, 10⁹ mm, a stroke must span 10 µm; at 1 m from the origin, 10 pm.
pub const MIN_EXTENT_RELATIVE: f64 = 1e-11;

/// A cubic Bézier that is one knot span of a B-spline.
///
/// Local parameter `t ∈ [0, 1]` of [`ParamBez::bez`] maps to the B-spline's global parameter
/// `u = u0 + t·(u1 − u0)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamBez {
    /// The Bézier itself.
    pub bez: CubicBez,
    /// Global B-spline parameter at local `t = 0`.
    pub u0: f64,
    /// Global B-spline parameter at local `t = 1`.
    pub u1: f64,
}

impl ParamBez {
    /// Global parameter of local parameter `t`.
    pub fn global(&self, t: f64) -> f64 {
        self.u0 + t * (self.u1 - self.u0)
    }

    /// Local parameter of global parameter `u` (not clamped).
    pub fn local(&self, u: f64) -> f64 {
        let du = self.u1 - self.u0;
        if du == 0.0 { 0.0 } else { (u - self.u0) / du }
    }
}

/// The smallest axis-aligned rectangle holding every point (`None` without points).
pub fn bounding_box(points: impl IntoIterator<Item = Point>) -> Option<Rect> {
    let mut points = points.into_iter();
    let first = points.next()?;
    Some(points.fold(Rect::from_points(first, first), |r, p| r.union_pt(p)))
}

/// Distance from `p` to the segment `a`–`b` (to `a` when the segment has no length).
pub fn distance_to_segment(p: Point, a: Point, b: Point) -> f64 {
    let ab = b - a;
    let len2 = ab.hypot2();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).hypot()
}

/// An angle brought into (−π, π].
pub fn wrap_angle(a: f64) -> f64 {
    let (sin, cos) = a.sin_cos();
    sin.atan2(cos)
}

/// Arc length along the polyline at each of its points (0 at the first).
pub fn cumulative_lengths(points: &[Point]) -> Vec<f64> {
    let mut acc = 0.0;
    let mut out = Vec::with_capacity(points.len());
    out.extend(points.first().map(|_| 0.0));
    for w in points.windows(2) {
        acc += w[0].distance(w[1]);
        out.push(acc);
    }
    out
}

/// Signed curvature of a parametric curve from its first and second derivatives:
/// κ = (x′y″ − x″y′) / (x′² + y′²)^{3/2}. Returns 0 where the first derivative vanishes.
pub fn curvature_from_derivs(d1: Vec2, d2: Vec2) -> f64 {
    let f = d1.hypot2();
    if f == 0.0 {
        0.0
    } else {
        d1.cross(d2) / (f * f.sqrt())
    }
}
