//! Typed errors of the LAC module.

use thiserror::Error;

/// Why a log-aesthetic curve could not be built or fitted.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum LacError {
    /// A parameter is NaN or infinite.
    #[error("LAC parameter `{field}` is not finite")]
    NotFinite {
        /// Name of the offending field.
        field: &'static str,
    },
    /// The arc length must be strictly positive.
    #[error("LAC segment length must be > 0, got {length}")]
    NonPositiveLength {
        /// The length given.
        length: f64,
    },
    /// The end curvatures have opposite signs (an inflection inside the segment).
    #[error("LAC end curvatures {kappa0} and {kappa1} have opposite signs")]
    OppositeCurvatureSigns {
        /// Curvature at the start.
        kappa0: f64,
        /// Curvature at the end.
        kappa1: f64,
    },
    /// `alpha` is null but the end curvatures differ (the curvature profile is undetermined).
    #[error("LAC segment with kappa0 = {kappa0} != kappa1 = {kappa1} needs an alpha")]
    MissingAlpha {
        /// Curvature at the start.
        kappa0: f64,
        /// Curvature at the end.
        kappa1: f64,
    },
    /// `alpha` is given but the curvature is constant (circular arc or line: alpha is meaningless).
    #[error("LAC segment with constant curvature {kappa} must have alpha = null, got {alpha}")]
    AlphaOnConstantCurvature {
        /// The constant curvature.
        kappa: f64,
        /// The alpha given.
        alpha: f64,
    },
    /// A zero-curvature end is only reachable at finite arc length when α < 0.
    #[error("a zero-curvature end needs alpha < 0, got alpha = {alpha}")]
    ZeroCurvatureNeedsNegativeAlpha {
        /// The alpha given.
        alpha: f64,
    },
    /// The curvature ratio is so large for this α that ρ^α overflows f64.
    #[error("curvature ratio {ratio:e} is out of range for alpha = {alpha} (rho^alpha overflows)")]
    CurvatureRatioOutOfRange {
        /// |κ| at the high-curvature end over |κ| at the other end.
        ratio: f64,
        /// The alpha given.
        alpha: f64,
    },
    /// The standard-form shape parameter Λ must be ≥ 0 and finite.
    #[error("LAC shape parameter Lambda must be finite and >= 0, got {lambda}")]
    InvalidLambda {
        /// The Λ given.
        lambda: f64,
    },
    /// A stored derived field (`end`, `theta1`) disagrees with the one recomputed from the
    /// parameters.
    #[error("stored `{field}` disagrees with the parameters by {error:e} (relative to the length)")]
    DerivedFieldMismatch {
        /// Name of the derived field.
        field: &'static str,
        /// Discrepancy, relative to the segment length (angles: in radians).
        error: f64,
    },
    /// G1 end data with the two end points (nearly) coincident.
    #[error("G1 end points coincide: no segment can join them")]
    CoincidentEndPoints,
    /// G1 end data that no monotone-curvature segment of this α can join: the tangents do not
    /// both turn the same way relative to the chord, or the angles exceed the drawable region.
    #[error(
        "G1 data (theta_a = {theta_a}, theta_b = {theta_b}) is outside the drawable region for alpha = {alpha}"
    )]
    OutsideDrawableRegion {
        /// Angle between the chord and the tangent at the first end (radians, signed).
        theta_a: f64,
        /// Angle between the tangent at the second end and the chord (radians, signed).
        theta_b: f64,
        /// The alpha asked for.
        alpha: f64,
    },
    /// No α in the allowed range gives a segment joining the G1 data.
    #[error("no alpha in [{min}, {max}] joins this G1 data with a log-aesthetic segment")]
    NoAlphaInRange {
        /// Smallest α allowed.
        min: f64,
        /// Largest α allowed.
        max: f64,
    },
    /// The α search gave up: the segment at the caller's guess missed the samples by more than
    /// the caller's limit (see [`super::alpha_search::SpanFitOptions::abandon_above`]).
    #[error("alpha search abandoned: the guess misses a sample by {max}, beyond {limit}")]
    SearchAbandoned {
        /// The largest sample distance at the guess.
        max: f64,
        /// The caller's limit.
        limit: f64,
    },
    /// An α range or fixed α that is not finite, or an empty range.
    #[error("the alpha range [{min}, {max}] is not a finite, non-empty interval")]
    InvalidAlphaRange {
        /// Smallest α asked for.
        min: f64,
        /// Largest α asked for.
        max: f64,
    },
    /// A segment curving more sharply than the caller allows.
    #[error("the segment's curvature exceeds the allowed {limit}")]
    CurvatureTooHigh {
        /// The largest curvature allowed.
        limit: f64,
    },
}
