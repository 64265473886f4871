//! The noise floor of a stroke: how far its samples sit from the curve the hand drew, estimated
//! from the samples alone.
//!
//! Two sources add up:
//!
//! - **The grid.** Coordinates that are all whole multiples of a step `q` (whole pixels from a
//!   mouse or a browser, device counts from a tablet) were rounded: each axis carries uniform
//!   rounding noise of standard deviation `q/√12`, and a point of the true curve lies up to
//!   `q·√2/2` from its sample. The step is found from the differences of consecutive
//!   coordinates (so an offset origin does not hide it): the smallest nonzero difference, or a
//!   small fraction of it, that divides every difference ([`NoiseFloor::grid`]).
//! - **The jitter.** Around a smooth curve sampled densely for its curvature, a quadratic fitted
//!   by least squares to a window of [`WINDOW`] consecutive samples (parametrised by chord
//!   length) follows the curve and leaves the noise: the residual of the window's middle sample
//!   along the fit's normal, divided by `√(1 − h)` (`h` its leverage, the hat matrix's diagonal
//!   entry), has the variance σ² of the noise across the curve. Only that component matters: a
//!   sample moved along the curve is no farther from it. σ is a trimmed root mean square of
//!   these standardised residuals ([`NoiseFloor::sigma`]): the median absolute value (times
//!   1.4826, the Gaussian's ratio) sets a cut of [`TRIM_SIGMAS`] of it, which keeps corners,
//!   hooks and the windows that straddle them out, and the root mean square of what remains is
//!   right for rounding noise too (whose median would overstate it by a quarter). On a grid the
//!   cut is at least [`GRID_TRIM_STEPS`] steps: rounded jitter throws samples a whole step off.
//!
//! On a grid the local fits take samples a few steps apart ([`GRID_DECORRELATION_STEPS`]):
//! rounding errors of neighbouring pixels are one staircase, not independent noise. Every sample
//! is still used: the fits run over each interleaved run of samples that far apart (every k-th
//! sample from each of the first k), not over one. Over 200 random planted chains with 0.3 px of
//! jitter then rounded, σ's estimate (true 0.42 px) spread over 0.35–0.52 px (5th to 95th
//! percentile) from one run and 0.37–0.49 px from all; at 0.23 px one stroke's floor fell to the
//! bare grid's and its single segment came back as 34 segments.
//!
//! The floor the tolerance may not go below ([`NoiseFloor::floor`]): on a grid whose samples are
//! only rounded, the grid's worst rounding `q·√2/2` (the true curve is within it of every
//! sample); where there is jitter, the larger of that and the largest excursion `n` samples of
//! the noise reach ([`noise_multiple`], `√(2·ln n)` times σ). A grid's samples are jittered
//! before rounding where a coordinate turns back while the stroke runs along its axis
//! ([`JITTER_REVERSALS`]; rounding is monotone, so on a smooth curve a coordinate turns back
//! only where the tangent is perpendicular to its axis), or where σ stands clear of the
//! staircase a grid alone reads ([`GRID_STAIRCASE_RATIO`]). The true curve
//! then lies within the tolerance of (nearly) every sample, so the fit need not chase any.

use crate::geom::{Point, Vec2};

/// Samples per window of the local quadratic fits: the fewest that leave the middle sample a
/// residual to measure (its leverage is about 1/2). In a symmetric window the curve's cubic
/// term cancels at the middle, so what the quadratic misses of the curve is its quartic term,
/// which a wider window raises by (7/5)⁴ ≈ 4: on sparse mouse strokes (15 px between samples)
/// seven samples read the curve's bending as noise (σ 0.63 px against 0.41 px with five on
/// `perfect-freehand-corners`). On dense strokes both agree.
pub const WINDOW: usize = 5;

/// Standardised residuals beyond this many robust standard deviations are left out of σ: a
/// Gaussian reaches it at 5 samples in 10⁴, while a window straddling a corner or a hook does at
/// once.
pub const TRIM_SIGMAS: f64 = 3.5;

/// On a grid, residuals within this many grid steps are never trimmed as outliers. Jitter of a
/// fraction of a step, rounded, leaves most samples of a curve that runs along the grid exactly
/// on it and throws a few a whole step off: the median absolute residual is then near zero, the
/// robust cut with it, and the steps the fit must still cover were dropped from σ (a line along
/// the grid with 0.3 px of jitter read σ = 0.10 px, and came back as 49 segments at its 0.73 px
/// floor). A corner or a hook, which trimming is for, is many steps off.
pub const GRID_TRIM_STEPS: f64 = 1.5;

/// The ratio of a Gaussian's standard deviation to its median absolute value.
const MAD_TO_SIGMA: f64 = 1.4826;

/// The smallest multiple of the jitter σ in the tolerance floor. The floor's multiple is the
/// expected largest of the stroke's `n` excursions across the curve, `√(2·ln n)` σ for Gaussian
/// jitter (3.0 at 90 samples, 3.4 at 300, 3.7 at 1000), and at least this: every sample must
/// lie within the tolerance, and a stiff curve cannot bend to one sample that the noise threw
/// farther than the rest without a joint of its own (measured: a planted two-segment C with
/// 0.41 px of noise came back as 29 segments at 2.4 σ).
pub const NOISE_MULTIPLE: f64 = 2.5;

/// Relative error within which a coordinate difference counts as a whole multiple of the grid
/// step: far above the rounding of an `f64` difference (a few 10⁻¹⁶ of the coordinates) and of
/// a decimal step written in a file (0.1 px as 0.1000000000000000055), far below any real
/// jitter.
const GRID_MATCH_RELATIVE: f64 = 1e-6;

/// Fractions of the smallest difference tried as the grid step (a fast pen may never move by
/// one count, only by two or three).
const GRID_DIVISORS: std::ops::RangeInclusive<u32> = 1..=4;

/// Fewest nonzero coordinate differences that make a grid: below it, a few whole-pixel
/// coincidences prove nothing.
const MIN_GRID_DIFFERENCES: usize = 8;

/// On a grid, the local fits take samples this many grid steps apart (by a stride over the
/// samples): rounding errors of samples closer than that are one staircase pattern, not
/// independent noise. Measured on planted curves on a whole-pixel grid sampled every 0.3 to
/// 2.7 px, noise-free: σ at most 1.45 times the grid's own `q/√12` with 2 steps, 1.7 times
/// without thinning; with 0.3 px of jitter: σ within 1.25 times the truth (3 steps keep too
/// few samples to tell the jitter from the grid).
pub const GRID_DECORRELATION_STEPS: f64 = 2.0;

/// On a grid, σ up to this multiple of the grid's own `q/√12` can be the grid's alone: along a
/// slowly turning curve the rounding errors of neighbouring samples are one staircase (a
/// sawtooth along the curve), not independent noise, and the local fits read part of it as more
/// noise. Measured on noise-free planted curves on a whole-pixel grid sampled every 0.25 to
/// 2.7 px (after thinning): σ from 0.8 to 1.45 times `q/√12`. Beyond it there is jitter. Within
/// it there may be too (0.3 px of jitter reads 1.03 to 1.9 times `q/√12`): a coordinate
/// turning back while the stroke runs along its axis tells ([`JITTER_REVERSALS`]).
pub const GRID_STAIRCASE_RATIO: f64 = 1.5;

/// Fewest standardised residuals for a jitter estimate (a stroke of fewer samples gets none).
const MIN_RESIDUALS: usize = 5;

/// A stroke's noise, estimated from its samples.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct NoiseFloor {
    /// The coordinate grid's step, when every coordinate difference is a whole multiple of one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid: Option<f64>,
    /// The noise across the curve: one standard deviation, in the stroke's units (grid rounding
    /// included). 0 when the stroke has too few samples to tell.
    pub sigma: f64,
    /// The smallest tolerance the samples support ([`NoiseFloor::floor`]).
    pub floor: f64,
}

impl NoiseFloor {
    /// Estimates the noise of a polyline's samples (consecutive repeats are skipped: a slow
    /// pointer repeats its position, which says nothing of the curve). Non-finite points are
    /// ignored (the boundary rejects them elsewhere).
    pub fn estimate(points: &[Point]) -> NoiseFloor {
        let mut distinct: Vec<Point> = Vec::with_capacity(points.len());
        for &p in points {
            if p.is_finite() && distinct.last() != Some(&p) {
                distinct.push(p);
            }
        }
        let grid = grid_step(&distinct);
        let sigma = match grid {
            // Rounding is independent only between samples a few steps apart: along a
            // staircase of neighbouring pixels it is one pattern, which the local fits would
            // partly read as the curve and partly as extra noise (σ 1.7 times the grid's own
            // on a curve sampled every 0.27 px). Fit samples at least that far apart.
            Some(q) => jitter_sigma(
                &interleaved(&distinct, GRID_DECORRELATION_STEPS * q),
                GRID_TRIM_STEPS * q,
            ),
            None => jitter_sigma(std::slice::from_ref(&distinct), 0.0),
        };
        let reversed = grid.is_some_and(|q| reversals(&distinct, q) >= JITTER_REVERSALS);
        let floor = floor_of(grid, sigma, distinct.len(), reversed);
        NoiseFloor { grid, sigma, floor }
    }

    /// The tolerance floor: `q·√2/2`, the grid's worst rounding, on a grid whose samples are
    /// only rounded (no reversals, σ within the grid's staircase); otherwise the larger of that
    /// (0 without a grid) and `k·σ`, `k` the expected largest excursion of the stroke's samples
    /// in σ ([`noise_multiple`]). Rounding jittered samples is noise independent from sample to
    /// sample like the jitter, so on a jittered grid all of σ counts.
    pub fn floor(&self) -> f64 {
        self.floor
    }
}

fn floor_of(grid: Option<f64>, sigma: f64, samples: usize, reversed: bool) -> f64 {
    let q = grid.unwrap_or(0.0);
    let worst_rounding = q * std::f64::consts::FRAC_1_SQRT_2;
    let staircase = grid.is_some() && !reversed && sigma <= GRID_STAIRCASE_RATIO * q / 12f64.sqrt();
    if staircase {
        worst_rounding
    } else {
        worst_rounding.max(noise_multiple(samples) * sigma)
    }
}

/// The multiple of the jitter that the largest of `samples` excursions reaches:
/// `√(2·ln samples)`, at least [`NOISE_MULTIPLE`].
pub fn noise_multiple(samples: usize) -> f64 {
    let n = samples.max(1) as f64;
    (2.0 * n.ln()).sqrt().max(NOISE_MULTIPLE)
}

/// Fewest reversals that show jitter on a grid: a coordinate turning back where the stroke runs
/// along its axis (between two moves that each run more along it than across, or where the chord
/// from four grid steps before the reversal to four after runs along the axis at least 0.3 times
/// as far as across). Rounding is monotone, so a coordinate of a rounded smooth curve turns back
/// only where the curve does: where its tangent is perpendicular to that axis. Over 300 random
/// planted chains rounded without jitter and sampled every 0.3, 0.6, 0.9, 1.4, 2 and 2.7 px, no
/// stroke showed more than one; with 0.3 px of jitter, two or more showed on every stroke sampled
/// every 0.9 px or closer, on 248 of 300 at 1.4 px, 63 at 2 px and 10 at 2.7 px, where only σ
/// can tell.
pub const JITTER_REVERSALS: usize = 2;

/// How far either side of a reversal, in grid steps, the chord that says which way the stroke
/// runs there reaches ([`reversals`]): far enough that rounding moves its direction by a few
/// degrees at most (two ends a pixel off over eight pixels), near enough that a pen curve turns
/// little over it.
const REVERSAL_REACH_STEPS: f64 = 4.0;

/// A reversal of one coordinate counts where the chord around it moves along that axis at least
/// this share of its move across it ([`reversals`]): its direction is then more than 16.7° from
/// the perpendicular, where a smooth curve would have to be for the coordinate to turn back (the
/// chord of a stretch around a tangent perpendicular to the axis runs nearly perpendicular to it).
const REVERSAL_ALONG_RATIO: f64 = 0.3;

/// Most samples the chord of [`reversals`] reaches over on either side: a pen resting in place
/// leaves any number of samples within [`REVERSAL_REACH_STEPS`] of one point, and walking them
/// all for each of its reversals would cost the square of their count. At the closest spacing
/// measured (0.3 px) four steps hold about fourteen samples; 64 leave those untouched.
const REVERSAL_MAX_SAMPLES: usize = 64;

/// How many times, counted up to [`JITTER_REVERSALS`] (all the floor asks), a coordinate turns
/// back (consecutive nonzero moves along its axis of opposite signs, between consecutive
/// distinct points) where a rounded smooth curve could not: either
/// both moves run at least as far along the axis as across it (the coordinate that moves more
/// turns back), or the chord from [`REVERSAL_REACH_STEPS`] grid steps before the reversal to as
/// far after it runs along the axis at least [`REVERSAL_ALONG_RATIO`] times as far as across (the
/// stroke there runs clearly along the axis, as on a diagonal drawn in steps of a pixel in each
/// coordinate, where no move runs more along one axis than the other). Jitter of a fraction of
/// the grid's step turns a coordinate back every few samples of a dense stroke.
fn reversals(points: &[Point], grid: f64) -> usize {
    let reach = REVERSAL_REACH_STEPS * grid;
    let mut count = 0;
    for axis in [Axis::X, Axis::Y] {
        // The last nonzero move along the axis: where it starts, and the move.
        let mut last: Option<(usize, Vec2)> = None;
        for i in 0..points.len().saturating_sub(1) {
            let step = points[i + 1] - points[i];
            if axis.along(step) == 0.0 {
                continue;
            }
            if let Some((j, before)) = last
                && axis.along(before) * axis.along(step) < 0.0
            {
                let mostly = |v: Vec2| axis.along(v).abs() >= axis.across(v).abs();
                let immediate = i == j + 1 && mostly(before) && mostly(step);
                if immediate || along_chord(points, axis, j, i + 1, reach) {
                    count += 1;
                    if count >= JITTER_REVERSALS {
                        return count;
                    }
                }
            }
            last = Some((i, step));
        }
    }
    count
}

/// Whether the chord from [`REVERSAL_REACH_STEPS`] grid steps (`reach`) before point `from` to as
/// far after point `to` runs along `axis` at least [`REVERSAL_ALONG_RATIO`] times as far as
/// across it.
fn along_chord(points: &[Point], axis: Axis, from: usize, to: usize, reach: f64) -> bool {
    let mut lo = from;
    while lo > 0 && from - lo < REVERSAL_MAX_SAMPLES && points[lo].distance(points[from]) < reach {
        lo -= 1;
    }
    let mut hi = to;
    while hi + 1 < points.len()
        && hi - to < REVERSAL_MAX_SAMPLES
        && points[hi].distance(points[to]) < reach
    {
        hi += 1;
    }
    let chord = points[hi] - points[lo];
    axis.along(chord).abs() >= REVERSAL_ALONG_RATIO * axis.across(chord).abs()
}

/// A coordinate axis of the plane.
#[derive(Clone, Copy)]
enum Axis {
    X,
    Y,
}

impl Axis {
    /// A vector's component along the axis.
    fn along(self, v: Vec2) -> f64 {
        match self {
            Axis::X => v.x,
            Axis::Y => v.y,
        }
    }

    /// A vector's component across the axis.
    fn across(self, v: Vec2) -> f64 {
        match self {
            Axis::X => v.y,
            Axis::Y => v.x,
        }
    }
}

/// The points split into k interleaved runs (every k-th point, from each of the first k), k the
/// smallest stride that makes the median spacing between a run's points at least `spacing`:
/// chosen by index, so that which samples go together does not depend on their noise (keeping
/// the first sample at least `spacing` from the last one kept favours samples the noise moved
/// away, and overstated σ by a fifth on a jittered pixel grid). Every sample is in one run, so
/// the local fits of all runs together see every sample (one run alone scattered σ's estimate
/// twice as widely).
fn interleaved(points: &[Point], spacing: f64) -> Vec<Vec<Point>> {
    let mut gaps: Vec<f64> = points.windows(2).map(|w| w[0].distance(w[1])).collect();
    if gaps.is_empty() {
        return vec![points.to_vec()];
    }
    gaps.sort_by(f64::total_cmp);
    let median = gaps[gaps.len() / 2];
    let stride = if median > 0.0 {
        // Saturating float→int conversion; at least 1.
        ((spacing / median).ceil() as usize).max(1)
    } else {
        1
    };
    (0..stride.min(points.len()))
        .map(|offset| points[offset..].iter().step_by(stride).copied().collect())
        .collect()
}

/// The grid step of the points' coordinates, if they lie on one.
fn grid_step(points: &[Point]) -> Option<f64> {
    let diffs: Vec<f64> = points
        .windows(2)
        .flat_map(|w| [(w[1].x - w[0].x).abs(), (w[1].y - w[0].y).abs()])
        .filter(|d| *d > 0.0)
        .collect();
    if diffs.len() < MIN_GRID_DIFFERENCES {
        return None;
    }
    let smallest = diffs.iter().copied().fold(f64::INFINITY, f64::min);
    GRID_DIVISORS.map(|k| smallest / f64::from(k)).find(|&q| {
        diffs.iter().all(|&d| {
            let m = d / q;
            (m - m.round()).abs() <= GRID_MATCH_RELATIVE * m.max(1.0)
        })
    })
}

/// The trimmed root mean square of the standardised normal residuals of the local quadratic
/// fits (0 with too few samples).
fn jitter_sigma(runs: &[Vec<Point>], least_cut: f64) -> f64 {
    let residuals: Vec<f64> = runs
        .iter()
        .flat_map(|run| run.windows(WINDOW).filter_map(standardised_residual))
        .collect();
    trimmed_rms(residuals, least_cut)
}

/// The root mean square of the residuals within [`TRIM_SIGMAS`] robust standard deviations, or
/// within `least_cut` where that is wider.
fn trimmed_rms(residuals: Vec<f64>, least_cut: f64) -> f64 {
    if residuals.len() < MIN_RESIDUALS {
        return 0.0;
    }
    let mut abs: Vec<f64> = residuals.iter().map(|r| r.abs()).collect();
    abs.sort_by(f64::total_cmp);
    let median = abs[abs.len() / 2];
    let cut = (TRIM_SIGMAS * MAD_TO_SIGMA * median).max(least_cut);
    let kept: Vec<f64> = abs.into_iter().filter(|r| *r <= cut).collect();
    if kept.is_empty() {
        return 0.0;
    }
    (kept.iter().map(|r| r * r).sum::<f64>() / kept.len() as f64).sqrt()
}

/// The middle sample's residual from the window's quadratic, across the fit's tangent and
/// divided by `√(1 − h)`; `None` where the window is degenerate (no length, or its parameters
/// too few to fit a quadratic).
fn standardised_residual(window: &[Point]) -> Option<f64> {
    let mid = window.len() / 2;
    // Chord length from the middle sample, scaled to the window's length for conditioning.
    let mut t = vec![0.0; window.len()];
    for i in (0..mid).rev() {
        t[i] = t[i + 1] - (window[i + 1] - window[i]).hypot();
    }
    for i in mid + 1..window.len() {
        t[i] = t[i - 1] + (window[i] - window[i - 1]).hypot();
    }
    let scale = t[window.len() - 1] - t[0];
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    let mut xtx = nalgebra::Matrix3::<f64>::zeros();
    let mut xty = nalgebra::Matrix3x2::<f64>::zeros();
    for (p, ti) in window.iter().zip(&t) {
        let s = ti / scale;
        let row = nalgebra::Vector3::new(1.0, s, s * s);
        xtx += row * row.transpose();
        xty += row * nalgebra::RowVector2::new(p.x, p.y);
    }
    let inverse = xtx.try_inverse()?;
    let beta = inverse * xty;
    // The middle sample sits at s = 0: its fitted point is the constant term, its leverage the
    // inverse's first diagonal entry, and the tangent there the linear term.
    let leverage = inverse[(0, 0)];
    let (fitted, tangent) = (
        Point::new(beta[(0, 0)], beta[(0, 1)]),
        kurbo::Vec2::new(beta[(1, 0)], beta[(1, 1)]),
    );
    let length = tangent.hypot();
    if !(length > 0.0 && leverage < 1.0) {
        return None;
    }
    let across = tangent.cross(window[mid] - fitted) / length;
    let r = across / (1.0 - leverage).sqrt();
    r.is_finite().then_some(r)
}
