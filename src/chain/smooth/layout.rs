//! The unknowns of a smooth chain and where each sits: [`Params`], [`Var`], [`Layout`] (which
//! joints are free, which α, the two forms of the chain).

use super::BOUND_SLACK;
use crate::chain::record::JointKind;
use crate::geom::{Point, Vec2};
use crate::lac::{LacError, LacSegment};
use nalgebra::DVector;

/// The unknowns of a chain.
#[derive(Clone, Debug)]
pub(super) struct Params {
    pub(super) theta0: f64,
    /// Each segment's own start point and tangent angle (the shooting form, see [`Form`]).
    pub(super) pose: Vec<(Point, f64)>,
    /// Log-magnitude of each joint's curvature (unused at zero joints).
    pub(super) u: Vec<f64>,
    /// Log-length of each segment.
    pub(super) v: Vec<f64>,
    /// α of each segment (unused where not free).
    pub(super) alpha: Vec<f64>,
    /// The point the chain's end must meet: fixed at a corner, moved by [`Var::EndShift`] at the
    /// stroke's own end (see [`Layout::free_end`]).
    pub(super) end: Point,
    /// The G1 chain's start and end points and the normals there, along which
    /// [`Var::StartShift`] and [`Var::EndShift`] move them.
    pub(super) anchors: [(Point, Vec2); 2],
    /// The shifts of the start and the end along those normals.
    pub(super) shift: [f64; 2],
    /// The tangent angle the chain's end must meet at a closed chain's seam held at the end
    /// only (the seam's angle one turn on, see [`Layout::seam`]); `None` elsewhere.
    pub(super) end_angle: Option<f64>,
    /// Where the chain is the whole closed chain ([`Layout::tied`]): the turn from its start's
    /// tangent angle to its end's (±2π for one round), which the end meets; the start's angle
    /// and the seam's curvature stay unknowns, tied to the end's by two constraint rows.
    pub(super) seam_turn: Option<f64>,
    /// Whether a whole closed chain's seam, where its curvature is not zero, holds dκ/ds on
    /// both sides too when the fit is C3 (one more row after the tie).
    pub(super) seam_c3: bool,
}

impl Params {
    /// The constraint rows after the C3 rows (`c3`: whether the fit is C3): the end angle of a
    /// seam held at the end (one), or a tied seam's angle and curvature (two), and its dκ/ds
    /// (one more, C3 only).
    pub(super) fn seam_rows(&self, c3: bool) -> usize {
        usize::from(self.end_angle.is_some())
            + 2 * usize::from(self.seam_turn.is_some())
            + usize::from(c3 && self.seam_c3 && self.seam_turn.is_some())
    }
}

/// One free unknown.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Var {
    Theta0,
    /// Segment k's start x, y and tangent angle (the shooting form).
    X(usize),
    Y(usize),
    Angle(usize),
    Joint(usize),
    Length(usize),
    Alpha(usize),
    /// The chain's start point across its tangent where it is free (see [`Layout::free_start`]):
    /// along the tangent it would slide beyond the first sample at no cost.
    StartShift,
    /// The chain's end point across its tangent where it is free.
    EndShift,
}

/// The chain's structure: which joints are zero, their signs, which α are free and within what.
#[derive(Clone, Debug)]
pub(super) struct Layout {
    /// Per joint (n + 1): sign of the curvature, 0 at a zero joint.
    pub(super) sigma: Vec<f64>,
    /// Per segment: its α range, `None` for a line (both joints zero) or a fixed α.
    pub(super) alpha_bounds: Vec<Option<(f64, f64)>>,
    /// Per segment: the largest length.
    pub(super) max_length: Vec<f64>,
    /// Per segment: the largest turning (radians, either sense; see [`MAX_EXTRA_TURNING`]).
    pub(super) max_turning: Vec<f64>,
    /// Per segment: the joint kind at its start (the last segment's end is in `end_kind`).
    pub(super) kinds: Vec<JointKind>,
    pub(super) end_kind: JointKind,
    /// The α search record carried from the G1 segment each segment comes from.
    pub(super) origin: Vec<usize>,
    /// Whether the chain's start and its end are a closed chain's seam
    /// ([`JointKind::Seam`]). Where both are ([`Layout::tied`]), the seam's tangent and
    /// curvature are unknowns shared by both ends through two constraint rows
    /// ([`Params::seam_turn`]); where one is (a part of the chain between a seam and a corner),
    /// its pose and curvature are held (the start's angle and the joint's curvature are not
    /// unknowns; the end's curvature is not, its angle is a constraint, [`Params::end_angle`]).
    /// Either way the last segment meets the first as smoothly as any two neighbours.
    pub(super) seam: [bool; 2],
}

/// How the unknowns lay out a chain.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Form {
    /// Multiple shooting: every segment from its own start pose, the joints' positions and
    /// tangents as equality constraints. A parameter moves one or two segments only, so the
    /// problem is as well conditioned on a 50-segment chain as on a 2-segment one; this is the
    /// form the fit runs in.
    Shooting,
    /// Forward: the chain laid out from its start pose, continuity by construction; the end
    /// point the only position constraint. The fit's answer is moved into it by a few Newton
    /// steps at the end, so that joints meet exactly, not to a tolerance.
    Forward,
}

impl Layout {
    pub(super) fn n(&self) -> usize {
        self.alpha_bounds.len()
    }

    /// Whether the chain is a whole closed chain, both its ends at the seam: the seam's tangent
    /// and curvature are then unknowns of both ends (see [`Layout::seam`]).
    pub(super) fn tied(&self) -> bool {
        self.seam[0] && self.seam[1]
    }

    /// Whether the seam holds end `end` (0 the start, 1 the end) fixed: a seam end of a part
    /// that is not the whole closed chain.
    pub(super) fn held(&self, end: usize) -> bool {
        self.seam[end] && !self.tied()
    }

    /// Whether the chain's start point is an unknown: at the stroke's own start, where the
    /// B-spline's end carries the first sample's noise (a whole-pixel grid puts it up to half a
    /// pixel's diagonal from the curve drawn). A corner is shared with the neighbouring part and
    /// stays.
    pub(super) fn free_start(&self) -> bool {
        self.kinds.first() == Some(&JointKind::Start)
    }

    /// Whether the chain's end point is an unknown (as [`Layout::free_start`]).
    pub(super) fn free_end(&self) -> bool {
        self.end_kind == JointKind::End
    }

    /// The end point's unknown where it is free.
    pub(super) fn end_vars(&self) -> Vec<Var> {
        if self.free_end() {
            vec![Var::EndShift]
        } else {
            Vec::new()
        }
    }

    /// The forward form's unknowns: the start angle, then [`Layout::shape_vars`], then the free
    /// end point's (the forward form lays the chain out from the start pose of the shooting
    /// form's first segment).
    pub(super) fn vars(&self) -> Vec<Var> {
        let mut vars = Vec::new();
        if !self.held(0) {
            vars.push(Var::Theta0);
        }
        vars.extend(self.shape_vars());
        vars.extend(self.end_vars());
        vars
    }

    /// The unknowns both forms share: the joints' log-curvatures (but zero joints), the
    /// segments' log-lengths and their free α.
    pub(super) fn shape_vars(&self) -> Vec<Var> {
        let mut vars = Vec::new();
        let held = |j: usize| (j == 0 && self.held(0)) || (j == self.n() && self.held(1));
        vars.extend(
            (0..=self.n())
                .filter(|&j| self.sigma[j] != 0.0 && !held(j))
                .map(Var::Joint),
        );
        vars.extend((0..self.n()).map(Var::Length));
        vars.extend(
            (0..self.n())
                .filter(|&k| self.alpha_bounds[k].is_some())
                .map(Var::Alpha),
        );
        vars
    }

    /// The shooting form's unknowns.
    pub(super) fn shooting_vars(&self) -> Vec<Var> {
        let first = usize::from(self.held(0));
        let mut vars: Vec<Var> = (first..self.n()).map(Var::Angle).collect();
        if self.free_start() {
            vars.push(Var::StartShift);
        }
        vars.extend((1..self.n()).flat_map(|k| [Var::X(k), Var::Y(k)]));
        vars.extend(self.shape_vars());
        vars.extend(self.end_vars());
        vars
    }

    pub(super) fn vars_of(&self, form: Form) -> Vec<Var> {
        match form {
            Form::Shooting => self.shooting_vars(),
            Form::Forward => self.vars(),
        }
    }

    /// Every segment from its own start pose.
    pub(super) fn build_shooting(&self, x: &Params) -> Result<Vec<LacSegment>, LacError> {
        (0..self.n())
            .map(|k| self.segment(x, k, x.pose[k].0, x.pose[k].1))
            .collect()
    }

    pub(super) fn build_form(&self, form: Form, x: &Params) -> Result<Vec<LacSegment>, LacError> {
        match form {
            Form::Shooting => self.build_shooting(x),
            Form::Forward => self.build(x, x.pose[0].0),
        }
    }

    /// The segments a change of `var` reshapes in the shooting form (none, `(1, 0)`, for the
    /// end point).
    pub(super) fn shooting_reach(&self, var: Var) -> (usize, usize) {
        match var {
            Var::Theta0 => (0, 0),
            Var::EndShift => (1, 0),
            Var::StartShift => (0, 0),
            Var::X(k) | Var::Y(k) | Var::Angle(k) | Var::Length(k) | Var::Alpha(k) => (k, k),
            Var::Joint(j) => (j.saturating_sub(1), j.min(self.n() - 1)),
        }
    }

    pub(super) fn kappa(&self, x: &Params, j: usize) -> f64 {
        if self.sigma[j] == 0.0 {
            0.0
        } else {
            self.sigma[j] * x.u[j].exp()
        }
    }

    /// Segment k of `x` starting at `start` with tangent angle `theta`.
    pub(super) fn segment(
        &self,
        x: &Params,
        k: usize,
        start: Point,
        theta: f64,
    ) -> Result<LacSegment, LacError> {
        let (ka, kb) = (self.kappa(x, k), self.kappa(x, k + 1));
        let alpha = (ka != kb).then_some(x.alpha[k]);
        LacSegment::new(start, theta, x.v[k].exp(), alpha, ka, kb)
    }

    /// The whole chain of `x` from `start`.
    pub(super) fn build(&self, x: &Params, start: Point) -> Result<Vec<LacSegment>, LacError> {
        let mut segments: Vec<LacSegment> = Vec::with_capacity(self.n());
        let (mut p, mut theta) = (start, x.theta0);
        for k in 0..self.n() {
            let seg = self.segment(x, k, p, theta)?;
            p = seg.end();
            theta = seg.theta1();
            segments.push(seg);
        }
        Ok(segments)
    }

    /// Segments `k0..=k1` of `x` rebuilt from the start pose of `segments[k0]`.
    pub(super) fn rebuild(
        &self,
        x: &Params,
        segments: &[LacSegment],
        k0: usize,
        k1: usize,
    ) -> Result<Vec<LacSegment>, LacError> {
        let (mut p, mut theta) = (segments[k0].start(), segments[k0].theta0());
        let mut out = Vec::with_capacity(k1 + 1 - k0);
        for k in k0..=k1 {
            let seg = self.segment(x, k, p, theta)?;
            p = seg.end();
            theta = seg.theta1();
            out.push(seg);
        }
        Ok(out)
    }

    /// The segments a change of `var` reshapes (the rest before them stay, after them move
    /// rigidly).
    pub(super) fn reach(&self, var: Var) -> (usize, usize) {
        match var {
            Var::Theta0 => (0, self.n() - 1),
            Var::EndShift => (1, 0),
            Var::StartShift => (0, self.n() - 1),
            Var::Joint(j) => (j.saturating_sub(1), j.min(self.n() - 1)),
            Var::Length(k) | Var::Alpha(k) | Var::X(k) | Var::Y(k) | Var::Angle(k) => (k, k),
        }
    }

    /// Whether a segment of `segments` (laid out by this layout) turns more than its
    /// [`MAX_EXTRA_TURNING`] bound.
    pub(super) fn winds(&self, segments: &[LacSegment]) -> bool {
        segments
            .iter()
            .zip(&self.max_turning)
            .any(|(s, &max)| (s.theta1() - s.theta0()).abs() > max)
    }

    /// Interior joints whose dκ/ds is constrained (C3): the non-zero ones.
    pub(super) fn c3_joints(&self) -> Vec<usize> {
        (1..self.n()).filter(|&j| self.sigma[j] != 0.0).collect()
    }

    /// Whether segment k's α is an unknown in the log scale w = −ln(−α) (α = −e^{−w}) rather
    /// than α itself: where the segment has a zero-curvature end (its α < 0 by its bounds).
    /// There the curvature leaves zero as s^{−1/α}, the shape is a power of the exponent −1/α,
    /// and a step in α moves it by 1/α² (25 times as much at α = −0.2 as at −1): a Gauss–Newton
    /// step that fits at α = −1.4 overshoots by far at −0.3. In w a step is a factor of α; a
    /// painting stroke's S whose α went from −1.35 to −0.2 in eight shrinking steps takes six.
    /// (For every α ≤ [`ZERO_END_ALPHA`] the nine recorded fixture files gave 11 segments fewer
    /// still, but a planted chain of three segments with a clothoid between two non-zero
    /// curvatures came back as four.)
    pub(super) fn log_alpha(&self, x: &Params, k: usize) -> bool {
        (self.sigma[k] == 0.0 || self.sigma[k + 1] == 0.0) && x.alpha[k] < 0.0
    }

    /// Whether `var` sits on its bound in `x` with `direction` (the sign of a step) pointing
    /// beyond it.
    pub(super) fn pushed_beyond(
        &self,
        var: Var,
        x: &Params,
        direction: f64,
        log_kappa: (f64, f64),
    ) -> bool {
        let at = |value: f64, lo: f64, hi: f64| {
            (value >= hi - BOUND_SLACK && direction > 0.0)
                || (value <= lo + BOUND_SLACK && direction < 0.0)
        };
        match var {
            Var::Alpha(k) => self.alpha_bounds[k].is_some_and(|(lo, hi)| at(x.alpha[k], lo, hi)),
            Var::Joint(j) => at(x.u[j], log_kappa.0, log_kappa.1),
            Var::Length(k) => at(x.v[k], f64::NEG_INFINITY, self.max_length[k].ln()),
            _ => false,
        }
    }

    /// Clamps `x` into the box: α within its bounds, curvature within the cap, length within
    /// its largest.
    pub(super) fn clamp(&self, x: &mut Params, (min_log_kappa, max_log_kappa): (f64, f64)) {
        for k in 0..self.n() {
            if let Some((lo, hi)) = self.alpha_bounds[k] {
                x.alpha[k] = x.alpha[k].clamp(lo, hi);
            }
            x.v[k] = x.v[k].min(self.max_length[k].ln());
        }
        for u in &mut x.u {
            *u = u.clamp(min_log_kappa, max_log_kappa);
        }
    }
}

pub(super) fn get(layout: &Layout, x: &Params, var: Var) -> f64 {
    match var {
        Var::Theta0 => x.theta0,
        Var::X(k) => x.pose[k].0.x,
        Var::Y(k) => x.pose[k].0.y,
        Var::Angle(k) => x.pose[k].1,
        Var::Joint(j) => x.u[j],
        Var::Length(k) => x.v[k],
        Var::Alpha(k) if layout.log_alpha(x, k) => -(-x.alpha[k]).ln(),
        Var::Alpha(k) => x.alpha[k],
        Var::StartShift => x.shift[0],
        Var::EndShift => x.shift[1],
    }
}

pub(super) fn set(layout: &Layout, x: &mut Params, var: Var, value: f64) {
    match var {
        Var::Theta0 => x.theta0 = value,
        Var::X(k) => x.pose[k].0.x = value,
        Var::Y(k) => x.pose[k].0.y = value,
        Var::Angle(k) => x.pose[k].1 = value,
        Var::Joint(j) => x.u[j] = value,
        Var::Length(k) => x.v[k] = value,
        Var::Alpha(k) if layout.log_alpha(x, k) => x.alpha[k] = -(-value).exp(),
        Var::Alpha(k) => x.alpha[k] = value,
        Var::StartShift => {
            x.shift[0] = value;
            x.pose[0].0 = x.anchors[0].0 + x.anchors[0].1 * value;
        }
        Var::EndShift => {
            x.shift[1] = value;
            x.end = x.anchors[1].0 + x.anchors[1].1 * value;
        }
    }
}

/// Undoes [`set`] of `var` on `moved`, a copy of `x`: the stored fields copied back, bit for
/// bit (setting `get` again would round a log-scale α).
pub(super) fn restore(moved: &mut Params, x: &Params, var: Var) {
    match var {
        Var::Theta0 => moved.theta0 = x.theta0,
        Var::X(k) | Var::Y(k) | Var::Angle(k) => moved.pose[k] = x.pose[k],
        Var::Joint(j) => moved.u[j] = x.u[j],
        Var::Length(k) => moved.v[k] = x.v[k],
        Var::Alpha(k) => moved.alpha[k] = x.alpha[k],
        Var::StartShift => {
            moved.shift[0] = x.shift[0];
            moved.pose[0] = x.pose[0];
        }
        Var::EndShift => {
            moved.shift[1] = x.shift[1];
            moved.end = x.end;
        }
    }
}

/// The left normal of tangent angle θ.
pub(super) fn normal(theta: f64) -> Vec2 {
    let (s, c) = theta.sin_cos();
    Vec2::new(-s, c)
}

pub(super) fn perp(v: Vec2) -> Vec2 {
    Vec2::new(-v.y, v.x)
}

/// `x` moved by `delta` over `vars`.
pub(super) fn step_by(layout: &Layout, x: &Params, vars: &[Var], delta: &DVector<f64>) -> Params {
    let mut out = x.clone();
    for (i, &var) in vars.iter().enumerate() {
        set(layout, &mut out, var, get(layout, x, var) + delta[i]);
    }
    out
}
