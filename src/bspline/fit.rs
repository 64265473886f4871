//! Fitting a cubic B-spline to samples within a distance tolerance.

use crate::geom::Point;

use super::curve::{BSpline, DEGREE};
use super::lsq::{BandedLsq, LsqError, Row};
use super::project::{Foot, Pieces};

/// How each sample is weighted in the least-squares objective.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Weighting {
    /// Each sample weighs the arc length it stands for (half the distance to each neighbour), so
    /// the objective approximates ∫‖C − stroke‖² ds and does not depend on the pen's speed. Samples
    /// piled up where the pen dwells weigh almost nothing and cannot pull the end tangents.
    #[default]
    ArcLength,
    /// Every sample weighs the same (the seed paper's objective).
    Uniform,
}

/// How the number of segments is searched.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SegmentSearch {
    /// 1 segment, then doubling until the tolerance holds, then bisection: O(log n) fits.
    #[default]
    DoublingBisection,
    /// 1, 2, 3, … segments until the tolerance holds: the seed paper's search, O(n) fits. Kept
    /// as the benchmark's peer.
    Linear,
}

/// Options for [`fit_bspline`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitOptions {
    /// Largest allowed distance from any sample to the curve, in the samples' units. No default
    /// here: it depends on the units (see [`crate::stroke::Units::default_tolerance`]).
    pub tolerance: f64,
    /// Upper bound on the number of segments (knot spans). Default 4096; the data also bound it
    /// (at most one control point per sample).
    pub max_segments: usize,
    /// Parameter-correction passes per least-squares solve: each sample's parameter is moved to
    /// its foot point and the curve solved again (Hoschek's intrinsic parameterisation).
    /// Default 3: the first pass removes most of the chord-length error, later ones polish.
    /// A count whose curve misses a sample by more than `HOPELESS_FACTOR` (3) tolerances gets
    /// no further pass: it fails either way.
    pub parameter_corrections: usize,
    /// Sample weighting. Default [`Weighting::ArcLength`].
    pub weighting: Weighting,
    /// Fairing. Default true: once the fewest segments are known, the curve is refitted with
    /// `FAIRING_SEGMENT_FACTOR` (2) times as many and the largest penalty on the jumps of C‴ at
    /// the knots that keeps every sample within the tolerance. A plain least-squares spline with just enough segments
    /// meets the tolerance with a curvature that wobbles around the drawn one, and every wobble
    /// is a spurious curvature extremum; the fairest curve within the tolerance has only the
    /// extrema the data demand.
    pub fair: bool,
    /// The segment-count search. Default [`SegmentSearch::DoublingBisection`].
    pub search: SegmentSearch,
    /// A point the curve must start at exactly (its first control point), e.g. a corner shared
    /// with the previous piece. Default `None`: the start is free like every other point.
    pub start: Option<Point>,
    /// A point the curve must end at exactly. Default `None`.
    pub end: Option<Point>,
}

/// Segment multiplier for the fairing pass: the extra freedom is what the penalty trades for
/// smoothness. 2 leaves the tolerance reachable with a strong penalty on every fixture.
pub const FAIRING_SEGMENT_FACTOR: usize = 2;

/// Range of the fairing weight λ searched, relative to the piece's natural scale
/// `λ_ref = tol² / J₀` (J₀ = Σ h‖ΔC‴‖² over the knots of the unpenalised fit, see
/// `jump_energy`), the weight at which the penalty
/// of the unpenalised curve equals the data term's whole budget of m·tol². Ten decades around it
/// cover every fixture: at 1e-6·λ_ref the penalty moves the curve by far less than the tolerance,
/// at 1e4·λ_ref it flattens any curve beyond it.
const FAIRING_RELATIVE_RANGE: (f64, f64) = (1e-6, 1e4);

/// A segment count whose least-squares curve misses a sample by more than this many
/// tolerances is not corrected further (it fails): the parameter corrections move the curve by
/// a fraction of what the chord-length parameters got wrong, not from several tolerances to
/// within one. Over the fixture strokes up to 600 samples the same counts pass and fail as with
/// every correction made, for 2 % fewer instructions.
const HOPELESS_FACTOR: f64 = 3.0;

/// Most penalised solves of the fairing search. Bisection on log λ needed 8 (10 decades to a
/// factor of 1.09); regula falsi (see `fair`) usually reaches [`FAIR_ENOUGH`] in 3 to 5.
const FAIRING_STEPS: usize = 8;

/// The fairing search stops at a weight whose curve passes with its largest distance at least
/// this fraction of the tolerance: the largest distance grows smoothly and monotonically with λ,
/// so the weight is then within a few percent of the boundary and the curve within a percent of
/// the tolerance of the fairest one. Over the fixture strokes up to 600 samples at five
/// tolerances (0.8–1.25 of the default), against 8 bisection steps: 2.7 fewer solves per fit
/// (11.0 against 13.7 in all), 2 % fewer instructions, 3 661 segments against 3 656 and the
/// same rms distance (0.95 gave 1 % more segments and a 5 % higher rms distance).
const FAIR_ENOUGH: f64 = 0.99;

/// The fairing search also stops once its bracket on ln λ is this narrow (a factor of 1.09, what
/// 8 bisection steps over 10 decades left).
const FAIRING_BRACKET: f64 = 0.09;

impl FitOptions {
    /// Options with this tolerance and every other field at its default.
    pub const fn new(tolerance: f64) -> Self {
        FitOptions {
            tolerance,
            max_segments: 4096,
            parameter_corrections: 3,
            weighting: Weighting::ArcLength,
            fair: true,
            search: SegmentSearch::DoublingBisection,
            start: None,
            end: None,
        }
    }

    /// Sets [`FitOptions::start`] and [`FitOptions::end`].
    pub const fn with_ends(mut self, start: Option<Point>, end: Option<Point>) -> Self {
        self.start = start;
        self.end = end;
        self
    }

    /// Sets [`FitOptions::search`].
    pub const fn with_search(mut self, search: SegmentSearch) -> Self {
        self.search = search;
        self
    }

    /// Sets [`FitOptions::fair`].
    pub const fn with_fairing(mut self, fair: bool) -> Self {
        self.fair = fair;
        self
    }

    /// Sets [`FitOptions::max_segments`].
    pub const fn with_max_segments(mut self, n: usize) -> Self {
        self.max_segments = n;
        self
    }

    /// Sets [`FitOptions::parameter_corrections`].
    pub const fn with_parameter_corrections(mut self, n: usize) -> Self {
        self.parameter_corrections = n;
        self
    }

    /// Sets [`FitOptions::weighting`].
    pub const fn with_weighting(mut self, w: Weighting) -> Self {
        self.weighting = w;
        self
    }
}

/// A fitted B-spline and how well it fits.
#[derive(Clone, Debug)]
pub struct BSplineFit {
    /// The curve, on the parameter domain [0, 1].
    pub curve: BSpline,
    /// Each sample's foot-point parameter.
    pub params: Vec<f64>,
    /// Each sample's distance to the curve (foot-point distance to the whole curve).
    pub distances: Vec<f64>,
    /// The largest of `distances`.
    pub max_deviation: f64,
    /// Root mean square of `distances`.
    pub rms_deviation: f64,
    /// Whether `max_deviation ≤ tolerance`. False only when even the largest allowed segment
    /// count could not reach the tolerance; the curve is then the best one found.
    pub within_tolerance: bool,
    /// How many least-squares fits the search made (segment counts tried, plus fairing trials).
    pub attempts: usize,
    /// The fairing weight λ of the final curve (0 when not faired): the curve minimises
    /// Σ wᵢ‖C(uᵢ) − qᵢ‖² + λ·m·Σₖ hₖ‖C‴(tₖ⁺) − C‴(tₖ⁻)‖² over its knots (mean sample weight 1,
    /// hₖ the mean length of the spans at interior knot tₖ, all in the fit's unit frame).
    pub fairing: f64,
}

/// Why a fit could not be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FitError {
    /// Fewer than two distinct points.
    #[error("need at least 2 distinct points, got {0}")]
    TooFewPoints(usize),
    /// The tolerance is not a positive finite number.
    #[error("the tolerance must be a positive finite number, got {0}")]
    BadTolerance(f64),
    /// The least-squares system could not be solved.
    #[error(transparent)]
    Lsq(#[from] LsqError),
}

/// Fits a clamped cubic B-spline to `points` so that every point lies within
/// `options.tolerance` of the curve.
///
/// - **Parameterisation**: chord length, then [`FitOptions::parameter_corrections`] passes of
///   foot-point correction. Chord length is the natural first guess for dense, evenly sampled pen
///   data; the correction makes the final parameters intrinsic (each sample's own foot point), so
///   the chord-vs-centripetal choice matters little in the result.
/// - **Knots**: averages of the sample parameters spread evenly over the samples (see
///   `averaged_knots`; de Boor's averaging at the interpolation limit): every span holds data,
///   so the system is never singular. Should a span still be short of data, fairing rows decide
///   it (see [`super::lsq::FAIRING_WEIGHT`]).
/// - **Segment count**: one segment first, then doubling until the tolerance holds, then
///   bisection between the last failing and the first passing count. The deviation is not
///   strictly monotonic in the count, so the result is the fewest segments the bisection saw
///   pass, not always the global fewest: a deliberate trade of O(log n) solves for O(n).
/// - Fewer than four distinct points are too few for a cubic: they become a straight line (the
///   least-squares line, as a cubic with evenly spaced collinear control points).
///
/// `points` must be finite with consecutive duplicates already merged (as
/// [`crate::pipeline`] does).
pub fn fit_bspline(points: &[Point], options: &FitOptions) -> Result<BSplineFit, FitError> {
    if !(options.tolerance.is_finite() && options.tolerance > 0.0) {
        return Err(FitError::BadTolerance(options.tolerance));
    }
    // Work in a frame centred on the points' bounding box and scaled to unit diagonal: the
    // fairness rows carry coefficients of order 1/Δu³, and with raw coordinates far from the
    // origin (a stroke at x ≈ 10⁴) the translation-invariant C‴ = Σ N‴ⱼPⱼ would be computed by
    // cancelling huge terms. In the unit frame the fit is invariant under translation and scale
    // to rounding.
    let Some(bounds) = crate::geom::bounding_box(points.iter().copied()) else {
        return Err(FitError::TooFewPoints(0));
    };
    let size = bounds.origin().distance(Point::new(bounds.x1, bounds.y1));
    if !(size > 0.0 && size.is_finite()) {
        return Err(FitError::TooFewPoints(1));
    }
    let centre = bounds.center();
    let to_unit = |p: Point| ((p - centre) / size).to_point();
    let unit: Vec<Point> = points.iter().map(|p| to_unit(*p)).collect();
    let unit_options = FitOptions {
        tolerance: options.tolerance / size,
        start: options.start.map(to_unit),
        end: options.end.map(to_unit),
        ..*options
    };
    let fit = fit_unit(&unit, &unit_options)?;
    Ok(from_unit(fit, centre, size, options.tolerance))
}

/// Maps a fit made in the unit frame back to the caller's coordinates.
fn from_unit(fit: BSplineFit, centre: Point, size: f64, tolerance: f64) -> BSplineFit {
    let control_points = fit
        .curve
        .control_points()
        .iter()
        .map(|p| centre + p.to_vec2() * size)
        .collect();
    let knots = fit.curve.knots().to_vec();
    let curve = BSpline::new(knots, control_points).unwrap_or(fit.curve);
    let distances: Vec<f64> = fit.distances.iter().map(|d| d * size).collect();
    let max_deviation = fit.max_deviation * size;
    BSplineFit {
        curve,
        params: fit.params,
        distances,
        max_deviation,
        rms_deviation: fit.rms_deviation * size,
        within_tolerance: max_deviation <= tolerance,
        attempts: fit.attempts,
        fairing: fit.fairing,
    }
}

/// [`fit_bspline`] in the unit frame.
fn fit_unit(points: &[Point], options: &FitOptions) -> Result<BSplineFit, FitError> {
    let chord = chord_params(points);
    let distinct = 1 + points.windows(2).filter(|w| w[0] != w[1]).count();
    let Some(chord) = chord.filter(|_| distinct >= 2) else {
        return Err(FitError::TooFewPoints(distinct));
    };
    if distinct < DEGREE + 1 {
        return Ok(fit_line(points, options));
    }
    let weights = weights(points, options.weighting);
    let max_segments = options.max_segments.clamp(1, distinct - DEGREE);
    // The data's bound too, for the fits below (see `fit_segments_penalised`).
    let options = &FitOptions {
        max_segments,
        ..*options
    };

    let mut attempts = 0;
    let mut attempt = |segments: usize| -> Result<BSplineFit, FitError> {
        attempts += 1;
        fit_segments(points, &weights, &chord, segments, options, true)
    };
    let step = |n: usize| match options.search {
        SegmentSearch::DoublingBisection => 2 * n,
        SegmentSearch::Linear => n + 1,
    };
    // Doubling (or the seed's one-by-one growth).
    let mut failed = 0;
    let mut n = 1;
    let mut passed = loop {
        let fit = attempt(n)?;
        if fit.within_tolerance {
            break fit;
        }
        if n >= max_segments {
            let mut fit = fit;
            fit.attempts = attempts;
            return Ok(exact(fit, points, options.tolerance));
        }
        failed = n;
        n = step(n).min(max_segments);
    };
    // Bisection on (failed, n].
    let mut hi = n;
    while hi - failed > 1 {
        let mid = failed + (hi - failed) / 2;
        let fit = attempt(mid)?;
        if fit.within_tolerance {
            hi = mid;
            passed = fit;
        } else {
            failed = mid;
        }
    }
    passed.attempts = attempts;
    if options.fair {
        let segments = (hi * FAIRING_SEGMENT_FACTOR).min(max_segments);
        passed = fair(points, &weights, &chord, segments, options, passed)?;
    }
    if passed.fairing == 0.0 {
        // The search's own fit is the answer: give it every parameter correction (it stopped at
        // the first that passed), keeping it as it is should that lift a sample over.
        let full = fit_segments(points, &weights, &chord, hi, options, false)?;
        let attempts = passed.attempts + 1;
        if full.within_tolerance {
            passed = full;
        }
        passed.attempts = attempts;
    }
    Ok(exact(passed, points, options.tolerance))
}

/// The fairest fit with `segments` segments that stays within the tolerance.
///
/// The plain least-squares fit with `segments` segments (parameter-corrected) fixes the knots and
/// the sample parameters; then a search on log λ over [`FAIRING_RELATIVE_RANGE`] × λ_ref finds
/// the largest fairing weight whose penalised solve keeps every sample's local foot-point
/// distance within the tolerance. With parameters and knots held, each trial is one linear
/// solve, so the search is well posed. The largest distance d(λ) grows smoothly with λ, and
/// ln(d/tol) is close to linear in ln λ near the boundary: after the range's middle (and its top,
/// when the middle passes), regula falsi with the Illinois modification on ln(d/tol) against
/// ln λ, from the passing and failing weights found, until a passing curve reaches
/// [`FAIR_ENOUGH`] of the tolerance or the bracket is [`FAIRING_BRACKET`] narrow. The plain fit
/// stands in for the range's bottom. `fallback` (the passing fit with the fewest segments) is
/// kept when no penalised fit passes: more segments without fairing would only add wobbles.
fn fair(
    points: &[Point],
    weights: &[f64],
    chord: &[f64],
    segments: usize,
    options: &FitOptions,
    fallback: BSplineFit,
) -> Result<BSplineFit, FitError> {
    let mut attempts = fallback.attempts + 1;
    let plain = fit_segments(points, weights, chord, segments, options, false)?;
    let jumps = jump_energy(&plain.curve);
    if !(plain.within_tolerance && jumps > 0.0 && jumps.is_finite()) {
        return Ok(BSplineFit {
            attempts,
            ..fallback
        });
    }
    let knots = plain.curve.knots().to_vec();
    let ends = (options.start, options.end);
    let params = plain.params.clone();
    let m = points.len() as f64;
    let tolerance = options.tolerance;
    // Data term: Σ wᵢ‖rᵢ‖² with mean weight 1, so its budget is m·tol²; the penalty of the
    // unpenalised curve at weight λ·m is λ·m·J₀. They balance at λ_ref = tol²/J₀.
    let reference = tolerance * tolerance / jumps;
    let range = (
        (reference * FAIRING_RELATIVE_RANGE.0).ln(),
        (reference * FAIRING_RELATIVE_RANGE.1).ln(),
    );
    // The penalised fit at ln λ = t; a solve that fails (not expected: fairness rows only add
    // rank) counts as a failing weight, never as a failed fit: the fallback always exists.
    // A design that cannot be set up (not expected: the plain fit used the same knots) fails
    // every weight, like a failed solve.
    let design = Design::new(points, &params, weights, knots, true, ends).ok();
    let mut trial = |t: f64| -> Option<BSplineFit> {
        attempts += 1;
        let curve = design.as_ref()?.solve(t.exp() * m).ok()?;
        let pieces = Pieces::new(curve.to_beziers());
        let feet: Vec<Foot> = points
            .iter()
            .zip(&params)
            .map(|(q, &u)| pieces.project_local(*q, u))
            .collect();
        let mut fit = summarise(curve, &feet, tolerance);
        fit.fairing = t.exp();
        Some(fit)
    };
    // ln(d/tol) of a trial: ≤ 0 passes.
    let excess = |fit: &Option<BSplineFit>| {
        fit.as_ref()
            .map_or(f64::INFINITY, |f| (f.max_deviation / tolerance).ln())
    };
    // The bracket: (ln λ, ln(d/tol)) passing at `low`, failing at `high`.
    let mut low = (range.0, (plain.max_deviation / tolerance).ln());
    let mut high: Option<(f64, f64)> = None;
    let mut best: Option<BSplineFit> = None;
    let mut next = 0.5 * (range.0 + range.1);
    // Which end the last trial replaced (−1 low, +1 high): replaced twice in a row, the other
    // end's value is halved (Illinois).
    let mut replaced = 0i8;
    for step in 0..FAIRING_STEPS {
        let fit = trial(next);
        let e = excess(&fit);
        if e <= 0.0 {
            low = (next, e);
            let close = fit
                .as_ref()
                .is_some_and(|f| f.max_deviation >= FAIR_ENOUGH * tolerance);
            best = fit;
            if close {
                break;
            }
            if replaced == -1
                && let Some(h) = high.as_mut()
            {
                h.1 *= 0.5;
            }
            replaced = -1;
        } else {
            high = Some((next, if e.is_finite() { e } else { f64::MAX }));
            if replaced == 1 {
                low.1 *= 0.5;
            }
            replaced = 1;
        }
        next = match high {
            // The middle passed: try the top of the range first.
            None if step == 0 => range.1,
            None => break,
            Some(h) => {
                if h.0 - low.0 <= FAIRING_BRACKET {
                    break;
                }
                // Regula falsi, kept off the bracket's ends (a tenth of it) so that a curved
                // excess cannot stall it at one end.
                let t = if h.1 < f64::MAX && h.1 > low.1 {
                    low.0 + (h.0 - low.0) * (-low.1 / (h.1 - low.1))
                } else {
                    0.5 * (low.0 + h.0)
                };
                let margin = 0.1 * (h.0 - low.0);
                t.clamp(low.0 + margin, h.0 - margin)
            }
        };
    }
    let mut out = best.unwrap_or(fallback);
    out.attempts = attempts;
    Ok(out)
}

/// J = Σₖ hₖ‖C‴(tₖ⁺) − C‴(tₖ⁻)‖² over the interior knots: on each Bézier piece of parameter
/// length Δu, C‴ = 6(p₃ − 3p₂ + 3p₁ − p₀)/Δu³ is constant; hₖ is the mean length of the two
/// pieces meeting at the knot.
fn jump_energy(curve: &BSpline) -> f64 {
    let thirds: Vec<(f64, kurbo::Vec2)> = curve
        .to_beziers()
        .iter()
        .map(|pb| {
            let du = pb.u1 - pb.u0;
            let b = &pb.bez;
            let d3 = (b.p3.to_vec2() - b.p2.to_vec2() * 3.0 + b.p1.to_vec2() * 3.0
                - b.p0.to_vec2())
                * (6.0 / (du * du * du));
            (du, d3)
        })
        .collect();
    thirds
        .windows(2)
        .map(|w| 0.5 * (w[0].0 + w[1].0) * (w[1].1 - w[0].1).hypot2())
        .sum()
}

/// Replaces the local (Newton) foot points of a fit by true distances to the curve, each on its
/// sample's own pass ([`Pieces::distance_on_pass`]): where the stroke comes back near itself (a
/// circle drawn past its start), its first sample's foot stays at the start, not at the end that
/// passes as near. The search runs on local distances, which are upper bounds: a count that
/// passes with them passes.
fn exact(fit: BSplineFit, points: &[Point], tolerance: f64) -> BSplineFit {
    let pieces = Pieces::new(fit.curve.to_beziers());
    let feet: Vec<Foot> = points
        .iter()
        .zip(fit.params.iter().zip(&fit.distances))
        .map(|(q, (&u, &distance))| pieces.distance_on_pass(*q, Foot { u, distance }))
        .collect();
    let (attempts, fairing) = (fit.attempts, fit.fairing);
    let mut out = summarise(fit.curve, &feet, tolerance);
    out.attempts = attempts;
    out.fairing = fairing;
    out
}

/// The weighted least-squares B-spline with the given knots through samples at given
/// parameters (no search, no parameter correction): the building block of [`fit_bspline`],
/// exposed for callers that know their parameterisation.
pub fn least_squares(
    points: &[Point],
    params: &[f64],
    weights: &[f64],
    knots: Vec<f64>,
) -> Result<BSpline, FitError> {
    Design::new(points, params, weights, knots, false, (None, None))?.solve(0.0)
}

/// The rows of a (penalised) least-squares system with fixed knots and sample parameters, in
/// the order they are rotated in: the fairing search solves the same design at several
/// weights, and the basis values and third derivatives need computing only once.
struct Design {
    knots: Vec<f64>,
    rows: Vec<Row>,
    ends: (Option<Point>, Option<Point>),
    /// The mean sample weight (the scale of the rank fix, see [`BandedLsq::solve`]).
    mean_weight: f64,
}

impl Design {
    /// The sample rows, with each interior knot's jump row (when `jumps`) just before the first
    /// sample of its span, keeping the rows in column order (see
    /// `BandedLsq::add_knot_jump_penalty`).
    fn new(
        points: &[Point],
        params: &[f64],
        weights: &[f64],
        knots: Vec<f64>,
        jumps: bool,
        ends: (Option<Point>, Option<Point>),
    ) -> Result<Design, FitError> {
        let n_ctrl = knots.len().saturating_sub(DEGREE + 1);
        if n_ctrl < DEGREE + 1 || points.len() != params.len() || points.len() != weights.len() {
            return Err(FitError::TooFewPoints(points.len()));
        }
        let mut rows = Vec::with_capacity(points.len() + if jumps { n_ctrl } else { 0 });
        let probe = SpanFinder::new(&knots);
        let mut next_knot = DEGREE + 1;
        for ((q, &u), &w) in points.iter().zip(params).zip(weights) {
            let span = probe.find(u);
            if jumps {
                while next_knot <= span {
                    rows.extend(Row::jump(&knots, next_knot));
                    next_knot += 1;
                }
            }
            rows.push(Row::sample(&knots, span, u, *q, w));
        }
        if jumps {
            while next_knot < n_ctrl {
                rows.extend(Row::jump(&knots, next_knot));
                next_knot += 1;
            }
        }
        let mean_weight = weights.iter().sum::<f64>() / weights.len().max(1) as f64;
        Ok(Design {
            knots,
            rows,
            ends,
            mean_weight,
        })
    }

    /// The curve of least weighted squares plus the fairness term
    /// `jump_weight · Σₖ hₖ‖C‴(tₖ⁺) − C‴(tₖ⁻)‖²` (the jump rows are there only when the design
    /// was made `jumps`).
    fn solve(&self, jump_weight: f64) -> Result<BSpline, FitError> {
        let n_ctrl = self.knots.len().saturating_sub(DEGREE + 1);
        let mut lsq = BandedLsq::new(&self.knots);
        // A clamped spline starts at its first control point and ends at its last.
        if let Some(p) = self.ends.0 {
            lsq.fix(0, p);
        }
        if let Some(p) = self.ends.1 {
            lsq.fix(n_ctrl - 1, p);
        }
        for row in &self.rows {
            lsq.add_row(row, jump_weight);
        }
        let solution = lsq.solve(self.mean_weight)?;
        BSpline::new(self.knots.clone(), solution.control_points)
            .map_err(|_| FitError::Lsq(LsqError::Underdetermined(0)))
    }
}

/// Least squares with a fixed number of segments, with parameter correction; distances
/// exact on the final curve.
///
/// With `until_within`, the corrections stop as soon as every sample is within the tolerance:
/// the segment-count search only asks whether a count passes, and a further correction only
/// lowers the distances.
fn fit_segments(
    points: &[Point],
    weights: &[f64],
    chord: &[f64],
    segments: usize,
    options: &FitOptions,
    until_within: bool,
) -> Result<BSplineFit, FitError> {
    let knots = averaged_knots(chord, segments);
    let mut params = chord.to_vec();
    let mut feet: Vec<Foot> = Vec::with_capacity(points.len());
    let mut curve;
    let mut pass = 0;
    loop {
        curve = Design::new(
            points,
            &params,
            weights,
            knots.clone(),
            false,
            (options.start, options.end),
        )?
        .solve(0.0)?;
        let pieces = Pieces::new(curve.to_beziers());
        feet.clear();
        feet.extend(
            points
                .iter()
                .zip(&params)
                .map(|(q, &u)| pieces.project_local(*q, u)),
        );
        if pass == options.parameter_corrections
            || (until_within && feet.iter().all(|f| f.distance <= options.tolerance))
        {
            break;
        }
        // Far from the tolerance, corrections will not get there: this count fails (unless it
        // is the most segments allowed, whose fit is the answer however far off it is).
        if segments < options.max_segments
            && feet
                .iter()
                .any(|f| f.distance > HOPELESS_FACTOR * options.tolerance)
        {
            break;
        }
        for (u, f) in params.iter_mut().zip(&feet) {
            *u = f.u;
        }
        pass += 1;
    }
    Ok(summarise(curve, &feet, options.tolerance))
}

fn summarise(curve: BSpline, feet: &[Foot], tolerance: f64) -> BSplineFit {
    let distances: Vec<f64> = feet.iter().map(|f| f.distance).collect();
    let max_deviation = distances.iter().copied().fold(0.0, f64::max);
    let rms_deviation =
        (distances.iter().map(|d| d * d).sum::<f64>() / distances.len().max(1) as f64).sqrt();
    BSplineFit {
        curve,
        params: feet.iter().map(|f| f.u).collect(),
        distances,
        max_deviation,
        rms_deviation,
        within_tolerance: max_deviation <= tolerance,
        attempts: 1,
        fairing: 0.0,
    }
}

/// Finds knot spans for parameters (the same rule as [`BSpline::find_span`] without a curve).
struct SpanFinder<'a> {
    knots: &'a [f64],
    last: usize,
}

impl<'a> SpanFinder<'a> {
    fn new(knots: &'a [f64]) -> Self {
        let n = knots.len() - DEGREE - 1;
        let mut last = n - 1;
        while last > DEGREE && knots[last] >= knots[last + 1] {
            last -= 1;
        }
        SpanFinder { knots, last }
    }

    fn find(&self, u: f64) -> usize {
        let n = self.knots.len() - DEGREE - 1;
        if u >= self.knots[n] {
            return self.last;
        }
        let idx = self.knots[DEGREE..n].partition_point(|&k| k <= u);
        (DEGREE + idx.saturating_sub(1)).min(self.last)
    }
}

/// The clamped knot vector for `segments` spans placed by averaging the parameters `u`.
///
/// Interior knot `j` (1 ≤ j < segments) is the mean of the parameter at the three (fractional)
/// sample indices `cⱼ − 1, cⱼ, cⱼ + 1` with `cⱼ = 1 + j·(m − 3)/segments` (linear interpolation
/// between samples). At the largest count, `segments = m − 3`, this is de Boor's averaging for
/// cubic interpolation, `t = (u_j + u_{j+1} + u_{j+2})/3`, which keeps the system well
/// conditioned; for fewer segments it spreads the knots evenly over the samples, so every span
/// holds data (Schoenberg–Whitney) and knots gather where the pen slowed down, which on
/// hand-drawn strokes is where the curvature is high. Needs `m ≥ segments + 3`.
fn averaged_knots(u: &[f64], segments: usize) -> Vec<f64> {
    let m = u.len();
    let at = |x: f64| -> f64 {
        let x = x.clamp(0.0, (m - 1) as f64);
        let i = (x.floor() as usize).min(m - 2);
        let a = x - i as f64;
        (1.0 - a) * u[i] + a * u[i + 1]
    };
    let step = (m - 3) as f64 / segments as f64;
    let mut knots = vec![0.0; DEGREE + 1];
    for j in 1..segments {
        let c = 1.0 + j as f64 * step;
        knots.push((at(c - 1.0) + at(c) + at(c + 1.0)) / 3.0);
    }
    knots.extend([1.0; DEGREE + 1]);
    knots
}

/// Normalised cumulative chord length, or `None` when the points have no extent.
fn chord_params(points: &[Point]) -> Option<Vec<f64>> {
    let mut u = crate::geom::cumulative_lengths(points);
    let total = u.last().copied().unwrap_or(0.0);
    if !(total > 0.0 && total.is_finite()) {
        return None;
    }
    for x in &mut u {
        *x /= total;
    }
    if let Some(last) = u.last_mut() {
        *last = 1.0;
    }
    Some(u)
}

/// Least-squares weights (see [`Weighting`]), normalised to mean 1.
fn weights(points: &[Point], weighting: Weighting) -> Vec<f64> {
    let m = points.len();
    if weighting == Weighting::Uniform || m < 2 {
        return vec![1.0; m];
    }
    let gaps: Vec<f64> = points.windows(2).map(|w| w[0].distance(w[1])).collect();
    let mut w: Vec<f64> = (0..m)
        .map(|i| {
            let before = if i > 0 { gaps[i - 1] } else { 0.0 };
            let after = gaps.get(i).copied().unwrap_or(0.0);
            0.5 * (before + after)
        })
        .collect();
    let mean = w.iter().sum::<f64>() / m as f64;
    // A floor keeps every row in the system (a zero weight would drop the sample's row), far
    // below any weight that could matter.
    let floor = MIN_RELATIVE_WEIGHT * mean;
    for x in &mut w {
        *x = (*x / mean).max(floor / mean);
    }
    w
}

/// Smallest weight relative to the mean (see [`weights`]).
const MIN_RELATIVE_WEIGHT: f64 = 1e-6;

/// The least-squares line through a handful of points, as a one-segment cubic.
fn fit_line(points: &[Point], options: &FitOptions) -> BSplineFit {
    let tolerance = options.tolerance;
    let n = points.len() as f64;
    let c = points.iter().fold(Point::ZERO, |a, p| a + p.to_vec2() / n);
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for p in points {
        let d = *p - c;
        sxx += d.x * d.x;
        sxy += d.x * d.y;
        syy += d.y * d.y;
    }
    // Principal axis of the scatter matrix.
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let dir = kurbo::Vec2::new(angle.cos(), angle.sin());
    let ts: Vec<f64> = points.iter().map(|p| (*p - c).dot(dir)).collect();
    let (t0, t1) = (ts[0], ts[ts.len() - 1]);
    let a = options.start.unwrap_or(c + dir * t0);
    let b = options.end.unwrap_or(c + dir * t1);
    let control_points = vec![a, a.lerp(b, 1.0 / 3.0), a.lerp(b, 2.0 / 3.0), b];
    let curve = match BSpline::new(BSpline::uniform_knots(1), control_points) {
        Ok(c) => c,
        // Unreachable for finite input (validated at the boundary); keep a clean fallback.
        Err(_) => return fit_line(&points[..1.min(points.len())], options),
    };
    let pieces = Pieces::new(curve.to_beziers());
    let chord = b - a;
    let feet: Vec<Foot> = points
        .iter()
        .map(|q| {
            let guess = if chord.hypot2() > 0.0 {
                (*q - a).dot(chord) / chord.hypot2()
            } else {
                0.0
            };
            let local = pieces.project_local(*q, guess.clamp(0.0, 1.0));
            pieces.distance(*q, local)
        })
        .collect();
    summarise(curve, &feet, tolerance)
}
