//! Whether a solved chain holds the tolerance, and the polish that carries the last such chain
//! towards its least-squares minimum.

use super::finish::finish;
use super::layout::{Layout, Params};
use super::lm::{minimax, solve};
use super::removal::fewer_joints;
use super::solver::{Evaluation, Solver, distances};
use super::{MINIMAX_REACH, SmoothInput};
use crate::chain::measure::own_deviation;
use crate::chain::record::Chain;

/// Whether the solved chain `e` of `x` (its samples assigned as `assign`, the largest distance
/// `worst`) holds the tolerance: `Some(None)` where it does as solved; where it misses by at
/// most [`MINIMAX_REACH`] and its minimax refit ([`minimax`]: a near miss is first fitted for its
/// largest distance rather than cut, see [`MINIMAX_ROUNDS`]) holds, `Some` of that round's
/// evaluation, assignment and unknowns. `None` where neither holds.
#[allow(clippy::type_complexity)]
pub(super) fn hold_tolerance(
    smooth: &SmoothInput,
    solver: &mut Solver,
    layout: &Layout,
    (x, assign, e): (&Params, &[Vec<usize>], &Evaluation),
    worst: f64,
) -> Option<Option<(Evaluation, Vec<Vec<usize>>, Params)>> {
    if worst <= smooth.tolerance {
        return holds(smooth, e).then_some(None);
    }
    if !(worst <= MINIMAX_REACH * smooth.tolerance) {
        return None;
    }
    let (e, a, z) = minimax(solver, layout, x, assign, e)?;
    holds(smooth, &e).then_some(Some((e, a, z)))
}

/// Whether every sample of `e` is within the tolerance of its own segment, the chain's honest
/// measure ([`own_deviation`] measures it afresh for the record, [`Solved::record`], once a
/// part's answer is chosen). A distance that is not a number never holds.
pub(super) fn holds(smooth: &SmoothInput, e: &Evaluation) -> bool {
    e.residuals
        .iter()
        .flatten()
        .all(|r| r.abs() <= smooth.tolerance)
}

/// The part's answer from the solved chain of `x` that holds the tolerance: its joints
/// removed where they can go ([`fewer_joints`]), then polished ([`polish`]). A chain that held
/// only after its minimax rounds (`least_squares` false) is polished only where a removal
/// changed it: its own least-squares fit is the one that missed. (A removal that held only after
/// minimax rounds is polished: the least-squares solve from its minimax chain can find another
/// minimum that holds; measured in `docs/performance-history.md` (chain constants).)
pub(super) fn settle(
    smooth: &SmoothInput,
    solver: &mut Solver,
    (layout, x, assign, evaluation): (&Layout, &Params, &[Vec<usize>], &Evaluation),
    least_squares: bool,
) -> Solved {
    let as_solved = || Solved {
        layout: layout.clone(),
        x: x.clone(),
        assign: assign.to_vec(),
        evaluation: evaluation.clone(),
    };
    match fewer_joints(smooth, solver, layout, x, assign, evaluation) {
        Some(s) => polish(smooth, solver, (&s.layout, &s.x, &s.assign, &s.evaluation)).unwrap_or(s),
        None if least_squares => {
            polish(smooth, solver, (layout, x, assign, evaluation)).unwrap_or_else(as_solved)
        }
        None => as_solved(),
    }
}

/// A solved chain: its layout, unknowns, the samples' assignment and its evaluation. Where it
/// holds the tolerance ([`holds`]), its record ([`Solved::record`]: the samples' distances to
/// the whole chain and each α's standard error) is made only for the part's answer, not for
/// every chain the removals and the polish pass on the way (on painting stroke 7, a stroke at
/// the median ratio to the G1 chain, the records of the chains passed on had been a twentieth
/// of its smooth fit).
pub(super) struct Solved {
    pub(super) layout: Layout,
    pub(super) x: Params,
    pub(super) assign: Vec<Vec<usize>>,
    pub(super) evaluation: Evaluation,
}

impl Solved {
    /// The chain record, with the largest distance from a sample to its own segment.
    pub(super) fn record(&self, smooth: &SmoothInput) -> Chain {
        let (e, assign) = (&self.evaluation, &self.assign);
        let largest = own_deviation(
            smooth.input.points,
            &e.segments,
            assign,
            &distances(e),
            smooth.chord_error,
        );
        finish(smooth, &self.layout, e, assign, largest)
    }
}

/// The solved chain of `x` (which holds the tolerance) polished towards its least-squares
/// minimum, where that lowers its squared distances and still holds the tolerance (a polish
/// whose steps end beyond the tolerance ends at its last chain within it, see
/// [`levenberg_marquardt`]); `None` where it does not (the chain as solved is then the
/// answer): the solve that found it stops as soon as a step gains little while every sample is
/// within the tolerance ([`WITHIN_DECREASE`]), and the cuts, minimax rounds and removals that
/// led to it aim at the tolerance, not at the lowest deviation.
pub(super) fn polish(
    smooth: &SmoothInput,
    solver: &mut Solver,
    (layout, x, assign, evaluation): (&Layout, &Params, &[Vec<usize>], &Evaluation),
) -> Option<Solved> {
    let (mut y, mut a) = (x.clone(), assign.to_vec());
    solver.polish = true;
    let e = solve(solver, layout, &mut y, &mut a, Some((evaluation, assign)));
    solver.polish = false;
    let e = e?;
    // Unweighted: a removal's evaluation may be a minimax round's, whose cost is weighted.
    let squares = |e: &Evaluation| e.residuals.iter().flatten().map(|r| r * r).sum::<f64>();
    if !(squares(&e) < squares(evaluation)) {
        return None;
    }
    holds(smooth, &e).then(|| Solved {
        layout: layout.clone(),
        x: y,
        assign: a,
        evaluation: e,
    })
}
