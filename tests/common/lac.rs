//! Planted log-aesthetic strokes.

use kansei::geom::{Point, Vec2};
use kansei::lac::LacSegment;
use kansei::stroke::{Sample, Stroke};

use super::Rng;

/// A segment of length `length` and slope `alpha` whose curvature falls by `ratio` (κ0 = ratio·κ1)
/// and which turns by `turning` radians in total, starting at the origin along +x.
pub fn planted_segment(alpha: f64, length: f64, ratio: f64, turning: f64) -> LacSegment {
    let unit = LacSegment::new(
        Point::ZERO,
        0.0,
        length,
        Some(alpha),
        ratio / length,
        1.0 / length,
    )
    .expect("planted segment");
    let scale = turning / (unit.theta1() - unit.theta0());
    LacSegment::new(
        Point::ZERO,
        0.0,
        length,
        Some(alpha),
        scale * ratio / length,
        scale / length,
    )
    .expect("planted segment")
}

/// Samples a segment as a pen would draw it: `n` samples at 5 ms with a speed that rises from
/// rest and falls back to it (s ∝ (1 − cos πτ)/2), `dwell` extra samples resting at each end,
/// and Gaussian noise of deviation `sigma` on every coordinate.
pub fn pen_stroke(segment: &LacSegment, n: usize, dwell: usize, sigma: f64, seed: u64) -> Stroke {
    let mut rng = Rng::new(seed);
    let mut jitter = |p: Point| p + Vec2::new(sigma * rng.normal(), sigma * rng.normal());
    let mut points = Vec::new();
    let start = segment.start();
    let end = segment.end();
    points.extend((0..dwell).map(|_| jitter(start)));
    for i in 0..=n {
        let tau = i as f64 / n as f64;
        let s = segment.length() * 0.5 * (1.0 - (std::f64::consts::PI * tau).cos());
        points.push(jitter(segment.point(s)));
    }
    points.extend((0..dwell).map(|_| jitter(end)));
    Stroke::new(
        points
            .iter()
            .enumerate()
            .map(|(i, p)| Sample::new(p.x, p.y).with_t(i as f64 * 0.005))
            .collect(),
    )
}
