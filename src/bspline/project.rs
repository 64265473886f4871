//! Foot-point distance from a point to a piecewise-cubic curve.
//!
//! Two levels: [`Pieces::project_local`] runs Newton's method on ‖C(u) − q‖² from a parameter
//! guess (cheap; used to correct sample parameters during fitting and gives an upper bound on the
//! distance), and [`Pieces::distance`] finds the true distance to the whole curve by exact
//! nearest-point search (kurbo's quintic root isolation) on every piece whose control-point box
//! could hold a closer point than the local one; [`Pieces::distance_on_pass`] does the same on
//! the sample's own pass of a curve that comes back near itself.

use crate::geom::{ParamBez, ParamCurve, Point, Rect, Vec2, bounding_box};
use kurbo::{ParamCurveArclen, ParamCurveNearest};

/// Newton stops when its step moves the foot point by less than this fraction of the curve's
/// size: 1e-13 is a few hundred ulps of a coordinate, below which the iteration only shuffles
/// rounding.
const NEWTON_STEP_RELATIVE: f64 = 1e-13;

/// Newton on the foot-point equation converges quadratically from a sample's chord-length or
/// previous parameter; eight steps leave it converged to rounding in every case seen, and the
/// result is still a valid (upper-bound) distance if not.
const NEWTON_MAX_STEPS: usize = 8;

/// How much longer than straight the curve between a sample's local foot and a nearer foot may
/// run for both to lie on the sample's own pass ([`Pieces::distance_on_pass`]): twice the
/// distance between the feet (plus the sample's distance). A half circle runs π/2 of its chord,
/// a loop or a return pass many times it.
pub const PASS_ARC_FACTOR: f64 = 2.0;

/// Accuracy of [`Pieces::arclen_between`], as a fraction of the chain's size: far below any
/// difference [`PASS_ARC_FACTOR`] decides on.
const ARCLEN_ACCURACY: f64 = 1e-9;

/// Accuracy, in the Bézier parameter, of kurbo's exact nearest-point root isolation.
const NEAREST_ACCURACY: f64 = 1e-12;

/// A point's foot on the curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Foot {
    /// Global parameter of the foot point.
    pub u: f64,
    /// Distance from the point to the foot point.
    pub distance: f64,
}

/// A contiguous chain of Bézier pieces, ready for projection queries.
pub struct Pieces {
    pieces: Vec<ParamBez>,
    /// Control-point bounding boxes of each piece.
    boxes: Vec<Rect>,
    /// The size of the whole chain (bounding-box diagonal), for relative tolerances.
    scale: f64,
}

impl Pieces {
    /// Wraps a non-empty chain of contiguous pieces.
    pub fn new(pieces: Vec<ParamBez>) -> Self {
        let boxes: Vec<Rect> = pieces
            .iter()
            .filter_map(|p| bounding_box([p.bez.p0, p.bez.p1, p.bez.p2, p.bez.p3]))
            .collect();
        let scale = boxes
            .iter()
            .copied()
            .reduce(|a, b| a.union(b))
            .map_or(0.0, |r| r.origin().distance(Point::new(r.x1, r.y1)));
        Pieces {
            pieces,
            boxes,
            scale,
        }
    }

    /// The pieces.
    pub fn pieces(&self) -> &[ParamBez] {
        &self.pieces
    }

    /// Index of the piece holding global parameter `u` (clamped to the chain).
    pub fn locate(&self, u: f64) -> usize {
        let i = self.pieces.partition_point(|p| p.u1 <= u);
        i.min(self.pieces.len().saturating_sub(1))
    }

    /// Point, first and second derivative with respect to the global parameter at `u`.
    pub fn eval_derivs(&self, u: f64) -> (Point, Vec2, Vec2) {
        let pb = &self.pieces[self.locate(u)];
        let du = pb.u1 - pb.u0;
        let t = pb.local(u).clamp(0.0, 1.0);
        let b = &pb.bez;
        let mt = 1.0 - t;
        let d0 = b.p1 - b.p0;
        let d1 = b.p2 - b.p1;
        let d2 = b.p3 - b.p2;
        let first = (d0 * (mt * mt) + d1 * (2.0 * t * mt) + d2 * (t * t)) * 3.0;
        let second = ((d1 - d0) * mt + (d2 - d1) * t) * 6.0;
        (b.eval(t), first / du, second / (du * du))
    }

    /// Newton's method on D(u) = ½‖C(u) − q‖² from `u_guess`, clamped to the chain's domain.
    /// The distance is that of a local foot point: an upper bound on the true distance.
    pub fn project_local(&self, q: Point, u_guess: f64) -> Foot {
        let (lo, hi) = self.domain();
        let mut u = u_guess.clamp(lo, hi);
        let stop = NEWTON_STEP_RELATIVE * self.scale.max(f64::MIN_POSITIVE);
        for _ in 0..NEWTON_MAX_STEPS {
            let (c, d1, d2) = self.eval_derivs(u);
            let r = c - q;
            let g = r.dot(d1);
            let speed2 = d1.hypot2();
            let h = speed2 + r.dot(d2);
            // Full Newton where D is convex, Gauss–Newton (always a descent direction) elsewhere.
            let denom = if h > 0.0 { h } else { speed2 };
            if denom <= 0.0 {
                break;
            }
            let next = (u - g / denom).clamp(lo, hi);
            let moved = (next - u).abs() * speed2.sqrt();
            u = next;
            if moved <= stop {
                break;
            }
        }
        let (c, _, _) = self.eval_derivs(u);
        Foot {
            u,
            distance: c.distance(q),
        }
    }

    /// The true distance from `q` to the chain, starting from a local foot point `near` (from
    /// [`Pieces::project_local`]): every piece whose control-point box lies closer than the
    /// current best is searched exactly.
    pub fn distance(&self, q: Point, near: Foot) -> Foot {
        self.nearest_accepted(q, near, |_, _| true)
    }

    /// The true distance from `q` to its own pass of the chain, starting from a local foot point
    /// `near` (from [`Pieces::project_local`]): [`Pieces::distance`], but a nearer foot is taken
    /// only where the curve between it and `near` runs about straight, no longer than
    /// [`PASS_ARC_FACTOR`] times the distance between the two feet plus `near`'s distance. On a
    /// stroke that comes back near itself (a circle drawn past its start, a figure eight, a
    /// line gone over twice) another pass may come nearer to a sample than its own; the curve
    /// from one pass to the other runs far (round the loop) for a short way across, so that foot
    /// is not taken for the sample's own.
    pub fn distance_on_pass(&self, q: Point, near: Foot) -> Foot {
        let at_near = self.eval_derivs(near.u).0;
        self.nearest_accepted(q, near, |u, foot| {
            let across = at_near.distance(foot);
            self.arclen_between(near.u, u) <= PASS_ARC_FACTOR * (across + near.distance)
        })
    }

    /// The nearest point of the chain to `q` nearer than `near` that `accept` takes (its global
    /// parameter and the point), searched exactly on every piece whose control-point box lies
    /// closer than the best so far.
    fn nearest_accepted(&self, q: Point, near: Foot, accept: impl Fn(f64, Point) -> bool) -> Foot {
        let mut best = near;
        for (pb, b) in self.pieces.iter().zip(&self.boxes) {
            let dx = (b.x0 - q.x).max(q.x - b.x1).max(0.0);
            let dy = (b.y0 - q.y).max(q.y - b.y1).max(0.0);
            if dx.hypot(dy) >= best.distance {
                continue;
            }
            let n = pb.bez.nearest(q, NEAREST_ACCURACY);
            let d = n.distance_sq.sqrt();
            if !(d < best.distance) {
                continue;
            }
            let u = pb.global(n.t);
            if accept(u, pb.bez.eval(n.t)) {
                best = Foot { u, distance: d };
            }
        }
        best
    }

    /// The length of the chain between the global parameters `a` and `b` (in either order).
    pub fn arclen_between(&self, a: f64, b: f64) -> f64 {
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        let accuracy = ARCLEN_ACCURACY * self.scale.max(f64::MIN_POSITIVE);
        self.pieces
            .iter()
            .filter(|p| p.u1 > a && p.u0 < b)
            .map(|p| {
                let t0 = p.local(a).clamp(0.0, 1.0);
                let t1 = p.local(b).clamp(0.0, 1.0);
                p.bez.subsegment(t0..t1).arclen(accuracy)
            })
            .sum()
    }

    /// The global parameter domain.
    pub fn domain(&self) -> (f64, f64) {
        match (self.pieces.first(), self.pieces.last()) {
            (Some(a), Some(b)) => (a.u0, b.u1),
            _ => (0.0, 0.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::CubicBez;

    fn arch() -> Pieces {
        let a = CubicBez::new((0.0, 0.0), (0.0, 1.0), (1.0, 2.0), (2.0, 2.0));
        let b = CubicBez::new((2.0, 2.0), (3.0, 2.0), (4.0, 1.0), (4.0, 0.0));
        Pieces::new(vec![
            ParamBez {
                bez: a,
                u0: 0.0,
                u1: 0.5,
            },
            ParamBez {
                bez: b,
                u0: 0.5,
                u1: 1.0,
            },
        ])
    }

    #[test]
    fn newton_finds_the_perpendicular_foot() {
        let p = arch();
        for i in 1..20 {
            let u = i as f64 / 20.0;
            let (c, d1, _) = p.eval_derivs(u);
            let normal = Vec2::new(-d1.y, d1.x).normalize();
            let q = c + normal * 0.05;
            let foot = p.project_local(q, (u + 0.03).min(1.0));
            assert!((foot.u - u).abs() < 1e-9, "u {u}: {}", foot.u);
            assert!((foot.distance - 0.05).abs() < 1e-12);
        }
    }

    #[test]
    fn global_search_beats_a_bad_local_foot() {
        let p = arch();
        // A point right beside the second piece, projected from the first piece's start.
        let q = Point::new(4.1, 0.5);
        let local = p.project_local(q, 0.0);
        let global = p.distance(q, local);
        assert!(global.distance < local.distance);
        let exact = p.pieces()[1].bez.nearest(q, 1e-14).distance_sq.sqrt();
        assert!((global.distance - exact).abs() < 1e-12);
        assert!(global.u > 0.5);
    }

    /// A hairpin: out along y = 0, a tight turn, back along y = 1.
    fn hairpin() -> Pieces {
        let line = |a: (f64, f64), b: (f64, f64)| {
            CubicBez::new(
                a,
                (a.0 + (b.0 - a.0) / 3.0, a.1 + (b.1 - a.1) / 3.0),
                (a.0 + 2.0 * (b.0 - a.0) / 3.0, a.1 + 2.0 * (b.1 - a.1) / 3.0),
                b,
            )
        };
        let turn = CubicBez::new((10.0, 0.0), (10.7, 0.0), (10.7, 1.0), (10.0, 1.0));
        Pieces::new(vec![
            ParamBez {
                bez: line((0.0, 0.0), (10.0, 0.0)),
                u0: 0.0,
                u1: 0.4,
            },
            ParamBez {
                bez: turn,
                u0: 0.4,
                u1: 0.6,
            },
            ParamBez {
                bez: line((10.0, 1.0), (0.0, 1.0)),
                u0: 0.6,
                u1: 1.0,
            },
        ])
    }

    /// A sample of the outward pass that lies nearer the return pass keeps its foot on its own
    /// pass (the curve between the two feet runs round the turn, far longer than the way
    /// across), where the whole-curve search takes the other; on a curve that passes by once
    /// the two searches agree.
    #[test]
    fn a_foot_stays_on_its_own_pass() {
        let p = hairpin();
        let q = Point::new(2.0, 0.6);
        let local = p.project_local(q, 0.05);
        assert!(
            local.u < 0.4 && (local.distance - 0.6).abs() < 1e-9,
            "{local:?}"
        );
        let whole = p.distance(q, local);
        assert!(
            whole.u > 0.6 && (whole.distance - 0.4).abs() < 1e-9,
            "{whole:?}"
        );
        let own = p.distance_on_pass(q, local);
        assert_eq!(own, local);
        // On a curve that passes by only once the two searches agree, a bad local start included.
        let arch = arch();
        let q = Point::new(4.1, 0.5);
        let local = arch.project_local(q, 0.0);
        assert_eq!(arch.distance_on_pass(q, local), arch.distance(q, local));
    }
}
