//! The biarc: two circular arcs joining two points with given tangents, G1 everywhere (Bolton
//! 1975; Sabin 1977). It exists for all G1 data with distinct points, so the chain falls back to
//! it where no log-aesthetic segment of an allowed α can join the data (a tiny span at a sharp
//! turn of the B-spline). Both arcs are LAC records with `alpha` null.
//!
//! Construction with equal tangent lengths d: the arcs meet at J = ((A + d·tA) + (B − d·tB))/2,
//! where the two control points A + d·tA and B − d·tB are 2d apart, i.e.
//! ‖v − d·t‖ = 2d with v = B − A and t = tA + tB:  (4 − t·t)·d² + 2(v·t)·d − v·v = 0, whose positive
//! root is d = (√((v·t)² + (4 − t·t)·v·v) − v·t)/(4 − t·t) (d = v·v/(2 v·t) when t·t = 4). The
//! joint tangent points from the first control point to the second.

use super::error::LacError;
use super::segment::LacSegment;
use crate::geom::{Point, Vec2};

/// `4 − t·t` below this is taken as exactly 0 (parallel equal tangents): the quadratic's leading
/// coefficient is then rounding noise relative to the others (which are O(1) for unit tangents).
const PARALLEL_TANGENTS: f64 = 1e-12;

/// The biarc from `a` (unit tangent `ta`) to `b` (unit tangent `tb`).
pub fn biarc(a: Point, ta: Vec2, b: Point, tb: Vec2) -> Result<[LacSegment; 2], LacError> {
    let v = b - a;
    if v.hypot() == 0.0 || !v.hypot().is_finite() {
        return Err(LacError::CoincidentEndPoints);
    }
    let t = ta + tb;
    let vt = v.dot(t);
    let vv = v.hypot2();
    let lead = 4.0 - t.hypot2();
    let d = if lead.abs() < PARALLEL_TANGENTS {
        if vt > 0.0 { vv / (2.0 * vt) } else { f64::NAN }
    } else {
        ((vt * vt + lead * vv).sqrt() - vt) / lead
    };
    if !(d.is_finite() && d > 0.0) {
        return Err(LacError::OutsideDrawableRegion {
            theta_a: f64::NAN,
            theta_b: f64::NAN,
            alpha: f64::NAN,
        });
    }
    let c0 = a + ta * d;
    let c1 = b - tb * d;
    let joint = c0.midpoint(c1);
    let tj = c1 - c0;
    let tj = if tj.hypot() > 0.0 { tj.normalize() } else { ta };
    Ok([arc(a, ta, joint)?, arc(joint, tj, b)?])
}

/// The circular arc (or line) from `p` with unit tangent `tp` to `q`.
fn arc(p: Point, tp: Vec2, q: Point) -> Result<LacSegment, LacError> {
    let chord = q - p;
    let c = chord.hypot();
    // Signed angle from the tangent to the chord: the arc turns by twice it.
    let phi = tp.cross(chord).atan2(tp.dot(chord));
    let kappa = 2.0 * phi.sin() / c;
    let length = if phi.abs() < f64::EPSILON {
        c
    } else {
        c * phi / phi.sin()
    };
    LacSegment::new(p, tp.y.atan2(tp.x), length, None, kappa, kappa)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_biarc_is_g1_and_ends_where_asked() {
        let cases = [
            (Point::new(0.0, 0.0), 0.0f64, Point::new(10.0, 0.0), 1.2f64),
            (Point::new(0.0, 0.0), 0.3, Point::new(5.0, 4.0), -2.0),
            (Point::new(1.0, 1.0), 1.0, Point::new(1.2, 1.0), -1.0),
            (Point::new(0.0, 0.0), 0.0, Point::new(10.0, 0.0), 0.0),
        ];
        for (a, ang_a, b, ang_b) in cases {
            let (ta, tb) = (
                Vec2::new(ang_a.cos(), ang_a.sin()),
                Vec2::new(f64::cos(ang_b), f64::sin(ang_b)),
            );
            let [s0, s1] = biarc(a, ta, b, tb).expect("biarc");
            assert!(s0.start().distance(a) < 1e-12);
            assert!(
                s1.end().distance(b) < 1e-9 * (s0.length() + s1.length()),
                "{:?} vs {b:?}",
                s1.end()
            );
            assert!(s0.end().distance(s1.start()) < 1e-9 * s0.length());
            let wrap = crate::geom::wrap_angle;
            assert!(wrap(s0.theta1() - s1.theta0()).abs() < 1e-9);
            assert!(
                wrap(s1.theta1() - ang_b).abs() < 1e-9,
                "end tangent {} vs {ang_b}",
                s1.theta1()
            );
            assert!(s0.alpha().is_none() && s1.alpha().is_none());
        }
    }
}
