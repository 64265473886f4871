//! Planted chains of log-aesthetic segments: laid out, sampled as a pen or a mouse would, and
//! compared with what the fitter gives back (distance and curvature profile against the planted
//! curve itself, not its samples).

use kansei::chain::Chain;
use kansei::geom::Point;
use kansei::lac::LacSegment;
use kansei::stroke::{Sample, Stroke};

use super::Rng;

/// A chain laid out from `start` at angle 0: each part (length, α, κ at its end), the first
/// starting at `kappa0`; consecutive parts share curvature (G2).
pub fn planted_at(start: Point, kappa0: f64, parts: &[(f64, Option<f64>, f64)]) -> Vec<LacSegment> {
    let (mut p, mut theta, mut kappa) = (start, 0.0, kappa0);
    parts
        .iter()
        .map(|&(length, alpha, k1)| {
            let seg = LacSegment::new(p, theta, length, alpha, kappa, k1).expect("planted segment");
            p = seg.end();
            theta = seg.theta1();
            kappa = k1;
            seg
        })
        .collect()
}

/// [`planted_at`] from the origin.
pub fn planted(kappa0: f64, parts: &[(f64, Option<f64>, f64)]) -> Vec<LacSegment> {
    planted_at(Point::ZERO, kappa0, parts)
}

/// `n + 1` samples evenly spaced in arc length along the chain, through `quantise`, 8 ms apart.
pub fn samples(chain: &[LacSegment], n: usize, mut quantise: impl FnMut(Point) -> Point) -> Stroke {
    let total: f64 = chain.iter().map(|s| s.length()).sum();
    let points: Vec<Point> = (0..=n)
        .map(|i| {
            let mut s = total * i as f64 / n as f64;
            for seg in chain {
                if s <= seg.length() {
                    return quantise(seg.point(s));
                }
                s -= seg.length();
            }
            quantise(chain[chain.len() - 1].end())
        })
        .collect();
    Stroke::new(
        points
            .iter()
            .enumerate()
            .map(|(i, p)| Sample::new(p.x, p.y).with_t(i as f64 * 0.008))
            .collect(),
    )
}

/// Points of the chain every `spacing` of arc length, with their curvature.
pub fn dense(chain: impl IntoIterator<Item = LacSegment>, spacing: f64) -> Vec<(Point, f64)> {
    chain
        .into_iter()
        .flat_map(|s| {
            s.samples(spacing)
                .map(|p| (p.point, p.kappa))
                .collect::<Vec<_>>()
        })
        .collect()
}

/// The point of `polyline` nearest to `q`: its distance, and the index of the nearer vertex of
/// the nearest edge.
fn nearest(polyline: &[(Point, f64)], q: Point) -> (f64, usize) {
    let mut best = (f64::INFINITY, 0);
    for (i, w) in polyline.windows(2).enumerate() {
        let ab = w[1].0 - w[0].0;
        let t = ((q - w[0].0).dot(ab) / ab.hypot2().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        let d = q.distance(w[0].0 + ab * t);
        if d < best.0 {
            best = (d, if t < 0.5 { i } else { i + 1 });
        }
    }
    best
}

/// Distance from each of `points` to the planted chain (a polyline every 0.05 of arc length,
/// made once: its chord error at the curvatures planted here is below 1e-4).
pub fn distances_to(truth: &[LacSegment], points: impl IntoIterator<Item = Point>) -> Vec<f64> {
    let polyline = dense(truth.iter().copied(), 0.05);
    points
        .into_iter()
        .map(|q| nearest(&polyline, q).0)
        .collect()
}

/// The fitted chains' segments.
pub fn segments(chains: &[Chain]) -> Vec<LacSegment> {
    chains
        .iter()
        .flat_map(|c| c.segments.iter().map(|s| s.segment))
        .collect()
}

/// The largest distance from the fitted chains to the planted chain, and back.
pub fn distance_between(chains: &[Chain], truth: &[LacSegment]) -> f64 {
    let step = truth.iter().map(|s| s.length()).sum::<f64>() / 2000.0;
    let fitted = dense(segments(chains), step);
    let planted = dense(truth.iter().copied(), step);
    let there = fitted
        .iter()
        .map(|p| nearest(&planted, p.0).0)
        .fold(0.0, f64::max);
    let back = planted
        .iter()
        .map(|p| nearest(&fitted, p.0).0)
        .fold(0.0, f64::max);
    there.max(back)
}

/// The curvature profile's error: mean |κ_fit − κ_true| over mean |κ_true|, along the planted
/// curve (κ_fit taken at the fitted chain's point nearest to each planted point).
pub fn profile_error(chains: &[Chain], truth: &[LacSegment]) -> f64 {
    let step = truth.iter().map(|s| s.length()).sum::<f64>() / 2000.0;
    let fitted = dense(segments(chains), step / 4.0);
    let planted = dense(truth.iter().copied(), step);
    let (mut diff, mut scale) = (0.0, 0.0);
    for &(p, k) in &planted {
        let (_, i) = nearest(&fitted, p);
        diff += (fitted[i].1 - k).abs();
        scale += k.abs();
    }
    diff / scale
}

/// [`samples`] with Gaussian noise of deviation `sigma` on each coordinate (a pen's jitter),
/// drawn from a generator seeded with `seed`.
pub fn jittered(chain: &[LacSegment], n: usize, sigma: f64, seed: u64) -> Stroke {
    let mut rng = super::Rng::new(seed);
    samples(chain, n, |p| {
        p + kurbo::Vec2::new(sigma * rng.normal(), sigma * rng.normal())
    })
}

/// Largest total turning of a planted chain (radians): beyond about a turn a stroke comes near
/// itself and "nearest point" comparisons stop meaning the same place.
pub const MAX_TURNING: f64 = 5.0;

/// The first `count` chains [`random_chain`] draws from a generator seeded `seed` (the draws it
/// refuses skipped): the random sweep's cases (`examples/planted_sweep.rs`, seed 1).
pub fn random_chains(seed: u64, count: usize) -> Vec<Vec<LacSegment>> {
    let mut rng = Rng::new(seed);
    let mut chains = Vec::with_capacity(count);
    while chains.len() < count {
        if let Some(chain) = random_chain(&mut rng) {
            chains.push(chain);
        }
    }
    chains
}

/// A random planted chain in pixels, G2 throughout: one to three segments of 80 to 200 px, α
/// uniform in [−1.5, 2.5], curvatures 0.003 to 0.03 /px changing 1.5 to 4 times per segment (at
/// most 0.04 /px), a quarter of the segments running into a curvature zero (α < 0) and the one
/// after it leaving it with either sign. `None` where the draw turns more than [`MAX_TURNING`]
/// or no segment joins it.
pub fn random_chain(rng: &mut Rng) -> Option<Vec<LacSegment>> {
    let m = 1 + (rng.uniform() * 3.0) as usize;
    let log_uniform =
        |rng: &mut Rng, a: f64, b: f64| (a.ln() + (b.ln() - a.ln()) * rng.uniform()).exp();
    let mut kappa = log_uniform(rng, 0.003, 0.03) * if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
    let (mut p, mut theta) = (
        Point::new(400.0, 300.0),
        rng.uniform() * std::f64::consts::TAU,
    );
    let mut chain = Vec::new();
    for _ in 0..m {
        let length = 80.0 + 120.0 * rng.uniform();
        let (alpha, end) = if kappa == 0.0 {
            // Leaving an inflection: α < 0 to a curvature of either sign.
            let alpha = -0.3 - 1.2 * rng.uniform();
            let k = log_uniform(rng, 0.003, 0.03) * if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
            (alpha, k)
        } else if rng.uniform() < 0.25 {
            // Into an inflection.
            (-0.3 - 1.2 * rng.uniform(), 0.0)
        } else {
            let alpha = -1.5 + 4.0 * rng.uniform();
            let mut ratio = log_uniform(rng, 1.5, 4.0);
            if rng.uniform() < 0.5 {
                ratio = 1.0 / ratio;
            }
            (alpha, (kappa * ratio).clamp(-0.04, 0.04))
        };
        let seg = LacSegment::new(p, theta, length, Some(alpha), kappa, end).ok()?;
        p = seg.end();
        theta = seg.theta1();
        kappa = end;
        chain.push(seg);
    }
    let turning: f64 = chain.iter().map(|s| (s.theta1() - s.theta0()).abs()).sum();
    (turning <= MAX_TURNING).then_some(chain)
}

/// A planted chain drawn the three ways the random sweep draws it, a sample every 0.9 px of
/// curve: on whole pixels (a mouse), with 0.3 px of jitter then rounded (a shaky mouse, jitter
/// seeded with `1000 + seed`), and a quarter of the size in millimetres with 0.02 mm of noise
/// (a tablet, seeded with `5000 + seed`; `mm` is the chain at that size).
pub struct Drawn {
    pub pixels: Stroke,
    pub jittered: Stroke,
    pub mm: Vec<LacSegment>,
    pub tablet: Stroke,
}

/// [`Drawn`] for `truth` (in pixels).
pub fn drawn_three_ways(truth: &[LacSegment], seed: u64) -> Drawn {
    let total: f64 = truth.iter().map(|s| s.length()).sum();
    let n = (total / 0.9) as usize;
    let pixels = samples(truth, n, |p| Point::new(p.x.round(), p.y.round()));
    let mut rng = Rng::new(1000 + seed);
    let jitter = samples(truth, n, |p| {
        let q = p + kurbo::Vec2::new(0.3 * rng.normal(), 0.3 * rng.normal());
        Point::new(q.x.round(), q.y.round())
    });
    let mm: Vec<LacSegment> = truth
        .iter()
        .map(|s| {
            LacSegment::new(
                Point::new(s.start().x * 0.25, s.start().y * 0.25),
                s.theta0(),
                s.length() * 0.25,
                s.alpha(),
                s.kappa0() / 0.25,
                s.kappa1() / 0.25,
            )
            .expect("scaled segment")
        })
        .collect();
    let tablet = jittered(&mm, n, 0.02, 5000 + seed);
    Drawn {
        pixels,
        jittered: jitter,
        mm,
        tablet,
    }
}
