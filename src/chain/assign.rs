//! Which samples each segment represents: the tiling of a piece's sample range into the
//! segments' inclusive ranges, and each segment's own points within it.

use super::record::{ChainInput, ChainSegment};

/// Each segment's own points (indices into `input.points`): those whose original index lies in
/// its sample range, a point on a range boundary given to the first segment that holds it (a
/// segment without samples repeats its neighbour's index); none for a segment without samples.
pub(crate) fn own_points(input: &ChainInput, segments: &[ChainSegment]) -> Vec<Vec<usize>> {
    let mut taken = vec![false; input.points.len()];
    segments
        .iter()
        .map(|s| {
            if s.params.is_none() {
                return Vec::new();
            }
            (0..input.points.len())
                .filter(|&i| (s.samples.0..=s.samples.1).contains(&input.indices[i]))
                .filter(|&i| !std::mem::replace(&mut taken[i], true))
                .collect()
        })
        .collect()
}

/// The original sample range of the points `list` (non-empty, in stroke order).
pub(crate) fn sample_range(indices: &[usize], list: &[usize]) -> (usize, usize) {
    let first = list.first().map_or(0, |&i| indices[i]);
    let last = list.last().map_or(first, |&i| indices[i]);
    (first, last)
}

/// The B-spline parameter interval spanned by the points `list` (indices into `params`, each
/// point's B-spline parameter); `None` when `list` is empty.
pub(crate) fn param_interval(params: &[f64], list: &[usize]) -> Option<(f64, f64)> {
    list.iter()
        .map(|&i| params[i])
        .fold(None, |acc: Option<(f64, f64)>, u| {
            Some(acc.map_or((u, u), |(lo, hi)| (lo.min(u), hi.max(u))))
        })
}

/// `segments`' sample ranges tiled afresh over `piece` ([`tile_ranges`] from each one's first
/// sample, a segment without samples, `params: None`, holding none): after segments were
/// replaced or inserted.
pub(crate) fn retile(segments: &mut [ChainSegment], piece: (usize, usize)) {
    let starts: Vec<Option<usize>> = segments
        .iter()
        .map(|s| s.params.map(|_| s.samples.0))
        .collect();
    for (s, range) in segments.iter_mut().zip(tile_ranges(&starts, piece)) {
        s.samples = range;
    }
}

/// Each segment's inclusive range of original sample indices from its first one (`None`: it
/// holds none): the ranges tile the piece `piece`, a segment ending where the next begins; a
/// segment without samples gets the single index where it sits.
pub(crate) fn tile_ranges(starts: &[Option<usize>], piece: (usize, usize)) -> Vec<(usize, usize)> {
    let (piece_first, piece_last) = piece;
    let mut previous_last: Option<usize> = None;
    let mut ranges = Vec::with_capacity(starts.len());
    for k in 0..starts.len() {
        let range = if starts[k].is_some() {
            let first = previous_last.map_or(piece_first, |l| l + 1);
            let last = starts[k + 1..]
                .iter()
                .find_map(|s| *s)
                .map_or(piece_last, |next| next.saturating_sub(1))
                .max(first);
            previous_last = Some(last);
            (first, last)
        } else {
            let at = previous_last.unwrap_or(piece_first);
            (at, at)
        };
        ranges.push(range);
    }
    ranges
}
