//! Corners and hooks from the turning angle over a short arc-length window.
//!
//! At sample `i` (arc length `sᵢ`), let `B` be the stroke's point at arc length `sᵢ − w` and `F`
//! the one at `sᵢ + w` (linear interpolation along the polyline, truncated at the stroke's ends).
//! The turning angle is the angle between `Pᵢ − B` and `F − Pᵢ`. A smooth curve of radius `r`
//! turns by about `2w/r` over the two windows, so a threshold `φ` flags radii below `2w/φ`; noise
//! of amplitude σ moves the angle by about `σ/w`, so a window of several tolerances keeps noise
//! well below the threshold.

use crate::geom::{Point, cumulative_lengths};

/// Options for corner and hook detection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CornerOptions {
    /// Turning angle (degrees) above which a sample is a corner. Default 70°: a deliberate change
    /// of direction; with the default window it flags turns tighter than a radius of about
    /// 13 tolerances.
    pub corner_angle: f64,
    /// Arc-length window `w` on each side, in the stroke's units. Default: 8 × the fitting
    /// tolerance (set by the pipeline): noise of half a tolerance moves the angle by ~4°.
    pub window: f64,
    /// Whether to drop hooks. Default true.
    pub drop_hooks: bool,
    /// Fraction of the stroke's arc length at each end where a sharp turn is a hook, not a
    /// corner. Default 0.08.
    pub hook_fraction: f64,
    /// Longest end part dropped as a hook, in the stroke's units: the end zone is the shorter of
    /// this and [`CornerOptions::hook_fraction`] of the stroke. Default [`HOOK_WINDOWS`] ×
    /// [`CornerOptions::window`] (40 tolerances: 4 mm at the default 0.1 mm). A pen's landing
    /// or lifting flick is a few millimetres at most; a sharp turn farther from the end starts
    /// or ends a leg the designer drew, which is cut there as a corner and kept.
    pub hook_length: f64,
    /// Turning angle (degrees) above which a turn in the end zone is a hook. Default 45°: hooks
    /// are small, so their turning is spread over a window and measures less than a corner's.
    pub hook_angle: f64,
}

impl CornerOptions {
    /// Defaults for a fitting tolerance `tolerance`.
    pub const fn for_tolerance(tolerance: f64) -> Self {
        CornerOptions {
            corner_angle: 70.0,
            window: 8.0 * tolerance,
            drop_hooks: true,
            hook_fraction: 0.08,
            hook_angle: 45.0,
            hook_length: HOOK_WINDOWS * 8.0 * tolerance,
        }
    }

    /// Sets [`CornerOptions::corner_angle`] (degrees).
    pub const fn with_corner_angle(mut self, degrees: f64) -> Self {
        self.corner_angle = degrees;
        self
    }

    /// Sets [`CornerOptions::drop_hooks`].
    pub const fn with_drop_hooks(mut self, drop: bool) -> Self {
        self.drop_hooks = drop;
        self
    }

    /// Sets [`CornerOptions::window`], and [`CornerOptions::hook_length`] to [`HOOK_WINDOWS`]
    /// windows.
    pub const fn with_window(mut self, window: f64) -> Self {
        self.window = window;
        self.hook_length = HOOK_WINDOWS * window;
        self
    }
}

/// Default [`CornerOptions::hook_length`] in turning windows: 4 mm at the default 0.1 mm
/// tolerance (20 px at 0.5 px, about 5 mm on a desktop screen). A landing or lifting flick is
/// usually under 2 mm; a fast lift drags it further, and the google-ink spring ends in one of
/// 18 px. The legs the 8 % zone alone took for hooks on the fixtures were 50 px and longer.
pub const HOOK_WINDOWS: f64 = 5.0;

/// Where to cut a stroke.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Cuts {
    /// Indices (into the distinct points) of corners, increasing.
    pub corners: Vec<usize>,
    /// Index where the stroke starts after a dropped landing hook.
    pub start_hook: Option<usize>,
    /// Index where the stroke ends before a dropped lifting hook.
    pub end_hook: Option<usize>,
}

/// Two turning angles closer than this (radians) are a tie, and the earlier sample wins: windows
/// of neighbouring samples on a sparse polyline can measure the same vertex, and the pick must
/// not depend on rounding (a rotated copy of the stroke must cut at the same sample).
const ANGLE_TIE: f64 = 1e-9;

/// A truncated window shorter than this fraction of `w` gives no angle: one noisy sample would
/// decide it.
const MIN_WINDOW_FRACTION: f64 = 0.25;

/// A vertex of the polyline turning by more than this (radians) is a fold: the pen went back
/// over its own path (an exact reversal on a whole-pixel grid turns by exactly π). No regular
/// curve follows a fold: the least-squares B-spline through one has a cusp (its speed vanishes)
/// and nothing after it can be fitted. The windowed angle sees a reversal too, but saturates at
/// π on every sample within half a window of it, so a fold is found at its vertex. 170°: a turn
/// this sharp between two samples is a reversal whatever the sampling; a smooth curve sampled
/// at 3 or more points per right angle turns by at most 30° at a vertex.
const FOLD_ANGLE: f64 = 170.0 * std::f64::consts::PI / 180.0;

/// A fold is only a corner where the pen went back by more than this fraction of the window
/// (both legs at the vertex, up to the next vertex that is not a near-duplicate): the window is
/// 8 tolerances, so 1/4 is two tolerances. Two samples within the tolerance of a smooth curve
/// can lie two tolerances apart across it, so a shorter back-step may be noise or quantisation
/// that a smooth curve absorbs (real strokes quantised to 0.5 px step back by half a pixel
/// where the pen slows; 0.3 px of jitter on a pixel grid steps back by a diagonal pixel, 1.41 px,
/// at its floor of 1.33 px), and cutting there would put corners into smooth strokes. At one
/// tolerance (1/8) the random planted sweep's jittered chains were cut so in 8 of 200; the
/// recorded fixtures' corners are the same at both.
const FOLD_LEG_FRACTION: f64 = 0.25;

/// Turning angle (radians, unsigned) at each polyline vertex, from its neighbours (0 at the
/// ends).
fn vertex_angles(points: &[Point]) -> Vec<f64> {
    (0..points.len())
        .map(|i| {
            if i == 0 || i + 1 >= points.len() {
                return 0.0;
            }
            let (v0, v1) = (points[i] - points[i - 1], points[i + 1] - points[i]);
            v0.cross(v1).atan2(v0.dot(v1)).abs()
        })
        .collect()
}

/// Turning angle (radians, unsigned) at every point; `None` where a window is too short.
pub fn turning_angles(points: &[Point], window: f64) -> Vec<Option<f64>> {
    turning_angles_along(points, &cumulative_lengths(points), window)
}

/// [`turning_angles`] given the points' cumulative arc lengths `s`.
fn turning_angles_along(points: &[Point], s: &[f64], window: f64) -> Vec<Option<f64>> {
    let n = points.len();
    let acc = s.last().copied().unwrap_or(0.0);
    let at = |target: f64| -> Point {
        let target = target.clamp(0.0, acc);
        let j = s.partition_point(|&x| x < target).clamp(1, n.max(2) - 1);
        let (a, b) = (s[j - 1], s[j]);
        let f = if b > a { (target - a) / (b - a) } else { 1.0 };
        points[j - 1].lerp(points[j], f)
    };
    let min_len = MIN_WINDOW_FRACTION * window;
    (0..n)
        .map(|i| {
            if n < 3 {
                return None;
            }
            let p = points[i];
            let b = at(s[i] - window);
            let f = at(s[i] + window);
            let (v0, v1) = (p - b, f - p);
            if v0.hypot() < min_len || v1.hypot() < min_len {
                return None;
            }
            Some(v0.cross(v1).atan2(v0.dot(v1)).abs())
        })
        .collect()
}

/// Finds corners and hooks (see the module doc). Each run of consecutive samples above the
/// threshold is one corner, at the run's sharpest sample.
pub fn find_corners(points: &[Point], options: &CornerOptions) -> Cuts {
    let n = points.len();
    let mut cuts = Cuts::default();
    if n < 3 || !(options.window > 0.0) {
        return cuts;
    }
    let s = cumulative_lengths(points);
    let angles = turning_angles_along(points, &s, options.window);
    let total = s[n - 1];
    let zone = (options.hook_fraction * total).min(options.hook_length);
    let corner = options.corner_angle.to_radians();
    let hook = options.hook_angle.to_radians();
    let vertex = vertex_angles(points);

    // Peaks: sharpest sample of each run above `threshold`. Where the windowed angles tie (an
    // exact reversal saturates them at π over a whole window), the sharper vertex wins: the
    // reversal's apex, not the first sample of the run.
    let peaks = |threshold: f64, range: std::ops::Range<usize>| -> Vec<(usize, f64)> {
        let mut out = Vec::new();
        let mut best: Option<(usize, f64)> = None;
        for i in range {
            match angles[i] {
                Some(a) if a > threshold => {
                    let sharper = |(j, b): (usize, f64)| {
                        a > b + ANGLE_TIE
                            || (a >= b - ANGLE_TIE && vertex[i] > vertex[j] + ANGLE_TIE)
                    };
                    if best.is_none_or(sharper) {
                        best = Some((i, a));
                    }
                }
                _ => {
                    if let Some(b) = best.take() {
                        out.push(b);
                    }
                }
            }
        }
        out.extend(best);
        out
    };

    let mut first = 0;
    let mut last = n - 1;
    if options.drop_hooks {
        let start_zone = s.partition_point(|&x| x <= zone);
        if let Some(&(i, _)) = peaks(hook, 0..start_zone.min(n)).last() {
            cuts.start_hook = Some(i);
            first = i;
        }
        let end_zone = s.partition_point(|&x| x < total - zone);
        if let Some(&(i, _)) = peaks(hook, end_zone.max(first + 1)..n).first() {
            cuts.end_hook = Some(i);
            last = i;
        }
    }
    let min_leg = FOLD_LEG_FRACTION * options.window;
    let folds = (first + 1..last).filter(|&i| {
        vertex[i] > FOLD_ANGLE
            && points[i].distance(points[i - 1]) > min_leg
            && points[i].distance(points[i + 1]) > min_leg
    });
    cuts.corners = peaks(corner, first..last + 1)
        .into_iter()
        .map(|(i, _)| i)
        .chain(folds)
        .filter(|&i| i > first && i < last)
        .collect();
    cuts.corners.sort_unstable();
    cuts.corners.dedup();
    cuts
}

#[cfg(test)]
mod tests {
    use super::*;

    fn polyline(corners: &[(f64, f64)], step: f64) -> Vec<Point> {
        let mut out = vec![Point::new(corners[0].0, corners[0].1)];
        for w in corners.windows(2) {
            let (a, b) = (Point::new(w[0].0, w[0].1), Point::new(w[1].0, w[1].1));
            let k = (a.distance(b) / step).ceil() as usize;
            out.extend((1..=k).map(|i| a.lerp(b, i as f64 / k as f64)));
        }
        out
    }

    #[test]
    fn a_right_angle_is_one_corner_at_its_apex() {
        let pts = polyline(&[(0.0, 0.0), (50.0, 0.0), (50.0, 40.0)], 0.5);
        let cuts = find_corners(&pts, &CornerOptions::for_tolerance(0.1));
        assert_eq!(cuts.corners.len(), 1);
        assert!(pts[cuts.corners[0]].distance(Point::new(50.0, 0.0)) < 1e-9);
        assert_eq!(cuts.start_hook, None);
        assert_eq!(cuts.end_hook, None);
    }

    #[test]
    fn a_gentle_arc_has_no_corner() {
        let pts: Vec<Point> = (0..=300)
            .map(|i| {
                let a = i as f64 / 300.0 * 3.0;
                Point::new(20.0 * a.cos(), 20.0 * a.sin())
            })
            .collect();
        let cuts = find_corners(&pts, &CornerOptions::for_tolerance(0.1));
        assert_eq!(cuts, Cuts::default());
    }

    #[test]
    fn a_landing_hook_is_dropped_and_can_be_kept() {
        // 1.5 mm hook back, then a 60 mm stroke.
        let pts = polyline(&[(1.0, -1.2), (0.0, 0.0), (60.0, 0.0)], 0.25);
        let cuts = find_corners(&pts, &CornerOptions::for_tolerance(0.1));
        let h = cuts.start_hook.expect("hook found");
        assert!(pts[h].distance(Point::ZERO) < 0.3, "{:?}", pts[h]);
        assert!(cuts.corners.is_empty());
        let kept = find_corners(
            &pts,
            &CornerOptions::for_tolerance(0.1).with_drop_hooks(false),
        );
        assert_eq!(kept.start_hook, None);
        assert_eq!(kept.corners.len(), 1);
    }

    #[test]
    fn a_drawn_leg_near_an_end_is_a_corner_not_a_hook() {
        // Legs of 10 mm at both ends of a 150 mm stroke: inside the 8 % end zones (12.8 mm) but
        // longer than the longest hook (4 mm at 0.1 mm): corners, and nothing is dropped.
        let pts = polyline(&[(8.0, -6.0), (0.0, 0.0), (150.0, 0.0), (142.0, 6.0)], 0.25);
        let options = CornerOptions::for_tolerance(0.1);
        assert!((options.hook_length - 4.0).abs() < 1e-12);
        let cuts = find_corners(&pts, &options);
        assert_eq!((cuts.start_hook, cuts.end_hook), (None, None));
        assert_eq!(cuts.corners.len(), 2);
        assert!(pts[cuts.corners[0]].distance(Point::ZERO) < 0.3);
        assert!(pts[cuts.corners[1]].distance(Point::new(150.0, 0.0)) < 0.3);
        // The same shape at a fifth of the size has 2 mm legs: hooks, dropped.
        let small: Vec<Point> = pts
            .iter()
            .map(|p| Point::new(p.x / 5.0, p.y / 5.0))
            .collect();
        let cuts = find_corners(&small, &options);
        assert!(cuts.start_hook.is_some() && cuts.end_hook.is_some());
        assert!(cuts.corners.is_empty());
    }
}
