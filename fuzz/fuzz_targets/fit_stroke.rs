//! Arbitrary small strokes through the whole pipeline (`pipeline::fit_one`), as a browser pen on
//! a pixel grid draws them: a few dozen samples on a grid, with reversals, repeats and collinear
//! runs, since every byte pair is a small move. Fails on a panic, on any failure other than a
//! documented input error, and on a broken guarantee (checked independently of the fitter's own
//! report by `tests/common/adversarial.rs`: distance of every represented sample to the chain,
//! ranges tiling their piece, every α accounted for by its record's `alpha_source`).
#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "../../tests/common/adversarial.rs"]
mod adversarial;

use kansei::pipeline::{FailureKind, PipelineOptions, StrokeOutcome, fit_one};
use kansei::stroke::Units;

fuzz_target!(|data: &[u8]| {
    let Some((stroke, tolerance)) = adversarial::stroke_from_bytes(data) else {
        return;
    };
    let options = PipelineOptions::default().with_tolerance(tolerance);
    match fit_one(&stroke, 0, tolerance, &options) {
        StrokeOutcome::Dot(dot) => {
            assert!(dot.max_deviation <= tolerance, "a dot beyond the tolerance");
        }
        StrokeOutcome::Failed(f) => {
            assert!(
                f.kind == FailureKind::Input,
                "the fitter failed on a valid stroke: {}",
                f.message
            );
        }
        StrokeOutcome::Curves(curves) => {
            let case = adversarial::Case {
                name: "fuzz".into(),
                stroke,
                units: Units::Px,
                tolerance,
            };
            let breaks = adversarial::check(&case, &Ok(curves));
            assert!(breaks.ok(), "{breaks:?}");
        }
    }
});
