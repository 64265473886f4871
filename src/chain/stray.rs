//! Segments that leave their samples: a loop between two neighbouring samples.
//!
//! The tolerance binds the chain at its samples only, so a segment may run a loop between two
//! neighbouring samples and still have every sample within the tolerance (seen: two segments of
//! 465 and 396 px over one sample of a planted chain drawn on a pixel grid, after the smooth
//! fit's cut rounds; two half circles 13 mm across between samples 0.45 mm apart after a
//! repair's biarc). A drawn curve between samples is about as long as the polyline through
//! them: over the recorded fixtures, in every continuity, no segment is longer than 1.005 times
//! the polyline through its samples and the samples on either side of it, plus a tolerance.

use super::record::{Chain, ChainInput};

/// Longest a segment may be, as a multiple of the length of the polyline through its samples
/// and the sample on either side of it, plus the tolerance (the most a curve within the
/// tolerance of two samples can add to their distance without turning back): twice that is a
/// loop, far beyond any fitted curve (1.005 at most over the recorded fixtures).
pub const LOOP_LENGTH_FACTOR: f64 = 2.0;

/// Whether some segment of `chain` is a loop: longer than [`LOOP_LENGTH_FACTOR`] times the
/// polyline through its samples and their neighbours, plus `tolerance`.
pub(crate) fn loops(input: &ChainInput<'_>, chain: &Chain, tolerance: f64) -> bool {
    let points = input.points;
    if points.len() < 2 {
        return false;
    }
    let last = points.len() - 1;
    chain.segments.iter().any(|s| {
        let (i, j) = s.samples;
        // Positions among the distinct points: the first at or after sample i, the last at or
        // before sample j (indices are increasing).
        let first = input.indices.partition_point(|&x| x < i);
        let end = input.indices.partition_point(|&x| x <= j);
        // From the sample before the segment's first to the one after its last.
        let lo = first.saturating_sub(1);
        let hi = end.min(last).max(lo);
        let reach: f64 = points[lo..=hi]
            .windows(2)
            .map(|w| w[0].distance(w[1]))
            .sum();
        s.segment.length() > LOOP_LENGTH_FACTOR * (reach + tolerance)
    })
}
