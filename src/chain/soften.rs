//! Ends that curl tighter than their samples resolve, turned towards the chord: the tries and
//! the fits both the G1 assembly and the smooth fit take their softened ends from.

use crate::geom::{Point, Vec2};
use crate::lac::{SpanFit, SpanFitOptions, fit_span, within};

/// Steps in which the G1 chain's `soften_ends` turns an end tangent towards the chord (then towards
/// the arc's tangent, and for a piece of one segment both ends together): the first that removes
/// the tight curl is kept, so the tangent moves no farther than it must, to a quarter of the
/// turn. On the nine recorded fixture files in g2, segments bending tighter than half a
/// tolerance: 14 turning towards the chord alone, 11 with all three (in g1: 27, 24). Eight steps
/// give the same 11 (23 in g1) for 8 % more time in the painting's G1 chains, where each
/// failing try is an α search.
pub(crate) const SOFTEN_STEPS: usize = 4;

/// The (start, end) tangent angles to try, in order, for a segment from `a` to `b` (each a point
/// and its tangent angle) whose start (`at_start`) or end curls tighter than its samples resolve
/// (see the G1 chain's `soften_ends`): that end turned towards the chord in [`SOFTEN_STEPS`] steps,
/// then towards the tangent of the circular arc through both ends that keeps the other end's
/// (its mirror image in the chord); and, where both ends are free (`both`), both towards the
/// chord together, a line at the last step. Towards the chord first: a segment whose other
/// tangent lies off the chord cannot leave along it (a log-aesthetic segment has no inflection),
/// and on a near line only the arc's tangent gives a segment at all (a painting stroke's start
/// hook, κ = 44.7 /px at a tolerance of 1 px, turned 3 rad in its first 0.02 px).
pub(crate) fn soften_tries(
    (a, a_angle): (Point, f64),
    (b, b_angle): (Point, f64),
    at_start: bool,
    both: bool,
) -> Vec<(f64, f64)> {
    let chord = b - a;
    let chord_angle = chord.y.atan2(chord.x);
    let towards = |angle: f64| crate::geom::wrap_angle(chord_angle - angle);
    let (from, other) = if at_start {
        (a_angle, b_angle)
    } else {
        (b_angle, a_angle)
    };
    let arc = chord_angle + towards(other);
    let fraction = |step: usize| step as f64 / SOFTEN_STEPS as f64;
    let mut tries: Vec<(f64, f64)> = [chord_angle, arc]
        .iter()
        .map(|&target| crate::geom::wrap_angle(target - from))
        .flat_map(|turn| {
            (1..=SOFTEN_STEPS).map(move |step| {
                let angle = from + turn * fraction(step);
                if at_start {
                    (angle, b_angle)
                } else {
                    (a_angle, angle)
                }
            })
        })
        .collect();
    if both {
        let (turn_a, turn_b) = (towards(a_angle), towards(b_angle));
        tries.extend((1..=SOFTEN_STEPS).map(|step| {
            let f = fraction(step);
            (a_angle + turn_a * f, b_angle + turn_b * f)
        }));
    }
    tries
}

/// The turns of [`soften_tries`] whose segment holds `points` (ordered from `a` to `b`) within
/// `tolerance` and bends no tighter than `options.max_curvature`, in the tries' order, each
/// with its fit: a lazy sequence, so a caller taking the first that suits it fits no further.
pub(crate) fn soften_fits<'p>(
    (a, a_angle): (Point, f64),
    (b, b_angle): (Point, f64),
    at_start: bool,
    both: bool,
    points: &'p [Point],
    options: SpanFitOptions,
    tolerance: f64,
) -> impl Iterator<Item = ((f64, f64), SpanFit)> + 'p {
    let tangent = |angle: f64| Vec2::new(angle.cos(), angle.sin());
    soften_tries((a, a_angle), (b, b_angle), at_start, both)
        .into_iter()
        .filter_map(move |(start_angle, end_angle)| {
            let fit = fit_span(
                a,
                tangent(start_angle),
                b,
                tangent(end_angle),
                points,
                &options,
            )
            .ok()?;
            (fit.deviation.max <= tolerance && within(&fit.segment, options.max_curvature))
                .then_some(((start_angle, end_angle), fit))
        })
}
