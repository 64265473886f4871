//! One part between corners: its smooth fit from the G1 chain, again from other joint
//! curvatures where the first start fails, and a joint pressed on the curvature bound found.

use super::ends::curvature_cap;
use super::layout::{Layout, Params};
use super::lm::solve;
use super::settle::{hold_tolerance, settle};
use super::solver::{Solver, distances, worst_sample};
use super::start::{cut, g1_alpha_start, start_layout};
use super::{
    END_TOLERANCE, MAX_CUT_ROUNDS, MAX_RADIUS_EXTENTS, MAX_SEGMENTS, STALLED_ROUNDS, SmoothInput,
    TRIAL_GAP_TOLERANCES,
};
use crate::chain::assign::own_points;
use crate::chain::record::{Chain, ChainSegment, Continuity};

/// Why a part's smooth fit failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Missed {
    /// It missed the tolerance with a joint's curvature on the bound
    /// ([`MIN_RADIUS_TOLERANCES`], [`MAX_TURN_PER_SAMPLE`]): the G1 joint (index in the part,
    /// 1..n) nearest it.
    Bound(usize),
    /// A round's solve gave no chain: its start met neither the joint equations nor, laid out
    /// forward, the part's end (see [`Solver::lay_out_from_start`]).
    Unstarted,
    /// Otherwise (no chain meeting the constraints, or cuts that stopped helping).
    Other,
}

/// [`smooth_chain`] of a chain without forced corners.
pub(super) fn smooth_part(smooth: &SmoothInput) -> Result<Chain, Missed> {
    let input = smooth.input;
    let chain = smooth.chain;
    // Each G1 segment's own samples (a sample on a range boundary, which a segment without
    // samples repeats, belongs to one segment only).
    let assign = own_points(input, &chain.segments);
    // One segment has no joint to make smooth: it is its own G2 (and C3) chain.
    if chain.segments.len() == 1 {
        return Ok(Chain {
            continuity: smooth.continuity,
            ..chain.clone()
        });
    }
    // The joints' curvatures start at the B-spline's; where the fit cannot start or finish from
    // there, at the G1 chain's own (the two sides' geometric mean). A miss against the curvature
    // bound is the samples' (the joint becomes a corner, see [`smooth_chain`]): on the fixture
    // strokes the second start never held where the first missed so, in 11 tries.
    // Where neither start holds (nor misses against the bound) and the first could not lay a
    // round's chain out ([`Missed::Unstarted`]), the first is tried once more with its chain
    // laid out forward from the start itself ([`Solver::lay_out_from_start`]): at 0.5 px, below
    // the hey stroke's noise floor, a part of 14 segments failed both starts so and stayed G1.
    // A first start that failed otherwise would fail the same way again.
    let mut first = None;
    for (start, from_start) in [
        (JointStart::Spline, false),
        (JointStart::Chain, false),
        (JointStart::Spline, true),
    ] {
        if from_start && first != Some(Missed::Unstarted) {
            break;
        }
        match smooth_from(smooth, assign.clone(), start, from_start) {
            Ok(chain) => return Ok(chain),
            Err(missed @ Missed::Bound(_)) => return Err(missed),
            Err(missed) => {
                first.get_or_insert(missed);
            }
        }
    }
    Err(Missed::Other)
}

/// Where the joints' curvatures of the starting chain come from (see [`start_layout`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum JointStart {
    /// The B-spline's curvature at the joint, where its sign agrees with the chain's.
    Spline,
    /// The G1 chain's two sides' geometric mean.
    Chain,
}

/// [`smooth_part`] from the joint curvatures of `start` (`lay_out_from_start`: see
/// [`Solver::lay_out_from_start`]).
pub(super) fn smooth_from(
    smooth: &SmoothInput,
    mut assign: Vec<Vec<usize>>,
    joint_start: JointStart,
    lay_out_from_start: bool,
) -> Result<Chain, Missed> {
    let points = smooth.input.points;
    let chain = smooth.chain;
    let max_log_kappa = curvature_cap(points, smooth.tolerance).ln();
    let extent = points
        .iter()
        .map(|p| p.distance(points[0]))
        .fold(smooth.tolerance, f64::max);
    let min_log_kappa = -(MAX_RADIUS_EXTENTS * extent).ln();
    let (mut layout, mut x) =
        start_layout(smooth, &mut assign, max_log_kappa, joint_start).ok_or(Missed::Other)?;
    let start = chain.segments[0].segment.start();
    let end = chain.segments.last().ok_or(Missed::Other)?.segment.end();
    let extent = points
        .iter()
        .map(|p| p.distance(start))
        .fold(start.distance(end), f64::max);
    let mut solver = Solver {
        points,
        start,
        scale: extent.max(smooth.tolerance),
        chord_error: smooth.chord_error,
        log_kappa: (min_log_kappa, max_log_kappa),
        c3: smooth.continuity == Continuity::C3,
        trial_slack: (TRIAL_GAP_TOLERANCES * smooth.tolerance / extent.max(smooth.tolerance))
            .max(END_TOLERANCE)
            / END_TOLERANCE,
        weights: Vec::new(),
        minimax: false,
        polish: false,
        tolerance: smooth.tolerance,
        window: None,
        lay_out_from_start,
        extend: std::cell::Cell::new(false),
    };
    layout.clamp(&mut x, solver.log_kappa);
    let (mut best_worst, mut stalled) = (f64::INFINITY, 0);
    for round in 0..=MAX_CUT_ROUNDS {
        if layout.n() > MAX_SEGMENTS {
            return Err(Missed::Other);
        }
        let started = (round == 0).then(|| (x.clone(), assign.clone()));
        let mut evaluation =
            solve(&solver, &layout, &mut x, &mut assign, None).ok_or(Missed::Unstarted)?;
        // The starting α match the G1 chain's turning (see [`start_layout`]); where the fit
        // ended with such an α pressed on its bound while the G1 chain's own α lies inside,
        // it may sit in a local minimum that the G1 α avoids (a planted S of two clothoids on a
        // pixel grid: α −3 against the planted −1, a third more cost): the fit from the G1 α
        // is tried too and the lower cost kept (also where the first holds the tolerance: its
        // curvature profile can be 13 % off the planted one).
        if let Some((mut other, mut other_assign)) = started
            && let Some(g1_alpha) = g1_alpha_start(&layout, &x, &other, &chain.segments)
        {
            other.alpha = g1_alpha;
            if let Some(e) = solve(&solver, &layout, &mut other, &mut other_assign, None)
                && e.cost < evaluation.cost
            {
                (evaluation, x, assign) = (e, other, other_assign);
            }
        }
        let own = distances(&evaluation);
        let (worst, _) = worst_sample(&own);
        if let Some(refit) = hold_tolerance(
            smooth,
            &mut solver,
            &layout,
            (&x, &assign, &evaluation),
            worst,
        ) {
            let (e, a, z) = match &refit {
                Some((e, a, z)) => (e, a.as_slice(), z),
                None => (&evaluation, assign.as_slice(), &x),
            };
            let answer = settle(smooth, &mut solver, (&layout, z, a, e), refit.is_none());
            return Ok(answer.record(smooth));
        }
        if let missed @ Missed::Bound(_) = on_bound(&layout, &x, &chain.segments, max_log_kappa) {
            return Err(missed);
        }
        if worst < best_worst {
            best_worst = worst;
            stalled = 0;
        } else {
            stalled += 1;
            if stalled >= STALLED_ROUNDS {
                return Err(on_bound(&layout, &x, &chain.segments, max_log_kappa));
            }
        }
        // Every segment that misses the tolerance is cut, the last first (a cut shifts the
        // indices after it).
        let missing: Vec<usize> = (0..own.len())
            .filter(|&k| own[k].iter().any(|&d| d > smooth.tolerance))
            .collect();
        if missing.is_empty() {
            return Err(Missed::Other);
        }
        for &k in missing.iter().rev() {
            cut(
                &mut layout,
                &mut x,
                &mut assign,
                &evaluation,
                k,
                smooth.alpha,
            )
            .ok_or(Missed::Other)?;
        }
    }
    Err(on_bound(&layout, &x, &chain.segments, max_log_kappa))
}

/// Relative margin within which a joint's log-curvature counts as on its upper bound.
pub(super) const ON_BOUND: f64 = 1e-9;

/// The failure of a fit that ended at `x`: [`Missed::Bound`] with the G1 joint nearest the
/// interior joint whose curvature sits on the upper bound (the largest such G1 joint's own bend
/// where the bound is reached inside a G1 segment), else [`Missed::Other`].
pub(super) fn on_bound(
    layout: &Layout,
    x: &Params,
    g1: &[ChainSegment],
    max_log_kappa: f64,
) -> Missed {
    let n = layout.n();
    let bend = |j: usize| -> f64 {
        // A G1 joint's own bend: the larger curvature of its two sides.
        match (g1.get(j.wrapping_sub(1)), g1.get(j)) {
            (Some(a), Some(b)) => a.segment.kappa1().abs().max(b.segment.kappa0().abs()),
            _ => 0.0,
        }
    };
    let mut best: Option<(f64, usize)> = None;
    for j in 1..n {
        if layout.sigma[j] == 0.0
            || x.u[j] < max_log_kappa - ON_BOUND * max_log_kappa.abs().max(1.0)
        {
            continue;
        }
        let (before, after) = (layout.origin[j - 1], layout.origin[j]);
        // A joint between G1 segments is that G1 joint; one cut inside a G1 segment stands for
        // the segment's end that bends more.
        let candidate = if before == after && bend(after + 1) > bend(after) {
            after + 1
        } else {
            after
        };
        if candidate == 0 || candidate >= g1.len() {
            continue;
        }
        let b = bend(candidate);
        if best.is_none_or(|(m, _)| b > m) {
            best = Some((b, candidate));
        }
    }
    best.map_or(Missed::Other, |(_, j)| Missed::Bound(j))
}
