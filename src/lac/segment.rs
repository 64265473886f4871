//! The canonical LAC segment record and its evaluation.
//!
//! A segment is fixed by `start`, `theta0`, `length` S, `alpha` and the signed end curvatures
//! `kappa0`, `kappa1` (same sign or zero). For α ≠ 0, ρ(s)^α is linear in s from ρ0^α to ρ1^α
//! (ρ^α = 0 where κ = 0, α < 0 only); for α = 0, ρ(s) = ρ0·(ρ1/ρ0)^{s/S}; `alpha = None` exactly
//! when κ0 = κ1 (circular arc, or line when both are 0). `end` and `theta1` are derived.
//!
//! ## Mapping onto the standard form
//! Let σ = ±1 be the sign of the curvature, κ_hi = max(|κ0|, |κ1|), c = 1/κ_hi. The segment is the
//! standard form ([`StandardLac`]) over u ∈ [0, U], U = S·κ_hi, scaled by c, with its
//! high-curvature end at u = 0:
//!
//! * |κ| non-increasing along travel ("uncurling", u = s/c):
//!   θ(s) = θ0 + σθ_std(u), P(s) = P0 + c·e^{iθ0}·C_{σ<0}[Q(0, u)];
//! * |κ| increasing ("curling", u = U − s/c, the standard form travelled backwards):
//!   θ(s) = θ0 + σ(θ_std(U) − θ_std(u)), P(s) = P0 + c·e^{i(θ0 + σθ_std(U))}·C_{σ>0}[Q(u, U)];
//!
//! where Q(a, b) = ∫_a^b e^{iθ_std} du and C_{cond} is complex conjugation (a mirror) when `cond`
//! holds. Both are checked by differentiation: dP/ds = e^{iθ(s)}.

use super::error::LacError;
use super::special::{cis, conj, sinc};
use super::standard::StandardLac;
use crate::geom::{Point, Vec2};
use serde::{Deserialize, Serialize};

/// Stored `end` and `theta1` must agree with the recomputed ones to this fraction of the length
/// (`theta1`: radians) when a record is read; the format promises 1e-9, our evaluation is good to
/// ~1e-14, so anything beyond 1e-9 is a different curve.
pub const DERIVED_FIELD_TOLERANCE: f64 = 1e-9;

/// One point of a segment: arc length, position, tangent angle and signed curvature.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LacSample {
    /// Arc length from the segment start.
    pub s: f64,
    /// Position.
    pub point: Point,
    /// Tangent angle (radians, continuous along the segment: θ0 plus the turning so far).
    pub theta: f64,
    /// Signed curvature (positive: left turn).
    pub kappa: f64,
}

/// How the segment's shape is computed.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Shape {
    /// κ0 = κ1 = 0.
    Line,
    /// κ0 = κ1 = κ ≠ 0.
    Arc { kappa: f64 },
    /// κ0 ≠ κ1: a scaled, rotated, possibly mirrored and reversed standard form.
    Spiral(Spiral),
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Spiral {
    std: StandardLac,
    /// Sign of the curvature (±1).
    sigma: f64,
    /// c = 1/κ_hi.
    scale: f64,
    /// U = S·κ_hi.
    u_end: f64,
    /// |κ| increases along travel.
    curling: bool,
    /// θ_std(U).
    theta_std_end: f64,
    /// Angle of the frame rotation e^{iβ} applied to the standard integral.
    frame_angle: f64,
    /// Conjugate (mirror) the standard integral before rotating.
    mirror: bool,
}

impl Spiral {
    /// Standard-form abscissa of the segment's arc length `s` (given as the fraction t = s/S, so
    /// that t = 0 and t = 1 map exactly onto the ends).
    fn u(&self, t: f64) -> f64 {
        if self.curling {
            (1.0 - t) * self.u_end
        } else {
            t * self.u_end
        }
    }

    /// Standard integral mapped into the segment frame.
    fn map(&self, q: Vec2) -> Vec2 {
        let q = if self.mirror { conj(q) } else { q };
        let (s, c) = self.frame_angle.sin_cos();
        Vec2::new(c * q.x - s * q.y, s * q.x + c * q.y) * self.scale
    }

    /// P(t_b) − P(t_a).
    fn delta(&self, ta: f64, tb: f64) -> Vec2 {
        let (ua, ub) = (self.u(ta), self.u(tb));
        if self.curling {
            self.map(self.std.tangent_integral(ub, ua))
        } else {
            self.map(self.std.tangent_integral(ua, ub))
        }
    }

    /// Turning θ(t) − θ0.
    fn turning(&self, t: f64) -> f64 {
        self.turning_at(self.std.theta(self.u(t)))
    }

    /// The turning θ(t) − θ0 at the point whose standard-form tangent angle is `theta_std`.
    fn turning_at(&self, theta_std: f64) -> f64 {
        if self.curling {
            self.sigma * (self.theta_std_end - theta_std)
        } else {
            self.sigma * theta_std
        }
    }

    /// Turning θ(t) − θ0 and the turnings from t to the fractions t ∓ dt (see
    /// [`StandardLac::theta_around`]).
    fn turning_around(&self, t: f64, dt: f64) -> (f64, Option<(f64, f64)>) {
        let (u, du) = (self.u(t), dt * self.u_end);
        let (theta, steps) = self.std.theta_around(u, du);
        if self.curling {
            // u runs backwards: t − dt is u + du.
            let steps = steps.map(|(minus, plus)| (-self.sigma * plus, -self.sigma * minus));
            (self.sigma * (self.theta_std_end - theta), steps)
        } else {
            let steps = steps.map(|(minus, plus)| (self.sigma * minus, self.sigma * plus));
            (self.sigma * theta, steps)
        }
    }

    /// Signed curvature at t.
    fn kappa(&self, t: f64) -> f64 {
        self.sigma * self.std.kappa(self.u(t)) / self.scale
    }

    /// Turning θ(t) − θ0 and signed curvature at t, from one standard-form evaluation.
    fn turning_kappa(&self, t: f64) -> (f64, f64) {
        let (theta, kappa) = self.std.theta_kappa(self.u(t));
        (self.turning_at(theta), self.sigma * kappa / self.scale)
    }
}

/// A log-aesthetic curve segment in its canonical record form (see the module documentation).
///
/// Serialises as `{"start": [x, y], "theta0", "length", "alpha", "kappa0", "kappa1",
/// "end": [x, y], "theta1"}`; deserialising validates the parameters and, when `end`/`theta1` are
/// present, checks them against the recomputed values ([`DERIVED_FIELD_TOLERANCE`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "LacSegmentRecord", into = "LacSegmentRecord")]
pub struct LacSegment {
    start: Point,
    theta0: f64,
    length: f64,
    alpha: Option<f64>,
    kappa0: f64,
    kappa1: f64,
    end: Point,
    theta1: f64,
    shape: Shape,
}

/// The JSON form of [`LacSegment`]; `end` and `theta1` are optional on input.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LacSegmentRecord {
    /// Start point [x, y].
    pub start: [f64; 2],
    /// Tangent angle at the start (radians).
    pub theta0: f64,
    /// Arc length S > 0.
    pub length: f64,
    /// Slope of the logarithmic curvature graph; null exactly when kappa0 == kappa1.
    pub alpha: Option<f64>,
    /// Signed curvature at the start.
    pub kappa0: f64,
    /// Signed curvature at the end.
    pub kappa1: f64,
    /// Derived end point [x, y] (checked when present on input).
    #[serde(default)]
    pub end: Option<[f64; 2]>,
    /// Derived tangent angle at the end (checked when present on input).
    #[serde(default)]
    pub theta1: Option<f64>,
}

impl TryFrom<LacSegmentRecord> for LacSegment {
    type Error = LacError;

    fn try_from(r: LacSegmentRecord) -> Result<Self, LacError> {
        let seg = LacSegment::new(
            Point::new(r.start[0], r.start[1]),
            r.theta0,
            r.length,
            r.alpha,
            r.kappa0,
            r.kappa1,
        )?;
        if let Some([x, y]) = r.end {
            let error = (Point::new(x, y) - seg.end).hypot() / seg.length;
            if error.is_nan() || error > DERIVED_FIELD_TOLERANCE {
                return Err(LacError::DerivedFieldMismatch {
                    field: "end",
                    error,
                });
            }
        }
        if let Some(theta1) = r.theta1 {
            let error = (theta1 - seg.theta1).abs();
            if error.is_nan() || error > DERIVED_FIELD_TOLERANCE {
                return Err(LacError::DerivedFieldMismatch {
                    field: "theta1",
                    error,
                });
            }
        }
        Ok(seg)
    }
}

impl From<LacSegment> for LacSegmentRecord {
    fn from(s: LacSegment) -> Self {
        LacSegmentRecord {
            start: [s.start.x, s.start.y],
            theta0: s.theta0,
            length: s.length,
            alpha: s.alpha,
            kappa0: s.kappa0,
            kappa1: s.kappa1,
            end: Some([s.end.x, s.end.y]),
            theta1: Some(s.theta1),
        }
    }
}

/// ln(a/b) for a ≥ b > 0 without overflow of a/b and without cancellation when a ≈ b.
fn ln_ratio(a: f64, b: f64) -> f64 {
    let q = a / b;
    if !q.is_finite() {
        a.ln() - b.ln()
    } else if q < 2.0 {
        // a − b is exact here (Sterbenz), so ln_1p keeps the full relative accuracy.
        ((a - b) / b).ln_1p()
    } else {
        q.ln()
    }
}

impl LacSegment {
    /// Builds and validates a segment (see the module documentation for the parameters).
    ///
    /// Errors: non-finite input, `length ≤ 0`, κ0 and κ1 of opposite signs, `alpha` missing with
    /// κ0 ≠ κ1 or present with κ0 = κ1, a zero-curvature end with α ≥ 0, or a curvature ratio so
    /// large that ρ^α overflows.
    pub fn new(
        start: Point,
        theta0: f64,
        length: f64,
        alpha: Option<f64>,
        kappa0: f64,
        kappa1: f64,
    ) -> Result<Self, LacError> {
        Self::build(start, theta0, length, alpha, kappa0, kappa1, None)
    }

    /// [`LacSegment::new`] for a caller that already knows the end point to within rounding of
    /// the solver that produced the parameters (the Yoshida–Saito construction, whose segment
    /// ends at its target point by construction): the end is taken, not integrated again.
    pub(crate) fn with_known_end(
        start: Point,
        theta0: f64,
        length: f64,
        alpha: Option<f64>,
        kappa0: f64,
        kappa1: f64,
        end: Point,
    ) -> Result<Self, LacError> {
        Self::build(start, theta0, length, alpha, kappa0, kappa1, Some(end))
    }

    fn build(
        start: Point,
        theta0: f64,
        length: f64,
        alpha: Option<f64>,
        kappa0: f64,
        kappa1: f64,
        known_end: Option<Point>,
    ) -> Result<Self, LacError> {
        for (field, v) in [
            ("start.x", start.x),
            ("start.y", start.y),
            ("theta0", theta0),
            ("length", length),
            ("alpha", alpha.unwrap_or(0.0)),
            ("kappa0", kappa0),
            ("kappa1", kappa1),
        ] {
            if !v.is_finite() {
                return Err(LacError::NotFinite { field });
            }
        }
        if length <= 0.0 {
            return Err(LacError::NonPositiveLength { length });
        }
        if kappa0 * kappa1 < 0.0 {
            return Err(LacError::OppositeCurvatureSigns { kappa0, kappa1 });
        }
        let shape = match alpha {
            None if kappa0 != kappa1 => return Err(LacError::MissingAlpha { kappa0, kappa1 }),
            Some(alpha) if kappa0 == kappa1 => {
                return Err(LacError::AlphaOnConstantCurvature {
                    kappa: kappa0,
                    alpha,
                });
            }
            None if kappa0 == 0.0 => Shape::Line,
            None => Shape::Arc { kappa: kappa0 },
            Some(alpha) => {
                let (k0, k1) = (kappa0.abs(), kappa1.abs());
                let (hi, lo) = if k0 >= k1 { (k0, k1) } else { (k1, k0) };
                if lo == 0.0 && alpha >= 0.0 {
                    return Err(LacError::ZeroCurvatureNeedsNegativeAlpha { alpha });
                }
                // κ0 ≠ κ1 with equal signs (or one zero): hi > 0.
                let sigma = if kappa0 + kappa1 > 0.0 { 1.0 } else { -1.0 };
                let u_end = length * hi;
                let ratio = (lo > 0.0).then(|| ln_ratio(hi, lo));
                let std = StandardLac::from_span(alpha, u_end, ratio)?;
                let curling = k1 > k0;
                let theta_std_end = std.theta(u_end);
                let (frame_angle, mirror) = if curling {
                    (theta0 + sigma * theta_std_end, sigma > 0.0)
                } else {
                    (theta0, sigma < 0.0)
                };
                Shape::Spiral(Spiral {
                    std,
                    sigma,
                    scale: 1.0 / hi,
                    u_end,
                    curling,
                    theta_std_end,
                    frame_angle,
                    mirror,
                })
            }
        };
        let mut seg = LacSegment {
            start,
            theta0,
            length,
            alpha,
            kappa0,
            kappa1,
            end: start,
            theta1: theta0,
            shape,
        };
        seg.end = known_end.unwrap_or_else(|| seg.start + seg.delta(0.0, 1.0));
        seg.theta1 = theta0 + seg.turning(1.0);
        Ok(seg)
    }

    /// Start point.
    pub fn start(&self) -> Point {
        self.start
    }
    /// Tangent angle at the start (radians).
    pub fn theta0(&self) -> f64 {
        self.theta0
    }
    /// Arc length S.
    pub fn length(&self) -> f64 {
        self.length
    }
    /// Slope α of the logarithmic curvature graph (`None` for arcs and lines).
    pub fn alpha(&self) -> Option<f64> {
        self.alpha
    }
    /// Signed curvature at the start.
    pub fn kappa0(&self) -> f64 {
        self.kappa0
    }
    /// Signed curvature at the end.
    pub fn kappa1(&self) -> f64 {
        self.kappa1
    }
    /// End point (derived).
    pub fn end(&self) -> Point {
        self.end
    }
    /// Tangent angle at the end (derived): θ0 + ∫₀ˢ κ.
    pub fn theta1(&self) -> f64 {
        self.theta1
    }

    /// The same segment (length, α, end curvatures) placed at `start` with start tangent
    /// `theta0`: a rigid motion of this one, without a new construction (the end point is the
    /// old chord turned by the change of angle). Equal to [`LacSegment::new`] at that pose to
    /// rounding.
    pub fn placed(&self, start: Point, theta0: f64) -> LacSegment {
        let turn = theta0 - self.theta0;
        let (sin, cos) = turn.sin_cos();
        let chord = self.end - self.start;
        let end = start + Vec2::new(cos * chord.x - sin * chord.y, sin * chord.x + cos * chord.y);
        let shape = match self.shape {
            Shape::Spiral(mut sp) => {
                sp.frame_angle += turn;
                Shape::Spiral(sp)
            }
            other => other,
        };
        LacSegment {
            start,
            theta0,
            end,
            theta1: self.theta1 + turn,
            shape,
            ..*self
        }
    }

    /// The standard form this segment is a piece of, with the scale c = ρ at the high-curvature
    /// end and the standard arc-length interval [0, U]; `None` for arcs and lines.
    pub fn standard_form(&self) -> Option<(StandardLac, f64, f64)> {
        match self.shape {
            Shape::Spiral(sp) => Some((sp.std, sp.scale, sp.u_end)),
            _ => None,
        }
    }

    /// Fraction t = s/S, clamped to [0, 1].
    fn fraction(&self, s: f64) -> f64 {
        (s / self.length).clamp(0.0, 1.0)
    }

    /// P(t_b) − P(t_a) for fractions t of the length.
    fn delta(&self, ta: f64, tb: f64) -> Vec2 {
        match self.shape {
            Shape::Line => cis(self.theta0) * ((tb - ta) * self.length),
            Shape::Arc { kappa } => {
                // Chord of the arc from θ(ta) over arc length d: d·e^{i(θa + κd/2)}·sinc(κd/2).
                let d = (tb - ta) * self.length;
                let theta_a = self.theta0 + kappa * ta * self.length;
                cis(theta_a + 0.5 * kappa * d) * (d * sinc(0.5 * kappa * d))
            }
            Shape::Spiral(sp) => sp.delta(ta, tb),
        }
    }

    /// Turning θ(t) − θ0.
    fn turning(&self, t: f64) -> f64 {
        match self.shape {
            Shape::Line => 0.0,
            Shape::Arc { kappa } => kappa * t * self.length,
            Shape::Spiral(sp) => sp.turning(t),
        }
    }

    /// Point at arc length `s` (clamped to [0, S]).
    pub fn point(&self, s: f64) -> Point {
        let t = self.fraction(s);
        if t == 1.0 {
            self.end
        } else {
            self.start + self.delta(0.0, t)
        }
    }

    /// Tangent angle at arc length `s` (clamped to [0, S]), in closed form.
    pub fn theta(&self, s: f64) -> f64 {
        self.theta0 + self.turning(self.fraction(s))
    }

    /// Tangent angles around arc length `s` (in [0, S], with s ± d too): θ(s − d), θ(s) and
    /// θ(s + d), the outer two as increments on θ(s) summed by a short series where the curvature
    /// changes little over ±d (see [`StandardLac::theta_around`]), else in closed form.
    pub(crate) fn theta_around(&self, s: f64, d: f64) -> [f64; 3] {
        let t = self.fraction(s);
        match self.shape {
            Shape::Line => [self.theta0; 3],
            Shape::Arc { kappa } => {
                let mid = self.theta0 + kappa * t * self.length;
                [mid - kappa * d, mid, mid + kappa * d]
            }
            Shape::Spiral(sp) => {
                let (turning, steps) = sp.turning_around(t, d / self.length);
                let mid = self.theta0 + turning;
                match steps {
                    Some((minus, plus)) => [mid + minus, mid, mid + plus],
                    None => [self.theta(s - d), mid, self.theta(s + d)],
                }
            }
        }
    }

    /// Signed curvature at arc length `s` (clamped to [0, S]).
    pub fn kappa(&self, s: f64) -> f64 {
        let t = self.fraction(s);
        match self.shape {
            Shape::Line => 0.0,
            Shape::Arc { kappa } => kappa,
            Shape::Spiral(sp) => {
                // The ends are given exactly; in between, from the standard form.
                if t == 0.0 {
                    self.kappa0
                } else if t == 1.0 {
                    self.kappa1
                } else {
                    sp.kappa(t)
                }
            }
        }
    }

    /// Arc-length derivative of the signed curvature, dκ/ds, at arc length `s` (clamped to
    /// [0, S]), in closed form. With ρ = 1/|κ| and σ the curvature's sign:
    ///
    /// * α ≠ 0: ρ^α = ρ0^α + c·s with c = (ρ1^α − ρ0^α)/S, so dκ/ds = −σ·(c/α)·|κ|^(1+α);
    /// * α = 0: ρ = ρ0·e^(λs) with λ = ln(ρ1/ρ0)/S, so dκ/ds = −λ·κ;
    /// * arcs and lines: 0.
    ///
    /// At a zero-curvature end (α < 0 only) |κ|^(1+α) is 0 for −1 < α < 0, 1 for the clothoid
    /// (α = −1: dκ/ds = −σc, constant) and infinite for α < −1 (κ leaves zero vertically in s).
    pub fn dkappa_ds(&self, s: f64) -> f64 {
        let Some(alpha) = self.alpha else {
            return 0.0;
        };
        let kappa = self.kappa(s);
        let sigma = if self.kappa0 + self.kappa1 < 0.0 {
            -1.0
        } else {
            1.0
        };
        let rho_pow = |k: f64| -> f64 {
            // ρ^α of |κ|: 0 at κ = 0 for α < 0 (the only α a zero end allows).
            if k == 0.0 { 0.0 } else { k.abs().powf(-alpha) }
        };
        if alpha == 0.0 {
            let lambda = (self.kappa0.abs() / self.kappa1.abs()).ln() / self.length;
            return -lambda * kappa;
        }
        let c = (rho_pow(self.kappa1) - rho_pow(self.kappa0)) / self.length;
        let magnitude = if kappa == 0.0 {
            if alpha > -1.0 {
                0.0
            } else if alpha == -1.0 {
                1.0
            } else {
                f64::INFINITY
            }
        } else {
            kappa.abs().powf(1.0 + alpha)
        };
        -sigma * (c / alpha) * magnitude
    }

    /// Tangent angle and signed curvature at arc length `s` (clamped to [0, S]): what
    /// [`LacSegment::theta`] and [`LacSegment::kappa`] give, for about the cost of one of them.
    pub(crate) fn theta_kappa(&self, s: f64) -> (f64, f64) {
        let t = self.fraction(s);
        match self.shape {
            Shape::Spiral(sp) if t > 0.0 && t < 1.0 => {
                let (turning, kappa) = sp.turning_kappa(t);
                (self.theta0 + turning, kappa)
            }
            _ => (self.theta(s), self.kappa(s)),
        }
    }

    /// Point, tangent angle and curvature at arc length `s` (clamped to [0, S]).
    pub fn sample(&self, s: f64) -> LacSample {
        let s = s.clamp(0.0, self.length);
        LacSample {
            s,
            point: self.point(s),
            theta: self.theta(s),
            kappa: self.kappa(s),
        }
    }

    /// Rendering fast path: samples at equal arc-length steps of at most `spacing`, both ends
    /// included (at least 2 samples). Each point is the previous one plus the integral over one
    /// step, so the cost is O(number of samples), not O(samples × length). A non-positive or
    /// non-finite `spacing` yields just the two ends.
    pub fn samples(&self, spacing: f64) -> LacSamples<'_> {
        let steps = if spacing > 0.0 && spacing.is_finite() {
            // Saturating float→int conversion; at least one step.
            ((self.length / spacing).ceil() as usize).max(1)
        } else {
            1
        };
        LacSamples {
            seg: self,
            steps,
            next: 0,
            prev_point: self.start,
        }
    }
}

/// Iterator returned by [`LacSegment::samples`].
#[derive(Clone, Debug)]
pub struct LacSamples<'a> {
    seg: &'a LacSegment,
    steps: usize,
    next: usize,
    prev_point: Point,
}

impl Iterator for LacSamples<'_> {
    type Item = LacSample;

    fn next(&mut self) -> Option<LacSample> {
        if self.next > self.steps {
            return None;
        }
        let i = self.next;
        self.next += 1;
        let seg = self.seg;
        let t = i as f64 / self.steps as f64;
        let point = if i == 0 {
            seg.start
        } else if i == self.steps {
            seg.end
        } else {
            let t_prev = (i - 1) as f64 / self.steps as f64;
            self.prev_point + seg.delta(t_prev, t)
        };
        self.prev_point = point;
        let s = t * seg.length;
        Some(LacSample {
            s,
            point,
            theta: seg.theta(s),
            kappa: seg.kappa(s),
        })
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = (self.steps + 1).saturating_sub(self.next);
        (n, Some(n))
    }
}

impl ExactSizeIterator for LacSamples<'_> {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_placed_segment_is_the_one_built_at_that_pose() {
        let pose = (Point::new(-12.5, 40.25), 2.1);
        for (alpha, k0, k1) in [
            (Some(-1.0), 0.0, 0.05),
            (Some(0.5), -0.02, -0.09),
            (Some(2.0), 0.08, 0.01),
            (None, 0.03, 0.03),
            (None, 0.0, 0.0),
        ] {
            let seg =
                LacSegment::new(Point::new(3.0, -1.0), -0.4, 30.0, alpha, k0, k1).expect("segment");
            let placed = seg.placed(pose.0, pose.1);
            let built = LacSegment::new(pose.0, pose.1, 30.0, alpha, k0, k1).expect("segment");
            assert!(placed.end().distance(built.end()) < 1e-12, "{alpha:?}");
            assert!((placed.theta1() - built.theta1()).abs() < 1e-12);
            for i in 0..=10 {
                let s = 3.0 * i as f64;
                assert!(
                    placed.point(s).distance(built.point(s)) < 1e-12,
                    "{alpha:?} at {s}"
                );
                assert!((placed.kappa(s) - built.kappa(s)).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn theta_kappa_is_theta_and_kappa() {
        for (alpha, k0, k1) in [
            (Some(-1.0), 0.0, 0.05),
            (Some(-2.5), 0.08, 0.01),
            (Some(0.0), -0.02, -0.09),
            (Some(1.0), 0.3, 0.01),
            (Some(2.0), -0.01, -0.2),
            (Some(0.7), 0.04, 0.04 * 1.000_001),
            (None, 0.05, 0.05),
            (None, 0.0, 0.0),
        ] {
            let segment =
                LacSegment::new(Point::new(1.0, -2.0), 0.3, 30.0, alpha, k0, k1).expect("segment");
            for i in 0..=20 {
                let s = segment.length() * i as f64 / 20.0;
                let (theta, kappa) = segment.theta_kappa(s);
                assert!((theta - segment.theta(s)).abs() <= 1e-15 * (1.0 + theta.abs()));
                assert!((kappa - segment.kappa(s)).abs() <= 1e-15 * kappa.abs().max(1e-300));
            }
        }
    }

    #[test]
    fn dkappa_ds_is_the_derivative_of_kappa() {
        for (alpha, k0, k1) in [
            (Some(-1.0), 0.01, 0.05),
            (Some(-2.5), 0.08, 0.01),
            (Some(-0.5), 0.02, 0.06),
            (Some(0.0), -0.02, -0.09),
            (Some(1.0), 0.3, 0.01),
            (Some(2.0), -0.01, -0.2),
            (None, 0.05, 0.05),
            (None, 0.0, 0.0),
        ] {
            let segment =
                LacSegment::new(Point::new(1.0, -2.0), 0.3, 30.0, alpha, k0, k1).expect("segment");
            // Central differences with h = 1e-5·S: truncation O(h²·κ‴) and rounding
            // O(ε·κ/h), both far below 1e-6 of the derivative's scale (|κ1 − κ0|/S).
            let h = 1e-5 * segment.length();
            let scale = ((k1 - k0) / segment.length()).abs().max(1e-300);
            for i in 1..20 {
                let s = segment.length() * i as f64 / 20.0;
                let fd = (segment.kappa(s + h) - segment.kappa(s - h)) / (2.0 * h);
                let exact = segment.dkappa_ds(s);
                assert!(
                    (fd - exact).abs() <= 1e-6 * scale.max(exact.abs()),
                    "α {alpha:?} at s {s}: {exact} vs {fd}"
                );
            }
        }
        // The clothoid's curvature is linear: dκ/ds = (κ1 − κ0)/S everywhere, ends included,
        // also from a zero-curvature end.
        for k0 in [0.0, 0.01] {
            let c = LacSegment::new(Point::ORIGIN, 0.0, 20.0, Some(-1.0), k0, 0.05).expect("seg");
            for s in [0.0, 7.0, 20.0] {
                let expected = (0.05 - k0) / 20.0;
                assert!(
                    (c.dkappa_ds(s) - expected).abs() <= 1e-14,
                    "{}",
                    c.dkappa_ds(s)
                );
            }
        }
    }
}
