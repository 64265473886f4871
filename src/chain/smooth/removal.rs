//! Fewer joints: a smooth chain's joints removed where the chain without them still holds the
//! tolerance (flat points, bumps, end flips), each removal solved again from its neighbours.

use super::layout::{Layout, Params};
use super::lm::solve;
use super::settle::{Solved, hold_tolerance};
use super::solver::{Evaluation, Solver, distances, worst_sample};
use super::start::{join_at, set_alpha_bounds};
use super::{REMOVAL_REACH, SmoothInput};
use crate::lac::LacSegment;

/// The solved chain with fewer joints, where one holds the tolerance: the fewest segments in
/// the continuity mode, which the G1 chain that starts the fit does not decide (its segments
/// are fitted to the samples' positions and tangents one by one). A joint can go where the
/// curvature runs monotonically through it (one log-aesthetic segment can then span both
/// neighbours; at a curvature extremum none can), tried in the order of the two sides' α
/// difference (a straight log curvature graph through the joint first). Each removal is solved
/// afresh from the joined chain (a near miss refitted towards its minimax fit, as the cut rounds
/// do) and kept where every sample is within the tolerance. A joint that could not go is tried
/// again only after a removal next to it (a removal reshapes its neighbourhood; elsewhere the
/// chain moves little), so a part of n segments costs about n solves, not n per removal.
/// Where no joint can go as it stands, the curvature's shape is changed where the samples
/// cannot show it, so that joints can go: a flat point made a zero joint ([`flat_points`]), a
/// bump between two inflections flattened ([`bumps`]), an inflection next to a part's end
/// dropped ([`end_flips`]); each is tried like a removal and, where it failed, again only after
/// a removal next to it. `None` where no joint can go.
pub(super) fn fewer_joints(
    smooth: &SmoothInput,
    solver: &mut Solver,
    layout: &Layout,
    x: &Params,
    assign: &[Vec<usize>],
    evaluation: &Evaluation,
) -> Option<Solved> {
    let (mut layout, mut x, mut assign) = (layout.clone(), x.clone(), assign.to_vec());
    let mut kept = evaluation.clone();
    let mut removed_any = false;
    // Per joint: tried and kept. A removal changes the chain near it only, so a joint that
    // could not go is tried again only once a neighbouring segment has changed.
    let mut failed = vec![false; layout.n() + 1];
    // Per joint: a flat point or bump made there did not hold (the same locality).
    let mut failed_move = vec![false; layout.n() + 1];
    'fewer: loop {
        let n = layout.n();
        let mut joints: Vec<(f64, usize)> = (1..n)
            .filter(|&j| !failed[j])
            .filter(|&j| {
                let (a, m, b) = (
                    layout.kappa(&x, j - 1),
                    layout.kappa(&x, j),
                    layout.kappa(&x, j + 1),
                );
                let sign = layout.sigma[j];
                sign != 0.0
                    && layout.sigma[j - 1] != -sign
                    && layout.sigma[j + 1] != -sign
                    && (m - a) * (b - m) >= 0.0
            })
            .map(|j| ((x.alpha[j - 1] - x.alpha[j]).abs(), j))
            .collect();
        joints.sort_by(|p, q| p.0.total_cmp(&q.0));
        for (_, j) in joints {
            failed[j] = true;
            let Some(found) = remove_joints(
                smooth,
                solver,
                (&layout, &x, assign.as_slice(), &kept),
                None,
                &[j],
            ) else {
                continue;
            };
            removed_any = true;
            (layout, x, assign, kept) = (found.layout, found.x, found.assign, found.evaluation);
            drop_joints(&mut failed, &[j]);
            drop_joints(&mut failed_move, &[j]);
            continue 'fewer;
        }
        // No joint can go as it is: where the curvature falls towards zero and rises again
        // without changing sign (a flat point), the joint at its least is made a zero joint and
        // its neighbours go with it (see [`flat_points`]).
        // And where it changes sign twice within the noise (a bump), the bump's joint takes
        // the curvature of the curve around it and its two zero joints go (see [`bumps`]).
        let moves = flat_points(&layout, &x, &kept.segments, smooth.tolerance)
            .into_iter()
            .chain(bumps(&layout, &x, &kept.segments, smooth.tolerance))
            .chain(end_flips(&layout, &x, &kept.segments, smooth.tolerance));
        for (reset, drops) in moves {
            let at = reset.joint();
            if failed_move[at] {
                continue;
            }
            failed_move[at] = true;
            let found = remove_joints(
                smooth,
                solver,
                (&layout, &x, assign.as_slice(), &kept),
                Some(reset),
                &drops,
            );
            let Some(found) = found else {
                continue;
            };
            removed_any = true;
            (layout, x, assign, kept) = (found.layout, found.x, found.assign, found.evaluation);
            drop_joints(&mut failed, &drops);
            drop_joints(&mut failed_move, &drops);
            continue 'fewer;
        }
        break;
    }
    removed_any.then_some(Solved {
        layout,
        x,
        assign,
        evaluation: kept,
    })
}

/// Per-joint flags of [`fewer_joints`] once the joints `drops` (in decreasing order) went: their
/// entries removed, and those of the joined segments' joints cleared (their neighbourhood
/// changed, so what failed there may hold now).
pub(super) fn drop_joints(flags: &mut Vec<bool>, drops: &[usize]) {
    for &d in drops {
        if d < flags.len() {
            flags.remove(d);
        }
    }
    let (Some(&low), Some(&high)) = (drops.iter().min(), drops.iter().max()) else {
        return;
    };
    // The joined segments run from joint low − 1 to joint high + 1 − drops.len().
    let end = (high + 1).saturating_sub(drops.len());
    for f in flags.iter_mut().take(end + 1).skip(low.saturating_sub(1)) {
        *f = false;
    }
}

/// The solved chain `(layout, x, assign, kept)` with the joints `drops` removed (in decreasing
/// order, each joining the segments on its two sides) and, first, the joint of `reset` made a
/// zero joint or given its curvature, solved locally ([`REMOVAL_REACH`] segments each side of
/// the joined ones move, the rest of the part stays and keeps its samples' distances): the
/// solved chain where it holds the tolerance (or does after minimax rounds, see [`hold_tolerance`]).
/// `None` otherwise.
pub(super) fn remove_joints(
    smooth: &SmoothInput,
    solver: &mut Solver,
    (layout, x, assign, kept): (&Layout, &Params, &[Vec<usize>], &Evaluation),
    reset: Option<Reset>,
    drops: &[usize],
) -> Option<Solved> {
    let (mut l, mut y, mut a) = (layout.clone(), x.clone(), assign.to_vec());
    if let Some(reset) = reset {
        let j = match reset {
            Reset::Zero(j) => {
                l.sigma[j] = 0.0;
                j
            }
            Reset::Curvature(j, kappa) => {
                l.sigma[j] = kappa.signum();
                y.u[j] = kappa.abs().ln();
                j
            }
        };
        let n = l.n();
        for k in (j.saturating_sub(1)..=j).filter(|&k| k < n) {
            set_alpha_bounds(smooth.alpha, &mut l, &mut y, k)?;
        }
    }
    // The evaluation near the joined chain: `kept` without the segments the drops take out.
    let mut near: Option<Evaluation> = None;
    let mut near_assign = assign.to_vec();
    for &j in drops {
        join_at(smooth.alpha, &mut l, &mut y, &mut a, &kept.segments, j)?;
        near = Some(without(near.as_ref().unwrap_or(kept), j));
        near_assign.remove(j);
    }
    let near = near?;
    l.clamp(&mut y, solver.log_kappa);
    // The joined segments: the last drop's left one to the first drop's, less the drops after it.
    let low = drops.iter().min()?.checked_sub(1)?;
    let high = drops.iter().max()?.checked_sub(drops.len())?;
    let window = (
        low.saturating_sub(REMOVAL_REACH),
        (high + REMOVAL_REACH).min(l.n() - 1),
    );
    solver.window = (window != (0, l.n() - 1)).then_some(window);
    let mut tried = None;
    if let Some(e) = solve(solver, &l, &mut y, &mut a, Some((&near, &near_assign))) {
        let worst = worst_sample(&distances(&e)).0;
        if let Some(refit) = hold_tolerance(smooth, solver, &l, (&y, &a, &e), worst) {
            tried = Some(refit.unwrap_or((e, a, y)));
        }
    }
    solver.window = None;
    let (e, a, y) = tried?;
    Some(Solved {
        layout: l,
        x: y,
        assign: a,
        evaluation: e,
    })
}

/// Flat points of the chain `x` (its segments `segments`): interior joints j whose curvature is
/// smaller in magnitude than at both neighbouring joints, all three of one sign (the curvature
/// falls towards zero and rises again without an inflection), each with the joints that go when
/// it is made a zero joint: its two neighbours (one where the other is the part's end), in
/// decreasing index. No log-aesthetic segment spans a curvature extremum, so the chain keeps a
/// joint on each side of a small non-zero least where a zero there needs none: a planted chain
/// falling to κ = 0 and rising again on the same side, drawn on whole pixels, came back as four
/// segments for two. Only a least within the noise of zero is tried: a curvature m over the two
/// segments around the joint bends them by m·L²/8 off their chord, and where that exceeds the
/// tolerance the samples show the curvature. Ordered by the curvature at j relative to its
/// neighbours', the nearest to zero first.
///
/// It trades a little more work for fewer segments; measured in
/// `docs/performance-history.md` (chain constants).
pub(super) fn flat_points(
    layout: &Layout,
    x: &Params,
    segments: &[LacSegment],
    tolerance: f64,
) -> Vec<(Reset, Vec<usize>)> {
    let n = layout.n();
    let found = (1..n)
        .filter_map(|j| {
            let sign = layout.sigma[j];
            if sign == 0.0 || layout.sigma[j - 1] != sign || layout.sigma[j + 1] != sign {
                return None;
            }
            let (a, m, b) = (
                layout.kappa(x, j - 1).abs(),
                layout.kappa(x, j).abs(),
                layout.kappa(x, j + 1).abs(),
            );
            if !(m < a && m < b) {
                return None;
            }
            let span = segments[j - 1].length() + segments[j].length();
            if !(sagitta(m, span) <= tolerance) {
                return None;
            }
            let drops = match (j >= 2, j + 1 < n) {
                (true, true) => vec![j + 1, j - 1],
                (false, true) => vec![j + 1],
                (true, false) => vec![j - 1],
                (false, false) => return None,
            };
            Some((m / a.min(b), Reset::Zero(j), drops))
        })
        .collect();
    order_by_key(found)
}

/// How far a curvature of magnitude `kappa` over a stretch of `length` bends it off its chord:
/// the sagitta κ·L²/8 (to first order). A shape move ([`flat_points`], [`bumps`],
/// [`end_flips`]) is tried only where the curvature it takes away bends its stretch by no
/// more than the tolerance: beyond it the samples show the curvature.
pub(super) fn sagitta(kappa: f64, length: f64) -> f64 {
    kappa.abs() * length * length / 8.0
}

/// Shape moves (a [`Reset`] and the joints that go with it) ordered by their key, the smallest
/// first.
pub(super) fn order_by_key(mut found: Vec<(f64, Reset, Vec<usize>)>) -> Vec<(Reset, Vec<usize>)> {
    found.sort_by(|p, q| p.0.total_cmp(&q.0));
    found
        .into_iter()
        .map(|(_, reset, drops)| (reset, drops))
        .collect()
}

/// End flips of the chain `x` (its segments `segments`): a part's first or last segment that
/// leaves a zero joint with the other sign than the segment beyond that joint (an inflection
/// next to the part's end), each with the end it makes a zero joint and the inflection that
/// goes. Only a flip within the noise is tried: the end's curvature m over the segment's length
/// L bends it by at most m·L²/8 off its chord.
pub(super) fn end_flips(
    layout: &Layout,
    x: &Params,
    segments: &[LacSegment],
    tolerance: f64,
) -> Vec<(Reset, Vec<usize>)> {
    let n = layout.n();
    if n < 2 {
        return Vec::new();
    }
    // (end joint, the inflection next to it, the joint beyond, the end's segment)
    let ends = [(0, 1, 2, 0), (n, n - 1, n - 2, n - 1)];
    ends.into_iter()
        .filter(|&(end, zero, beyond, k)| {
            let sign = layout.sigma[end];
            sign != 0.0
                && layout.sigma[zero] == 0.0
                && layout.sigma[beyond] == -sign
                && sagitta(layout.kappa(x, end), segments[k].length()) <= tolerance
        })
        .map(|(end, zero, _, _)| (Reset::Zero(end), vec![zero]))
        .collect()
}

/// What a joint-removal try sets first (see [`remove_joints`]).
#[derive(Clone, Copy, Debug)]
pub(super) enum Reset {
    /// The joint becomes a zero joint (a flat point, see [`flat_points`]).
    Zero(usize),
    /// The joint takes this curvature, sign included (a bump, see [`bumps`]).
    Curvature(usize, f64),
}

impl Reset {
    /// The joint it sets.
    pub(super) fn joint(self) -> usize {
        match self {
            Reset::Zero(j) | Reset::Curvature(j, _) => j,
        }
    }
}

/// Bumps of the chain `x` (its segments `segments`): interior joints j between two zero joints
/// j ± 1 whose curvature has the other sign than at j ± 2, which share theirs (the curvature
/// changes sign twice and comes back), each with the curvature it takes when the bump goes (the
/// geometric mean of the curvatures at j ± 2) and the zero joints that go with it, in
/// decreasing index. A whole-pixel staircase can read as a wiggle: a planted chain of one sign
/// came back with a bump of κ = 0.054 /px over 1.2 px between two spirals through zero, its
/// curvature profile 33 % off the planted curve's. Each inflection holds a joint that no removal
/// can take (no log-aesthetic segment changes sign). Only a bump within the noise is tried: its
/// largest curvature m over its two segments bends them by m·L²/8 off their chord, and where
/// that exceeds the tolerance the samples show it. Ordered by that bend, the smallest first.
///
/// It trades a little more work for fewer segments; measured in
/// `docs/performance-history.md` (chain constants).
pub(super) fn bumps(
    layout: &Layout,
    x: &Params,
    segments: &[LacSegment],
    tolerance: f64,
) -> Vec<(Reset, Vec<usize>)> {
    let n = layout.n();
    let found = (2..n.saturating_sub(1))
        .filter_map(|j| {
            let outside = layout.sigma[j - 2];
            if outside == 0.0
                || layout.sigma[j + 2] != outside
                || layout.sigma[j] != -outside
                || layout.sigma[j - 1] != 0.0
                || layout.sigma[j + 1] != 0.0
            {
                return None;
            }
            let span = segments[j - 1].length() + segments[j].length();
            let bend = sagitta(layout.kappa(x, j), span);
            if !(bend <= tolerance) {
                return None;
            }
            let kappa = outside
                * (layout.kappa(x, j - 2) * layout.kappa(x, j + 2))
                    .abs()
                    .sqrt();
            Some((bend, Reset::Curvature(j, kappa), vec![j + 1, j - 1]))
        })
        .collect();
    order_by_key(found)
}

/// `e` with segment `j` taken out (its entries of every list), as the evaluation near a chain
/// whose segments j − 1 and j were joined: the segments before and after keep their places.
pub(super) fn without(e: &Evaluation, j: usize) -> Evaluation {
    let drop = |k: &usize| *k != j;
    let keep = |len: usize| (0..len).filter(drop);
    Evaluation {
        segments: keep(e.segments.len()).map(|k| e.segments[k]).collect(),
        residuals: keep(e.residuals.len())
            .map(|k| e.residuals[k].clone())
            .collect(),
        feet: keep(e.feet.len()).map(|k| e.feet[k].clone()).collect(),
        foot_points: keep(e.foot_points.len())
            .map(|k| e.foot_points[k].clone())
            .collect(),
        cost: e.cost,
    }
}
