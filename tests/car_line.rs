//! A measured car character line (`fixtures/curves/`, the Prius lines of Graiff Zurita, Kajiwara
//! and Miura's LAC fairing data, which their method fits with one log-aesthetic curve each):
//! where one segment holds the line within the tolerance, kansei answers one segment, every
//! sample within the tolerance of it by an independent measurement, its α stating that it sits
//! on the range's end where it does; and the segment count never rises as the tolerance is
//! loosened from the unit's default.

mod common;

use common::export::{grid_of, project};
use kansei::pipeline::{PipelineOptions, StrokeOutcome, fit_with_noise};
use kansei::stroke::StrokeFile;

/// The grid search finds the nearest point to ~1e-11 of a grid step (see tests/fixtures_whole.rs).
const MEASURE_SLACK: f64 = 1e-6;

fn lines() -> StrokeFile {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/fixtures/curves/prius-character-lines.json"
    );
    let text = std::fs::read_to_string(path).expect("fixture");
    StrokeFile::read_json(&text).expect("fixture parses")
}

/// Segments of one line fitted at `tolerance`, each sample's measured distance to the chain
/// checked against it.
fn fit(file: &StrokeFile, index: usize, tolerance: f64) -> Vec<kansei::chain::ChainSegment> {
    let options = PipelineOptions::default().with_tolerance(tolerance);
    let StrokeOutcome::Curves(curves) =
        fit_with_noise(&file.strokes[index], index, file.units, &options)
    else {
        panic!("line {index} at {tolerance}: no curves");
    };
    let mut out = Vec::new();
    for c in curves {
        let chain = c.chain.expect("a chain");
        assert!(chain.within_tolerance, "line {index} at {tolerance}");
        let grids: Vec<_> = chain.segments.iter().map(|s| grid_of(&s.segment)).collect();
        let samples = &file.strokes[index].samples[c.samples.0..=c.samples.1];
        for s in samples {
            let d = chain
                .segments
                .iter()
                .zip(&grids)
                .map(|(seg, grid)| project(&seg.segment, grid, s.point()).1)
                .fold(f64::INFINITY, f64::min);
            assert!(
                d <= tolerance * (1.0 + MEASURE_SLACK),
                "line {index} at {tolerance}: a sample {d} from the chain"
            );
        }
        out.extend(chain.segments);
    }
    out
}

#[test]
fn a_character_line_that_one_segment_holds_is_one_segment() {
    let file = lines();
    // ps_2 at 1.6 mm: the two-segment answer of the merges between fixed end tangents became
    // one segment once the merged segment's ends move in the refinement.
    let segments = fit(&file, 1, 1.6);
    assert_eq!(segments.len(), 1, "{segments:?}");
    let s = &segments[0];
    // Its α is where the search stopped: on the range's end, and the record says so.
    if let Some(alpha) = s.segment.alpha()
        && (alpha.abs() - 3.0).abs() <= 0.01
    {
        assert!(
            s.alpha_bound.is_some(),
            "α {alpha} on the bound without saying so"
        );
        assert!(!s.alpha_determined());
    }
}

#[test]
fn loosening_the_tolerance_never_adds_segments_on_a_character_line() {
    let file = lines();
    for index in 0..file.strokes.len() {
        let mut previous = usize::MAX;
        for tolerance in [0.1, 0.3, 1.0, 1.6, 2.5] {
            let n = fit(&file, index, tolerance).len();
            assert!(
                n <= previous,
                "line {index}: {n} segments at {tolerance}, {previous} before"
            );
            previous = n;
        }
        assert_eq!(previous, 1, "line {index}: one segment at 2.5 mm");
    }
}
