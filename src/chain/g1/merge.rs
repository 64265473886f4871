//! Fewer segments: runs a line holds become one line, neighbours one segment covers are merged,
//! and ends that curl tighter than their samples resolve are softened.

use super::refine::{RefineOptions, refine};
use super::state::State;
use super::{Fitter, MIN_SPAN_SAMPLES, NEVER_ABANDON, Searched};
use crate::chain::record::JointKind;
use crate::chain::soften::soften_fits;
use crate::geom::Point;
use crate::lac::{AlphaSearch, Deviation, LacError, LacSegment, SpanFitOptions, within};

/// A merge's α search also gives up when, at its starting α, the linear model of the distances
/// in α predicts that no α within two cells brings every sample within this many tolerances
/// (`SpanFitOptions::unreachable_above`): the merged segment must be within one, and the model's
/// error near the guess (a few percent of the distances there, which are at most
/// [`MERGE_ABANDON_FACTOR`] tolerances) is well inside the margin. It saves work for about the
/// same segments and fit; measured in `docs/performance-history.md` (chain constants).
const MERGE_UNREACHABLE_FACTOR: f64 = 1.5;

/// A merge's α search gives up when the merged segment at its starting α (the parts' α,
/// weighted by their samples) misses a sample by more than this many tolerances: the search
/// moves α by little from there, and a segment that far off does not come within the
/// tolerance. It saves work for about the same segments and fit; measured in
/// `docs/performance-history.md` (chain constants).
const MERGE_ABANDON_FACTOR: f64 = 3.0;

/// Whether a merge may drop a joint of this kind (curvature extrema, inflections and
/// subdivisions are the B-spline's or the cuts' candidates; starts, ends and corners stay).
fn removable(kind: JointKind) -> bool {
    matches!(
        kind,
        JointKind::CurvatureExtremum | JointKind::Subdivision | JointKind::Inflection
    )
}

/// How far (in tolerances) a run's merged segment between its fixed outer joints may miss a
/// sample for [`Fitter::merge_runs_refined`] to refine it: turning its end tangents brings a
/// segment several tolerances off within (the Prius line's: 4 tolerances off); one farther off is
/// another curve, and each try costs a refinement of the chain. 30 merges as many runs as a
/// looser factor; measured in `docs/performance-history.md` (chain constants).
const REFINED_MERGE_FACTOR: f64 = 30.0;

/// Longest run of segments [`Fitter::merge_fewest`] tries to replace by one: past eight, a run
/// that the greedy merges and the cuts left apart is as good as never one segment, and every run
/// costs an α search.
const MAX_MERGE_RUN: usize = 8;

impl<'a> Fitter<'a> {
    /// Replaces runs of segments by one straight segment where a line between the run's outer
    /// joints holds all its samples within the tolerance: noise on a near-straight stretch flips
    /// the curvature's sign again and again, and no log-aesthetic segment can cross an
    /// inflection, but a line absorbs them all. From each joint the run is extended as far as the
    /// chord holds the samples (a cheap point-to-segment test); the run's outer joints then turn
    /// their tangents to the chord, so the chain stays G1, and the segments beyond them, rebuilt
    /// with the turned tangents, must stay within the tolerance too. Returns whether any run was
    /// straightened.
    pub(super) fn straighten(
        &self,
        state: &mut State<'a>,
        searches: &mut Vec<AlphaSearch>,
    ) -> bool {
        let near_chord = |a: Point, b: Point, samples: &[usize]| {
            samples.iter().all(|&i| {
                let q = self.input.points[i];
                let ab = b - a;
                let f = ((q - a).dot(ab) / ab.hypot2()).clamp(0.0, 1.0);
                q.distance(a + ab * f) <= self.resolution.tolerance
            })
        };
        let mut changed = false;
        let mut i = 0;
        while i + 1 < state.len() {
            // The longest run i..k (k ≥ i + 2 joints apart) that the chord holds.
            let mut k = i + 1;
            let mut held: Vec<usize> = state.samples[i].clone();
            while k < state.len() {
                let mut extended = held.clone();
                extended.extend(&state.samples[k]);
                let (a, b) = (state.joints[i].p, state.joints[k + 1].p);
                if b.distance(a) == 0.0 || !near_chord(a, b, &extended) {
                    break;
                }
                held = extended;
                k += 1;
            }
            // Joints i and k now bound the run of segments i..k (k − i segments).
            if k - i < 2 {
                i += 1;
                continue;
            }
            let chord = state.joints[k].p - state.joints[i].p;
            let angle = chord.y.atan2(chord.x);
            let mut trial = state.clone();
            trial.joints[i].angle = angle;
            trial.joints[k].angle = angle;
            trial.joints.drain(i + 1..k);
            let alpha = trial.alphas[i];
            trial.alphas.splice(i..k, [alpha]);
            trial.samples.splice(i..k, [held]);
            let affected = i.saturating_sub(1)..(i + 2).min(trial.len());
            let fits = affected.clone().all(
                |m| matches!(trial.evaluate(m, self.resolution.chord_error), Ok(e) if e.max <= self.resolution.tolerance),
            );
            if fits {
                *state = trial;
                let line = AlphaSearch {
                    alpha: None,
                    ..AlphaSearch::default()
                };
                searches.splice(i..k, [line]);
                changed = true;
            }
            i += 1;
        }
        changed
    }

    /// Removes joints at curvature extrema, subdivisions and inflections where one segment covers
    /// both neighbours' samples within the tolerance. The data decide: a B-spline inflection
    /// that one single-signed segment can absorb was noise (near-straight stretches flip the
    /// sign again and again), and a real one cannot be absorbed. Where the two hold fewer than
    /// [`MIN_SPAN_SAMPLES`] samples, the merged segment must also stay within the tolerance of
    /// the B-spline between the joints (its α is searched on B-spline points, as for a short
    /// span): the few samples cannot decide the shape, but they cannot justify a joint either
    /// (over the fixture strokes up to 600 samples, merging these too leaves 843 segments instead
    /// of 1 140, the rms distance unchanged). Returns whether any was removed.
    pub(super) fn merge(&self, state: &mut State<'a>, searches: &mut Vec<AlphaSearch>) -> bool {
        let mut merged = false;
        let mut j = 1;
        while j + 1 < state.joints.len() {
            if removable(state.joints[j].kind) {
                let (union, found) = self.search_merged(state, j - 1..j + 1);
                // Too few samples to decide the merged shape: the search ran on the B-spline's
                // points instead, and the merged segment must stay within the tolerance of them.
                let sparse = union.len() < MIN_SPAN_SAMPLES;
                if let Ok(found) = found
                    && (!sparse || found.max <= self.resolution.tolerance)
                {
                    let search = found.search;
                    let mut trial = state.clone();
                    self.replace_run(&mut trial, j - 1..j + 1, union, found.alpha, found.fit);
                    if matches!(trial.evaluate(j - 1, self.resolution.chord_error), Ok(e) if e.max <= self.resolution.tolerance)
                    {
                        *state = trial;
                        searches.splice(j - 1..=j, [search]);
                        merged = true;
                        continue;
                    }
                }
            }
            j += 1;
        }
        merged
    }

    /// Segments `run` of the state as one: their samples together, and the α search between the
    /// run's outer joints, starting from the parts' α weighted by their samples and giving up as
    /// a merge does ([`MERGE_ABANDON_FACTOR`], [`MERGE_UNREACHABLE_FACTOR`]).
    pub(super) fn search_merged(
        &self,
        state: &State,
        run: std::ops::Range<usize>,
    ) -> (Vec<usize>, Result<Searched, LacError>) {
        let parts = &state.samples[run.clone()];
        let union: Vec<usize> = parts.iter().flatten().copied().collect();
        let weights: f64 = parts.iter().map(|l| l.len() as f64).sum();
        let guess = parts
            .iter()
            .zip(&state.alphas[run.clone()])
            .map(|(l, a)| l.len() as f64 * a)
            .sum::<f64>()
            / weights.max(1.0);
        let (a, b) = (state.joints[run.start], state.joints[run.end]);
        let found = self.search(
            &a,
            &b,
            &union,
            (a.u, b.u),
            Some(guess),
            (
                MERGE_ABANDON_FACTOR * self.resolution.tolerance,
                MERGE_UNREACHABLE_FACTOR * self.resolution.tolerance,
            ),
        );
        (union, found)
    }

    /// Replaces segments `run` of `state` by one segment between the run's outer joints, holding
    /// `union` (their samples) with α `alpha`; `fit` is that segment and its samples' distances
    /// when the α search ran on the samples (remembered, not built and measured again).
    pub(super) fn replace_run(
        &self,
        state: &mut State<'a>,
        run: std::ops::Range<usize>,
        union: Vec<usize>,
        alpha: f64,
        fit: Option<(LacSegment, Deviation)>,
    ) {
        state.joints.drain(run.start + 1..run.end);
        state.alphas.splice(run.clone(), [alpha]);
        state.samples.splice(run.clone(), [union]);
        if let Some((segment, deviation)) = fit {
            state.remember(run.start, segment, deviation, self.resolution.chord_error);
        }
    }

    /// Whether every segment of `state` holds its samples within the tolerance.
    pub(super) fn holds(&self, state: &State) -> bool {
        (0..state.len()).all(
            |k| matches!(state.evaluate(k, self.resolution.chord_error), Ok(e) if e.max <= self.resolution.tolerance),
        )
    }

    /// Merges runs of segments into single segments so that the chain has the fewest segments
    /// that hold the tolerance over its current joints, then the smallest sum of squared
    /// distances: a shortest path over the joints (dynamic programming), each edge one segment
    /// through two joints' positions and tangents, searched for its α like a merge. The greedy
    /// [`Fitter::merge`] takes the first pair that fits, which can block two merges that fit
    /// together; this sees every run of up to [`MAX_MERGE_RUN`] segments. Only the joints a merge
    /// may drop (curvature extrema, inflections, subdivisions) are skipped; a run whose merged
    /// segment misses a sample by more than [`MERGE_ABANDON_FACTOR`] tolerances ends the longer
    /// runs through it too. Returns whether the chain changed.
    pub(super) fn merge_fewest(
        &self,
        state: &mut State<'a>,
        searches: &mut Vec<AlphaSearch>,
    ) -> bool {
        let m = state.len();
        if m < 2 {
            return false;
        }
        let squares = |d: &[f64]| d.iter().map(|r| r * r).sum::<f64>();
        let own: Vec<f64> = (0..m)
            .map(|k| {
                state
                    .evaluate(k, self.resolution.chord_error)
                    .map(|e| squares(&e.residuals[..state.samples[k].len()]))
                    .unwrap_or(f64::INFINITY)
            })
            .collect();
        // best[j]: (segments, sum of squares, where the last segment starts, its merged fit).
        type Step = (
            usize,
            f64,
            usize,
            Option<(f64, AlphaSearch, LacSegment, Deviation)>,
        );
        let mut best: Vec<Step> = Vec::with_capacity(m + 1);
        best.push((0, 0.0, 0, None));
        for j in 1..=m {
            let mut choice: Step = (best[j - 1].0 + 1, best[j - 1].1 + own[j - 1], j - 1, None);
            let lowest = j.saturating_sub(MAX_MERGE_RUN);
            let mut i = j - 1;
            while i > lowest && removable(state.joints[i].kind) {
                i -= 1;
                // Segments i..j as one.
                if best[i].0 + 1 > choice.0 {
                    continue;
                }
                let (union, found) = self.search_merged(state, i..j);
                if union.len() < MIN_SPAN_SAMPLES {
                    continue;
                }
                let Ok(found) = found else {
                    break;
                };
                let Some((segment, deviation)) = found.fit else {
                    continue;
                };
                if deviation.max > self.resolution.tolerance
                    || !within(&segment, self.resolution.max_curvature)
                {
                    if found.max > MERGE_ABANDON_FACTOR * self.resolution.tolerance {
                        break;
                    }
                    continue;
                }
                let total = best[i].1 + squares(&deviation.distances);
                let count = best[i].0 + 1;
                if count < choice.0 || (count == choice.0 && total < choice.1) {
                    choice = (
                        count,
                        total,
                        i,
                        Some((found.alpha, found.search, segment, deviation)),
                    );
                }
            }
            best.push(choice);
        }
        if best[m].0 >= m {
            return false;
        }
        // Walk back along the path, merging from the end so earlier indices stay valid.
        let mut trial = state.clone();
        let mut trial_searches = searches.clone();
        let mut j = m;
        while j > 0 {
            let (_, _, i, merged) = best[j].clone();
            if let Some((alpha, search, segment, deviation)) = merged {
                let union: Vec<usize> = trial.samples[i..j].iter().flatten().copied().collect();
                self.replace_run(&mut trial, i..j, union, alpha, Some((segment, deviation)));
                trial_searches.splice(i..j, [search]);
            }
            j = i;
        }
        let holds = self.holds(&trial);
        if holds {
            *state = trial;
            *searches = trial_searches;
        }
        holds
    }

    /// Replaces each run of segments between joints no merge may drop (the piece's ends, its
    /// corners) by one segment where that segment, refined with the rest of the chain, holds the
    /// tolerance. The merges above test a merged segment between its outer joints as they are:
    /// their tangents are the B-spline's or the refined parts', and a curve that is one
    /// log-aesthetic segment with other end tangents is then never found (a car's character line
    /// that one LAC holds within 1.32 mm came back as two segments at 1.6 mm). Here the merged
    /// segment's end poses move in the refinement (freely at the piece's ends). Only runs whose
    /// merged segment between the fixed joints is within [`REFINED_MERGE_FACTOR`] tolerances are
    /// tried: one refinement each. Returns whether any run was merged.
    pub(super) fn merge_runs_refined(
        &self,
        state: &mut State<'a>,
        searches: &mut Vec<AlphaSearch>,
        options: &RefineOptions,
    ) -> bool {
        let ends: Vec<usize> = (0..state.joints.len())
            .filter(|&j| j == 0 || j + 1 == state.joints.len() || !removable(state.joints[j].kind))
            .collect();
        let mut merged = false;
        // From the last run, so that the earlier joints' indices stay valid.
        for w in ends.windows(2).rev() {
            let (i, j) = (w[0], w[1]);
            if j - i < 2 {
                continue;
            }
            let union: Vec<usize> = state.samples[i..j].iter().flatten().copied().collect();
            if union.len() < MIN_SPAN_SAMPLES {
                continue;
            }
            let (a, b) = (state.joints[i], state.joints[j]);
            let found = self.search(&a, &b, &union, (a.u, b.u), None, NEVER_ABANDON);
            let Ok(found) = found else {
                continue;
            };
            if found.max > REFINED_MERGE_FACTOR * self.resolution.tolerance {
                continue;
            }
            let mut trial = state.clone();
            self.replace_run(&mut trial, i..j, union, found.alpha, found.fit);
            let off_curve = |p: Point, u: f64| self.pieces.project_local(p, u).distance;
            // Only the merged segment moves (the runs around it end at fixed joints).
            let active: Vec<bool> = (0..trial.len()).map(|k| k == i).collect();
            if refine(&mut trial, options, Some(&active), &off_curve).is_none() {
                continue;
            }
            if self.holds(&trial) {
                *state = trial;
                searches.splice(i..j, [found.search]);
                merged = true;
            }
        }
        merged
    }

    /// Turns the tangent at a corner or a free end of the piece where the segment leaving it
    /// curls tighter than its samples resolve (a radius under half a tolerance,
    /// [`crate::chain::measure::MIN_RADIUS_TOLERANCES`]), so that the segment need not: the tangent there is the piece's own (a corner is G0), and the B-spline's end
    /// tangent, which the segment started from, follows the last few samples' noise. The tangent
    /// is turned towards the segment's chord in steps ([`SOFTEN_STEPS`]), then towards the
    /// tangent of the circular arc through both ends that keeps the other end's (on a near line
    /// the chord's tangent asks for an inflection no log-aesthetic segment has); a piece of one
    /// segment also turns both its ends towards the chord together. The first turn whose
    /// segment (α searched again, walking from the segment's own and abandoned where it cannot
    /// hold the tolerance, as the merges' searches are) stays within the bound and holds its
    /// samples within the tolerance is kept; nothing else moves. Returns whether any end was
    /// turned. (The whole-range search at every turn took a quarter more time here for more
    /// curls: in g1, 24 against 20 segments tighter than half a tolerance on the nine fixture
    /// files.)
    pub(super) fn soften_ends(&self, state: &mut State<'a>, searches: &mut [AlphaSearch]) -> bool {
        let n = state.len();
        if n == 0 {
            return false;
        }
        let cap = 1.0 / (crate::chain::measure::MIN_RADIUS_TOLERANCES * self.resolution.tolerance);
        let mut changed = false;
        // (segment, joint at the end that may turn, whether that is its start)
        for (k, j, at_start) in [(0, 0, true), (n - 1, n, false)] {
            if !state.joints[j].kind.tangent_free() {
                continue;
            }
            let Ok(segment) = state.segment(k) else {
                continue;
            };
            let end_kappa = if at_start {
                segment.kappa0()
            } else {
                segment.kappa1()
            };
            if end_kappa.abs() <= cap || state.samples[k].len() < MIN_SPAN_SAMPLES {
                continue;
            }
            let (a, b) = (state.joints[k], state.joints[k + 1]);
            let points: Vec<Point> = state.points_of(k);
            let options = SpanFitOptions {
                max_curvature: cap,
                guess: Some(state.alphas[k]),
                abandon_above: self.resolution.tolerance,
                unreachable_above: self.resolution.tolerance,
                ..self.span_options()
            };
            let fits = soften_fits(
                (a.p, a.angle),
                (b.p, b.angle),
                at_start,
                n == 1,
                &points,
                options,
                self.resolution.tolerance,
            );
            for ((start_angle, end_angle), fit) in fits {
                let (mut ta, mut tb) = (a, b);
                ta.angle = start_angle;
                tb.angle = end_angle;
                // Only segment k uses a joint that turns (an end of the piece): set them, and
                // keep them if the state's own measure of the segment agrees (it takes the
                // search's, remembered).
                let kept = (state.joints[k], state.joints[k + 1], state.alphas[k]);
                (state.joints[k], state.joints[k + 1]) = (ta, tb);
                state.alphas[k] = fit.segment.alpha().unwrap_or(self.options.alpha.middle());
                state.remember(k, fit.segment, fit.deviation, self.resolution.chord_error);
                if matches!(state.evaluate(k, self.resolution.chord_error), Ok(e) if e.max <= self.resolution.tolerance)
                {
                    searches[k] = fit.search;
                    changed = true;
                    break;
                }
                (state.joints[k], state.joints[k + 1], state.alphas[k]) = kept;
            }
        }
        changed
    }
}
