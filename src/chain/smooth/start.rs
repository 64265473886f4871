//! The smooth fit's starting chain from the G1 one, and the cuts of a segment that misses.

use super::layout::{Layout, Params, normal};
use super::part::JointStart;
use super::solver::Evaluation;
use super::{BOUND_SLACK, MAX_EXTRA_TURNING, MAX_LENGTH_FACTOR, SmoothInput, ZERO_END_ALPHA};
use crate::bspline::project::Pieces;
use crate::chain::record::{ChainSegment, JointKind};
use crate::geom::Point;
use crate::lac::{AlphaChoice, LacSegment, deviation};

/// The α of a second start (see [`smooth_from`]): each segment's G1 α where it lies inside the
/// segment's α bounds, the first start's elsewhere; `None` unless some segment of the fitted
/// `x` ended with its α on a bound while its G1 α lies inside.
pub(super) fn g1_alpha_start(
    layout: &Layout,
    x: &Params,
    first: &Params,
    g1: &[ChainSegment],
) -> Option<Vec<f64>> {
    let mut alpha = first.alpha.clone();
    let mut stuck = false;
    for k in 0..layout.n() {
        let (Some((lo, hi)), Some(a)) = (
            layout.alpha_bounds[k],
            g1.get(layout.origin[k]).and_then(|s| s.segment.alpha()),
        ) else {
            continue;
        };
        if a > lo + BOUND_SLACK && a < hi - BOUND_SLACK {
            stuck |= x.alpha[k] <= lo + BOUND_SLACK || x.alpha[k] >= hi - BOUND_SLACK;
            alpha[k] = a;
        }
    }
    stuck.then_some(alpha)
}

/// The layout and starting unknowns from the G1 chain (see the module documentation); `None`
/// where the α choice cannot make an inflection G2.
pub(super) fn start_layout(
    smooth: &SmoothInput,
    assign: &mut Vec<Vec<usize>>,
    max_log_kappa: f64,
    joint_start: JointStart,
) -> Option<(Layout, Params)> {
    let segs: Vec<LacSegment> = smooth.chain.segments.iter().map(|s| s.segment).collect();
    let side = |s: &LacSegment| {
        let t = s.kappa0() + s.kappa1();
        if t > 0.0 {
            1.0
        } else if t < 0.0 {
            -1.0
        } else {
            0.0
        }
    };
    let n = segs.len();
    // The B-spline's curvature at each joint (its foot on the B-spline): the G1 chain's two
    // sides differ there, the B-spline, a C2 curve within the tolerance of the same samples, has
    // one value.
    let pieces = Pieces::new(smooth.input.curve.to_beziers());
    let spline_kappa = |j: usize| -> f64 {
        let (q, guess) = if j < n {
            (
                segs[j].start(),
                smooth.chain.segments[j].params.map(|p| p.0),
            )
        } else {
            (
                segs[n - 1].end(),
                smooth.chain.segments[n - 1].params.map(|p| p.1),
            )
        };
        let guess = guess.unwrap_or_else(|| pieces.domain().0);
        let foot = pieces.project_local(q, guess);
        let (_, d1, d2) = pieces.eval_derivs(foot.u);
        let speed = d1.hypot();
        if speed > 0.0 {
            d1.cross(d2) / (speed * speed * speed)
        } else {
            0.0
        }
    };
    let mut sigma = Vec::with_capacity(n + 1);
    let mut u = Vec::with_capacity(n + 1);
    for j in 0..=n {
        let (g1, s) = if j == 0 {
            (segs[0].kappa0().abs(), side(&segs[0]))
        } else if j == n {
            (segs[n - 1].kappa1().abs(), side(&segs[n - 1]))
        } else {
            let (a, b) = (segs[j - 1].kappa1().abs(), segs[j].kappa0().abs());
            let (sa, sb) = (side(&segs[j - 1]), side(&segs[j]));
            if sa * sb <= 0.0 {
                (0.0, 0.0)
            } else {
                let mean = match (a == 0.0, b == 0.0) {
                    (false, false) => (a * b).sqrt(),
                    (true, false) => b,
                    (false, true) => a,
                    (true, true) => 0.0,
                };
                (mean, sa)
            }
        };
        if g1 == 0.0 || s == 0.0 {
            sigma.push(0.0);
            u.push(0.0);
            continue;
        }
        let spline = match joint_start {
            JointStart::Spline => spline_kappa(j),
            JointStart::Chain => 0.0,
        };
        let magnitude = if spline * s > 0.0 { spline.abs() } else { g1 };
        sigma.push(s);
        u.push(magnitude.ln());
    }
    let mut layout = Layout {
        sigma,
        alpha_bounds: Vec::with_capacity(n),
        max_length: segs
            .iter()
            .map(|s| MAX_LENGTH_FACTOR * s.length())
            .collect(),
        max_turning: segs
            .iter()
            .map(|s| (s.theta1() - s.theta0()).abs() + MAX_EXTRA_TURNING)
            .collect(),
        kinds: smooth.chain.segments.iter().map(|s| s.start).collect(),
        end_kind: smooth.chain.segments[n - 1].end,
        origin: (0..n).collect(),
        seam: [false; 2],
    };
    // Each segment's start pose, its angle continued from the one before (the G1 segments keep
    // theirs in (−π, π]).
    let mut pose = Vec::with_capacity(n);
    let mut theta = segs[0].theta0();
    for (k, seg) in segs.iter().enumerate() {
        if k > 0 {
            // The G1 chain's segments keep their own angles in (−π, π]; a smooth chain's run
            // on continuously.
            theta += crate::geom::wrap_angle(seg.theta0() - segs[k - 1].theta1());
        }
        pose.push((seg.start(), theta));
        theta += seg.theta1() - seg.theta0();
    }
    let mut x = Params {
        theta0: segs[0].theta0(),
        pose,
        u,
        v: segs.iter().map(|s| s.length().ln()).collect(),
        alpha: segs.iter().map(|s| s.alpha().unwrap_or(-1.0)).collect(),
        end: segs[n - 1].end(),
        anchors: [
            (segs[0].start(), normal(segs[0].theta0())),
            (segs[n - 1].end(), normal(segs[n - 1].theta1())),
        ],
        shift: [0.0; 2],
        end_angle: None,
        seam_turn: None,
        seam_c3: false,
    };
    hold_seam(smooth, &mut layout, &mut x, theta);
    for k in 0..n {
        layout.alpha_bounds.push(None);
        set_alpha_bounds(smooth.alpha, &mut layout, &mut x, k)?;
        x.u.iter_mut().for_each(|u| *u = u.min(max_log_kappa));
        if let Some(bounds) = layout.alpha_bounds[k] {
            let target = segs[k].theta1() - segs[k].theta0();
            x.alpha[k] = alpha_for_turning(&layout, &x, k, target, bounds);
        }
    }
    // A segment that bends to the end where the smooth chain asks κ = 0 of it (an arc into an
    // inflection or a line) keeps its G1 shape but for a transition spiral at that end, as
    // long as a clothoid leaving the arc drifts from it by the tolerance: a G1 arc swept to zero
    // curvature over its whole length starts the fit far from the samples (half a pixel's
    // tolerance, an S of two 270° arcs drawn with a mouse: 17 px off, 12 segments after the
    // cuts; with the transitions 4).
    let mut k = 0;
    while k < layout.n() {
        let Some(seg) = segs.get(layout.origin[k]).copied() else {
            k += 1;
            continue;
        };
        let (zero_a, zero_b) = (layout.sigma[k] == 0.0, layout.sigma[k + 1] == 0.0);
        let bend = match (zero_a, zero_b) {
            (true, false) => seg.kappa0().abs(),
            (false, true) => seg.kappa1().abs(),
            _ => 0.0,
        };
        let transition = (TRANSITION_SHIFT * smooth.tolerance / bend).sqrt();
        if !(bend > 0.0 && transition < TRANSITION_SHARE * seg.length()) {
            k += 1;
            continue;
        }
        let at = if zero_a {
            transition
        } else {
            seg.length() - transition
        };
        let feet: Vec<f64> = {
            let pts: Vec<Point> = assign[k].iter().map(|&i| smooth.input.points[i]).collect();
            deviation(&seg, &pts, smooth.chord_error).feet
        };
        let pose = (seg.point(at), x.pose[k].1 + seg.theta(at) - seg.theta0());
        let kappa = seg.kappa(at);
        if kappa == 0.0 || !kappa.is_finite() {
            k += 1;
            continue;
        }
        split_at(&mut layout, &mut x, assign, k, (kappa, pose), at, &feet);
        // The part away from the zero joint keeps the G1 segment's α (any α: both its ends
        // curve); the transition starts as a clothoid.
        let (far, near) = if zero_a { (k + 1, k) } else { (k, k + 1) };
        x.alpha[far] = seg.alpha().unwrap_or(-1.0);
        x.alpha[near] = -1.0;
        for m in [k, k + 1] {
            set_alpha_bounds(smooth.alpha, &mut layout, &mut x, m)?;
        }
        k += 2;
    }
    // A curved segment between two zero joints is cut at its middle (it could only be a line).
    let mut k = 0;
    while k < layout.n() {
        let curved = segs
            .get(layout.origin[k])
            .is_some_and(|s| s.kappa0() != 0.0 || s.kappa1() != 0.0);
        if layout.sigma[k] == 0.0 && layout.sigma[k + 1] == 0.0 && curved {
            let seg = segs[layout.origin[k]];
            let half = 0.5 * seg.length();
            let mid = seg.kappa(half);
            if mid == 0.0 {
                return None;
            }
            let feet: Vec<f64> = {
                let pts: Vec<Point> = assign[k].iter().map(|&i| smooth.input.points[i]).collect();
                deviation(&seg, &pts, smooth.chord_error).feet
            };
            let pose = (
                seg.point(half),
                x.pose[k].1 + seg.theta(half) - seg.theta0(),
            );
            split_at(&mut layout, &mut x, assign, k, (mid, pose), half, &feet);
            for m in [k, k + 1] {
                set_alpha_bounds(smooth.alpha, &mut layout, &mut x, m)?;
            }
            k += 2;
        } else {
            k += 1;
        }
    }
    Some((layout, x))
}

/// Holds a closed chain's seam where the part starts or ends there (see [`Layout::seam`]): the
/// start's angle and curvature and the end's curvature are set to the seam's
/// ([`crate::chain::ChainInput::seam`]), and the end's angle must meet the seam's one turn on
/// (`end_theta`: the G1 chain's end angle run on from its start, which picks the turn). A
/// seam of curvature 0 is an inflection joint on both sides. Where the seam's curvature has not
/// the sign of the G1 segment's curvature there, a chain from one to the other could not be
/// built: that end stays a corner (its point held, its tangent free) and says so.
fn hold_seam(smooth: &SmoothInput, layout: &mut Layout, x: &mut Params, end_theta: f64) {
    // The α bounds are not laid out yet: the segments are the kinds'.
    let n = layout.kinds.len();
    let ends = [layout.kinds[0], layout.end_kind].map(|k| k == JointKind::Seam);
    let Some(seam) = smooth.input.seam.filter(|_| ends.contains(&true)) else {
        for (held, kind) in ends.into_iter().zip([0, n]) {
            if held {
                set_kind(layout, kind, JointKind::Corner);
            }
        }
        return;
    };
    let sign = if seam.kappa > 0.0 {
        1.0
    } else if seam.kappa < 0.0 {
        -1.0
    } else {
        0.0
    };
    let turn = std::f64::consts::TAU;
    // The seam's angle on the turn nearest `near`.
    let nearest = |near: f64| seam.theta + turn * ((near - seam.theta) / turn).round();
    for (end, joint) in [(0, 0), (1, n)] {
        if !ends[end] {
            continue;
        }
        if sign == 0.0 {
            // An inflection at the seam: a zero joint on both sides.
            layout.sigma[joint] = 0.0;
            x.u[joint] = 0.0;
        } else if layout.sigma[joint] != sign {
            set_kind(layout, joint, JointKind::Corner);
            continue;
        }
        layout.seam[end] = true;
        if sign != 0.0 {
            x.u[joint] = seam.kappa.abs().ln();
        }
        if end == 0 {
            let theta = nearest(x.pose[0].1);
            x.pose[0].1 = theta;
            x.theta0 = theta;
        } else {
            x.end_angle = Some(nearest(end_theta));
        }
    }
    // A whole closed chain: its end meets its start one turn on, whatever the start's angle.
    if layout.tied()
        && let Some(target) = x.end_angle.take()
    {
        x.seam_turn = Some(target - x.pose[0].1);
        // dκ/ds is continuous across a seam of non-zero curvature in C3 (an inflection's is
        // not held at any joint, as at the other zero joints).
        x.seam_c3 = sign != 0.0;
    }
}

/// Sets the kind of joint `j` (0..=n) of `layout`.
fn set_kind(layout: &mut Layout, j: usize, kind: JointKind) {
    match layout.kinds.get_mut(j) {
        Some(k) => *k = kind,
        None => layout.end_kind = kind,
    }
}

/// A transition spiral of the starting chain (see [`start_layout`]) is as long as a clothoid
/// from the arc's curvature κ to zero whose shift from the arc, κL²/24, is the tolerance:
/// L = √(24·tolerance/κ).
pub(super) const TRANSITION_SHIFT: f64 = 24.0;

/// A segment gets a transition at its zero end only where the transition is shorter than this
/// share of it (a shorter segment is a spiral to zero already, or nearly).
pub(super) const TRANSITION_SHARE: f64 = 0.5;

/// Grid of α values over a segment's bounds on which [`alpha_for_turning`] looks for the
/// turning closest to its target before bisecting: the turning is monotone in α between the
/// same end curvatures over the same length in every case tried, the grid only guards the
/// bracket.
pub(super) const TURNING_GRID: usize = 12;

/// Bisection steps of [`alpha_for_turning`]: 2⁻²⁰ of a grid cell.
pub(super) const TURNING_BISECTIONS: usize = 20;

/// The α within `bounds` whose segment k (its joints' curvatures and length from `x`) turns
/// closest to `target`: the starting chain then keeps the G1 chain's tangent at every joint.
pub(super) fn alpha_for_turning(
    layout: &Layout,
    x: &Params,
    k: usize,
    target: f64,
    bounds: (f64, f64),
) -> f64 {
    let (ka, kb) = (layout.kappa(x, k), layout.kappa(x, k + 1));
    let length = x.v[k].exp();
    let turning = |alpha: f64| -> Option<f64> {
        let alpha = (ka != kb).then_some(alpha);
        let seg = LacSegment::new(Point::ZERO, 0.0, length, alpha, ka, kb).ok()?;
        Some(seg.theta1() - target)
    };
    let (lo, hi) = bounds;
    let grid: Vec<(f64, f64)> = (0..=TURNING_GRID)
        .filter_map(|i| {
            let a = lo + (hi - lo) * i as f64 / TURNING_GRID as f64;
            turning(a).map(|t| (a, t))
        })
        .collect();
    let Some(&best) = grid.iter().min_by(|p, q| p.1.abs().total_cmp(&q.1.abs())) else {
        return x.alpha[k];
    };
    let bracket = grid
        .windows(2)
        .find(|w| w[0].1 * w[1].1 <= 0.0)
        .map(|w| (w[0], w[1]));
    let Some((mut a, mut b)) = bracket else {
        return best.0;
    };
    for _ in 0..TURNING_BISECTIONS {
        let mid = 0.5 * (a.0 + b.0);
        let Some(t) = turning(mid) else { break };
        if t * a.1 <= 0.0 {
            b = (mid, t);
        } else {
            a = (mid, t);
        }
    }
    if a.1.abs() <= b.1.abs() { a.0 } else { b.0 }
}

/// Sets segment k's α bounds from the choice and its zero ends; `None` when no α is allowed.
pub(super) fn set_alpha_bounds(
    choice: AlphaChoice,
    layout: &mut Layout,
    x: &mut Params,
    k: usize,
) -> Option<()> {
    let zero_a = layout.sigma[k] == 0.0;
    let zero_b = layout.sigma[k + 1] == 0.0;
    if zero_a && zero_b {
        layout.alpha_bounds[k] = None;
        return Some(());
    }
    let (lo, hi) = match choice {
        AlphaChoice::Range { min, max } => (min, max),
        AlphaChoice::Fixed(a) => (a, a),
    };
    let hi = if zero_a || zero_b {
        hi.min(ZERO_END_ALPHA)
    } else {
        hi
    };
    if lo > hi {
        return None;
    }
    x.alpha[k] = x.alpha[k].clamp(lo, hi);
    layout.alpha_bounds[k] = (lo < hi).then_some((lo, hi));
    Some(())
}

/// Splits segment k at arc length `at` (curvature `kappa` there) into two segments of the same
/// α, handing its samples to the halves by their feet.
pub(super) fn split_at(
    layout: &mut Layout,
    x: &mut Params,
    assign: &mut Vec<Vec<usize>>,
    k: usize,
    (kappa, pose): (f64, (Point, f64)),
    at: f64,
    feet: &[f64],
) {
    x.pose.insert(k + 1, pose);
    let length = x.v[k].exp();
    let sign = if kappa > 0.0 { 1.0 } else { -1.0 };
    layout.sigma.insert(k + 1, sign);
    x.u.insert(k + 1, kappa.abs().ln());
    x.v[k] = at.ln();
    x.v.insert(k + 1, (length - at).ln());
    x.alpha.insert(k + 1, x.alpha[k]);
    layout.alpha_bounds.insert(k + 1, layout.alpha_bounds[k]);
    let max = layout.max_length[k];
    layout.max_length.insert(k + 1, max);
    let max = layout.max_turning[k];
    layout.max_turning.insert(k + 1, max);
    layout.kinds.insert(k + 1, JointKind::Subdivision);
    let origin = layout.origin[k];
    layout.origin.insert(k + 1, origin);
    // As many samples as have their feet before the cut go to the first half, taken in stroke
    // order: the halves keep contiguous runs of samples (on a jagged stroke a sample's foot
    // can lie before its predecessor's), so their ranges tile the piece.
    let before = feet.iter().filter(|&&s| s < at).count();
    let mut first = std::mem::take(&mut assign[k]);
    let second = first.split_off(before.min(first.len()));
    assign[k] = first;
    assign.insert(k + 1, second);
}

/// Joins segments j − 1 and j of a solved chain into one (joint j goes): the joined segment
/// runs between the outer joints' curvatures over both lengths, with the α that keeps the two
/// segments' turning (`segments` the solved chain), and holds both segments' samples. `None`
/// where the choice of α cannot hold the joined segment's ends (a zero end without a negative α).
pub(super) fn join_at(
    choice: AlphaChoice,
    layout: &mut Layout,
    x: &mut Params,
    assign: &mut Vec<Vec<usize>>,
    segments: &[LacSegment],
    j: usize,
) -> Option<()> {
    let (a, b) = (segments.get(j - 1)?, segments.get(j)?);
    let turning = (a.theta1() - a.theta0()) + (b.theta1() - b.theta0());
    x.pose.remove(j);
    layout.sigma.remove(j);
    x.u.remove(j);
    x.v[j - 1] = (a.length() + b.length()).ln();
    x.v.remove(j);
    x.alpha.remove(j);
    layout.alpha_bounds.remove(j);
    layout.max_length[j - 1] += layout.max_length[j];
    layout.max_length.remove(j);
    layout.max_turning[j - 1] += layout.max_turning[j];
    layout.max_turning.remove(j);
    layout.kinds.remove(j);
    layout.origin.remove(j);
    let moved = assign.remove(j);
    assign[j - 1].extend(moved);
    set_alpha_bounds(choice, layout, x, j - 1)?;
    if let Some(bounds) = layout.alpha_bounds[j - 1] {
        x.alpha[j - 1] = alpha_for_turning(layout, x, j - 1, turning, bounds);
    }
    Some(())
}

/// Cuts segment k of the solved chain at its middle. A line (no curvature at its middle to give
/// the new joint, its ends held at κ = 0 by its neighbours) that misses the tolerance must bend:
/// the new joint bends towards its farthest sample, with the curvature of the arc through the
/// line's ends that reaches it (8d/L², d that sample's distance), and both halves become spirals
/// leaving κ = 0 (α ≤ [`ZERO_END_ALPHA`]). `None` where neither can be done (a line whose
/// samples all lie on it, or an α choice without a negative α).
pub(super) fn cut(
    layout: &mut Layout,
    x: &mut Params,
    assign: &mut Vec<Vec<usize>>,
    evaluation: &Evaluation,
    k: usize,
    choice: AlphaChoice,
) -> Option<()> {
    let seg = evaluation.segments.get(k)?;
    let half = 0.5 * seg.length();
    let kappa = seg.kappa(half);
    if !kappa.is_finite() {
        return None;
    }
    let pose = (seg.point(half), seg.theta(half));
    if kappa != 0.0 {
        split_at(
            layout,
            x,
            assign,
            k,
            (kappa, pose),
            half,
            &evaluation.feet[k],
        );
        return Some(());
    }
    let farthest = evaluation
        .residuals
        .get(k)?
        .iter()
        .copied()
        .max_by(|a, b| a.abs().total_cmp(&b.abs()))?;
    let length = seg.length();
    let bend = 8.0 * farthest / (length * length);
    if bend == 0.0 || !bend.is_finite() {
        return None;
    }
    let mut trial = (layout.clone(), x.clone(), assign.clone());
    split_at(
        &mut trial.0,
        &mut trial.1,
        &mut trial.2,
        k,
        (bend, pose),
        half,
        &evaluation.feet[k],
    );
    set_alpha_bounds(choice, &mut trial.0, &mut trial.1, k)?;
    set_alpha_bounds(choice, &mut trial.0, &mut trial.1, k + 1)?;
    (*layout, *x, *assign) = trial;
    Some(())
}
