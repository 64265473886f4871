//! A smooth chain measured against its samples: the residuals, the joint equations and the
//! samples' assignment to segments ([`Solver`], [`Evaluation`]).

use super::layout::{Form, Params, Var, normal, perp};
use super::{C3_TOLERANCE, END_TOLERANCE};
use crate::geom::{Point, Vec2};
use crate::lac::deviation::deviation_near;
use crate::lac::{LacSegment, deviation};
use nalgebra::DVector;

/// The samples' signed distances to a chain, with their feet.
#[derive(Clone, Debug)]
pub(super) struct Evaluation {
    pub(super) segments: Vec<LacSegment>,
    /// Per segment, per assigned sample: signed distance (left of travel positive).
    pub(super) residuals: Vec<Vec<f64>>,
    /// Per segment, per assigned sample: foot arc length.
    pub(super) feet: Vec<Vec<f64>>,
    /// Per segment, per assigned sample: foot point and left normal there.
    pub(super) foot_points: Vec<Vec<(Point, Vec2)>>,
    pub(super) cost: f64,
}

pub(super) struct Solver<'a> {
    pub(super) points: &'a [Point],
    pub(super) start: Point,
    pub(super) scale: f64,
    pub(super) chord_error: f64,
    /// Bounds of the joints' log-curvature magnitudes (see [`MIN_RADIUS_TOLERANCES`],
    /// [`MAX_RADIUS_EXTENTS`]).
    pub(super) log_kappa: (f64, f64),
    pub(super) c3: bool,
    /// How much looser than exact ([`END_TOLERANCE`], [`C3_TOLERANCE`]) a trial step's
    /// projection need meet the constraints (see [`TRIAL_GAP_TOLERANCES`]).
    pub(super) trial_slack: f64,
    /// Per sample, the weight of its squared distance in the fit's cost (empty: all 1; see
    /// [`MINIMAX_ROUNDS`]).
    pub(super) weights: Vec<f64>,
    /// Whether the fit is refitting for the largest distance ([`minimax`]): it then stops as
    /// soon as every sample is within the tolerance.
    pub(super) minimax: bool,
    /// Whether the fit is polishing a chain that holds the tolerance towards its least-squares
    /// minimum ([`POLISH_DECREASE`]).
    pub(super) polish: bool,
    /// The part's tolerance (see [`WITHIN_DECREASE`]).
    pub(super) tolerance: f64,
    /// The segments a local solve moves (first and last, inclusive; see
    /// [`REMOVAL_REACH`]): every unknown of the others, and the curvatures of the joints at the
    /// window's two ends, stay where they are. `None`: the whole part moves.
    pub(super) window: Option<(usize, usize)>,
    /// Whether a part's own solve (not a try from a solved chain, nor a local one) whose first
    /// projection fails lays its chain out forward from the starting chain rather than from
    /// where the failed Newton steps stopped (see [`smooth_part`]): those are usually nearer
    /// the joint equations, but a segment may wind beyond its bound there, and the layout then
    /// fails with it.
    pub(super) lay_out_from_start: bool,
    /// Whether a sample beyond a segment's end at an interior joint is measured against the
    /// segment's second-order extension there rather than its end point (see [`extend_feet`]):
    /// set while the polish ([`Solver::polish`]) iterates, never for a chain's final measure.
    pub(super) extend: std::cell::Cell<bool>,
}

impl Solver<'_> {
    /// Whether `var` stays where it is in this solve (outside its [`Solver::window`]).
    pub(super) fn frozen(&self, var: Var, n: usize) -> bool {
        let Some((first, last)) = self.window else {
            return false;
        };
        match var {
            Var::X(k) | Var::Y(k) | Var::Angle(k) | Var::Length(k) | Var::Alpha(k) => {
                k < first || k > last
            }
            // The window's end joints are shared with a segment that stays, but for the
            // part's own ends.
            Var::Joint(j) => {
                let after_first = first < j || (j == 0 && first == 0);
                let before_last = j <= last || (j == n && last + 1 == n);
                !(after_first && before_last)
            }
            Var::Theta0 | Var::StartShift => first > 0,
            Var::EndShift => last + 1 < n,
        }
    }

    /// Whether a change of `var`, which reshapes or moves the segments `reach` (first and last,
    /// inclusive), reaches the window: otherwise its Jacobian column is not needed.
    pub(super) fn reaches_window(&self, (k0, k1): (usize, usize)) -> bool {
        match self.window {
            None => true,
            Some((first, last)) => k0 <= last && k1 >= first,
        }
    }

    pub(super) fn points_of(&self, list: &[usize]) -> Vec<Point> {
        list.iter().map(|&i| self.points[i]).collect()
    }

    /// The weight of sample `i`'s squared distance.
    pub(super) fn weight(&self, i: usize) -> f64 {
        self.weights.get(i).copied().unwrap_or(1.0)
    }

    /// Distances of the assigned samples to `segments`, seeded at `near`'s feet where its
    /// segment holds the same samples.
    pub(super) fn evaluate(
        &self,
        segments: Vec<LacSegment>,
        assign: &[Vec<usize>],
        near: Option<(&Evaluation, &[Vec<usize>])>,
    ) -> Evaluation {
        self.evaluate_within(segments, assign, near, f64::INFINITY)
            .0
    }

    /// [`Solver::evaluate`], given up (`None`) as soon as the cost of the segments evaluated so
    /// far exceeds `bound`: a trial step that cannot lower the cost below the current chain's
    /// is refused whatever its other segments' distances are, so their feet are not searched.
    pub(super) fn evaluate_below(
        &self,
        segments: Vec<LacSegment>,
        assign: &[Vec<usize>],
        near: Option<(&Evaluation, &[Vec<usize>])>,
        bound: f64,
    ) -> Option<Evaluation> {
        let (e, complete) = self.evaluate_within(segments, assign, near, bound);
        complete.then_some(e)
    }

    /// The evaluation, and whether it is complete: it stops after the first segment at which
    /// the cost exceeds `bound` (never for an infinite bound).
    fn evaluate_within(
        &self,
        segments: Vec<LacSegment>,
        assign: &[Vec<usize>],
        near: Option<(&Evaluation, &[Vec<usize>])>,
        bound: f64,
    ) -> (Evaluation, bool) {
        let n = segments.len();
        let mut e = Evaluation {
            residuals: Vec::with_capacity(n),
            feet: Vec::with_capacity(n),
            foot_points: Vec::with_capacity(n),
            cost: 0.0,
            segments,
        };
        for (k, list) in assign.iter().enumerate() {
            let (mut residuals, mut feet, mut foot_points) =
                self.distances_of(&e.segments[k], k, list, near);
            if self.extend.get() {
                let ends = (k > 0, k + 1 < n);
                extend_feet(
                    &e.segments[k],
                    ends,
                    list.iter().map(|&i| self.points[i]),
                    (&mut residuals, &mut feet, &mut foot_points),
                );
            }
            e.cost += residuals
                .iter()
                .zip(list)
                .map(|(r, &i)| self.weight(i) * r * r)
                .sum::<f64>();
            e.residuals.push(residuals);
            e.feet.push(feet);
            e.foot_points.push(foot_points);
            if e.cost > bound {
                return (e, false);
            }
        }
        (e, true)
    }

    /// Segment `seg` (the chain's `k`-th) against its samples `list`: their signed distances,
    /// feet and foot points with the residuals' gradient directions (see [`Evaluation`]).
    /// `near` seeds the feet where it assigns the segment the same samples, and gives them as
    /// they were where it also has the same segment (one a step left as it was: outside a local
    /// solve's window, see [`Solver::window`]).
    fn distances_of(
        &self,
        seg: &LacSegment,
        k: usize,
        list: &[usize],
        near: Option<(&Evaluation, &[Vec<usize>])>,
    ) -> (Vec<f64>, Vec<f64>, Vec<(Point, Vec2)>) {
        let old = near.filter(|(_, old_assign)| old_assign.get(k).map(Vec::as_slice) == Some(list));
        if let Some((old, _)) = old
            && old.segments.get(k) == Some(seg)
            && let (Some(residuals), Some(feet), Some(foot_points)) = (
                old.residuals.get(k),
                old.feet.get(k),
                old.foot_points.get(k),
            )
            && residuals.len() == list.len()
            // Feet on an extension are the iteration's measure, not the chain's.
            && (self.extend.get() || feet.iter().all(|&f| (0.0..=seg.length()).contains(&f)))
        {
            return (residuals.clone(), feet.clone(), foot_points.clone());
        }
        let pts = self.points_of(list);
        let mut d = match old {
            Some((old, _)) => deviation_from(
                seg,
                &pts,
                (&old.feet[k], old.segments[k].length()),
                self.chord_error,
            ),
            None => deviation(seg, &pts, self.chord_error),
        };
        let mut foot_points = if d.foot_points.len() == pts.len() {
            std::mem::take(&mut d.foot_points)
        } else {
            d.feet
                .iter()
                .map(|&s| {
                    let sample = seg.sample(s);
                    (sample.point, normal(sample.theta))
                })
                .collect()
        };
        // The signed distances, in place of the distances.
        let mut residuals = std::mem::take(&mut d.distances);
        for (r, side) in residuals.iter_mut().zip(&d.sides) {
            if *side < 0.0 {
                *r = -*r;
            }
        }
        // The residual's gradient direction: the normal at an interior foot, the direction
        // from the foot where the foot is a segment end (a sample beyond it).
        for ((f, n), (q, r)) in foot_points.iter_mut().zip(pts.iter().zip(&residuals)) {
            let v = *q - *f;
            if v.hypot() > 0.0 && *r != 0.0 {
                *n = v / *r;
            }
        }
        (residuals, d.feet, foot_points)
    }

    /// The constraint values of a chain: end point minus the target (scaled by the extent);
    /// in the shooting form each joint's position and tangent gaps (the segment's end pose
    /// minus the next one's start pose in `x`); then for C3 the dκ/ds differences at
    /// `c3_joints`; last, at a closed chain's seam, the end's tangent angle minus its target
    /// ([`Params::end_angle`]), or for a whole closed chain minus the start's one turn on and
    /// the end joint's log-curvature minus the start's ([`Params::seam_turn`]), and for C3 the
    /// dκ/ds difference across the seam ([`Params::seam_c3`]).
    pub(super) fn constraints(
        &self,
        form: Form,
        segments: &[LacSegment],
        x: &Params,
        c3_joints: &[usize],
    ) -> DVector<f64> {
        let mut c = Vec::with_capacity(3 + 3 * segments.len() + c3_joints.len());
        self.constraints_into(form, segments, x, c3_joints, &mut c);
        DVector::from_vec(c)
    }

    /// [`Solver::constraints`] into `c` (cleared first).
    pub(super) fn constraints_into(
        &self,
        form: Form,
        segments: &[LacSegment],
        x: &Params,
        c3_joints: &[usize],
        c: &mut Vec<f64>,
    ) {
        c.clear();
        let end = segments.last().map_or(self.start, |s| s.end());
        c.push((end.x - x.end.x) / self.scale);
        c.push((end.y - x.end.y) / self.scale);
        if form == Form::Shooting {
            for k in 1..segments.len() {
                let (p, theta) = x.pose[k];
                let before = &segments[k - 1];
                c.push((before.end().x - p.x) / self.scale);
                c.push((before.end().y - p.y) / self.scale);
                c.push(before.theta1() - theta);
            }
        }
        if self.c3 {
            for &j in c3_joints {
                c.push(c3_gap(&segments[j - 1], &segments[j]));
            }
        }
        if let (Some(target), Some(last)) = (x.end_angle, segments.last()) {
            c.push(last.theta1() - target);
        }
        // A whole closed chain: the end's tangent one turn on from the start's, and the end
        // joint's log-curvature the start joint's.
        if let (Some(turn), Some(last)) = (x.seam_turn, segments.last()) {
            let start = match form {
                Form::Shooting => x.pose[0].1,
                Form::Forward => x.theta0,
            };
            c.push(last.theta1() - start - turn);
            let n = segments.len();
            c.push(x.u[n] - x.u[0]);
            if self.c3 && x.seam_c3 {
                c.push(c3_gap(last, &segments[0]));
            }
        }
    }

    /// Whether `c` (from [`Solver::constraints`] of an `n`-segment chain) is met to `slack`
    /// times [`END_TOLERANCE`] and [`C3_TOLERANCE`].
    pub(super) fn constraints_met(
        &self,
        form: Form,
        n: usize,
        c: &DVector<f64>,
        slack: f64,
    ) -> bool {
        let positions = match form {
            Form::Shooting => 2 + 3 * n.saturating_sub(1),
            Form::Forward => 2,
        };
        c.iter().enumerate().all(|(i, v)| {
            v.abs()
                <= slack
                    * if i < positions {
                        END_TOLERANCE
                    } else {
                        C3_TOLERANCE
                    }
        })
    }
}

/// The C3 condition at a joint as a dimensionless gap: the difference of dκ/ds either side
/// relative to their magnitude (dκ/ds of both sides share the joint's curvature, so the gap is
/// the relative jump of the logarithmic curvature graph's ordinate there, to first order).
pub(super) fn c3_gap(before: &LacSegment, after: &LacSegment) -> f64 {
    let a = before.dkappa_ds(before.length());
    let b = after.dkappa_ds(0.0);
    let scale = a.abs().max(b.abs());
    if scale > 0.0 && scale.is_finite() {
        (a - b) / scale
    } else {
        0.0
    }
}

/// The largest of an evaluation's distances.
pub(super) fn largest_distance(e: &Evaluation) -> f64 {
    e.residuals
        .iter()
        .flatten()
        .fold(0.0_f64, |m, r| m.max(r.abs()))
}

/// Each segment's samples' distances (unsigned) in an evaluation.
pub(super) fn distances(e: &Evaluation) -> Vec<Vec<f64>> {
    e.residuals
        .iter()
        .map(|r| r.iter().map(|v| v.abs()).collect())
        .collect()
}

/// The largest own distance and the segment holding it.
pub(super) fn worst_sample(own: &[Vec<f64>]) -> (f64, Option<usize>) {
    let mut best = (0.0, None);
    for (k, d) in own.iter().enumerate() {
        for &v in d {
            if v > best.0 || best.1.is_none() {
                best = (v.max(best.0), Some(k));
            }
        }
    }
    best
}

/// One end of a segment as its extension starts from it: the end point, its unit tangent and
/// left normal, and the signed curvature there.
#[derive(Clone, Copy, Debug)]
pub(super) struct EndPose {
    point: Point,
    tangent: Vec2,
    left: Vec2,
    kappa: f64,
}

impl EndPose {
    /// Segment `seg`'s end (`at_end`) or start.
    pub(super) fn of(seg: &LacSegment, at_end: bool) -> Self {
        let (point, theta, kappa) = if at_end {
            (seg.end(), seg.theta1(), seg.kappa1())
        } else {
            (seg.start(), seg.theta0(), seg.kappa0())
        };
        let left = normal(theta);
        EndPose {
            point,
            tangent: Vec2::new(left.y, -left.x),
            left,
            kappa,
        }
    }

    /// The point of the second-order extension at `t` along it (beyond the segment's end for
    /// `t` > 0 from its end, before its start for `t` < 0 from its start),
    /// E(t) = P + T·t + N·κ·t²/2, and its derivative E′(t) = T + N·κ·t (N the left normal).
    fn at(self, t: f64) -> (Point, Vec2) {
        (
            self.point + self.tangent * t + self.left * (0.5 * self.kappa * t * t),
            self.tangent + self.left * (self.kappa * t),
        )
    }

    /// The foot of `q` on the extension by Newton's method on (E(t) − q)·E′(t) = 0 from its
    /// projection on the tangent: `t` and the foot point with the extension's left normal
    /// there, or `None` where the foot is not beyond the segment (`beyond`: the sign of `t`
    /// there, + past the end, − before the start) or the iteration leaves its basin.
    fn foot(self, q: Point, beyond: f64) -> Option<(f64, Point, Vec2)> {
        let mut t = (q - self.point).dot(self.tangent);
        for _ in 0..EXTENSION_NEWTON_STEPS {
            if !(t * beyond > 0.0) {
                return None;
            }
            let (p, d) = self.at(t);
            let slope = d.dot(d) + (p - q).dot(self.left * self.kappa);
            if !(slope > 0.0) {
                return None;
            }
            t -= (p - q).dot(d) / slope;
        }
        if !(t * beyond > 0.0) {
            return None;
        }
        let (p, d) = self.at(t);
        Some((t, p, perp(d) / d.hypot()))
    }
}

/// Newton steps on a sample's foot on a segment's extension ([`EndPose::foot`]): within a few
/// sample spacings of the end the extension is nearly straight and two steps settle it; the
/// third makes the foot's error negligible against the distance's.
pub(super) const EXTENSION_NEWTON_STEPS: usize = 3;

/// The samples `points` of segment `seg` whose foot is an end at an interior joint (`ends`:
/// whether its start, its end is one) with the sample beyond it, measured against the
/// segment's second-order extension there ([`EndPose`]) instead of its end point: their signed
/// distances, feet (beyond [0, S]) and foot points with normals. At a G2 joint the extension
/// follows the next segment to third order, so a sample beyond the joint is measured about as
/// that segment would measure it, and its distance changes smoothly as the joint slides past
/// it (measured against the end point it has a kink where the end passes the sample's foot,
/// which the linear model of a Levenberg–Marquardt step cannot see: see [`Solver::extend`]).
pub(super) fn extend_feet(
    seg: &LacSegment,
    (at_start, at_end): (bool, bool),
    points: impl Iterator<Item = Point>,
    (residuals, feet, foot_points): (&mut [f64], &mut [f64], &mut [(Point, Vec2)]),
) {
    let length = seg.length();
    let ends = [
        (at_start, 0.0, -1.0, EndPose::of(seg, false)),
        (at_end, length, 1.0, EndPose::of(seg, true)),
    ];
    for (m, q) in points.enumerate() {
        for &(open, origin, beyond, pose) in &ends {
            if !(open && feet[m] == origin) {
                continue;
            }
            if let Some((t, p, n)) = pose.foot(q, beyond) {
                residuals[m] = (q - p).dot(n);
                feet[m] = origin + t;
                foot_points[m] = (p, n);
            }
        }
    }
}

/// The points of `seg` at arc lengths `feet` (ordered), those beyond [0, S] on its
/// extensions ([`EndPose`]), into `out`.
pub(super) fn points_on(seg: &LacSegment, feet: &[f64], out: &mut Vec<Point>) {
    crate::lac::deviation::points_at_into(seg, feet, out);
    let length = seg.length();
    let (mut start, mut end) = (None, None);
    for (p, &s) in out.iter_mut().zip(feet) {
        if s > length {
            *p = end
                .get_or_insert_with(|| EndPose::of(seg, true))
                .at(s - length)
                .0;
        } else if s < 0.0 {
            *p = start.get_or_insert_with(|| EndPose::of(seg, false)).at(s).0;
        }
    }
}

/// Distance from `q` to `segment` (one sample).
pub(super) fn distance(solver: &Solver, segment: &LacSegment, q: Point) -> f64 {
    deviation(segment, &[q], solver.chord_error).max
}

/// Distance from `q`, a sample next to a joint, to `segment` on one side of it: its foot
/// polished by Newton's method from the joint (`at_end`: the segment's end, else its start),
/// where a sample handed across a joint has its foot on either segment; searched along the
/// whole segment where the polish does not settle.
pub(super) fn distance_at_joint(
    solver: &Solver,
    segment: &LacSegment,
    q: Point,
    at_end: bool,
) -> f64 {
    let seed = if at_end { segment.length() } else { 0.0 };
    crate::lac::deviation::distance_near(segment, q, seed)
        .unwrap_or_else(|| distance(solver, segment, q))
}

/// The distances from `points` to `segment`, each foot polished by Newton's method from its foot
/// on a nearby segment (`old`: those feet and that segment's length; scaled to this one's), the
/// whole segment searched where the polish does not settle. A polished foot is a local nearest
/// point: its distance is never below the global one.
pub(super) fn deviation_from(
    segment: &LacSegment,
    points: &[Point],
    (feet, length): (&[f64], f64),
    chord_error: f64,
) -> crate::lac::Deviation {
    let ratio = segment.length() / length;
    let seeds: Vec<f64> = feet.iter().map(|s| s * ratio).collect();
    deviation_near(segment, points, &seeds)
        .unwrap_or_else(|| deviation(segment, points, chord_error))
}

/// Hands the samples at each joint to the nearer of its two segments (keeping every segment at
/// least one sample it had); true when any moved.
pub(super) fn reassign(
    solver: &Solver,
    segments: &[LacSegment],
    assign: &mut [Vec<usize>],
) -> bool {
    let mut changed = false;
    // The distances to the segment before joint k + 1 (from its end) and after it (its start).
    let before = |k: usize, q: Point| distance_at_joint(solver, &segments[k], q, true);
    let after = |k: usize, q: Point| distance_at_joint(solver, &segments[k + 1], q, false);
    for k in 0..segments.len().saturating_sub(1) {
        while assign[k].len() > 1 {
            let Some(&i) = assign[k].last() else { break };
            let q = solver.points[i];
            if after(k, q) < before(k, q) {
                assign[k].pop();
                assign[k + 1].insert(0, i);
                changed = true;
            } else {
                break;
            }
        }
        while assign[k + 1].len() > 1 {
            let i = assign[k + 1][0];
            let q = solver.points[i];
            if before(k, q) < after(k, q) {
                assign[k + 1].remove(0);
                assign[k].push(i);
                changed = true;
            } else {
                break;
            }
        }
    }
    changed
}

/// [`reassign`] at the chain of `e`, and `e` evaluated again where a sample moved (each segment
/// that kept its samples from its old feet); true when any moved.
pub(super) fn reassigned(solver: &Solver, e: &mut Evaluation, assign: &mut [Vec<usize>]) -> bool {
    let before = assign.to_vec();
    if !reassign(solver, &e.segments, assign) {
        return false;
    }
    *e = solver.evaluate(e.segments.clone(), assign, Some((&*e, &before)));
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn solver(points: &[Point], window: Option<(usize, usize)>) -> Solver<'_> {
        Solver {
            points,
            start: Point::ORIGIN,
            scale: 1.0,
            chord_error: 1e-3,
            log_kappa: (-10.0, 10.0),
            c3: false,
            trial_slack: 1.0,
            weights: Vec::new(),
            minimax: false,
            polish: false,
            tolerance: 1.0,
            window,
            lay_out_from_start: false,
            extend: std::cell::Cell::new(false),
        }
    }

    /// A log-aesthetic segment (α 0.5, κ from 0.02 to 0.05 over 60) and its two halves.
    fn halves() -> (LacSegment, LacSegment, LacSegment) {
        let whole = LacSegment::new(Point::new(3.0, -2.0), 0.4, 60.0, Some(0.5), 0.02, 0.05)
            .expect("a valid segment");
        let cut = 30.0;
        let head = LacSegment::new(
            whole.start(),
            whole.theta0(),
            cut,
            Some(0.5),
            whole.kappa0(),
            whole.kappa(cut),
        )
        .expect("its head");
        let tail = LacSegment::new(
            whole.point(cut),
            whole.theta(cut),
            whole.length() - cut,
            Some(0.5),
            whole.kappa(cut),
            whole.kappa1(),
        )
        .expect("its tail");
        (whole, head, tail)
    }

    /// The extension past a half's end (before its start) follows the whole segment to third
    /// order: halving the reach divides the gap by about 8, and the gap stays within the
    /// curve's own third-order Taylor term, |N·dκ/ds − T·κ²|·t³/6 ≤ (|dκ/ds| + κ²)·t³/6, with a
    /// factor for the fourth-order rest.
    #[test]
    fn an_extension_follows_the_curve_it_continues_to_third_order() {
        let (whole, head, tail) = halves();
        let cut = head.length();
        let gap = |t: f64| {
            let past = EndPose::of(&head, true)
                .at(t)
                .0
                .distance(whole.point(cut + t));
            let before = EndPose::of(&tail, false)
                .at(-t)
                .0
                .distance(whole.point(cut - t));
            (past, before)
        };
        let (k, dk) = (whole.kappa(cut), whole.dkappa_ds(cut));
        for t in [2.0, 4.0] {
            let (past, before) = gap(t);
            let bound = 1.5 * (dk.abs() + k * k) * t.powi(3) / 6.0;
            assert!(
                past <= bound && before <= bound,
                "{past}, {before} against {bound}"
            );
        }
        let ((p2, b2), (p4, b4)) = (gap(2.0), gap(4.0));
        for ratio in [p2 / p4, b2 / b4] {
            assert!(
                (0.08..=0.2).contains(&ratio),
                "gap ratio {ratio} for half the reach"
            );
        }
    }

    /// A sample past a joint is measured on the extension (about its distance to the curve
    /// beyond the joint), one whose foot is inside the segment is left as it was, and so is one
    /// past an end that is not a joint.
    #[test]
    fn a_sample_past_a_joint_is_measured_on_the_extension() {
        let (whole, head, _) = halves();
        let cut = head.length();
        let offset = 0.7;
        let on = |s: f64| whole.point(s) + normal(whole.theta(s)) * offset;
        let points = [on(10.0), on(cut + 3.0)];
        let d = crate::lac::deviation(&head, &points, 1e-6);
        let signed: Vec<f64> = d.signed_distances();
        let foot_points: Vec<(Point, Vec2)> = d
            .feet
            .iter()
            .map(|&s| (head.point(s), normal(head.theta(s))))
            .collect();
        assert_eq!(d.feet[1], cut, "the second sample's foot is the end");
        for ends in [(true, true), (false, false)] {
            let (mut r, mut f, mut fp) = (signed.clone(), d.feet.clone(), foot_points.clone());
            extend_feet(&head, ends, points.into_iter(), (&mut r, &mut f, &mut fp));
            assert_eq!((r[0], f[0]), (signed[0], d.feet[0]), "an inner foot stays");
            if ends.1 {
                // Off by the normal part of the extension's third-order gap 3 past the joint,
                // |dκ/ds|·27/6 ≈ 2e-3 here (κ 0.030, dκ/ds 4.5e-4; the tangential part moves
                // the foot); against the end point by more than a unit.
                assert!((r[1] - offset).abs() < 5e-3, "{} on the extension", r[1]);
                assert!((f[1] - (cut + 3.0)).abs() < 1e-2, "foot {}", f[1]);
                assert!(
                    signed[1] - offset > 1.0,
                    "the end point is {} away",
                    signed[1]
                );
            } else {
                assert_eq!(
                    (r[1], f[1]),
                    (signed[1], d.feet[1]),
                    "no joint, no extension"
                );
            }
        }
    }

    /// A window moves its segments' own unknowns and the joints between them; the joints at its
    /// two ends are shared with segments that stay, unless they are the part's own ends.
    #[test]
    fn a_window_moves_its_segments_and_its_inner_joints() {
        let points = [Point::ORIGIN];
        let n = 8;
        let whole = solver(&points, None);
        assert!((0..=n).all(|j| !whole.frozen(Var::Joint(j), n)));
        let inner = solver(&points, Some((2, 4)));
        let free: Vec<usize> = (0..=n)
            .filter(|&j| !inner.frozen(Var::Joint(j), n))
            .collect();
        assert_eq!(free, vec![3, 4]);
        for k in 0..n {
            let inside = (2..=4).contains(&k);
            for var in [
                Var::X(k),
                Var::Y(k),
                Var::Angle(k),
                Var::Length(k),
                Var::Alpha(k),
            ] {
                assert_eq!(inner.frozen(var, n), !inside, "{var:?}");
            }
        }
        assert!(inner.frozen(Var::StartShift, n) && inner.frozen(Var::EndShift, n));
        let first = solver(&points, Some((0, 2)));
        let free: Vec<usize> = (0..=n)
            .filter(|&j| !first.frozen(Var::Joint(j), n))
            .collect();
        assert_eq!(free, vec![0, 1, 2]);
        assert!(!first.frozen(Var::StartShift, n) && first.frozen(Var::EndShift, n));
        let last = solver(&points, Some((5, 7)));
        let free: Vec<usize> = (0..=n)
            .filter(|&j| !last.frozen(Var::Joint(j), n))
            .collect();
        assert_eq!(free, vec![6, 7, 8]);
        assert!(last.frozen(Var::StartShift, n) && !last.frozen(Var::EndShift, n));
        // A column reaches the window where the segments it changes meet it.
        assert!(inner.reaches_window((1, 2)) && inner.reaches_window((4, 5)));
        assert!(!inner.reaches_window((0, 1)) && !inner.reaches_window((5, 6)));
    }
}
