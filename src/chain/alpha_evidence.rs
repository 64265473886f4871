//! What the samples say about a segment's α: whether it sits on the bound of the allowed range
//! (a search stopped by its range has found no minimum there, only a wall), and how well the
//! samples determine it.
//!
//! ## Uncertainty
//! With the segment's joints (end points and tangents) held, α is one parameter of a
//! least-squares fit of the samples' signed distances `d_i(α)`. Its standard error is
//!
//! σ_α = s / ‖∂d/∂α‖,   s² = Σ d_i² / (n − 1),
//!
//! `s` the residual scale (noise and what the curve family cannot follow) and `∂d/∂α` the
//! distances' sensitivity, by central differences of the segment rebuilt at α ± h through the
//! same joints. This is conditional on the joints, so a lower bound on the uncertainty the whole
//! chain's fit leaves. On a near arc or a near line every α gives nearly the same shape:
//! `‖∂d/∂α‖` is tiny and σ_α large, and the number is the search's choice among equals, not a
//! finding ([`UNDETERMINED_ALPHA`]).

use serde::{Deserialize, Serialize};

use crate::lac::AlphaChoice;
use crate::lac::alpha_search::{ALPHA_TOLERANCE, AlphaSearch};

/// α within this of an end of the allowed range sits on it: the search's own accuracy when its
/// answer is final.
pub const ALPHA_BOUND_TOLERANCE: f64 = ALPHA_TOLERANCE;

/// A standard error of α above this leaves α undetermined: the special values of the family
/// (clothoid −1, Nielsen's spiral 0, logarithmic spiral 1, involute 2) are one apart, and an α
/// known only to ±0.5 cannot tell neighbours apart.
pub const UNDETERMINED_ALPHA: f64 = 0.5;

/// Step of the central differences in α: small against α's scale (1) and large enough that the
/// distances' change (h times a sensitivity of at least ~1e-6 of the segment's size where α is
/// determined at all) stands far above the construction's rounding (1e-12 relative).
pub const ALPHA_DIFFERENCE_STEP: f64 = 1e-4;

/// Which end of the allowed α range a segment's α sits on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AlphaBound {
    /// The range's smallest α.
    Min,
    /// The range's largest α.
    Max,
}

impl AlphaBound {
    /// The bound `alpha` sits on under `choice` (within [`ALPHA_BOUND_TOLERANCE`]); `None` for an
    /// interior α, for no α (an arc or a line) and for a fixed α (the user's, not a search's).
    pub fn of(alpha: Option<f64>, choice: AlphaChoice) -> Option<AlphaBound> {
        let AlphaChoice::Range { min, max } = choice else {
            return None;
        };
        let alpha = alpha?;
        if alpha <= min + ALPHA_BOUND_TOLERANCE {
            Some(AlphaBound::Min)
        } else if alpha >= max - ALPHA_BOUND_TOLERANCE {
            Some(AlphaBound::Max)
        } else {
            None
        }
    }
}

/// What chose a segment's α, and so what the number is evidence of.
///
/// A search ([`crate::lac::alpha_search`]) scans α over the segment's own samples with its
/// joints' positions and tangents held; the G1 chain's refinement then moves α together with
/// the joints; the curvature-continuous fit chooses it together with the joints' shared
/// curvatures, the lengths and the poses, where no search with the joints held can reproduce
/// the segment (its end curvatures would move with α). Each is a minimum of the samples'
/// squared distances over what it frees; `alpha_search` in the record stays the search the
/// segment started from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AlphaSource {
    /// The α search of the segment itself: α is its pick, to the search's accuracy
    /// ([`ALPHA_TOLERANCE`]).
    Search,
    /// The G1 chain's refinement, which moved α (or chose one where the search found an arc or
    /// a line) with the joints' positions and tangents.
    Refinement,
    /// The curvature-continuous (G2, C3) fit, with the chain's other unknowns.
    Smooth,
    /// The user's (`--alpha`): no evidence either way.
    Fixed,
}

impl AlphaSource {
    /// The source of a G1 chain segment's `alpha` under `choice`, `search` being the search it
    /// started from: `None` for no α (an arc or a line), [`AlphaSource::Fixed`] for a fixed
    /// choice, [`AlphaSource::Search`] where α is the search's pick to [`ALPHA_TOLERANCE`],
    /// else [`AlphaSource::Refinement`].
    pub fn of_g1(alpha: Option<f64>, search: &AlphaSearch, choice: AlphaChoice) -> Option<Self> {
        let alpha = alpha?;
        Some(match (choice, search.alpha) {
            (AlphaChoice::Fixed(_), _) => AlphaSource::Fixed,
            (_, Some(found))
                if search.evaluations > 0 && (alpha - found).abs() <= ALPHA_TOLERANCE =>
            {
                AlphaSource::Search
            }
            _ => AlphaSource::Refinement,
        })
    }

    /// The source of a curvature-continuous chain segment's `alpha` under `choice`: `None` for
    /// no α, [`AlphaSource::Fixed`] for a fixed choice, else [`AlphaSource::Smooth`].
    pub fn of_smooth(alpha: Option<f64>, choice: AlphaChoice) -> Option<Self> {
        alpha?;
        Some(match choice {
            AlphaChoice::Fixed(_) => AlphaSource::Fixed,
            AlphaChoice::Range { .. } => AlphaSource::Smooth,
        })
    }
}

/// The standard error of α from the samples' signed distances at α (`residuals`) and at α ± h
/// (`minus`, `plus`, [`ALPHA_DIFFERENCE_STEP`]; either may be missing where the construction at
/// that α fails, and the difference is then one-sided). `None` with fewer than two samples or
/// without a difference; +∞ where the distances do not move with α at all.
pub fn alpha_uncertainty(
    residuals: &[f64],
    minus: Option<&[f64]>,
    plus: Option<&[f64]>,
) -> Option<f64> {
    let n = residuals.len();
    if n < 2 {
        return None;
    }
    let h = ALPHA_DIFFERENCE_STEP;
    let slope: Vec<f64> = match (minus, plus) {
        (Some(m), Some(p)) if m.len() == n && p.len() == n => {
            m.iter().zip(p).map(|(a, b)| (b - a) / (2.0 * h)).collect()
        }
        (None, Some(p)) if p.len() == n => {
            residuals.iter().zip(p).map(|(r, b)| (b - r) / h).collect()
        }
        (Some(m), None) if m.len() == n => {
            residuals.iter().zip(m).map(|(r, a)| (r - a) / h).collect()
        }
        _ => return None,
    };
    let sensitivity = slope.iter().map(|g| g * g).sum::<f64>().sqrt();
    let scale = (residuals.iter().map(|r| r * r).sum::<f64>() / (n - 1) as f64).sqrt();
    if !(sensitivity.is_finite() && scale.is_finite()) {
        return None;
    }
    Some(if sensitivity > 0.0 {
        scale / sensitivity
    } else {
        f64::INFINITY
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bound_is_named_only_for_a_searched_range() {
        let range = AlphaChoice::default();
        assert_eq!(AlphaBound::of(Some(-3.0), range), Some(AlphaBound::Min));
        assert_eq!(AlphaBound::of(Some(2.995), range), Some(AlphaBound::Max));
        assert_eq!(AlphaBound::of(Some(1.0), range), None);
        assert_eq!(AlphaBound::of(None, range), None);
        assert_eq!(AlphaBound::of(Some(3.0), AlphaChoice::Fixed(3.0)), None);
    }

    #[test]
    fn the_uncertainty_is_the_residual_scale_over_the_sensitivity() {
        // d_i(α) = r_i + g_i·(α − α0): the central difference recovers g exactly.
        let r = [0.1, -0.2, 0.15, -0.05];
        let g = [1.0, 2.0, 2.0, 1.0];
        let h = ALPHA_DIFFERENCE_STEP;
        let minus: Vec<f64> = r.iter().zip(&g).map(|(r, g)| r - g * h).collect();
        let plus: Vec<f64> = r.iter().zip(&g).map(|(r, g)| r + g * h).collect();
        let s = (r.iter().map(|r| r * r).sum::<f64>() / 3.0).sqrt();
        let expected = s / 10f64.sqrt();
        let got = alpha_uncertainty(&r, Some(&minus), Some(&plus)).expect("a value");
        assert!((got - expected).abs() < 1e-9 * expected, "{got} {expected}");
        let one_sided = alpha_uncertainty(&r, None, Some(&plus)).expect("a value");
        assert!((one_sided - expected).abs() < 1e-9 * expected);
        // Distances that do not move with α leave it undetermined.
        assert_eq!(
            alpha_uncertainty(&r, Some(&r), Some(&r)),
            Some(f64::INFINITY)
        );
        assert_eq!(alpha_uncertainty(&r[..1], Some(&r[..1]), None), None);
        assert_eq!(alpha_uncertainty(&r, None, None), None);
    }
}
