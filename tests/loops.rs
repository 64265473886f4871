//! Strokes that come back near themselves (`tests/common/loops.rs`: circles, ellipses,
//! superellipses and blobs from 0.9 to 2 turns, figure eights open and closed, cursive loops,
//! spirals; with a mouse on whole pixels and on a tablet in mm), through the default pipeline.
//!
//! What holds today, asserted: the record is honest (every chain's `max_deviation` is each
//! sample's distance to its own segment, measured here on the segments' dense polylines, and
//! every chain that says it is within the tolerance is), and a shape that passes near its start
//! no longer collapses into a polyline of one segment per sample; a shape drawn round once or
//! more comes back as one closed curve, its seam as continuous as its other joints. The figures
//! per class come from `cargo run --release --example loop_shapes`.

mod common;

use common::adversarial::{CHECK_CHORD_FRACTION, chain_polyline, own_segment_deviation};
use common::loops::{shapes, truth_for};
use kansei::chain::Continuity;
use kansei::lac::LacSegment;
use kansei::pipeline::{PipelineOptions, StrokeOutcome, fit_with_noise};

/// Shapes per class (each drawn with a mouse and on a tablet).
const PER_CLASS: usize = 2;

/// The generator's seed.
const SEED: u64 = 44;

/// The record states the honest measure, and the guarantee it states holds.
#[test]
fn the_record_is_each_sample_against_its_own_segment() {
    let mut broken = Vec::new();
    for shape in shapes(PER_CLASS, SEED) {
        let StrokeOutcome::Curves(curves) =
            fit_with_noise(&shape.stroke, 0, shape.units, &PipelineOptions::default())
        else {
            broken.push(format!("{}: no curves", shape.name));
            continue;
        };
        for fit in &curves {
            let Some(chain) = &fit.chain else { continue };
            let segments: Vec<&LacSegment> = chain.segments.iter().map(|s| &s.segment).collect();
            let tolerance = fit.tolerance;
            let (lines, delta) = chain_polyline(&segments, CHECK_CHORD_FRACTION * tolerance);
            let measured = own_segment_deviation(chain, &lines, &shape.stroke.samples, fit.samples);
            let slack = delta + CHECK_CHORD_FRACTION * tolerance + 1e-9 * 1000.0;
            if (measured - chain.max_deviation).abs() > slack {
                broken.push(format!(
                    "{} samples {:?}: max_deviation {} but each sample to its own segment {measured}",
                    shape.name, fit.samples, chain.max_deviation
                ));
            }
            if chain.within_tolerance && measured > tolerance + slack {
                broken.push(format!(
                    "{} samples {:?}: within_tolerance but {measured} > {tolerance}",
                    shape.name, fit.samples
                ));
            }
        }
    }
    assert!(broken.is_empty(), "{}", broken.join("\n"));
}

/// Circles, ellipses and blobs drawn past their start (up to two turns) come back as smooth
/// chains of a few segments per turn, not as one line per sample (before the B-spline's feet
/// followed the stroke's order, a circle drawn one sample past its start became 162 segments,
/// `g1`), and every point of the chain lies within the tolerance of the shape drawn, and back
/// (plus the samples' own distance from the shape: a mouse's whole pixels put the last sample up
/// to 0.7 px off it, and the chain ends within the tolerance of that sample).
#[test]
fn closed_shapes_drawn_past_their_start_do_not_collapse() {
    let mut broken = Vec::new();
    for shape in shapes(PER_CLASS, SEED)
        .into_iter()
        .filter(|s| matches!(s.class, "circle" | "ellipse"))
    {
        let StrokeOutcome::Curves(curves) =
            fit_with_noise(&shape.stroke, 0, shape.units, &PipelineOptions::default())
        else {
            broken.push(format!("{}: no curves", shape.name));
            continue;
        };
        let tolerance = curves[0].tolerance;
        let closed = curves.iter().any(|c| c.closure.is_some());
        // A closed curve bridges the gap where the stroke stopped short of its start: its
        // points there lie up to half the gap from the ink's ends.
        let bridge = curves
            .iter()
            .filter_map(|c| c.closure)
            .map(|c| 0.5 * c.gap)
            .fold(0.0, f64::max);
        let truth = truth_for(&shape, closed);
        let chains: Vec<_> = curves.into_iter().filter_map(|c| c.chain).collect();
        let segments: usize = chains.iter().map(|c| c.segments.len()).sum();
        // A circle is one arc per turn, an ellipse about one segment per quarter: eight per turn
        // is a generous bound that a collapse (hundreds) breaks.
        let bound = (8.0 * shape.turns).ceil() as usize;
        if chains.len() != 1 || segments > bound {
            broken.push(format!(
                "{}: {} pieces, {segments} segments for {:.2} turns",
                shape.name,
                chains.len(),
                shape.turns
            ));
        }
        if chains
            .iter()
            .any(|c| c.continuity == Continuity::G1 && c.segments.len() > 1)
        {
            broken.push(format!("{}: fell back to g1", shape.name));
        }
        // Within the tolerance of the samples, which lie within their own error of the shape
        // (one round of it where the fit closed).
        let (there, back) = common::loops::two_way_distance(&chains, &truth);
        let drawn = common::loops::sample_error(&shape.stroke, &truth);
        if there > tolerance + drawn + bridge || back > tolerance + drawn {
            broken.push(format!(
                "{}: chain to shape {:.2}, shape to chain {:.2} tolerances",
                shape.name,
                there / tolerance,
                back / tolerance
            ));
        }
    }
    assert!(broken.is_empty(), "{}", broken.join("\n"));
}

/// Largest gap at a closed chain's seam, relative to the chain's size: the smooth fit lays the
/// chain out forward and meets its end point to 1e-10 of its extent (`END_TOLERANCE`) and its
/// end angle to 1e-9 rad (`C3_TOLERANCE`); the curvature on both sides is one number.
const SEAM_GAP: f64 = 1e-9;

/// A shape drawn round once or more (circles, ellipses, superellipses, blobs, closed figure
/// eights; up to two turns, mouse and tablet) comes back as one closed curve: `closed`, a smooth
/// closure, G2 throughout with the seam as continuous as any joint (its point, tangent and
/// curvature met to [`SEAM_GAP`]), one round long (the overshoot and a second round folded onto
/// it, within twice the tolerance), within the tolerance of one round of the shape and back
/// (plus the samples' own error), in at most twelve segments per round (sixteen for the
/// superellipse's four tight corners, the blob's wobbles and the eight's two lobes; the
/// example's figures per class are in docs/pipeline.md).
#[test]
fn closed_shapes_come_back_as_one_closed_curve() {
    let mut broken = Vec::new();
    for shape in shapes(PER_CLASS, SEED).into_iter().filter(|s| s.closed) {
        let StrokeOutcome::Curves(curves) =
            fit_with_noise(&shape.stroke, 0, shape.units, &PipelineOptions::default())
        else {
            broken.push(format!("{}: no curves", shape.name));
            continue;
        };
        let name = &shape.name;
        let tolerance = curves[0].tolerance;
        let [curve] = curves.as_slice() else {
            broken.push(format!("{name}: {} pieces", curves.len()));
            continue;
        };
        let Some(closure) = curve.closure else {
            broken.push(format!("{name}: not closed"));
            continue;
        };
        if !(closure.whole && closure.kind == kansei::closure::ClosureKind::Smooth) {
            broken.push(format!("{name}: {closure:?}"));
        }
        if closure.folded_deviation > kansei::closure::FOLDED_TOLERANCES * tolerance {
            broken.push(format!("{name}: folded {:.3}", closure.folded_deviation));
        }
        let Some(chain) = &curve.chain else {
            broken.push(format!("{name}: no chain"));
            continue;
        };
        if chain.continuity != Continuity::G2 || !chain.within_tolerance {
            broken.push(format!(
                "{name}: {:?}, {:.3} of {tolerance:.3}",
                chain.continuity, chain.max_deviation
            ));
        }
        let (first, last) = (
            &chain.segments[0].segment,
            &chain.segments[chain.segments.len() - 1].segment,
        );
        let size: f64 = chain.segments.iter().map(|s| s.segment.length()).sum();
        let turn = std::f64::consts::TAU;
        let tangent = last.theta1() - first.theta0();
        let tangent_gap = (tangent - turn * (tangent / turn).round()).abs();
        // Relative to the larger side, or to the chain's own scale where both are near zero
        // (a seam at an inflection holds κ = 0 on both sides, up to the end's rounding).
        let kappa_gap = (last.kappa1() - first.kappa0()).abs()
            / first
                .kappa0()
                .abs()
                .max(last.kappa1().abs())
                .max(1.0 / size);
        if last.end().distance(first.start()) > SEAM_GAP * size
            || tangent_gap > SEAM_GAP
            || kappa_gap > SEAM_GAP
        {
            broken.push(format!(
                "{name}: seam gap {:.2e}, tangent {tangent_gap:.2e}, curvature {kappa_gap:.2e}",
                last.end().distance(first.start()) / size
            ));
        }
        let bound = match shape.class {
            "circle" | "ellipse" => 12,
            _ => 16,
        };
        if chain.segments.len() > bound {
            broken.push(format!("{name}: {} segments", chain.segments.len()));
        }
        let truth = truth_for(&shape, true);
        let (there, back) = common::loops::two_way_distance(std::slice::from_ref(chain), &truth);
        let drawn = common::loops::sample_error(&shape.stroke, &truth);
        if there.max(back) > tolerance + drawn {
            broken.push(format!(
                "{name}: chain to shape {:.2}, shape to chain {:.2} tolerances",
                there / tolerance,
                back / tolerance
            ));
        }
    }
    assert!(broken.is_empty(), "{}", broken.join("\n"));
}
