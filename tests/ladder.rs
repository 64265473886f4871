//! Loosening the tolerance never adds segments nor pieces: every fixture stroke fitted at a
//! ladder of tolerances from its own (the default: the unit's, raised to its noise floor) up to
//! three times it, between and on the fitter's rungs, has a segment count and a piece count that
//! never rise (the pieces: its corners are read at its own tolerance on every rung); where the
//! stroke's own fit holds its tolerance, every looser fit holds the one it was asked for. The
//! scribble fixture keeps its pieces up to eight times its tolerance.

use std::path::Path;

use kansei::pipeline::{PipelineOptions, StrokeOutcome, fit_with_noise};
use kansei::stroke::StrokeFile;

/// Multiples of a stroke's own tolerance: on rungs of the ladder (1, 1.1², 1.1⁵ …) and between
/// them, up to 3.
const FACTORS: [f64; 6] = [1.0, 1.05, 1.21, 1.5, 1.9, 3.0];

/// The chain's reported largest distance is measured on a trace with a chord error of 1e-3 of
/// the tolerance the chain was fitted at (`chain::fit`): at most that much short of the exact.
const REPORT_CHORD_FRACTION: f64 = 1e-3;

fn files() -> Vec<std::path::PathBuf> {
    let mut files = Vec::new();
    for dir in ["fixtures/strokes", "fixtures/synthetic"] {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join(dir);
        for entry in std::fs::read_dir(&dir).expect("fixture directory") {
            let path = entry.expect("entry").path();
            if path.extension().is_some_and(|e| e == "json") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

#[test]
fn loosening_the_tolerance_never_adds_segments_on_any_fixture_stroke() {
    let mut strokes = 0;
    for path in files() {
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("?");
        let text = std::fs::read_to_string(&path).expect("readable fixture");
        let file = StrokeFile::read_json(&text).expect("fixture parses");
        for (index, stroke) in file.strokes.iter().enumerate() {
            let own = PipelineOptions::default()
                .stroke_tolerance(stroke, file.units)
                .own;
            let mut previous: Option<(f64, usize, usize)> = None;
            let mut own_held = None;
            for factor in FACTORS {
                let tolerance = own * factor;
                let options = PipelineOptions::default().with_tolerance(tolerance);
                let (segments, pieces) = match fit_with_noise(stroke, index, file.units, &options) {
                    StrokeOutcome::Curves(curves) => {
                        let mut held = true;
                        for c in &curves {
                            let chain = c.chain.as_ref().expect("a chain");
                            assert_eq!(c.tolerance, tolerance, "{name} stroke {index}");
                            // The report is honest either way.
                            let slack = tolerance * REPORT_CHORD_FRACTION;
                            if chain.within_tolerance {
                                assert!(
                                    chain.max_deviation <= tolerance + slack,
                                    "{name} stroke {index} at {tolerance}: max {}",
                                    chain.max_deviation
                                );
                            } else {
                                assert!(chain.max_deviation > tolerance - slack);
                                held = false;
                            }
                        }
                        // The stroke's own fit is the ladder's first rung: where it holds,
                        // every looser fit holds too.
                        match own_held {
                            None => own_held = Some(held),
                            Some(true) => assert!(held, "{name} stroke {index} at {tolerance}"),
                            Some(false) => {}
                        }
                        let segments = curves
                            .iter()
                            .map(|c| c.chain.as_ref().map_or(0, |ch| ch.segments.len()))
                            .sum();
                        (segments, curves.len())
                    }
                    StrokeOutcome::Dot(_) => {
                        own_held.get_or_insert(true);
                        (0, 0)
                    }
                    StrokeOutcome::Failed(f) => {
                        // Strokes the default cannot fit are not this test's subject.
                        assert_eq!(factor, 1.0, "{name} stroke {index}: {}", f.message);
                        break;
                    }
                };
                if let Some((t, n, p)) = previous {
                    assert!(
                        segments <= n,
                        "{name} stroke {index}: {n} segments at {t}, {segments} at {tolerance}"
                    );
                    assert!(
                        pieces <= p,
                        "{name} stroke {index}: {p} pieces at {t}, {pieces} at {tolerance}"
                    );
                }
                previous = Some((tolerance, segments, pieces));
            }
            strokes += 1;
        }
    }
    assert!(strokes > 50, "only {strokes} strokes");
}

/// The scribble fixture (issue 44: 12 pieces at 1 px, 16 at 2, 17 at 4, with new corners at
/// smooth turns) keeps its pieces from 1 px to 8 px, and its segments never rise.
#[test]
fn loosening_the_scribble_keeps_its_pieces() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures/strokes/perfect-freehand-scribble.json");
    let text = std::fs::read_to_string(&path).expect("readable fixture");
    let file = StrokeFile::read_json(&text).expect("fixture parses");
    let mut previous: Option<(f64, usize, usize)> = None;
    for tolerance in [1.0, 2.0, 4.0, 8.0] {
        let options = PipelineOptions::default().with_tolerance(tolerance);
        let StrokeOutcome::Curves(curves) =
            fit_with_noise(&file.strokes[0], 0, file.units, &options)
        else {
            panic!("the scribble is a curve at {tolerance}");
        };
        let segments: usize = curves
            .iter()
            .map(|c| c.chain.as_ref().map_or(0, |ch| ch.segments.len()))
            .sum();
        if let Some((t, n, p)) = previous {
            assert!(
                curves.len() <= p,
                "{p} pieces at {t}, {} at {tolerance}",
                curves.len()
            );
            assert!(
                segments <= n,
                "{n} segments at {t}, {segments} at {tolerance}"
            );
        }
        previous = Some((tolerance, segments, curves.len()));
    }
}
