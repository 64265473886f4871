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
