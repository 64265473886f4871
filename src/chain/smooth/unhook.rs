//! A hook at a corner made a corner: the last resort of the smooth chain against a segment that
//! curls into one of its free ends.
//!
//! A segment between two corners (or a corner and the stroke's own end) has both tangents free.
//! Where it still bends beyond the curvature bound at one end after the turned tangents of
//! [`super::smooth`]'s softening (`soften_isolated`) found no segment within the tolerance, the
//! samples at that end turn faster than any segment the bound allows: the pen hooked there (a
//! painting stroke reversing at sample spacings of 20 px: κ = 100 /px at the corner, a radius of
//! a hundredth of a pixel that no two samples show). Rather than keep a needle, the hook is said
//! as what it is:
//!
//! 1. if the straight line between the segment's ends holds all its samples within the
//!    tolerance (or it holds none), the segment becomes that line;
//! 2. a segment holding a single sample becomes two lines meeting at a corner there;
//! 3. otherwise the sample next to the curled end becomes a corner (then the next one, up to
//!    [`MAX_HOOK_SAMPLES`]): a line from the end to that sample holds the samples before it, and
//!    a segment from it to the other end (its tangent at first the old segment's there, then
//!    the softening's turns) holds the rest within the tolerance and the bound.
//!
//! Every sample stays within the tolerance of its segment (each candidate is measured before it
//! is taken); the chain gains one G0 joint per hook, never a segment bending beyond the bound.
//! Where none works the segment is kept as it is.

use super::SmoothInput;
use super::finish::smooth_alpha_uncertainty;
use crate::chain::alpha_evidence::{AlphaBound, AlphaSource};
use crate::chain::assign::{param_interval, sample_range};
use crate::chain::record::{ChainSegment, JointKind};
use crate::chain::soften::soften_fits;
use crate::geom::{Point, Vec2};
use crate::lac::LacSegment;
use crate::lac::alpha_search::{AlphaSearch, fit_span};
use crate::lac::deviation::deviation;

/// Most samples a hook may hold: a hook is the pen's turn at a corner, a sample or two before
/// the stroke goes its new way; more than that is a curve the tolerance should hold, and
/// cutting deeper would trade a needle for a corner inside the drawn shape.
pub const MAX_HOOK_SAMPLES: usize = 2;

/// The segments replacing `s`, a segment between two free ends (corners, or the stroke's own
/// ends) that curls beyond `cap` at one of them and whose own samples are the points `list` (in
/// stroke order: those of its tiled range, none shared with a neighbour): one line, or a hook
/// line and a segment meeting at a new corner, in stroke order; `None` where no replacement
/// holds its samples (see the module documentation).
pub(super) fn unhook(
    smooth: &SmoothInput,
    s: &ChainSegment,
    list: &[usize],
    cap: f64,
) -> Option<Vec<ChainSegment>> {
    let segment = s.segment;
    let bend = |seg: &LacSegment| seg.kappa0().abs().max(seg.kappa1().abs());
    let input = smooth.input;
    // A segment holding no samples may take any shape between its ends: the straight one.
    if list.is_empty() {
        let mut line = line_segment(smooth, s, segment.start(), segment.end(), &[])?;
        line.samples = s.samples;
        return Some(vec![line]);
    }
    let points: Vec<Point> = list.iter().map(|&i| input.points[i]).collect();
    let (a, b) = (segment.start(), segment.end());
    // 1. The chord.
    if let Some(line) = line_segment(smooth, s, a, b, list) {
        return Some(vec![line]);
    }
    // 2. A single sample off the chord: the corner is there, a line to it and one on.
    if let [p] = points[..] {
        let mut to = line_segment(smooth, s, a, p, list)?;
        let mut on = line_segment(smooth, s, p, b, &[])?;
        on.samples = to.samples;
        (to.end, on.start) = (JointKind::Corner, JointKind::Corner);
        return Some(vec![to, on]);
    }
    // 3. A hook cut off the curled end.
    let at_start = segment.kappa0().abs() >= segment.kappa1().abs();
    let options = smooth.soften_options(cap, segment.alpha());
    let tangent = |angle: f64| Vec2::new(angle.cos(), angle.sin());
    for m in 1..=MAX_HOOK_SAMPLES.min(points.len().saturating_sub(1)) {
        // The new corner's sample, the hook's samples and the rest's, in stroke order.
        let (corner, hook, rest) = if at_start {
            (m, 0..m, m..points.len())
        } else {
            let c = points.len() - 1 - m;
            (c, c + 1..points.len(), 0..c + 1)
        };
        let q = points[corner];
        let hook_line = if at_start {
            line_segment(smooth, s, a, q, &list[hook.clone()])
        } else {
            line_segment(smooth, s, q, b, &list[hook.clone()])
        };
        let Some(hook_line) = hook_line else {
            continue;
        };
        // The old segment's tangent where it passes the new corner's sample: past the curl.
        let foot = deviation(&segment, &[q], smooth.chord_error)
            .feet
            .first()
            .copied()?;
        let q_angle = segment.theta(foot);
        let ((from, from_angle), (to, to_angle)) = if at_start {
            ((q, q_angle), (b, segment.theta1()))
        } else {
            ((a, segment.theta0()), (q, q_angle))
        };
        let rest_list = &list[rest.clone()];
        // The rest as a line where one holds it (on a few samples, often), else as a segment.
        let rest_line = if at_start {
            line_segment(smooth, s, q, b, rest_list)
        } else {
            line_segment(smooth, s, a, q, rest_list)
        };
        if let Some(rest_line) = rest_line {
            return Some(if at_start {
                vec![hook_line, rest_line]
            } else {
                vec![rest_line, hook_line]
            });
        }
        let rest_points = &points[rest];
        let direct = fit_span(
            from,
            tangent(from_angle),
            to,
            tangent(to_angle),
            rest_points,
            &options,
        )
        .ok()
        .filter(|f| f.deviation.max <= smooth.tolerance && bend(&f.segment) <= cap);
        let fit = direct.or_else(|| {
            soften_fits(
                (from, from_angle),
                (to, to_angle),
                at_start,
                true,
                rest_points,
                options,
                smooth.tolerance,
            )
            .next()
            .map(|(_, f)| f)
        });
        let Some(fit) = fit else {
            continue;
        };
        let d = &fit.deviation;
        let curve = ChainSegment {
            segment: fit.segment,
            samples: sample_range(input.indices, rest_list),
            max_deviation: d.max,
            rms_deviation: d.rms,
            alpha_source: AlphaSource::of_g1(fit.segment.alpha(), &fit.search, smooth.alpha),
            search: fit.search.clone(),
            start: if at_start { JointKind::Corner } else { s.start },
            end: if at_start { s.end } else { JointKind::Corner },
            params: param_interval(input.params, rest_list),
            alpha_bound: AlphaBound::of(fit.segment.alpha(), smooth.alpha),
            alpha_uncertainty: smooth_alpha_uncertainty(
                smooth,
                &fit.segment,
                rest_list,
                &d.signed_distances(),
                &d.feet,
            ),
        };
        return Some(if at_start {
            vec![hook_line, curve]
        } else {
            vec![curve, hook_line]
        });
    }
    None
}

/// The line from `a` to `b` as a chain segment holding the samples `list` (point indices, in
/// stroke order), with `s`'s joint kinds where it shares an end with `s` and a corner
/// elsewhere; `None` where a sample lies beyond the tolerance or the ends coincide. Without
/// samples it holds none (no parameter interval; the caller sets its one-sample range).
pub(super) fn line_segment(
    smooth: &SmoothInput,
    s: &ChainSegment,
    a: Point,
    b: Point,
    list: &[usize],
) -> Option<ChainSegment> {
    let input = smooth.input;
    let chord = b - a;
    let length = chord.hypot();
    if !(length > 0.0) {
        return None;
    }
    let line = LacSegment::new(a, chord.y.atan2(chord.x), length, None, 0.0, 0.0).ok()?;
    let points: Vec<Point> = list.iter().map(|&i| input.points[i]).collect();
    let (max, rms) = if points.is_empty() {
        (0.0, 0.0)
    } else {
        let d = deviation(&line, &points, smooth.chord_error);
        if !(d.max <= smooth.tolerance) {
            return None;
        }
        (d.max, d.rms)
    };
    let (start_shared, end_shared) = (a == s.segment.start(), b == s.segment.end());
    Some(ChainSegment {
        segment: line,
        samples: sample_range(input.indices, list),
        max_deviation: max,
        rms_deviation: rms,
        search: AlphaSearch {
            alpha: None,
            rms,
            ..AlphaSearch::default()
        },
        start: if start_shared {
            s.start
        } else {
            JointKind::Corner
        },
        end: if end_shared { s.end } else { JointKind::Corner },
        params: param_interval(input.params, list),
        alpha_bound: None,
        alpha_source: None,
        alpha_uncertainty: None,
    })
}
