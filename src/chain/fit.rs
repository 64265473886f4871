use rustc_hash::FxHashSet;

use serde::{Deserialize, Serialize};

use super::alpha_evidence::{
    ALPHA_DIFFERENCE_STEP, AlphaBound, AlphaSource, UNDETERMINED_ALPHA, alpha_uncertainty,
};
use super::refine::{
    CONVERGED_RMS, MAX_JOINT_OFF_CURVE, RefineOptions, STARTING_CONVERGED_RMS, refine,
};
use super::smooth::{Continuity, SmoothInput, smooth_chain};
use super::state::{Joint, SegmentKey, State};
use crate::bspline::BSpline;
use crate::bspline::project::Pieces;
use crate::geom::{Point, Vec2};
use crate::lac::lcg::{lcg_of_bezier_span_rough, lcg_slope};
use crate::lac::{
    AlphaChoice, AlphaSearch, Deviation, LacError, LacSegment, SpanFit, SpanFitOptions,
    alpha_search::{ALPHA_TOLERANCE, SEED_ALPHA_TOLERANCE},
    biarc, deviation, fit_span, within,
};
use crate::split::{Spans, SplitKind};

/// Distances are seeded on a polyline whose chord error is this fraction of the tolerance, then
/// polished to exact foot points; the α search ranks candidates at ten times it.
const CHORD_ERROR_FRACTION: f64 = 1e-3;

/// Smallest radius of curvature a segment may have, as a fraction of the tolerance: a curve
/// bending within a hundredth of the tolerance turns inside a disc the samples cannot resolve
/// (a corner, not a curve), and such radii (seen: 4e-12 px at the drawable region's edge) also
/// take the segment's evaluation past the accuracy its record promises.
const MIN_RADIUS_FRACTION: f64 = 1e-2;

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

/// A span holding fewer samples than this is fitted against points of its B-spline instead
/// (evenly spaced in the parameter): with one or two samples the α search has nothing to choose
/// by, and a short span's shape is the B-spline's anyway.
const MIN_SPAN_SAMPLES: usize = 3;

/// Number of B-spline points standing in for the samples of a short span.
const SPAN_REFERENCE_POINTS: usize = 8;

/// Points of a span's logarithmic curvature graph whose least-squares slope starts the span's α
/// search: enough to average out the B-spline's curvature wiggles, a few microseconds of
/// evaluation.
const LCG_GUESS_POINTS: usize = 16;

/// The limits of [`Fitter::search`] for a search that never gives up.
const NEVER_ABANDON: (f64, f64) = (f64::INFINITY, f64::INFINITY);

/// A merge's α search also gives up when, at its starting α, the linear model of the distances
/// in α predicts that no α within two cells brings every sample within this many tolerances
/// (`SpanFitOptions::unreachable_above`): the merged segment must be within one, and the model's
/// error near the guess (a few percent of the distances there, which are at most
/// [`MERGE_ABANDON_FACTOR`] tolerances) is well inside the margin. Over the fixture strokes up
/// to 600 samples at three tolerances: 2.5 % fewer instructions on the median stroke, 2 218
/// segments against 2 215 and the same rms distance (1.25: 4 %, but 2 225 segments).
const MERGE_UNREACHABLE_FACTOR: f64 = 1.5;

/// A merge's α search gives up when the merged segment at its starting α (the parts' α,
/// weighted by their samples) misses a sample by more than this many tolerances: the search
/// moves α by little from there, and a segment that far off does not come within the
/// tolerance. Over the fixture strokes up to 600 samples: 8 % fewer instructions in all and on
/// the median stroke, 737 segments against 736 and the same rms distance (0.236 of the
/// tolerance against 0.237); 2 saves 2 % more for 6 more segments; 4 saves 6 % for none.
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
/// another curve, and each try costs a refinement of the chain. Over the fixture strokes at the
/// default tolerance 30 merges as many runs as 100 (730 segments), 10 six fewer, 5 nine fewer.
const REFINED_MERGE_FACTOR: f64 = 30.0;

/// Steps in which [`Fitter::soften_ends`] turns an end tangent towards the chord (then towards
/// the arc's tangent, and for a piece of one segment both ends together): the first that removes
/// the tight curl is kept, so the tangent moves no farther than it must, to a quarter of the
/// turn. On the nine recorded fixture files in g2, segments bending tighter than half a
/// tolerance: 14 turning towards the chord alone, 11 with all three (in g1: 27, 24). Eight steps
/// give the same 11 (23 in g1) for 8 % more time in the painting's G1 chains, where each
/// failing try is an α search.
const SOFTEN_STEPS: usize = 4;

/// Longest run of segments [`Fitter::merge_fewest`] tries to replace by one: past eight, a run
/// that the greedy merges and the cuts left apart is as good as never one segment, and every run
/// costs an α search.
const MAX_MERGE_RUN: usize = 8;

/// Options of [`fit_chain`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainOptions {
    /// α allowed per segment. Default: the range [−3, 3] ([`AlphaChoice::default`]).
    pub alpha: AlphaChoice,
    /// Rounds of subdividing the segments that miss the tolerance. Default 6 (a segment can be
    /// cut into 64): beyond that, what remains is the data's, not the curve family's.
    pub max_depth: usize,
    /// Merge neighbours that one segment covers within the tolerance. Default true.
    pub merge: bool,
    /// Refine joints and α by Levenberg–Marquardt. Default true.
    pub refine: bool,
    /// Iteration budget of each refinement. Default 30.
    pub refine_iterations: usize,
    /// Continuity at the smooth joints. Default [`Continuity::G2`]. With G2 or C3 the G1
    /// chain is refitted with one curvature per joint (see [`super::smooth`]); where that
    /// cannot hold the tolerance the G1 chain is kept.
    pub continuity: Continuity,
}

impl Default for ChainOptions {
    fn default() -> Self {
        ChainOptions {
            alpha: AlphaChoice::default(),
            max_depth: 6,
            merge: true,
            refine: true,
            refine_iterations: 30,
            continuity: Continuity::G2,
        }
    }
}

/// What a joint between segments (or an end of the chain) is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JointKind {
    /// The start of the piece.
    Start,
    /// The end of the piece.
    End,
    /// A corner shared with the neighbouring piece.
    Corner,
    /// An inflection of the B-spline.
    Inflection,
    /// A curvature extremum of the B-spline.
    CurvatureExtremum,
    /// A joint added to meet the tolerance.
    Subdivision,
}

impl JointKind {
    /// Whether the tangent on either side of the joint is its segment's own (G0): a start, an
    /// end or a corner.
    pub fn tangent_free(self) -> bool {
        matches!(self, JointKind::Start | JointKind::End | JointKind::Corner)
    }
}

impl From<SplitKind> for JointKind {
    fn from(k: SplitKind) -> Self {
        match k {
            SplitKind::Start => JointKind::Start,
            SplitKind::End => JointKind::End,
            SplitKind::Corner => JointKind::Corner,
            SplitKind::Inflection => JointKind::Inflection,
            SplitKind::CurvatureExtremum => JointKind::CurvatureExtremum,
        }
    }
}

/// One segment of the chain.
#[derive(Clone, Debug)]
pub struct ChainSegment {
    /// The log-aesthetic segment.
    pub segment: LacSegment,
    /// Inclusive range of the stroke's sample indices it represents.
    pub samples: (usize, usize),
    /// Largest distance from those samples to the segment.
    pub max_deviation: f64,
    /// Root mean square of those distances.
    pub rms_deviation: f64,
    /// The α search that started it (the final α may differ after refinement).
    pub search: AlphaSearch,
    /// What chose its α (`None`: no α, an arc or a line).
    pub alpha_source: Option<AlphaSource>,
    /// What its start joint is.
    pub start: JointKind,
    /// What its end joint is.
    pub end: JointKind,
    /// The B-spline parameter interval its samples' foot points span (`None` without samples):
    /// where to compare it with the B-spline.
    pub params: Option<(f64, f64)>,
    /// The end of the allowed α range its α sits on (`None`: an interior α, no α, or a fixed
    /// one): a search stopped there found a wall, not a minimum.
    pub alpha_bound: Option<AlphaBound>,
    /// The standard error of its α given its joints' positions and tangents
    /// ([`super::alpha_evidence`]); `None` where α is absent or fixed, or the probes could not
    /// be built; +∞ where the samples do not move with α at all.
    pub alpha_uncertainty: Option<f64>,
}

impl ChainSegment {
    /// Whether the samples determine its α: an α with an uncertainty of at most
    /// [`UNDETERMINED_ALPHA`], not on the range's end. False for an arc or a line (no α), a
    /// fixed α (the user's), an α without an estimate and one on the bound (the search found a
    /// wall, not a minimum).
    pub fn alpha_determined(&self) -> bool {
        self.alpha_bound.is_none()
            && self
                .alpha_uncertainty
                .is_some_and(|u| u <= UNDETERMINED_ALPHA)
    }
}

/// The chain of one piece.
#[derive(Clone, Debug)]
pub struct Chain {
    /// The segments, in order.
    pub segments: Vec<ChainSegment>,
    /// Largest sample distance over all segments.
    pub max_deviation: f64,
    /// Whether every sample is within the tolerance.
    pub within_tolerance: bool,
    /// Whether Levenberg–Marquardt refinement ran.
    pub refined: bool,
    /// The continuity its smooth joints hold.
    pub continuity: Continuity,
}

/// Why a chain could not be built.
#[derive(Debug, thiserror::Error)]
pub enum ChainError {
    /// The input is inconsistent (lengths differ, no spans).
    #[error("inconsistent chain input: {0}")]
    Input(&'static str),
    /// No segment, not even a biarc, could join a span's G1 data.
    #[error("span u = {u0}..{u1}: {source}")]
    Span {
        /// Start parameter.
        u0: f64,
        /// End parameter.
        u1: f64,
        /// The cause.
        source: LacError,
    },
}

/// What [`fit_chain`] works from.
#[derive(Clone, Copy, Debug)]
pub struct ChainInput<'a> {
    /// Distinct sample positions, in stroke order.
    pub points: &'a [Point],
    /// Each point's B-spline parameter (its foot point).
    pub params: &'a [f64],
    /// Each point's original sample index.
    pub indices: &'a [usize],
    /// The inclusive original sample range of the piece.
    pub samples: (usize, usize),
    /// The B-spline.
    pub curve: &'a BSpline,
    /// Its spans.
    pub spans: &'a Spans,
}

/// Fits the chain (see the module doc).
pub fn fit_chain(
    input: &ChainInput,
    tolerance: f64,
    options: &ChainOptions,
) -> Result<Chain, ChainError> {
    if input.points.len() != input.params.len() || input.points.len() != input.indices.len() {
        return Err(ChainError::Input(
            "points, params and indices differ in length",
        ));
    }
    if input.spans.spans.is_empty() {
        return Err(ChainError::Input("no spans"));
    }
    options
        .alpha
        .validate()
        .map_err(|source| ChainError::Span {
            u0: 0.0,
            u1: 0.0,
            source,
        })?;
    let fitter = Fitter::new(input, tolerance, options);
    let (mut state, mut searches) = fitter.initial()?;
    fitter.repair(&mut state, &mut searches)?;
    // Merge before refining as well as after: most of the B-spline's spans are noise (over the
    // fixture strokes up to 600 samples, 60 % hold at most one sample), and the refinement then
    // works on the chain the data need (1 066 segments in the end instead of 1 140, the rms
    // distance unchanged).
    if options.merge {
        fitter.straighten(&mut state, &mut searches);
        fitter.merge(&mut state, &mut searches);
        fitter.repair(&mut state, &mut searches)?;
    }
    let refine_options = fitter.refine_options(&state);
    // The segments the last refinement ended with (see `Fitter::refine_guarded`).
    let mut settled = None;
    if options.refine {
        fitter.refine_guarded(&mut state, &refine_options, &mut settled);
    }
    for _ in 0..options.max_depth {
        if !fitter.subdivide(&mut state, &mut searches) {
            break;
        }
        fitter.repair(&mut state, &mut searches)?;
        if options.refine {
            fitter.refine_guarded(&mut state, &refine_options, &mut settled);
        }
    }
    if options.merge {
        let straightened = fitter.straighten(&mut state, &mut searches);
        let merged = fitter.merge(&mut state, &mut searches);
        let fewer = fitter.merge_fewest(&mut state, &mut searches);
        if (straightened || merged || fewer) && options.refine {
            fitter.refine_guarded(&mut state, &refine_options, &mut settled);
        }
        if options.refine {
            fitter.merge_runs_refined(&mut state, &mut searches, &refine_options);
        }
        // A chain of one segment has no joint to make smooth: the G1 chain is the answer in
        // every continuity, refined to convergence (see `STARTING_CONVERGED_RMS`).
        if options.refine && options.continuity != Continuity::G1 && state.len() == 1 {
            let answer = RefineOptions {
                converged_rms: CONVERGED_RMS,
                ..refine_options
            };
            fitter.refine_guarded(&mut state, &answer, &mut None);
        }
        fitter.soften_ends(&mut state, &mut searches);
    }
    // Straightening and merging check the segments they change, but a refinement guarded on the
    // distances alone, or a tangent turned at a run's end, can leave a neighbour that no α joins
    // (seen with the seed's unfaired B-spline): make every segment constructible again.
    fitter.repair(&mut state, &mut searches)?;
    // A repair that dropped a segment the data cannot resolve hands its samples to a neighbour,
    // which may then miss the tolerance: cut again where needed (no refinement, which could undo
    // the repair).
    for _ in 0..options.max_depth {
        if !fitter.subdivide(&mut state, &mut searches) {
            break;
        }
        fitter.repair(&mut state, &mut searches)?;
    }
    let chain = fitter.finish(&state, searches)?;
    // Where every cut left a segment beyond the tolerance, its samples zigzag at the
    // tolerance's scale: they are joined by lines (see `super::polyline`).
    let last_resort = |chain: Chain| {
        super::polyline::join_missing(input, &chain, tolerance, fitter.chord_error).unwrap_or(chain)
    };
    if options.continuity == Continuity::G1 {
        return Ok(last_resort(chain));
    }
    // The G1 chain that starts a smooth fit is refined less (`STARTING_CONVERGED_RMS`); where it
    // ends beyond the tolerance, the G1 chain refined to convergence may not (a jiggle of the
    // synthetic fixtures: 1.30 against 0.41 of a 0.71 tolerance, eight segments against five),
    // and a smooth fit from a chain beyond the tolerance starts where the guarantee is already
    // lost. The better of the two starts it.
    let chain = if chain.within_tolerance {
        chain
    } else {
        let strict = fit_chain(
            input,
            tolerance,
            &ChainOptions {
                continuity: Continuity::G1,
                ..*options
            },
        );
        match strict {
            Ok(strict) if strict.max_deviation < chain.max_deviation => strict,
            _ => chain,
        }
    };
    let smooth = smooth_chain(&SmoothInput {
        input,
        chain: &chain,
        tolerance,
        chord_error: fitter.chord_error,
        alpha: options.alpha,
        continuity: options.continuity,
    });
    // A smooth chain farther from its samples than the G1 chain it started from is not taken
    // (the guarantee before the continuity), nor one that runs a loop between its samples where
    // the G1 chain does not (see `super::stray`).
    Ok(last_resort(match smooth {
        Some(smooth)
            if (smooth.within_tolerance
                || !chain.within_tolerance && smooth.max_deviation <= chain.max_deviation)
                && (!super::stray::loops(input, &smooth, tolerance)
                    || super::stray::loops(input, &chain, tolerance)) =>
        {
            smooth
        }
        _ => chain,
    }))
}

/// How far from a changed segment a later refinement still moves the chain (in segments): 1,
/// the neighbours, which share a joint with it. Over the fixture strokes up to 600 samples,
/// against refining the whole chain every time: 16 % fewer instructions on the median stroke
/// (15.5 M against 18.3 M), 5 % fewer in all, 736 segments against 731 and the rms distance
/// 0.237 of the tolerance against 0.235. 0 saves 10 % in all but lifts the rms distance to 0.244;
/// 2 gives back most of the saving for no better fit.
const NEIGHBOUR_RING: usize = 1;

/// The segments a refinement may move after `settled` (the segments the last refinement ended
/// with): those not among them (cut by a subdivision, made by a merge, or next to a moved joint)
/// and those within [`NEIGHBOUR_RING`] of them. Elsewhere the chain is where the last refinement
/// left it, at a minimum of its own residuals: moving it again costs a Jacobian and an
/// evaluation per segment and iteration for changes far below the tolerance.
fn changed_and_neighbours(state: &State<'_>, settled: &FxHashSet<SegmentKey>) -> Vec<bool> {
    let changed: Vec<bool> = (0..state.len())
        .map(|k| !settled.contains(&state.key(k)))
        .collect();
    (0..changed.len())
        .map(|k| {
            (k.saturating_sub(NEIGHBOUR_RING)..=(k + NEIGHBOUR_RING).min(changed.len() - 1))
                .any(|m| changed[m])
        })
        .collect()
}

/// The (start, end) tangent angles to try, in order, for a segment from `a` to `b` (each a point
/// and its tangent angle) whose start (`at_start`) or end curls tighter than its samples resolve
/// (see [`Fitter::soften_ends`]): that end turned towards the chord in [`SOFTEN_STEPS`] steps,
/// then towards the tangent of the circular arc through both ends that keeps the other end's
/// (its mirror image in the chord); and, where both ends are free (`both`), both towards the
/// chord together, a line at the last step. Towards the chord first: a segment whose other
/// tangent lies off the chord cannot leave along it (a log-aesthetic segment has no inflection),
/// and on a near line only the arc's tangent gives a segment at all (a painting stroke's start
/// hook, κ = 44.7 /px at a tolerance of 1 px, turned 3 rad in its first 0.02 px).
pub(super) fn soften_tries(
    (a, a_angle): (Point, f64),
    (b, b_angle): (Point, f64),
    at_start: bool,
    both: bool,
) -> Vec<(f64, f64)> {
    let chord = b - a;
    let chord_angle = chord.y.atan2(chord.x);
    let towards = |angle: f64| crate::geom::wrap_angle(chord_angle - angle);
    let (from, other) = if at_start {
        (a_angle, b_angle)
    } else {
        (b_angle, a_angle)
    };
    let arc = chord_angle + towards(other);
    let fraction = |step: usize| step as f64 / SOFTEN_STEPS as f64;
    let mut tries: Vec<(f64, f64)> = [chord_angle, arc]
        .iter()
        .map(|&target| crate::geom::wrap_angle(target - from))
        .flat_map(|turn| {
            (1..=SOFTEN_STEPS).map(move |step| {
                let angle = from + turn * fraction(step);
                if at_start {
                    (angle, b_angle)
                } else {
                    (a_angle, angle)
                }
            })
        })
        .collect();
    if both {
        let (turn_a, turn_b) = (towards(a_angle), towards(b_angle));
        tries.extend((1..=SOFTEN_STEPS).map(|step| {
            let f = fraction(step);
            (a_angle + turn_a * f, b_angle + turn_b * f)
        }));
    }
    tries
}

/// The turns of [`soften_tries`] whose segment holds `points` (ordered from `a` to `b`) within
/// `tolerance` and bends no tighter than `options.max_curvature`, in the tries' order, each
/// with its fit: a lazy sequence, so a caller taking the first that suits it fits no further.
pub(super) fn soften_fits<'p>(
    (a, a_angle): (Point, f64),
    (b, b_angle): (Point, f64),
    at_start: bool,
    both: bool,
    points: &'p [Point],
    options: SpanFitOptions,
    tolerance: f64,
) -> impl Iterator<Item = ((f64, f64), SpanFit)> + 'p {
    let tangent = |angle: f64| Vec2::new(angle.cos(), angle.sin());
    soften_tries((a, a_angle), (b, b_angle), at_start, both)
        .into_iter()
        .filter_map(move |(start_angle, end_angle)| {
            let fit = fit_span(
                a,
                tangent(start_angle),
                b,
                tangent(end_angle),
                points,
                &options,
            )
            .ok()?;
            (fit.deviation.max <= tolerance && within(&fit.segment, options.max_curvature))
                .then_some(((start_angle, end_angle), fit))
        })
}

/// What [`Fitter::search`] found.
struct Searched {
    /// The α (the range's middle for an arc or a line).
    alpha: f64,
    /// The search's record.
    search: AlphaSearch,
    /// The largest distance to the chosen segment from the points searched on: the samples, or
    /// the B-spline's reference points where the samples were too few.
    max: f64,
    /// The chosen segment and its samples' distances, when the search ran on the samples (not
    /// on reference points): what [`State::remember`] takes, so that the state does not build
    /// and measure it again.
    fit: Option<(LacSegment, Deviation)>,
}

/// The state shared by the fitting steps.
struct Fitter<'a> {
    input: &'a ChainInput<'a>,
    pieces: Pieces,
    /// The samples' B-spline parameters, non-decreasing along the stroke (see [`Fitter::new`]).
    params: Vec<f64>,
    /// Point indices sorted by parameter.
    order: Vec<usize>,
    tolerance: f64,
    chord_error: f64,
    /// Largest curvature a segment may have (see [`MIN_RADIUS_FRACTION`]).
    max_curvature: f64,
    options: &'a ChainOptions,
}

impl<'a> Fitter<'a> {
    fn new(input: &'a ChainInput<'a>, tolerance: f64, options: &'a ChainOptions) -> Self {
        let pieces = Pieces::new(input.curve.to_beziers());
        // The samples' parameters, made non-decreasing along the stroke: a sample's foot point on
        // the whole curve can lie on another pass where the stroke comes near itself (the
        // B-spline fit reports the nearest point), and a segment would then hold samples from
        // both passes, its sample range overlapping its neighbours'. Such a sample is projected
        // again from the parameter of the sample before it, along its own pass.
        let mut params = Vec::with_capacity(input.params.len());
        let mut floor = f64::NEG_INFINITY;
        for (p, &u) in input.points.iter().zip(input.params) {
            let u = if u < floor {
                pieces.project_local(*p, floor).u.max(floor)
            } else {
                u
            };
            floor = u;
            params.push(u);
        }
        let mut order: Vec<usize> = (0..input.points.len()).collect();
        order.sort_by(|&i, &j| params[i].total_cmp(&params[j]).then(i.cmp(&j)));
        Fitter {
            input,
            pieces,
            params,
            order,
            tolerance,
            chord_error: CHORD_ERROR_FRACTION * tolerance,
            max_curvature: 1.0 / (MIN_RADIUS_FRACTION * tolerance),
            options,
        }
    }

    /// The α search's options: the chain's α choice, chord error and curvature limit; a coarse
    /// α tolerance when the refinement will move α anyway; no guess, never abandoned.
    fn span_options(&self) -> SpanFitOptions {
        SpanFitOptions {
            choice: self.options.alpha,
            chord_error: self.chord_error,
            max_curvature: self.max_curvature,
            guess: None,
            alpha_tolerance: if self.options.refine {
                SEED_ALPHA_TOLERANCE
            } else {
                ALPHA_TOLERANCE
            },
            abandon_above: f64::INFINITY,
            unreachable_above: f64::INFINITY,
        }
    }

    fn refine_options(&self, state: &State) -> RefineOptions {
        let scale: f64 = state
            .joints
            .windows(2)
            .map(|w| w[0].p.distance(w[1].p))
            .sum();
        RefineOptions {
            max_iterations: self.options.refine_iterations,
            alpha_range: match self.options.alpha {
                AlphaChoice::Range { min, max } => Some((min, max)),
                AlphaChoice::Fixed(_) => None,
            },
            chord_error: self.chord_error,
            scale: scale.max(self.tolerance),
            tolerance: self.tolerance,
            converged_rms: if self.options.continuity == Continuity::G1 {
                CONVERGED_RMS
            } else {
                STARTING_CONVERGED_RMS
            },
        }
    }

    /// Position and unit tangent of the B-spline at `u`.
    fn g1(&self, u: f64) -> (Point, Vec2) {
        let (p, d1, _) = self.pieces.eval_derivs(u);
        (p, d1.normalize())
    }

    /// Indices of the samples whose parameter lies in `[u0, u1)` (`[u0, u1]` at the end of the
    /// curve), in parameter order.
    fn samples_in(&self, u0: f64, u1: f64) -> Vec<usize> {
        let end = self.pieces.domain().1;
        self.order
            .iter()
            .copied()
            .filter(|&i| {
                let u = self.params[i];
                u >= u0 && (u < u1 || (u1 >= end && u <= u1))
            })
            .collect()
    }

    /// The α search between two joints for the given samples (B-spline points on `[u0, u1]`
    /// stand in when there are too few samples), walking from `guess` when there is one (see
    /// [`fit_span`]).
    fn search(
        &self,
        a: &Joint,
        b: &Joint,
        samples: &[usize],
        u: (f64, f64),
        guess: Option<f64>,
        (abandon_above, unreachable_above): (f64, f64),
    ) -> Result<Searched, LacError> {
        let on_samples = samples.len() >= MIN_SPAN_SAMPLES;
        let points: Vec<Point> = if on_samples {
            samples.iter().map(|&i| self.input.points[i]).collect()
        } else {
            self.reference_points(u)
        };
        let fit = fit_span(
            a.p,
            a.tangent(),
            b.p,
            b.tangent(),
            &points,
            &SpanFitOptions {
                guess,
                abandon_above,
                unreachable_above,
                ..self.span_options()
            },
        )?;
        // Arcs and lines have no α: any value reproduces them; keep the range's middle.
        let alpha = fit.segment.alpha().unwrap_or(self.options.alpha.middle());
        Ok(Searched {
            alpha,
            search: fit.search,
            max: fit.deviation.max,
            fit: on_samples.then_some((fit.segment, fit.deviation)),
        })
    }

    /// [`SPAN_REFERENCE_POINTS`] B-spline points spread over `[u.0, u.1]`: they stand in for the
    /// samples where a span has too few to decide its shape.
    fn reference_points(&self, u: (f64, f64)) -> Vec<Point> {
        (0..SPAN_REFERENCE_POINTS)
            .map(|i| {
                let f = (i as f64 + 0.5) / SPAN_REFERENCE_POINTS as f64;
                self.pieces.eval_derivs(u.0 + f * (u.1 - u.0)).0
            })
            .collect()
    }

    fn joint_at(&self, u: f64, kind: JointKind) -> Joint {
        let (p, t) = self.g1(u);
        Joint {
            p,
            angle: t.y.atan2(t.x),
            kind,
            fixed: kind == JointKind::Corner,
            u,
        }
    }

    /// One segment per run of spans ([`Fitter::runs`]), joints on the B-spline, α from the
    /// search (a run no LAC can join is left to [`Fitter::repair`]).
    fn initial(&self) -> Result<(State<'a>, Vec<AlphaSearch>), ChainError> {
        let all = &self.input.spans.spans;
        let runs = self.runs();
        let mut joints = vec![self.joint_at(all[0].u0, all[0].start.into())];
        let (mut alphas, mut samples, mut searches) = (Vec::new(), Vec::new(), Vec::new());
        let mut fits = Vec::new();
        for run in runs {
            let (first, last) = (&all[run.start], &all[run.end - 1]);
            let (u0, u1) = (first.u0, last.u1);
            let start = *joints.last().ok_or(ChainError::Input("no joints"))?;
            let end = self.joint_at(u1, last.end.into());
            let held = self.samples_in(u0, u1);
            let pieces: Vec<_> = all[run.clone()]
                .iter()
                .flat_map(|s| s.pieces.iter().copied())
                .collect();
            // A span no α can join keeps a placeholder: `repair`, which runs next, gives it the
            // α its samples choose or splits it into a biarc.
            // The slope of the span's logarithmic curvature graph starts the α search.
            let guess = lcg_slope(&lcg_of_bezier_span_rough(&pieces, LCG_GUESS_POINTS));
            let (alpha, search, fit) = self
                .search(&start, &end, &held, (u0, u1), guess, NEVER_ABANDON)
                .map(|found| (found.alpha, found.search, found.fit))
                .unwrap_or((self.options.alpha.middle(), AlphaSearch::default(), None));
            fits.push(fit);
            alphas.push(alpha);
            samples.push(held);
            searches.push(search);
            joints.push(end);
        }
        let state = State {
            points: self.input.points,
            joints,
            alphas,
            samples,
            max_curvature: self.max_curvature,
            memo: Default::default(),
        };
        for (k, fit) in fits.into_iter().enumerate() {
            if let Some((segment, deviation)) = fit {
                state.remember(k, segment, deviation, self.chord_error);
            }
        }
        Ok((state, searches))
    }

    /// The runs of consecutive spans that start as one segment each: a run closes once it holds
    /// [`MIN_SPAN_SAMPLES`] samples, or at a joint that cannot be merged (a corner or the
    /// piece's end); a short tail joins the run before it. Most of the B-spline's spans hold at
    /// most one sample (60 % over the fixture strokes up to 600 samples): their extrema and
    /// inflections are the noise's, which [`Fitter::merge`] would remove one α search at a time,
    /// and where one is real the run misses the tolerance and [`Fitter::subdivide`] cuts it
    /// again. Over those strokes this takes 12 % fewer instructions in all and ends with fewer
    /// segments (731 against 766) and a lower rms distance (0.235 of the tolerance against
    /// 0.244).
    fn runs(&self) -> Vec<std::ops::Range<usize>> {
        let spans = &self.input.spans.spans;
        let mergeable =
            |k: SplitKind| matches!(k, SplitKind::CurvatureExtremum | SplitKind::Inflection);
        let mut runs: Vec<std::ops::Range<usize>> = Vec::new();
        let mut start = 0;
        for (i, span) in spans.iter().enumerate() {
            let held = self.samples_in(spans[start].u0, span.u1).len();
            if held >= MIN_SPAN_SAMPLES || !mergeable(span.end) {
                runs.push(start..i + 1);
                start = i + 1;
            }
        }
        if start < spans.len() {
            match runs.last_mut() {
                Some(last) if mergeable(spans[start - 1].end) => last.end = spans.len(),
                _ => runs.push(start..spans.len()),
            }
        }
        runs
    }

    /// Cuts every segment that misses the tolerance where the B-spline passes its middle sample
    /// (the median of its samples' parameters): a new joint on the B-spline, with the
    /// B-spline's tangent, keeps the chain G1 and puts the joint on the data even where the
    /// segment is off it. Searches α for both halves. Returns whether any was cut.
    fn subdivide(&self, state: &mut State<'a>, searches: &mut Vec<AlphaSearch>) -> bool {
        let mut cut = false;
        let mut k = 0;
        while k < state.len() {
            let failing = match state.evaluate(k, self.chord_error) {
                Ok(e) => e.max > self.tolerance,
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
                    && mid.p.distance(j.p) < self.tolerance
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
            let apart = COINCIDENT_JOINT_FRACTION * self.tolerance;
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
                    state.remember(m, segment, deviation, self.chord_error);
                }
            }
            cut = true;
            k += 2;
        }
        cut
    }

    /// Refines, keeping the result only if its largest sample distance stays within the tolerance
    /// or at most where it was: least squares lowers the sum of squares, which can still lift one
    /// sample over the tolerance.
    ///
    /// `settled` holds the segments of the chain the last refinement ended with (`None` before
    /// the first): only the segments not among them, and their neighbours, move (see
    /// [`Fitter::changed_and_neighbours`]); it is updated to this refinement's chain.
    fn refine_guarded(
        &self,
        state: &mut State<'a>,
        options: &RefineOptions,
        settled: &mut Option<FxHashSet<SegmentKey>>,
    ) {
        let active = settled
            .as_ref()
            .map(|keys| changed_and_neighbours(state, keys));
        if active.as_ref().is_some_and(|a| !a.contains(&true)) {
            return;
        }
        let before = state.clone();
        // `refine` measures the chain (all samples) before and after: no evaluation is repeated.
        let off_curve = |p: Point, u: f64| self.pieces.project_local(p, u).distance;
        if let Some(r) = refine(state, options, active.as_deref(), &off_curve)
            && r.end_max > self.tolerance.max(r.start_max)
        {
            *state = before;
        }
        *settled = Some((0..state.len()).map(|k| state.key(k)).collect());
    }

    /// Makes every segment of the state constructible: a segment whose α cannot join its joints
    /// gets the α its samples choose, and where no α can, the biarc's joint is inserted (both
    /// arcs are reproduced by any α). Refinement and output rely on a valid state.
    fn repair(
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
            let coincident =
                a.u == b.u || a.p.distance(b.p) <= COINCIDENT_JOINT_FRACTION * self.tolerance;
            let arcs = biarc(a.p, a.tangent(), b.p, b.tangent());
            // Arcs tighter than the smallest radius turn inside a disc the samples cannot resolve
            // (seen: joints 0.01 px apart at a 0.5 px tolerance, their tangents an S): the two
            // joints are one, as far as the data can tell.
            let unresolved = arcs.as_ref().is_ok_and(|[s0, s1]| {
                !(within(s0, self.max_curvature) && within(s1, self.max_curvature))
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
                off > MAX_JOINT_OFF_CURVE * self.tolerance && off > a.p.distance(b.p)
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
                u: 0.5 * (a.u + b.u),
            };
            // The samples (in stroke order) are cut in two where the larger distance of a
            // first part to the first arc and of the rest to the second is least: each arc holds
            // a run of consecutive samples, so the segments' sample ranges tile the piece.
            let d0 = deviation(&s0, &reference, self.chord_error).distances;
            let d1 = deviation(&s1, &reference, self.chord_error).distances;
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
    fn research(&self, state: &mut State<'a>, searches: &mut [AlphaSearch], k: usize) {
        let (a, b) = (state.joints[k], state.joints[k + 1]);
        let guess = Some(state.alphas[k]);
        if let Ok(found) = self.search(&a, &b, &state.samples[k], (a.u, b.u), guess, NEVER_ABANDON)
        {
            state.alphas[k] = found.alpha;
            searches[k] = found.search;
            if let Some((segment, deviation)) = found.fit {
                state.remember(k, segment, deviation, self.chord_error);
            }
        }
    }

    /// Cuts segment `k` at the B-spline's point halfway (in the parameter) between its joints,
    /// its samples split by their parameters, each half given its α search. Returns false (and
    /// changes nothing) where that point is not apart from both joints.
    fn split_on_curve(
        &self,
        state: &mut State<'a>,
        searches: &mut Vec<AlphaSearch>,
        k: usize,
    ) -> bool {
        let (a, b) = (state.joints[k], state.joints[k + 1]);
        let um = 0.5 * (a.u + b.u);
        let mid = self.joint_at(um, JointKind::Subdivision);
        let apart = COINCIDENT_JOINT_FRACTION * self.tolerance;
        if !(a.u < um && um < b.u) || mid.p.distance(a.p) <= apart || mid.p.distance(b.p) <= apart {
            return false;
        }
        // Halves within the tolerance of their joints' chord are no curve to cut further: the
        // repair then fails on this span and the pipeline cuts the piece at its sharpest vertex.
        // Without this floor, a fold on a fine grid (0.005 px steps at 0.1 px) was cut again and
        // again, both halves each time, for minutes (the fuzzer's hang).
        let floor = MIN_SPLIT_CHORD_FRACTION * self.tolerance;
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

    /// Replaces runs of segments by one straight segment where a line between the run's outer
    /// joints holds all its samples within the tolerance: noise on a near-straight stretch flips
    /// the curvature's sign again and again, and no log-aesthetic segment can cross an
    /// inflection, but a line absorbs them all. From each joint the run is extended as far as the
    /// chord holds the samples (a cheap point-to-segment test); the run's outer joints then turn
    /// their tangents to the chord, so the chain stays G1, and the segments beyond them, rebuilt
    /// with the turned tangents, must stay within the tolerance too. Returns whether any run was
    /// straightened.
    fn straighten(&self, state: &mut State<'a>, searches: &mut Vec<AlphaSearch>) -> bool {
        let near_chord = |a: Point, b: Point, samples: &[usize]| {
            samples.iter().all(|&i| {
                let q = self.input.points[i];
                let ab = b - a;
                let f = ((q - a).dot(ab) / ab.hypot2()).clamp(0.0, 1.0);
                q.distance(a + ab * f) <= self.tolerance
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
                |m| matches!(trial.evaluate(m, self.chord_error), Ok(e) if e.max <= self.tolerance),
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
    fn merge(&self, state: &mut State<'a>, searches: &mut Vec<AlphaSearch>) -> bool {
        let mut merged = false;
        let mut j = 1;
        while j + 1 < state.joints.len() {
            if removable(state.joints[j].kind) {
                let (union, found) = self.search_merged(state, j - 1..j + 1);
                // Too few samples to decide the merged shape: the search ran on the B-spline's
                // points instead, and the merged segment must stay within the tolerance of them.
                let sparse = union.len() < MIN_SPAN_SAMPLES;
                if let Ok(found) = found
                    && (!sparse || found.max <= self.tolerance)
                {
                    let search = found.search;
                    let mut trial = state.clone();
                    self.replace_run(&mut trial, j - 1..j + 1, union, found.alpha, found.fit);
                    if matches!(trial.evaluate(j - 1, self.chord_error), Ok(e) if e.max <= self.tolerance)
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
    fn search_merged(
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
                MERGE_ABANDON_FACTOR * self.tolerance,
                MERGE_UNREACHABLE_FACTOR * self.tolerance,
            ),
        );
        (union, found)
    }

    /// Replaces segments `run` of `state` by one segment between the run's outer joints, holding
    /// `union` (their samples) with α `alpha`; `fit` is that segment and its samples' distances
    /// when the α search ran on the samples (remembered, not built and measured again).
    fn replace_run(
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
            state.remember(run.start, segment, deviation, self.chord_error);
        }
    }

    /// Whether every segment of `state` holds its samples within the tolerance.
    fn holds(&self, state: &State) -> bool {
        (0..state.len()).all(
            |k| matches!(state.evaluate(k, self.chord_error), Ok(e) if e.max <= self.tolerance),
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
    fn merge_fewest(&self, state: &mut State<'a>, searches: &mut Vec<AlphaSearch>) -> bool {
        let m = state.len();
        if m < 2 {
            return false;
        }
        let squares = |d: &[f64]| d.iter().map(|r| r * r).sum::<f64>();
        let own: Vec<f64> = (0..m)
            .map(|k| {
                state
                    .evaluate(k, self.chord_error)
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
                if deviation.max > self.tolerance || !within(&segment, self.max_curvature) {
                    if found.max > MERGE_ABANDON_FACTOR * self.tolerance {
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
    fn merge_runs_refined(
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
            if found.max > REFINED_MERGE_FACTOR * self.tolerance {
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
    /// [`super::smooth::MIN_RADIUS_TOLERANCES`]), so that the segment need not: the tangent there is the piece's own (a corner is G0), and the B-spline's end
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
    fn soften_ends(&self, state: &mut State<'a>, searches: &mut [AlphaSearch]) -> bool {
        let n = state.len();
        if n == 0 {
            return false;
        }
        let cap = 1.0 / (super::smooth::MIN_RADIUS_TOLERANCES * self.tolerance);
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
                abandon_above: self.tolerance,
                unreachable_above: self.tolerance,
                ..self.span_options()
            };
            let fits = soften_fits(
                (a.p, a.angle),
                (b.p, b.angle),
                at_start,
                n == 1,
                &points,
                options,
                self.tolerance,
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
                state.remember(k, fit.segment, fit.deviation, self.chord_error);
                if matches!(state.evaluate(k, self.chord_error), Ok(e) if e.max <= self.tolerance) {
                    searches[k] = fit.search;
                    changed = true;
                    break;
                }
                (state.joints[k], state.joints[k + 1], state.alphas[k]) = kept;
            }
        }
        changed
    }

    /// The output segments with their sample ranges and deviations.
    ///
    /// Sample ranges tile the piece in order: every segment holds a run of consecutive samples
    /// (its samples' parameters are non-decreasing along the stroke, see [`Fitter::new`]), and
    /// its range runs from the first of them (the piece's first sample for the first segment)
    /// to the sample before the next segment's first (the piece's last for the last segment),
    /// so merged duplicates belong to the segment of the sample they were merged into. A
    /// segment that holds no sample (it bridges the gap between two consecutive samples; its
    /// `params` is `None`) has the one-sample range of the sample before it, shared with the
    /// segment before it (with the next one's first if it is the first segment).
    ///
    /// A segment's `max_deviation` is over the samples it holds; the chain's is each sample's
    /// distance to the whole chain (the nearest segment, not only its own), so that
    /// `within_tolerance` and `max_deviation` state the guarantee itself.
    fn finish(&self, state: &State, mut searches: Vec<AlphaSearch>) -> Result<Chain, ChainError> {
        let n = state.len();
        // A spiral whose α no search chose (a placeholder where a search found nothing, or a
        // line or arc the refinement bent since) is searched now between its final joints; the
        // searched α is kept where it fits the samples no worse than the one it replaces, or
        // within the tolerance.
        let mut state = state.clone();
        for k in 0..n {
            let placeholder = searches[k].evaluations == 0
                && state.segment(k).is_ok_and(|seg| seg.alpha().is_some());
            if !placeholder {
                continue;
            }
            let before = state.evaluate(k, self.chord_error).map(|e| e.max);
            let mut trial = state.clone();
            let mut trial_searches = searches.clone();
            self.research(&mut trial, &mut trial_searches, k);
            let after = trial.evaluate(k, self.chord_error).map(|e| e.max);
            if let (Ok(after), before) = (after, before)
                && trial_searches[k].evaluations > 0
                && before.map_or(true, |b| after <= b.max(self.tolerance))
            {
                state = trial;
                searches = trial_searches;
            }
        }
        let state = &state;
        let mut segments = Vec::with_capacity(n);
        let evaluated = (0..n)
            .map(|k| state.evaluate(k, self.chord_error))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|source| ChainError::Span {
                u0: 0.0,
                u1: 0.0,
                source,
            })?;
        // Each segment's first original sample index (None when it holds none).
        let starts: Vec<Option<usize>> = (0..n)
            .map(|k| {
                state.samples[k]
                    .iter()
                    .map(|&i| self.input.indices[i])
                    .min()
            })
            .collect();
        let ranges = tile_ranges(&starts, self.input.samples);
        for (k, (search, evaluated)) in searches.into_iter().zip(&evaluated).enumerate() {
            let distances = &evaluated.residuals[..state.samples[k].len()];
            let rms = if distances.is_empty() {
                0.0
            } else {
                (distances.iter().map(|r| r * r).sum::<f64>() / distances.len() as f64).sqrt()
            };
            let params = param_interval(&self.params, &state.samples[k]);
            let range = ranges[k];
            let alpha = evaluated.segment.alpha();
            segments.push(ChainSegment {
                segment: evaluated.segment,
                samples: range,
                max_deviation: evaluated.max,
                rms_deviation: rms,
                alpha_source: AlphaSource::of_g1(alpha, &search, self.options.alpha),
                search,
                start: state.joints[k].kind,
                end: state.joints[k + 1].kind,
                params,
                alpha_bound: AlphaBound::of(alpha, self.options.alpha),
                alpha_uncertainty: self.alpha_uncertainty(state, k, evaluated),
            });
        }
        let max_deviation = self.chain_deviation(state, &evaluated);
        Ok(Chain {
            segments,
            max_deviation,
            within_tolerance: max_deviation <= self.tolerance,
            refined: self.options.refine,
            continuity: Continuity::G1,
        })
    }

    /// The standard error of segment `k`'s α given its joints: its samples' distances at α ± h,
    /// the segment rebuilt through the same joints ([`alpha_uncertainty`]). `None` for no α or
    /// a fixed one.
    fn alpha_uncertainty(
        &self,
        state: &State,
        k: usize,
        evaluated: &super::state::Evaluated,
    ) -> Option<f64> {
        let alpha = evaluated.segment.alpha()?;
        if matches!(self.options.alpha, AlphaChoice::Fixed(_)) {
            return None;
        }
        let (a, b) = (state.joints[k], state.joints[k + 1]);
        let n = state.samples[k].len();
        let probe = |x: f64| {
            state
                .sample_residuals_with(k, &a, &b, x, evaluated)
                .ok()
                .filter(|r| r.len() >= n)
        };
        let (minus, plus) = (
            probe(alpha - ALPHA_DIFFERENCE_STEP),
            probe(alpha + ALPHA_DIFFERENCE_STEP),
        );
        alpha_uncertainty(
            &evaluated.residuals[..n],
            minus.as_deref().map(|r| &r[..n]),
            plus.as_deref().map(|r| &r[..n]),
        )
    }

    /// The largest distance from a sample to the chain (see [`nearest_deviation`]).
    fn chain_deviation(&self, state: &State, evaluated: &[super::state::Evaluated]) -> f64 {
        let segments: Vec<LacSegment> = evaluated.iter().map(|e| e.segment).collect();
        let own: Vec<Vec<f64>> = evaluated
            .iter()
            .zip(&state.samples)
            .map(|(e, list)| e.residuals[..list.len()].iter().map(|r| r.abs()).collect())
            .collect();
        nearest_deviation(
            self.input.points,
            &segments,
            &state.samples,
            &own,
            self.chord_error,
        )
    }
}

/// Each segment's own points (indices into `input.points`): those whose original index lies in
/// its sample range, a point on a range boundary given to the first segment that holds it (a
/// segment without samples repeats its neighbour's index); none for a segment without samples.
pub(super) fn own_points(input: &ChainInput, segments: &[ChainSegment]) -> Vec<Vec<usize>> {
    let mut taken = vec![false; input.points.len()];
    segments
        .iter()
        .map(|s| {
            if s.params.is_none() {
                return Vec::new();
            }
            (0..input.points.len())
                .filter(|&i| (s.samples.0..=s.samples.1).contains(&input.indices[i]))
                .filter(|&i| !std::mem::replace(&mut taken[i], true))
                .collect()
        })
        .collect()
}

/// The largest distance from a point to the chain `segments` (its nearest segment), each
/// segment's own points `lists` ([`own_points`]) measured afresh: for a chain assembled from
/// parts or edited after its fit, whose recorded figures no longer hold.
pub(super) fn measured_deviation(
    input: &ChainInput,
    segments: &[ChainSegment],
    lists: &[Vec<usize>],
    chord_error: f64,
) -> f64 {
    let own: Vec<Vec<f64>> = segments
        .iter()
        .zip(lists)
        .map(|(s, list)| {
            let points: Vec<Point> = list.iter().map(|&i| input.points[i]).collect();
            deviation(&s.segment, &points, chord_error).distances
        })
        .collect();
    let curves: Vec<LacSegment> = segments.iter().map(|s| s.segment).collect();
    nearest_deviation(input.points, &curves, lists, &own, chord_error)
}

/// The original sample range of the points `list` (non-empty, in stroke order).
pub(super) fn sample_range(indices: &[usize], list: &[usize]) -> (usize, usize) {
    let first = list.first().map_or(0, |&i| indices[i]);
    let last = list.last().map_or(first, |&i| indices[i]);
    (first, last)
}

/// The B-spline parameter interval spanned by the points `list` (indices into `params`, each
/// point's B-spline parameter); `None` when `list` is empty.
pub(super) fn param_interval(params: &[f64], list: &[usize]) -> Option<(f64, f64)> {
    list.iter()
        .map(|&i| params[i])
        .fold(None, |acc: Option<(f64, f64)>, u| {
            Some(acc.map_or((u, u), |(lo, hi)| (lo.min(u), hi.max(u))))
        })
}

/// `segments`' sample ranges tiled afresh over `piece` ([`tile_ranges`] from each one's first
/// sample, a segment without samples, `params: None`, holding none): after segments were
/// replaced or inserted.
pub(super) fn retile(segments: &mut [ChainSegment], piece: (usize, usize)) {
    let starts: Vec<Option<usize>> = segments
        .iter()
        .map(|s| s.params.map(|_| s.samples.0))
        .collect();
    for (s, range) in segments.iter_mut().zip(tile_ranges(&starts, piece)) {
        s.samples = range;
    }
}

/// Each segment's inclusive range of original sample indices from its first one (`None`: it
/// holds none): the ranges tile the piece `piece`, a segment ending where the next begins; a
/// segment without samples gets the single index where it sits.
pub(crate) fn tile_ranges(starts: &[Option<usize>], piece: (usize, usize)) -> Vec<(usize, usize)> {
    let (piece_first, piece_last) = piece;
    let mut previous_last: Option<usize> = None;
    let mut ranges = Vec::with_capacity(starts.len());
    for k in 0..starts.len() {
        let range = if starts[k].is_some() {
            let first = previous_last.map_or(piece_first, |l| l + 1);
            let last = starts[k + 1..]
                .iter()
                .find_map(|s| *s)
                .map_or(piece_last, |next| next.saturating_sub(1))
                .max(first);
            previous_last = Some(last);
            (first, last)
        } else {
            let at = previous_last.unwrap_or(piece_first);
            (at, at)
        };
        ranges.push(range);
    }
    ranges
}

/// The distance from `q` to `segment` found from its trace (a polyline through its points within
/// the chord error of it, [`crate::lac::deviation::trace`], computed once per segment by the
/// caller): the global distance to the segment, where a foot-point search may settle on a local
/// minimum.
fn traced_distance(segment: &LacSegment, trace: &[(f64, Point)], q: Point) -> f64 {
    let mut best = (f64::INFINITY, 0.0);
    let mut previous: Option<(Point, f64)> = None;
    for &(sb, b) in trace {
        let (a, sa) = previous.unwrap_or((b, sb));
        let (d, f) = crate::lac::deviation::segment_distance(q, a, b);
        if d < best.0 {
            best = (d, sa + f * (sb - sa));
        }
        previous = Some((b, sb));
    }
    // The trace lies within the chord error of the curve, so its distance can fall short of the
    // curve's by that much: the foot is found on the curve from the trace's nearest point (the
    // curve's point there where that search does not settle), a distance to a point of the
    // curve, never below the true one.
    let at = best.1;
    crate::lac::deviation::deviation_near(segment, &[q], &[at])
        .map_or_else(|| q.distance(segment.point(at)), |d| d.max)
}

/// The largest distance from a sample to the chain (its nearest segment), given each
/// segment's samples (`samples[k]`, indices into `points`) and their distances to it (`own`).
/// A sample's distance to its own segment bounds its distance to the chain from above, so the
/// samples are taken farthest from their own segment first, each measured against the others
/// too, until the next one's own distance cannot beat the largest found: usually after one or
/// two.
pub(crate) fn nearest_deviation(
    points: &[Point],
    segments: &[LacSegment],
    samples: &[Vec<usize>],
    own: &[Vec<f64>],
    chord_error: f64,
) -> f64 {
    let mut order: Vec<(f64, usize)> = Vec::new();
    for (list, distances) in samples.iter().zip(own) {
        for (&i, &d) in list.iter().zip(distances) {
            order.push((d, i));
        }
    }
    order.sort_by(|x, y| y.0.total_cmp(&x.0));
    let mut worst: f64 = 0.0;
    // Each segment's trace, made the first time a sample asks for it.
    let mut traces: Vec<Option<Vec<(f64, Point)>>> = vec![None; segments.len()];
    for &(d, i) in &order {
        if d <= worst {
            break;
        }
        // Its own segment too: a residual is the distance to a local foot point (Newton from a
        // seed along the segment), which on a tightly curling segment need not be the nearest
        // one (seen: 2.16 px from a sample lying on the segment's end).
        let q = points[i];
        let mut nearest = d;
        for (segment, trace) in segments.iter().zip(&mut traces) {
            // Every point of a segment lies within half its length of its middle.
            let length = segment.length();
            if q.distance(segment.point(0.5 * length)) - 0.5 * length >= nearest {
                continue;
            }
            let local = deviation(segment, &[q], chord_error).max;
            let trace =
                trace.get_or_insert_with(|| crate::lac::deviation::trace(segment, chord_error));
            nearest = nearest.min(local).min(traced_distance(segment, trace, q));
        }
        worst = worst.max(nearest);
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The largest distance from a sample to the chain is at most the largest distance from a
    /// sample to its own segment (which the smooth fit relies on to tell a chain holds the
    /// tolerance without measuring it against the other segments), and is the true one: a
    /// sample that its own segment passes far from but another passes near counts at the
    /// nearer distance.
    #[test]
    fn the_chain_distance_is_the_nearest_segment_and_bounded_by_the_own() {
        let chord_error = 1e-4;
        // A log-aesthetic segment and a line back along beside it (a hairpin).
        let curve = LacSegment::new(Point::new(0.0, 0.0), 0.0, 40.0, Some(0.5), 0.02, 0.05)
            .expect("a valid segment");
        let back = curve.end();
        let line = LacSegment::new(back, std::f64::consts::PI, 30.0, None, 0.0, 0.0)
            .expect("a valid line");
        let segments = [curve, line];
        let points: Vec<Point> = (0..12)
            .map(|i| {
                let s = 3.0 * i as f64 + 1.0;
                curve.point(s) + Vec2::new(0.1 * (i as f64).sin(), 0.2 * (i as f64 * 0.7).cos())
            })
            .chain((0..8).map(|i| line.point(3.0 * i as f64 + 2.0) + Vec2::new(0.0, 0.3)))
            .collect();
        // The last curve sample handed to the line, which passes far from it.
        let samples = vec![(0..11).collect::<Vec<usize>>(), (11..20).collect()];
        let own: Vec<Vec<f64>> = samples
            .iter()
            .zip(&segments)
            .map(|(list, seg)| {
                list.iter()
                    .map(|&i| deviation(seg, &[points[i]], chord_error).max)
                    .collect()
            })
            .collect();
        let largest_own = own.iter().flatten().fold(0.0_f64, |m, &d| m.max(d));
        let nearest = nearest_deviation(&points, &segments, &samples, &own, chord_error);
        let brute = points
            .iter()
            .map(|&q| {
                segments
                    .iter()
                    .map(|seg| deviation(seg, &[q], chord_error).max)
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0_f64, f64::max);
        assert!(nearest <= largest_own, "{nearest} > {largest_own}");
        assert!(
            largest_own > 2.0 * brute,
            "the handed sample is far from its own segment"
        );
        assert!((nearest - brute).abs() <= 1e-9, "{nearest} against {brute}");
    }
}
