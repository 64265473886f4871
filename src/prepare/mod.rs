//! Preparing a stroke for fitting: merge duplicate samples, cut it at corners, drop the pen's
//! landing and lifting hooks.
//!
//! In: a validated [`crate::stroke::Stroke`]. Out: [`Piece`]s, each a run of distinct points to be
//! fitted by one B-spline, with the inclusive range of original sample indices it represents, and
//! how each end came about ([`PieceEnd`]). Samples in a dropped hook belong to no piece.
//!
//! Dwell (samples piling up at almost zero speed) needs no cutting here: the fit weighs each
//! sample by the arc length it covers ([`crate::bspline::Weighting::ArcLength`]), so a dwell's
//! samples weigh almost nothing and do not bias the end tangents, yet every one of them is still
//! held to the tolerance.

mod corners;
mod dedup;

pub use corners::{CornerOptions, find_corners, turning_angles};
pub use dedup::{Distinct, merge_duplicates};

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
pub fn prepare(stroke: &Stroke, options: &CornerOptions) -> Vec<Piece> {
    let distinct = merge_duplicates(stroke);
    let n = distinct.points.len();
    if n == 0 {
        return Vec::new();
    }
    let cuts = find_corners(&distinct.points, options);
    let mut start = 0;
    let mut start_kind = PieceEnd::StrokeEnd;
    if let Some(h) = cuts.start_hook {
        start = h;
        start_kind = PieceEnd::Hook;
    }
    let mut last = n - 1;
    let mut last_kind = PieceEnd::StrokeEnd;
    if let Some(h) = cuts.end_hook {
        last = h;
        last_kind = PieceEnd::Hook;
    }
    let mut bounds: Vec<(usize, PieceEnd)> = vec![(start, start_kind)];
    bounds.extend(
        cuts.corners
            .iter()
            .filter(|&&c| c > start && c < last)
            .map(|&c| (c, PieceEnd::Corner)),
    );
    bounds.push((last, last_kind));
    bounds
        .windows(2)
        .map(|w| {
            let ((a, ka), (b, kb)) = (w[0], w[1]);
            let first_sample = distinct.first[a];
            // A piece ending at a corner shares the corner sample with the next piece; the last
            // piece also owns the duplicates merged into its final point.
            let last_sample = if kb == PieceEnd::Corner {
                distinct.first[b]
            } else {
                distinct.last[b]
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
