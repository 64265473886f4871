//! Shapes that come back near themselves (`tests/common/loops.rs`) through the default pipeline,
//! judged against the shape they were drawn from: a table per class of segments (median, max),
//! the distance between chain and shape both ways, beyond the samples' own distance from the
//! shape, in tolerances (largest), the curvature
//! profile's error (median), and how many fell back to G1, missed the tolerance or broke into
//! pieces.
//!
//! `cargo run --release --example loop_shapes [per_class] [seed] [dir]` (defaults 10 and 1):
//! with a directory, every stroke is written there as `<name>.json` (`kansei-stroke`), to fit
//! again with `kansei fit`. `VERBOSE=1` prints a line per stroke.

#[path = "../tests/common/mod.rs"]
mod common;

use common::loops::{CLASSES, profile_error, sample_error, shapes, truth_for, two_way_distance};
use kansei::chain::Continuity;
use kansei::pipeline::{PipelineOptions, StrokeOutcome, fit_with_noise};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

fn main() {
    let mut args = std::env::args().skip(1);
    let per_class: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(10);
    let seed: u64 = args.next().and_then(|a| a.parse().ok()).unwrap_or(1);
    let dir = args.next();
    let all = shapes(per_class, seed);
    if let Some(dir) = &dir {
        for shape in &all {
            let file = kansei::stroke::StrokeFile::new(shape.units, vec![shape.stroke.clone()]);
            let path = format!("{dir}/{}.json", shape.name);
            if let Err(e) = std::fs::write(&path, file.to_json()) {
                eprintln!("{path}: {e}");
            }
        }
    }
    println!(
        "| class | strokes | segments median / max | chain↔shape beyond the samples' error (tol) max | profile error median | G1 | outside tol | several pieces | closed (of meant) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for class in CLASSES {
        let (mut segs, mut dist, mut prof) = (Vec::new(), Vec::new(), Vec::new());
        let (mut g1, mut outside, mut pieces, mut n) = (0, 0, 0, 0);
        let (mut closed, mut meant) = (0, 0);
        for shape in all.iter().filter(|s| s.class == class) {
            n += 1;
            let StrokeOutcome::Curves(curves) =
                fit_with_noise(&shape.stroke, 0, shape.units, &PipelineOptions::default())
            else {
                println!("{}: no curves", shape.name);
                continue;
            };
            let tolerance = curves[0].tolerance;
            meant += usize::from(shape.closed);
            let closed_fit = curves.iter().any(|c| c.closure.is_some());
            closed += usize::from(closed_fit);
            let truth = truth_for(shape, closed_fit);
            let chains: Vec<_> = curves.into_iter().filter_map(|c| c.chain).collect();
            if chains.len() > 1 {
                pieces += 1;
            }
            g1 += chains
                .iter()
                .filter(|c| c.continuity == Continuity::G1 && c.segments.len() > 1)
                .count();
            outside += chains.iter().filter(|c| !c.within_tolerance).count();
            segs.push(chains.iter().map(|c| c.segments.len()).sum::<usize>() as f64);
            let (there, back) = two_way_distance(&chains, &truth);
            // Beyond what the samples' own error from the shape allows (see `sample_error`).
            let drawn = sample_error(&shape.stroke, &truth);
            dist.push((there.max(back) - drawn).max(0.0) / tolerance);
            prof.push(profile_error(&chains, &truth));
            if std::env::var("VERBOSE").is_ok() {
                println!(
                    "  {} {} samples: {} segments, {:.2}/{:.2} tol, profile {:.1} %",
                    shape.name,
                    shape.stroke.samples.len(),
                    segs.last().unwrap_or(&0.0),
                    there / tolerance,
                    back / tolerance,
                    100.0 * prof.last().unwrap_or(&0.0)
                );
            }
        }
        println!(
            "| {class} | {n} | {} / {} | {:.2} | {:.1} % | {g1} | {outside} | {pieces} | {closed} ({meant}) |",
            median(segs.clone()),
            segs.iter().copied().fold(0.0, f64::max),
            dist.iter().copied().fold(0.0, f64::max),
            100.0 * median(prof)
        );
    }
}
