//! The G1 chain: the seed paper's assembly of log-aesthetic segments over the B-spline's spans,
//! position and tangent shared at every joint.
//!
//! One segment per run of spans holding at least three samples (most spans hold one sample or
//! none: their extrema are the noise's), each the Yoshida–Saito segment through its ends'
//! positions and tangents with the α that fits its samples best; a Levenberg–Marquardt
//! refinement ([`refine`]) then moves joints and α together, and after every later change only
//! where the chain changed. A segment whose samples are not all within the tolerance is cut
//! between its two middle samples (the new joint on the B-spline) and refitted
//! ([`repair`]); runs a line holds become one line and neighbours one segment covers are merged
//! ([`merge`]); [`finish`] writes the record.

use crate::bspline::project::Pieces;
use crate::chain::measure::Resolution;
use crate::chain::record::{Chain, ChainError, ChainInput, ChainOptions, Continuity, JointKind};
use crate::geom::{Point, Vec2};
use crate::lac::lcg::{lcg_of_bezier_span_rough, lcg_slope};
use crate::lac::{
    AlphaChoice, AlphaSearch, Deviation, LacError, LacSegment, SpanFitOptions,
    alpha_search::{ALPHA_TOLERANCE, SEED_ALPHA_TOLERANCE},
    fit_span,
};
use crate::split::SplitKind;
use refine::{CONVERGED_RMS, RefineOptions, STARTING_CONVERGED_RMS, refine};
use rustc_hash::FxHashSet;
use state::{Joint, SegmentKey, State};

mod edges;
mod finish;
mod jacobian;
mod merge;
pub(crate) mod refine;
mod repair;
pub(crate) mod state;

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

/// Most a starting segment may turn (radians). A segment between two joints is fixed by their
/// positions and tangents, and the tangents' angles, each read against the chord between the
/// joints, say nothing of whole turns: what one segment can turn lies within a turn either way.
/// Runs that turn farther (a spiral, a circle drawn past its start: one span without curvature
/// extrema) are cut at equal turning into parts of at most three quarters of a turn, clear of
/// that limit. (A half turn cut runs the construction joins: a planted flat-point chain's third
/// segment turns 3.4 rad and came back as two.)
const MAX_RUN_TURNING: f64 = 1.5 * std::f64::consts::PI;

/// Tangent directions read per Bézier piece of the B-spline to find a run's turning: a piece of a
/// fitted B-spline turns far less than a quarter turn between two of them.
const TURNING_POINTS_PER_PIECE: usize = 8;

/// The G1 chain of `input` within `tolerance` (see the module documentation), with the
/// resolution it was measured at.
pub(crate) fn fit_g1(
    input: &ChainInput,
    tolerance: f64,
    options: &ChainOptions,
) -> Result<(Chain, Resolution), ChainError> {
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
    Ok((fitter.finish(&state, searches)?, fitter.resolution))
}

/// How far from a changed segment a later refinement still moves the chain (in segments): 1,
/// the neighbours, which share a joint with it. Against refining the whole chain every time it
/// trades a little fit quality for less work; measured in
/// `docs/performance-history.md` (chain constants).
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
    /// The tolerance and the scales that follow from it.
    resolution: Resolution,
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
            resolution: Resolution::new(tolerance),
            options,
        }
    }

    /// The α search's options: the chain's α choice, chord error and curvature limit; a coarse
    /// α tolerance when the refinement will move α anyway; no guess, never abandoned.
    fn span_options(&self) -> SpanFitOptions {
        SpanFitOptions {
            choice: self.options.alpha,
            chord_error: self.resolution.chord_error,
            max_curvature: self.resolution.max_curvature,
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
            chord_error: self.resolution.chord_error,
            scale: scale.max(self.resolution.tolerance),
            tolerance: self.resolution.tolerance,
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
        let angle = t.y.atan2(t.x);
        // A seam's joint is the seam's pose (its angle on the B-spline's turn there).
        let seam = self.input.seam.filter(|_| kind == JointKind::Seam);
        Joint {
            p: seam.map_or(p, |s| s.point),
            angle: seam.map_or(angle, |s| angle + crate::geom::wrap_angle(s.theta - angle)),
            kind,
            fixed: kind.fixed_point(),
            held_angle: seam.is_some(),
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
        // Each run, cut where it turns too far for one segment (see `MAX_RUN_TURNING`).
        let mut parts = Vec::new();
        for run in runs {
            let (first, last) = (&all[run.start], &all[run.end - 1]);
            let cuts = self.turning_cuts(first.u0, last.u1);
            let mut u = first.u0;
            for &c in &cuts {
                parts.push((run.clone(), (u, c), JointKind::Subdivision));
                u = c;
            }
            parts.push((run.clone(), (u, last.u1), last.end.into()));
        }
        for (run, (u0, u1), end_kind) in parts {
            let start = *joints.last().ok_or(ChainError::Input("no joints"))?;
            let end = self.joint_at(u1, end_kind);
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
            max_curvature: self.resolution.max_curvature,
            memo: Default::default(),
        };
        for (k, fit) in fits.into_iter().enumerate() {
            if let Some((segment, deviation)) = fit {
                state.remember(k, segment, deviation, self.resolution.chord_error);
            }
        }
        Ok((state, searches))
    }

    /// Where to cut the B-spline between `u0` and `u1` so that no part turns more than
    /// [`MAX_RUN_TURNING`]: at equal steps of its turning (none where it turns less). A spiral
    /// has no curvature extremum and a circle drawn past its start none that its samples
    /// show, so one span can turn more than a whole turn; a segment between two joints is fixed
    /// by their tangents, whose angles say nothing of whole turns between them, and the seed
    /// paper's construction turns less than a half turn.
    fn turning_cuts(&self, u0: f64, u1: f64) -> Vec<f64> {
        let first = self.pieces.locate(u0);
        let last = self.pieces.locate(u1);
        let n = TURNING_POINTS_PER_PIECE * (last - first + 1);
        let angle = |u: f64| {
            let (_, d1, _) = self.pieces.eval_derivs(u);
            d1.y.atan2(d1.x)
        };
        // The turning from u0 at each of n + 1 parameters.
        let us: Vec<f64> = (0..=n)
            .map(|i| u0 + (u1 - u0) * i as f64 / n as f64)
            .collect();
        let mut turned = vec![0.0; us.len()];
        let mut previous = angle(u0);
        for i in 1..us.len() {
            let a = angle(us[i]);
            turned[i] = turned[i - 1] + crate::geom::wrap_angle(a - previous);
            previous = a;
        }
        let total = turned.last().copied().unwrap_or(0.0).abs();
        let parts = (total / MAX_RUN_TURNING).ceil() as usize;
        if parts <= 1 {
            return Vec::new();
        }
        (1..parts)
            .filter_map(|k| {
                let target = total * k as f64 / parts as f64;
                let i = turned.iter().position(|t| t.abs() >= target)?;
                // Linear between the two parameters around the target.
                let (a, b) = (turned[i - 1].abs(), turned[i].abs());
                let f = if b > a { (target - a) / (b - a) } else { 0.0 };
                Some(us[i - 1] + f * (us[i] - us[i - 1]))
            })
            .collect()
    }

    /// The runs of consecutive spans that start as one segment each: a run closes once it holds
    /// [`MIN_SPAN_SAMPLES`] samples, or at a joint that cannot be merged (a corner or the
    /// piece's end); a short tail joins the run before it. Most of the B-spline's spans hold at
    /// most one sample (60 % over the fixture strokes up to 600 samples): their extrema and
    /// inflections are the noise's, which [`Fitter::merge`] would remove one α search at a time,
    /// and where one is real the run misses the tolerance and [`Fitter::subdivide`] cuts it
    /// again. This takes less work and ends with fewer segments and a lower rms distance;
    /// measured in `docs/performance-history.md` (chain constants).
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
            && r.end_max > self.resolution.tolerance.max(r.start_max)
        {
            *state = before;
        }
        *settled = Some((0..state.len()).map(|k| state.key(k)).collect());
    }
}
