//! Preparing a stroke for fitting: merge duplicate samples, trim the pen's dwell at either end,
//! drop its landing and lifting hooks, cut the stroke at corners.
//!
//! In: a validated [`crate::stroke::Stroke`]. Out: [`Piece`]s, each a run of distinct points to be
//! fitted by one B-spline, with the inclusive range of original sample indices it represents, and
//! how each end came about ([`PieceEnd`]). Samples in a dropped hook belong to no piece.
//!
//! Dwell at the ends (samples piling up at almost zero speed, scattered by tremor) is trimmed
//! ([`dwell`]): a curve held to the tolerance of every such sample would have to loop into the
//! cloud. Elsewhere the fit weighs each sample by the arc length it covers
//! ([`crate::bspline::Weighting::ArcLength`]), so a slow stretch's many samples do not outweigh a
//! fast one's few.

mod corners;
mod dedup;
pub mod dwell;

pub use corners::{CornerOptions, HOOK_WINDOWS, find_corners, turning_angles};
pub use dedup::{Distinct, merge_duplicates};
pub use dwell::{DwellOptions, trim_dwell};

use crate::geom::Point;
use crate::stroke::Stroke;

/// How a piece's end arose.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PieceEnd {
    /// The stroke's own start or end.
    StrokeEnd,
    /// A corner (G0 joint with the neighbouring piece).
    Corner,
    /// A hook was dropped beyond this end.
    Hook,
    /// Dwell samples were trimmed beyond this end.
    Dwell,
    /// Where a closed stroke's curve meets itself ([`crate::closure`]): the first piece's
    /// start and the last piece's end.
    Seam,
}

/// A run of distinct points between corners.
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    /// Distinct positions, in stroke order.
    pub points: Vec<Point>,
    /// For each point, the original sample index it came from (the first of a merged run).
    pub indices: Vec<usize>,
    /// Inclusive range of original sample indices the piece represents.
    pub samples: (usize, usize),
    /// How the piece starts.
    pub start: PieceEnd,
    /// How the piece ends.
    pub end: PieceEnd,
}

/// Splits a stroke into pieces (see the module doc).
pub fn prepare(stroke: &Stroke, options: &CornerOptions, dwell: &DwellOptions) -> Vec<Piece> {
    let distinct = merge_duplicates(stroke);
    let n = distinct.points.len();
    if n == 0 {
        return Vec::new();
    }
    let (lo, hi) = trim_dwell(&distinct.points, dwell);
    let cuts = find_corners(&distinct.points[lo..=hi], options);
    let mut start = lo;
    let mut start_kind = if lo > 0 {
        PieceEnd::Dwell
    } else {
        PieceEnd::StrokeEnd
    };
    if let Some(h) = cuts.start_hook {
        start = lo + h;
        start_kind = PieceEnd::Hook;
    }
    let mut last = hi;
    let mut last_kind = if hi < n - 1 {
        PieceEnd::Dwell
    } else {
        PieceEnd::StrokeEnd
    };
    if let Some(h) = cuts.end_hook {
        last = lo + h;
        last_kind = PieceEnd::Hook;
    }
    let mut bounds: Vec<(usize, PieceEnd)> = vec![(start, start_kind)];
    bounds.extend(
        cuts.corners
            .iter()
            .map(|&c| lo + c)
            .filter(|&c| c > start && c < last)
            .map(|c| (c, PieceEnd::Corner)),
    );
    bounds.push((last, last_kind));
    bounds
        .windows(2)
        .map(|w| {
            let ((a, ka), (b, kb)) = (w[0], w[1]);
            let first_sample = distinct.first[a];
            // A piece ending at a corner shares the corner sample with the next piece, one
            // ending where samples were dropped ends at its last kept sample; the stroke's own
            // last piece also owns the duplicates merged into its final point.
            let last_sample = match kb {
                PieceEnd::StrokeEnd => distinct.last[b],
                PieceEnd::Corner | PieceEnd::Hook | PieceEnd::Dwell | PieceEnd::Seam => {
                    distinct.first[b]
                }
            };
            Piece {
                points: distinct.points[a..=b].to_vec(),
                indices: distinct.first[a..=b].to_vec(),
                samples: (first_sample, last_sample),
                start: ka,
                end: kb,
            }
        })
        .collect()
}
