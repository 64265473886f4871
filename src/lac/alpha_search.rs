//! The α that fits a span best: the Yoshida–Saito segment through the span's G1 end data whose
//! samples lie closest to it.
//!
//! The objective is the root mean square foot-point distance of the span's samples to the
//! segment ([`mod@super::deviation`]); α values whose segment cannot join the data (outside the
//! drawable region) score +∞. A grid over the allowed range ([`GRID_STEP`]) finds the best cell
//! (the objective is not unimodal over the whole range: the drawable region can end inside it),
//! then Brent's method ([`super::minimize::brent`]) minimises continuously on the two cells around
//! it to [`ALPHA_TOLERANCE`]. This replaces the seed paper's choice among a few fixed α values.

use serde::{Deserialize, Serialize};

use super::deviation::{Deviation, deviation, rough_deviation};
use super::error::LacError;
use super::minimize::brent;
use super::segment::LacSegment;
use super::yoshida_saito::{fit_g1, fit_g1_near};
use crate::geom::{Point, Vec2};

/// Grid step of the coarse α scan. 0.5 resolves the cells in which the objective is unimodal on
/// every planted and fixture span seen; finer costs evaluations for nothing Brent won't find.
pub const GRID_STEP: f64 = 0.5;

/// The search ranks α values with distances exact to this multiple of the caller's chord error
/// (coarser, hence faster, tracing); the chosen segment's distances are then computed exactly.
const SEARCH_CHORD_FACTOR: f64 = 10.0;

/// Absolute tolerance on α of the continuous search. α is reported to about 1e-3, and the
/// deviation changes by far less than a tolerance over 1e-4 of α.
pub const ALPHA_TOLERANCE: f64 = 1e-4;

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
    /// The objective on the coarse grid, as `[α, rms]` (infeasible α left out).
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

/// Fits the best LAC segment (see the module doc) through `a` (tangent `ta`) and `b` (tangent
/// `tb`) to `samples`, ordered from `a` to `b`. Distances are exact to `chord_error`. Segments
/// whose curvature anywhere exceeds `max_curvature` in magnitude count as infeasible (pass
/// `f64::INFINITY` for no limit).
pub fn fit_span(
    a: Point,
    ta: Vec2,
    b: Point,
    tb: Vec2,
    samples: &[Point],
    choice: AlphaChoice,
    chord_error: f64,
    max_curvature: f64,
) -> Result<SpanFit, LacError> {
    choice.validate()?;
    let (min, max) = match choice {
        AlphaChoice::Range { min, max } => (min, max),
        AlphaChoice::Fixed(alpha) => (alpha, alpha),
    };
    let mut evaluations = 0usize;
    let search_chord = SEARCH_CHORD_FACTOR * chord_error;
    // The last segment built starts the next construction: successive α are close.
    let mut last: Option<LacSegment> = None;
    let mut evaluate = |alpha: f64| -> Option<(LacSegment, Deviation)> {
        evaluations += 1;
        let built = fit_g1_near(a, ta, b, tb, alpha, last.as_ref()).ok()?;
        last = Some(built);
        let segment = Some(built).filter(|s| within(s, max_curvature))?;
        let d = rough_deviation(&segment, samples, search_chord);
        Some((segment, d))
    };

    // A fixed α, or data that make an arc or a line whatever α is.
    let first = evaluate(0.5 * (min + max));
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

    // Coarse grid.
    let cells = (((max - min) / GRID_STEP).ceil() as usize).max(1);
    let grid_alpha = |i: usize| min + (max - min) * i as f64 / cells as f64;
    let mut grid = Vec::with_capacity(cells + 1);
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

    // Brent on the cells around the best grid point.
    let lo = grid_alpha(k.saturating_sub(1));
    let hi = grid_alpha((k + 1).min(cells));
    let objective = |alpha: f64| evaluate(alpha).map_or(f64::INFINITY, |(_, d)| d.rms);
    let minimum = brent(objective, lo, hi, ALPHA_TOLERANCE, MAX_BRENT_EVALUATIONS);
    let grid_best = grid_alpha(k);
    let alpha = if minimum.value.is_finite() {
        minimum.x
    } else {
        grid_best
    };
    let (segment, deviation) = match fit_g1(a, ta, b, tb, alpha) {
        Ok(segment) if within(&segment, max_curvature) => {
            let d = deviation(&segment, samples, chord_error);
            (segment, d)
        }
        Ok(_) => return Err(LacError::NoAlphaInRange { min, max }),
        Err(e) => return Err(e),
    };
    let search = AlphaSearch {
        range: [min, max],
        alpha: segment.alpha(),
        rms: deviation.rms,
        evaluations: evaluations + 1,
        grid,
    };
    Ok(SpanFit {
        segment,
        deviation,
        search,
    })
}

/// Whether the segment's curvature stays within `max_curvature` (curvature is monotonic, so the
/// ends bound it).
pub fn within(segment: &LacSegment, max_curvature: f64) -> bool {
    segment.kappa0().abs().max(segment.kappa1().abs()) <= max_curvature
}
