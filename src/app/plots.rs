//! The plots of the selected segment: curvature against arc length (the B-spline's span and the
//! LAC), the logarithmic curvature graph with its line of slope α, and the α search
//! (rms deviation against α). [`SegmentPlots::of`] computes the series; [`show`] draws them.

use eframe::egui;
use egui_plot::{Legend, Line, Plot, Points, VLine};

use crate::chain::ChainSegment;
use crate::export::pieces_between;
use crate::geom::{ParamCurve, ParamCurveDeriv, curvature_from_derivs};
use crate::lac::{lcg_line, lcg_of_bezier_span, lcg_of_segment};
use crate::pipeline::CurveFit;

/// Points per curve in the curvature plot.
pub const CURVATURE_POINTS: usize = 200;

/// Points of each logarithmic curvature graph (as `kansei fit --lcg` writes).
pub const LCG_POINTS: usize = 64;

/// The series of one segment's plots.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SegmentPlots {
    /// LAC curvature κ(s), `[s, κ]`.
    pub lac_curvature: Vec<[f64; 2]>,
    /// The B-spline span's curvature over the same samples, `[s, κ]`, s from the span's start.
    pub bspline_curvature: Vec<[f64; 2]>,
    /// The LAC's LCG, `[ln ρ, ln(ρ·|ds/dρ|)]`.
    pub lac_lcg: Vec<[f64; 2]>,
    /// The B-spline span's LCG.
    pub bspline_lcg: Vec<[f64; 2]>,
    /// The line of slope α through the LAC's LCG, two points spanning it.
    pub alpha_line: Vec<[f64; 2]>,
    /// The α search's grid, `[α, rms]`.
    pub alpha_search: Vec<[f64; 2]>,
    /// The segment's α (`None`: an arc or a line).
    pub alpha: Option<f64>,
}

impl SegmentPlots {
    /// The series for `segment` of `fit`.
    pub fn of(fit: &CurveFit, segment: &ChainSegment) -> Self {
        let lac = &segment.segment;
        let length = lac.length();
        let lac_curvature = (0..=CURVATURE_POINTS)
            .map(|i| {
                let s = length * i as f64 / CURVATURE_POINTS as f64;
                [s, lac.kappa(s)]
            })
            .collect();
        let span = segment
            .params
            .map(|(u0, u1)| pieces_between(&fit.bspline.curve.to_beziers(), u0, u1))
            .unwrap_or_default();
        let bspline_curvature = bezier_curvature(&span);
        let pairs = |v: Vec<crate::lac::LcgPoint>| -> Vec<[f64; 2]> {
            v.iter().map(|p| [p.log_rho, p.log_rho_ds_drho]).collect()
        };
        let lac_points = lcg_of_segment(lac, LCG_POINTS);
        let alpha_line = match (lac.alpha(), lcg_line(&lac_points)) {
            (Some(alpha), Some(line)) => {
                let xs = lac_points.iter().map(|p| p.log_rho);
                let lo = xs.clone().fold(f64::INFINITY, f64::min);
                let hi = xs.fold(f64::NEG_INFINITY, f64::max);
                // The line of slope α through the points' centroid.
                let (mx, my) = (
                    lac_points.iter().map(|p| p.log_rho).sum::<f64>() / line.count as f64,
                    lac_points.iter().map(|p| p.log_rho_ds_drho).sum::<f64>() / line.count as f64,
                );
                vec![[lo, my + alpha * (lo - mx)], [hi, my + alpha * (hi - mx)]]
            }
            _ => Vec::new(),
        };
        SegmentPlots {
            lac_curvature,
            bspline_curvature,
            lac_lcg: pairs(lac_points),
            bspline_lcg: pairs(lcg_of_bezier_span(&span, LCG_POINTS)),
            alpha_line,
            alpha_search: segment.search.grid.clone(),
            alpha: lac.alpha(),
        }
    }
}

/// Curvature against (chord-summed) arc length along Bézier pieces.
fn bezier_curvature(pieces: &[crate::geom::ParamBez]) -> Vec<[f64; 2]> {
    let per_piece = (CURVATURE_POINTS / pieces.len().max(1)).max(2);
    let mut out = Vec::with_capacity(per_piece * pieces.len());
    let mut s = 0.0;
    let mut previous: Option<crate::geom::Point> = None;
    for piece in pieces {
        let d1 = piece.bez.deriv();
        let d2 = d1.deriv();
        for i in 0..=per_piece {
            let t = i as f64 / per_piece as f64;
            let p = piece.bez.eval(t);
            if let Some(q) = previous {
                s += (p - q).hypot();
            }
            previous = Some(p);
            let kappa = curvature_from_derivs(d1.eval(t).to_vec2(), d2.eval(t).to_vec2());
            out.push([s, kappa]);
        }
    }
    out
}

/// Draws the three plots side by side, each `height` points tall.
pub fn show(ui: &mut egui::Ui, plots: &SegmentPlots, height: f32) {
    let width = (ui.available_width() / 3.0 - 8.0).max(80.0);
    ui.horizontal(|ui| {
        ui.vertical(|ui| {
            ui.label("curvature κ against arc length s");
            Plot::new("curvature")
                .legend(Legend::default())
                .width(width)
                .height(height)
                .show(ui, |p| {
                    p.line(Line::new("B-spline", plots.bspline_curvature.clone()));
                    p.line(Line::new("LAC", plots.lac_curvature.clone()));
                });
        });
        ui.vertical(|ui| {
            ui.label("LCG: ln(ρ·|ds/dρ|) against ln ρ");
            Plot::new("lcg")
                .legend(Legend::default())
                .width(width)
                .height(height)
                .show(ui, |p| {
                    p.points(Points::new("B-spline", plots.bspline_lcg.clone()).radius(1.5));
                    p.points(Points::new("LAC", plots.lac_lcg.clone()).radius(1.5));
                    if !plots.alpha_line.is_empty() {
                        let name = format!("slope α = {:.3}", plots.alpha.unwrap_or(f64::NAN));
                        p.line(Line::new(name, plots.alpha_line.clone()));
                    }
                });
        });
        ui.vertical(|ui| {
            ui.label("α search: rms deviation against α");
            Plot::new("alpha-search")
                .legend(Legend::default())
                .width(width)
                .height(height)
                .show(ui, |p| {
                    p.line(Line::new("rms", plots.alpha_search.clone()));
                    if let Some(alpha) = plots.alpha {
                        p.vline(VLine::new("α", alpha));
                    }
                });
        });
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Point;
    use crate::pipeline::{PipelineOptions, fit_stroke};
    use crate::stroke::Stroke;

    #[test]
    fn a_circle_arc_has_matching_constant_curvature() {
        // A quarter circle of radius 40: κ = ±1/40 along both curves.
        let arc = Stroke::from_points((0..=90).map(|d| {
            let a = (d as f64).to_radians();
            Point::new(40.0 * a.cos(), 40.0 * a.sin())
        }));
        let fits = fit_stroke(&arc, 0, 0.1, &PipelineOptions::default());
        let Ok(fits) = fits else {
            panic!("the arc does not fit: {fits:?}");
        };
        let fit = &fits[0];
        let Some(chain) = &fit.chain else {
            panic!("no chain");
        };
        for segment in &chain.segments {
            let plots = SegmentPlots::of(fit, segment);
            assert_eq!(plots.lac_curvature.len(), CURVATURE_POINTS + 1);
            assert!(!plots.bspline_curvature.is_empty());
            // Each curve's ∫κ ds (trapezoids) is its turning: θ1 − θ0 for the LAC, to the
            // trapezoid rule's error; the B-spline over the same stretch turns as much, to the
            // tangent error a 0.1 fit of a radius-40 arc allows.
            let turning = |v: &[[f64; 2]]| -> f64 {
                v.windows(2)
                    .map(|w| 0.5 * (w[0][1] + w[1][1]) * (w[1][0] - w[0][0]))
                    .sum()
            };
            let theta = segment.segment.theta1() - segment.segment.theta0();
            assert!((turning(&plots.lac_curvature) - theta).abs() < 1e-3);
            // The B-spline's plotted ∫κ ds is its own turning over the segment's parameter
            // interval (its end tangents carry the usual least-squares end bias, so it may turn
            // a few degrees more than the LAC, which is held to the end samples).
            let Some((u0, u1)) = segment.params else {
                panic!("a segment with samples has a parameter interval");
            };
            let h = 1e-7 * (u1 - u0);
            let curve = &fit.bspline.curve;
            let angle = |a: Point, b: Point| (b - a).atan2();
            let raw = angle(curve.eval(u1 - h), curve.eval(u1))
                - angle(curve.eval(u0), curve.eval(u0 + h));
            let own = (raw + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
            let b = turning(&plots.bspline_curvature);
            assert!(
                (b - own).abs() < 2e-3,
                "B-spline ∫κ ds {b}, its tangent turns {own}"
            );
            assert!((b - theta).abs() < 0.1, "B-spline turns {b}, LAC {theta}");
            // And their typical curvature is the circle's (a chain within 0.1 of the samples
            // may bend a few percent more or less over a short segment; seen: 3 %).
            for v in [&plots.lac_curvature, &plots.bspline_curvature] {
                let mut k: Vec<f64> = v.iter().map(|p| p[1].abs()).collect();
                k.sort_by(f64::total_cmp);
                let median = k[k.len() / 2];
                assert!(
                    (median - 1.0 / 40.0).abs() < 0.1 / 40.0,
                    "median κ = {median}"
                );
            }
        }
    }

    #[test]
    fn the_alpha_line_has_slope_alpha() {
        use crate::lac::LacSegment;
        // A planted clothoid-like spiral, α = −1 (κ from 0.01 to 0.05 over 60 units).
        let segment = LacSegment::new(Point::ORIGIN, 0.0, 60.0, Some(-1.0), 0.01, 0.05);
        let Ok(segment) = segment else {
            panic!("{segment:?}");
        };
        let fit = fit_stroke(
            &Stroke::from_points(segment.samples(0.5).map(|s| s.point)),
            0,
            0.05,
            &PipelineOptions::default(),
        );
        let Ok(fit) = fit else {
            panic!("{fit:?}");
        };
        let Some(chain) = &fit[0].chain else {
            panic!("no chain");
        };
        let seg = &chain.segments[0];
        let plots = SegmentPlots::of(&fit[0], seg);
        let [a, b] = [plots.alpha_line[0], plots.alpha_line[1]];
        let slope = (b[1] - a[1]) / (b[0] - a[0]);
        assert!((slope - seg.segment.alpha().unwrap_or(f64::NAN)).abs() < 1e-9);
        assert!(!plots.alpha_search.is_empty());
    }
}
