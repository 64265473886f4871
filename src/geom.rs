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
    nearest_on_segment(p, a, b).0
}

/// The point of the segment `a`–`b` nearest to `p`: its distance from `p` and its fraction
/// t ∈ [0, 1] along the segment (the foot is a + t·(b − a); t = 0 when the segment has no
/// length). t is the projection (p − a)·(b − a)/|b − a|², clamped to the segment.
pub fn nearest_on_segment(p: Point, a: Point, b: Point) -> (f64, f64) {
    let ab = b - a;
    let len2 = ab.hypot2();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((p - (a + ab * t)).hypot(), t)
}

/// An angle brought into (−π, π], as atan2(sin a, cos a): within an ulp or so of its result,
/// and exact for small angles of either sign (a difference of two nearly equal directions stays
/// what it is), at the cost of a `sin_cos` and an `atan2`. The one the chain's joints use.
pub fn wrap_angle(a: f64) -> f64 {
    let (sin, cos) = a.sin_cos();
    sin.atan2(cos)
}

/// An angle brought into (−π, π] by whole turns of 2π (`rem_euclid`, then one turn back above
/// π): exact for a ≥ 0, where a − k·2π is computed without rounding; a negative angle is rounded
/// once, to the resolution of 2π (≈ 9e-16). The one the Yoshida–Saito construction uses for the
/// angles between the chord and the end tangents.
///
/// Two forms on purpose: every fit depends on which one each caller uses, bit for bit. Over the
/// fixtures, planted chains and adversarial strokes of `tests/same_output.rs`, the construction
/// through [`wrap_angle`] changes 466 of the 547 recorded fits, the chain through this one 108,
/// and both through a third form (a ∈ (−π, π] unchanged, whole turns otherwise) 360.
pub fn wrap_angle_by_turns(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let w = a.rem_euclid(TAU);
    if w > PI { w - TAU } else { w }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_nearest_point_of_a_segment_is_its_foot_or_an_end() {
        let (a, b) = (Point::new(1.0, 1.0), Point::new(5.0, 4.0)); // length 5
        // Beside the segment: the perpendicular foot, 2 away, at t = 0.6 (3 along).
        let foot = a + (b - a) * 0.6;
        let normal = Vec2::new(-3.0, 4.0) * (1.0 / 5.0);
        let (d, t) = nearest_on_segment(foot + normal * 2.0, a, b);
        assert!((d - 2.0).abs() < 1e-15 && (t - 0.6).abs() < 1e-15);
        // Before a and beyond b: the ends, at their distances.
        let before = a - (b - a) * 0.2 + normal;
        assert_eq!(nearest_on_segment(before, a, b), (before.distance(a), 0.0));
        let beyond = b + (b - a) * 0.4;
        assert_eq!(nearest_on_segment(beyond, a, b), (beyond.distance(b), 1.0));
        // A segment without length is its point.
        assert_eq!(nearest_on_segment(b, a, a), (b.distance(a), 0.0));
        assert_eq!(distance_to_segment(foot + normal * 2.0, a, b), d);
    }

    #[test]
    fn wrapped_angles_differ_by_whole_turns() {
        use std::f64::consts::{PI, TAU};
        let angles = [
            0.0, 1e-300, -1e-300, 1e-15, -1e-15, 0.5, -0.5, 3.0, -3.0, PI, -PI, 4.0, -4.0, -6.07,
            100.0, -1e6,
        ];
        for wrap in [wrap_angle, wrap_angle_by_turns] {
            for a in angles {
                let w = wrap(a);
                assert!((-PI..=PI).contains(&w), "{a} -> {w}");
                let turns = (a - w) / TAU;
                assert!((turns - turns.round()).abs() < 1e-9, "{a} -> {w}");
                assert!((w.sin() - a.sin()).abs() < 1e-9 && (w.cos() - a.cos()).abs() < 1e-9);
            }
        }
        // Small angles are their own atan2 wrap, exactly, whatever their sign; by whole turns,
        // angles in [0, π] are, and one turn is one subtraction of the f64 2π.
        for a in [1e-300, -1e-300, 1e-15, -1e-15, 1e-8, -1e-8] {
            assert_eq!(wrap_angle(a), a);
        }
        for a in [0.0, 1e-300, 1e-15, 0.5, 3.0, PI] {
            assert_eq!(wrap_angle_by_turns(a), a);
            assert_eq!(wrap_angle_by_turns(a + TAU), (a + TAU) - TAU);
        }
        // The two differ in the last bits: −2π by whole turns is 0, by atan2 the sine of the
        // f64 2π.
        assert_eq!(wrap_angle_by_turns(-TAU), 0.0);
        assert!(wrap_angle(-TAU) > 0.0 && wrap_angle(-TAU) < 1e-15);
    }
}
