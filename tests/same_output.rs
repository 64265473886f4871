//! A recorded oracle of the fitter's output, byte for byte: every fixture stroke file in g1, g2
//! and c3, a random planted sweep drawn three ways, and the adversarial strokes, each fitted and
//! written as `kansei-curve` JSON, and the JSON's FNV-1a hash compared with the hash recorded in
//! `fixtures/same-output.txt`.
//!
//! This is the check for changes that must not change any fit (a move of code between modules,
//! a renamed type, a rewritten loop that computes the same numbers): its tolerance is zero, every
//! byte. A change that is meant to change fits records the new hashes on purpose:
//!
//! ```text
//! KANSEI_SAME_OUTPUT_WRITE=fixtures/same-output.txt cargo test --test same_output
//! ```
//!
//! and says in its commit why the outputs moved. The hashes are of one machine kind's floating
//! point (x86_64, glibc's libm); on another kind they may differ and the test says which cases.

mod common;

use std::fmt::Write as _;

use common::adversarial::cases;
use common::planted::{drawn_three_ways, random_chains};
use kansei::chain::Continuity;
use kansei::export::CurveFile;
use kansei::pipeline::{
    FitOutput, PipelineOptions, StrokeOutcome, fit_file, fit_stroke, fit_with_noise,
};
use kansei::stroke::Units;

/// Planted chains in the sweep (each drawn three ways).
const PLANTED_CASES: usize = 40;
/// Adversarial strokes per class (8 classes).
const ADVERSARIAL_PER_CLASS: usize = 25;
/// The adversarial generator's seed, as tests/adversarial_strokes.rs.
const ADVERSARIAL_SEED: u64 = 0x6b61_6e73_6569;

/// FNV-1a, 64 bits: a stable hash with no dependency (not for security, only for identity).
fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

fn line(out: &mut String, name: &str, json: &str) {
    let _ = writeln!(out, "{name} {:016x} {}", fnv1a(json.as_bytes()), json.len());
}

fn options(continuity: Continuity) -> PipelineOptions {
    let mut options = PipelineOptions::default();
    options.chain.continuity = continuity;
    options
}

/// Every case's line, in a fixed order.
fn digest() -> String {
    let mut out = String::new();
    let modes = [
        ("g1", Continuity::G1),
        ("g2", Continuity::G2),
        ("c3", Continuity::C3),
    ];
    for name in common::fixture_names() {
        let file = common::fixture(&name);
        for (mode, continuity) in modes {
            let json = match fit_file(&file, &options(continuity)) {
                Ok(output) => CurveFile::from_output(&output).to_json(),
                Err(e) => format!("error: {e}"),
            };
            line(&mut out, &format!("fixture/{name}/{mode}"), &json);
        }
    }
    for (i, truth) in random_chains(1, PLANTED_CASES).iter().enumerate() {
        let drawn = drawn_three_ways(truth, i as u64);
        for (kind, stroke, units) in [
            ("pixels", &drawn.pixels, Units::Px),
            ("jittered", &drawn.jittered, Units::Px),
            ("tablet", &drawn.tablet, Units::Mm),
        ] {
            let options = PipelineOptions::default();
            let json = match fit_with_noise(stroke, 0, units, &options) {
                StrokeOutcome::Curves(curves) => {
                    let tolerance = options.tolerance_for(units);
                    CurveFile::from_output(&FitOutput::with_curves(units, tolerance, curves))
                        .to_json()
                }
                other => format!("{other:?}"),
            };
            line(&mut out, &format!("planted/{i}/{kind}"), &json);
        }
    }
    for case in cases(ADVERSARIAL_PER_CLASS, ADVERSARIAL_SEED) {
        for (mode, continuity) in [("g1", Continuity::G1), ("g2", Continuity::G2)] {
            let json = match fit_stroke(&case.stroke, 0, case.tolerance, &options(continuity)) {
                Ok(curves) => CurveFile::from_output(&FitOutput::with_curves(
                    case.units,
                    case.tolerance,
                    curves,
                ))
                .to_json(),
                Err(e) => format!("error: {e}"),
            };
            line(
                &mut out,
                &format!("adversarial/{}/{mode}", case.name),
                &json,
            );
        }
    }
    out
}

#[test]
fn every_fit_is_byte_for_byte_as_recorded() {
    let now = digest();
    if let Ok(path) = std::env::var("KANSEI_SAME_OUTPUT_WRITE") {
        std::fs::write(&path, &now).unwrap_or_else(|e| panic!("{path}: {e}"));
        return;
    }
    let path = format!("{}/fixtures/same-output.txt", env!("CARGO_MANIFEST_DIR"));
    let recorded = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let differ: Vec<String> = recorded
        .lines()
        .zip(now.lines())
        .filter(|(a, b)| a != b)
        .map(|(a, b)| format!("recorded {a}\n     now {b}"))
        .collect();
    let (r, n) = (recorded.lines().count(), now.lines().count());
    assert!(
        differ.is_empty() && r == n,
        "{} of {r} recorded fits differ ({n} now):\n{}",
        differ.len(),
        differ.join("\n")
    );
}
