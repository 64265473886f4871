//! Distances from a span's samples to an LAC segment.
//!
//! The segment is traced as a polyline at a spacing `h` whose chord error κ_max·h²/8 is at most
//! the caller's `chord_error` (κ_max is the larger end curvature: curvature is monotonic). Each
//! step integrates e^{iθ(s)} with the 3-point Gauss–Legendre rule on the closed-form θ, split
//! into sub-steps turning at most 0.1 rad ([`POLISH_STEP_TURN`]), where the rule's error, about
//! h·(κh)⁶/2·10⁶, is below 1e-12 of the step while the curvature changes slowly over it (see
//! [`POLISH_STEP_TURN`] for where it does not): three θ evaluations per vertex at pen curvatures
//! instead of a full adaptive panel. Next to the curvature's zero of a spiral with α < 0, where
//! κ is a power of the distance from it that the rule follows badly, the integral is the
//! power series of e^{iθ} about the zero instead, exact term by term (`near_zero`); a stretch
//! over which |κ| changes more than twofold is cut where it doubles (`graded`), so that the
//! turning bound of each part stays near its true turning. The samples, ordered along the span, are
//! projected onto it by a walk that starts each search at the previous sample's foot: the cost is
//! about one pass over the polyline per span, not samples × polyline. Those distances are exact to
//! within `chord_error` (the polyline lies inside the curve's convex side by at most that much);
//! [`deviation`] then polishes them into exact foot-point distances.

use super::quadrature::{GAUSS_LEGENDRE_3, Panel, panel_count};
use super::segment::LacSegment;
use super::special::{cis, cis_small, cmul};
use crate::geom::{Point, Vec2, nearest_on_segment};

/// Most polyline vertices used for one segment. A span whose required spacing would need more
/// (an extreme curvature ratio) is traced at the coarser spacing this allows; the chord error
/// then grows where the curvature is highest, over a vanishing length.
const MAX_VERTICES: usize = 20_000;

/// The walk stops searching once the polyline has moved this many spacings beyond twice the best
/// distance found: past that, only a curve that comes back towards the sample (a loop, which a
/// monotone-curvature span turning less than 2π cannot make within that reach) could be closer.
const LOOKAHEAD_SPACINGS: f64 = 4.0;

/// The samples' distances to a segment.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Deviation {
    /// Each sample's distance to the segment.
    pub distances: Vec<f64>,
    /// Each sample's foot point, as arc length along the segment.
    pub feet: Vec<f64>,
    /// Each sample's side: +1 left of the direction of travel, −1 right (0 on it).
    pub sides: Vec<f64>,
    /// Each sample's foot point on the segment and the unit normal there (left of travel),
    /// where every distance is to an exact foot point found by Newton's method; empty where
    /// the distances are (at least in part) a polyline's ([`rough_deviation`], or a polished
    /// foot that fell back to the polyline's). The chain refinement linearises the distances
    /// about them without integrating the segment again.
    pub foot_points: Vec<(Point, Vec2)>,
    /// The largest distance (0 without samples).
    pub max: f64,
    /// The root mean square distance (0 without samples).
    pub rms: f64,
}

impl Deviation {
    /// Each sample's signed distance: its distance times its side (positive left of travel).
    pub fn signed_distances(&self) -> Vec<f64> {
        self.distances
            .iter()
            .zip(&self.sides)
            .map(|(d, side)| d * side)
            .collect()
    }
}

/// Most Newton steps polishing a polyline foot into the exact foot point. The polyline foot is
/// within one spacing of the exact one and Newton converges quadratically from there: three or
/// four steps reach rounding from the seeding spacing; the iteration stops earlier once a step
/// is below [`FOOT_STEP_TOLERANCE`].
const FOOT_NEWTON_STEPS: usize = 8;

/// A Newton step on the foot shorter than this fraction of the segment's length ends the polish
/// without being taken (see [`newton_foot`]): the distance then exceeds the true one by about
/// step²/(2·distance), 5e-12 of the length for a sample a thousandth of the length away (and by
/// at most the step for a sample on the curve), never less than it. Over the fixture strokes up
/// to 600 samples at three tolerances, against 1e-9 (which squared one more step towards
/// rounding): 1 % fewer instructions on the median stroke for the same segments and rms
/// distance (1e-6: 2 %, for 6 more segments in 2 222).
const FOOT_STEP_TOLERANCE: f64 = 1e-7;

/// The polyline that seeds [`deviation`]'s Newton polish is traced at this multiple of the
/// caller's chord error: Newton only needs a start in the right foot's basin (within a spacing of
/// it), and the polish integrates from the nearest vertex in steps short enough for any spacing
/// ([`POLISH_STEP_TURN`]), so a coarser seed costs √10 ≈ 3 times fewer vertices for the same
/// exact answer.
pub const SEED_CHORD_FACTOR: f64 = 10.0;

/// Largest turning (radians) of one 3-point Gauss–Legendre step of the polish: the rule's error
/// is about h·(κh)⁶/2·10⁶, below 1e-12 of the step at 0.1 rad, while the curvature changes
/// slowly over the step. Where it changes fast relative to itself the higher derivatives of θ
/// add to that: over a length of 4 with curvature 0.1 → 2, points were off by 1.7e-10 of the
/// length at α = 0, 2.4e-8 at α = 3 and 1.3e-7 at α = −3 (the branch point of θ(s) 5e-4
/// before the start). Far below any tolerance a fit uses (≥ 1e-3 of a segment). Steps bounded
/// by |d ln κ/ds| as well, with a 5-point rule, bring all to 1e-13; written plainly that doubled
/// a fit's cost (the rate is recomputed per call); Taylor-series steps of θ (1e-14), even from a
/// walker that carries θ, κ and d ln κ/ds from vertex to vertex, cost more than they save (the
/// rate bound that makes them exact takes about three steps per trace vertex: 3.71e9 against
/// 2.35e9 instructions over the fixture strokes).
pub const POLISH_STEP_TURN: f64 = 0.1;

/// Most steps of one integration between vertices or to a foot (the step count follows the
/// curvature; this bounds the work where [`MAX_VERTICES`] forces a coarse spacing near an
/// extreme curvature).
const MAX_POLISH_STEPS: usize = 64;

/// Exact distances from `samples` (ordered along the segment) to `segment`, by Newton's method
/// on the foot-point equation (P(s) − q)·T(s) = 0. First by marching from foot to foot along the
/// segment (`marched`: the work follows the samples); where that does not settle, from the
/// polyline foot (see [`project_ordered`], traced at [`SEED_CHORD_FACTOR`] times `chord_error`),
/// with P(s) integrated from the nearest polyline vertex. Exact to the integration's accuracy
/// ([`POLISH_STEP_TURN`]) and smooth in the segment's parameters (the chain refinement
/// differentiates it). Every distance is to a point of the segment, so none is below the true
/// one: a tolerance checked on them holds.
///
/// Marching instead of tracing first, over the fixture strokes up to 600 samples: 3 % fewer
/// instructions on the median stroke (7 % more in all: long, densely sampled strokes), and the α
/// searches, ranking by exact distances instead of a polyline's, end with a lower rms distance
/// (0.245 of the tolerance against 0.256).
pub fn deviation(segment: &LacSegment, samples: &[Point], chord_error: f64) -> Deviation {
    marched(segment, samples).unwrap_or_else(|| traced(segment, samples, chord_error))
}

/// [`deviation`] from polyline feet (the fallback where marching does not settle).
fn traced(segment: &LacSegment, samples: &[Point], chord_error: f64) -> Deviation {
    let seed = SEED_CHORD_FACTOR * chord_error;
    let polyline = trace(segment, seed);
    let mut d = project_raw(&polyline, samples);
    polish_feet(segment, &polyline, samples, seed, &mut d);
    summarise(d)
}

/// Exact distances from `samples` to `segment` by Newton's method on the foot-point equation
/// started at `seeds` (an arc length per sample: the feet on a nearby segment, rescaled to this
/// one's length), without tracing a polyline: for a segment a small step away from the one the
/// seeds came from (a refinement trial), whose feet move by far less than the curve's radius.
/// The starting points come from one pass along the segment ([`points_at`]). `None` when a foot
/// does not settle within [`FOOT_NEWTON_STEPS`] or the iteration leaves the foot's basin (the
/// caller then traces: [`deviation`]).
pub(crate) fn deviation_near(
    segment: &LacSegment,
    samples: &[Point],
    seeds: &[f64],
) -> Option<Deviation> {
    if seeds.len() != samples.len() {
        return None;
    }
    let length = segment.length();
    let starts = points_at(segment, seeds);
    let mut d = Deviation {
        distances: Vec::with_capacity(samples.len()),
        feet: Vec::with_capacity(samples.len()),
        sides: Vec::with_capacity(samples.len()),
        foot_points: Vec::with_capacity(samples.len()),
        ..Deviation::default()
    };
    for ((q, &seed), start) in samples.iter().zip(seeds).zip(starts) {
        let foot = newton_foot(
            segment,
            *q,
            seed.clamp(0.0, length),
            start,
            |from, to, p| p + integrate(segment, from, to),
        );
        if !foot.settled {
            return None;
        }
        d.distances.push(q.distance(foot.p));
        d.feet.push(foot.s);
        d.sides.push(foot.side(segment, *q));
        d.foot_points.push((foot.p, foot.normal?));
    }
    Some(summarise(d))
}

/// [`deviation_near`] of one sample `q` from `seed`: its distance, without the record's vectors
/// (the same iteration, so the same number); `None` where [`deviation_near`] gives none.
pub(crate) fn distance_near(segment: &LacSegment, q: Point, seed: f64) -> Option<f64> {
    let length = segment.length();
    let seed = seed.clamp(0.0, length);
    let start = if seed == length {
        segment.end()
    } else {
        let (here, there) = (segment.kappa(0.0).abs(), segment.kappa(seed).abs());
        segment.start() + integrate_within(segment, 0.0, seed, here, there)
    };
    let foot = newton_foot(segment, q, seed, start, |from, to, p| {
        p + integrate(segment, from, to)
    });
    (foot.settled && foot.normal.is_some()).then(|| q.distance(foot.p))
}

/// Exact distances from `samples` (ordered along the segment) to `segment` by Newton's method
/// on the foot-point equation, marching along the segment from one sample's foot to the next
/// (each seeded one chord between the samples beyond the previous foot; the first by its
/// projection on the start tangent): no polyline, so the work follows the samples, not the
/// segment's length and curvature. Each distance is to a point of the segment, so never below
/// the true one. `None` (the caller traces instead) when a foot does not settle, leaves its
/// basin, or the feet do not advance along the segment as the samples do.
pub(crate) fn marched(segment: &LacSegment, samples: &[Point]) -> Option<Deviation> {
    let length = segment.length();
    let mut d = Deviation {
        distances: Vec::with_capacity(samples.len()),
        feet: Vec::with_capacity(samples.len()),
        sides: Vec::with_capacity(samples.len()),
        foot_points: Vec::with_capacity(samples.len()),
        ..Deviation::default()
    };
    let (mut s, mut p) = (0.0, segment.start());
    let mut previous: Option<Point> = None;
    for q in samples {
        let seed = match previous {
            Some(before) => (s + q.distance(before)).min(length),
            None => {
                let (sin, cos) = segment.theta0().sin_cos();
                (*q - p).dot(Vec2::new(cos, sin)).clamp(0.0, length)
            }
        };
        p = move_along(segment, s, seed, p);
        let foot = newton_foot(segment, *q, seed, p, |from, to, p| {
            move_along(segment, from, to, p)
        });
        if !foot.settled || foot.s < s {
            return None;
        }
        d.distances.push(q.distance(foot.p));
        d.feet.push(foot.s);
        d.sides.push(foot.side(segment, *q));
        d.foot_points.push((foot.p, foot.normal?));
        (s, p) = (foot.s, foot.p);
        previous = Some(*q);
    }
    Some(summarise(d))
}

/// The segment's point at arc length `to`, given its point `p` at `from`: integrated from there,
/// except at the ends, which are known exactly (a march's integration error, see
/// [`POLISH_STEP_TURN`], does not reach a foot at either end).
fn move_along(segment: &LacSegment, from: f64, to: f64, p: Point) -> Point {
    if to == segment.length() {
        segment.end()
    } else if to == 0.0 {
        segment.start()
    } else {
        p + integrate(segment, from, to)
    }
}

/// Distances to the polyline only (exact to `chord_error`): cheaper, for ranking candidates.
pub fn rough_deviation(segment: &LacSegment, samples: &[Point], chord_error: f64) -> Deviation {
    let polyline = trace(segment, chord_error);
    project_ordered(&polyline, samples)
}

/// Replaces polyline feet by exact foot points (see [`deviation`]).
fn polish_feet(
    segment: &LacSegment,
    polyline: &[(f64, Point)],
    samples: &[Point],
    chord_error: f64,
    d: &mut Deviation,
) {
    let mut exact = Vec::with_capacity(samples.len());
    for (i, q) in samples.iter().enumerate() {
        let start = point_near(segment, polyline, d.feet[i]);
        // Unsettled (a non-positive slope, or the step budget spent): the distance check below
        // decides whether the last iterate is kept.
        let foot = newton_foot(segment, *q, d.feet[i], start, |_, to, _| {
            point_near(segment, polyline, to)
        });
        let distance = q.distance(foot.p);
        // The exact distance differs from the polyline's by at most the chord error (the chords
        // cut inside the curve); anything farther means Newton wandered to another foot, and the
        // polyline's foot is kept, measured to the curve's point there: the polyline's own
        // distance can fall up to the chord error short of the curve's, a distance to a point of
        // the curve never does.
        if distance <= d.distances[i] + chord_error {
            d.distances[i] = distance;
            d.feet[i] = foot.s;
            d.sides[i] = foot.side(segment, *q);
            if let Some(normal) = foot.normal {
                exact.push((foot.p, normal));
            }
        } else {
            d.distances[i] = q.distance(start);
        }
    }
    d.foot_points = if exact.len() == samples.len() {
        exact
    } else {
        Vec::new()
    };
}

/// Where [`newton_foot`] ended.
struct FootFound {
    /// Arc length of the foot.
    s: f64,
    /// The segment's point there.
    p: Point,
    /// Whether it settled (see [`newton_foot`]).
    settled: bool,
    /// The sample's side there (see [`side`]), when the iteration knew the normal at `s`.
    side: Option<f64>,
    /// The unit normal (left of travel) at `s`, when the iteration knew it.
    normal: Option<Vec2>,
}

impl FootFound {
    /// The side of `q`, from the iteration or computed afresh.
    fn side(&self, segment: &LacSegment, q: Point) -> f64 {
        self.side
            .unwrap_or_else(|| side(segment, self.s, q, self.p))
    }
}

/// Newton's method on the foot-point equation (P(s) − q)·T(s) = 0 from arc length `s` with point
/// `p`, the next point found by `move_to(from, to, p)`: the foot, and whether it settled (a step
/// below [`FOOT_STEP_TOLERANCE`] of the length, or none, or an end with the sample beyond it)
/// rather than stopping at a non-positive slope or after [`FOOT_NEWTON_STEPS`]. A step below the
/// tolerance is not taken: the iterate is then within about that step of the foot, and its
/// distance to the sample exceeds the true one by a second-order amount (about
/// step²/(2·distance), see [`FOOT_STEP_TOLERANCE`]); moving there would cost an integration for
/// nothing. Over the fixture strokes up to 600
/// samples at three tolerances, with θ and κ from one evaluation and the side from the last
/// normal: 6 % fewer instructions on the median stroke.
fn newton_foot(
    segment: &LacSegment,
    q: Point,
    mut s: f64,
    mut p: Point,
    mut move_to: impl FnMut(f64, f64, Point) -> Point,
) -> FootFound {
    let length = segment.length();
    for _ in 0..FOOT_NEWTON_STEPS {
        let (theta, kappa) = segment.theta_kappa(s);
        let (sin, cos) = theta.sin_cos();
        let r = p - q;
        let along = r.dot(Vec2::new(cos, sin));
        let across = r.dot(Vec2::new(-sin, cos));
        let found = |settled: bool| FootFound {
            s,
            p,
            settled,
            side: Some((-across).signum()),
            normal: Some(Vec2::new(-sin, cos)),
        };
        // At an end with the sample beyond it, the distance grows into the segment: the end is
        // the (constrained) foot, whatever the curvature there.
        if (s == length && along <= 0.0) || (s == 0.0 && along >= 0.0) {
            return found(true);
        }
        let slope = 1.0 + kappa * across;
        if !(slope > 0.0) {
            return found(false);
        }
        let next = (s - along / slope).clamp(0.0, length);
        if (next - s).abs() <= FOOT_STEP_TOLERANCE * length {
            return found(true);
        }
        p = move_to(s, next, p);
        s = next;
    }
    FootFound {
        s,
        p,
        settled: false,
        side: None,
        normal: None,
    }
}

/// The side of `q` relative to the segment at its foot `p` (arc length `s`): +1 left of the
/// direction of travel, −1 right, 0 on it.
fn side(segment: &LacSegment, s: f64, q: Point, p: Point) -> f64 {
    let (sin, cos) = segment.theta(s).sin_cos();
    (q - p).dot(Vec2::new(-sin, cos)).signum()
}

/// The segment's point at arc length `s`, integrated from the nearest polyline vertex with the
/// 3-point rule in steps turning at most [`POLISH_STEP_TURN`] (curvature is monotonic, so the
/// larger end curvature of the stretch bounds it).
fn point_near(segment: &LacSegment, polyline: &[(f64, Point)], s: f64) -> Point {
    let k = polyline.partition_point(|v| v.0 <= s);
    let (s0, p0) = match (
        k.checked_sub(1).and_then(|j| polyline.get(j)),
        polyline.get(k),
    ) {
        (Some(a), Some(b)) => {
            if s - a.0 <= b.0 - s {
                *a
            } else {
                *b
            }
        }
        (Some(a), None) => *a,
        (None, Some(b)) => *b,
        (None, None) => return segment.point(s),
    };
    p0 + integrate(segment, s0, s)
}

/// The segment's points at the arc lengths `s` (clamped to [0, S]), integrated from each to the
/// next ([`integrate`]) starting at the segment's start: for lengths in increasing order (foot
/// points of ordered samples) about one pass along the segment, instead of one integration from
/// the start per point. Exact to about 1e-12 of the length where the curvature varies slowly
/// (see [`POLISH_STEP_TURN`] for where it does not).
pub(crate) fn points_at(segment: &LacSegment, s: &[f64]) -> Vec<Point> {
    let mut out = Vec::with_capacity(s.len());
    points_at_into(segment, s, &mut out);
    out
}

/// [`points_at`] into `out` (cleared first).
pub(crate) fn points_at_into(segment: &LacSegment, s: &[f64], out: &mut Vec<Point>) {
    out.clear();
    let length = segment.length();
    let mut at = 0.0;
    let mut p = segment.start();
    // |κ| at `at`, carried from one point to the next.
    let mut here = segment.kappa(0.0).abs();
    out.extend(s.iter().map(|&target| {
        let target = target.clamp(0.0, length);
        if target == length {
            return segment.end();
        }
        let there = segment.kappa(target).abs();
        p += integrate_within(segment, at, target, here, there);
        at = target;
        here = there;
        p
    }));
}

/// P(b) − P(a) by the 3-point Gauss–Legendre rule in steps turning at most
/// [`POLISH_STEP_TURN`] (curvature is monotonic, so the larger end curvature bounds the turning),
/// or next to the curvature's zero by its series ([`near_zero`]). `b` may be below `a`.
fn integrate(segment: &LacSegment, a: f64, b: f64) -> Vec2 {
    integrate_within(
        segment,
        a,
        b,
        segment.kappa(a).abs(),
        segment.kappa(b).abs(),
    )
}

/// [`integrate`] given |κ| at `a` and at `b`.
fn integrate_within(segment: &LacSegment, a: f64, b: f64, kappa_a: f64, kappa_b: f64) -> Vec2 {
    let (low, high) = (kappa_a.min(kappa_b), kappa_a.max(kappa_b));
    // Lines, arcs, and stretches whose curvature changes slowly: the turning bound alone.
    let Some(alpha) = segment.alpha().filter(|_| high > SERIES_RATIO * low) else {
        return stepped(segment, a, b, high);
    };
    if alpha < 0.0
        && let Some(d) = near_zero(segment, alpha, a, b, kappa_a, kappa_b)
    {
        return d;
    }
    if high > GRADE_RATIO * low {
        return graded(segment, alpha, a, b, kappa_a, kappa_b);
    }
    stepped(segment, a, b, high)
}

/// Largest curvature ratio over one stretch of [`graded`]: within it the turning bound κ_max·h
/// of [`stepped`] is within a factor of the true turning, and the rule's error follows it.
/// Points within 5e-7 of the length of the closed form where the equal steps left them up to
/// 9e-5 off (α from 0 to 3, curvature ratios up to 9 000), for 1 % more instructions over the
/// fixture strokes; a ratio of 1.12 brings them within 1e-9 for 13 % more.
const GRADE_RATIO: f64 = 2.0;

/// Most stretches of [`graded`] (a curvature ratio of 2^64, far beyond any segment's).
const MAX_GRADES: usize = 64;

/// [`stepped`] over stretches of [a, b] on each of which |κ| changes by [`GRADE_RATIO`] at
/// most. The turning bound κ_max·|b − a| of one stretch overestimates its turning by the
/// curvature ratio: next to the end of a spiral with α > 0 where κ grows without bound (its
/// branch point just beyond), a stretch from κ = 0.013 to 116 /px over 13.4 px asked for 15 000
/// steps, was capped at [`MAX_POLISH_STEPS`] equal ones, and its last step, κ from 0.8 to 116,
/// put the point 4e-4 px off the curve. |κ|^(−α) is affine in s (ln |κ| at α = 0), so stretches
/// geometric in |κ| are found in closed form.
fn graded(segment: &LacSegment, alpha: f64, a: f64, b: f64, kappa_a: f64, kappa_b: f64) -> Vec2 {
    let ratio = kappa_b / kappa_a;
    let grades = (ratio.ln().abs() / GRADE_RATIO.ln()).ceil();
    if !(grades.is_finite() && grades >= 1.0) {
        return stepped(segment, a, b, kappa_a.max(kappa_b));
    }
    let grades = (grades as usize).min(MAX_GRADES);
    let (power_a, power_b) = (kappa_a.powf(-alpha), kappa_b.powf(-alpha));
    let mut sum = Vec2::ZERO;
    let (mut from, mut kappa_from) = (a, kappa_a);
    for k in 1..=grades {
        let (to, kappa_to) = if k == grades {
            (b, kappa_b)
        } else {
            let kappa = kappa_a * ratio.powf(k as f64 / grades as f64);
            let fraction = if alpha == 0.0 {
                k as f64 / grades as f64
            } else {
                (kappa.powf(-alpha) - power_a) / (power_b - power_a)
            };
            (a + fraction * (b - a), kappa)
        };
        sum += stepped(segment, from, to, kappa_from.max(kappa_to));
        (from, kappa_from) = (to, kappa_to);
    }
    sum
}

/// A stretch whose end curvatures differ by less than this factor is stepped: next to a zero,
/// where |κ| ∝ u^p, the rule's error on θ ∝ u^(p+1) over a stretch is about (ln r)⁶/2·10⁶ of
/// its turning times its length for a curvature ratio r (whatever p), below 1e-12 for r < 1.12;
/// beyond, the series.
const SERIES_RATIO: f64 = 1.12;

/// Largest turning from the curvature's zero, |θ − θ*|, that [`near_zero`]'s series sums:
/// its terms fall as |t|ᵏ/k!, below 1e-17 by the twentieth.
const SERIES_TURN: f64 = 1.0;

/// Terms of [`near_zero`]'s series at most (see [`SERIES_TURN`]).
const SERIES_TERMS: usize = 24;

/// Farthest the curvature's zero may lie from the stretch, in stretch lengths, for
/// [`near_zero`]: its first term is the difference of the two distances from it, which loses
/// their rounding (1e-16 of them).
const SERIES_REACH: f64 = 1e3;

/// P(b) − P(a) on a spiral with α < 0 by a series about the curvature's zero, where the 3-point
/// rule in s is poor: there |κ|^(−α) is affine in s, so |κ| = (c·u)^p with p = −1/α and u the
/// arc length from the zero s* (which lies at or beyond an end of the segment), and the turning
/// from it is t(s) = θ(s) − θ* = u·κ(s)/(p + 1), a power u·|u|^p of u. Then
///
/// ∫ₐᵇ e^{iθ} ds = e^{iθ*} Σₖ (iᵏ/k!) (u_b·t_bᵏ − u_a·t_aᵏ) / (k(p + 1) + 1),
///
/// exact term by term. Next to a zero end with α near 0 the power p is large (20 at α = −0.05)
/// and θ far from the polynomials the rule integrates: one step over the first 32 px of a 43 px
/// segment, turning 1e-3 rad, put its point 1.2e-3 px off the curve, and a reported distance
/// 0.0020 px where the sample lay 0.0032 px away; stepping foot to foot the points were off by
/// 1e-5 of the length at α = −0.05, 3e-6 at −0.2, 4e-8 at −0.7. With the series they are within
/// 1e-13, and over the fixture strokes up to 600 samples the fits take 2 % fewer instructions
/// (3 161 → 3 106 M; a series of a dozen products where the rule took several steps, and
/// trials that converge sooner). The part of [a, b] turning more than [`SERIES_TURN`] from
/// the zero, where the curvature changes slowly relative to a step again, is stepped. `None`
/// where the series does not apply (a zero too far, or none: equal curvatures).
fn near_zero(
    segment: &LacSegment,
    alpha: f64,
    a: f64,
    b: f64,
    kappa_a: f64,
    kappa_b: f64,
) -> Option<Vec2> {
    let (lo, hi) = (a.min(b), a.max(b));
    let (k_lo, k_hi) = if a <= b {
        (kappa_a, kappa_b)
    } else {
        (kappa_b, kappa_a)
    };
    let power = -1.0 / alpha;
    // |κ|^(−α) at the two ends, affine in s: where it vanishes.
    let (r_lo, r_hi) = (k_lo.powf(-alpha), k_hi.powf(-alpha));
    let slope = (r_hi - r_lo) / (hi - lo);
    if !(slope != 0.0 && slope.is_finite()) {
        return None;
    }
    let zero = lo - r_lo / slope;
    if !((zero - lo).abs().max((zero - hi).abs()) <= SERIES_REACH * (hi - lo)) {
        return None;
    }
    // The curvature's sign is its segment's (a spiral has no inflection).
    let sign = if segment.kappa0() + segment.kappa1() < 0.0 {
        -1.0
    } else {
        1.0
    };
    let turning = |u: f64, k: f64| sign * u * k / (power + 1.0);
    // The stretch nearer the zero, up to where it turns SERIES_TURN from it; the rest stepped.
    let (near, far) = if (zero - lo).abs() <= (zero - hi).abs() {
        (lo, hi)
    } else {
        (hi, lo)
    };
    let (k_near, k_far) = if near == lo {
        (k_lo, k_hi)
    } else {
        (k_hi, k_lo)
    };
    let (u_near, u_far) = (near - zero, far - zero);
    let (t_near, t_far) = (turning(u_near, k_near), turning(u_far, k_far));
    if !(t_near.abs() <= SERIES_TURN) {
        return None;
    }
    let (split, u_split, t_split, k_split) = if t_far.abs() <= SERIES_TURN {
        (far, u_far, t_far, k_far)
    } else {
        // |t| = |u|^(p+1)·(its factor): where it reaches SERIES_TURN.
        let u = u_far * (SERIES_TURN / t_far.abs()).powf(1.0 / (power + 1.0));
        let s = zero + u;
        let k = segment.kappa(s).abs();
        (s, u, turning(u, k), k)
    };
    let theta_zero = segment.theta(near) - t_near;
    let mut sum = Vec2::ZERO;
    let (mut pow_near, mut pow_split, mut factorial) = (1.0, 1.0, 1.0);
    for k in 0..SERIES_TERMS {
        if k > 0 {
            pow_near *= t_near;
            pow_split *= t_split;
            factorial *= k as f64;
        }
        let term = (u_split * pow_split - u_near * pow_near)
            / (factorial * (k as f64 * (power + 1.0) + 1.0));
        // iᵏ: 1, i, −1, −i.
        sum += match k % 4 {
            0 => Vec2::new(term, 0.0),
            1 => Vec2::new(0.0, term),
            2 => Vec2::new(-term, 0.0),
            _ => Vec2::new(0.0, -term),
        };
        if pow_split.abs().max(pow_near.abs()) / factorial < SERIES_FLOOR {
            break;
        }
    }
    // From `near` to `split`, turned by θ*; then the stepped rest from `split` to `far`.
    let series = cmul(cis(theta_zero), sum);
    let rest = if split == far {
        Vec2::ZERO
    } else {
        stepped(segment, split, far, k_split.max(k_far))
    };
    let near_to_far = series + rest;
    Some(if near == a { near_to_far } else { -near_to_far })
}

/// A term of [`near_zero`]'s series below this fraction of the stretch ends it.
const SERIES_FLOOR: f64 = 1e-18;

/// The 3-point rule over [a, b] in steps turning at most [`POLISH_STEP_TURN`], `kappa` a bound on
/// |κ| over [a, b].
fn stepped(segment: &LacSegment, a: f64, b: f64, kappa: f64) -> Vec2 {
    let turn = kappa * (b - a).abs();
    let steps = panel_count(turn, POLISH_STEP_TURN).min(MAX_POLISH_STEPS);
    let mut sum = Vec2::ZERO;
    let [(outer_weight, _), (middle_weight, _), (_, outer)] = GAUSS_LEGENDRE_3;
    for Panel { mid, half } in Panel::equal(a, b, steps) {
        // e^{iθ} at the nodes as e^{iθ_mid}·e^{i(θ − θ_mid)}: one sin_cos per step, the rest by
        // the small-angle series (the step turns at most POLISH_STEP_TURN); the angles around
        // the middle as increments on it (see `LacSegment::theta_around`), the outer two
        // weighted together.
        let [before, theta_mid, after] = segment.theta_around(mid, half * outer);
        let phase_mid = cis(theta_mid);
        let sides = cis_small(before - theta_mid) + cis_small(after - theta_mid);
        sum += (phase_mid * middle_weight + cmul(phase_mid, sides) * outer_weight) * half;
    }
    sum
}

/// The segment as `(arc length, point)` vertices with chord error at most `chord_error`; the last
/// vertex is the segment's exact end.
///
/// The step follows the local curvature, h = √(8·e/|κ|), with κ the larger of its two ends'
/// (curvature is monotonic, so that bounds it over the step): a segment whose curvature is high
/// only near one end gets dense vertices only there. The count is about ∫√(|κ|/8e) ds, not
/// L·√(κ_max/8e).
pub fn trace(segment: &LacSegment, chord_error: f64) -> Vec<(f64, Point)> {
    let length = segment.length();
    let min_step = length / MAX_VERTICES as f64;
    let step_for = |kappa: f64| -> f64 {
        if kappa > 0.0 && chord_error > 0.0 {
            (8.0 * chord_error / kappa).sqrt().max(min_step)
        } else {
            length
        }
    };
    let mut out = Vec::new();
    let mut s0 = 0.0;
    let mut p = segment.start();
    out.push((0.0, p));
    // |κ| at s0, carried from the previous step when its end was evaluated there.
    let mut here = segment.kappa(0.0).abs();
    while s0 < length {
        let first = step_for(here).min(length - s0);
        let far = segment.kappa(s0 + first).abs();
        let mut h = first.min(step_for(far)).min(length - s0);
        // Land exactly on the end rather than leave a sliver step.
        if length - (s0 + h) < 0.25 * h {
            h = length - s0;
        }
        // |κ| is monotonic: the larger of its values at the step's ends bounds it over the step
        // (`far` still bounds it when the step was shortened; a step stretched to the end ends
        // at κ1).
        let end_kappa = if h == first {
            far
        } else if h == length - s0 {
            segment.kappa1().abs()
        } else {
            segment.kappa(s0 + h).abs()
        };
        p += integrate_within(segment, s0, s0 + h, here, end_kappa);
        s0 += h;
        here = end_kappa;
        out.push((s0, p));
    }
    if let Some(last) = out.last_mut() {
        *last = (length, segment.end());
    }
    out
}

/// Projects ordered samples onto an ordered polyline.
pub fn project_ordered(polyline: &[(f64, Point)], samples: &[Point]) -> Deviation {
    let out = project_raw(polyline, samples);
    summarise(out)
}

/// [`project_ordered`] without the summary figures.
fn project_raw(polyline: &[(f64, Point)], samples: &[Point]) -> Deviation {
    let mut out = Deviation {
        distances: Vec::with_capacity(samples.len()),
        feet: Vec::with_capacity(samples.len()),
        sides: Vec::with_capacity(samples.len()),
        ..Deviation::default()
    };
    if polyline.is_empty() {
        return out;
    }
    if polyline.len() == 1 {
        for q in samples {
            out.distances.push(q.distance(polyline[0].1));
            out.feet.push(polyline[0].0);
            out.sides.push(0.0);
        }
        return out;
    }
    let mut start = 0usize;
    for q in samples {
        // Samples can step back a little (noise): begin a couple of vertices behind.
        let mut k = start.saturating_sub(2);
        let mut best = (f64::INFINITY, polyline[0].0, start, 0.0);
        while k + 1 < polyline.len() {
            let (s0, a) = polyline[k];
            let (s1, b) = polyline[k + 1];
            let (d, f) = nearest_on_segment(*q, a, b);
            if d < best.0 {
                best = (d, s0 + f * (s1 - s0), k, (b - a).cross(*q - a).signum());
            }
            if q.distance(a) > 2.0 * best.0 + LOOKAHEAD_SPACINGS * (s1 - s0) {
                break;
            }
            k += 1;
        }
        out.distances.push(best.0);
        out.feet.push(best.1);
        out.sides.push(if best.0 > 0.0 { best.3 } else { 0.0 });
        start = best.2;
    }
    out
}

fn summarise(mut d: Deviation) -> Deviation {
    let n = d.distances.len();
    d.max = 0.0;
    d.rms = 0.0;
    if n > 0 {
        d.max = d.distances.iter().copied().fold(0.0, f64::max);
        d.rms = (d.distances.iter().map(|x| x * x).sum::<f64>() / n as f64).sqrt();
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_samples_of_an_arc_are_at_their_offset() {
        // A quarter circle of radius 20: samples 0.05 outside it.
        let seg = LacSegment::new(
            Point::new(20.0, 0.0),
            std::f64::consts::FRAC_PI_2,
            10.0 * std::f64::consts::PI,
            None,
            0.05,
            0.05,
        )
        .expect("arc");
        let samples: Vec<Point> = (0..=40)
            .map(|i| {
                let a = std::f64::consts::FRAC_PI_2 * i as f64 / 40.0;
                Point::new(20.05 * a.cos(), 20.05 * a.sin())
            })
            .collect();
        let d = deviation(&seg, &samples, 1e-6);
        for (x, s) in d.distances.iter().zip(&d.feet) {
            assert!((x - 0.05).abs() < 2e-6, "{x}");
            assert!(*s >= 0.0 && *s <= seg.length());
        }
        assert!((d.max - 0.05).abs() < 2e-6 && (d.rms - 0.05).abs() < 2e-6);
        // Feet advance with the samples.
        assert!(d.feet.windows(2).all(|w| w[1] >= w[0]));
        assert!((d.feet[20] - seg.length() / 2.0).abs() < 1e-3);
    }

    #[test]
    fn the_trace_lies_on_the_segment() {
        // The vertices must be exact to far below the chord error they are traced for (here 1 %
        // of it), whatever α and however fast the curvature changes (κ 0.2 → 0.01 over a length
        // of 40: for α = 3 most of that fall happens within the first step).
        let chord = 1e-3;
        for alpha in [-1.5, -1.0, 0.0, 0.5, 1.0, 2.0, 3.0] {
            let seg = LacSegment::new(Point::new(1.0, 2.0), 0.3, 40.0, Some(alpha), 0.2, 0.01)
                .expect("segment");
            for &(s, p) in &trace(&seg, chord) {
                let error = p.distance(seg.point(s));
                assert!(error < 1e-2 * chord, "alpha {alpha}, s {s}: {error}");
            }
        }
    }

    #[test]
    fn points_next_to_a_curvature_zero_are_on_the_curve() {
        // From a zero-curvature end (or one a hair above zero, whose power law starts just
        // before the segment) with α in (−1, 0), κ grows as a power s^(−1/α) above 1, which the
        // 3-point rule in s integrates badly in one step (1.1e-5 of the length at α = −0.05,
        // 2.8e-6 at −0.2, before the series of `near_zero`). Marched foot to foot, traced, and in
        // one stretch, in both directions along the segment, every point is within 1e-10 of the
        // length of the closed form.
        let length = 43.0;
        for alpha in [-0.05, -0.1, -0.2, -0.3, -0.5, -0.7, -1.0, -2.0] {
            for (k0, k1) in [(0.0, 0.136), (-1e-21, -0.136), (0.136, 0.0), (0.001, 0.2)] {
                let seg = LacSegment::new(Point::new(3.0, -1.0), 0.7, length, Some(alpha), k0, k1)
                    .expect("segment");
                let mut worst = farthest_off_curve(&seg, &[0.1, 0.3, 0.5, 0.75, 0.9]);
                for &(s, p) in &trace(&seg, 1e-3) {
                    worst = worst.max(p.distance(seg.point(s)));
                }
                assert!(
                    worst <= 1e-10 * length,
                    "α {alpha}, κ {k0} → {k1}: {worst} off the curve"
                );
            }
        }
    }

    #[test]
    fn points_next_to_a_growing_curvature_are_on_the_curve() {
        // A spiral whose curvature grows by thousands over its length (with α > 0 its branch
        // point, where κ is infinite, lies just beyond the end): one stretch's turning bound
        // κ_max·h asked for thousands of steps and the capped, equal steps left the point by up
        // to 1e-4 of the length (1.2e-3 px for a fuzz input's α = 0.993, κ 0.013 → 116 /px over
        // 13.4 px). Graded stretches keep every point within 1e-6 of the length, whichever way
        // along the segment it is integrated.
        for (alpha, k0, k1, length) in [
            (0.993, 0.0126, 115.66, 13.448),
            (1.0, 0.01, 50.0, 10.0),
            (2.0, 0.01, 50.0, 10.0),
            (0.5, 0.01, 20.0, 10.0),
            (3.0, 0.2, 0.01, 40.0),
            (0.0, 0.01, 20.0, 10.0),
        ] {
            let seg = LacSegment::new(Point::new(3.0, -1.0), 0.7, length, Some(alpha), k0, k1)
                .expect("segment");
            let worst = farthest_off_curve(&seg, &[0.1, 0.3, 0.5, 0.75, 0.9, 0.99]);
            assert!(
                worst <= 1e-6 * length,
                "α {alpha}, κ {k0} → {k1}: {worst} off the curve"
            );
        }
    }

    /// The farthest of `seg`'s points from its closed form ([`LacSegment::point`]): marched
    /// foot to foot ([`points_at`], denser towards the end), and integrated in one stretch to
    /// each of `fractions` of the length from the start and from the end.
    fn farthest_off_curve(seg: &LacSegment, fractions: &[f64]) -> f64 {
        let length = seg.length();
        let feet: Vec<f64> = (1..20)
            .map(|i| length * (f64::from(i) / 20.0).sqrt())
            .collect();
        let mut worst: f64 = 0.0;
        for (p, &s) in points_at(seg, &feet).iter().zip(&feet) {
            worst = worst.max(p.distance(seg.point(s)));
        }
        for s in fractions.iter().map(|f| f * length) {
            let forward = seg.start() + integrate(seg, 0.0, s);
            let backward = seg.end() + integrate(seg, length, s);
            worst = worst
                .max(forward.distance(seg.point(s)))
                .max(backward.distance(seg.point(s)));
        }
        worst
    }

    /// A spiral (α = 0.5, S = 50) and samples at s = 50·i/40 for i in `range`, offset along the
    /// exact normal by 0.08 (even i) or −0.05 (odd i).
    fn offset_spiral_samples(range: std::ops::Range<usize>) -> (LacSegment, Vec<Point>) {
        let seg = LacSegment::new(Point::new(0.0, 0.0), 0.2, 50.0, Some(0.5), 0.15, 0.02)
            .expect("segment");
        let samples = range
            .map(|i| {
                let s = 50.0 * i as f64 / 40.0;
                let th = seg.theta(s);
                let offset: f64 = if i % 2 == 0 { 0.08 } else { -0.05 };
                seg.point(s) + Vec2::new(-th.sin(), th.cos()) * offset
            })
            .collect();
        (seg, samples)
    }

    #[test]
    fn marched_feet_are_the_traced_feet() {
        // Samples on both sides of a spiral, and beyond both ends (their feet are the ends).
        for alpha in [-2.0, -1.0, 0.0, 0.5, 1.0, 2.0] {
            let seg = LacSegment::new(Point::new(1.0, 2.0), 0.2, 50.0, Some(alpha), 0.15, 0.02)
                .expect("segment");
            let samples: Vec<Point> = (-2..43)
                .map(|i| {
                    let s = 50.0 * i as f64 / 40.0;
                    let th = seg.theta(s);
                    let offset: f64 = if i % 2 == 0 { 0.3 } else { -0.2 };
                    let beyond = (s - s.clamp(0.0, 50.0)) * Vec2::new(th.cos(), th.sin());
                    seg.point(s) + beyond + Vec2::new(-th.sin(), th.cos()) * offset
                })
                .collect();
            let marched = marched(&seg, &samples).expect("settles");
            let traced = traced(&seg, &samples, 1e-3);
            for i in 0..samples.len() {
                let (m, t) = (marched.distances[i], traced.distances[i]);
                // Both integrate with the polish's 3-point rule, each from its own points
                // (the march from foot to foot, the polish from polyline vertices): they agree
                // to that rule's accuracy, a few 1e-9 of the length where the curvature changes
                // fast (see POLISH_STEP_TURN).
                assert!(
                    (m - t).abs() < 1e-7,
                    "α {alpha}, sample {i}: {m} against {t}"
                );
                // Each foot is within one untaken Newton step of the true one.
                assert!(
                    (marched.feet[i] - traced.feet[i]).abs()
                        <= 2.0 * FOOT_STEP_TOLERANCE * seg.length(),
                    "sample {i}"
                );
                assert_eq!(marched.sides[i], traced.sides[i]);
            }
            assert_eq!(marched.feet[0], 0.0);
            assert_eq!(marched.feet[samples.len() - 1], seg.length());
        }
        // A sample that the march would reach only by going back along the segment is left to
        // the tracing: feet come out ordered, or not at all.
        let (seg, mut samples) = offset_spiral_samples(0..41);
        samples.swap(10, 30);
        assert!(marched(&seg, &samples).is_none());
        let d = deviation(&seg, &samples, 1e-3);
        assert!(d.max < 0.081, "{}", d.max);
    }

    #[test]
    fn feet_from_a_nearby_segment_are_the_traced_feet() {
        // A refinement trial: the segment moves a little; Newton from the old feet (rescaled)
        // must land on the feet that tracing finds.
        let (seg, samples) = offset_spiral_samples(0..41);
        let old = deviation(&seg, &samples, 0.01);
        let moved = LacSegment::new(
            Point::new(0.02, -0.01),
            0.203,
            50.1,
            Some(0.55),
            0.149,
            0.021,
        )
        .expect("segment");
        let seeds: Vec<f64> = old.feet.iter().map(|f| f * 50.1 / 50.0).collect();
        let near = deviation_near(&moved, &samples, &seeds).expect("settles");
        let traced = traced(&moved, &samples, 0.01);
        for i in 0..samples.len() {
            assert!(
                (near.distances[i] - traced.distances[i]).abs() < 1e-9,
                "sample {i}"
            );
            assert!((near.feet[i] - traced.feet[i]).abs() < 1e-6, "sample {i}");
            assert_eq!(near.sides[i], traced.sides[i]);
        }
        assert!((near.max - traced.max).abs() < 1e-9);
        // Seeds that do not match the samples are refused, not guessed.
        assert!(deviation_near(&moved, &samples, &seeds[1..]).is_none());
    }

    #[test]
    fn polished_distances_are_exact_foot_points() {
        // Samples offset along the exact normal of a spiral come back at exactly their offset.
        let (seg, samples) = offset_spiral_samples(1..40);
        let d = deviation(&seg, &samples, 0.01);
        for (i, (x, side)) in d.distances.iter().zip(&d.sides).enumerate() {
            let offset: f64 = if (i + 1) % 2 == 0 { 0.08 } else { -0.05 };
            assert!((x - offset.abs()).abs() < 1e-9, "sample {i}: {x}");
            assert_eq!(*side, offset.signum());
            assert!((d.feet[i] - 50.0 * (i + 1) as f64 / 40.0).abs() < 1e-7);
        }
    }

    #[test]
    fn a_sample_beyond_a_tightly_curling_end_has_its_foot_at_the_end() {
        // Curvature 2 at the end, the sample past the end and past its centre of curvature:
        // Newton's slope 1 + κ(P − q)·N is negative there, yet the end is the foot.
        let seg =
            LacSegment::new(Point::new(0.0, 0.0), 0.0, 6.0, Some(0.5), 0.1, 2.0).expect("segment");
        let (end, theta) = (seg.end(), seg.theta1());
        let (tangent, normal) = (
            Vec2::new(theta.cos(), theta.sin()),
            Vec2::new(-theta.sin(), theta.cos()),
        );
        let q = end + tangent * 0.2 + normal * 1.0;
        let d = deviation_near(&seg, &[q], &[seg.length()]).expect("settles at the end");
        assert_eq!(d.feet, vec![seg.length()]);
        assert!((d.distances[0] - q.distance(end)).abs() < 1e-12);
    }
}
