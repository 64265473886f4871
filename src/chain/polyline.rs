//! The last resort of a chain that misses its tolerance: the samples joined by lines.
//!
//! Every cut and refit of the chain (subdivision to [`super::ChainOptions::max_depth`], the
//! smooth fit's cut rounds) can still leave a segment whose own samples lie farther than the
//! tolerance from it. That happens where the samples zigzag at the scale of the tolerance: a
//! mouse jiggling within a pixel or two, a random walk on the pixel grid (two of the 48
//! synthetic fixture strokes, 0.73 and 0.81 px off at a 0.71 px tolerance). No smooth curve
//! tells such samples from a zigzag, and the polyline through them is what they show: such a
//! segment becomes the lines from its start through each of its own samples to its end,
//! meeting at corners (G0 joints, as a smooth chain's corners are), every sample on a vertex.
//! Its neighbours meet the first and the last line at corners too. A chain within its tolerance
//! is never touched, and the replacement is taken only where the whole chain then holds.

use super::assign::{own_points, param_interval, retile, sample_range};
use super::measure::measured_deviation;
use super::record::{Chain, ChainInput, ChainSegment, JointKind};
use crate::geom::Point;
use crate::lac::LacSegment;
use crate::lac::alpha_search::AlphaSearch;

/// `chain` with every segment whose own samples miss `tolerance` replaced by the polyline
/// through them (see the module documentation), where the chain misses its tolerance and the
/// replaced chain holds it; `None` otherwise (the chain stands).
pub(crate) fn join_missing(
    input: &ChainInput,
    chain: &Chain,
    tolerance: f64,
    chord_error: f64,
) -> Option<Chain> {
    if chain.within_tolerance {
        return None;
    }
    let lists = own_points(input, &chain.segments);
    let mut out: Vec<ChainSegment> = Vec::with_capacity(chain.segments.len());
    let mut replaced = false;
    // Whether the last segment pushed ends at a polyline (the next one starts at a corner).
    let mut after_polyline = false;
    for (s, list) in chain.segments.iter().zip(&lists) {
        let misses = !list.is_empty() && !(s.max_deviation <= tolerance);
        let lines = if misses {
            polyline(input, s, list)
        } else {
            None
        };
        match lines {
            Some(lines) => {
                replaced = true;
                if let Some(previous) = out.last_mut()
                    && !previous.end.tangent_free()
                {
                    previous.end = JointKind::Corner;
                }
                out.extend(lines);
                after_polyline = true;
            }
            None => {
                let mut s = s.clone();
                if after_polyline && !s.start.tangent_free() {
                    s.start = JointKind::Corner;
                }
                out.push(s);
                after_polyline = false;
            }
        }
    }
    if !replaced {
        return None;
    }
    retile(&mut out, input.samples);
    let lists = own_points(input, &out);
    let max_deviation = measured_deviation(input, &out, &lists, chord_error);
    (max_deviation <= tolerance).then(|| Chain {
        segments: out,
        max_deviation,
        within_tolerance: true,
        ..chain.clone()
    })
}

/// The lines from `s`'s start through its own points `list` (in stroke order) to its end: the
/// line ending at a point holds it, the last line (from the last point to the end, where they
/// differ) holds none. `None` where a line cannot be built.
fn polyline(input: &ChainInput, s: &ChainSegment, list: &[usize]) -> Option<Vec<ChainSegment>> {
    // Vertices: the start, each point (with the points it holds), the end.
    let mut vertices: Vec<(Point, Vec<usize>)> = vec![(s.segment.start(), Vec::new())];
    for &i in list {
        let p = input.points[i];
        match vertices.last_mut() {
            Some((q, held)) if *q == p => held.push(i),
            _ => vertices.push((p, vec![i])),
        }
    }
    let end = s.segment.end();
    if vertices.last().is_some_and(|(q, _)| *q != end) {
        vertices.push((end, Vec::new()));
    }
    let mut lines = Vec::with_capacity(vertices.len());
    let count = vertices.len() - 1;
    for (j, pair) in vertices.windows(2).enumerate() {
        let ((a, _), (b, held)) = (&pair[0], &pair[1]);
        let chord = *b - *a;
        let length = chord.hypot();
        let line = LacSegment::new(*a, chord.y.atan2(chord.x), length, None, 0.0, 0.0).ok()?;
        let mut held = held.clone();
        // Points on the start itself lie on the first line's start.
        if j == 0 {
            held.splice(0..0, vertices[0].1.iter().copied());
        }
        lines.push(ChainSegment {
            segment: line,
            samples: if held.is_empty() {
                // Sample-less: re-tiled by the caller.
                (s.samples.1, s.samples.1)
            } else {
                sample_range(input.indices, &held)
            },
            max_deviation: 0.0,
            rms_deviation: 0.0,
            search: AlphaSearch {
                alpha: None,
                ..AlphaSearch::default()
            },
            start: if j == 0 { s.start } else { JointKind::Corner },
            end: if j + 1 == count {
                s.end
            } else {
                JointKind::Corner
            },
            params: param_interval(input.params, &held),
            alpha_bound: None,
            alpha_source: None,
            alpha_uncertainty: None,
        });
    }
    // The first and last lines meet the neighbours at corners (a line's curvature, 0, meets
    // theirs in a jump).
    if let Some(first) = lines.first_mut()
        && !first.start.tangent_free()
    {
        first.start = JointKind::Corner;
    }
    if let Some(last) = lines.last_mut()
        && !last.end.tangent_free()
    {
        last.end = JointKind::Corner;
    }
    (!lines.is_empty()).then_some(lines)
}
