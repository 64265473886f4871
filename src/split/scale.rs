//! The curve's overall curvature scale, which sets the curvature treated as zero.

use super::SplitOptions;
use super::curvature::PieceCurvature;
use crate::geom::{ParamBez, ParamCurve};

/// Samples per piece for the arc length and total turning. They only set a threshold, so ~1e-3
/// relative accuracy is plenty: chords over 32 equal steps of a cubic err by `O(1/32²)` in
/// length, and the turning sum is exact within every step where κ keeps its sign (the angle
/// between the end tangents of a step that turns less than π).
const SAMPLES_PER_PIECE: usize = 32;

/// Arc length `L` and total absolute turning `Θ = ∫|κ| ds` of the chain, measured on a fixed
/// grid (see [`SAMPLES_PER_PIECE`]). Turning at a joint with a tangent discontinuity is included.
pub(crate) fn length_and_turning(pieces: &[ParamBez], curvatures: &[PieceCurvature]) -> (f64, f64) {
    let mut length = 0.0;
    let mut turning = 0.0;
    let mut previous_tangent = None;
    for (piece, curvature) in pieces.iter().zip(curvatures) {
        let mut previous_point = piece.bez.eval(0.0);
        for j in 0..=SAMPLES_PER_PIECE {
            let t = j as f64 / SAMPLES_PER_PIECE as f64;
            let tangent = curvature.tangent(t);
            if let Some(prev) = previous_tangent {
                turning += f64::atan2(
                    kurbo::Vec2::cross(prev, tangent),
                    kurbo::Vec2::dot(prev, tangent),
                )
                .abs();
            }
            previous_tangent = Some(tangent);
            if j > 0 {
                let point = piece.bez.eval(t);
                length += (point - previous_point).hypot();
                previous_point = point;
            }
        }
    }
    (length, turning)
}

/// The curvature magnitude treated as zero:
/// `κ_straight = max(straight_relative · Θ, straight_turning) / L`.
pub(crate) fn straight_curvature(
    pieces: &[ParamBez],
    curvatures: &[PieceCurvature],
    options: &SplitOptions,
) -> f64 {
    let (length, turning) = length_and_turning(pieces, curvatures);
    // L > 0: every piece is regular (checked before), so it has positive length.
    (options.straight_relative * turning).max(options.straight_turning) / length
}
