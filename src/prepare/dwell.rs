//! Dwell: the samples a pen piles up, almost without moving, where it lands and before it lifts.
//!
//! Tremor of a resting pen scatters those samples by up to a few tenths of a millimetre; the
//! tolerance is a distance to every sample, so a curve held to them must loop into the cloud,
//! which wrecks the end tangent. A dwell is the longest run of samples at an end of the stroke
//! that stays within [`DwellOptions::radius`] of its own centroid, holds at least
//! [`DwellOptions::min_samples`] samples, and wanders: its path is more than
//! [`DWELL_PATH_RATIO`] times its diameter. The last condition tells a resting, trembling pen
//! (back and forth in a small disc) from a pen that merely moves slowly or is sampled densely
//! (its path is about as long as the stretch it covers). At the end, the run's first sample (where the pen
//! arrived) is kept as the stroke's end and the rest lie outside the curve's sample range; at
//! the start, symmetrically, the run's last sample (where the pen set off) is kept.

use crate::geom::{Point, Vec2};

/// Options for dwell trimming.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DwellOptions {
    /// Radius of a dwell cloud, in the stroke's units. Default (set by the pipeline) 3 × the
    /// fitting tolerance: tremor within one tolerance harms nothing, and a slow but real end of a
    /// stroke moves further than three tolerances over the last few samples.
    pub radius: f64,
    /// Fewest samples in a dwell. Default 5: at 100–200 Hz that is 25–50 ms of resting pen,
    /// while a stroke that merely slows down rarely puts five samples within three tolerances.
    pub min_samples: usize,
}

impl DwellOptions {
    /// Defaults for a fitting tolerance.
    pub const fn for_tolerance(tolerance: f64) -> Self {
        DwellOptions {
            radius: 3.0 * tolerance,
            min_samples: 5,
        }
    }
}

/// A run is a dwell only if its path is longer than this multiple of its diameter. Tremor of a
/// resting pen (σ ≈ 0.03 mm at 200 Hz) walks a path many times its extent; a straight or gently
/// curving approach, however slow or densely sampled, walks a path about equal to it (the chord
/// of a stretch turning by a right angle is still 0.9 of its length).
pub const DWELL_PATH_RATIO: f64 = 3.0;

/// Whether a run of points wanders like a resting pen (see [`DWELL_PATH_RATIO`]).
fn wanders(run: &[Point]) -> bool {
    let path: f64 = run.windows(2).map(|w| w[0].distance(w[1])).sum();
    let mut diameter: f64 = 0.0;
    for (i, a) in run.iter().enumerate() {
        for b in &run[i + 1..] {
            diameter = diameter.max(a.distance(*b));
        }
    }
    path > DWELL_PATH_RATIO * diameter
}

/// The inclusive range of `points` left after trimming the dwell at each end.
pub fn trim_dwell(points: &[Point], options: &DwellOptions) -> (usize, usize) {
    let n = points.len();
    if n == 0 {
        return (0, 0);
    }
    let end_run = run_length(points.iter().rev(), options.radius);
    let last = if end_run >= options.min_samples && wanders(&points[n - end_run..]) {
        n - end_run
    } else {
        n - 1
    };
    let start_run = run_length(points[..=last].iter(), options.radius);
    let first = if start_run >= options.min_samples && wanders(&points[..start_run]) {
        start_run - 1
    } else {
        0
    };
    // Keep at least two points: a stroke that is all dwell keeps its extent.
    if last <= first {
        (0, n - 1)
    } else {
        (first, last)
    }
}

/// How many leading points stay within `radius` of the running centroid of the run.
fn run_length<'a>(points: impl Iterator<Item = &'a Point>, radius: f64) -> usize {
    let mut sum = Vec2::ZERO;
    let mut count = 0usize;
    for p in points {
        if count > 0 {
            let centroid = (sum / count as f64).to_point();
            if centroid.distance(*p) > radius {
                break;
            }
        }
        sum += p.to_vec2();
        count += 1;
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cloud_at_the_end_is_trimmed_to_the_arrival_sample() {
        let mut pts: Vec<Point> = (0..50).map(|i| Point::new(i as f64, 0.0)).collect();
        let arrival = pts.len() - 1;
        // Eight samples jittering within 0.2 of the last point.
        for k in 0..8 {
            let a = k as f64 * 2.3;
            pts.push(Point::new(49.0 + 0.15 * a.cos(), 0.15 * a.sin()));
        }
        let (first, last) = trim_dwell(&pts, &DwellOptions::for_tolerance(0.1));
        assert_eq!(first, 0);
        assert_eq!(last, arrival);
    }

    #[test]
    fn a_cloud_at_the_start_is_trimmed_to_the_departure_sample() {
        let mut pts: Vec<Point> = (0..6)
            .map(|k| Point::new(0.1 * (2.3 * k as f64).sin(), 0.1 * (2.3 * k as f64).cos()))
            .collect();
        let departure = pts.len(); // (0,0) follows the cloud and is still within it
        pts.extend((0..50).map(|i| Point::new(i as f64, 0.0)));
        let (first, last) = trim_dwell(&pts, &DwellOptions::for_tolerance(0.1));
        assert_eq!(first, departure);
        assert_eq!(last, pts.len() - 1);
    }

    #[test]
    fn a_stroke_that_slows_down_is_not_trimmed() {
        // Spacing shrinks geometrically but the last five samples span more than 3 tolerances.
        let mut x = 0.0;
        let pts: Vec<Point> = (0..40)
            .map(|i| {
                x += 2.0 * 0.95f64.powi(i);
                Point::new(x, 0.0)
            })
            .collect();
        assert_eq!(trim_dwell(&pts, &DwellOptions::for_tolerance(0.1)), (0, 39));
    }

    #[test]
    fn dense_sampling_is_not_dwell() {
        // 0.01 mm apart along a line: 30 samples within 0.3 mm, but walking straight.
        let pts: Vec<Point> = (0..400).map(|i| Point::new(0.01 * i as f64, 0.0)).collect();
        assert_eq!(
            trim_dwell(&pts, &DwellOptions::for_tolerance(0.1)),
            (0, 399)
        );
    }

    #[test]
    fn all_dwell_keeps_everything() {
        let pts: Vec<Point> = (0..10).map(|k| Point::new(0.01 * k as f64, 0.0)).collect();
        assert_eq!(trim_dwell(&pts, &DwellOptions::for_tolerance(0.1)), (0, 9));
    }
}
