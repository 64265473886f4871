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

#[cfg(test)]
mod tests {
    use super::*;

    /// The ranges tile the piece: the first starts at the piece's first sample, each next one
    /// right after the one before, the last ends at the piece's last sample; a segment without
    /// samples sits on a single index where the one before it ended.
    #[test]
    fn ranges_tile_the_piece() {
        let piece = (10, 40);
        let starts = [Some(10), Some(17), None, Some(25), Some(26), None];
        let ranges = tile_ranges(&starts, piece);
        assert_eq!(
            ranges,
            vec![(10, 16), (17, 24), (24, 24), (25, 25), (26, 40), (40, 40)]
        );
        // Contiguous over the segments that hold samples, covering the piece exactly.
        let held: Vec<(usize, usize)> = ranges
            .iter()
            .zip(&starts)
            .filter(|(_, s)| s.is_some())
            .map(|(r, _)| *r)
            .collect();
        assert_eq!(held.first().map(|r| r.0), Some(piece.0));
        assert_eq!(held.last().map(|r| r.1), Some(piece.1));
        assert!(held.windows(2).all(|w| w[1].0 == w[0].1 + 1));
    }

    /// A first segment that starts after the piece's first sample still begins the tiling at
    /// the piece's start (the samples before it are its own).
    #[test]
    fn the_first_range_starts_at_the_piece() {
        assert_eq!(
            tile_ranges(&[Some(5), Some(9)], (0, 12)),
            vec![(0, 8), (9, 12)]
        );
    }

    /// The sample range and parameter interval of a list of points.
    #[test]
    fn range_and_interval_of_a_list() {
        let indices = [3, 4, 7, 8, 11];
        assert_eq!(sample_range(&indices, &[1, 2, 3]), (4, 8));
        let params = [0.0, 0.5, 0.25, 1.0, 2.0];
        assert_eq!(param_interval(&params, &[1, 2, 3]), Some((0.25, 1.0)));
        assert_eq!(param_interval(&params, &[]), None);
    }
}
