//! Every distance the chain is judged by: the resolution a fit works at ([`Resolution`]), and the
//! largest distance from a sample to the chain.

use super::record::{ChainInput, ChainSegment};
use crate::geom::Point;
use crate::lac::LacSegment;
use crate::lac::deviation::deviation;

/// Distances are seeded on a polyline whose chord error is this fraction of the tolerance, then
/// polished to exact foot points; the α search ranks candidates at ten times it.
const CHORD_ERROR_FRACTION: f64 = 1e-3;

/// Smallest radius of curvature a segment may have, as a fraction of the tolerance: a curve
/// bending within a hundredth of the tolerance turns inside a disc the samples cannot resolve
/// (a corner, not a curve), and such radii (seen: 4e-12 px at the drawable region's edge) also
/// take the segment's evaluation past the accuracy its record promises.
const MIN_RADIUS_FRACTION: f64 = 1e-2;
// Two radii, on purpose: [`MIN_RADIUS_FRACTION`] bounds what a segment may be at all (its
// evaluation's accuracy), [`MIN_RADIUS_TOLERANCES`] what a fitted curve should show (the
// samples' resolution); the G1 chain may pass through bends between the two on its way to
// the smooth chain, which then holds them as corners or softens them.

/// Smallest radius of curvature a smooth chain (and a softened end of the G1 chain) may bend
/// at, in tolerances: a bend tighter than half a
/// tolerance turns inside a disc the samples cannot tell from a corner; the G1 chain's needles
/// (κ = 75 /px on a three-sample segment at 0.5 px) were exactly that.
pub const MIN_RADIUS_TOLERANCES: f64 = 0.5;

/// The scale a chain is fitted and measured at, all of it from the tolerance: how far a sample
/// may lie from its segment, how finely distances are evaluated, and how tightly a segment may
/// bend before it turns inside a disc the samples cannot resolve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Resolution {
    /// Largest distance from a sample to the chain.
    pub tolerance: f64,
    /// Chord error of the distance evaluations ([`CHORD_ERROR_FRACTION`] of the tolerance).
    pub chord_error: f64,
    /// Largest curvature a segment may have (a radius of [`MIN_RADIUS_FRACTION`] of the
    /// tolerance).
    pub max_curvature: f64,
}

impl Resolution {
    /// The resolution of `tolerance`.
    pub(crate) fn new(tolerance: f64) -> Self {
        Resolution {
            tolerance,
            chord_error: CHORD_ERROR_FRACTION * tolerance,
            max_curvature: 1.0 / (MIN_RADIUS_FRACTION * tolerance),
        }
    }
}

/// The largest distance from a point to its own segment ([`own_deviation`]), each
/// segment's own points `lists` ([`own_points`]) measured afresh: for a chain assembled from
/// parts or edited after its fit, whose recorded figures no longer hold.
pub(crate) fn measured_deviation(
    input: &ChainInput,
    segments: &[ChainSegment],
    lists: &[Vec<usize>],
    chord_error: f64,
) -> f64 {
    let own: Vec<Vec<f64>> = segments
        .iter()
        .zip(lists)
        .map(|(s, list)| {
            let points: Vec<Point> = list.iter().map(|&i| input.points[i]).collect();
            deviation(&s.segment, &points, chord_error).distances
        })
        .collect();
    let curves: Vec<LacSegment> = segments.iter().map(|s| s.segment).collect();
    own_deviation(input.points, &curves, lists, &own, chord_error)
}

/// The distance from `q` to `segment` found from its trace (a polyline through its points within
/// the chord error of it, [`crate::lac::deviation::trace`], computed once per segment by the
/// caller): the global distance to the segment, where a foot-point search may settle on a local
/// minimum.
fn traced_distance(segment: &LacSegment, trace: &[(f64, Point)], q: Point) -> f64 {
    let mut best = (f64::INFINITY, 0.0);
    let mut previous: Option<(Point, f64)> = None;
    for &(sb, b) in trace {
        let (a, sa) = previous.unwrap_or((b, sb));
        let (d, f) = crate::geom::nearest_on_segment(q, a, b);
        if d < best.0 {
            best = (d, sa + f * (sb - sa));
        }
        previous = Some((b, sb));
    }
    // The trace lies within the chord error of the curve, so its distance can fall short of the
    // curve's by that much: the foot is found on the curve from the trace's nearest point (the
    // curve's point there where that search does not settle), a distance to a point of the
    // curve, never below the true one.
    let at = best.1;
    crate::lac::deviation::deviation_near(segment, &[q], &[at])
        .map_or_else(|| q.distance(segment.point(at)), |d| d.max)
}

/// The distance from `q` to `segment` measured afresh: the nearer of a local foot (Newton from
/// the segment's start) and the foot found from the segment's trace, made into `trace` the first
/// time it is asked for (a segment turning more than half a turn can hold a far local foot).
pub(crate) fn distance_on(
    segment: &LacSegment,
    trace: &mut Option<Vec<(f64, Point)>>,
    q: Point,
    chord_error: f64,
) -> f64 {
    let local = deviation(segment, &[q], chord_error).max;
    let trace = trace.get_or_insert_with(|| crate::lac::deviation::trace(segment, chord_error));
    local.min(traced_distance(segment, trace, q))
}

/// The largest distance from a sample to its own segment, given each segment's samples
/// (`samples[k]`, indices into `points`) and their distances to it as the fit found them
/// (`own`): the honest measure of a chain. A sample is measured against the segment that
/// represents it (or a segment next to it: a sample at a joint lies where both meet, and which
/// of the two holds it is the tiling's choice), never against another part of the chain that
/// passes near it: where a stroke comes back near itself (a loop, an overshoot past a circle's
/// start, a line gone over twice) the nearest part of the chain may be another pass, and a
/// segment that left its own samples would count as fitted.
///
/// A distance the fit found is to a local foot point (Newton from a seed along the segment),
/// which on a tightly curling segment need not be the nearest point of that segment (seen: 2.16
/// px from a sample lying on the segment's end): the samples are taken farthest first, each
/// measured afresh on its own segment (its trace, then the exact foot), until the next one's
/// found distance cannot beat the largest measured: usually after one or two.
pub(crate) fn own_deviation(
    points: &[Point],
    segments: &[LacSegment],
    samples: &[Vec<usize>],
    own: &[Vec<f64>],
    chord_error: f64,
) -> f64 {
    let mut order: Vec<(f64, usize, usize)> = Vec::new();
    for (k, (list, distances)) in samples.iter().zip(own).enumerate() {
        for (&i, &d) in list.iter().zip(distances) {
            order.push((d, i, k));
        }
    }
    order.sort_by(|x, y| y.0.total_cmp(&x.0));
    let mut worst: f64 = 0.0;
    // Each segment's trace, made the first time a sample asks for it.
    let mut traces: Vec<Option<Vec<(f64, Point)>>> = vec![None; segments.len()];
    for &(d, i, k) in &order {
        if d <= worst {
            break;
        }
        let q = points[i];
        let mut nearest = d;
        for m in k.saturating_sub(1)..=(k + 1).min(segments.len() - 1) {
            nearest = nearest.min(distance_on(&segments[m], &mut traces[m], q, chord_error));
        }
        worst = worst.max(nearest);
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Vec2;

    /// Every scale of a resolution is proportional to its tolerance, and the curvature limit
    /// inversely: a stroke drawn twice the size is fitted at twice the tolerance to the same
    /// chain, scaled.
    #[test]
    fn a_resolution_scales_with_its_tolerance() {
        let (a, b) = (Resolution::new(0.5), Resolution::new(2.0));
        assert!((b.chord_error / a.chord_error - 4.0).abs() <= 1e-12);
        assert!((a.max_curvature / b.max_curvature - 4.0).abs() <= 1e-12);
        assert!(a.chord_error < a.tolerance);
        // The hard curvature limit lies beyond what a smooth chain may show.
        assert!(a.max_curvature > 1.0 / (MIN_RADIUS_TOLERANCES * a.tolerance));
    }

    /// The honest measure: a sample handed to a segment that passes far from it counts at that
    /// distance, though another segment of the chain (the other arm of a hairpin) passes near
    /// it; and the measure is each sample's true distance to its own segment, found afresh
    /// where the fit's distance (here inflated on purpose) overstates it.
    #[test]
    fn a_sample_counts_at_its_distance_to_its_own_segment() {
        let chord_error = 1e-4;
        // A log-aesthetic segment and a line back along beside it (a hairpin).
        let curve = LacSegment::new(Point::new(0.0, 0.0), 0.0, 40.0, Some(0.5), 0.02, 0.05)
            .expect("a valid segment");
        let back = curve.end();
        let line = LacSegment::new(back, std::f64::consts::PI, 30.0, None, 0.0, 0.0)
            .expect("a valid line");
        // The line first, a segment far from both between them, the curve last: the curve is
        // not the line's neighbour in the chain, so it does not stand in for it.
        let far = LacSegment::new(Point::new(1000.0, 1000.0), 0.0, 10.0, None, 0.0, 0.0)
            .expect("a valid line");
        let segments = [line, far, curve];
        let points: Vec<Point> = (0..12)
            .map(|i| {
                let s = 3.0 * i as f64 + 1.0;
                curve.point(s) + Vec2::new(0.1 * (i as f64).sin(), 0.2 * (i as f64 * 0.7).cos())
            })
            .chain((0..8).map(|i| line.point(3.0 * i as f64 + 2.0) + Vec2::new(0.0, 0.3)))
            .collect();
        // The last curve sample handed to the line, which passes far from it.
        let samples = vec![
            (11..20).collect::<Vec<usize>>(),
            Vec::new(),
            (0..11).collect(),
        ];
        let own: Vec<Vec<f64>> = samples
            .iter()
            .zip(&segments)
            .map(|(list, seg)| {
                list.iter()
                    .map(|&i| deviation(seg, &[points[i]], chord_error).max)
                    .collect()
            })
            .collect();
        let largest_own = own.iter().flatten().fold(0.0_f64, |m, &d| m.max(d));
        let nearest = points
            .iter()
            .map(|&q| {
                segments
                    .iter()
                    .map(|seg| deviation(seg, &[q], chord_error).max)
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0_f64, f64::max);
        assert!(
            largest_own > 2.0 * nearest,
            "the handed sample is far from its own segment, near the other"
        );
        let honest = own_deviation(&points, &segments, &samples, &own, chord_error);
        assert!(
            (honest - largest_own).abs() <= 1e-9,
            "{honest} against {largest_own}"
        );
        // Distances the fit overstated are measured afresh on their own segment.
        let inflated: Vec<Vec<f64>> = own
            .iter()
            .map(|d| d.iter().map(|x| x + 5.0).collect())
            .collect();
        let again = own_deviation(&points, &segments, &samples, &inflated, chord_error);
        assert!(
            (again - largest_own).abs() <= 1e-9,
            "{again} against {largest_own}"
        );
    }
}
