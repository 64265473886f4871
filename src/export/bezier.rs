//! LAC segments as cubic Béziers within a stated error, through kurbo's curve fitting.
//!
//! [`LacCurve`] is the adapter that lets kurbo's fitter ([`kurbo::fit_to_bezpath`]) sample a
//! segment: the fitting parameter is the arc-length fraction t = s/S, so the derivative is
//! dP/dt = S·(cos θ(s), sin θ(s)) (an LAC is parametrised by arc length: |dP/ds| = 1).
//!
//! kurbo estimates its error from 20 samples per cubic; [`segment_beziers`] then *measures* the
//! distance between the cubics and the exact segment both ways (see [`bezier_error`]) and, when
//! the measure exceeds the accuracy asked for, halves that part of the segment by arc length and
//! fits each half again (at most [`MAX_SPLIT_DEPTH`] levels). The result carries the measured
//! error, so what a file states is what was checked.
//!
//! The work per segment is bounded whatever the segment, so a pathological one (a spiral of
//! thousands of turns, a length 10¹⁴ times the accuracy, an accuracy finer than `f64` can
//! place a point) never hangs: measured, a fixture stroke asked for 10⁻¹² px takes 10 s and
//! comes back within 2.4·10⁻⁶ px (stated), the default takes 0.04 s:
//!
//! * the segment is first cut into parts of at most [`MAX_TURNING_PER_PART`] turning (at most
//!   [`MAX_PARTS_PER_SEGMENT`] parts), each fitted and measured on its own, so no part comes
//!   back near itself and measuring is local;
//! * kurbo's fitter halves a part it cannot fit until the halves fit, without limit (down to
//!   adjacent floating-point parameters); every such step and every halving of ours spends one
//!   of the segment's [`MAX_FIT_STEPS_PER_SEGMENT`] steps, and once they are spent each range
//!   left is drawn as its chord (kurbo's own fallback), so the fit ends; such a fit is tried
//!   again at a coarser accuracy, at most [`MAX_COARSENINGS`] times, and the best kept;
//! * the reference polyline has at most [`MAX_POINTS_PER_SEGMENT`](super::MAX_POINTS_PER_SEGMENT) points, and when that cap
//!   widens its spacing its chord error is taken from the spacing actually used;
//! * measuring prunes by bounding boxes, so its cost grows with the points measured, not with
//!   their product with the cubics.
//!
//! A segment that cannot be fitted within those bounds comes back with the error it has, larger
//! than the accuracy asked for; the writers report it.
//!
//! Lines become one exact cubic (control points at the thirds); arcs and spirals go through the
//! fitter. The SVG writer draws arcs and lines exactly with `A`/`L` instead.

use std::cell::Cell;
use std::ops::Range;

use kurbo::{
    BezPath, CubicBez, CurveFitSample, ParamCurve, ParamCurveFit, ParamCurveNearest, PathEl, Rect,
};

use crate::geom::{Point, Vec2};
use crate::lac::LacSegment;

use super::svg::{MAX_TURNING_PER_STEP, lac_spacing};

/// The default export accuracy as a fraction of the fitting tolerance: a tenth keeps the export
/// error an order of magnitude below the error the fit already allows, so the exported curve is,
/// for every purpose, the fitted one.
pub const DEFAULT_ACCURACY_FRACTION: f64 = 0.1;

/// How many times [`segment_beziers`] may halve a part of a segment whose fit measures beyond
/// the accuracy: 2¹² parts bound the work; a part still beyond it at that depth is kept as
/// fitted, and its measured error reported (not observed on the fixtures).
pub const MAX_SPLIT_DEPTH: usize = 12;

/// Points measured on each cubic when checking it against the segment (besides its ends, which
/// lie on the segment by construction). 32 points on a cubic that is within a tenth of the
/// tolerance of a monotone-curvature curve leave gaps far shorter than any feature of either.
pub const CHECK_POINTS_PER_CUBIC: usize = 32;

/// The exact segment is represented, for measuring, by a polyline within this fraction of the
/// accuracy of it ([`lac_spacing`]); that chord error is added to every cubic-to-segment
/// distance, so the measure is an upper bound at the measured points.
pub const REFERENCE_CHORD_FRACTION: f64 = 0.01;

/// Largest turning (radians) of one part of a segment fitted on its own: a half turn. A part of
/// an LAC (curvature of one sign) turning at most π never comes back near itself, so a point of
/// it is near only the cubics fitted to its neighbourhood. Fitted segments rarely turn more
/// than this; on the fixtures the cut took the exports from 1365 cubics to 1359, all within
/// the accuracy as before.
pub const MAX_TURNING_PER_PART: f64 = std::f64::consts::PI;

/// Most parts a segment is cut into by [`MAX_TURNING_PER_PART`]: 256 half turns. Beyond that
/// the parts turn more, and [`MAX_FIT_STEPS_PER_SEGMENT`] bounds their fitting.
pub const MAX_PARTS_PER_SEGMENT: usize = 256;

/// Most fitting steps spent on one segment: a step is a node of kurbo's recursive halving
/// (a cubic tried on a parameter range) or one of [`segment_beziers`]' own halvings. A pen
/// stroke's segment needs a few dozen at most (at most 9 cubics per segment on the fixtures);
/// 256 leave a wide margin and bound the worst case: a step samples the curve about fifty
/// times, so one attempt costs at most about 13 000 evaluations (under 2 s for a clothoid of
/// 80 000 turns, whose parts are the slowest kind to evaluate), and a segment at most
/// [`MAX_COARSENINGS`] + 1 attempts.
pub const MAX_FIT_STEPS_PER_SEGMENT: usize = 256;

/// Relative accuracy of kurbo's nearest-point search when measuring segment-to-cubic distances
/// (a fraction of the export accuracy).
const NEAREST_ACCURACY_FRACTION: f64 = 1e-3;

/// A [`LacSegment`], or the part of it between two arc lengths, seen by kurbo's curve fitter:
/// parameter t ∈ [0, 1] is the arc-length fraction of that part.
///
/// kurbo's [`kurbo::fit_to_bezpath`] halves a range it cannot fit without limit; a curve made
/// with [`LacCurve::with_budget`] spends one step of the budget per halving it allows and, once
/// the budget is spent, has kurbo draw each range left as its chord, so the fit ends.
#[derive(Clone, Copy, Debug)]
pub struct LacCurve<'a> {
    segment: &'a LacSegment,
    s0: f64,
    s1: f64,
    budget: Option<&'a Cell<usize>>,
}

impl<'a> LacCurve<'a> {
    /// The adapter for the whole of `segment`.
    pub fn new(segment: &'a LacSegment) -> Self {
        LacCurve {
            segment,
            s0: 0.0,
            s1: segment.length(),
            budget: None,
        }
    }

    /// The adapter for the part of `segment` between arc lengths `s0` and `s1` (clamped to the
    /// segment).
    pub fn part(segment: &'a LacSegment, s0: f64, s1: f64) -> Self {
        let clamp = |s: f64| s.clamp(0.0, segment.length());
        LacCurve {
            segment,
            s0: clamp(s0),
            s1: clamp(s1),
            budget: None,
        }
    }

    /// The same curve, spending `budget` (steps left, shared with any other curve given it) on
    /// kurbo's halvings; see the type's documentation.
    pub fn with_budget(self, budget: &'a Cell<usize>) -> Self {
        LacCurve {
            budget: Some(budget),
            ..self
        }
    }

    /// Arc length on the segment of parameter `t`.
    fn arc_length(&self, t: f64) -> f64 {
        self.s0 + t * (self.s1 - self.s0)
    }
}

impl ParamCurveFit for LacCurve<'_> {
    /// The point and the derivative at t: an LAC has a continuous tangent everywhere (its
    /// curvature is finite), so `sign` (which side of a corner) does not matter.
    fn sample_pt_tangent(&self, t: f64, _sign: f64) -> CurveFitSample {
        let (p, tangent) = self.sample_pt_deriv(t);
        CurveFitSample { p, tangent }
    }

    /// P(s) and dP/dt = (s1 − s0)·(cos θ(s), sin θ(s)), s = s0 + t·(s1 − s0).
    fn sample_pt_deriv(&self, t: f64) -> (Point, Vec2) {
        let s = self.arc_length(t);
        (
            self.segment.point(s),
            Vec2::from_angle(self.segment.theta(s)) * (self.s1 - self.s0),
        )
    }

    /// None while the budget lasts (or without one): the curvature of an LAC segment is finite
    /// and monotonic between its two finite end values, so it has neither cusps nor corners. (Its
    /// largest curvature is at an end, which kurbo asks us never to report.)
    ///
    /// kurbo asks this once per range it fits (after a range short enough for a line), and
    /// halves the range when its cubic misses. With the budget spent, the answer is the range's
    /// start: kurbo takes a break at an end of the range as its signal to draw the chord and
    /// stop.
    fn break_cusp(&self, range: Range<f64>) -> Option<f64> {
        let budget = self.budget?;
        match budget.get().checked_sub(1) {
            Some(left) => {
                budget.set(left);
                None
            }
            None => Some(range.start),
        }
    }
}

/// A segment as cubic Béziers, and how far they are from it.
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentBeziers {
    /// The cubics, joined end to end, from the segment's start to its end.
    pub cubics: Vec<CubicBez>,
    /// The measured distance between the cubics and the segment ([`bezier_error`]).
    pub error: f64,
}

/// The cubics of a kurbo path (its first move-to and its curve-tos; kurbo's fitter emits only
/// those, and a line-to becomes a cubic with control points at the thirds).
fn cubics_of(path: &BezPath) -> Vec<CubicBez> {
    let mut out = Vec::new();
    let mut pen = Point::ORIGIN;
    for el in path.elements() {
        match *el {
            PathEl::MoveTo(p) => pen = p,
            PathEl::LineTo(p) => {
                out.push(CubicBez::new(
                    pen,
                    pen.lerp(p, 1.0 / 3.0),
                    pen.lerp(p, 2.0 / 3.0),
                    p,
                ));
                pen = p;
            }
            PathEl::QuadTo(p1, p2) => {
                out.push(kurbo::QuadBez::new(pen, p1, p2).raise());
                pen = p2;
            }
            PathEl::CurveTo(p1, p2, p3) => {
                out.push(CubicBez::new(pen, p1, p2, p3));
                pen = p3;
            }
            PathEl::ClosePath => {}
        }
    }
    out
}

/// The line from `a` to `b` as a cubic (control points at the thirds: exact, uniform speed).
fn line_cubic(a: Point, b: Point) -> CubicBez {
    CubicBez::new(a, a.lerp(b, 1.0 / 3.0), a.lerp(b, 2.0 / 3.0), b)
}

/// The exact segment for measuring: its points every [`lac_spacing`] (chord error
/// [`REFERENCE_CHORD_FRACTION`] × the accuracy, or that of the spacing actually used when the
/// polyline's point cap widened it), with their arc lengths.
struct Reference {
    s: Vec<f64>,
    points: Vec<Point>,
    chord: f64,
}

impl Reference {
    fn new(segment: &LacSegment, accuracy: f64) -> Self {
        let wanted = REFERENCE_CHORD_FRACTION * accuracy;
        let spacing = lac_spacing(segment, wanted);
        let (s, points) = segment.samples(spacing).map(|x| (x.s, x.point)).unzip();
        Reference {
            s,
            points,
            chord: wanted.max(chord_error(segment, spacing)),
        }
    }

    /// The polyline of the part between arc lengths `s0` and `s1` (whose points are `a` and
    /// `b`): those end points and the reference points strictly between.
    fn part(&self, (s0, a): (f64, Point), (s1, b): (f64, Point)) -> Vec<Point> {
        let first = self.s.partition_point(|&s| s <= s0);
        let last = self.s.partition_point(|&s| s < s1).max(first);
        let mut out = Vec::with_capacity(last - first + 2);
        out.push(a);
        out.extend_from_slice(&self.points[first..last]);
        out.push(b);
        out
    }
}

/// A bound on the distance between an LAC and the chords of its points `spacing` apart: the
/// sagitta κ_max·h²/8 while a step turns at most [`MAX_TURNING_PER_STEP`] (see
/// [`lac_spacing`]); beyond that, `h` itself (every point of a piece of length h lies within h
/// of its chord's start).
fn chord_error(segment: &LacSegment, spacing: f64) -> f64 {
    let kappa_max = segment.kappa0().abs().max(segment.kappa1().abs());
    if kappa_max * spacing <= MAX_TURNING_PER_STEP {
        kappa_max * spacing * spacing / 8.0
    } else {
        spacing
    }
}

/// Squared distance from `p` to the rectangle `r` (0 inside).
fn distance_sq_to_rect(p: Point, r: &Rect) -> f64 {
    let dx = (r.x0 - p.x).max(p.x - r.x1).max(0.0);
    let dy = (r.y0 - p.y).max(p.y - r.y1).max(0.0);
    dx * dx + dy * dy
}

/// The box of a cubic's control points, which holds the cubic (convex hull property).
fn control_box(c: &CubicBez) -> Rect {
    Rect::from_points(c.p0, c.p1).union_pt(c.p2).union_pt(c.p3)
}

/// Reference points per block when measuring from the cubics: a block's box prunes its chords
/// together.
const CHORDS_PER_BLOCK: usize = 32;

/// Items searched on each side of the previous point's nearest one when measuring a long
/// polyline against many cubics (more than [`FULL_SEARCH_PAIRS`] pairs). The minimum over any
/// subset of the items is at least the true minimum, so a narrowed search can only overstate
/// the error, never understate it; within a part turning at most [`MAX_TURNING_PER_PART`] the
/// nearest item stays among the neighbours of the previous point's.
const SEARCH_WINDOW: usize = 16;

/// Point–item pairs up to which measuring searches every item (pruned by bounding boxes): the
/// fixtures' segments stay far below it, a pathological one far above.
const FULL_SEARCH_PAIRS: usize = 1 << 20;

/// The smallest value of `cost(i)` over the items within `window` of `hint` in `0..n`, visiting
/// `hint` first and then only the items whose lower bound `bound(i)` is below the best so far;
/// returns it with its index (infinity for no items).
fn pruned_min(
    (n, hint, window): (usize, usize, usize),
    bound: impl Fn(usize) -> f64,
    cost: impl Fn(usize) -> f64,
) -> (f64, usize) {
    if n == 0 {
        return (f64::INFINITY, 0);
    }
    let hint = hint.min(n - 1);
    let mut best = (cost(hint), hint);
    let range = hint.saturating_sub(window)..hint.saturating_add(window).saturating_add(1).min(n);
    for i in range.filter(|&i| i != hint) {
        if bound(i) < best.0 {
            let c = cost(i);
            if c < best.0 {
                best = (c, i);
            }
        }
    }
    best
}

/// The two-sided distance between `cubics` and the part of `segment` whose polyline is
/// `reference` (see [`bezier_error`]). Both are in order along the curve, so the previous
/// point's nearest item is the first one tried, and bounding boxes prune the rest.
fn measure(reference: &[Point], chord: f64, cubics: &[CubicBez], accuracy: f64) -> f64 {
    let nearest_accuracy = NEAREST_ACCURACY_FRACTION * accuracy;
    let window = if reference.len().saturating_mul(cubics.len()) <= FULL_SEARCH_PAIRS {
        usize::MAX
    } else {
        SEARCH_WINDOW
    };
    let boxes: Vec<Rect> = cubics.iter().map(control_box).collect();
    let mut worst: f64 = 0.0;
    let mut hint = 0;
    for &p in reference {
        let (d2, i) = pruned_min(
            (cubics.len(), hint, window),
            |i| distance_sq_to_rect(p, &boxes[i]),
            |i| cubics[i].nearest(p, nearest_accuracy).distance_sq,
        );
        worst = worst.max(d2.sqrt());
        hint = i;
    }
    let chords = reference.len().saturating_sub(1);
    let blocks: Vec<(usize, Rect)> = (0..chords)
        .step_by(CHORDS_PER_BLOCK)
        .map(|start| {
            let end = (start + CHORDS_PER_BLOCK).min(chords);
            let r = reference[start + 1..=end].iter().fold(
                Rect::from_points(reference[start], reference[start]),
                |r, &q| r.union_pt(q),
            );
            (start, r)
        })
        .collect();
    let block_window = window / CHORDS_PER_BLOCK + 1;
    let mut hint = 0;
    for c in cubics {
        for i in 1..=CHECK_POINTS_PER_CUBIC {
            let q = c.eval(i as f64 / (CHECK_POINTS_PER_CUBIC + 1) as f64);
            let (d, b) = pruned_min(
                (blocks.len(), hint, block_window),
                |b| distance_sq_to_rect(q, &blocks[b].1).sqrt(),
                |b| {
                    let start = blocks[b].0;
                    let end = (start + CHORDS_PER_BLOCK).min(chords);
                    reference[start..=end]
                        .windows(2)
                        .map(|w| crate::geom::distance_to_segment(q, w[0], w[1]))
                        .fold(f64::INFINITY, f64::min)
                },
            );
            if d.is_finite() {
                worst = worst.max(d + chord);
            }
            hint = b;
        }
    }
    worst
}

/// The largest distance between `cubics` and `segment`, measured both ways:
///
/// * from the segment: its points every [`lac_spacing`] (chord error
///   [`REFERENCE_CHORD_FRACTION`] × `accuracy`) to the nearest cubic (kurbo's nearest point);
/// * from the cubics: [`CHECK_POINTS_PER_CUBIC`] points on each to that polyline, plus the
///   polyline's chord error (the polyline lies within it of the segment, so this bounds the
///   distance to the segment itself).
///
/// This is the two-sided (Hausdorff) distance at the measured points. `accuracy` only sets the
/// measuring resolution.
pub fn bezier_error(segment: &LacSegment, cubics: &[CubicBez], accuracy: f64) -> f64 {
    let reference = Reference::new(segment, accuracy);
    measure(&reference.points, reference.chord, cubics, accuracy)
}

/// Spends one step of `budget`; false when none is left.
fn spend(budget: &Cell<usize>) -> bool {
    match budget.get().checked_sub(1) {
        Some(left) => {
            budget.set(left);
            true
        }
        None => false,
    }
}

/// A part of a segment fitted on its own: the part as a segment of its own starting at arc
/// length `offset` of the whole (so evaluating it costs what its own turning costs), or `None`
/// for the whole segment itself (`offset` 0); and its range on that curve, arc lengths with
/// their points.
struct Part {
    sub: Option<LacSegment>,
    offset: f64,
    range: ((f64, Point), (f64, Point)),
}

impl Part {
    /// The curve the part's arc lengths refer to.
    fn curve<'a>(&'a self, segment: &'a LacSegment) -> &'a LacSegment {
        self.sub.as_ref().unwrap_or(segment)
    }
}

/// Fits `curve` (whose arc length 0 is `offset` on the whole segment) between its arc lengths
/// `s0` and `s1`, from `a` to `b` (its points there), appending the cubics to `out`; returns
/// their measured error. A part kurbo's fit misses (measured beyond `accuracy`) is halved by arc
/// length, down to [`MAX_SPLIT_DEPTH`] levels and while `budget` lasts.
fn fit_part(
    (curve, offset): (&LacSegment, f64),
    reference: &Reference,
    ((s0, a), (s1, b)): ((f64, Point), (f64, Point)),
    accuracy: f64,
    (depth, budget): (usize, &Cell<usize>),
    out: &mut Vec<CubicBez>,
) -> f64 {
    let source = LacCurve::part(curve, s0, s1).with_budget(budget);
    let mut cubics = cubics_of(&kurbo::fit_to_bezpath(&source, accuracy));
    if let Some(first) = cubics.first_mut() {
        first.p0 = a;
    }
    if let Some(last) = cubics.last_mut() {
        last.p3 = b;
    }
    if cubics.is_empty() {
        cubics.push(line_cubic(a, b));
    }
    let error = measure(
        &reference.part((offset + s0, a), (offset + s1, b)),
        reference.chord,
        &cubics,
        accuracy,
    );
    if error <= accuracy || depth >= MAX_SPLIT_DEPTH || !spend(budget) {
        out.extend(cubics);
        return error;
    }
    let mid = 0.5 * (s0 + s1);
    let m = curve.point(mid);
    let next = (depth + 1, budget);
    let part = (curve, offset);
    let left = fit_part(part, reference, ((s0, a), (mid, m)), accuracy, next, out);
    let right = fit_part(part, reference, ((mid, m), (s1, b)), accuracy, next, out);
    left.max(right)
}

/// The part of `segment` between arc lengths `s0` and `s1` as a segment of its own starting at
/// `start` (the previous part's end): the same α, the curvatures and tangent angle of `segment`
/// there. None when those do not make a valid segment (a part so short that its end curvatures
/// round to equal values).
fn sub_segment(segment: &LacSegment, (s0, s1): (f64, f64), start: Point) -> Option<LacSegment> {
    let (k0, k1) = (segment.kappa(s0), segment.kappa(s1));
    let alpha = segment.alpha().filter(|_| k0 != k1);
    LacSegment::new(start, segment.theta(s0), s1 - s0, alpha, k0, k1).ok()
}

/// Bisection steps locating a part's end by its turning: 64 halvings of the arc length reach
/// adjacent floating-point values from any start.
const PART_BISECTION_STEPS: usize = 64;

/// The arc lengths cutting `segment` into parts of equal turning, each at most
/// [`MAX_TURNING_PER_PART`] (at most [`MAX_PARTS_PER_SEGMENT`] parts), from 0 to its length.
/// The tangent angle of an LAC is monotonic in arc length (its curvature keeps one sign), so
/// each cut is found by bisection.
fn part_ends(segment: &LacSegment) -> Vec<f64> {
    let length = segment.length();
    let turning = segment.theta1() - segment.theta0();
    let parts = (turning.abs() / MAX_TURNING_PER_PART).ceil();
    // `parts` is a non-negative whole number (or NaN, which `as` maps to 0), clamped below the cap.
    let parts = (parts.min(MAX_PARTS_PER_SEGMENT as f64) as usize).max(1);
    let mut ends = vec![0.0];
    for k in 1..parts {
        let target = turning * k as f64 / parts as f64;
        let (mut lo, mut hi) = (ends[ends.len() - 1], length);
        for _ in 0..PART_BISECTION_STEPS {
            let mid = 0.5 * (lo + hi);
            if ((segment.theta(mid) - segment.theta0()) - target) * turning.signum() < 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        ends.push(0.5 * (lo + hi));
    }
    ends.push(length);
    ends
}

/// `segment` as cubic Béziers within `accuracy` of it (measured; see the module documentation).
///
/// A line is one exact cubic (error 0). Otherwise the segment is cut into parts turning at most
/// [`MAX_TURNING_PER_PART`], and kurbo's [`kurbo::fit_to_bezpath`] fits each (recursive
/// halving by arc length; its optimising sibling `fit_to_bezpath_opt` can panic in kurbo 0.13,
/// kurbo issue #601). kurbo judges its fit from 20 samples per cubic, which a hook (curvature
/// falling by orders of magnitude within the first percent of the length) can fool; so the
/// result is measured ([`bezier_error`]), and a part measured beyond the accuracy is halved and
/// fitted again. All of it spends at most [`MAX_FIT_STEPS_PER_SEGMENT`] steps; a fit that
/// spends them all is tried again coarser (up to [`MAX_COARSENINGS`] times) and the one that
/// measures best is kept, its measured error then above `accuracy`. The ends are the segment's
/// exact end points, so consecutive segments share their joints bit for bit. A non-positive or
/// non-finite `accuracy` is replaced by [`FALLBACK_ACCURACY_FRACTION`] of the segment's length,
/// and one finer than [`ACCURACY_FLOOR_ULPS`] rounding steps of the coordinates is raised to
/// that.
pub fn segment_beziers(segment: &LacSegment, accuracy: f64) -> SegmentBeziers {
    if segment.kappa0() == 0.0 && segment.kappa1() == 0.0 {
        return SegmentBeziers {
            cubics: vec![line_cubic(segment.start(), segment.end())],
            error: 0.0,
        };
    }
    let accuracy = if accuracy.is_finite() && accuracy > 0.0 {
        accuracy
    } else {
        FALLBACK_ACCURACY_FRACTION * segment.length()
    };
    let accuracy = accuracy.max(accuracy_floor(segment));
    let reference = Reference::new(segment, accuracy);
    let parts = parts_of(segment);
    let mut best: Option<SegmentBeziers> = None;
    let mut target = accuracy;
    for _ in 0..=MAX_COARSENINGS {
        let budget = Cell::new(MAX_FIT_STEPS_PER_SEGMENT);
        let mut cubics = Vec::new();
        let mut error: f64 = 0.0;
        for part in &parts {
            let e = fit_part(
                (part.curve(segment), part.offset),
                &reference,
                part.range,
                target,
                (0, &budget),
                &mut cubics,
            );
            error = error.max(e);
        }
        let spent = budget.get() == 0;
        if best.as_ref().is_none_or(|b| error < b.error) {
            best = Some(SegmentBeziers { cubics, error });
        }
        if !spent {
            break;
        }
        target *= COARSENING_FACTOR;
    }
    best.unwrap_or_else(|| SegmentBeziers {
        cubics: vec![line_cubic(segment.start(), segment.end())],
        error: f64::INFINITY,
    })
}

/// How many times [`segment_beziers`] asks for a coarser fit when a fit spends all of its
/// [`MAX_FIT_STEPS_PER_SEGMENT`] steps (whose unfinished ranges kurbo then draws as chords):
/// each time [`COARSENING_FACTOR`] coarser, with a fresh budget, keeping the fit that measures
/// best. An accuracy the segment cannot reach within the budget (a hook asked for 10⁻⁸ of a
/// pixel) so still gets a fit near the best reachable one rather than chords.
pub const MAX_COARSENINGS: usize = 8;

/// The factor between successive accuracies tried after a fit spent its budget.
pub const COARSENING_FACTOR: f64 = 10.0;

/// The parts of `segment` at [`part_ends`], each as a segment of its own starting where the
/// previous one ends (so evaluating a part costs what its own turning costs), the last ending
/// at the segment's exact end; one part is the segment itself.
fn parts_of(segment: &LacSegment) -> Vec<Part> {
    let ends = part_ends(segment);
    let last = ends.len() - 2;
    let mut start = segment.start();
    let mut parts = Vec::with_capacity(ends.len() - 1);
    for (k, w) in ends.windows(2).enumerate() {
        let sub = (last > 0)
            .then(|| sub_segment(segment, (w[0], w[1]), start))
            .flatten();
        let (offset, (s0, s1)) = match &sub {
            Some(sub) => (w[0], (0.0, sub.length())),
            None => (0.0, (w[0], w[1])),
        };
        // The segment's own end closes the last part, so joints between segments are exact.
        let end = if k == last {
            segment.end()
        } else {
            sub.as_ref().unwrap_or(segment).point(s1)
        };
        parts.push(Part {
            sub,
            offset,
            range: ((s0, start), (s1, end)),
        });
        start = end;
    }
    parts
}

/// The finest accuracy fitted, in units in the last place of the segment's extent (the largest
/// coordinate it reaches): kurbo fits in absolute coordinates, and asked for less than a few
/// hundred rounding steps of them it halves ranges down to coincident end points and solves
/// for wild control points there. 256 ulps is a relative 6·10⁻¹⁴: 6·10⁻⁵ at a billion units,
/// far below anything a pen or a CAD tool resolves at that size.
pub const ACCURACY_FLOOR_ULPS: f64 = 256.0;

/// [`ACCURACY_FLOOR_ULPS`] rounding steps of the largest coordinate `segment` can reach (its
/// start's plus its length).
fn accuracy_floor(segment: &LacSegment) -> f64 {
    let start = segment.start();
    let extent = start.x.abs().max(start.y.abs()) + segment.length();
    ACCURACY_FLOOR_ULPS * f64::EPSILON * extent
}

/// The accuracy used when the one given is not a positive number: this fraction of the
/// segment's length (a thousandth: invisible at the size the segment is drawn).
pub const FALLBACK_ACCURACY_FRACTION: f64 = 1e-3;
