//! A smooth chain measured against its samples: the residuals, the joint equations and the
//! samples' assignment to segments ([`Solver`], [`Evaluation`]).

use super::*;

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
            let (residuals, feet, foot_points) = self.distances_of(&e.segments[k], k, list, near);
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
    /// `c3_joints`.
    pub(super) fn constraints(
        &self,
        form: Form,
        segments: &[LacSegment],
        x: &Params,
        c3_joints: &[usize],
    ) -> DVector<f64> {
        let mut c = Vec::with_capacity(2 + 3 * segments.len() + c3_joints.len());
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
