//! Tuning of the split: what counts as a real curvature extremum, what counts as straight.

use super::SplitError;

/// Options of [`split_spans`](super::split_spans). Build with [`SplitOptions::default`] and the
/// `with_*` builders; every field is documented with its default and the reason for it.
///
/// Two thresholds decide which extrema are noise. For a neighbouring pair of nodes (curvature
/// extrema, inflections, or an extremum and an end of the curve) with curvature magnitudes
/// `k_a, k_b`, the pair is insignificant when
///
/// ```text
/// | k_a − k_b | < max( extremum_relative · max(k_a, k_b),  κ_straight ),
/// κ_straight = max( straight_relative · Θ,  straight_turning ) / L,
/// ```
///
/// where `L` is the curve's arc length and `Θ = ∫|κ| ds` its total absolute turning, so `Θ / L`
/// is the curve's mean curvature magnitude (its overall curvature scale). `κ_straight` is the
/// curvature treated as zero: a span whose `|κ|` stays below it is straight
/// ([`CurvatureSign::Zero`](super::CurvatureSign::Zero)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SplitOptions {
    /// Relative curvature change below which a neighbouring max/min pair of `|κ|` is noise and is
    /// dropped. Default `0.05`: a least-squares cubic fitted to a hand-drawn stroke carries a
    /// ripple of a few percent in `|κ|` from tremor and sampling, a 5 % change of radius is
    /// invisible, and the log-aesthetic fit of the next stage absorbs it; the features the paper
    /// splits at (its Fig. 5) change curvature by far more. Must be in `[0, 1)`; `0` keeps every
    /// extremum that `f64` can resolve.
    pub extremum_relative: f64,
    /// Curvature treated as zero, as a fraction of the curve's mean curvature magnitude `Θ / L`.
    /// Default `0.02`: wiggles of `κ` around zero that are 50 times weaker than the stroke's typical
    /// bending are fitting noise on a near-straight stretch, not inflections. Must be finite and
    /// `≥ 0`.
    pub straight_relative: f64,
    /// Curvature treated as zero, as a total turning angle in radians spread over the whole arc
    /// length: `κ < straight_turning / L` turns the tangent by less than this over the entire
    /// stroke. Default `0.01` rad (0.57°): invisible, and it keeps a stroke that is straight up to
    /// rounding (whose `Θ` is itself ~0, making `straight_relative` useless) from producing a
    /// flood of inflections. Must be finite and `≥ 0`.
    pub straight_turning: f64,
    /// Two split candidates closer than this fraction of the total parameter range `u_end −
    /// u_start` are one split (a root found at `t ≈ 1` of one piece and `t ≈ 0` of the next is the
    /// joint). Also the tolerance of the parameter contiguity check between pieces. Default
    /// `1e-9`: roots are accurate to ~1e-15 in `t`, so this never merges distinct features, while
    /// it absorbs the rounding of knot values computed upstream (a few ulps of `u`). Must be in
    /// `[0, 1e-3]`.
    pub joint_tolerance: f64,
    /// The fitting tolerance (a distance, in the curve's units): a neighbouring pair of nodes of
    /// one curvature sign, `ℓ` apart in arc length, whose curvature magnitudes differ by `δκ` is
    /// also noise when `δκ·ℓ²/8 < tolerance`, the bump moving the curve by less than the samples
    /// can resolve. (Pairs that involve an inflection are left to the relative and straight
    /// thresholds, so spans keep one curvature sign.)
    /// Default `0` (test off: the split alone does not know the tolerance); the pipeline sets
    /// it to the B-spline's fitting tolerance. Must be finite and `≥ 0`.
    pub tolerance: f64,
    /// Whether the curve's start and end are free ends of a stroke (not corners). Next to a free
    /// end an inflection is also noise when the stretch from it to the end bends by less than
    /// the tolerance (`|κ_end|·ℓ²/8 < tolerance`, `|κ|` being monotonic between them): the
    /// stretch is straight as far as the samples tell, its sign is the noise's, and the end's
    /// curvature is taken as zero (a curve drawn into a flat end, κ → 0, had an inflection found
    /// a few samples before its end, and a tangle of segments after it). Default `(false,
    /// false)`; the pipeline sets it from the piece's ends (a corner's curvature stays the
    /// B-spline's).
    pub free_ends: (bool, bool),
}

impl SplitOptions {
    /// The defaults (see each field).
    pub const DEFAULT: SplitOptions = SplitOptions {
        extremum_relative: 0.05,
        straight_relative: 0.02,
        straight_turning: 0.01,
        joint_tolerance: 1e-9,
        tolerance: 0.0,
        free_ends: (false, false),
    };

    /// Largest accepted [`SplitOptions::joint_tolerance`]: a thousandth of the parameter range
    /// already merges features a user can see.
    pub const MAX_JOINT_TOLERANCE: f64 = 1e-3;

    /// Sets [`SplitOptions::extremum_relative`].
    pub const fn with_extremum_relative(mut self, value: f64) -> Self {
        self.extremum_relative = value;
        self
    }

    /// Sets [`SplitOptions::straight_relative`].
    pub const fn with_straight_relative(mut self, value: f64) -> Self {
        self.straight_relative = value;
        self
    }

    /// Sets [`SplitOptions::straight_turning`].
    pub const fn with_straight_turning(mut self, value: f64) -> Self {
        self.straight_turning = value;
        self
    }

    /// Sets [`SplitOptions::joint_tolerance`].
    pub const fn with_joint_tolerance(mut self, value: f64) -> Self {
        self.joint_tolerance = value;
        self
    }

    /// Sets [`SplitOptions::tolerance`].
    pub const fn with_tolerance(mut self, value: f64) -> Self {
        self.tolerance = value;
        self
    }

    /// Sets [`SplitOptions::free_ends`].
    pub const fn with_free_ends(mut self, start: bool, end: bool) -> Self {
        self.free_ends = (start, end);
        self
    }

    /// Checks every field against its documented range.
    pub fn validate(&self) -> Result<(), SplitError> {
        let check = |name, value: f64, ok: bool, expected| {
            if ok && value.is_finite() {
                Ok(())
            } else {
                Err(SplitError::InvalidOption {
                    name,
                    value,
                    expected,
                })
            }
        };
        let e = self.extremum_relative;
        check(
            "extremum_relative",
            e,
            (0.0..1.0).contains(&e),
            "0 <= value < 1",
        )?;
        let r = self.straight_relative;
        check("straight_relative", r, r >= 0.0, "finite, >= 0")?;
        let a = self.straight_turning;
        check("straight_turning", a, a >= 0.0, "finite, >= 0")?;
        let j = self.joint_tolerance;
        check(
            "joint_tolerance",
            j,
            (0.0..=Self::MAX_JOINT_TOLERANCE).contains(&j),
            "0 <= value <= 1e-3",
        )?;
        let t = self.tolerance;
        check("tolerance", t, t >= 0.0, "finite, >= 0")
    }
}

impl Default for SplitOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_builders_set_fields() {
        assert_eq!(SplitOptions::default().validate(), Ok(()));
        const O: SplitOptions = SplitOptions::DEFAULT
            .with_extremum_relative(0.1)
            .with_straight_relative(0.0)
            .with_straight_turning(0.5)
            .with_joint_tolerance(1e-6)
            .with_tolerance(0.25)
            .with_free_ends(true, false);
        assert_eq!(
            O,
            SplitOptions {
                extremum_relative: 0.1,
                straight_relative: 0.0,
                straight_turning: 0.5,
                joint_tolerance: 1e-6,
                tolerance: 0.25,
                free_ends: (true, false),
            }
        );
        assert_eq!(O.validate(), Ok(()));
    }

    #[test]
    fn out_of_range_options_are_rejected() {
        let d = SplitOptions::default();
        for bad in [
            d.with_extremum_relative(1.0),
            d.with_extremum_relative(-0.1),
            d.with_extremum_relative(f64::NAN),
            d.with_straight_relative(-1.0),
            d.with_straight_relative(f64::INFINITY),
            d.with_straight_turning(f64::NAN),
            d.with_joint_tolerance(0.01),
        ] {
            assert!(
                matches!(bad.validate(), Err(SplitError::InvalidOption { .. })),
                "{bad:?}"
            );
        }
    }
}
