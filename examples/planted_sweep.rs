//! Random planted G2 chains through the default pipeline: how often the fit comes back as the
//! hand meant it, on curves no fixture was tuned to.
//!
//! Each case is a chain of one to three log-aesthetic segments with random α, lengths and
//! curvatures (inflections through α < 0 segments included), drawn three ways: on a whole-pixel
//! grid (a mouse), with 0.3 px of jitter then rounded (a shaky mouse), and a quarter of the size
//! in millimetres with 0.02 mm of noise (a tablet). Fitted with the defaults (no tolerance
//! given), each is checked as `tests/intent.rs` checks its three planted cases: one piece, no more
//! segments than planted, the curvature profile within 5 % of the planted curve's, within the
//! reported tolerance of the planted curve, every sample within the tolerance.
//!
//! `cargo run --release --example planted_sweep [cases] [seed] [dir]` (defaults 200 and 1):
//! with a directory, each failing case's stroke is written there as `<case>-<kind>.json`
//! (`kansei-stroke`), to fit again with `kansei fit`.

#[path = "../tests/common/mod.rs"]
mod common;

use common::planted::{
    distance_between, distances_to, drawn_three_ways, profile_error, random_chains, segments,
};
use kansei::lac::LacSegment;
use kansei::pipeline::{PipelineOptions, StrokeOutcome, fit_with_noise};
use kansei::stroke::{Stroke, Units};

/// What went wrong, if anything, fitting `stroke` drawn from `truth`; the stroke itself, when
/// something did.
fn check(truth: &[LacSegment], stroke: &Stroke, units: Units) -> (Vec<String>, Option<String>) {
    let wrong = problems(truth, stroke, units);
    let json = (!wrong.is_empty())
        .then(|| kansei::stroke::StrokeFile::new(units, vec![stroke.clone()]).to_json());
    (wrong, json)
}

fn problems(truth: &[LacSegment], stroke: &Stroke, units: Units) -> Vec<String> {
    let mut wrong = Vec::new();
    let StrokeOutcome::Curves(curves) =
        fit_with_noise(stroke, 0, units, &PipelineOptions::default())
    else {
        return vec!["no curves".into()];
    };
    let tolerance = curves[0].tolerance;
    let chains: Vec<_> = curves.into_iter().filter_map(|c| c.chain).collect();
    if chains.len() != 1 {
        wrong.push(format!("{} pieces", chains.len()));
    }
    let n: usize = chains.iter().map(|c| c.segments.len()).sum();
    if n > truth.len() {
        wrong.push(format!("{n} segments for {}", truth.len()));
    }
    let profile = profile_error(&chains, truth);
    if profile > 0.05 {
        wrong.push(format!("profile {:.1} %", 100.0 * profile));
    }
    let off = distance_between(&chains, truth);
    if off > tolerance {
        wrong.push(format!("{:.2} tolerances off", off / tolerance));
    }
    if !chains.iter().all(|c| c.within_tolerance) {
        wrong.push("samples outside".into());
    }
    if !wrong.is_empty() {
        // Is the planted answer within reach of the samples? The planted curve's largest and rms
        // distance to them beside the fit's: where the fit's rms is below the planted curve's,
        // the samples favour the fit and the profile's miss is the data's, not the fitter's;
        // where the planted curve holds every sample within the tolerance, a chain with the
        // planted count exists and more segments are the fitter's miss.
        let fitted = segments(&chains);
        let (t_max, t_rms) = spread(&distances_to(truth, stroke.points()));
        let (_, f_rms) = spread(&distances_to(&fitted, stroke.points()));
        wrong.push(format!(
            "[{n} segments; planted max {:.2} rms {:.3} tol, fit rms {:.3} tol: {}]",
            t_max / tolerance,
            t_rms / tolerance,
            f_rms / tolerance,
            if t_max > tolerance {
                "planted beyond tolerance"
            } else if f_rms < t_rms {
                "data-limited"
            } else {
                "fitter-limited"
            }
        ));
    }
    wrong
}

/// The largest and the rms of distances.
fn spread(d: &[f64]) -> (f64, f64) {
    let max = d.iter().copied().fold(0.0, f64::max);
    let rms = (d.iter().map(|x| x * x).sum::<f64>() / d.len().max(1) as f64).sqrt();
    (max, rms)
}

fn describe(chain: &[LacSegment]) -> String {
    chain
        .iter()
        .map(|s| {
            format!(
                "[L {:.0} α {:.2} κ {:.4}→{:.4}]",
                s.length(),
                s.alpha().unwrap_or(f64::NAN),
                s.kappa0(),
                s.kappa1()
            )
        })
        .collect::<Vec<_>>()
        .join(" ")
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let cases: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(200);
    let seed: u64 = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(1);
    let chains = random_chains(seed, cases);
    let kinds = ["pixels", "jitter 0.3 px + pixels", "tablet 0.02 mm"];
    let dump = args.get(3).map(std::path::PathBuf::from);
    let results: Vec<Vec<(Vec<String>, Option<String>)>> = std::thread::scope(|scope| {
        let handles: Vec<_> = chains
            .chunks(chains.len().div_ceil(2))
            .enumerate()
            .map(|(h, part)| {
                scope.spawn(move || {
                    part.iter()
                        .enumerate()
                        .map(|(i, truth)| {
                            let k = (h * 100_000 + i) as u64;
                            let d = drawn_three_ways(truth, k);
                            vec![
                                check(truth, &d.pixels, Units::Px),
                                check(truth, &d.jittered, Units::Px),
                                check(&d.mm, &d.tablet, Units::Mm),
                            ]
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("worker"))
            .collect()
    });
    for (k, kind) in kinds.iter().enumerate() {
        let failed: Vec<usize> = (0..cases)
            .filter(|&i| !results[i][k].0.is_empty())
            .collect();
        println!("{kind}: {} of {cases} as planted", cases - failed.len());
        for &i in &failed {
            println!(
                "  #{i} {}: {}",
                describe(&chains[i]),
                results[i][k].0.join(", ")
            );
            if let (Some(dir), Some(json)) = (&dump, &results[i][k].1) {
                let path = dir.join(format!("{i}-{}.json", ["pixels", "jitter", "tablet"][k]));
                if let Err(e) = std::fs::write(&path, json) {
                    eprintln!("{}: {e}", path.display());
                }
            }
        }
    }
}
