//! Cuts and repairs: segments that miss the tolerance cut on the B-spline, and spans no
//! log-aesthetic segment joins made constructible (a cut, a biarc, or a drop).

use super::refine::MAX_JOINT_OFF_CURVE;
use super::state::{Joint, State};
use super::{Fitter, NEVER_ABANDON};
use crate::chain::record::{ChainError, JointKind};
use crate::lac::{AlphaSearch, LacError, biarc, deviation, fit_span, within};

/// Passes of [`Fitter::repair`] per segment it starts with, plus [`REPAIR_PASSES_EXTRA`]: a
/// repair visits each segment once and cuts a few of them, each cut at most a few times over
/// (a fixture stroke needs well under one per segment); a budget of 16 per segment is only
/// spent by a drop and a cut undoing each other.
const REPAIR_PASSES_PER_SEGMENT: usize = 16;
/// Passes of [`Fitter::repair`] beyond those per segment (a chain of one segment may need a few
/// cuts).
const REPAIR_PASSES_EXTRA: usize = 64;

/// A segment no biarc can join is cut on the B-spline only while a half's chord exceeds this
/// many tolerances ([`Fitter::split_on_curve`]): below that, the samples there lie within the
/// tolerance of a line between the joints, and cutting cannot make a curve of them.
const MIN_SPLIT_CHORD_FRACTION: f64 = 1.0;

/// Fewest samples of a span no log-aesthetic segment joins for which [`Fitter::repair`] cuts
/// the span on the B-spline before it tries the biarc. The biarc is the answer for a span whose
/// few samples cannot tell a shape (a sharp turn between sparse mouse samples: the recorded
/// fixtures' biarcs hold 0 to 3); for a span whose samples draw one, two arcs stand in for
/// curvature that varies, and the next rounds cut and refit them again and again (a planted
/// chain with a flat point, drawn with 0.02 mm of tablet noise: a span of 437 samples no
/// single α joins became two arcs, and the subdivisions after it 115 segments, curvatures up to
/// 950 /mm and loops between samples; cut on the B-spline, the three planted segments).
const MIN_SAMPLES_BEFORE_BIARC: usize = 4;

/// Joints closer than this fraction of the tolerance coincide: a segment between them has no
/// length to speak of (and none that the data could resolve).
const COINCIDENT_JOINT_FRACTION: f64 = 1e-6;

impl<'a> Fitter<'a> {
    /// Cuts every segment that misses the tolerance where the B-spline passes its middle sample
    /// (the median of its samples' parameters): a new joint on the B-spline, with the
    /// B-spline's tangent, keeps the chain G1 and puts the joint on the data even where the
    /// segment is off it. Searches α for both halves. Returns whether any was cut.
    pub(super) fn subdivide(&self, state: &mut State<'a>, searches: &mut Vec<AlphaSearch>) -> bool {
        let mut cut = false;
        let mut k = 0;
        while k < state.len() {
            let failing = match state.evaluate(k, self.resolution.chord_error) {
                Ok(e) => e.max > self.resolution.tolerance,
                Err(_) => true,
            };
            if !failing || state.samples[k].is_empty() {
                k += 1;
                continue;
            }
            let held = &state.samples[k];
            // Between the two middle samples; a lone sample gets the joint at its own B-spline
            // point, which lies within the B-spline's deviation (≤ tolerance) of it.
            let (median, um) = if held.len() == 1 {
                (1, self.params[held[0]])
            } else {
                let m = held.len() / 2;
                (m, 0.5 * (self.params[held[m - 1]] + self.params[held[m]]))
            };
            let mid = self.joint_at(um, JointKind::Subdivision);
            let (a, b) = (state.joints[k], state.joints[k + 1]);
            // A cut within the tolerance of a free end of the piece would leave a segment the
            // data cannot resolve (refinement can move an end joint off the B-spline's end,
            // and the last sample then misses): put that end back on the B-spline instead.
            let free_end = |j: &Joint| {
                matches!(j.kind, JointKind::Start | JointKind::End)
                    && !j.fixed
                    && mid.p.distance(j.p) < self.resolution.tolerance
            };
            if let Some(which) = [(k + 1, b), (k, a)]
                .into_iter()
                .find_map(|(i, j)| free_end(&j).then_some(i))
            {
                let joint = state.joints[which];
                let (u0, u1) = self.pieces.domain();
                let u = if joint.kind == JointKind::End { u1 } else { u0 };
                let snapped = self.joint_at(u, joint.kind);
                if snapped.p != joint.p || snapped.angle != joint.angle {
                    state.joints[which] = snapped;
                    cut = true;
                }
                k += 1;
                continue;
            }
            // A cut on top of an existing joint would make a segment of no length.
            let apart = COINCIDENT_JOINT_FRACTION * self.resolution.tolerance;
            if mid.u == a.u
                || mid.u == b.u
                || mid.p.distance(a.p) <= apart
                || mid.p.distance(b.p) <= apart
            {
                k += 1;
                continue;
            }
            let (first, second) = (held[..median].to_vec(), held[median..].to_vec());
            let parent = state.alphas[k];
            // Both halves get their own α search (on B-spline points where a half holds fewer
            // than MIN_SPAN_SAMPLES samples, as for a short span): an α inherited from the parent
            // would be a default no search chose.
            let searched = |x: &Joint, y: &Joint, s: &[usize]| {
                self.search(x, y, s, (x.u, y.u), Some(parent), NEVER_ABANDON)
                    .ok()
                    .map(|found| (found.alpha, found.search, found.fit))
            };
            let (alpha0, search0, fit0) =
                searched(&a, &mid, &first).unwrap_or((parent, AlphaSearch::default(), None));
            let (alpha1, search1, fit1) =
                searched(&mid, &b, &second).unwrap_or((parent, AlphaSearch::default(), None));
            state.joints.insert(k + 1, mid);
            state.alphas.splice(k..=k, [alpha0, alpha1]);
            state.samples.splice(k..=k, [first, second]);
            searches.splice(k..=k, [search0, search1]);
            for (m, fit) in [(k, fit0), (k + 1, fit1)] {
                if let Some((segment, deviation)) = fit {
                    state.remember(m, segment, deviation, self.resolution.chord_error);
                }
            }
            cut = true;
            k += 2;
        }
        cut
    }

    /// Makes every segment of the state constructible: a segment whose α cannot join its joints
    /// gets the α its samples choose, and where no α can, the biarc's joint is inserted (both
    /// arcs are reproduced by any α). Refinement and output rely on a valid state.
    pub(super) fn repair(
        &self,
        state: &mut State<'a>,
        searches: &mut Vec<AlphaSearch>,
    ) -> Result<(), ChainError> {
        let middle = self.options.alpha.middle();
        let mut k = 0;
        // Each pass of the loop either moves on, drops a segment or cuts one; drops and cuts can
        // undo each other where the data fold on themselves (the fuzzer found a fold on a fine
        // grid that cycled for minutes), so the passes are bounded: past the budget the repair
        // fails and the pipeline cuts the piece at its sharpest vertex instead.
        let mut budget = REPAIR_PASSES_PER_SEGMENT * (state.len() + 1) + REPAIR_PASSES_EXTRA;
        while k < state.len() {
            if state.segment(k).is_ok() {
                k += 1;
                continue;
            }
            if budget == 0 {
                return Err(ChainError::Span {
                    u0: state.joints[k].u,
                    u1: state.joints[k + 1].u,
                    source: LacError::CoincidentEndPoints,
                });
            }
            budget -= 1;
            let (a, b) = (state.joints[k], state.joints[k + 1]);
            let mut reference = state.points_of(k);
            if reference.is_empty() {
                reference.push(a.p.midpoint(b.p));
            }
            if let Ok(fit) = fit_span(
                a.p,
                a.tangent(),
                b.p,
                b.tangent(),
                &reference,
                &self.span_options(),
            ) {
                state.alphas[k] = fit.segment.alpha().unwrap_or(middle);
                searches[k] = fit.search;
                k += 1;
                continue;
            }
            // Joints at one parameter of the B-spline are one point of the data, whatever
            // rounding left between their positions (seen: 1.4e-9 apart at a 1e-9 tolerance).
            let coincident = a.u == b.u
                || a.p.distance(b.p) <= COINCIDENT_JOINT_FRACTION * self.resolution.tolerance;
            let arcs = biarc(a.p, a.tangent(), b.p, b.tangent());
            // Arcs tighter than the smallest radius turn inside a disc the samples cannot resolve
            // (seen: joints 0.01 px apart at a 0.5 px tolerance, their tangents an S): the two
            // joints are one, as far as the data can tell.
            let unresolved = arcs.as_ref().is_ok_and(|[s0, s1]| {
                !(within(s0, self.resolution.max_curvature)
                    && within(s1, self.resolution.max_curvature))
            });
            // A biarc between joints whose tangents turn against their chord can meet itself
            // far away: two half circles whose joint lies across a loop (seen: joints 0.45 mm
            // apart at a 0.1 mm tolerance; the arcs met 13 mm off the stroke, every sample
            // still within the tolerance, and the next rounds cut such loops into more). A
            // biarc that follows the data strays from the B-spline by a fraction of its chord;
            // one whose joint is farther from it than the joints are apart, and beyond where a
            // refinement may take a joint ([`MAX_JOINT_OFF_CURVE`]), says the joints are out
            // of order along the data: as for arcs the data cannot resolve, one of them goes.
            let astray = arcs.as_ref().is_ok_and(|[s0, _]| {
                let off = self
                    .pieces
                    .project_local(s0.end(), 0.5 * (a.u + b.u))
                    .distance;
                off > MAX_JOINT_OFF_CURVE * self.resolution.tolerance && off > a.p.distance(b.p)
            });
            if (coincident || unresolved || astray) && state.len() > 1 {
                // A segment of no length (or none the data resolve): drop it and one of its
                // joints (the chain's last joint is kept: it is the piece's end). The segment
                // after it is rebuilt from the surviving joint, so the chain stays G1.
                let drop = if k + 1 == state.len() { k } else { k + 1 };
                state.joints.remove(drop);
                let samples = state.samples.remove(k);
                state.alphas.remove(k);
                searches.remove(k);
                let into = k.min(state.len() - 1);
                state.samples[into].extend(samples);
                let params = self.params.as_slice();
                state.samples[into].sort_by(|&x, &y| params[x].total_cmp(&params[y]));
                // The joint before may now be the one no segment joins.
                k = k.saturating_sub(1);
                continue;
            }
            let [s0, s1] = match arcs {
                Ok(arcs) if !(coincident || unresolved || astray) => {
                    // Two arcs stand for the data's shape only where the samples cannot tell
                    // one: where they can, the span is cut on the B-spline, and each half is a
                    // log-aesthetic segment of its own samples (see
                    // [`MIN_SAMPLES_BEFORE_BIARC`]).
                    if state.samples[k].len() >= MIN_SAMPLES_BEFORE_BIARC
                        && self.split_on_curve(state, searches, k)
                    {
                        continue;
                    }
                    arcs
                }
                // No biarc joins the data (tangents reversed along the chord, a piece that ends
                // where it starts, which no single segment can join, or arcs tighter than the
                // smallest radius in a piece of one segment, which nothing can be dropped
                // into; the arcs would be built and fail later): cut at the
                // B-spline's point halfway between the joints, as a subdivision does. The data
                // are a loop or a fold there, and the halves are each joinable.
                arcs => {
                    if self.split_on_curve(state, searches, k) {
                        continue;
                    }
                    let source = arcs.err().unwrap_or(LacError::CoincidentEndPoints);
                    return Err(ChainError::Span {
                        u0: a.u,
                        u1: b.u,
                        source,
                    });
                }
            };
            let mid = Joint {
                p: s0.end(),
                angle: s0.theta1(),
                kind: JointKind::Subdivision,
                fixed: false,
                held_angle: false,
                u: 0.5 * (a.u + b.u),
            };
            // The samples (in stroke order) are cut in two where the larger distance of a
            // first part to the first arc and of the rest to the second is least: each arc holds
            // a run of consecutive samples, so the segments' sample ranges tile the piece.
            let d0 = deviation(&s0, &reference, self.resolution.chord_error).distances;
            let d1 = deviation(&s1, &reference, self.resolution.chord_error).distances;
            let held = &state.samples[k];
            let n = held.len().min(d0.len()).min(d1.len());
            let mut suffix = vec![0.0f64; n + 1];
            for m in (0..n).rev() {
                suffix[m] = suffix[m + 1].max(d1[m]);
            }
            let (mut best, mut prefix, mut cut) = (suffix[0], 0.0f64, 0);
            for m in 1..=n {
                prefix = prefix.max(d0[m - 1]);
                if prefix.max(suffix[m]) < best {
                    (best, cut) = (prefix.max(suffix[m]), m);
                }
            }
            let (first, second) = (held[..cut].to_vec(), held[cut..].to_vec());
            state.joints.insert(k + 1, mid);
            state.alphas.splice(k..=k, [middle, middle]);
            state.samples.splice(k..=k, [first, second]);
            searches.splice(k..=k, [AlphaSearch::default(), AlphaSearch::default()]);
            // Each arc's G1 data is an arc's, which every α reproduces; search anyway, so that
            // the α refinement starts from (and the record shows) is a search's, not a default.
            self.research(state, searches, k);
            self.research(state, searches, k + 1);
            k += 2;
        }
        Ok(())
    }

    /// Searches segment `k`'s α again between its current joints, from its current α, and keeps
    /// the result if the search finds one (see [`Fitter::search`]).
    pub(super) fn research(&self, state: &mut State<'a>, searches: &mut [AlphaSearch], k: usize) {
        let (a, b) = (state.joints[k], state.joints[k + 1]);
        let guess = Some(state.alphas[k]);
        if let Ok(found) = self.search(&a, &b, &state.samples[k], (a.u, b.u), guess, NEVER_ABANDON)
        {
            state.alphas[k] = found.alpha;
            searches[k] = found.search;
            if let Some((segment, deviation)) = found.fit {
                state.remember(k, segment, deviation, self.resolution.chord_error);
            }
        }
    }

    /// Cuts segment `k` at the B-spline's point halfway (in the parameter) between its joints,
    /// its samples split by their parameters, each half given its α search. Returns false (and
    /// changes nothing) where that point is not apart from both joints.
    pub(super) fn split_on_curve(
        &self,
        state: &mut State<'a>,
        searches: &mut Vec<AlphaSearch>,
        k: usize,
    ) -> bool {
        let (a, b) = (state.joints[k], state.joints[k + 1]);
        let um = 0.5 * (a.u + b.u);
        let mid = self.joint_at(um, JointKind::Subdivision);
        let apart = COINCIDENT_JOINT_FRACTION * self.resolution.tolerance;
        if !(a.u < um && um < b.u) || mid.p.distance(a.p) <= apart || mid.p.distance(b.p) <= apart {
            return false;
        }
        // Halves within the tolerance of their joints' chord are no curve to cut further: the
        // repair then fails on this span and the pipeline cuts the piece at its sharpest vertex.
        // Without this floor, a fold on a fine grid (0.005 px steps at 0.1 px) was cut again and
        // again, both halves each time, for minutes (the fuzzer's hang).
        let floor = MIN_SPLIT_CHORD_FRACTION * self.resolution.tolerance;
        if mid.p.distance(a.p) <= floor && mid.p.distance(b.p) <= floor {
            return false;
        }
        let params = self.params.as_slice();
        let (first, second): (Vec<usize>, Vec<usize>) =
            state.samples[k].iter().partition(|&&i| params[i] < um);
        let alpha = state.alphas[k];
        state.joints.insert(k + 1, mid);
        state.alphas.splice(k..=k, [alpha, alpha]);
        state.samples.splice(k..=k, [first, second]);
        searches.splice(k..=k, [AlphaSearch::default(), AlphaSearch::default()]);
        self.research(state, searches, k);
        self.research(state, searches, k + 1);
        true
    }
}
