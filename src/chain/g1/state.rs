//! The chain as unknowns: joints (position, tangent angle) and one α per segment. Every segment
//! is the Yoshida–Saito segment of its two joints ([`crate::lac::fit_g1`]), so any state is G1.

use crate::chain::record::JointKind;
use crate::geom::{Point, Vec2};
use crate::lac::deviation::{Deviation, deviation_near, points_at};
use crate::lac::yoshida_saito::{drawable_margin, fit_g1_probe};
use crate::lac::{LacError, LacSegment, deviation, fit_g1_near, within};
use rustc_hash::FxHashMap;
use std::cell::RefCell;
use std::rc::Rc;

/// A drawable margin (radians) below minus this is outside the region beyond doubt: far above
/// the series' rounding (~1e-13 rad, see [`drawable_margin`]), far below any step a refinement
/// takes.
const CLEARLY_OUTSIDE: f64 = 1e-9;

/// A joint of the chain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Joint {
    /// Position.
    pub p: Point,
    /// Tangent angle (radians).
    pub angle: f64,
    /// What the joint is.
    pub kind: JointKind,
    /// Whether the position is held (a corner shared with the neighbouring piece, a seam).
    pub fixed: bool,
    /// Whether the tangent is held too (a closed chain's seam: both of its sides meet the
    /// seam's tangent, see [`JointKind::Seam`]).
    pub held_angle: bool,
    /// The B-spline parameter the joint was taken at (refinement moves the joint off the
    /// B-spline; this stays where it came from, to find the B-spline between two joints).
    pub u: f64,
}

impl Joint {
    /// A joint whose position may move, taken at B-spline parameter 0 (for tests that build a
    /// state by hand).
    #[cfg(test)]
    pub fn free(p: Point, angle: f64, kind: JointKind) -> Self {
        Joint {
            p,
            angle,
            kind,
            fixed: false,
            held_angle: false,
            u: 0.0,
        }
    }

    /// The unit tangent.
    pub fn tangent(&self) -> Vec2 {
        Vec2::new(self.angle.cos(), self.angle.sin())
    }
}

/// The chain's unknowns and the samples each segment answers for.
#[derive(Clone, Debug)]
pub(crate) struct State<'a> {
    /// All sample positions of the piece.
    pub points: &'a [Point],
    /// K + 1 joints.
    pub joints: Vec<Joint>,
    /// K slopes.
    pub alphas: Vec<f64>,
    /// For each segment, the indices (into `points`, ordered along the curve) of the samples it
    /// is measured against.
    pub samples: Vec<Vec<usize>>,
    /// Segments curving more than this are not allowed (see the chain's minimum radius).
    pub max_curvature: f64,
    /// Segments and evaluations already computed, shared by the clones of a state (see
    /// [`Memo`]).
    pub memo: Memo,
}

/// A segment's data: both joints' position and angle and its α, as bits.
pub(crate) type SegmentKey = [u64; 7];

/// An evaluation's data: the segment's, its samples, the chord error's bits, and which end
/// anchors its residuals carry (joint index, sample index).
type EvaluationKey = (SegmentKey, Vec<usize>, u64, Vec<(usize, u64, u64)>);

/// What the fitting steps have built, by their exact data: the same segment between the same
/// joints is asked for again and again (repair, subdivision, every refinement's start, merging,
/// the final measure), and building it is a Yoshida–Saito solve, measuring it a trace and a
/// projection. Shared by a state's clones (trial states included: a rejected trial's entries are
/// simply never asked for again); the result is the same as building afresh, to the solver's
/// tolerance.
#[derive(Clone, Debug, Default)]
pub(crate) struct Memo(Rc<RefCell<MemoTables>>);

#[derive(Debug, Default)]
struct MemoTables {
    segments: FxHashMap<SegmentKey, Result<LacSegment, LacError>>,
    /// By segment data, samples, chord error (bits) and the end anchors the residuals carry.
    evaluations: FxHashMap<EvaluationKey, Evaluated>,
}

/// Signed distances of a segment's samples (the LM residuals).
#[derive(Clone, Debug)]
pub(crate) struct Evaluated {
    /// Signed distance of each sample (left of travel positive).
    pub residuals: Vec<f64>,
    /// Largest |residual|.
    pub max: f64,
    /// The segment.
    pub segment: LacSegment,
    /// Each sample's foot point, as arc length along the segment.
    pub feet: Vec<f64>,
    /// Each sample's foot point and the unit normal there, when the distances are exact (see
    /// [`crate::lac::Deviation::foot_points`]; empty otherwise).
    pub foot_points: Vec<(Point, Vec2)>,
}

impl State<'_> {
    /// Number of segments.
    pub fn len(&self) -> usize {
        self.alphas.len()
    }

    /// Segment `k` of the state.
    pub fn segment(&self, k: usize) -> Result<LacSegment, LacError> {
        self.segment_near(k, None)
    }

    /// Segment `k`, its construction warm-started from `near` (the same segment in a nearby
    /// state; see [`fit_g1_near`]).
    pub fn segment_near(
        &self,
        k: usize,
        near: Option<&LacSegment>,
    ) -> Result<LacSegment, LacError> {
        let key = self.key(k);
        if let Some(known) = self.memo.0.borrow().segments.get(&key) {
            return known.clone();
        }
        let (a, b) = (self.joints[k], self.joints[k + 1]);
        let built = fit_g1_near(a.p, a.tangent(), b.p, b.tangent(), self.alphas[k], near).and_then(
            |segment| {
                if within(&segment, self.max_curvature) {
                    Ok(segment)
                } else {
                    Err(LacError::CurvatureTooHigh {
                        limit: self.max_curvature,
                    })
                }
            },
        );
        self.memo.0.borrow_mut().segments.insert(key, built.clone());
        built
    }

    /// Segment `k`'s evaluation as a memo key.
    fn evaluation_key(&self, k: usize, chord_error: f64) -> EvaluationKey {
        let anchors = self
            .anchors(k)
            .into_iter()
            .map(|(j, q)| (j, q.x.to_bits(), q.y.to_bits()))
            .collect();
        (
            self.key(k),
            self.samples[k].clone(),
            chord_error.to_bits(),
            anchors,
        )
    }

    /// Segment `k`'s data as a memo key.
    pub(crate) fn key(&self, k: usize) -> SegmentKey {
        let (a, b) = (self.joints[k], self.joints[k + 1]);
        [
            a.p.x.to_bits(),
            a.p.y.to_bits(),
            a.angle.to_bits(),
            b.p.x.to_bits(),
            b.p.y.to_bits(),
            b.angle.to_bits(),
            self.alphas[k].to_bits(),
        ]
    }

    /// Segment `k` and its samples' signed distances (exact foot points; `chord_error` only sets
    /// the tracing that seeds them).
    pub fn evaluate(&self, k: usize, chord_error: f64) -> Result<Evaluated, LacError> {
        self.evaluate_near(k, chord_error, None)
    }

    /// [`State::evaluate`] warm-started from `near` (see [`State::segment_near`]).
    pub fn evaluate_near(
        &self,
        k: usize,
        chord_error: f64,
        near: Option<&LacSegment>,
    ) -> Result<Evaluated, LacError> {
        let memo_key = self.evaluation_key(k, chord_error);
        if let Some(known) = self.memo.0.borrow().evaluations.get(&memo_key) {
            return Ok(known.clone());
        }
        let segment = self.segment_near(k, near)?;
        let evaluated = self.measure(k, segment, chord_error);
        self.memo
            .0
            .borrow_mut()
            .evaluations
            .insert(memo_key, evaluated.clone());
        Ok(evaluated)
    }

    /// Segment `k`'s samples measured against `segment` (built from the state's data for `k`).
    pub fn measure(&self, k: usize, segment: LacSegment, chord_error: f64) -> Evaluated {
        let d = deviation(&segment, &self.points_of(k), chord_error);
        self.evaluated(k, segment, d)
    }

    /// [`State::measure`] for a segment a small step away from `near`'s (a refinement trial): the
    /// feet are found by Newton's method from `near`'s, rescaled to the new length
    /// ([`deviation_near`]), and only traced afresh when that fails.
    pub fn measure_near(
        &self,
        k: usize,
        segment: LacSegment,
        near: &Evaluated,
        chord_error: f64,
    ) -> Evaluated {
        let points = self.points_of(k);
        let ratio = segment.length() / near.segment.length();
        let seeds: Vec<f64> = near.feet.iter().map(|f| f * ratio).collect();
        let d = deviation_near(&segment, &points, &seeds)
            .unwrap_or_else(|| deviation(&segment, &points, chord_error));
        self.evaluated(k, segment, d)
    }

    /// Records `segment` as segment `k` of this state, with `deviation`, its samples' exact
    /// distances (computed with `chord_error`): a search that chose the segment for exactly this
    /// segment's joints, α and samples has built and measured it already. Kept only when the
    /// curvature limit allows the segment (as [`State::segment`] would).
    pub fn remember(&self, k: usize, segment: LacSegment, deviation: Deviation, chord_error: f64) {
        if !within(&segment, self.max_curvature)
            || deviation.distances.len() != self.samples[k].len()
        {
            return;
        }
        let evaluated = self.evaluated(k, segment, deviation);
        let (key, memo_key) = (self.key(k), self.evaluation_key(k, chord_error));
        let mut tables = self.memo.0.borrow_mut();
        tables.segments.insert(key, Ok(segment));
        tables.evaluations.insert(memo_key, evaluated);
    }

    /// The evaluation of segment `k` from its samples' distances.
    fn evaluated(&self, k: usize, segment: LacSegment, d: Deviation) -> Evaluated {
        let mut residuals = d.signed_distances();
        residuals.extend(self.end_anchors(k));
        Evaluated {
            residuals,
            max: d.max,
            segment,
            feet: d.feet,
            foot_points: d.foot_points,
        }
    }

    /// Segment `k`'s drawable margin (see [`drawable_margin`]).
    pub fn margin(&self, k: usize) -> Option<f64> {
        let (a, b) = (self.joints.get(k)?, self.joints.get(k + 1)?);
        drawable_margin(a.p, a.tangent(), b.p, b.tangent(), *self.alphas.get(k)?)
    }

    /// Whether segment `k` is built from the same data (joints and α) in both states.
    pub fn same_segment(&self, other: &State<'_>, k: usize) -> bool {
        self.alphas[k] == other.alphas[k]
            && self.joints[k] == other.joints[k]
            && self.joints[k + 1] == other.joints[k + 1]
    }

    /// Signed residuals of segment `k`'s samples under a first-order model around `near` (an
    /// evaluation of the same segment in a nearby state): each sample is measured against the
    /// point at its old foot's arc length, along that point's normal,
    /// r = (q − P(s))·N(s). At an exact foot this is the signed distance, and since a small change
    /// of the curve moves the foot only along the tangent, it differs from the distance to the
    /// changed curve by second-order terms: enough for a finite-difference Jacobian, at the cost
    /// of one point per sample instead of a traced polyline. Feet clamped at an end (the sample
    /// lies beyond it) are measured by the distance to the end point, with the old side.
    #[cfg(test)]
    pub fn residuals_near(&self, k: usize, near: &Evaluated) -> Result<Vec<f64>, LacError> {
        let segment = self.segment_near(k, Some(&near.segment))?;
        Ok(self.model_residuals(k, &segment, near))
    }

    /// The first-order residuals of [`State::residuals_near`] for a given `segment` in place of
    /// segment `k`, end anchors included (the refinement also takes them at the current state,
    /// where `segment` is `near`'s own).
    #[cfg(test)]
    pub fn model_residuals(&self, k: usize, segment: &LacSegment, near: &Evaluated) -> Vec<f64> {
        let mut residuals = residuals_at_feet(segment, &self.points_of(k), near);
        residuals.extend(self.end_anchors(k));
        residuals
    }

    /// Segment `k`'s sample rows of the first-order model (no end anchors) with its joints
    /// and α replaced by `a`, `b`, `alpha` (a probe of the refinement's Jacobian), the
    /// construction one Newton step from `near`'s segment ([`fit_g1_probe`]: the probe is a
    /// tiny step away, and the step's O(h²) error is far below what the difference resolves).
    pub fn sample_residuals_with(
        &self,
        k: usize,
        a: &Joint,
        b: &Joint,
        alpha: f64,
        near: &Evaluated,
    ) -> Result<Vec<f64>, LacError> {
        let segment = fit_g1_probe(a.p, a.tangent(), b.p, b.tangent(), alpha, &near.segment)?;
        if !within(&segment, self.max_curvature) {
            return Err(LacError::CurvatureTooHigh {
                limit: self.max_curvature,
            });
        }
        Ok(residuals_at_feet(&segment, &self.points_of(k), near))
    }

    /// The extra residuals that pin the chain's free ends to the data: for the first segment
    /// (when the piece starts freely, not at a corner) the along-track offset
    /// (q_first − P_start)·T_start of its first sample from the start joint, and likewise for the
    /// last segment's end. The sample distances alone leave an end joint free to slide along the
    /// curve (it barely changes them), and the refinement then lets the chain overrun the stroke;
    /// these rows hold each end at its end sample's foot. They count in the least-squares cost,
    /// not in the reported distances.
    pub fn end_anchors(&self, k: usize) -> Vec<f64> {
        self.anchors(k)
            .into_iter()
            .map(|(j, q)| {
                let joint = &self.joints[j];
                (q - joint.p).dot(joint.tangent())
            })
            .collect()
    }

    /// The end anchors of segment `k` (see [`State::end_anchors`]) as (joint index, sample).
    pub fn anchors(&self, k: usize) -> Vec<(usize, Point)> {
        let mut out = Vec::new();
        let Some(samples) = self.samples.get(k) else {
            return out;
        };
        if k == 0
            && let (Some(&first), Some(joint)) = (samples.first(), self.joints.first())
            && joint.kind == JointKind::Start
        {
            out.push((0, self.points[first]));
        }
        let last_joint = self.joints.len().saturating_sub(1);
        if k + 1 == self.len()
            && let (Some(&last), Some(joint)) = (samples.last(), self.joints.last())
            && joint.kind == JointKind::End
        {
            out.push((last_joint, self.points[last]));
        }
        out
    }

    /// The sample positions of segment `k`.
    pub fn points_of(&self, k: usize) -> Vec<Point> {
        self.samples[k].iter().map(|&i| self.points[i]).collect()
    }

    /// Every segment evaluated, or the first failure.
    pub fn evaluate_all(&self, chord_error: f64) -> Result<Vec<Evaluated>, LacError> {
        (0..self.len())
            .map(|k| self.evaluate(k, chord_error))
            .collect()
    }

    /// This state evaluated, given `evaluated`, the evaluation of `base` (a nearby state with as
    /// many segments): a segment built from the same data as in `base` is taken over, the others
    /// are built warm-started from `base`'s. All segments are built before any is measured, and
    /// segment `first` (when given: the one that failed last time) before the others, so that a
    /// state with an unbuildable segment costs as few constructions as possible; on failure, the
    /// index of the segment that cannot be built.
    pub fn evaluate_all_from(
        &self,
        chord_error: f64,
        base: &State<'_>,
        evaluated: &[Evaluated],
        first: Option<usize>,
    ) -> Result<Vec<Evaluated>, usize> {
        let n = self.len().min(evaluated.len());
        // A segment clearly outside its drawable region fails before any construction: the
        // margin is a short series, a construction a quadrature per Newton step.
        if let Some(k) = (0..n).find(|&k| {
            !self.same_segment(base, k) && self.margin(k).is_some_and(|m| m < -CLEARLY_OUTSIDE)
        }) {
            return Err(k);
        }
        let mut built: Vec<Option<LacSegment>> = vec![None; n];
        let order = first
            .filter(|&f| f < n)
            .into_iter()
            .chain((0..n).filter(|&k| Some(k) != first));
        for k in order {
            if !self.same_segment(base, k) {
                built[k] = Some(
                    self.segment_near(k, Some(&evaluated[k].segment))
                        .map_err(|_| k)?,
                );
            }
        }
        Ok(built
            .into_iter()
            .zip(evaluated)
            .enumerate()
            .map(|(k, (segment, old))| match segment {
                Some(segment) => {
                    let evaluated = self.measure_near(k, segment, old, chord_error);
                    let memo_key = self.evaluation_key(k, chord_error);
                    self.memo
                        .0
                        .borrow_mut()
                        .evaluations
                        .insert(memo_key, evaluated.clone());
                    evaluated
                }
                None => old.clone(),
            })
            .collect())
    }
}

/// Sum of squared residuals.
pub(crate) fn cost(evaluated: &[Evaluated]) -> f64 {
    evaluated
        .iter()
        .flat_map(|e| e.residuals.iter())
        .map(|r| r * r)
        .sum()
}

/// The first-order residual model of [`State::residuals_near`] for `segment`.
fn residuals_at_feet(segment: &LacSegment, points: &[Point], near: &Evaluated) -> Vec<f64> {
    model_at_feet(segment, points, near)
        .into_iter()
        .map(|m| m.residual)
        .collect()
}

/// One sample row of the first-order model: the residual, the curve point it is measured from,
/// and the unit direction it is measured along (the normal at an interior foot; from the point
/// towards the sample, signed like the residual, at a foot clamped to an end). A small
/// displacement δP of the curve near the foot changes the residual by −δP·direction.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FootModel {
    /// The residual.
    pub residual: f64,
    /// The curve point at the foot.
    pub point: Point,
    /// The direction the residual is measured along.
    pub direction: Vec2,
}

/// The first-order model of [`model_at_feet`] for `near`'s own segment, from the foot points and
/// normals its measurement found (no integration along the segment); `None` when it has none
/// (see [`Evaluated::foot_points`]).
pub(crate) fn model_at_own_feet(points: &[Point], near: &Evaluated) -> Option<Vec<FootModel>> {
    if near.foot_points.len() != points.len() {
        return None;
    }
    let length = near.segment.length();
    Some(
        points
            .iter()
            .zip(&near.feet)
            .zip(&near.residuals)
            .zip(&near.foot_points)
            .map(|(((q, &foot), &r), &(point, normal))| {
                if foot <= 0.0 || foot >= length {
                    end_model(*q, point, r)
                } else {
                    FootModel {
                        residual: r,
                        point,
                        direction: normal,
                    }
                }
            })
            .collect(),
    )
}

/// The row of a foot clamped to an end at `point`: measured from the point towards the sample
/// `q`, signed like the residual `r`.
fn end_model(q: Point, point: Point, r: f64) -> FootModel {
    let distance = q.distance(point);
    let direction = if distance > 0.0 {
        (q - point) * (1.0f64.copysign(r) / distance)
    } else {
        Vec2::ZERO
    };
    FootModel {
        residual: distance.copysign(r),
        point,
        direction,
    }
}

/// The first-order model of [`State::residuals_near`] for `segment`, row by row.
pub(crate) fn model_at_feet(
    segment: &LacSegment,
    points: &[Point],
    near: &Evaluated,
) -> Vec<FootModel> {
    let old_length = near.segment.length();
    let on_curve = points_at(segment, &near.feet);
    points
        .iter()
        .zip(&near.feet)
        .zip(&near.residuals)
        .zip(on_curve)
        .map(|(((q, &foot), &r), point)| {
            if foot <= 0.0 || foot >= old_length {
                end_model(*q, point, r)
            } else {
                let theta = segment.theta(foot);
                let normal = Vec2::new(-theta.sin(), theta.cos());
                FootModel {
                    residual: (*q - point).dot(normal),
                    point,
                    direction: normal,
                }
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lac::{SpanFitOptions, fit_span};

    #[test]
    fn a_remembered_search_result_is_what_the_state_would_build_and_measure() {
        let planted = LacSegment::new(Point::new(3.0, 1.0), 0.5, 25.0, Some(0.7), 0.09, 0.03)
            .expect("segment");
        let points: Vec<Point> = (1..30)
            .map(|i| {
                let s = planted.length() * i as f64 / 30.0;
                let th = planted.theta(s);
                planted.point(s) + Vec2::new(-th.sin(), th.cos()) * (0.01 * (i % 3) as f64)
            })
            .collect();
        let joints = vec![
            Joint::free(planted.start(), planted.theta0(), JointKind::Start),
            Joint::free(planted.end(), planted.theta1(), JointKind::End),
        ];
        let chord_error = 1e-5;
        let fit = fit_span(
            joints[0].p,
            joints[0].tangent(),
            joints[1].p,
            joints[1].tangent(),
            &points,
            &SpanFitOptions::new(chord_error),
        )
        .expect("fits");
        let state = |alpha: f64| State {
            points: &points,
            joints: joints.clone(),
            alphas: vec![alpha],
            samples: vec![(0..points.len()).collect()],
            max_curvature: f64::INFINITY,
            memo: Default::default(),
        };
        let alpha = fit.segment.alpha().expect("a spiral");
        let remembered = state(alpha);
        remembered.remember(0, fit.segment, fit.deviation.clone(), chord_error);
        let fresh = state(alpha);
        let (a, b) = (
            remembered.evaluate(0, chord_error).expect("evaluates"),
            fresh.evaluate(0, chord_error).expect("evaluates"),
        );
        // The memo answers with the search's own segment and distances...
        assert_eq!(a.segment, fit.segment);
        assert_eq!(a.max, fit.deviation.max);
        // ...which are the state's own to the construction's and the feet's accuracy.
        assert_eq!(a.residuals.len(), b.residuals.len());
        for (x, y) in a.residuals.iter().zip(&b.residuals) {
            assert!((x - y).abs() < 1e-9 * planted.length(), "{x} vs {y}");
        }
        assert!((a.segment.kappa0() - b.segment.kappa0()).abs() < 1e-9 * b.segment.kappa0().abs());
    }

    #[test]
    fn the_model_from_the_measured_feet_is_the_integrated_one() {
        // Samples on both sides of a spiral, some beyond its ends (feet clamped there): the
        // foot points and normals the measurement found give the model that integrating the
        // segment at the feet gives.
        let planted = LacSegment::new(Point::new(3.0, 1.0), 0.5, 25.0, Some(-0.6), 0.02, 0.11)
            .expect("segment");
        let points: Vec<Point> = (-2..33)
            .map(|i| {
                let s = planted.length() * i as f64 / 30.0;
                let clamped = s.clamp(0.0, planted.length());
                let th = planted.theta(clamped);
                let (sin, cos) = th.sin_cos();
                planted.point(clamped)
                    + Vec2::new(cos, sin) * (s - clamped)
                    + Vec2::new(-sin, cos) * (0.05 * ((i % 5) as f64 - 2.0))
            })
            .collect();
        let joints = vec![
            Joint::free(planted.start(), planted.theta0(), JointKind::Start),
            Joint::free(planted.end(), planted.theta1(), JointKind::End),
        ];
        let state = State {
            points: &points,
            joints,
            alphas: vec![-0.6],
            samples: vec![(0..points.len()).collect()],
            max_curvature: f64::INFINITY,
            memo: Default::default(),
        };
        let e = state.evaluate(0, 1e-5).expect("evaluates");
        let own = model_at_own_feet(&points, &e).expect("exact feet");
        let integrated = model_at_feet(&e.segment, &points, &e);
        assert_eq!(own.len(), points.len());
        let ends = e
            .feet
            .iter()
            .filter(|&&f| f <= 0.0 || f >= e.segment.length());
        assert!(ends.count() >= 4, "samples beyond both ends");
        for (a, b) in own.iter().zip(&integrated) {
            assert!((a.residual - b.residual).abs() < 1e-11 * planted.length());
            assert!(a.point.distance(b.point) < 1e-11 * planted.length());
            assert!((a.direction - b.direction).hypot() < 1e-11);
        }
    }
}
