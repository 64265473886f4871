//! The constrained Levenberg–Marquardt solve, its projection onto the joint equations and the
//! minimax rounds.

use super::jacobian::{ConstraintJacobian, shooting_jacobian};
use super::layout::{Form, Layout, Params, step_by};
use super::normal::{Normal, NormalPattern, band_order, normal_equations};
use super::project::{LeastNorm, constraint_order, project};
use super::solver::{Evaluation, Solver, largest_distance, reassigned};
use crate::chain::solve::band_lu::BandMatrix;
use crate::chain::solve::damping::{Damping, DampingOptions, DampingRule};
use crate::lac::LacSegment;
use nalgebra::DVector;

/// Iterations of one Levenberg–Marquardt solve. Each accepted step lowers the squared distances;
/// from the G1 chain, 10–20 steps reach the minimum to the stopping rule below.
pub(super) const MAX_ITERATIONS: usize = 40;

/// The solve stops when an accepted step lowers the sum of squared distances by less than this
/// fraction (or the model predicts less): the distances then move by half a percent. Tighter
/// values cost time for no better fit (with the consistent Jacobian of [`shooting_jacobian`]);
/// measured in `docs/performance-history.md` (chain constants).
pub(super) const RELATIVE_DECREASE: f64 = 1e-2;

/// The solve also stops when an accepted step lowers the sum of squared distances by less than
/// this fraction while every sample is within the tolerance: the chain then holds, and what the
/// steps left would bring is the polish's to bring (it carries the part's final chain to its
/// least-squares minimum, see [`POLISH_DECREASE`]); until then the chain only starts the joint
/// removals. Measured in `docs/performance-history.md` (chain constants).
/// A less converged start loses more
/// joints in the removals (as we read it: the steps after the chain holds fit the same joints
/// closer to the samples' noise, which a removal must then undo).
pub(super) const WITHIN_DECREASE: f64 = 0.3;

/// The stopping fraction of a polish: the least-squares solve of a part's final chain, which
/// holds the tolerance, carried on until a step gains less than this.
pub(super) const POLISH_DECREASE: f64 = 1e-4;

/// A polish also stops when a step lowers the squared distances by less than this multiple of
/// the residual variance (their sum over the residual degrees of freedom, the samples less the
/// free unknowns): the log-likelihood of the fit then moves by less than half of it, however
/// many samples the part has. On a part of few samples, where the unknowns nearly interpolate
/// them and the steps crawl along a valley the samples hardly tell ([`POLISH_DECREASE`] there
/// asks less than a thousandth of the variance), it ends the crawl: a 2-segment part of 9
/// samples (painting stroke 18) ran 40 polish steps of 1–4 % each. A part with no residual
/// degree of freedom is not polished: its least-squares chain interpolates the samples, noise
/// and all. On the random planted sweep (`planted_sweep 200 1`), 1e-2 and 3e-2 leave every
/// case as it was (168 / 115 / 178 as planted), 1e-1 loses 4 / 2 / 2.
pub(super) const POLISH_SIGNIFICANCE: f64 = 3e-2;

/// The decrease of the cost `cost` of a chain assigned as `e`, with `free` free unknowns, below
/// which a polish step ends the solve (see [`POLISH_SIGNIFICANCE`]).
pub(super) fn polish_stop(cost: f64, e: &Evaluation, free: usize) -> f64 {
    let samples = e.residuals.iter().map(Vec::len).sum::<usize>();
    match samples.checked_sub(free) {
        Some(dof) if dof > 0 => cost * POLISH_DECREASE.max(POLISH_SIGNIFICANCE / dof as f64),
        _ => f64::INFINITY,
    }
}

/// How far past a segment's end, in lengths of the segment, a polish may measure a sample on
/// the segment's extension ([`super::solver::EndPose`]): the extension is the segment's
/// second-order expansion at the joint, which the next segment follows only near it, and a
/// sample a whole segment's length beyond the end is no longer next to the joint: a step that
/// puts one there has pulled the segment away from its samples, and the polish ends at the
/// chain before it. Laid out, such chains missed their own samples (one 0.4 tolerances off on
/// the extension was 14 off its own segment): on the fixture strokes up to 600 samples, every
/// polish that ended within the tolerance had kept its samples within 0.87 lengths on every
/// chain it evaluated, and the six that reached 1.0 to 187 lengths all ended beyond the
/// tolerance and were thrown away, after up to 20 iterations on parts of up to 410 samples.
/// The polish ends at the chain before such a step, which is then the answer where it holds (as
/// below, where a polish ends beyond the tolerance): this saves work and fits as well. Refusing
/// such a step instead, like one that raises the cost, keeps those polishes going for no saving;
/// measured in `docs/performance-history.md` (chain constants).
pub(super) const EXTENSION_REACH: f64 = 1.0;

/// Whether a sample of `e` lies on a segment's extension more than [`EXTENSION_REACH`] of the
/// segment's length past its end (or before its start).
pub(super) fn beyond_reach(e: &Evaluation) -> bool {
    e.segments.iter().zip(&e.feet).any(|(segment, feet)| {
        let length = segment.length();
        let reach = EXTENSION_REACH * length;
        feet.iter().any(|&s| s > length + reach || s < -reach)
    })
}

/// Marquardt's damping starts at this multiple of the normal matrix's diagonal. Most solves
/// start near an answer (a cut chain, a minimax round, a second start), where a bolder first step
/// is refused; 1e-2 took the least work for about the same segments (scanned with the G1 chain
/// refined as a start only, see `refine::STARTING_CONVERGED_RMS`); measured in
/// `docs/performance-history.md` (chain constants).
pub(super) const INITIAL_DAMPING: f64 = 1e-2;

/// Damping after a refused step is multiplied by a factor that starts at this and doubles with
/// each refusal in a row; after an accepted step it is scaled by max(1/3, 1 − (2ρ − 1)³), ρ the
/// ratio of the actual to the predicted decrease (Nielsen's rule): a step that did what the
/// model said lowers it, one that barely helped keeps it. A fixed ×4 / ÷3 made the fit alternate
/// refused and accepted steps (each refusal a projection onto the constraints).
pub(super) const DAMPING_GROWTH: f64 = 2.0;

/// Beyond this damping the step is too short to matter: the solve has converged or is stuck.
pub(super) const MAX_DAMPING: f64 = 1e8;

/// The smooth fit's damping (Nielsen's rule, see [`DAMPING_GROWTH`]): from
/// [`INITIAL_DAMPING`], a try at [`MAX_DAMPING`] itself still made.
pub(super) const DAMPING: DampingOptions = DampingOptions {
    initial: INITIAL_DAMPING,
    max: MAX_DAMPING.next_up(),
    rule: DampingRule::Nielsen {
        growth: DAMPING_GROWTH,
    },
};

/// A diagonal entry of the normal matrix below this fraction of the largest is raised to it
/// before damping: an unknown the samples barely see (α of a near arc, the curvature at a
/// joint of a near line) is then held by the damping instead of moving freely inside the
/// constraints' null space, where its steps are as long as the linearisation allows and their
/// projections fail; a floor far above it holds the unknowns too tightly. Measured in
/// `docs/performance-history.md` (chain constants).
pub(super) const DIAGONAL_FLOOR: f64 = 1e-4;

/// A fresh constraint Jacobian is reused for the next projection step while the last step cut
/// the violation at least by this factor (Newton converging, the Jacobian still good enough):
/// slower steps leave worse trials. Measured in
/// `docs/performance-history.md` (chain constants).
pub(super) const FRESH_REUSE_RATE: f64 = 0.1;

/// Newton steps projecting a point onto the constraints. From the starting chain (the G1
/// chain with one curvature per joint) the steps converge linearly, a factor of 3 to 20 per
/// step (the bounds clamp some of them): 30 reach the constraints from a violation of the
/// order of the chain's extent. Measured in `docs/performance-history.md` (chain constants).
pub(super) const PROJECTION_STEPS: usize = 30;

/// Chord steps projecting a Levenberg–Marquardt trial back onto the constraints (see
/// [`project`]): a trial a damped step away from the constraints converges in two or three; one
/// that does not within this many is refused like a step that raises the cost. On the nine
/// recorded fixture files, 6 gave 915 segments in 0.88 s, 12 gives 896 in 0.78 s.
pub(super) const TRIAL_PROJECTION_STEPS: usize = 12;

/// Rounds of Lawson's reweighting (see [`minimax`]) a least-squares chain whose largest distance
/// misses the tolerance by at most [`MINIMAX_REACH`] gets before its segments are cut: the
/// samples of a whole-pixel grid lie up to half a pixel's diagonal from the true curve, right at
/// the noise floor's tolerance, and the least-squares fit of the true segments can miss it by a
/// little where a minimax fit of the same segments holds it.
pub(super) const MINIMAX_ROUNDS: usize = 4;

/// Least factor (relative to the largest distance) by which a round of [`minimax`] multiplies a
/// sample's weight: a sample on the curve keeps a say in the next round instead of dropping
/// out for good.
pub(super) const LAWSON_FLOOR: f64 = 0.05;

/// The least-squares chain of `layout` at `x` refitted for its largest distance (Lawson's
/// iteration): each round multiplies every sample's weight by its distance (relative to the
/// largest, at least [`LAWSON_FLOOR`]) and solves again from the last answer, which moves the
/// chain towards the minimax fit of the same segments. The first round whose largest distance
/// is within the tolerance is returned with its assignment and unknowns; `None` if none is within
/// [`MINIMAX_ROUNDS`]. The solver's weights are left uniform.
pub(super) fn minimax(
    solver: &mut Solver,
    layout: &Layout,
    x: &Params,
    assign: &[Vec<usize>],
    evaluation: &Evaluation,
) -> Option<(Evaluation, Vec<Vec<usize>>, Params)> {
    let (mut x, mut assign) = (x.clone(), assign.to_vec());
    solver.weights = vec![1.0; solver.points.len()];
    solver.minimax = true;
    let mut found = None;
    let mut last: Option<Evaluation> = None;
    for _ in 0..MINIMAX_ROUNDS {
        let e = last.as_ref().unwrap_or(evaluation);
        let worst = largest_distance(e);
        if !(worst > 0.0) {
            break;
        }
        for (residuals, list) in e.residuals.iter().zip(&assign) {
            for (r, &i) in residuals.iter().zip(list) {
                solver.weights[i] *= (r.abs() / worst).max(LAWSON_FLOOR);
            }
        }
        let total: f64 = solver.weights.iter().sum();
        let mean = total / solver.weights.len() as f64;
        if !(mean > 0.0 && mean.is_finite()) {
            break;
        }
        for w in &mut solver.weights {
            *w /= mean;
        }
        let before = assign.clone();
        let Some(next) = solve(solver, layout, &mut x, &mut assign, Some((e, &before))) else {
            break;
        };
        if largest_distance(&next) <= solver.tolerance {
            found = Some((next, assign, x));
            break;
        }
        last = Some(next);
    }
    solver.weights = Vec::new();
    solver.minimax = false;
    found
}

/// The Levenberg–Marquardt fit in the shooting form from `x` and its evaluation `e`, moving
/// both (and the samples' assignment): each step solves the damped Gauss–Newton system with the
/// linearised constraints (KKT, Marquardt's scaling) and is projected back onto them; `None`
/// where no chain could be built.
pub(super) fn levenberg_marquardt(
    solver: &Solver,
    layout: &Layout,
    x: &mut Params,
    assign: &mut [Vec<usize>],
    e: &mut Evaluation,
) -> Option<()> {
    let vars = layout.shooting_vars();
    let c3_joints = layout.c3_joints();
    let m = vars.len();
    // The unknowns that reach each segment: its residuals' only nonzero columns.
    let reaching: Vec<Vec<usize>> = (0..layout.n())
        .map(|k| {
            (0..m)
                .filter(|&i| {
                    let (k0, k1) = layout.shooting_reach(vars[i]);
                    (k0..=k1).contains(&k)
                })
                .collect()
        })
        .collect();
    // Where JᵀJ can be nonzero: column j's rows are the unknowns that share a segment with it
    // (see [`normal_equations`]), and its diagonal.
    let pattern = NormalPattern::new(m, &reaching)?;
    // The KKT system's band order: the layout, and so the rows, stay fixed through the solve.
    let constraint_rows = constraint_order(
        Form::Shooting,
        layout.n(),
        solver.c3,
        &c3_joints,
        x.seam_rows(solver.c3),
    );
    let nc = constraint_rows.len();
    // The unknowns the constraints leave free: the fit's own degrees of freedom.
    let free = m.saturating_sub(nc);
    let position = band_order(layout, &vars, nc, &c3_joints);
    let mut damping = Damping::new(DAMPING);
    // A polish's last chain within the tolerance (with its evaluation and assignment) before a
    // step that took a sample beyond it: where the polish ends beyond the tolerance, it ends
    // there instead (see below).
    let mut last_within: Option<(Params, Evaluation, Vec<Vec<usize>>)> = None;
    for iteration in 0..MAX_ITERATIONS {
        let (jr, jc) = shooting_jacobian(solver, layout, x, e, &vars, &c3_joints, &reaching)?;
        let c = solver.constraints(Form::Shooting, &e.segments, x, &c3_joints);
        if c.len() != nc {
            return None;
        }
        let (mut a, mut g) = normal_equations(solver, &jr, &pattern, e, assign);
        let floor = DIAGONAL_FLOOR * a.max_diagonal().max(f64::MIN_POSITIVE);
        // An unknown on its bound that the descent direction pushes beyond it is held there
        // (an active set): clamped after the step instead, it bends every step the model
        // predicts, and the damping rises until the steps are too short to matter. So is one
        // that the step itself pushes beyond (the joint equations can ask it of an unknown the
        // gradient alone would not move there: a stroke's end curvature on the cap, clamped
        // back from each trial, left the model eight times too hopeful, ρ ≈ 0.1, for ten
        // steps); the step is then solved again.
        let mut jc = jc;
        let mut held = vec![false; m];
        let hold = |i: usize,
                    held: &mut [bool],
                    a: &mut Normal,
                    g: &mut DVector<f64>,
                    jc: &mut ConstraintJacobian| {
            held[i] = true;
            a.hold(i, floor.max(1.0));
            g[i] = 0.0;
            jc.clear_column(i);
        };
        for (i, &var) in vars.iter().enumerate() {
            if solver.frozen(var, layout.n())
                || layout.pushed_beyond(var, x, -g[i], solver.log_kappa)
            {
                hold(i, &mut held, &mut a, &mut g, &mut jc);
            }
        }
        let mut accepted = None;
        'assemble: for _ in 0..=m {
            // The KKT system [A + λD, Jcᵀ; Jc, 0] in the band order, as its nonzero entries.
            let mut entries = Vec::with_capacity(
                a.stored() + 2 * (0..m).map(|j| jc.column(j).len()).sum::<usize>() + nc,
            );
            // Whether some unknown moves each constraint.
            let mut moved_by = vec![false; nc];
            for j in 0..m {
                for (i, v) in a.column(j) {
                    entries.push((position[i], position[j], v));
                }
                for &(r, v) in jc.column(j) {
                    moved_by[r] = true;
                    entries.push((position[m + r], position[j], v));
                    entries.push((position[j], position[m + r], v));
                }
            }
            // A constraint no unknown moves (one among held segments, see [`Solver::window`])
            // gets a unit diagonal: its multiplier then moves nothing.
            for r in (0..nc).filter(|&r| !moved_by[r]) {
                entries.push((position[m + r], position[m + r], 1.0));
            }
            let (lower, upper) = entries.iter().fold((0, 0), |(l, u), &(i, j, _)| {
                (l.max(i.saturating_sub(j)), u.max(j.saturating_sub(i)))
            });
            let mut rhs = vec![0.0; m + nc];
            for i in 0..m {
                rhs[position[i]] = -g[i];
            }
            for r in 0..nc {
                rhs[position[m + r]] = -c[r];
            }
            // The trials' chord projections share one factor of the constraint Jacobian.
            let mut chord: Option<Option<LeastNorm>> = None;
            while damping.may_try() {
                let mut kkt = BandMatrix::zeros(m + nc, lower, upper);
                for &(i, j, v) in &entries {
                    kkt.add(i, j, v);
                }
                for i in 0..m {
                    kkt.add(
                        position[i],
                        position[i],
                        damping.lambda() * a.diagonal(i).max(floor),
                    );
                }
                let Some(solution) = kkt.solve(&rhs) else {
                    damping.refuse();
                    continue;
                };
                let delta = DVector::from_iterator(m, (0..m).map(|i| solution[position[i]]));
                let beyond: Vec<usize> = (0..m)
                    .filter(|&i| {
                        !held[i] && layout.pushed_beyond(vars[i], x, delta[i], solver.log_kappa)
                    })
                    .collect();
                if !beyond.is_empty() {
                    for i in beyond {
                        hold(i, &mut held, &mut a, &mut g, &mut jc);
                    }
                    continue 'assemble;
                }
                // The decrease of Σr² the Gauss–Newton model predicts for this step. Below the
                // stopping fraction the step could not continue the solve even if it were
                // accepted: converged (or damped to a standstill), without spending a
                // projection. A round of [`minimax`] takes its first step whatever it gains:
                // the reweighting moves the weighted cost's minimum by little (often under the
                // fraction: the round then ended where it began and the next reweighted the
                // same chain), but towards the largest distance, which is what the round is for.
                let predicted = -(2.0 * g.dot(&delta) + delta.dot(&a.times(&delta)));
                let stop_below = if solver.minimax && iteration == 0 {
                    0.0
                } else if solver.polish {
                    polish_stop(e.cost, e, free)
                } else {
                    RELATIVE_DECREASE * e.cost
                };
                if !(predicted > stop_below) {
                    break;
                }
                let mut trial = step_by(layout, x, &vars, &delta);
                let factor = chord
                    .get_or_insert_with(|| LeastNorm::new(&jc, &constraint_rows))
                    .as_ref();
                let projected = project(
                    Form::Shooting,
                    solver,
                    layout,
                    &mut trial,
                    &c3_joints,
                    Some(factor),
                )
                // Chord steps that do not reach the constraints: once more with fresh
                // Jacobians before the step is refused (see [`project`]).
                .or_else(|| {
                    trial = step_by(layout, x, &vars, &delta);
                    project(Form::Shooting, solver, layout, &mut trial, &c3_joints, None)
                });
                let Some(segments) = projected else {
                    damping.refuse();
                    continue;
                };
                let Some(t) = solver.evaluate_below(segments, assign, Some((e, assign)), e.cost)
                else {
                    damping.refuse();
                    continue;
                };
                if t.cost < e.cost {
                    let rho = ((e.cost - t.cost) / predicted).min(1.0);
                    damping.accept(rho);
                    accepted = Some((trial, t));
                    break;
                }
                damping.refuse();
            }
            break;
        }
        let Some((trial, t)) = accepted else {
            break;
        };
        // A polish step that pulls a segment away from its samples ends the polish at the
        // chain before it (see [`EXTENSION_REACH`]).
        if solver.polish && beyond_reach(&t) {
            break;
        }
        let decrease = e.cost - t.cost;
        let before = e.cost;
        let within = largest_distance(&t) <= solver.tolerance;
        if solver.polish {
            if within {
                last_within = None;
            } else if largest_distance(e) <= solver.tolerance {
                last_within = Some((x.clone(), e.clone(), assign.to_vec()));
            }
        }
        *x = trial;
        *e = t;
        if solver.minimax && within {
            break;
        }
        let stop = if solver.polish {
            decrease <= polish_stop(before, e, free)
        } else {
            decrease <= RELATIVE_DECREASE * before
                || (decrease <= WITHIN_DECREASE * before && within)
        };
        if !reassigned(solver, e, assign) && stop {
            break;
        }
    }
    // A polish carries a chain within the tolerance towards its least-squares minimum, which
    // may lie beyond it; the answer must hold it. Where the polish ends beyond the tolerance,
    // its last chain within it is its answer rather than none (which left the part's chain
    // unpolished). Refusing the step that leaves instead stopped polishes that come back within
    // it. Measured in docs/performance-history.md (chain constants).
    if let Some((wx, we, wa)) = last_within
        && largest_distance(e) > solver.tolerance
    {
        *x = wx;
        *e = we;
        assign.clone_from_slice(&wa);
    }
    Some(())
}

/// The constrained fit from `x` (shooting form, see [`Form`]), then the answer laid out forward
/// so that the joints meet exactly; the forward chain's evaluation, or `None` where no chain
/// meeting the constraints could be built. `x` keeps the shooting solution (the next cut starts
/// from it). `near`: an evaluation of a chain close to `x`'s with its assignment (the last
/// round's, in [`minimax`]), whose feet seed the first evaluation's where a segment holds the
/// same samples.
pub(super) fn solve(
    solver: &Solver,
    layout: &Layout,
    x: &mut Params,
    assign: &mut [Vec<usize>],
    near: Option<(&Evaluation, &[Vec<usize>])>,
) -> Option<Evaluation> {
    let c3_joints = layout.c3_joints();
    // Where the layout below starts from (see [`Solver::lay_out_from_start`]).
    let started =
        (solver.lay_out_from_start && solver.window.is_none() && near.is_none()).then(|| x.clone());
    let segments = match project(Form::Shooting, solver, layout, x, &c3_joints, None) {
        Some(segments) => segments,
        None => {
            // The G1 chain's joints are too far from a smooth chain's for the joint equations
            // (a tangent gap of 1.5 rad where no α ≤ 0 turns a segment ending at an inflection
            // as far as the G1 one did): the chain laid out forward from its start meets them by
            // construction and leaves only its end point to move. Its poses start the fit.
            if let Some(started) = started {
                *x = started;
            }
            let (mut forward, segments) = laid_forward(solver, layout, x, &c3_joints)?;
            forward.pose = segments.iter().map(|s| (s.start(), s.theta0())).collect();
            *x = forward;
            segments
        }
    };
    // The polish iterates on the joints' extensions (see [`Solver::extend`]); the answer is
    // measured against its own segments.
    let extend = solver.extend.replace(solver.polish);
    let mut e = solver.evaluate(segments, assign, near);
    reassigned(solver, &mut e, assign);
    let solved = levenberg_marquardt(solver, layout, x, assign, &mut e);
    solver.extend.set(extend);
    solved?;
    let (_, segments) = laid_forward(solver, layout, x, &c3_joints)?;
    // The forward chain is the solution's to the joints' gaps (a tenth of the tolerance): each
    // foot is polished from the solution's own, not searched for again along the whole
    // segment. A polished foot is a local nearest point, its distance never below the global
    // one, so a chain found within the tolerance is within it.
    Some(solver.evaluate(segments, assign, Some((&e, assign))))
}

/// The chain of `x` laid out forward from its first pose, its end point brought onto the
/// target by [`project`]: the unknowns there and the chain; `None` where the projection fails.
pub(super) fn laid_forward(
    solver: &Solver,
    layout: &Layout,
    x: &Params,
    c3_joints: &[usize],
) -> Option<(Params, Vec<LacSegment>)> {
    let mut forward = x.clone();
    forward.theta0 = forward.pose[0].1;
    // A free end is where the chain laid out forward ends: nothing to meet but C3's equations.
    if layout.free_end() {
        let laid = layout.build_form(Form::Forward, &forward).ok()?;
        forward.end = laid.last()?.end();
        if !solver.c3 {
            return Some((forward, laid));
        }
    }
    let segments = project(Form::Forward, solver, layout, &mut forward, c3_joints, None)?;
    Some((forward, segments))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{Point, Vec2};

    /// A sample may sit on a segment's extension up to [`EXTENSION_REACH`] of that segment's own
    /// length past either end; one farther ends the polish, whichever segment it is.
    #[test]
    fn a_sample_beyond_a_segments_length_past_its_end_is_out_of_reach() {
        let short =
            LacSegment::new(Point::ORIGIN, 0.0, 10.0, Some(0.5), 0.02, 0.05).expect("a segment");
        let long = LacSegment::new(short.end(), short.theta1(), 40.0, Some(-1.0), 0.05, 0.01)
            .expect("a segment");
        let evaluation = |feet: [Vec<f64>; 2]| Evaluation {
            segments: vec![short, long],
            residuals: feet.iter().map(|f| vec![0.0; f.len()]).collect(),
            foot_points: feet
                .iter()
                .map(|f| vec![(Point::ORIGIN, Vec2::ZERO); f.len()])
                .collect(),
            feet: feet.to_vec(),
            cost: 0.0,
        };
        let reach = EXTENSION_REACH;
        let within = evaluation([
            vec![-9.9 * reach, 5.0, 10.0 + 9.9 * reach],
            vec![-39.9 * reach, 40.0 + 39.9 * reach],
        ]);
        assert!(!beyond_reach(&within));
        for feet in [
            [vec![10.0 + 10.1 * reach], vec![20.0]],
            [vec![-10.1 * reach], vec![20.0]],
            [vec![5.0], vec![40.0 + 40.1 * reach]],
            [vec![5.0], vec![-40.1 * reach]],
        ] {
            assert!(beyond_reach(&evaluation(feet.clone())), "{feet:?}");
        }
    }
}
