//! Split quality on planted strokes: how often the pipeline finds exactly the true curvature
//! extrema and inflections, for kansei and for the seed paper's B-spline stage (segments added
//! one by one, no fairing), on the same strokes.
//!
//! `cargo run --release --example planted_splits`

#[path = "../tests/common/mod.rs"]
mod common;

use common::*;
use kansei::geom::Point;
use kansei::pipeline::{PipelineOptions, fit_stroke};
use kansei::split::SplitKind;

/// (curvature extrema, inflections) the pipeline finds.
fn count(
    stroke: &kansei::stroke::Stroke,
    tolerance: f64,
    options: &PipelineOptions,
) -> Option<(usize, usize)> {
    let fits = fit_stroke(stroke, 0, tolerance, options).ok()?;
    let of = |kind| {
        fits.iter()
            .flat_map(|c| c.spans.splits.iter())
            .filter(|s| s.kind == kind)
            .count()
    };
    Some((of(SplitKind::CurvatureExtremum), of(SplitKind::Inflection)))
}

fn wave(x: f64) -> Point {
    Point::new(x, 15.0 * (x / 20.0).sin())
}

fn spiral(t: f64) -> Point {
    let r = 10.0 * (0.15 * t).exp();
    Point::new(r * t.cos(), r * t.sin())
}

fn main() {
    type Case = (&'static str, fn(f64) -> Point, f64, f64, (usize, usize));
    let cases: [Case; 4] = [
        ("ellipse arc", ellipse, -1.0, 1.0, (1, 0)),
        ("S-curve", s_curve, -48.0, 48.0, (0, 1)),
        ("sine wave", wave, -10.0, 120.0, (2, 2)),
        ("log spiral", spiral, 0.0, 6.0, (0, 0)),
    ];
    let tolerance = 0.1;
    let seeds = 10;
    println!(
        "exact split counts out of {seeds} noise seeds, tolerance {tolerance} mm, 401 samples"
    );
    println!(
        "{:<12} {:>8} {:>8} {:>8}",
        "curve", "sigma", "kansei", "seed"
    );
    let (mut ours, mut peer, mut all) = (0, 0, 0);
    for (name, curve, a, b, truth) in cases {
        for sigma in [0.0, 0.01, 0.02, 0.03] {
            let (mut o, mut p) = (0, 0);
            for seed in 0..seeds {
                let stroke = sample_curve(curve, a, b, 400, sigma, seed);
                o += usize::from(
                    count(&stroke, tolerance, &PipelineOptions::splits_only()) == Some(truth),
                );
                p += usize::from(
                    count(
                        &stroke,
                        tolerance,
                        &PipelineOptions::splits_only().seed_method(),
                    ) == Some(truth),
                );
            }
            println!("{name:<12} {sigma:>8} {o:>8} {p:>8}");
            ours += o;
            peer += p;
            all += seeds as usize;
        }
    }
    println!("{:<12} {:>8} {ours:>8} {peer:>8}   (of {all})", "total", "");
}
