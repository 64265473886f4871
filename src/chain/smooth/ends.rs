//! The ends of a smooth part: a tail of a few samples past a tight end curl cut away, an
//! isolated segment's curling ends turned towards its chord, and the curvature cap they obey.

use super::finish::smooth_alpha_uncertainty;
use super::{MAX_TAIL_SAMPLES, MAX_TURN_PER_SAMPLE, MIN_RADIUS_TOLERANCES, SmoothInput};
use crate::chain::record::{ChainSegment, JointKind};
use crate::chain::soften::soften_fits;
use crate::geom::Point;
use crate::lac::LacSegment;

/// `segments` (a G1 chain) without its end tail, where it has one: at the stroke's own end,
/// the run of segments that each touch a joint bending beyond `cap` (a joint the smooth chain
/// would make a corner) and together hold at most [`MAX_TAIL_SAMPLES`] samples. The segment
/// before the run is extended along its own law to the chain's end (see [`extend`]) and
/// takes the run's samples; the smooth fit then moves its end (a free end moves across its
/// tangent only, so the samples must be within its reach from the start). The G1 chain's
/// subdivisions and biarc repairs at a free end, where the B-spline's end follows the last
/// samples' noise, can leave such a tangle: a planted chain on whole pixels ended in six arcs
/// of 0.1–0.9 px bending up to 18 /px over its last four samples, one drawn with tablet noise
/// in two bending to 65 and 31.6 /mm over its last three; each such joint became a corner of
/// the smooth chain and the segments after it stayed. Measured in
/// `docs/performance-history.md` (chain constants).
/// `None` where there is no tail, or the segment cannot be extended.
pub(super) fn without_end_tail(segments: &[ChainSegment], cap: f64) -> Option<Vec<ChainSegment>> {
    let n = segments.len();
    if segments.last()?.end != JointKind::End {
        return None;
    }
    // Joint j (1..n) bends beyond the cap.
    let cut = |j: usize| {
        j > 0
            && j < n
            && segments[j - 1]
                .segment
                .kappa1()
                .abs()
                .max(segments[j].segment.kappa0().abs())
                > cap
    };
    let mut t = n;
    while t > 1
        && (cut(t - 1) || cut(t))
        && segments[n - 1]
            .samples
            .1
            .saturating_sub(segments[t - 1].samples.0)
            < MAX_TAIL_SAMPLES
    {
        t -= 1;
    }
    // A tail is the end of something: the segments kept must hold samples (a short piece whose
    // every segment curls is not a tail; cut, it left one segment holding none of its samples
    // and a record that measured none of them).
    if t == n || segments[..t].iter().all(|s| s.params.is_none()) {
        return None;
    }
    let end = segments[n - 1].segment.end();
    let mut kept = segments[..t].to_vec();
    let last = kept.last_mut()?;
    let reach = last.segment.end().distance(end);
    last.segment = extend(&last.segment, last.segment.length() + reach)?;
    last.samples.1 = segments[n - 1].samples.1;
    last.end = JointKind::End;
    Some(kept)
}

/// `segment` continued along its own law to the length `length` (ρ^α affine in arc length, or
/// ρ exponential for α = 0; an arc or a line as it is); `None` for a spiral with a zero
/// curvature at either end (left as it is: a curvature that ends at zero cannot go on, and the
/// rare spiral leaving zero is not worth a special case) and where the law runs out before
/// `length` (a curvature falling to zero within it, for α < 0).
pub(super) fn extend(segment: &LacSegment, length: f64) -> Option<LacSegment> {
    let (k0, k1, l) = (segment.kappa0(), segment.kappa1(), segment.length());
    let kappa = match segment.alpha() {
        _ if k0 == k1 => k1,
        _ if k0 == 0.0 || k1 == 0.0 || !(l > 0.0) => return None,
        Some(alpha) if alpha != 0.0 => {
            let (r0, r1) = ((1.0 / k0.abs()).powf(alpha), (1.0 / k1.abs()).powf(alpha));
            let r = r0 + (r1 - r0) * length / l;
            if !(r > 0.0) {
                return None;
            }
            k1.signum() / r.powf(1.0 / alpha)
        }
        _ => k1 * (k1 / k0).abs().powf(length / l - 1.0),
    };
    if !kappa.is_finite() {
        return None;
    }
    LacSegment::new(
        segment.start(),
        segment.theta0(),
        length,
        segment.alpha(),
        k0,
        kappa,
    )
    .ok()
}

/// Refits `s`, a segment between two free ends (corners, or the stroke's own ends) curling
/// beyond `cap` at one of them, with turned end tangents: the first of [`soften_tries`] whose
/// segment (α searched again, within `cap`) holds its own samples `list` within the tolerance.
/// Returns whether it was refitted.
pub(super) fn soften_isolated(
    smooth: &SmoothInput,
    s: &mut ChainSegment,
    list: &[usize],
    cap: f64,
) -> bool {
    let segment = s.segment;
    if list.is_empty() {
        return false;
    }
    let input = smooth.input;
    let points: Vec<Point> = list.iter().map(|&i| input.points[i]).collect();
    let options = smooth.soften_options(cap, segment.alpha());
    let at_start = segment.kappa0().abs() >= segment.kappa1().abs();
    let (a, b) = (
        (segment.start(), segment.theta0()),
        (segment.end(), segment.theta1()),
    );
    let Some((_, fit)) =
        soften_fits(a, b, at_start, true, &points, options, smooth.tolerance).next()
    else {
        return false;
    };
    let d = &fit.deviation;
    s.alpha_uncertainty =
        smooth_alpha_uncertainty(smooth, &fit.segment, list, &d.signed_distances(), &d.feet);
    s.alpha_bound = crate::chain::alpha_evidence::AlphaBound::of(fit.segment.alpha(), smooth.alpha);
    s.alpha_source = crate::chain::alpha_evidence::AlphaSource::of_g1(
        fit.segment.alpha(),
        &fit.search,
        smooth.alpha,
    );
    s.segment = fit.segment;
    s.max_deviation = d.max;
    s.rms_deviation = d.rms;
    s.search = fit.search;
    true
}

/// The largest curvature a smooth chain of these samples may have at a joint (see
/// [`MIN_RADIUS_TOLERANCES`], [`MAX_TURN_PER_SAMPLE`]).
pub(super) fn curvature_cap(points: &[Point], tolerance: f64) -> f64 {
    let mut steps: Vec<f64> = points.windows(2).map(|w| w[0].distance(w[1])).collect();
    steps.sort_by(f64::total_cmp);
    let spacing = steps.get(steps.len() / 2).copied().unwrap_or(0.0);
    (1.0 / (MIN_RADIUS_TOLERANCES * tolerance))
        .min(MAX_TURN_PER_SAMPLE / spacing.max(f64::MIN_POSITIVE))
}
