//! Levenberg–Marquardt refinement of a chain (beyond the seed paper).
//!
//! The B-spline's end points and tangents are only estimates: noise and the pen's dwell bias a
//! tangent at a high-curvature end by a degree or more, and with the G1 data held that moves the
//! best α by 0.1–0.2. Here every joint's position (unless held) and tangent angle and every
//! segment's α are unknowns, each segment stays the Yoshida–Saito segment of its joints (so the
//! chain stays G1), and the sum of squared signed foot-point distances of the samples is
//! minimised: x ← x − (JᵀJ + λ·diag(JᵀJ))⁻¹ Jᵀr, with J by forward differences (a joint moves
//! only its two segments, an α only its own) and λ adapted (Marquardt 1963). A step is taken only
//! when it lowers the cost, so the result is never worse than the start.
//!
//! With the unknowns ordered joint₀, α₀, joint₁, α₁, …, a segment's residuals depend on one
//! contiguous block of at most 7 unknowns, so JᵀJ is a band matrix of half-bandwidth ≤ 6: it is
//! assembled block by block and solved by a band Cholesky ([`super::band`]), O(K) per iteration
//! for K segments instead of the O(K³) of a dense solve.
//!
//! A segment exists only while its G1 data lie in the drawable region of its α, and the best fit
//! often sits at that region's edge (the samples want an α the joints cannot carry). A trial that
//! leaves the region holds that segment from then on: both edges of its region (margins in
//! radians, in the mirror frame of the iterate, see `yoshida_saito::edge_margins`) are
//! linearised at each iterate and the damped step is moved to the nearest step, in the system's
//! own metric, that keeps them (an active-set solve over the held segments, `keep_inside`).
//! Damping alone cannot do that: at the edge every damped step still points outside, only
//! shorter, and the whole chain stalls. One edge is not enough either: a near-straight segment's
//! region is a wedge narrower than a step.

use super::state::{Evaluated, State, cost};
use crate::chain::g1::edges::{EdgeConstraint, keep_inside};
use crate::chain::g1::jacobian::jacobian;
use crate::chain::solve::band::Band;
use crate::chain::solve::damping::{Damping, DampingOptions, DampingRule};
use crate::geom::Point;

/// Options of [`refine`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RefineOptions {
    /// Iteration budget (Jacobian evaluations).
    pub max_iterations: usize,
    /// Allowed α interval; `None` holds every α (a fixed-α chain).
    pub alpha_range: Option<(f64, f64)>,
    /// Chord error of the tracing that seeds the foot points.
    pub chord_error: f64,
    /// Length scale of the chain: the finite-difference steps on positions and the bound on a
    /// segment's length ([`MAX_LENGTH_FACTOR`]) are relative to it.
    pub scale: f64,
    /// The fit's tolerance (a distance): an iteration that moves the rms sample distance by less
    /// than `converged_rms` of it has converged.
    pub tolerance: f64,
    /// See `tolerance`: [`CONVERGED_RMS`] for a chain that is the answer,
    /// [`STARTING_CONVERGED_RMS`] for one that only starts a smooth fit.
    pub converged_rms: f64,
}

/// Finite-difference step on a position, relative to the chain's scale: about √ε of it, the
/// classic optimum for forward differences of a function exact to rounding (the reference
/// Jacobian of the tests; the refinement's own takes positions analytically).
#[cfg(test)]
pub(super) const POSITION_STEP: f64 = 1e-7;
/// Finite-difference step on a tangent angle (radians).
pub(super) const ANGLE_STEP: f64 = 1e-7;
/// Finite-difference step on α.
pub(super) const ALPHA_STEP: f64 = 1e-6;
/// Initial damping relative to the diagonal of JᵀJ. The first step from the α search's chain
/// is rarely in the Gauss–Newton regime (α moves far along the directions the data barely see);
/// measured in `docs/performance-history.md` (chain constants).
pub(super) const LAMBDA_START: f64 = 1e-2;
/// Damping beyond which no step can help any more (the step has shrunk to rounding).
pub(super) const LAMBDA_MAX: f64 = 1e12;
/// Damping growth after a rejected step: ×10 reaches a short, safe step within a few trials
/// (each trial re-evaluates the whole chain).
pub(super) const LAMBDA_GROWTH: f64 = 10.0;
/// The refinement's damping (Marquardt's rule): from [`LAMBDA_START`], ×[`LAMBDA_GROWTH`] after a
/// refused trial, ÷3 after an accepted one (down to 1e-12, far below any step that changes the
/// chain), tries up to [`LAMBDA_MAX`]. Each trial re-evaluates the whole chain, so a refusal
/// jumps far; the smooth fit's projections make its trials dearer still, and it takes Nielsen's
/// rule instead (`smooth::lm::DAMPING`).
pub(super) const DAMPING: DampingOptions = DampingOptions {
    initial: LAMBDA_START,
    max: LAMBDA_MAX,
    rule: DampingRule::Marquardt {
        growth: LAMBDA_GROWTH,
        shrink: 3.0,
        floor: 1e-12,
    },
};
/// Rejected trials per iteration before the refinement stops: after eight the step is 1e-8 of
/// the Gauss–Newton one, and no useful descent is left.
pub(super) const MAX_TRIES: usize = 8;
/// Relative cost decrease below which the iteration has converged: a tenth of a percent of the
/// sum of squared distances moves the rms distance by 0.05 %, invisible against any tolerance;
/// iterating on costs time for nothing. Measured in
/// `docs/performance-history.md` (chain constants).
pub(super) const CONVERGED: f64 = 1e-3;
/// An iteration that lowers the rms sample distance by less than this share of the tolerance has
/// converged too: one percent of the tolerance is far below the pen's noise and invisible against
/// the guarantee, and the iterations after it crawl (most refinements of the fixture strokes then
/// gain another few percent of the cost in tens of iterations, each a full chain evaluation).
pub(crate) const CONVERGED_RMS: f64 = 0.01;
/// [`CONVERGED_RMS`] of a G1 chain that starts a smooth (G2, C3) fit, which moves every joint
/// again: refining it further costs time the smooth fit spends anyway. Measured in
/// `docs/performance-history.md` (chain constants).
pub(crate) const STARTING_CONVERGED_RMS: f64 = 0.05;
/// Margin (radians of chord angle, see [`drawable_margin`]) a step keeps from a drawable-region
/// edge it is held away from: a hundred times the angle probe, so that the next Jacobian's probes
/// stay buildable. A segment already closer keeps its margin instead of losing it.
pub(super) const EDGE_MARGIN: f64 = 1e-5;
/// Finite-difference step of a margin gradient on a position, relative to the chord (the margin
/// is invariant under scaling).
pub(super) const MARGIN_POSITION_STEP: f64 = 1e-7;

/// Longest segment a refinement step may make, as a multiple of the chain's scale
/// ([`RefineOptions::scale`]: the length of its joints' polyline when the chain's refinements
/// are set up). The squared distances do not see a segment's length: a joint with one or two
/// samples nearby can leave through a loop that still passes by them, and a step did so (a
/// fixed-α chain moved a joint 1.8e12 away from a 700-pixel stroke through two segments of
/// length 9e13 and 1.8e12 whose loops met samples 50 and 51, and the export of such a segment
/// never ended). On ordinary strokes it rarely turns a step down; measured in
/// `docs/performance-history.md` (chain constants).
pub(super) const MAX_LENGTH_FACTOR: f64 = 10.0;

/// Farthest a refinement step may take a joint from the B-spline near the parameter it was made
/// at, in tolerances. The chain is held to its samples only (the distance runs from each sample
/// to the chain), so where the stroke passes near itself a joint can slide across to the other
/// pass and still have samples within the tolerance: on a densely sampled spiral (100 000
/// samples, turns a few millimetres apart) 105 of 494 joints ended out of order along the
/// B-spline and the chain missed its tolerance 14 times over. A joint on a chain within the
/// tolerance of samples that lie within the tolerance of the B-spline is within about two
/// tolerances of it; 4 leave room for a joint the chain pulls off a B-spline wobble.
pub(crate) const MAX_JOINT_OFF_CURVE: f64 = 4.0;

/// Whether no joint of `trial` is farther than [`MAX_JOINT_OFF_CURVE`] tolerances from the
/// B-spline near its parameter, unless it already was in `current` and has not moved farther.
pub(super) fn near_curve(
    trial: &State<'_>,
    current: &State<'_>,
    options: &RefineOptions,
    off_curve: &dyn Fn(Point, f64) -> f64,
) -> bool {
    let limit = MAX_JOINT_OFF_CURVE * options.tolerance;
    trial.joints.iter().zip(&current.joints).all(|(t, c)| {
        t.p == c.p || {
            let d = off_curve(t.p, t.u);
            d <= limit || d <= off_curve(c.p, c.u)
        }
    })
}

/// Whether every segment of an evaluated trial is at most [`MAX_LENGTH_FACTOR`] times the
/// chain's scale long.
pub(super) fn bounded(evaluated: &[Evaluated], options: &RefineOptions) -> bool {
    evaluated
        .iter()
        .all(|e| e.segment.length() <= MAX_LENGTH_FACTOR * options.scale)
}

/// One unknown.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Unknown {
    X(usize),
    Y(usize),
    Angle(usize),
    Alpha(usize),
}

/// The unknowns in band order (joint₀, α₀, joint₁, α₁, …) and, for each segment, the
/// contiguous range of unknown indices its residuals depend on. With `active` (one flag per
/// segment), only the segments flagged may change: their α, and the joints all of whose
/// segments are flagged; the others get an empty range.
pub(super) fn unknowns(
    state: &State<'_>,
    options: &RefineOptions,
    active: Option<&[bool]>,
) -> (Vec<Unknown>, Vec<std::ops::Range<usize>>) {
    let segments = state.len();
    let moves = |k: usize| active.is_none_or(|a| a.get(k).copied().unwrap_or(false));
    let mut out = Vec::new();
    for (j, joint) in state.joints.iter().enumerate() {
        // A joint moves the segments on both sides of it: it is free only when they all may change.
        let free = (j == 0 || moves(j - 1)) && (j == segments || moves(j));
        if free {
            if !joint.fixed {
                out.push(Unknown::X(j));
                out.push(Unknown::Y(j));
            }
            if !joint.held_angle {
                out.push(Unknown::Angle(j));
            }
        }
        if options.alpha_range.is_some() && j < segments && moves(j) {
            out.push(Unknown::Alpha(j));
        }
    }
    // Segment k depends on joint k's unknowns, α_k and joint k+1's unknowns: contiguous in this
    // order (empty for a segment that may not change).
    let mut ranges = vec![0..0; segments];
    for (c, &u) in out.iter().enumerate() {
        for k in touched(u, segments) {
            let range = &mut ranges[k];
            *range = if range.start == range.end {
                c..c + 1
            } else {
                range.start..c + 1
            };
        }
    }
    (out, ranges)
}

/// The segments an unknown moves.
pub(super) fn touched(unknown: Unknown, segments: usize) -> std::ops::Range<usize> {
    match unknown {
        Unknown::X(j) | Unknown::Y(j) | Unknown::Angle(j) => {
            j.saturating_sub(1)..(j + 1).min(segments)
        }
        Unknown::Alpha(k) => k..k + 1,
    }
}

/// Whether `unknown` is an α on an end of its range (within [`ALPHA_BOUND_SLACK`]) that a step
/// of `delta` would push beyond it.
pub(super) fn pushes_beyond(
    state: &State<'_>,
    unknown: Unknown,
    delta: f64,
    options: &RefineOptions,
) -> bool {
    let (Unknown::Alpha(k), Some((lo, hi))) = (unknown, options.alpha_range) else {
        return false;
    };
    let alpha = state.alphas[k];
    (delta > 0.0 && alpha >= hi - ALPHA_BOUND_SLACK)
        || (delta < 0.0 && alpha <= lo + ALPHA_BOUND_SLACK)
}

/// An α within this of an end of its range is on it (α is dimensionless; the search's own
/// resolution is far coarser).
pub(super) const ALPHA_BOUND_SLACK: f64 = 1e-9;

pub(super) fn add(state: &mut State<'_>, unknown: Unknown, delta: f64, options: &RefineOptions) {
    match unknown {
        Unknown::X(j) => state.joints[j].p.x += delta,
        Unknown::Y(j) => state.joints[j].p.y += delta,
        Unknown::Angle(j) => state.joints[j].angle += delta,
        Unknown::Alpha(k) => {
            let (lo, hi) = options
                .alpha_range
                .unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
            state.alphas[k] = (state.alphas[k] + delta).clamp(lo, hi);
        }
    }
}

#[cfg(test)]
pub(super) fn step_of(unknown: Unknown, options: &RefineOptions) -> f64 {
    match unknown {
        Unknown::X(_) | Unknown::Y(_) => POSITION_STEP * options.scale,
        Unknown::Angle(_) => ANGLE_STEP,
        Unknown::Alpha(_) => ALPHA_STEP,
    }
}

/// Refines `state` in place, moving only the segments flagged in `active` (all when `None`; see
/// [`unknowns`]); returns the chain's largest sample distance before and after (or `None` if the
/// start itself cannot be evaluated, in which case the state is untouched).
///
/// `off_curve(p, u)` is the distance from `p` to the B-spline near its parameter `u` (a local
/// foot point): a step that takes a joint farther than [`MAX_JOINT_OFF_CURVE`] tolerances from
/// the B-spline near where the joint was made is refused (see there).
pub(crate) fn refine(
    state: &mut State<'_>,
    options: &RefineOptions,
    active: Option<&[bool]>,
    off_curve: &dyn Fn(Point, f64) -> f64,
) -> Option<Refined> {
    let mut current = state.evaluate_all(options.chord_error).ok()?;
    let start_max = max_distance(&current);
    let mut current_cost = cost(&current);
    let (unknowns, ranges) = unknowns(state, options, active);
    if unknowns.is_empty() || current_cost == 0.0 {
        return Some(Refined {
            start_max,
            end_max: start_max,
        });
    }
    let width = ranges.iter().map(|r| r.len()).max().unwrap_or(1);
    // Residual rows (sample distances and end anchors), for the rms.
    let rows = current
        .iter()
        .map(|e| e.residuals.len())
        .sum::<usize>()
        .max(1) as f64;
    let mut damping = Damping::new(DAMPING);
    // The segment that could not be built in the last rejected trial: tried first next time.
    let mut unbuildable = None;
    // Segments held inside their drawable region (see `EdgeConstraint`).
    let mut held: Vec<usize> = Vec::new();
    for _ in 0..options.max_iterations {
        let blocks = jacobian(state, &current, &unknowns, &ranges, options);
        // JᵀJ (band) and Jᵀr, block by block, without the unknowns `pinned` (an α on the end
        // of its range that the step pushes beyond: see below), which keep a unit diagonal and
        // do not move.
        let normal = |pinned: &[bool]| {
            let mut jtj = Band::zeros(unknowns.len(), width.saturating_sub(1));
            let mut jtr = vec![0.0; unknowns.len()];
            for ((block, range), e) in blocks.iter().zip(&ranges).zip(&current) {
                let cols = range.len();
                for (i, r) in e.residuals.iter().enumerate() {
                    let row = &block[i * cols..(i + 1) * cols];
                    for a in 0..cols {
                        if row[a] == 0.0 || pinned[range.start + a] {
                            continue;
                        }
                        jtr[range.start + a] += row[a] * r;
                        for b in 0..=a {
                            if !pinned[range.start + b] {
                                jtj.add(range.start + a, range.start + b, row[a] * row[b]);
                            }
                        }
                    }
                }
            }
            for (i, _) in pinned.iter().enumerate().filter(|(_, p)| **p) {
                jtj.add(i, i, 1.0);
            }
            (jtj, jtr)
        };
        let mut pinned = vec![false; unknowns.len()];
        let (mut jtj, mut jtr) = normal(&pinned);
        // Segments that left their drawable region in an earlier trial are held inside it,
        // linearised at this iterate.
        let mut edges: Vec<EdgeConstraint> = held
            .iter()
            .filter_map(|&k| EdgeConstraint::at(state, k, &unknowns, &ranges[k]))
            .flatten()
            .collect();
        let mut improved = false;
        let mut tries = 0;
        while damping.may_try() && tries < MAX_TRIES {
            tries += 1;
            let mut a = jtj.clone();
            for i in 0..a.n() {
                // Marquardt's scaling, with a floor for unknowns the data barely see.
                a.add(
                    i,
                    i,
                    damping.lambda() * jtj.get(i, i).max(f64::MIN_POSITIVE.sqrt()),
                );
            }
            let Some(delta) = a
                .factor()
                .and_then(|f| keep_inside(&f, f.solve(&jtr), &edges))
            else {
                damping.refuse();
                continue;
            };
            // An α on the end of its range that the step pushes beyond is held there and the
            // step solved again: clamped after the step instead, it bends the step the model
            // chose, and the trial fails or gains less than predicted.
            let beyond: Vec<usize> = (0..unknowns.len())
                .filter(|&c| !pinned[c] && pushes_beyond(state, unknowns[c], -delta[c], options))
                .collect();
            if !beyond.is_empty() {
                for c in beyond {
                    pinned[c] = true;
                }
                (jtj, jtr) = normal(&pinned);
                tries -= 1;
                continue;
            }
            let mut trial = state.clone();
            for (c, &u) in unknowns.iter().enumerate() {
                add(&mut trial, u, -delta[c], options);
            }
            match trial.evaluate_all_from(options.chord_error, state, &current, unbuildable) {
                Ok(e)
                    if cost(&e) < current_cost
                        && bounded(&e, options)
                        && near_curve(&trial, state, options, off_curve) =>
                {
                    let new_cost = cost(&e);
                    let decrease = (current_cost - new_cost) / current_cost;
                    let rms_gain = ((current_cost / rows).sqrt() - (new_cost / rows).sqrt())
                        / options.tolerance;
                    *state = trial;
                    current = e;
                    current_cost = new_cost;
                    // Marquardt's rule does not read the gain ratio.
                    damping.accept(1.0);
                    improved = decrease > CONVERGED && rms_gain > options.converged_rms;
                    break;
                }
                Err(k) => {
                    unbuildable = Some(k);
                    // Left the drawable region: hold the segment inside it (same damping) the
                    // first time; any other failure, or a held segment failing again, damps.
                    let outside = trial.margin(k).is_some_and(|m| m < 0.0);
                    if outside
                        && !held.contains(&k)
                        && let Some(pair) = EdgeConstraint::at(state, k, &unknowns, &ranges[k])
                    {
                        held.push(k);
                        edges.extend(pair);
                    } else {
                        damping.refuse();
                    }
                }
                Ok(_) => damping.refuse(),
            }
        }
        if !improved {
            break;
        }
    }
    Some(Refined {
        start_max,
        end_max: max_distance(&current),
    })
}

/// The largest sample distance of an evaluated chain.
pub(super) fn max_distance(evaluated: &[Evaluated]) -> f64 {
    evaluated.iter().map(|e| e.max).fold(0.0, f64::max)
}

/// What [`refine`] did to the chain's largest sample distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Refined {
    /// Before.
    pub start_max: f64,
    /// After.
    pub end_max: f64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chain::JointKind;
    use crate::chain::g1::jacobian::jacobian_by_differences;
    use crate::chain::g1::state::Joint;
    use crate::geom::Point;
    use crate::geom::Vec2;
    use crate::lac::LacSegment;

    /// A two-segment chain with noisy samples and joints moved off the data.
    pub(super) fn points_and_state() -> (Vec<Point>, Vec<Joint>, Vec<f64>, Vec<Vec<usize>>) {
        let s0 = LacSegment::new(Point::new(0.0, 0.0), 0.3, 40.0, Some(0.5), 0.05, 0.02)
            .expect("segment");
        let s1 =
            LacSegment::new(s0.end(), s0.theta1(), 30.0, Some(-1.0), 0.02, 0.004).expect("segment");
        let mut points = Vec::new();
        let mut samples = vec![Vec::new(), Vec::new()];
        for (k, seg) in [s0, s1].iter().enumerate() {
            for i in 0..25 {
                let s = seg.length() * (i as f64 + 0.5) / 25.0;
                let th = seg.theta(s);
                let offset = 0.03 * if i % 2 == 0 { 1.0 } else { -0.7 };
                samples[k].push(points.len());
                points.push(seg.point(s) + Vec2::new(-th.sin(), th.cos()) * offset);
            }
        }
        let joint = Joint::free;
        let joints = vec![
            joint(Point::new(0.1, -0.05), 0.31, JointKind::Start),
            joint(
                s0.end() + Vec2::new(0.05, 0.04),
                s0.theta1() - 0.01,
                JointKind::CurvatureExtremum,
            ),
            joint(
                s1.end() + Vec2::new(-0.03, 0.02),
                s1.theta1() + 0.02,
                JointKind::End,
            ),
        ];
        (points, joints, vec![0.45, -0.9], samples)
    }

    /// The state of [`points_and_state`]'s data, no curvature limit.
    pub(super) fn test_state(
        points: &[Point],
        joints: Vec<Joint>,
        alphas: Vec<f64>,
        samples: Vec<Vec<usize>>,
    ) -> State<'_> {
        State {
            points,
            joints,
            alphas,
            samples,
            max_curvature: f64::INFINITY,
            memo: Default::default(),
        }
    }

    /// Refinement options for [`points_and_state`]'s chain (about 70 long, noise 0.03).
    pub(super) fn test_options(max_iterations: usize) -> RefineOptions {
        RefineOptions {
            max_iterations,
            alpha_range: Some((-3.0, 3.0)),
            chord_error: 1e-4,
            scale: 70.0,
            tolerance: 0.1,
            converged_rms: CONVERGED_RMS,
        }
    }

    #[test]
    pub(super) fn the_fast_jacobian_matches_forward_differences() {
        let (points, joints, alphas, samples) = points_and_state();
        let state = test_state(&points, joints, alphas, samples);
        let options = test_options(1);
        let current = state.evaluate_all(options.chord_error).expect("evaluates");
        let (unknowns, ranges) = unknowns(&state, &options, None);
        let fast = jacobian(&state, &current, &unknowns, &ranges, &options);
        let slow = jacobian_by_differences(&state, &current, &unknowns, &ranges, &options);
        for (k, (f, d)) in fast.iter().zip(&slow).enumerate() {
            let cols = ranges[k].len();
            for c in 0..cols {
                let column =
                    |b: &[f64]| b.iter().skip(c).step_by(cols).copied().collect::<Vec<_>>();
                let (fc, dc) = (column(f), column(d));
                let scale = dc.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                for (i, (x, y)) in fc.iter().zip(&dc).enumerate() {
                    assert!(
                        (x - y).abs() <= 1e-4 * scale + 1e-6,
                        "segment {k}, unknown {:?}, row {i}: {x} vs {y}",
                        unknowns[ranges[k].start + c]
                    );
                }
            }
        }
    }

    #[test]
    pub(super) fn a_step_may_not_take_a_joint_off_the_curve_near_where_it_was_made() {
        let (points, joints, alphas, samples) = points_and_state();
        let current = test_state(&points, joints, alphas, samples);
        let options = test_options(30);
        let tol = options.tolerance;
        // The curve the joints were made on: here the x axis, so the distance off it is |y|.
        let off_curve = |p: Point, _u: f64| p.y.abs();
        fn moved<'a>(from: &State<'a>, by: Vec2) -> State<'a> {
            let mut trial = from.clone();
            trial.joints[1].p = Point::new(trial.joints[1].p.x, 0.0) + by;
            trial
        }
        let on = moved(&current, Vec2::ZERO);
        // Along the curve, however far: allowed; off it, within 4 tolerances: allowed.
        assert!(near_curve(
            &moved(&on, Vec2::new(50.0 * tol, 0.0)),
            &on,
            &options,
            &off_curve
        ));
        assert!(near_curve(
            &moved(&on, Vec2::new(0.0, 3.9 * tol)),
            &on,
            &options,
            &off_curve
        ));
        // Beyond: refused.
        assert!(!near_curve(
            &moved(&on, Vec2::new(0.0, 4.1 * tol)),
            &on,
            &options,
            &off_curve
        ));
        // A joint already beyond may come back, or stay, but not go farther.
        let far = moved(&on, Vec2::new(0.0, 10.0 * tol));
        assert!(near_curve(
            &moved(&on, Vec2::new(0.0, 8.0 * tol)),
            &far,
            &options,
            &off_curve
        ));
        assert!(near_curve(&far.clone(), &far, &options, &off_curve));
        assert!(!near_curve(
            &moved(&on, Vec2::new(0.0, 12.0 * tol)),
            &far,
            &options,
            &off_curve
        ));
    }

    #[test]
    pub(super) fn a_refinement_of_some_segments_leaves_the_others_as_they_are() {
        let (points, joints, alphas, samples) = points_and_state();
        let mut state = test_state(&points, joints, alphas, samples);
        let options = test_options(30);
        // Only the second segment may change: its α and its end joint move, the shared joint
        // and the first segment do not.
        let active = [false, true];
        let (unknowns_of, ranges) = unknowns(&state, &options, Some(&active));
        assert!(ranges[0].is_empty());
        assert_eq!(
            unknowns_of,
            vec![
                Unknown::Alpha(1),
                Unknown::X(2),
                Unknown::Y(2),
                Unknown::Angle(2)
            ]
        );
        let before = state.clone();
        let cost_before = cost(&state.evaluate_all(options.chord_error).expect("evaluates"));
        refine(&mut state, &options, Some(&active), &|_, _| 0.0).expect("refines");
        assert_eq!(state.joints[..2], before.joints[..2]);
        assert_eq!(state.alphas[0], before.alphas[0]);
        assert!(state.joints[2] != before.joints[2] && state.alphas[1] != before.alphas[1]);
        let cost_after = cost(&state.evaluate_all(options.chord_error).expect("evaluates"));
        assert!(cost_after < cost_before, "{cost_after} vs {cost_before}");
        // Nothing flagged: nothing to move.
        let (none, _) = unknowns(&state, &options, Some(&[false, false]));
        assert!(none.is_empty());
    }
}
