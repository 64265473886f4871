//! Log-aesthetic curves (LAC).
//!
//! A log-aesthetic curve has a straight logarithmic curvature graph: its radius of curvature ρ and
//! arc length s satisfy ρ(s)^α = c0·s + c1 (α ≠ 0) or ρ(s) = c0·e^{c1·s} (α = 0), the tangent angle
//! is θ′(s) = κ(s) = ±1/ρ(s) and the point is P(s) = P0 + ∫ (cos θ, sin θ) ds (Miura 2006; Yoshida
//! & Saito 2006; Ziatdinov, Yoshida & Kim 2012). α = 1 is the logarithmic spiral, α = 2 the circle
//! involute, α = −1 the clothoid, α = 0 Nielsen's spiral.
//!
//! * [`standard`]: the normalised form (origin, tangent +x, ρ(0) = 1, shape parameter Λ): κ(s),
//!   θ(s), s(θ) in closed form, P(s) by closed forms (α = 1, 2) or quadrature.
//! * [`log_radius`]: the fast quadrature in w = ln ρ, whose integrand is entire.
//! * [`quadrature`]: the Gauss–Legendre rules and panels every integral of e^{iθ} here is
//!   written with (and which integrator is used where, and why they differ), and the adaptive
//!   arc-length integrator: panels graded in ln ρ, with an exact series at the κ = 0 end of
//!   α < 0 curves.
//! * [`segment`]: the canonical segment record ([`LacSegment`], JSON via serde) and its evaluation,
//!   including the rendering fast path [`LacSegment::samples`].
//! * [`yoshida_saito`]: the segment of a given α joining G1 end data ([`fit_g1`]).
//! * [`alpha_search`]: the best α for a span (a walk from a guess or a grid, then Brent), [`fit_span`].
//! * [`mod@biarc`]: two circular arcs joining G1 data, the fallback where no LAC can.
//! * `sensitivity`: how a Yoshida–Saito segment's points move with its end tangents and α (the
//!   chain refinement's Jacobian).
//! * [`mod@deviation`]: distances from a span's samples to a segment.
//! * [`minimize`]: Brent's scalar minimisation (the α search).
//! * [`lcg`]: the logarithmic curvature graph of a segment or of a span of Béziers, and its
//!   least-squares slope.
//! * [`error`]: the typed errors, [`LacError`].

pub mod alpha_search;
pub mod biarc;
pub mod deviation;
pub mod error;
pub mod lcg;
pub mod log_radius;
pub mod minimize;
pub mod quadrature;
pub mod segment;
pub(crate) mod sensitivity;
mod special;
pub mod standard;
pub mod yoshida_saito;

pub use alpha_search::{
    AlphaChoice, AlphaSearch, SpanFit, SpanFitOptions, fit_span, parse_alpha_range, within,
};
pub use biarc::biarc;
pub use deviation::{Deviation, deviation, rough_deviation};
pub use error::LacError;
pub use lcg::{LcgLine, LcgPoint, lcg_line, lcg_of_bezier_span, lcg_of_segment, lcg_slope};
pub use segment::{LacSample, LacSamples, LacSegment, LacSegmentRecord};
pub use standard::StandardLac;
pub use yoshida_saito::{fit_g1, fit_g1_near};
