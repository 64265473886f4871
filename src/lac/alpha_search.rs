//! The α that fits a span best: the Yoshida–Saito segment through the span's G1 end data whose
//! samples lie closest to it.
//!
//! The objective is the root mean square foot-point distance of the span's samples to the
//! segment ([`mod@super::deviation`]); α values whose segment cannot join the data (outside the
//! drawable region) score +∞. A grid over the allowed range ([`GRID_STEP`]) finds the best cell
//! (the objective is not unimodal over the whole range: the drawable region can end inside it),
//! then Brent's method ([`super::minimize::brent`]) minimises continuously on the two cells around
//! it to a tolerance ([`ALPHA_TOLERANCE`], or [`SEED_ALPHA_TOLERANCE`] when a refinement
//! follows). This replaces the seed paper's choice among a few fixed α values.
//!
//! With a starting guess (the slope of the span's logarithmic curvature graph, or the α of the
//! segment a span was cut from or merged out of: [`fit_span`]'s `guess`) the grid is replaced by
//! Gauss–Newton steps on α: the derivative of every sample distance in α comes from one pass
//! along the segment (`sensitivity`), so a step costs one evaluation and the search ends where
//! the step falls below the tolerance or the model sees the objective flat (`gauss_newton`).
//! Where the derivatives are not available (arcs, κ = 0 ends) or no step helps, a walk takes over:
//! cells of [`GRID_STEP`] are stepped downhill from the guess until the objective rises, and
//! Brent takes the two cells around the lowest point. A guess that cannot join the data steps
//! towards α = 0.5 until one can (`FEASIBLE_TOWARDS`) and the search starts there; a walk that
//! finds nothing finite falls back to the grid.
//!
//! Over the fixture strokes up to 600 samples at three tolerances, Gauss–Newton instead of the
//! walk and Brent: 6.4 evaluations per search against 7.6, 6 % fewer instructions in all
//! (3.82e9 against 4.06e9) and 11 % fewer on the median stroke (9.97 M against 11.19 M), for as
//! many segments (2 201 against 2 221) and the same rms distance (0.218 of the tolerance against
//! 0.216).

use serde::{Deserialize, Serialize};

use super::deviation::{Deviation, deviation, marched, rough_deviation};
use super::error::LacError;
use super::minimize::{brent, brent_from};
use super::segment::LacSegment;
use super::sensitivity::sensitivities;
use super::yoshida_saito::{fit_g1, fit_g1_near};
use crate::geom::{Point, Vec2};

/// Grid step of the coarse α scan. 0.5 resolves the cells in which the objective is unimodal on
/// every planted and fixture span seen; finer costs evaluations for nothing Brent won't find.
pub const GRID_STEP: f64 = 0.5;

/// The search ranks α values by exact foot-point distances, marched from sample to sample
/// along the candidate; where the march does not settle, by distances to a polyline traced at
/// this multiple of the caller's chord error (coarser, hence faster); the chosen segment's
/// distances are then computed exactly.
/// With the chain's chord error of 1e-3 of the tolerance, 30 traces at 3 % of it: the polyline's
/// bias is nearly the same for neighbouring α, so the ranking holds, and over the fixture strokes
/// up to 600 samples it takes 5 % fewer instructions than 10 for as many segments (1 147 against
/// 1 161; 100 saves 2 % more).
const SEARCH_CHORD_FACTOR: f64 = 30.0;

/// Absolute tolerance on α of the continuous search when its answer is final (no refinement
/// follows): α's accuracy, below the 0.05 the planted-α tests ask of the whole fit.
pub const ALPHA_TOLERANCE: f64 = 1e-2;

/// Absolute tolerance on α of the search when a chain refinement follows ([`crate::chain`]): the
/// search then only seeds the Levenberg–Marquardt refinement, which moves α anyway (by 0.1–0.2 on
/// noisy ends) and optimises it jointly with the joints. Brent's last steps polish what the
/// refinement redoes: over the fixture strokes up to 600 samples, 0.3 takes 15 % fewer
/// instructions than 0.05 for as many segments (1 139), and the planted-α tests hold.
pub const SEED_ALPHA_TOLERANCE: f64 = 0.3;

/// Where a search whose guess cannot join the data looks for an α that can: the α values that
/// can join given G1 data form an interval which, for the end-angle ratios pen data has, holds
/// [0, 1] (the limit ratio of a nearly straight span rises with α up to 0 and falls beyond 1;
/// see `yoshida_saito::flat_ratio_guess`), so stepping from the guess towards its middle meets
/// the interval's nearer edge, where the best α of such data usually lies. Over the fixture
/// strokes up to 600 samples 38 % of the guesses cannot join their data; each used to cost the
/// whole grid.
const FEASIBLE_TOWARDS: f64 = 0.5;

/// Where the guess cannot join the data, the first α on the way to α = 0.5
/// (`FEASIBLE_TOWARDS`) that can stands in for it, and the limits
/// [`SpanFitOptions::abandon_above`] and [`SpanFitOptions::unreachable_above`] apply there
/// multiplied by this: that α sits at the edge of the drawable interval, farther from the
/// search's answer than a guess usually is. Over the fixture strokes up to 600 samples at three
/// tolerances (108 fits), with the merges' limits: 6 % fewer instructions on the median stroke,
/// 2 222 segments against 2 221 and the same rms distance (at the guess's own limits: 2 232
/// segments; merged segments missing by up to 27 tolerances were searched to the end before).
pub const WALKED_ABANDON: f64 = 2.0;

/// Evaluation budget of the Brent stage (it converges in 10–20 on smooth objectives).
const MAX_BRENT_EVALUATIONS: usize = 40;

/// The α values a segment may take.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AlphaChoice {
    /// Search the closed interval.
    Range {
        /// Smallest α.
        min: f64,
        /// Largest α.
        max: f64,
    },
    /// Every segment has this α (a designer who wants only clothoids asks for −1).
    Fixed(f64),
}

impl Default for AlphaChoice {
    /// The range [−3, 3]: from beyond the clothoid (−1) past the circle involute (2), covering
    /// the aesthetic curves designers use.
    fn default() -> Self {
        AlphaChoice::Range {
            min: -3.0,
            max: 3.0,
        }
    }
}

/// Parses `MIN:MAX` (as `kansei fit --alpha-range` and the service's `alpha_range` take it) into a
/// finite, non-empty interval.
pub fn parse_alpha_range(text: &str) -> Result<(f64, f64), String> {
    let (a, b) = text
        .split_once(':')
        .ok_or_else(|| format!("expected MIN:MAX, got {text:?}"))?;
    let parse = |x: &str| x.trim().parse::<f64>().map_err(|e| format!("{x:?}: {e}"));
    let (min, max) = (parse(a)?, parse(b)?);
    if min.is_finite() && max.is_finite() && min <= max {
        Ok((min, max))
    } else {
        Err(format!("{text:?} is not a finite interval with MIN <= MAX"))
    }
}

impl AlphaChoice {
    /// The range's middle (the fixed α itself): the value to give a segment whose α does not
    /// matter (an arc or a line, which every α reproduces) or is not known yet.
    pub fn middle(&self) -> f64 {
        match *self {
            AlphaChoice::Range { min, max } => 0.5 * (min + max),
            AlphaChoice::Fixed(alpha) => alpha,
        }
    }

    /// Checks that the range is finite and non-empty.
    pub fn validate(&self) -> Result<(), LacError> {
        let (min, max) = match *self {
            AlphaChoice::Range { min, max } => (min, max),
            AlphaChoice::Fixed(a) => (a, a),
        };
        if min.is_finite() && max.is_finite() && min <= max {
            Ok(())
        } else {
            Err(LacError::InvalidAlphaRange { min, max })
        }
    }
}

/// What the α search did, for the output and the app's α-search plot.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AlphaSearch {
    /// The range searched (both ends equal for a fixed α).
    pub range: [f64; 2],
    /// The α chosen (`None` when the data make an arc or a line, for which α is meaningless).
    pub alpha: Option<f64>,
    /// The objective (rms sample distance) at the chosen α.
    pub rms: f64,
    /// Objective evaluations (segment constructions).
    pub evaluations: usize,
    /// The objective at the coarse points visited (the grid, or the walk from a guess), as
    /// `[α, rms]` in increasing α (infeasible α left out).
    pub grid: Vec<[f64; 2]>,
}

/// A span's fitted segment.
#[derive(Clone, Debug)]
pub struct SpanFit {
    /// The segment.
    pub segment: LacSegment,
    /// The samples' distances to it.
    pub deviation: Deviation,
    /// The search.
    pub search: AlphaSearch,
}

/// Options of [`fit_span`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpanFitOptions {
    /// The α values allowed. Default: [`AlphaChoice::default`], the range [−3, 3].
    pub choice: AlphaChoice,
    /// Distances are exact to this (a length in the samples' units). No default: it follows the
    /// tolerance (see [`SpanFitOptions::new`]).
    pub chord_error: f64,
    /// Segments whose curvature anywhere exceeds this in magnitude count as infeasible. Default
    /// +∞ (no limit).
    pub max_curvature: f64,
    /// A starting guess of α (clamped to the range; ignored when not finite): the search walks
    /// from it instead of scanning the whole grid. Default `None`.
    pub guess: Option<f64>,
    /// Brent stops within this of the minimum. Default [`ALPHA_TOLERANCE`] (a final answer);
    /// [`SEED_ALPHA_TOLERANCE`] when a refinement follows.
    pub alpha_tolerance: f64,
    /// Give up ([`LacError::SearchAbandoned`]) when the segment at the guess has a sample
    /// farther than this from it: for a caller that only wants a segment within some distance
    /// of the samples (a merge) and knows that a guess missing by far more will not get there.
    /// Where the guess cannot join the data, the first α that can stands in for it, with
    /// [`WALKED_ABANDON`] times the limit. Default +∞ (never give up).
    pub abandon_above: f64,
    /// Give up ([`LacError::SearchAbandoned`]) too when, at the guess, the linear model of the
    /// sample distances in α predicts that no α within [`REACH`] of it brings every sample within
    /// this: the largest distance the search's answer can have is at least that minimax (the
    /// search minimises the rms distance, not the largest). For a caller that only keeps answers
    /// within some distance (a merge); as for `abandon_above`, [`WALKED_ABANDON`] times it at a
    /// stand-in for the guess. Default +∞ (never give up).
    pub unreachable_above: f64,
}

impl SpanFitOptions {
    /// Options with this chord error and every other field at its default.
    pub fn new(chord_error: f64) -> Self {
        SpanFitOptions {
            choice: AlphaChoice::default(),
            chord_error,
            max_curvature: f64::INFINITY,
            guess: None,
            alpha_tolerance: ALPHA_TOLERANCE,
            abandon_above: f64::INFINITY,
            unreachable_above: f64::INFINITY,
        }
    }
}

/// Fits the best LAC segment (see the module doc) through `a` (tangent `ta`) and `b` (tangent
/// `tb`) to `samples`, ordered from `a` to `b`, as set by `options`.
pub fn fit_span(
    a: Point,
    ta: Vec2,
    b: Point,
    tb: Vec2,
    samples: &[Point],
    options: &SpanFitOptions,
) -> Result<SpanFit, LacError> {
    let SpanFitOptions {
        choice,
        chord_error,
        max_curvature,
        guess,
        alpha_tolerance,
        abandon_above,
        unreachable_above,
    } = *options;
    choice.validate()?;
    let (min, max) = match choice {
        AlphaChoice::Range { min, max } => (min, max),
        AlphaChoice::Fixed(alpha) => (alpha, alpha),
    };
    let mut evaluations = 0usize;
    let search_chord = SEARCH_CHORD_FACTOR * chord_error;
    // The last segment built starts the next construction: successive α are close.
    let mut last: Option<LacSegment> = None;
    // The lowest-scoring segment so far, with its α and, when the march gave them, its exact
    // distances: Brent's answer is always one it evaluated, so the chosen segment is neither
    // built nor measured a second time.
    let mut best_seen: Option<(f64, LacSegment, f64, Option<Deviation>)> = None;
    let mut evaluate = |alpha: f64| -> Option<(LacSegment, Deviation)> {
        evaluations += 1;
        let built = fit_g1_near(a, ta, b, tb, alpha, last.as_ref()).ok()?;
        last = Some(built);
        let segment = Some(built).filter(|s| within(s, max_curvature))?;
        let (d, exact) = match marched(&segment, samples) {
            Some(d) => (d, true),
            None => (rough_deviation(&segment, samples, search_chord), false),
        };
        if best_seen.as_ref().is_none_or(|(_, _, rms, _)| d.rms < *rms) {
            best_seen = Some((alpha, segment, d.rms, exact.then(|| d.clone())));
        }
        Some((segment, d))
    };

    let mut guess = guess.filter(|g| g.is_finite()).map(|g| g.clamp(min, max));
    let mut first = evaluate(guess.unwrap_or(0.5 * (min + max)));
    // Where the guess cannot join the data, the first α that can on the way from it towards the
    // middle of [0, 1] (see [`FEASIBLE_TOWARDS`]) stands in for it (and the search starts
    // there).
    let mut walked = false;
    if let (Some(g), None) = (guess, &first)
        && min < max
    {
        let towards = FEASIBLE_TOWARDS.clamp(min, max);
        let mut alpha = g;
        while alpha != towards {
            alpha = if alpha < towards {
                (alpha + GRID_STEP).min(towards)
            } else {
                (alpha - GRID_STEP).max(towards)
            };
            if let Some(found) = evaluate(alpha) {
                (guess, first) = (Some(alpha), Some(found));
                walked = true;
                break;
            }
        }
    }
    // A fixed α, or data that make an arc or a line whatever α is.
    if let Some((segment, _)) = &first
        && (segment.alpha().is_none() || min == max)
    {
        let (segment, _) = first.expect("matched Some just above");
        let deviation = deviation(&segment, samples, chord_error);
        let search = AlphaSearch {
            range: [min, max],
            alpha: segment.alpha(),
            rms: deviation.rms,
            evaluations,
            grid: Vec::new(),
        };
        return Ok(SpanFit {
            segment,
            deviation,
            search,
        });
    }
    if min == max {
        return Err(LacError::NoAlphaInRange { min, max });
    }
    let stand_in = if walked { WALKED_ABANDON } else { 1.0 };
    if let (Some(_), Some((_, d))) = (guess, &first)
        && d.max > stand_in * abandon_above
    {
        return Err(LacError::SearchAbandoned {
            max: d.max,
            limit: stand_in * abandon_above,
        });
    }
    // The distances' linear model in α at the guess, when the reach limit asks for it; the first
    // Gauss–Newton step takes it over.
    let mut guess_model = None;
    if let (Some(g), Some((segment, d))) = (guess, &first)
        && unreachable_above.is_finite()
    {
        guess_model = linear_model(segment, d);
        if let Some(best) = guess_model
            .as_deref()
            .and_then(|m| predicted_minimax(m, (min - g).max(-REACH), (max - g).min(REACH)))
            && best > stand_in * unreachable_above
        {
            return Err(LacError::SearchAbandoned {
                max: best,
                limit: stand_in * unreachable_above,
            });
        }
    }

    let mut grid = Vec::new();
    // Where the search starts: the guess (or the feasible α standing in for it).
    let start = guess.zip(first);
    // Gauss–Newton steps from there (see [`gauss_newton`]); the walk and Brent where they
    // cannot go on, the grid without a start.
    let newton = start.as_ref().and_then(|(alpha, (segment, d))| {
        gauss_newton(
            (*alpha, *segment, d.clone()),
            guess_model,
            (min, max),
            alpha_tolerance,
            &mut grid,
            &mut evaluate,
        )
    });
    let alpha = match newton {
        Some(alpha) => alpha,
        None => walk_and_brent(
            start.map(|(g, (_, d))| (g, d.rms)),
            (min, max),
            alpha_tolerance,
            &mut grid,
            &mut evaluate,
        )?,
    };
    let (segment, known) = match best_seen {
        Some((seen, segment, _, known)) if seen == alpha => (segment, known),
        _ => {
            evaluations += 1;
            match fit_g1(a, ta, b, tb, alpha) {
                Ok(segment) if within(&segment, max_curvature) => (segment, None),
                Ok(_) => return Err(LacError::NoAlphaInRange { min, max }),
                Err(e) => return Err(e),
            }
        }
    };
    let deviation = known.unwrap_or_else(|| deviation(&segment, samples, chord_error));
    grid.sort_by(|p, q| p[0].total_cmp(&q[0]));
    grid.dedup_by(|p, q| p[0] == q[0]);
    let search = AlphaSearch {
        range: [min, max],
        alpha: segment.alpha(),
        rms: deviation.rms,
        evaluations,
        grid,
    };
    Ok(SpanFit {
        segment,
        deviation,
        search,
    })
}

/// The walk from `start` (α and its objective) and Brent on the bracket it finds, or, without a
/// start or where the walk finds no direction, the grid over `range` and Brent on the cells
/// around its best point: the search where Gauss–Newton cannot go on (see the module
/// documentation). Brent starts from the points the walk or the grid evaluated (their parabola
/// gives the first step). The α found, or [`LacError::NoAlphaInRange`].
fn walk_and_brent(
    start: Option<(f64, f64)>,
    (min, max): (f64, f64),
    alpha_tolerance: f64,
    grid: &mut Vec<[f64; 2]>,
    evaluate: &mut impl FnMut(f64) -> Option<(LacSegment, Deviation)>,
) -> Result<f64, LacError> {
    // The bracket [lo, hi] around the best point found, by a walk from the start or the grid.
    let walked = match start {
        Some((g, rms)) => walk(g, rms, min, max, grid, |alpha| {
            evaluate(alpha).map(|(_, d)| d.rms)
        }),
        None => None,
    };
    let (lo, hi, best_alpha) = match walked {
        Some(bracket) => bracket,
        None => {
            grid.clear();
            let cells = (((max - min) / GRID_STEP).ceil() as usize).max(1);
            let grid_alpha = |i: usize| min + (max - min) * i as f64 / cells as f64;
            let mut best: Option<(usize, f64)> = None;
            for i in 0..=cells {
                let alpha = grid_alpha(i);
                if let Some((_, d)) = evaluate(alpha) {
                    grid.push([alpha, d.rms]);
                    if best.is_none_or(|(_, r)| d.rms < r) {
                        best = Some((i, d.rms));
                    }
                }
            }
            let Some((k, _)) = best else {
                return Err(LacError::NoAlphaInRange { min, max });
            };
            (
                grid_alpha(k.saturating_sub(1)),
                grid_alpha((k + 1).min(cells)),
                grid_alpha(k),
            )
        }
    };

    // Brent on the cells around the best point, started from the points the walk or the grid
    // already evaluated there (their parabola gives the first step).
    let value_at = |alpha: f64| grid.iter().find(|p| p[0] == alpha).map(|p| (alpha, p[1]));
    let best = value_at(best_alpha);
    let known: Vec<(f64, f64)> = [lo, hi].into_iter().filter_map(value_at).collect();
    let objective = |alpha: f64| evaluate(alpha).map_or(f64::INFINITY, |(_, d)| d.rms);
    let minimum = match best {
        Some(best) => brent_from(
            objective,
            (lo, hi),
            best,
            &known,
            alpha_tolerance,
            MAX_BRENT_EVALUATIONS,
        ),
        None => brent(objective, lo, hi, alpha_tolerance, MAX_BRENT_EVALUATIONS),
    };
    Ok(if minimum.value.is_finite() {
        minimum.x
    } else {
        best_alpha
    })
}

/// Walks downhill from `start` (objective `start_value`) in steps of [`GRID_STEP`] within
/// `[min, max]` until the objective rises (or the range ends), recording each point in `grid`;
/// returns the bracket (the cells on both sides of the lowest point) and the lowest point.
/// `None` when a neighbour of the start is infeasible on both sides (no direction to walk in
/// with confidence: the grid decides).
fn walk(
    start: f64,
    start_value: f64,
    min: f64,
    max: f64,
    grid: &mut Vec<[f64; 2]>,
    mut objective: impl FnMut(f64) -> Option<f64>,
) -> Option<(f64, f64, f64)> {
    grid.push([start, start_value]);
    let mut probe = |alpha: f64, grid: &mut Vec<[f64; 2]>| -> f64 {
        match objective(alpha) {
            Some(v) => {
                grid.push([alpha, v]);
                v
            }
            None => f64::INFINITY,
        }
    };
    let left = (start - GRID_STEP).max(min);
    let right = (start + GRID_STEP).min(max);
    let f_left = if left < start {
        probe(left, grid)
    } else {
        f64::INFINITY
    };
    let f_right = if right > start {
        probe(right, grid)
    } else {
        f64::INFINITY
    };
    if !f_left.is_finite() && !f_right.is_finite() && left < start && start < right {
        return None;
    }
    if start_value <= f_left && start_value <= f_right {
        return Some((left, right, start));
    }
    // Step towards the lower neighbour while the objective keeps falling.
    let direction = if f_left < f_right { -1.0 } else { 1.0 };
    let (mut previous, mut best, mut best_value) = if direction < 0.0 {
        (start, left, f_left)
    } else {
        (start, right, f_right)
    };
    loop {
        let next = (best + direction * GRID_STEP).clamp(min, max);
        if next == best {
            // The range ends at the best point: bracket it with its inner cell.
            return Some((previous.min(best), previous.max(best), best));
        }
        let value = probe(next, grid);
        if value >= best_value {
            return Some((previous.min(next), previous.max(next), best));
        }
        previous = best;
        best = next;
        best_value = value;
    }
}

/// Whether the segment's curvature stays within `max_curvature` (curvature is monotonic, so the
/// ends bound it).
pub fn within(segment: &LacSegment, max_curvature: f64) -> bool {
    segment.kappa0().abs().max(segment.kappa1().abs()) <= max_curvature
}

/// Most Gauss–Newton steps of [`gauss_newton`]: from a guess within a cell of the minimum it
/// converges in two or three.
const MAX_NEWTON_STEPS: usize = 8;

/// Halvings of a Gauss–Newton step that does not lower the objective before the search hands
/// over to the walk.
const MAX_STEP_HALVINGS: usize = 3;

/// A Gauss–Newton step whose model predicts a smaller relative decrease of the sum of squared
/// distances than this ends the search: 1e-3 moves the rms distance by 0.05 %, and an objective
/// that flat in α (a nearly straight span, or data that barely see α) would otherwise be walked
/// along a whole cell per evaluation for nothing.
const FLAT_GAIN: f64 = 1e-3;

/// Gauss–Newton on α from `start` (α, segment, distances), within `range`: each step is
/// −Σ rᵢ·r′ᵢ / Σ r′ᵢ² with rᵢ the signed sample distances and r′ᵢ their derivatives in α at
/// fixed end data (one pass along the segment, [`sensitivities`]), at most a trust length long
/// (a grid cell at first, doubled after a step that helped, halved after one that did not).
/// Stops with the current α once a step is below `tolerance` or the model predicts less than
/// [`FLAT_GAIN`]; `None` (the walk and Brent take over from the evaluations made) where the
/// derivatives are not available or no step helps. From a guess within a cell of the minimum:
/// two or three evaluations instead of the walk's three or four and Brent's. `model`, when
/// given, is `start`'s [`linear_model`] already computed (the reach test's).
fn gauss_newton(
    start: (f64, LacSegment, Deviation),
    mut model: Option<Vec<(f64, f64)>>,
    (min, max): (f64, f64),
    tolerance: f64,
    grid: &mut Vec<[f64; 2]>,
    evaluate: &mut impl FnMut(f64) -> Option<(LacSegment, Deviation)>,
) -> Option<f64> {
    let (mut alpha, mut segment, mut d) = start;
    grid.push([alpha, d.rms]);
    let mut trust = GRID_STEP;
    for _ in 0..MAX_NEWTON_STEPS {
        let model = match model.take() {
            Some(known) => known,
            None => linear_model(&segment, &d)?,
        };
        let (gradient, curvature) = model.iter().fold((0.0, 0.0), |(g, c), (r, slope)| {
            (g + r * slope, c + slope * slope)
        });
        if !(curvature > 0.0) {
            return None;
        }
        let step = (-gradient / curvature).clamp(-trust, trust);
        // The model's decrease of Σr² over the step, against Σr².
        let gain = -(2.0 * gradient * step + curvature * step * step);
        let squares = d.rms * d.rms * d.distances.len() as f64;
        if gain <= FLAT_GAIN * squares {
            return Some(alpha);
        }
        let mut trial = (alpha + step).clamp(min, max);
        let mut improved = false;
        for _ in 0..=MAX_STEP_HALVINGS {
            if (trial - alpha).abs() <= tolerance {
                return Some(alpha);
            }
            if let Some((s, e)) = evaluate(trial) {
                grid.push([trial, e.rms]);
                if e.rms < d.rms {
                    let full = (trial - alpha).abs() >= trust;
                    (alpha, segment, d) = (trial, s, e);
                    if full {
                        trust *= 2.0;
                    }
                    improved = true;
                    break;
                }
            }
            trial = alpha + 0.5 * (trial - alpha);
            trust *= 0.5;
        }
        if !improved {
            return None;
        }
    }
    Some(alpha)
}

/// Each sample's signed distance r to `segment` (distances `d`) and its derivative r′ in α at
/// fixed end data; `None` where the derivatives are not available.
fn linear_model(segment: &LacSegment, d: &Deviation) -> Option<Vec<(f64, f64)>> {
    let derivatives = sensitivities(segment, &d.feet)?;
    Some(
        d.feet
            .iter()
            .zip(&d.distances)
            .zip(&d.sides)
            .zip(&derivatives)
            .map(|(((&foot, &distance), &side), derivative)| {
                let theta = segment.theta(foot);
                // r = (q − P)·N at an interior foot, so r′ = −P′·N (zero at an end: P′ = 0).
                let slope = -derivative.alpha.dot(Vec2::new(-theta.sin(), theta.cos()));
                (side * distance, slope)
            })
            .collect(),
    )
}

/// How far from the guess (in α) [`SpanFitOptions::unreachable_above`] looks: two cells, as far
/// as the linear model of the distances is worth trusting.
pub const REACH: f64 = 2.0 * GRID_STEP;

/// Golden-section steps of [`predicted_minimax`]: 0.618⁴⁰ of the interval, far below anything
/// the linear model resolves.
const MINIMAX_STEPS: usize = 40;

/// min over δ ∈ [lo, hi] of maxᵢ |rᵢ + r′ᵢ·δ| under the linear model (rᵢ, r′ᵢ) of the distances
/// in α ([`linear_model`]): a convex function of δ, minimised by golden section. `None` when the
/// interval is empty.
fn predicted_minimax(model: &[(f64, f64)], lo: f64, hi: f64) -> Option<f64> {
    if !(lo <= hi) {
        return None;
    }
    let worst = |delta: f64| {
        model
            .iter()
            .map(|(r, slope)| (r + slope * delta).abs())
            .fold(0.0, f64::max)
    };
    let golden = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (lo, hi);
    for _ in 0..MINIMAX_STEPS {
        let (c, e) = (b - golden * (b - a), a + golden * (b - a));
        if worst(c) <= worst(e) {
            b = e;
        } else {
            a = c;
        }
    }
    Some(worst(0.5 * (a + b)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// G1 data and samples of a planted segment of slope `alpha`.
    fn planted(alpha: f64) -> (LacSegment, Vec<Point>) {
        let segment = LacSegment::new(Point::new(2.0, -1.0), 0.4, 30.0, Some(alpha), 0.08, 0.02)
            .expect("segment");
        let samples = (1..40)
            .map(|i| segment.point(segment.length() * i as f64 / 40.0))
            .collect();
        (segment, samples)
    }

    /// The segment's G1 data: its ends and unit tangents there.
    fn g1(segment: &LacSegment) -> (Point, Vec2, Point, Vec2) {
        let tangent = |theta: f64| Vec2::new(theta.cos(), theta.sin());
        (
            segment.start(),
            tangent(segment.theta0()),
            segment.end(),
            tangent(segment.theta1()),
        )
    }

    fn search(
        segment: &LacSegment,
        samples: &[Point],
        options: &SpanFitOptions,
    ) -> Result<SpanFit, LacError> {
        let (a, ta, b, tb) = g1(segment);
        fit_span(a, ta, b, tb, samples, options)
    }

    /// The options of a search from `guess` on [`planted`] data (distances exact to 1e-6).
    fn guided(guess: f64) -> SpanFitOptions {
        SpanFitOptions {
            guess: Some(guess),
            ..SpanFitOptions::new(1e-6)
        }
    }

    #[test]
    fn the_search_finds_a_planted_alpha() {
        for alpha in [-1.0, 0.0, 0.5, 1.5] {
            let (segment, samples) = planted(alpha);
            for guess in [None, Some(alpha + 1.2)] {
                let options = SpanFitOptions {
                    guess,
                    ..SpanFitOptions::new(1e-6)
                };
                let fit = search(&segment, &samples, &options).expect("fits");
                let found = fit.segment.alpha().expect("a spiral");
                assert!(
                    (found - alpha).abs() < 0.05,
                    "α {alpha}, guess {guess:?}: {found}"
                );
                assert!(fit.deviation.max < 1e-3, "{}", fit.deviation.max);
            }
        }
    }

    #[test]
    fn gauss_newton_from_a_guess_within_a_cell_takes_few_evaluations() {
        for alpha in [-1.5, -1.0, 0.0, 0.5, 1.5, 2.0] {
            let (segment, samples) = planted(alpha);
            for offset in [-0.45, 0.3] {
                let options = guided(alpha + offset);
                let fit = search(&segment, &samples, &options).expect("fits");
                let found = fit.segment.alpha().expect("a spiral");
                assert!(
                    (found - alpha).abs() < ALPHA_TOLERANCE,
                    "α {alpha}, guess {offset:+}: {found}"
                );
                // The walk and Brent need several more from such a guess (13 for the first).
                assert!(
                    fit.search.evaluations <= 4,
                    "α {alpha}, guess {offset:+}: {} evaluations",
                    fit.search.evaluations
                );
            }
        }
    }

    #[test]
    fn a_search_gives_up_when_no_alpha_within_reach_can_meet_the_limit() {
        let (segment, samples) = planted(-1.0);
        let options = |guess: f64, unreachable_above: f64| SpanFitOptions {
            unreachable_above,
            ..guided(guess)
        };
        // A tenth of what the segment at α = −0.7 misses by: reachable from there (α = −1 fits
        // exactly), not from α = 2.
        let (a, ta, b, tb) = g1(&segment);
        let near = fit_g1(a, ta, b, tb, -0.7).expect("joins");
        let limit = 0.1 * deviation(&near, &samples, 1e-6).max;
        // Near the clothoid the model sees α = −1 within reach and the search goes on to it.
        let fit = search(&segment, &samples, &options(-0.7, limit)).expect("reachable");
        assert!((fit.segment.alpha().expect("a spiral") + 1.0).abs() < 0.05);
        // From α = 2 no α within two cells comes near the samples: given up after one
        // evaluation, reporting the model's best.
        assert!(matches!(
            search(&segment, &samples, &options(2.0, limit)),
            Err(LacError::SearchAbandoned { max, limit: l }) if max > l && l == limit
        ));
        // Without a limit the same guess still finds the clothoid.
        let fit = search(&segment, &samples, &options(2.0, f64::INFINITY)).expect("fits");
        assert!((fit.segment.alpha().expect("a spiral") + 1.0).abs() < 0.05);
    }

    #[test]
    fn a_search_gives_up_only_when_its_guess_misses_by_more_than_the_limit() {
        let (segment, samples) = planted(-1.0);
        let options = |guess: f64, abandon_above: f64| SpanFitOptions {
            abandon_above,
            ..guided(guess)
        };
        // The clothoid's own α fits to rounding; α = 2 misses by far more than 1e-3.
        assert!(search(&segment, &samples, &options(-1.0, 1e-3)).is_ok());
        assert!(matches!(
            search(&segment, &samples, &options(2.0, 1e-3)),
            Err(LacError::SearchAbandoned { max, limit }) if max > limit && limit == 1e-3
        ));
        // Without a limit the same guess still finds the clothoid.
        let fit = search(&segment, &samples, &options(2.0, f64::INFINITY)).expect("fits");
        assert!((fit.segment.alpha().expect("a spiral") + 1.0).abs() < 0.05);
    }

    #[test]
    fn a_stand_in_for_a_guess_that_cannot_join_the_data_gets_twice_the_limit() {
        // A clothoid from κ = 0 (no α below −1 joins its ends) with every sample moved off it
        // by 0.5: every α misses by about that much. From α = −3 the walk stands in α = −1.
        let segment = LacSegment::new(Point::new(0.0, 0.0), 0.2, 40.0, Some(-1.0), 0.0, 0.05)
            .expect("segment");
        let offset = 0.5;
        let samples: Vec<Point> = (1..40)
            .map(|i| {
                let s = segment.length() * i as f64 / 40.0;
                let (sin, cos) = segment.theta(s).sin_cos();
                segment.point(s) + Vec2::new(-sin, cos) * offset
            })
            .collect();
        let options = |abandon_above: f64| SpanFitOptions {
            abandon_above,
            ..guided(-3.0)
        };
        // 0.6 of the miss would abandon at a guess; at the stand-in the limit is 1.2 of it.
        let fit = search(&segment, &samples, &options(0.6 * offset)).expect("searched on");
        assert!(fit.deviation.max > 0.6 * offset);
        // 0.4 of it gives up, reporting the doubled limit.
        assert!(matches!(
            search(&segment, &samples, &options(0.4 * offset)),
            Err(LacError::SearchAbandoned { max, limit })
                if max > limit && limit == WALKED_ABANDON * 0.4 * offset
        ));
    }

    #[test]
    fn a_guess_that_cannot_join_the_data_steps_to_one_that_can() {
        // A clothoid from κ = 0 sits on the edge of the drawable region of α = −1: no α below
        // it can join its ends, and α = −1 itself fits best.
        let segment = LacSegment::new(Point::new(0.0, 0.0), 0.2, 40.0, Some(-1.0), 0.0, 0.05)
            .expect("segment");
        let samples: Vec<Point> = (1..40)
            .map(|i| segment.point(segment.length() * i as f64 / 40.0))
            .collect();
        let (a, ta, b, tb) = g1(&segment);
        assert!(fit_g1(a, ta, b, tb, -3.0).is_err());
        // The seeding tolerance: the walk's points decide, as in a chain fit.
        let options = SpanFitOptions {
            guess: Some(-3.0),
            alpha_tolerance: SEED_ALPHA_TOLERANCE,
            ..SpanFitOptions::new(1e-6)
        };
        let fit = search(&segment, &samples, &options).expect("fits");
        let found = fit.segment.alpha().expect("a spiral");
        assert!((found + 1.0).abs() < 0.05, "{found}");
        // Fewer than the 13 points of the grid the search used to fall back to: the guess, the
        // steps to α = −1 and the walk's neighbours.
        assert!(fit.search.evaluations < 13, "{}", fit.search.evaluations);
    }
}
