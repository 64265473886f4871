//! The noise floor of a stroke (`NoiseFloor::estimate`): whole-pixel and offset grids found,
//! Gaussian jitter measured across the curve, a clean curve with a corner noise-free, and bad
//! input without a panic.

mod common;

use common::Rng;
use kansei::geom::Point;
use kansei::stroke::{NoiseFloor, noise_multiple};

/// An arc of radius 300 over 2 radians, sampled every 1.5 units.
fn arc() -> Vec<Point> {
    let n = 400;
    (0..n)
        .map(|i| {
            let a = 2.0 * i as f64 / n as f64;
            Point::new(500.0 + 300.0 * a.cos(), 400.0 + 300.0 * a.sin())
        })
        .collect()
}

#[test]
fn a_whole_pixel_grid_is_found_and_its_floor_is_the_worst_rounding() {
    let points: Vec<Point> = arc()
        .into_iter()
        .map(|p| Point::new(p.x.round(), p.y.round()))
        .collect();
    let noise = NoiseFloor::estimate(&points);
    assert_eq!(noise.grid, Some(1.0));
    let sigma = 1.0 / 12f64.sqrt();
    assert!((noise.sigma - sigma).abs() < 0.15 * sigma, "{noise:?}");
    assert!(noise.floor >= std::f64::consts::FRAC_1_SQRT_2);
    assert!(noise.floor <= 3.0 * sigma, "{noise:?}");
}

#[test]
fn an_offset_quarter_pixel_grid_is_found() {
    let points: Vec<Point> = arc()
        .into_iter()
        .map(|p| Point::new((p.x * 4.0).round() / 4.0 + 0.3, (p.y * 4.0).round() / 4.0))
        .collect();
    let noise = NoiseFloor::estimate(&points);
    let q = noise.grid.expect("a grid");
    assert!((q - 0.25).abs() < 1e-9, "{q}");
}

#[test]
fn gaussian_jitter_is_measured_across_the_curve() {
    let mut rng = Rng::new(7);
    for sigma in [0.02, 0.2, 1.0] {
        let points: Vec<Point> = arc()
            .into_iter()
            .map(|p| Point::new(p.x + sigma * rng.normal(), p.y + sigma * rng.normal()))
            .collect();
        let noise = NoiseFloor::estimate(&points);
        assert_eq!(noise.grid, None);
        assert!(
            (noise.sigma - sigma).abs() < 0.15 * sigma,
            "σ {sigma}: {noise:?}"
        );
        let k = noise_multiple(points.len());
        assert!((noise.floor - k * noise.sigma).abs() < 1e-12);
    }
}

#[test]
fn a_clean_curve_has_no_noise_and_a_corner_does_not_make_any() {
    let mut points = arc();
    let last = *points.last().expect("points");
    points.extend((1..200).map(|i| last + kansei::geom::Vec2::new(1.5 * i as f64, 0.0)));
    let noise = NoiseFloor::estimate(&points);
    assert!(noise.sigma < 1e-6, "{noise:?}");
}

#[test]
fn too_few_or_bad_samples_give_no_jitter_and_no_panic() {
    assert_eq!(NoiseFloor::estimate(&[]).sigma, 0.0);
    let points = [Point::new(0.0, 0.0), Point::new(f64::NAN, 1.0)];
    assert_eq!(NoiseFloor::estimate(&points).floor, 0.0);
    let same = vec![Point::new(1.0, 1.0); 50];
    assert_eq!(NoiseFloor::estimate(&same).floor, 0.0);
}

/// The arc of [`arc`] sampled every `spacing` units, with Gaussian jitter of `jitter` on each
/// coordinate, then rounded to whole pixels: a shaky mouse. Returns the samples and each one's
/// distance from the true arc.
fn shaky(spacing: f64, jitter: f64, seed: u64) -> (Vec<Point>, Vec<f64>) {
    let mut rng = Rng::new(seed);
    let n = (600.0 / spacing) as usize;
    let centre = Point::new(500.3, 400.6);
    let points: Vec<Point> = (0..n)
        .map(|i| {
            let a = 2.0 * i as f64 / n as f64;
            let p = centre + kansei::geom::Vec2::new(300.0 * a.cos(), 300.0 * a.sin());
            Point::new(
                (p.x + jitter * rng.normal()).round(),
                (p.y + jitter * rng.normal()).round(),
            )
        })
        .collect();
    let off = points
        .iter()
        .map(|p| (p.distance(centre) - 300.0).abs())
        .collect();
    (points, off)
}

#[test]
fn jitter_on_a_pixel_grid_raises_the_floor_to_what_the_samples_need() {
    // Jitter of a third of a pixel, then rounding: σ across the curve is about 1.44 times the
    // rounding's own, which a noise-free staircase can also read (up to 1.45 times), so σ alone
    // cannot tell them apart. The coordinates reversing where they move most can: rounding is
    // monotone. The floor must then cover the samples' real excursions from the curve.
    for (k, spacing) in [0.3, 0.9].into_iter().enumerate() {
        for seed in 1..=4 {
            let (points, off) = shaky(spacing, 0.3, 10 * k as u64 + seed);
            let noise = NoiseFloor::estimate(&points);
            assert_eq!(noise.grid, Some(1.0));
            let outside = off.iter().filter(|d| **d > noise.floor).count();
            assert!(
                outside * 100 <= points.len(),
                "spacing {spacing}, seed {seed}: {outside} of {} samples beyond the floor {noise:?}",
                points.len()
            );
            // And not beyond what the noise itself reaches (its σ across the curve is
            // √(0.3² + 1/12) = 0.42; a fifth over the expected largest excursion).
            let true_sigma = (0.09f64 + 1.0 / 12.0).sqrt();
            assert!(
                noise.floor <= 1.2 * noise_multiple(points.len()) * true_sigma,
                "spacing {spacing}, seed {seed}: {noise:?}"
            );
        }
        // The same arc rounded without jitter never reverses a coordinate where it moves most:
        // its floor stays the worst rounding.
        let (points, _) = shaky(spacing, 0.0, 1);
        let noise = NoiseFloor::estimate(&points);
        assert_eq!(noise.floor, std::f64::consts::FRAC_1_SQRT_2, "{noise:?}");
    }
}

#[test]
fn jitter_along_the_grid_is_not_trimmed_away() {
    // A line running nearly along the pixel grid, with 0.3 px of jitter, rounded: most samples
    // land exactly on the line's pixel row and a few a whole pixel off it. The median residual
    // is then near zero, and a cut at a few robust deviations would drop the whole-pixel steps
    // that the fit must still cover (σ read 0.10 px where the samples' own deviation from the
    // line is 0.3 px). Residuals within a step and a half of the grid are kept.
    for seed in 1..=6 {
        let mut rng = Rng::new(40 + seed);
        let angle = 0.01 * seed as f64;
        let (origin, dir) = (
            Point::new(100.0, 200.02),
            kansei::geom::Vec2::new(angle.cos(), angle.sin()),
        );
        let points: Vec<Point> = (0..130)
            .map(|i| {
                let p = origin + dir * (0.9 * i as f64);
                Point::new(
                    (p.x + 0.3 * rng.normal()).round(),
                    (p.y + 0.3 * rng.normal()).round(),
                )
            })
            .collect();
        // The samples' own deviation across the line.
        let across: Vec<f64> = points.iter().map(|p| dir.cross(*p - origin)).collect();
        let rms = (across.iter().map(|d| d * d).sum::<f64>() / across.len() as f64).sqrt();
        let noise = NoiseFloor::estimate(&points);
        assert!(
            noise.sigma >= 0.7 * rms,
            "seed {seed}: σ {} against the samples' {rms}",
            noise.sigma
        );
    }
}

#[test]
fn jitter_on_a_pixel_grid_is_measured_from_every_sample() {
    // σ across the curve of 0.3 px of jitter then rounding is √(0.3² + 1/12) = 0.42 px. The
    // local fits take samples two pixels apart (rounding is one staircase between neighbours);
    // fitting every such interleaved run, not just one, uses every sample. What matters is the
    // low side: a σ read short sets the floor below the noise's excursions and the fit chases
    // them (one run alone read as little as 0.30 px here, five of 24 draws more than a sixth
    // short). On strokes of 120 samples (a 108 px stretch of the arc), none of 24 draws is read
    // more than a tenth short, nor more than a third over.
    let true_sigma = (0.09f64 + 1.0 / 12.0).sqrt();
    let estimates: Vec<f64> = (1..=24)
        .map(|seed| NoiseFloor::estimate(&shaky(0.9, 0.3, 100 + seed).0[..120]).sigma)
        .collect();
    for (seed, sigma) in estimates.iter().enumerate() {
        let ratio = sigma / true_sigma;
        assert!(
            (0.9..=4.0 / 3.0).contains(&ratio),
            "draw {seed}: σ {sigma} for {true_sigma}: {estimates:?}"
        );
    }
}

#[test]
fn a_sparse_jittered_stroke_is_told_from_a_rounded_one() {
    // Random planted chains sampled every 1.4 px, rounded to whole pixels with and without
    // 0.3 px of jitter first. σ alone cannot tell the two (both read about 1.0–1.5 times the
    // grid's own q/√12), and at this spacing the coordinate that moves more seldom turns back
    // between two moves. A coordinate turning back while the stroke, over four pixels either
    // side, runs along its axis can: rounding is monotone, so a rounded smooth curve's coordinate
    // turns back only where its tangent is perpendicular to that axis. Every rounded stroke keeps
    // the grid's floor (it was never farther from its curve than q·√2/2); most jittered ones are
    // read as jittered (53 of these 60, 248 of 300 chains; counting only the coordinate that
    // moves more turning back between two moves, and three such, read 43 of these 60).
    let chains = common::planted::random_chains(7, 60);
    let mut jittered_read = 0;
    for (k, truth) in chains.iter().enumerate() {
        let total: f64 = truth.iter().map(|s| s.length()).sum();
        let n = (total / 1.4) as usize;
        let rounded = common::planted::samples(truth, n, |p| Point::new(p.x.round(), p.y.round()));
        let noise = NoiseFloor::estimate(&rounded.points());
        assert_eq!(
            noise.floor,
            std::f64::consts::FRAC_1_SQRT_2,
            "chain {k} rounded: {noise:?}"
        );
        let mut jitter = Rng::new(900 + k as u64);
        let shaky = common::planted::samples(truth, n, |p| {
            Point::new(
                (p.x + 0.3 * jitter.normal()).round(),
                (p.y + 0.3 * jitter.normal()).round(),
            )
        });
        let noise = NoiseFloor::estimate(&shaky.points());
        if noise.floor > std::f64::consts::FRAC_1_SQRT_2 {
            jittered_read += 1;
        }
    }
    assert!(
        jittered_read * 5 >= chains.len() * 4,
        "{jittered_read} of {} jittered strokes read as jittered",
        chains.len()
    );
}
