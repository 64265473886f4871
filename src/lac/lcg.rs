//! The logarithmic curvature graph (LCG) of a curve.
//!
//! For a curve with radius of curvature ρ(s) = 1/|κ(s)| over arc length s, the LCG plots
//!
//! x = ln ρ,   y = ln(ρ·|ds/dρ|)
//!
//! (natural logarithms; Miura 2006, Yoshida & Saito 2006; the seed paper's eq. 1, there called
//! the logarithmic distribution diagram of curvature, LDDC). A log-aesthetic curve is exactly the
//! curve whose LCG is a straight line, its slope being α: ρ^{α−1}·dρ/ds = c0 gives
//! y = α·x − ln|c0|. The LCG does not depend on the direction of travel (|ds/dρ| is unsigned),
//! nor on rotation or translation; scaling the curve by k moves every point by (ln k, ln k).
//!
//! * [`lcg_of_segment`]: the LCG of a [`LacSegment`] from the closed form of dρ/ds;
//! * [`lcg_of_bezier_span`]: the LCG of a span of cubic Béziers (a piece of the least-squares
//!   B-spline) from the analytic derivatives of the Béziers;
//! * [`lcg_line`], [`lcg_slope`]: the least-squares line through LCG points, whose slope is the
//!   initial α guess for a span.
//!
//! Both samplers place their `count` points at the midpoints of `count` equal arc-length cells,
//! s_i = (i + ½)·S/count. Avoiding the ends keeps them off the split points, where a span's
//! |κ| has an extremum (κ′ = 0, so y = +∞) or an LAC has κ = 0 (x = +∞).

use super::segment::LacSegment;
use crate::geom::{ParamBez, ParamCurve, ParamCurveDeriv, Vec2, curvature_from_derivs};
use kurbo::ParamCurveArclen;
use serde::Serialize;

/// Arc lengths of Bézier pieces are measured to this fraction of the piece's control-polygon
/// length (an upper bound of its arc length). Arc length only decides where the points sit and
/// their reported `s`; κ and κ′ (hence x and y) are evaluated exactly at the found parameter,
/// so 1e-10 is far finer than needed while kurbo's adaptive quadrature still meets it in a few
/// subdivisions.
pub const ARCLEN_RELATIVE_ACCURACY: f64 = 1e-10;

/// One point of a logarithmic curvature graph.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LcgPoint {
    /// Arc length from the start of the segment or span.
    pub s: f64,
    /// x = ln ρ, ρ = 1/|κ| the radius of curvature.
    pub log_rho: f64,
    /// y = ln(ρ·|ds/dρ|).
    pub log_rho_ds_drho: f64,
}

/// The least-squares line y = slope·x + intercept through LCG points, with its residuals.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LcgLine {
    /// Slope: α for a log-aesthetic curve.
    pub slope: f64,
    /// Intercept: −ln|c0| for a log-aesthetic curve with ρ^{α−1}·dρ/ds = c0.
    pub intercept: f64,
    /// Root mean square of the vertical residuals y − (slope·x + intercept).
    pub rms_residual: f64,
    /// Largest absolute vertical residual.
    pub max_residual: f64,
    /// Number of (finite) points used.
    pub count: usize,
}

/// Midpoint of cell `i` of `count` equal cells of [0, length].
fn cell_midpoint(i: usize, count: usize, length: f64) -> f64 {
    (i as f64 + 0.5) / count as f64 * length
}

/// The LCG of a log-aesthetic segment at `count` arc lengths s_i = (i + ½)·S/count.
///
/// With a = |κ0|, b = |κ1| (so ρ0^α = a^{−α}, ρ1^α = b^{−α}, which is 0 at a κ = 0 end):
///
/// * α ≠ 0: ρ^α is linear in s, so α·ρ^{α−1}·dρ/ds = (ρ1^α − ρ0^α)/S = D/S and
///   ln|ds/dρ| = ln(S·|α|) + (α − 1)·ln ρ − ln|D|, where D = a^{−α}·expm1(−α·ln(b/a)) when both
///   ends curve (no cancellation for α or b/a near 1) and D = ±(the nonzero end's ρ^α) otherwise;
/// * α = 0: ρ = ρ0·(ρ1/ρ0)^{s/S}, so dρ/ds = ρ·ln(a/b)/S and ln|ds/dρ| = ln S − ln ρ −
///   ln|ln(a/b)|;
///
/// and y = ln ρ + ln|ds/dρ|, with ρ = 1/|κ(s)| from the segment's evaluator. Circular arcs and
/// lines (`alpha` = `None`) have no LCG: the result is empty. Points where κ = 0 (ln ρ
/// undefined) are skipped.
pub fn lcg_of_segment(segment: &LacSegment, count: usize) -> Vec<LcgPoint> {
    let Some(alpha) = segment.alpha() else {
        return Vec::new();
    };
    let length = segment.length();
    let (a, b) = (segment.kappa0().abs(), segment.kappa1().abs());
    // ln|ds/dρ| = slope_term·ln ρ + constant.
    let (slope_term, constant) = if alpha == 0.0 {
        // κ0 ≠ κ1 with α = 0 means both ends curve (validated by `LacSegment::new`).
        (-1.0, length.ln() - (a.ln() - b.ln()).abs().ln())
    } else {
        let ln_abs_d = if a > 0.0 && b > 0.0 {
            -alpha * a.ln() + (-alpha * (b.ln() - a.ln())).exp_m1().abs().ln()
        } else {
            // One end has κ = 0, so ρ^α = 0 there (α < 0); D is the other end's ρ^α.
            -alpha * a.max(b).ln()
        };
        (alpha - 1.0, (length * alpha.abs()).ln() - ln_abs_d)
    };
    (0..count)
        .filter_map(|i| {
            let s = cell_midpoint(i, count, length);
            let kappa = segment.kappa(s).abs();
            if kappa == 0.0 {
                return None;
            }
            let log_rho = -kappa.ln();
            let log_ds_drho = slope_term * log_rho + constant;
            Some(LcgPoint {
                s,
                log_rho,
                log_rho_ds_drho: log_rho + log_ds_drho,
            })
        })
        .collect()
}

/// Curvature κ and its arc-length derivative κ′ = dκ/ds of a cubic at local parameter `t`.
///
/// With f = |C′|², g = C′×C″: κ = g/f^{3/2}, f′ = 2·C′·C″, g′ = C′×C‴ (C″×C″ = 0), so
/// dκ/dt = (g′·f − 1.5·g·f′)/f^{5/2} and κ′ = (dκ/dt)/√f. `None` where C′ = 0 (a cusp: no
/// tangent, no curvature).
fn curvature_and_derivative(piece: &ParamBez, t: f64) -> Option<(f64, f64)> {
    let d1c = piece.bez.deriv();
    let d2c = d1c.deriv();
    let d1 = d1c.eval(t).to_vec2();
    let d2 = d2c.eval(t).to_vec2();
    let d3: Vec2 = d2c.deriv().eval(t).to_vec2();
    let f = d1.hypot2();
    if !(f > 0.0) {
        return None;
    }
    let kappa = curvature_from_derivs(d1, d2);
    let g = d1.cross(d2);
    let df = 2.0 * d1.dot(d2);
    let dg = d1.cross(d3);
    let dkappa_dt = (dg * f - 1.5 * g * df) / (f * f * f.sqrt());
    Some((kappa, dkappa_dt / f.sqrt()))
}

/// The LCG of a span given as consecutive cubic Bézier pieces (e.g. a
/// [`Span`](crate::split::Span)'s `pieces`), at `count` arc lengths s_i = (i + ½)·L/count along
/// the span (L its total arc length, s measured from the start of the first piece).
///
/// At each point κ and κ′ = dκ/ds come from the pieces' analytic derivatives (see the formulas
/// in the module source), and since |dρ/ds| = |κ′|/κ²:
///
/// x = ln ρ = −ln|κ|,   y = ln(ρ·|ds/dρ|) = ln|κ| − ln|κ′|.
///
/// Points where κ = 0 or κ′ = 0 (a logarithm undefined), or where a piece has no tangent, are
/// skipped; so are all points of a span of zero length.
pub fn lcg_of_bezier_span(pieces: &[ParamBez], count: usize) -> Vec<LcgPoint> {
    // Each piece's arc length, and the accuracy its inverse is found to.
    let accuracies: Vec<f64> = pieces
        .iter()
        .map(|p| {
            let b = p.bez;
            let polygon = (b.p1 - b.p0).hypot() + (b.p2 - b.p1).hypot() + (b.p3 - b.p2).hypot();
            ARCLEN_RELATIVE_ACCURACY * polygon
        })
        .collect();
    let lengths: Vec<f64> = pieces
        .iter()
        .zip(&accuracies)
        .map(|(p, &accuracy)| p.bez.arclen(accuracy))
        .collect();
    lcg_along(pieces, count, &lengths, |piece, s| {
        pieces[piece].bez.inv_arclen(s, accuracies[piece])
    })
}

/// [`lcg_of_bezier_span`] with the points placed along the pieces by a polyline of
/// [`ROUGH_TABLE_STEPS`] chords per piece instead of kurbo's arc length to
/// [`ARCLEN_RELATIVE_ACCURACY`]: each point is then off its place by well under a percent of its
/// piece, which moves the graph's slope far less than a starting guess needs, for a small
/// fraction of the cost (the α search's guess, [`crate::chain`]).
pub(crate) fn lcg_of_bezier_span_rough(pieces: &[ParamBez], count: usize) -> Vec<LcgPoint> {
    // Cumulative chord length at t = j/STEPS of each piece.
    let tables: Vec<[f64; ROUGH_TABLE_STEPS + 1]> = pieces
        .iter()
        .map(|p| {
            let mut table = [0.0; ROUGH_TABLE_STEPS + 1];
            let mut last = p.bez.p0;
            for j in 1..=ROUGH_TABLE_STEPS {
                let next = p.bez.eval(j as f64 / ROUGH_TABLE_STEPS as f64);
                table[j] = table[j - 1] + (next - last).hypot();
                last = next;
            }
            table
        })
        .collect();
    let lengths: Vec<f64> = tables.iter().map(|t| t[ROUGH_TABLE_STEPS]).collect();
    lcg_along(pieces, count, &lengths, |piece, s| {
        let table = &tables[piece];
        let j = table
            .partition_point(|&l| l <= s)
            .clamp(1, ROUGH_TABLE_STEPS);
        let (l0, l1) = (table[j - 1], table[j]);
        let within = if l1 > l0 { (s - l0) / (l1 - l0) } else { 0.0 };
        ((j - 1) as f64 + within.clamp(0.0, 1.0)) / ROUGH_TABLE_STEPS as f64
    })
}

/// Chords per piece of [`lcg_of_bezier_span_rough`]'s arc-length table: a chord turning τ is
/// shorter than its arc by about τ²/24 of it. The slope is then within 1e-3 of the exact graph's
/// for spans of a few pieces, and 0.06 off for a single cubic standing for a whole strongly
/// curving segment (curvature ratio 12, unevenly parametrised): an eighth of the cell the α
/// search steps by. 16 chords cost as much overall and move the fits only by the fit's chaos.
const ROUGH_TABLE_STEPS: usize = 8;

/// The LCG points of [`lcg_of_bezier_span`] given each piece's arc length (`lengths`) and the
/// parameter at arc length s within a piece (`parameter(piece, s)`).
fn lcg_along(
    pieces: &[ParamBez],
    count: usize,
    lengths: &[f64],
    parameter: impl Fn(usize, f64) -> f64,
) -> Vec<LcgPoint> {
    let total: f64 = lengths.iter().sum();
    if !(total > 0.0) {
        return Vec::new();
    }
    let mut points = Vec::with_capacity(count);
    let mut piece = 0;
    let mut piece_start = 0.0;
    for i in 0..count {
        let s = cell_midpoint(i, count, total);
        // Advance to the piece containing s (the last piece takes any rounding excess).
        while piece + 1 < pieces.len() && s > piece_start + lengths[piece] {
            piece_start += lengths[piece];
            piece += 1;
        }
        if !(lengths[piece] > 0.0) {
            continue;
        }
        let t = parameter(piece, s - piece_start);
        let Some((kappa, dkappa)) = curvature_and_derivative(&pieces[piece], t) else {
            continue;
        };
        let (kappa, dkappa) = (kappa.abs(), dkappa.abs());
        if kappa == 0.0 || dkappa == 0.0 || !kappa.is_finite() || !dkappa.is_finite() {
            continue;
        }
        let log_kappa = kappa.ln();
        points.push(LcgPoint {
            s,
            log_rho: -log_kappa,
            log_rho_ds_drho: log_kappa - dkappa.ln(),
        });
    }
    points
}

/// The least-squares line y = slope·x + intercept through the finite points (non-finite ones are
/// ignored), with its residuals. `None` with fewer than two distinct x.
///
/// Computed about the means (x̄, ȳ): slope = Σ(x − x̄)(y − ȳ) / Σ(x − x̄)², which avoids the
/// cancellation of the raw normal equations when the x are far from 0.
pub fn lcg_line(points: &[LcgPoint]) -> Option<LcgLine> {
    let finite = || {
        points
            .iter()
            .filter(|p| p.log_rho.is_finite() && p.log_rho_ds_drho.is_finite())
    };
    let count = finite().count();
    if count < 2 {
        return None;
    }
    let n = count as f64;
    let mean_x = finite().map(|p| p.log_rho).sum::<f64>() / n;
    let mean_y = finite().map(|p| p.log_rho_ds_drho).sum::<f64>() / n;
    let (sxx, sxy) = finite().fold((0.0, 0.0), |(sxx, sxy), p| {
        let (dx, dy) = (p.log_rho - mean_x, p.log_rho_ds_drho - mean_y);
        (sxx + dx * dx, sxy + dx * dy)
    });
    if !(sxx > 0.0) {
        return None;
    }
    let slope = sxy / sxx;
    let intercept = mean_y - slope * mean_x;
    let (sum_sq, max_residual) = finite().fold((0.0, 0.0_f64), |(sum_sq, max), p| {
        let r = p.log_rho_ds_drho - (slope * p.log_rho + intercept);
        (sum_sq + r * r, max.max(r.abs()))
    });
    Some(LcgLine {
        slope,
        intercept,
        rms_residual: (sum_sq / n).sqrt(),
        max_residual,
        count,
    })
}

/// The least-squares slope of the LCG points: α for a log-aesthetic curve, the initial α guess
/// for a span. `None` with fewer than two distinct x. See [`lcg_line`].
pub fn lcg_slope(points: &[LcgPoint]) -> Option<f64> {
    lcg_line(points).map(|line| line.slope)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::segment_beziers;
    use crate::geom::Point;

    #[test]
    fn the_rough_graph_has_the_exact_graphs_slope() {
        for alpha in [-1.5, -1.0, 0.0, 0.5, 1.0, 2.0] {
            let segment = LacSegment::new(Point::new(0.0, 0.0), 0.2, 12.0, Some(alpha), 0.02, 0.25)
                .expect("segment");
            // The segment as cubic Béziers, from one to a few pieces, like a span of the split
            // B-spline.
            for accuracy in [1e-1, 1e-2, 1e-3, 1e-4] {
                let pieces: Vec<ParamBez> = segment_beziers(&segment, accuracy)
                    .cubics
                    .into_iter()
                    .enumerate()
                    .map(|(i, bez)| ParamBez {
                        bez,
                        u0: i as f64,
                        u1: (i + 1) as f64,
                    })
                    .collect();
                let exact = lcg_slope(&lcg_of_bezier_span(&pieces, 16)).expect("slope");
                let rough = lcg_slope(&lcg_of_bezier_span_rough(&pieces, 16)).expect("slope");
                // A guess for a search stepping by up to 0.5: a tenth is a fifth of a cell (a
                // single piece for the whole segment is the worst case, 0.06 off).
                assert!(
                    (exact - rough).abs() < 0.1,
                    "α {alpha}, {} pieces: {exact} vs {rough}",
                    pieces.len()
                );
            }
        }
    }
}
