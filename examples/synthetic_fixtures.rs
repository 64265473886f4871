//! Writes the synthetic fixtures `fixtures/synthetic/synthetic-*.json`: small strokes of the kinds
//! that broke the pipeline on real browser-pen handwriting (whole pixels, px units), drawn by the
//! deterministic generator of `tests/common/adversarial.rs` (seeded: the files are the same on
//! every run). Run from the repository root:
//!
//! ```sh
//! cargo run --example synthetic_fixtures
//! ```
//!
//! It refuses to replace a fixture that differs from what it would write, unless given
//! `--replace` (a fixture is a recorded oracle: changing it is a decision).

#[path = "../tests/common/adversarial.rs"]
mod adversarial;

use adversarial::{SplitMix, points_of};
use kansei::geom::Point;
use kansei::stroke::{Sample, Stroke, StrokeFile, Units};

/// Strokes per class in a file.
const PER_FILE: usize = 12;
/// The generator's seed for these files.
const SEED: u64 = 0x6b61_6e73_6569;

fn stroke(points: &[Point]) -> Stroke {
    Stroke::new(
        points
            .iter()
            .enumerate()
            .map(|(k, p)| Sample::new(p.x, p.y).with_t(k as f64 * 0.008))
            .collect(),
    )
}

fn main() -> std::process::ExitCode {
    let replace = std::env::args().any(|a| a == "--replace");
    let mut rng = SplitMix::new(SEED);
    let mut files: Vec<(&str, Vec<Stroke>)> = Vec::new();
    for (name, class) in [
        ("synthetic-reversals", "reversal"),
        ("synthetic-jiggle", "jiggle"),
        ("synthetic-pixel-grid", "pixel-grid"),
    ] {
        let strokes = (0..PER_FILE)
            .map(|_| stroke(&points_of(class, &mut rng)))
            .collect();
        files.push((name, strokes));
    }
    // Taps between letters: a tap (one position, repeated), a tap with a pixel of tremor, a
    // stroke of a few distinct points, and a short line, in turn.
    let mut taps = Vec::new();
    for i in 0..PER_FILE {
        let x = 40.0 + 30.0 * i as f64;
        let spot = Point::new(x, 100.0);
        taps.push(match i % 4 {
            0 => stroke(&[spot; 3]),
            1 => stroke(&[spot, Point::new(x + 1.0, 100.0), spot, Point::new(x, 99.0)]),
            2 => stroke(&points_of("few-distinct", &mut rng)),
            _ => stroke(
                &(0..12)
                    .map(|k| Point::new(x, 80.0 + 2.0 * k as f64))
                    .collect::<Vec<_>>(),
            ),
        });
    }
    files.push(("synthetic-taps", taps));
    let mut failed = false;
    for (name, strokes) in files {
        let mut file = StrokeFile::new(Units::Px, strokes);
        file.source = Some(format!(
            "synthetic, this project's (MIT OR Apache-2.0): examples/synthetic_fixtures.rs, \
             generator tests/common/adversarial.rs, seed {SEED:#x}"
        ));
        let path = format!("fixtures/synthetic/{name}.json");
        let text = file.to_json();
        match std::fs::read_to_string(&path) {
            Ok(old) if old == text => println!("{path}: unchanged"),
            Ok(_) if !replace => {
                eprintln!("{path}: differs from what this would write; --replace to replace it");
                failed = true;
            }
            _ => match kansei::io::write_atomic(std::path::Path::new(&path), text.as_bytes()) {
                Ok(()) => println!("{path}: written ({} strokes)", file.strokes.len()),
                Err(e) => {
                    eprintln!("{e}");
                    failed = true;
                }
            },
        }
    }
    if failed {
        std::process::ExitCode::FAILURE
    } else {
        std::process::ExitCode::SUCCESS
    }
}
