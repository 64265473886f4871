//! The one composition of the stages, used by the CLI, the tests and the benchmarks.
//!
//! stroke → [`prepare`](crate::prepare) (duplicates, corners, hooks) → per piece
//! [`fit_bspline`] → [`split_spans`] → [`CurveFit`].
//!
//! Every stroke of a file is accounted for ([`fit_one`], [`fit_file`]): it becomes curves, a
//! [`DotFit`] (a tap: every sample within the tolerance of one point), or a
//! [`StrokeFailure`] naming the stroke and why; one stroke's failure never costs the others.

use crate::bspline::{BSplineFit, FitError, FitOptions, SegmentSearch, fit_bspline};
use crate::chain::{Chain, ChainError, ChainInput, ChainOptions, SeamPose, fit_chain};
use crate::closure::{
    Closure, ClosureKind, ClosureRecord, close_pieces, find_closure, folded_deviation, seam_pose,
};
use crate::prepare::{CornerOptions, DwellOptions, Piece, PieceEnd, prepare};
use crate::split::{Spans, SplitError, SplitKind, SplitOptions, split_spans};
use crate::stroke::{NoiseFloor, Stroke, StrokeFile, Units};

/// Options for the whole pipeline.
#[derive(Clone, Debug, PartialEq)]
pub struct PipelineOptions {
    /// Fitting tolerance in the stroke's units. Default `None`: per stroke, the unit's default
    /// ([`Units::default_tolerance`]) raised to the stroke's noise floor when
    /// [`PipelineOptions::noise_floor`] is on ([`PipelineOptions::stroke_tolerance`]). A given
    /// tolerance is used as given, even below the floor (the fit then follows the noise, and
    /// [`StrokeTolerance::below_floor`] says so).
    pub tolerance: Option<f64>,
    /// Raise the default tolerance to each stroke's noise floor ([`NoiseFloor::floor`]: the
    /// worst rounding of its coordinate grid and the largest excursion of its jitter,
    /// [`crate::stroke::noise_multiple`]). Default true; off, every stroke gets the unit's default, as the seed paper did.
    pub noise_floor: bool,
    /// The tolerance a stroke starts from when `tolerance` is not given, before its noise floor
    /// raises it. Default `None`: the unit's default ([`Units::default_tolerance`]). The app sets
    /// it from screen pixels at the zoom a stroke was drawn at.
    pub base_tolerance: Option<f64>,
    /// Corner turning angle, degrees. Default 70 (see [`CornerOptions`]).
    pub corner_angle: f64,
    /// Keep the pen's landing and lifting as drawn: its hooks and its dwell. Default false.
    pub keep_hooks: bool,
    /// Upper bound on B-spline segments per piece. Default 4096.
    pub max_segments: usize,
    /// Fair the B-spline (see [`FitOptions::fair`]). Default true.
    pub fair: bool,
    /// Segment-count search. Default [`SegmentSearch::DoublingBisection`].
    pub search: SegmentSearch,
    /// Options of the split stage (defaults: [`SplitOptions::default`]).
    pub split: SplitOptions,
    /// Fit the log-aesthetic chain. Default true; off, the pipeline stops after the split (the
    /// benchmark times the earlier stages that way).
    pub lac: bool,
    /// Options of the chain stage (defaults: [`ChainOptions::default`]).
    pub chain: ChainOptions,
    /// The tolerance a stroke's dwell, hooks and corners are read at ([`prepare`]). Default
    /// `None`: the fit's tolerance. The tolerance ladder ([`fit_on_ladder`]) reads them at the
    /// stroke's own tolerance on every rung: corners are what the samples show, and read at a
    /// looser tolerance (a window of 8 tolerances) a smooth turn became one, so loosening added
    /// pieces (the scribble fixture: 12 pieces at 1 px, 25 at 8).
    pub prepare_tolerance: Option<f64>,
    /// Fit a stroke that comes back to its start as a closed curve ([`crate::closure`]).
    /// Default true (the CLI's `--close auto`); off (`--close never`), every stroke is fitted
    /// open. Closure needs the chain ([`PipelineOptions::lac`]): its folded samples are
    /// measured against it.
    pub close: bool,
}

impl Default for PipelineOptions {
    fn default() -> Self {
        PipelineOptions {
            tolerance: None,
            noise_floor: true,
            base_tolerance: None,
            corner_angle: 70.0,
            keep_hooks: false,
            max_segments: 4096,
            fair: true,
            search: SegmentSearch::DoublingBisection,
            split: SplitOptions::default(),
            lac: true,
            chain: ChainOptions::default(),
            prepare_tolerance: None,
            close: true,
        }
    }
}

impl PipelineOptions {
    /// The nominal tolerance for strokes in `units`: the given one, else the unit's default (a
    /// stroke's own may be higher: [`PipelineOptions::stroke_tolerance`]).
    pub fn tolerance_for(&self, units: Units) -> f64 {
        self.tolerance.unwrap_or(units.default_tolerance())
    }

    /// The tolerance one stroke is fitted to, with the noise it was chosen by: the given
    /// tolerance, or the base tolerance ([`PipelineOptions::base_tolerance`], by default the
    /// unit's) raised to the stroke's noise floor (when [`PipelineOptions::noise_floor`] is on).
    pub fn stroke_tolerance(&self, stroke: &Stroke, units: Units) -> StrokeTolerance {
        let points: Vec<crate::geom::Point> = stroke.samples.iter().map(|s| s.point()).collect();
        let noise = NoiseFloor::estimate(&points);
        let base = self.base_tolerance.unwrap_or(units.default_tolerance());
        let own = if self.noise_floor {
            base.max(noise.floor)
        } else {
            base
        };
        StrokeTolerance {
            tolerance: self.tolerance.unwrap_or(own),
            own,
            noise,
        }
    }

    /// The default options without the log-aesthetic stage: prepare, B-spline and split only.
    pub fn splits_only() -> Self {
        PipelineOptions {
            lac: false,
            ..PipelineOptions::default()
        }
    }

    /// The seed paper's configuration: segments added one at a time, plain least squares (no
    /// fairing). The benchmark's peer.
    pub fn seed_method(mut self) -> Self {
        self.fair = false;
        self.search = SegmentSearch::Linear;
        self
    }

    /// Sets [`PipelineOptions::tolerance`].
    pub fn with_tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = Some(tolerance);
        self
    }

    fn corner_options(&self, tolerance: f64) -> CornerOptions {
        CornerOptions::for_tolerance(tolerance)
            .with_corner_angle(self.corner_angle)
            .with_drop_hooks(!self.keep_hooks)
    }
}

/// The tolerance a stroke is fitted to, and the noise floor it was chosen by.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrokeTolerance {
    /// The tolerance, in the stroke's units.
    pub tolerance: f64,
    /// The stroke's own tolerance: what `tolerance` is when none is given (the base tolerance
    /// raised to the noise floor), and the first rung of its tolerance ladder
    /// ([`fit_on_ladder`]).
    pub own: f64,
    /// The stroke's estimated noise.
    pub noise: NoiseFloor,
}

impl StrokeTolerance {
    /// Whether the tolerance is below the noise floor: the fit must then follow the samples'
    /// noise to keep each within it (more segments, curvature that is the noise's).
    pub fn below_floor(&self) -> bool {
        self.tolerance < self.noise.floor
    }
}

/// One fitted piece of a stroke.
#[derive(Clone, Debug)]
pub struct CurveFit {
    /// Index of the stroke.
    pub stroke: usize,
    /// Inclusive range of original sample indices represented.
    pub samples: (usize, usize),
    /// The B-spline fit (its distances cover every represented sample: merged duplicates share
    /// their representative's position).
    pub bspline: BSplineFit,
    /// Spans of monotonic curvature, with their split points. The first and last split are
    /// `start`/`end`, or `corner` where the piece meets a neighbour at a corner.
    pub spans: Spans,
    /// The piece's distinct sample positions (what was fitted), in stroke order.
    pub points: Vec<crate::geom::Point>,
    /// For each of `points`, its original sample index.
    pub indices: Vec<usize>,
    /// The log-aesthetic chain (`None` when [`PipelineOptions::lac`] is off).
    pub chain: Option<Chain>,
    /// The tolerance the piece was fitted to (its `within_tolerance` flags refer to it).
    pub tolerance: f64,
    /// The stroke's estimated noise (`None` where the caller fitted with a bare tolerance,
    /// [`fit_stroke`]).
    pub noise: Option<NoiseFloor>,
    /// On a closed stroke's last piece: how the stroke closes (its chain ends where the first
    /// piece's starts; a stroke of one piece is one closed curve). `None` on every other piece.
    pub closure: Option<ClosureRecord>,
}

/// A stroke fitted as one point: a tap, or any stroke whose samples all lie within the
/// tolerance of the centre of their bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DotFit {
    /// Index of the stroke.
    pub stroke: usize,
    /// Inclusive range of sample indices represented: all of the stroke's.
    pub samples: (usize, usize),
    /// The dot: the centre of the samples' bounding box.
    pub point: crate::geom::Point,
    /// Largest distance from a sample to `point` (at most the tolerance).
    pub max_deviation: f64,
}

/// What kind of problem kept a stroke from being fitted.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FailureKind {
    /// The stroke's data breaks a rule of the input format (a pressure outside 0..1, time
    /// running backwards, no samples, a shape too small for its coordinates): the message
    /// names the sample and field.
    Input,
    /// The fitter could not fit a valid stroke. This is a defect of kansei: please report it
    /// with the stroke.
    Fit,
}

/// A stroke that could not be fitted.
#[derive(Clone, Debug, PartialEq)]
pub struct StrokeFailure {
    /// Index of the stroke.
    pub stroke: usize,
    /// Which kind of problem.
    pub kind: FailureKind,
    /// The message, naming the stroke (and sample, field or piece where there is one).
    pub message: String,
}

/// What became of one stroke.
#[derive(Clone, Debug)]
pub enum StrokeOutcome {
    /// Fitted pieces (one per run between corners), in stroke order.
    Curves(Vec<CurveFit>),
    /// A tap or a stroke smaller than the tolerance.
    Dot(DotFit),
    /// Not fitted, and why.
    Failed(StrokeFailure),
}

/// The pipeline's result for a file: every stroke is in exactly one of `curves` (one entry per
/// piece), `dots` and `failures`.
#[derive(Clone, Debug)]
pub struct FitOutput {
    /// Units of the input.
    pub units: Units,
    /// Tolerance used.
    pub tolerance: f64,
    /// All pieces of all strokes fitted as curves, in order.
    pub curves: Vec<CurveFit>,
    /// Strokes fitted as dots, in order.
    pub dots: Vec<DotFit>,
    /// Strokes that could not be fitted, in order.
    pub failures: Vec<StrokeFailure>,
}

impl FitOutput {
    /// An output with curves only (no dots, no failures).
    pub fn with_curves(units: Units, tolerance: f64, curves: Vec<CurveFit>) -> Self {
        FitOutput {
            units,
            tolerance,
            curves,
            dots: Vec::new(),
            failures: Vec::new(),
        }
    }

    /// Adds one stroke's outcome.
    pub fn push(&mut self, outcome: StrokeOutcome) {
        match outcome {
            StrokeOutcome::Curves(curves) => self.curves.extend(curves),
            StrokeOutcome::Dot(dot) => self.dots.push(dot),
            StrokeOutcome::Failed(failure) => self.failures.push(failure),
        }
    }
}

/// Strokes fitted to a tolerance below their noise floor (a given tolerance; the default is never
/// below it): the fit then follows the samples' noise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BelowFloor {
    /// The file's tolerance.
    pub tolerance: f64,
    /// How many strokes.
    pub strokes: usize,
    /// The largest of their floors.
    pub floor: f64,
}

impl std::fmt::Display for BelowFloor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the tolerance {} is below the noise floor of {} stroke(s) (up to {:.3e}): the fit \
             will follow the noise",
            self.tolerance, self.strokes, self.floor
        )
    }
}

impl FitOutput {
    /// The strokes fitted below their noise floor, if any.
    pub fn below_floor(&self) -> Option<BelowFloor> {
        let mut strokes: Vec<usize> = Vec::new();
        let mut floor: f64 = 0.0;
        for c in &self.curves {
            if let Some(n) = c.noise
                && c.tolerance < n.floor
            {
                if strokes.last() != Some(&c.stroke) {
                    strokes.push(c.stroke);
                }
                floor = floor.max(n.floor);
            }
        }
        (!strokes.is_empty()).then_some(BelowFloor {
            tolerance: self.tolerance,
            strokes: strokes.len(),
            floor,
        })
    }
}

/// Why the pipeline failed on a stroke.
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    /// The tolerance is not a positive finite number.
    #[error("the tolerance must be a positive finite number, got {0}")]
    BadTolerance(f64),
    /// B-spline fitting failed.
    #[error("stroke {stroke}, samples {first}..={last}: {source}")]
    Fit {
        /// Stroke index.
        stroke: usize,
        /// First sample of the piece.
        first: usize,
        /// Last sample of the piece.
        last: usize,
        /// The cause.
        source: FitError,
    },
    /// The log-aesthetic chain could not be built.
    #[error("stroke {stroke}, samples {first}..={last}: {source}")]
    Chain {
        /// Stroke index.
        stroke: usize,
        /// First sample of the piece.
        first: usize,
        /// Last sample of the piece.
        last: usize,
        /// The cause.
        source: ChainError,
    },
    /// Splitting failed.
    #[error("stroke {stroke}, samples {first}..={last}: {source}")]
    Split {
        /// Stroke index.
        stroke: usize,
        /// First sample of the piece.
        first: usize,
        /// Last sample of the piece.
        last: usize,
        /// The cause.
        source: SplitError,
    },
}

/// Fits one stroke, whatever it holds: validated at the boundary (a failure of
/// [`FailureKind::Input`] if it breaks a rule), a dot if every sample lies within the
/// tolerance of one point, else curves through [`fit_stroke`] (a failure of
/// [`FailureKind::Fit`] if that fails, or panics: a defect, contained to its stroke).
pub fn fit_one(
    stroke: &Stroke,
    index: usize,
    tolerance: f64,
    options: &PipelineOptions,
) -> StrokeOutcome {
    let failed = |kind, message: String| {
        StrokeOutcome::Failed(StrokeFailure {
            stroke: index,
            kind,
            message,
        })
    };
    if let Err(e) = stroke.validate(index) {
        return failed(FailureKind::Input, e.to_string());
    }
    if let Some((point, max_deviation)) = stroke.as_dot(tolerance) {
        return StrokeOutcome::Dot(DotFit {
            stroke: index,
            samples: (0, stroke.samples.len().saturating_sub(1)),
            point,
            max_deviation,
        });
    }
    if let Err(e) = stroke.check_resolvable(index) {
        return failed(FailureKind::Input, e.to_string());
    }
    // The stages return typed errors and do not panic by design; should one panic all the
    // same, the defect costs this stroke only. The default hook has already printed it.
    let fitted = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        fit_stroke(stroke, index, tolerance, options)
    }));
    match fitted {
        Ok(Ok(curves)) => StrokeOutcome::Curves(curves),
        Ok(Err(e)) => failed(FailureKind::Fit, e.to_string()),
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| (*s).to_owned())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_owned());
            failed(
                FailureKind::Fit,
                format!("stroke {index}: internal error: {what}"),
            )
        }
    }
}

/// [`fit_one`] at the stroke's tolerance ([`PipelineOptions::stroke_tolerance`]), its curves
/// carrying the noise it was chosen by. A tolerance looser than the stroke's own
/// ([`StrokeTolerance::own`]) is met on the stroke's tolerance ladder ([`fit_on_ladder`]), so
/// that loosening the tolerance never adds segments.
pub fn fit_with_noise(
    stroke: &Stroke,
    index: usize,
    units: Units,
    options: &PipelineOptions,
) -> StrokeOutcome {
    let chosen = options.stroke_tolerance(stroke, units);
    let mut outcome = if options.lac && chosen.tolerance > chosen.own {
        fit_on_ladder(stroke, index, chosen, options)
    } else {
        fit_one(stroke, index, chosen.tolerance, options)
    };
    if let StrokeOutcome::Curves(curves) = &mut outcome {
        for c in curves {
            c.noise = Some(chosen.noise);
        }
    }
    outcome
}

/// Ratio between consecutive rungs of a stroke's tolerance ladder ([`fit_on_ladder`]): a
/// tolerance between two rungs is met by fits at most this much tighter than it. Over 13
/// tolerances from 0.5 to 4 px on the px fixture strokes, 1.1 leaves the ladder's segment counts
/// within 4 % of fresh fits at each tolerance (1.25 cost half as much but left up to 9 % more
/// segments); twice the stroke's own tolerance costs eight fits, each cheaper than the first
/// (looser fits have fewer segments).
pub const LADDER_RATIO: f64 = 1.1;

/// Most rungs a ladder climbs: past 40 rungs (about 41 times the stroke's own tolerance) the
/// top rung stands for every looser tolerance (still never more segments; the fit is then
/// tighter than asked).
pub const LADDER_MAX_RUNGS: usize = 40;

/// Fits a stroke to a tolerance looser than its own ([`StrokeTolerance::own`]) on its tolerance
/// ladder: the rungs `own · LADDER_RATIO^k` at or below the tolerance (at most
/// [`LADDER_MAX_RUNGS`]) are each fitted, and among the fits whose chains hold the tolerance
/// (every chain's largest distance within it, whether or not it held its own rung), the one
/// with the fewest segments is kept (the tightest among equals). The rungs depend on the stroke
/// alone and a fit holding a tolerance holds every looser one: a looser tolerance adds
/// candidates and drops none, so its fewest segments are never more. A fresh fit at
/// the tolerance itself is not a candidate: each stage decides afresh at each tolerance
/// (corners, B-spline knots, split points, cuts and merges), and fresh fits made the count rise
/// on loosening for 7 of the 52 px fixture strokes above their own tolerance. A dot at the
/// tolerance is a dot (no segment). The curves state the tolerance asked for.
pub fn fit_on_ladder(
    stroke: &Stroke,
    index: usize,
    chosen: StrokeTolerance,
    options: &PipelineOptions,
) -> StrokeOutcome {
    let tolerance = chosen.tolerance;
    if !(tolerance.is_finite() && chosen.own.is_finite() && chosen.own > 0.0) {
        return fit_one(stroke, index, tolerance, options);
    }
    // A dot at the tolerance beats any rung; checked first (validation too), as fit_one does.
    if stroke.validate(index).is_err() || stroke.as_dot(tolerance).is_some() {
        return fit_one(stroke, index, tolerance, options);
    }
    // Rungs from the top: looser fits are cheaper, and one segment cannot be beaten (a dot at a
    // rung would be a dot at the tolerance).
    let rungs: Vec<f64> = (0..LADDER_MAX_RUNGS as i32)
        .map(|k| chosen.own * LADDER_RATIO.powi(k))
        .take_while(|&r| r <= tolerance)
        .collect();
    let count = |curves: &[CurveFit]| -> usize {
        curves
            .iter()
            .map(|c| c.chain.as_ref().map_or(0, |ch| ch.segments.len()))
            .sum()
    };
    // A rung's fit is a candidate if every chain holds the tolerance asked for (its largest
    // distance, measured): a chain that misses its own rung may still hold it. Where none does,
    // the fit closest to the samples stands.
    let holds = |curves: &[CurveFit]| {
        curves.iter().all(|c| {
            c.chain
                .as_ref()
                .is_some_and(|ch| ch.max_deviation <= tolerance)
        })
    };
    let worst = |curves: &[CurveFit]| {
        curves
            .iter()
            .filter_map(|c| c.chain.as_ref().map(|ch| ch.max_deviation))
            .fold(0.0, f64::max)
    };
    let mut best: Option<(usize, Vec<CurveFit>)> = None;
    let mut closest: Option<(f64, Vec<CurveFit>)> = None;
    let mut last_failure = None;
    // Every rung reads the stroke's corners at its own tolerance (see
    // [`PipelineOptions::prepare_tolerance`]): the same pieces on every rung.
    let options = &PipelineOptions {
        prepare_tolerance: Some(chosen.own),
        ..options.clone()
    };
    for &rung in rungs.iter().rev() {
        match fit_one(stroke, index, rung, options) {
            StrokeOutcome::Curves(curves) if holds(&curves) => {
                let n = count(&curves);
                if best.as_ref().is_none_or(|(m, _)| n <= *m) {
                    best = Some((n, curves));
                    if n <= 1 {
                        break;
                    }
                }
            }
            StrokeOutcome::Curves(curves) => {
                let w = worst(&curves);
                if closest.as_ref().is_none_or(|(c, _)| w < *c) {
                    closest = Some((w, curves));
                }
            }
            other => last_failure = Some(other),
        }
    }
    match best.map(|(_, c)| c).or(closest.map(|(_, c)| c)) {
        Some(mut curves) => {
            for c in &mut curves {
                c.tolerance = tolerance;
                c.bspline.within_tolerance = c.bspline.max_deviation <= tolerance;
                if let Some(chain) = &mut c.chain {
                    chain.within_tolerance = chain.max_deviation <= tolerance;
                }
            }
            StrokeOutcome::Curves(curves)
        }
        None => last_failure.unwrap_or_else(|| fit_one(stroke, index, tolerance, options)),
    }
}

/// Runs the curve stages on one stroke that is valid ([`Stroke::validate`]) and not a dot
/// ([`Stroke::as_dot`]); [`fit_one`] checks both first.
pub fn fit_stroke(
    stroke: &Stroke,
    index: usize,
    tolerance: f64,
    options: &PipelineOptions,
) -> Result<Vec<CurveFit>, PipelineError> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(PipelineError::BadTolerance(tolerance));
    }
    let fit_options = FitOptions::new(tolerance)
        .with_max_segments(options.max_segments)
        .with_fairing(options.fair)
        .with_search(options.search);
    let read_at = options
        .prepare_tolerance
        .filter(|t| t.is_finite() && *t > 0.0)
        .unwrap_or(tolerance);
    let dwell = if options.keep_hooks {
        // Keeping the pen's landing and lifting as drawn keeps its dwell too.
        DwellOptions {
            min_samples: usize::MAX,
            ..DwellOptions::for_tolerance(read_at)
        }
    } else {
        DwellOptions::for_tolerance(read_at)
    };
    let pieces: Vec<Piece> = prepare(stroke, &options.corner_options(read_at), &dwell);
    // The pieces a closed fit fitted, by piece: one not taken leaves its inner pieces, whose
    // fits do not depend on the closure, to the open fit.
    let mut fitted = Vec::new();
    if options.close && options.lac {
        let corner = options.corner_angle.to_radians();
        if let Some(closure) = find_closure(&pieces, tolerance, corner)
            && let Some(curves) = fit_closed(
                stroke,
                index,
                tolerance,
                options,
                &fit_options,
                &pieces,
                &closure,
                &mut fitted,
            )
        {
            return Ok(curves);
        }
    }
    fit_pieces(
        pieces,
        index,
        tolerance,
        options,
        &fit_options,
        None,
        Known::Reuse(&fitted),
    )
}

/// The pieces already fitted for [`fit_pieces`]: those of a closed fit are kept (`Keep`, each
/// piece without a seam end, with its fit) for the open fit that may follow to reuse
/// (`Reuse`); an open fit alone keeps nothing (no copy on the common path).
enum Known<'a> {
    Keep(&'a mut Vec<(Piece, CurveFit)>),
    Reuse(&'a [(Piece, CurveFit)]),
}

/// Where a closed stroke's curve closes, for [`fit_piece`]: the point both of its ends are held
/// at, and the seam's pose where it closes smoothly (`None`: at a corner).
#[derive(Clone, Copy, Debug)]
struct Closing {
    meet: crate::geom::Point,
    seam: Option<SeamPose>,
}

/// A stroke that comes back to its start ([`find_closure`]) fitted as a closed curve; `None`
/// where that fails, misses the tolerance (on its own samples, or by more than
/// [`crate::closure::FOLDED_TOLERANCES`] on the folded ones) or falls back to G1 where a smooth
/// chain was asked for: the stroke is then fitted open.
fn fit_closed(
    stroke: &Stroke,
    index: usize,
    tolerance: f64,
    options: &PipelineOptions,
    fit_options: &FitOptions,
    pieces: &[Piece],
    closure: &Closure,
    fitted: &mut Vec<(Piece, CurveFit)>,
) -> Option<Vec<CurveFit>> {
    let closed = close_pieces(pieces.to_vec(), closure);
    let seam = match closure.kind {
        ClosureKind::Smooth => seam_pose(&closed, closure, tolerance),
        ClosureKind::Corner => None,
    };
    // A seam bending tighter than the samples resolve (the smooth chain's curvature bound: a
    // stroke stopping short of its start with its end turned away, a curl at its start) is no
    // smooth closure, and a corner there is not what was drawn: the stroke is fitted open.
    let bound = 1.0 / (crate::chain::smooth::MIN_RADIUS_TOLERANCES * tolerance);
    if seam.is_some_and(|s| s.kappa.abs() > bound) {
        return None;
    }
    // A smooth closure whose seam cannot be read closes at the first sample, as a corner.
    let kind = if seam.is_some() {
        ClosureKind::Smooth
    } else {
        ClosureKind::Corner
    };
    let meet = seam.map_or(closed.first()?.points.first().copied()?, |s| s.point);
    let mut curves = fit_pieces(
        closed.clone(),
        index,
        tolerance,
        options,
        fit_options,
        Some(Closing { meet, seam }),
        Known::Keep(fitted),
    )
    .ok()?;
    // A closed curve that misses the tolerance, has fallen back to G1 where a smooth chain was
    // asked for, or (a G1 chain) fell back to lines meeting at corners somewhere, is not
    // taken: the open fit is.
    let smooth = options.chain.continuity != crate::chain::Continuity::G1;
    let cornered = |ch: &Chain| {
        ch.segments
            .windows(2)
            .any(|w| w[0].end == crate::chain::JointKind::Corner)
    };
    if !curves.iter().all(|c| {
        c.chain.as_ref().is_some_and(|ch| {
            ch.within_tolerance
                && !(smooth && ch.continuity == crate::chain::Continuity::G1)
                && (smooth || !cornered(ch))
        })
    }) {
        return None;
    }
    let chains: Vec<&[crate::chain::ChainSegment]> = curves
        .iter()
        .filter_map(|c| c.chain.as_ref().map(|ch| ch.segments.as_slice()))
        .collect();
    // The curves' pieces as fitted (a piece cut at its sharpest vertex is two curves).
    let loop_pieces: Vec<Piece> = curves
        .iter()
        .map(|c| Piece {
            points: c.points.clone(),
            indices: c.indices.clone(),
            samples: c.samples,
            start: PieceEnd::Corner,
            end: PieceEnd::Corner,
        })
        .collect();
    let positions: Vec<crate::geom::Point> = stroke.samples.iter().map(|s| s.point()).collect();
    let folded = folded_deviation(&positions, closure, &loop_pieces, &chains, tolerance);
    if !(folded <= crate::closure::FOLDED_TOLERANCES * tolerance) {
        return None;
    }
    let whole = curves.len() == 1;
    let last = curves.last_mut()?;
    last.closure = Some(ClosureRecord {
        whole,
        kind,
        folded: closure.folded,
        folded_deviation: folded,
        gap: closure.gap,
    });
    Some(curves)
}

/// Fits `pieces` in order, each through [`fit_piece`] (a piece too short for its tolerance, or
/// folding back on itself, is cut at its sharpest vertex first), taking a piece's fit from
/// `known` where it is there ([`Known`]).
fn fit_pieces(
    pieces: Vec<Piece>,
    index: usize,
    tolerance: f64,
    options: &PipelineOptions,
    fit_options: &FitOptions,
    closing: Option<Closing>,
    mut known: Known,
) -> Result<Vec<CurveFit>, PipelineError> {
    let mut pending = pieces;
    pending.reverse();
    let mut curves = Vec::with_capacity(pending.len());
    while let Some(piece) = pending.pop() {
        // A piece fitted already (between a closed stroke's first and last pieces, whose closed
        // fit was not taken) is the same fit: its ends do not depend on the closure.
        let reused = match &known {
            Known::Reuse(fitted) => fitted
                .iter()
                .find(|(p, _)| *p == piece)
                .map(|(_, c)| Ok(c.clone())),
            Known::Keep(_) => None,
        };
        let result = reused
            .unwrap_or_else(|| fit_piece(&piece, index, tolerance, options, fit_options, closing));
        let seam = piece.start == PieceEnd::Seam || piece.end == PieceEnd::Seam;
        if let (Known::Keep(fitted), Ok(curve)) = (&mut known, &result)
            && !seam
        {
            fitted.push((piece.clone(), curve.clone()));
        }
        match result {
            // Fewer than four distinct points are fitted by a straight line (too few for a
            // cubic): where the line misses a sample by more than the tolerance, the samples turn
            // at a vertex the data show and the two sides are lines that hold every sample.
            Ok(curve)
                if !curve.bspline.within_tolerance
                    && (3..MIN_CURVE_POINTS).contains(&piece.points.len()) =>
            {
                let (a, b) = cut_at_sharpest(&piece);
                pending.push(b);
                pending.push(a);
            }
            Ok(curve) => curves.push(curve),
            // The piece's B-spline has a cusp, or so nearly one that no segment's curvature is
            // finite there: the stroke folds back within the corner detection's reach (a
            // reversal with legs no longer than the tolerance, seen on quarter-pixel grids). The
            // fold is a corner the samples show: cut at the sharpest vertex and fit both sides,
            // as the corner detection would have. Each cut leaves fewer points per piece, so this
            // ends (two points make a straight line).
            Err(
                PipelineError::Split {
                    source: SplitError::Singular { .. },
                    ..
                }
                | PipelineError::Chain { .. },
            ) if piece.points.len() >= 3 => {
                let (a, b) = cut_at_sharpest(&piece);
                pending.push(b);
                pending.push(a);
            }
            Err(e) => return Err(e),
        }
    }
    Ok(curves)
}

/// Fewest distinct points a piece needs for a curve: fewer are fitted by a straight line
/// ([`fit_bspline`]).
const MIN_CURVE_POINTS: usize = 4;

/// The piece cut at its sharpest interior vertex (the largest turning angle of its polyline)
/// into two pieces meeting there at a corner.
fn cut_at_sharpest(piece: &Piece) -> (Piece, Piece) {
    let p = &piece.points;
    let turning = |i: usize| {
        let (u, v) = (p[i] - p[i - 1], p[i + 1] - p[i]);
        u.cross(v).atan2(u.dot(v)).abs()
    };
    let k = (1..p.len() - 1)
        .max_by(|&i, &j| turning(i).total_cmp(&turning(j)))
        .unwrap_or(p.len() / 2);
    let corner = piece.indices[k];
    let a = Piece {
        points: p[..=k].to_vec(),
        indices: piece.indices[..=k].to_vec(),
        samples: (piece.samples.0, corner),
        start: piece.start,
        end: PieceEnd::Corner,
    };
    let b = Piece {
        points: p[k..].to_vec(),
        indices: piece.indices[k..].to_vec(),
        samples: (corner, piece.samples.1),
        start: PieceEnd::Corner,
        end: piece.end,
    };
    (a, b)
}

/// Fits one piece: B-spline, split, chain. `closing`: where a closed stroke's ends meet.
fn fit_piece(
    piece: &Piece,
    index: usize,
    tolerance: f64,
    options: &PipelineOptions,
    fit_options: &FitOptions,
    closing: Option<Closing>,
) -> Result<CurveFit, PipelineError> {
    let (first, last) = piece.samples;
    // A corner is shared: both pieces pass exactly through the corner sample (G0). A closed
    // stroke's ends both pass through where it closes.
    let held = |end: PieceEnd, p: Option<&crate::geom::Point>| match end {
        PieceEnd::Corner => p.copied(),
        PieceEnd::Seam => closing.map(|c| c.meet),
        _ => None,
    };
    let fit_options = fit_options.with_ends(
        held(piece.start, piece.points.first()),
        held(piece.end, piece.points.last()),
    );
    let bspline =
        fit_bspline(&piece.points, &fit_options).map_err(|source| PipelineError::Fit {
            stroke: index,
            first,
            last,
            source,
        })?;
    let free = |end: PieceEnd| !matches!(end, PieceEnd::Corner | PieceEnd::Seam);
    let split = options
        .split
        .with_tolerance(tolerance)
        .with_free_ends(free(piece.start), free(piece.end));
    let mut spans = split_spans(&bspline.curve.to_beziers(), &split).map_err(|source| {
        PipelineError::Split {
            stroke: index,
            first,
            last,
            source,
        }
    })?;
    let seam = closing.and_then(|c| c.seam);
    let mark = |end: PieceEnd| match end {
        PieceEnd::Corner => Some(SplitKind::Corner),
        PieceEnd::Seam if seam.is_some() => Some(SplitKind::Seam),
        PieceEnd::Seam => Some(SplitKind::Corner),
        _ => None,
    };
    mark_ends(&mut spans, mark(piece.start), mark(piece.end));
    let chain = if options.lac {
        let input = ChainInput {
            points: &piece.points,
            params: &bspline.params,
            indices: &piece.indices,
            samples: piece.samples,
            curve: &bspline.curve,
            spans: &spans,
            seam,
        };
        let chain = fit_chain(&input, tolerance, &options.chain).map_err(|source| {
            PipelineError::Chain {
                stroke: index,
                first,
                last,
                source,
            }
        })?;
        Some(chain)
    } else {
        None
    };
    Ok(CurveFit {
        stroke: index,
        samples: piece.samples,
        bspline,
        spans,
        points: piece.points.clone(),
        indices: piece.indices.clone(),
        chain,
        tolerance,
        noise: None,
        closure: None,
    })
}

/// Relabels a piece's first/last split (and span end) as `start`/`end` say where they are
/// given: a corner where it meets a neighbour at a corner, a seam where a closed stroke closes.
fn mark_ends(spans: &mut Spans, start: Option<SplitKind>, end: Option<SplitKind>) {
    if let Some(kind) = start {
        if let Some(s) = spans.splits.first_mut() {
            s.kind = kind;
        }
        if let Some(s) = spans.spans.first_mut() {
            s.start = kind;
        }
    }
    if let Some(kind) = end {
        if let Some(s) = spans.splits.last_mut() {
            s.kind = kind;
        }
        if let Some(s) = spans.spans.last_mut() {
            s.end = kind;
        }
    }
}

/// Fits every stroke of every file on up to `threads` threads (each takes the next stroke from a
/// shared queue, so long and short strokes balance), and returns one output per file, in order,
/// each exactly what [`fit_file`] gives: the strokes are independent and their outcomes are put
/// back in stroke order. `progress(done, total)` is called after each stroke, from the threads.
pub fn fit_files(
    files: &[&StrokeFile],
    options: &PipelineOptions,
    threads: usize,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<FitOutput>, PipelineError> {
    use std::sync::Mutex;
    use std::sync::atomic::{AtomicUsize, Ordering};
    for file in files {
        let tolerance = options.tolerance_for(file.units);
        if !(tolerance.is_finite() && tolerance > 0.0) {
            return Err(PipelineError::BadTolerance(tolerance));
        }
    }
    let jobs: Vec<(usize, usize)> = files
        .iter()
        .enumerate()
        .flat_map(|(f, file)| (0..file.strokes.len()).map(move |s| (f, s)))
        .collect();
    let slots: Vec<Mutex<Option<StrokeOutcome>>> = jobs.iter().map(|_| Mutex::new(None)).collect();
    let (next, done) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let work = || {
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            let Some(&(f, s)) = jobs.get(i) else {
                break;
            };
            let file = files[f];
            let outcome = fit_with_noise(&file.strokes[s], s, file.units, options);
            // fit_one contains panics, so no lock is ever poisoned; take it either way.
            *slots[i].lock().unwrap_or_else(|e| e.into_inner()) = Some(outcome);
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, jobs.len());
        }
    };
    let workers = threads.clamp(1, jobs.len().max(1));
    if workers == 1 {
        // One worker runs on the calling thread ([`fit_file`], a service worker): no spawn.
        work();
    } else {
        std::thread::scope(|scope| {
            for _ in 0..workers {
                scope.spawn(work);
            }
        });
    }
    let mut outputs: Vec<FitOutput> = files
        .iter()
        .map(|file| {
            FitOutput::with_curves(file.units, options.tolerance_for(file.units), Vec::new())
        })
        .collect();
    for ((f, s), slot) in jobs.iter().zip(slots) {
        let outcome = slot.into_inner().unwrap_or_else(|e| e.into_inner());
        // Every job was taken by a worker and filled before the scope ended.
        let outcome = outcome.unwrap_or_else(|| {
            StrokeOutcome::Failed(StrokeFailure {
                stroke: *s,
                kind: FailureKind::Fit,
                message: format!("stroke {s}: not fitted"),
            })
        });
        outputs[*f].push(outcome);
    }
    Ok(outputs)
}

/// Runs the pipeline on every stroke of a file ([`fit_one`] each): every stroke is accounted
/// for in the output. Fails only on options that no stroke could be fitted with (a tolerance
/// that is not a positive finite number).
pub fn fit_file(file: &StrokeFile, options: &PipelineOptions) -> Result<FitOutput, PipelineError> {
    let mut outputs = fit_files(&[file], options, 1, &|_, _| {})?;
    // One file in, one output out.
    Ok(outputs.swap_remove(0))
}
