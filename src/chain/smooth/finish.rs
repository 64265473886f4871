//! The smooth chain's record: each segment's samples, distances and α evidence, the joints'
//! kinds, laid out forward so that joints meet exactly.

use super::SmoothInput;
use super::layout::Layout;
use super::solver::{Evaluation, deviation_from};
use crate::chain::assign::{param_interval, tile_ranges};
use crate::chain::record::{Chain, ChainSegment};
use crate::geom::{Point, Vec2};
use crate::lac::{AlphaChoice, LacSegment};

/// The chain record of a solved smooth chain.
pub(super) fn finish(
    smooth: &SmoothInput,
    layout: &Layout,
    e: &Evaluation,
    assign: &[Vec<usize>],
    max_deviation: f64,
) -> Chain {
    let input = smooth.input;
    let starts: Vec<Option<usize>> = assign
        .iter()
        .map(|l| l.iter().map(|&i| input.indices[i]).min())
        .collect();
    // The part's own sample range: a part between corners inside the piece must not reach
    // its neighbours' samples.
    let part = match (
        smooth.chain.segments.iter().find(|s| s.params.is_some()),
        smooth.chain.segments.last(),
    ) {
        (Some(first), Some(last)) => (first.samples.0, last.samples.1),
        _ => input.samples,
    };
    let ranges = tile_ranges(&starts, part);
    let n = layout.n();
    let segments = (0..n)
        .map(|k| {
            let r = &e.residuals[k];
            let max = r.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            let rms = if r.is_empty() {
                0.0
            } else {
                (r.iter().map(|v| v * v).sum::<f64>() / r.len() as f64).sqrt()
            };
            let params = param_interval(input.params, &assign[k]);
            ChainSegment {
                segment: e.segments[k],
                samples: ranges[k],
                max_deviation: max,
                rms_deviation: rms,
                search: smooth.chain.segments[layout.origin[k]].search.clone(),
                alpha_source: crate::chain::alpha_evidence::AlphaSource::of_smooth(
                    e.segments[k].alpha(),
                    smooth.alpha,
                ),
                alpha_bound: crate::chain::alpha_evidence::AlphaBound::of(
                    e.segments[k].alpha(),
                    smooth.alpha,
                ),
                alpha_uncertainty: smooth_alpha_uncertainty(
                    smooth,
                    &e.segments[k],
                    &assign[k],
                    r,
                    &e.feet[k],
                ),
                start: layout.kinds[k],
                end: if k + 1 < n {
                    layout.kinds[k + 1]
                } else {
                    layout.end_kind
                },
                params,
            }
        })
        .collect();
    Chain {
        segments,
        max_deviation,
        within_tolerance: max_deviation <= smooth.tolerance,
        refined: smooth.chain.refined,
        continuity: smooth.continuity,
    }
}

/// The standard error of a smooth segment's α given its end points and tangents (as for the G1
/// chain's segments, [`super::alpha_evidence`]): the segment rebuilt through them at α ± h by
/// the Yoshida–Saito construction, its samples' signed distances differenced. Its end
/// curvatures then move with α, which the G2 chain does not allow: the figure says how well the
/// samples tell α with the joints' positions and tangents held, not the chain's own conditional.
/// `None` for no α or a fixed one, or where the constructions fail.
pub(super) fn smooth_alpha_uncertainty(
    smooth: &SmoothInput,
    segment: &LacSegment,
    samples: &[usize],
    residuals: &[f64],
    feet: &[f64],
) -> Option<f64> {
    let alpha = segment.alpha()?;
    if matches!(smooth.alpha, AlphaChoice::Fixed(_)) {
        return None;
    }
    let points: Vec<Point> = samples.iter().map(|&i| smooth.input.points[i]).collect();
    let tangent = |theta: f64| Vec2::new(theta.cos(), theta.sin());
    let signed = |x: f64| -> Option<Vec<f64>> {
        let probe = crate::lac::yoshida_saito::fit_g1_near(
            segment.start(),
            tangent(segment.theta0()),
            segment.end(),
            tangent(segment.theta1()),
            x,
            Some(segment),
        )
        .ok()?;
        // The probe is the segment a step of α away: its feet are polished from the
        // segment's own.
        let d = deviation_from(
            &probe,
            &points,
            (feet, segment.length()),
            smooth.chord_error,
        );
        Some(d.signed_distances())
    };
    let step = crate::chain::alpha_evidence::ALPHA_DIFFERENCE_STEP;
    let (minus, plus) = (signed(alpha - step), signed(alpha + step));
    crate::chain::alpha_evidence::alpha_uncertainty(residuals, minus.as_deref(), plus.as_deref())
}
