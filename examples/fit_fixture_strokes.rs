//! Fits every fixture stroke of up to 600 samples through the whole pipeline, one line each (best
//! time of `REPS` rounds, default 3; samples; segments), then the totals with the mean over
//! strokes of the rms sample distance relative to the tolerance (the fit's quality, to read
//! beside the speed): a profiling aid, not a benchmark (that is `cargo bench --bench lac`). The instruction counts in the README come from
//! `REPS=1 valgrind --tool=callgrind target/release/examples/fit_fixture_strokes`.
//! Arguments filter the files by name; `ONLY=i` keeps stroke i of each.
//! `TOLERANCE_FACTORS=0.9,1,1.1` fits every stroke once per factor of its file's default
//! tolerance: the fit is chaotic in its details (a change far below the tolerance can move one
//! stroke's work by a third), so comparing two versions over several tolerances tells a real
//! change from a reshuffle better than one fit per stroke does.
//! `FLOOR=1` fits each stroke at its own tolerance, as `kansei fit` does without `--tolerance`
//! (the unit's default raised to the stroke's noise floor; the factors then scale that), and
//! `CONTINUITY=g1` (or `c3`) sets the chain's continuity (default: the default, G2). The
//! per-stroke instruction counts in docs/performance.md are
//! `REPS=1 FLOOR=1 ONLY=i valgrind --tool=callgrind target/release/examples/fit_fixture_strokes
//! <file>` minus the same with `REPS=0` (the file's parse), in each continuity.
#[path = "../tests/common/mod.rs"]
mod common;

use common::{fixture, fixture_names};
use kansei::pipeline::{PipelineOptions, fit_stroke};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let reps: usize = std::env::var("REPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3);
    let (mut strokes, mut segments) = (0usize, 0usize);
    // Sum over strokes of the chain's rms sample distance relative to the tolerance.
    let mut relative_rms = 0.0;
    for name in fixture_names() {
        if !args.is_empty() && !args.iter().any(|a| name.contains(a.as_str())) {
            continue;
        }
        let file = fixture(&name);
        let factors: Vec<f64> = std::env::var("TOLERANCE_FACTORS")
            .ok()
            .map(|v| v.split(',').filter_map(|f| f.trim().parse().ok()).collect())
            .filter(|f: &Vec<f64>| !f.is_empty())
            .unwrap_or_else(|| vec![1.0]);
        for (factor, (i, s)) in factors.iter().flat_map(|&f| {
            file.strokes
                .iter()
                .enumerate()
                .map(move |stroke| (f, stroke))
        }) {
            let mut options = PipelineOptions::default();
            if let Ok(continuity) = std::env::var("CONTINUITY") {
                match continuity.parse() {
                    Ok(c) => options.chain.continuity = c,
                    Err(e) => {
                        eprintln!("CONTINUITY: {e}");
                        std::process::exit(2);
                    }
                }
            }
            let base = if std::env::var("FLOOR").is_ok_and(|v| v == "1") {
                options.stroke_tolerance(s, file.units).tolerance
            } else {
                file.units.default_tolerance()
            };
            let tol = factor * base;
            let options = options.with_tolerance(tol);
            if s.samples.len() > 600 {
                continue;
            }
            if let Ok(only) = std::env::var("ONLY")
                && only.parse::<usize>().ok() != Some(i)
            {
                continue;
            }
            let mut best = f64::INFINITY;
            let mut segs = 0;
            let mut rms = 0.0;
            for _ in 0..reps {
                let t = Instant::now();
                let r = fit_stroke(s, i, tol, &options);
                best = best.min(t.elapsed().as_secs_f64());
                if let Ok(f) = r {
                    let (mut squares, mut count) = (0.0, 0usize);
                    for segment in f
                        .iter()
                        .filter_map(|c| c.chain.as_ref())
                        .flat_map(|c| &c.segments)
                    {
                        let n = (segment.samples.1 + 1).saturating_sub(segment.samples.0);
                        squares += segment.rms_deviation.powi(2) * n as f64;
                        count += n;
                    }
                    rms = (squares / count.max(1) as f64).sqrt() / tol;
                    segs = f
                        .iter()
                        .filter_map(|c| c.chain.as_ref())
                        .map(|c| c.segments.len())
                        .sum();
                }
            }
            strokes += 1;
            segments += segs;
            relative_rms += rms;
            println!(
                "{:8.2} ms  {:4} samples {:3} segs  {}.json#{}  rms/tolerance {:.4}  tolerance ×{}",
                best * 1e3,
                s.samples.len(),
                segs,
                name,
                i,
                rms,
                factor
            );
        }
    }
    println!(
        "{strokes} strokes, {segments} segments, mean rms/tolerance {:.4}",
        relative_rms / strokes.max(1) as f64
    );
}
