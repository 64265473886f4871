//! The DXF export: one cubic `SPLINE` entity per fitted piece, written with the `dxf` crate.
//!
//! ## The Bézier form
//!
//! Each piece's LAC chain becomes the Bézier chain of [`segment_beziers`] (lines exact, arcs and
//! spirals within the export accuracy), and that chain is written as one degree-3 B-spline in
//! Bézier form: control points P0 P1 P2 P3 P4 … (consecutive cubics share their end control
//! point) and a clamped knot vector whose interior knots have multiplicity 3,
//!
//! ```text
//! [0 0 0 0, k1 k1 k1, k2 k2 k2, …, kn kn kn kn],   kj = arc length of cubics 1..j,
//! ```
//!
//! so each knot span is exactly one of the cubics and the spline is the chain, not an
//! approximation of it. One spline per piece rather than per segment: a piece is what the
//! designer drew in one movement (strokes are cut only at corners), so a CAD user selects,
//! offsets or trims it as one curve, and its G1 joints stay inside one entity instead of
//! depending on a tool's join tolerance. The knots are arc lengths, so the spline's parameter
//! runs at nearly unit speed (tools that place points by parameter spread them evenly).
//!
//! ## The C2 form
//!
//! A curvature-continuous chain (`g2`, `c3`) is written instead, where it holds the accuracy,
//! as a cubic B-spline with simple knots fitted to the chain ([`c2_spline`], [`SplineForm::C2`]):
//! the Bézier form is only C0 in its parameter at the triple knots, and a CAD tool that reads
//! continuity off the knots would see breaks the chain does not have. The C2 spline's curvature
//! follows the chain's within what the accuracy allows, not exactly; a G1 chain keeps the Bézier
//! form, whose joints are the chain's own (its curvature jumps are real). The report says which
//! form each piece got.
//!
//! Numbers are written by the `dxf` crate with 12 decimals (an absolute rounding of at most
//! 5·10⁻¹³ in the data's units, negligible beside any accuracy).
//!
//! The header says `$ACADVER` AC1015 (R2000: the oldest version with `$INSUNITS`; SPLINE needs
//! R13) and `$INSUNITS` 4 (millimetres) for mm data, 0 (unitless) for px and device counts.

use dxf::entities::{Entity, EntityType, ModelPoint, Spline};
use dxf::enums::{AcadVersion, Units as DxfUnits};
use dxf::{Drawing, Point as DxfPoint};
use kurbo::{CubicBez, ParamCurveArclen};

use crate::bspline::{FitOptions, fit_bspline};
use crate::chain::{Chain, Continuity, JointKind};
use crate::geom::Point;
use crate::pipeline::FitOutput;
use crate::stroke::Units;

use super::bezier::segment_beziers;
use super::svg::export_accuracy;

/// Relative accuracy of the cubics' arc lengths used as knots (they only set the parameter
/// speed, never the shape).
const KNOT_ARCLEN_ACCURACY: f64 = 1e-9;

/// Share of the accuracy the C2 spline's least-squares fit may use at the chain's points; the
/// rest covers the spline between them and the polyline standing in for the chain.
pub const C2_FIT_FRACTION: f64 = 0.5;

/// The chain is sampled for the C2 fit so densely that its polyline is within this share of the
/// accuracy of the chain (spacing `√(8·share·accuracy/κ_max)`).
pub const C2_CHORD_FRACTION: f64 = 0.05;

/// Most chain points the C2 fit takes: beyond, the piece is written in Bézier form.
pub const C2_MAX_POINTS: usize = 20_000;

/// Points per knot span at which the C2 spline is measured against the chain.
pub const C2_CHECKS_PER_SPAN: usize = 16;

/// How a piece's spline is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SplineForm {
    /// The chain's Bézier cubics as one B-spline with triple interior knots: the LAC chain
    /// itself within the accuracy, joints included, but only C0 in its parameter (G1 as drawn).
    Bezier,
    /// A cubic B-spline with simple knots (C2) fitted to the chain within the accuracy: what a
    /// CAD tool expects of a curvature-continuous curve. Written for G2 and C3 chains without a
    /// corner inside when it holds the accuracy; its curvature follows the chain's to within
    /// what the accuracy allows, not exactly.
    C2,
}

/// Options of [`dxf_drawing`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DxfOptions {
    /// Largest distance between the splines and the exact LAC chain. Default `None`: a tenth of
    /// the fitting tolerance ([`super::DEFAULT_ACCURACY_FRACTION`]).
    pub accuracy: Option<f64>,
}

/// What was written for one fitted piece.
#[derive(Clone, Debug, PartialEq)]
pub struct DxfSplineReport {
    /// Index of the stroke.
    pub stroke: usize,
    /// Cubics per LAC segment, in order.
    pub cubics: Vec<usize>,
    /// Largest measured distance between the spline and the chain.
    pub error: f64,
    /// How it was written.
    pub form: SplineForm,
}

/// A DXF drawing and what it holds.
#[derive(Clone, Debug)]
pub struct DxfExport {
    /// The drawing (write it with [`DxfExport::to_bytes`] or the `dxf` crate).
    pub drawing: Drawing,
    /// The accuracy the splines were written to.
    pub accuracy: f64,
    /// One report per SPLINE entity, in order (pieces without a chain are left out).
    pub splines: Vec<DxfSplineReport>,
}

/// The DXF could not be written.
#[derive(Debug, thiserror::Error)]
#[error("writing DXF: {0}")]
pub struct DxfWriteError(#[from] dxf::DxfError);

impl DxfExport {
    /// The largest measured error over every spline.
    pub fn max_error(&self) -> f64 {
        self.splines.iter().map(|s| s.error).fold(0.0, f64::max)
    }

    /// The drawing as ASCII DXF.
    pub fn to_bytes(&self) -> Result<Vec<u8>, DxfWriteError> {
        let mut out = Vec::new();
        self.drawing.save(&mut out)?;
        Ok(out)
    }
}

/// The `$INSUNITS` of data in `units`.
pub const fn dxf_units(units: Units) -> DxfUnits {
    match units {
        Units::Mm => DxfUnits::Millimeters,
        Units::Px | Units::Device => DxfUnits::Unitless,
    }
}

/// The knots and control points of a chain of cubics (each ending where the next starts) as
/// one clamped cubic B-spline with triple interior knots; zero-length cubics are dropped.
/// Returns `None` when nothing is left.
pub fn bezier_chain_spline(cubics: &[CubicBez]) -> Option<(Vec<f64>, Vec<kurbo::Point>)> {
    let mut knots = vec![0.0; 4];
    let mut points = Vec::new();
    let mut total = 0.0;
    for c in cubics {
        let length = c.arclen(KNOT_ARCLEN_ACCURACY * (c.p3 - c.p0).hypot().max(f64::MIN_POSITIVE));
        if !(length > 0.0) || !length.is_finite() {
            continue;
        }
        if points.is_empty() {
            points.push(c.p0);
        }
        points.extend([c.p1, c.p2, c.p3]);
        total += length;
        knots.extend([total; 3]);
    }
    if points.is_empty() {
        return None;
    }
    // The last knot has multiplicity 4 (clamped end).
    knots.push(total);
    Some((knots, points))
}

/// The DXF drawing of a fit (see the module documentation).
pub fn dxf_drawing(output: &FitOutput, options: &DxfOptions) -> DxfExport {
    let accuracy = export_accuracy(options.accuracy, output.tolerance);
    let mut drawing = Drawing::new();
    drawing.header.version = AcadVersion::R2000;
    drawing.header.default_drawing_units = dxf_units(output.units);
    let mut splines = Vec::new();
    for fit in &output.curves {
        let Some(chain) = fit.chain.as_ref() else {
            continue;
        };
        let mut cubics = Vec::new();
        let mut counts = Vec::new();
        let mut error: f64 = 0.0;
        for cs in &chain.segments {
            let b = segment_beziers(&cs.segment, accuracy);
            counts.push(b.cubics.len());
            error = error.max(b.error);
            // Share the joint: the next segment starts where this chain ends.
            let mut seg_cubics = b.cubics;
            if let (Some(prev), Some(first)) = (cubics.last(), seg_cubics.first_mut()) {
                let prev: &CubicBez = prev;
                first.p0 = prev.p3;
            }
            cubics.extend(seg_cubics);
        }
        // A curvature-continuous chain as a C2 spline where one holds the accuracy; not one
        // with a corner inside (a hook the smooth fit left G0): a C2 spline would follow the
        // corner within the accuracy by a tight bend, hiding from a CAD user the corner that the
        // Bézier form keeps (a knot of multiplicity three there).
        let cornered = chain
            .segments
            .iter()
            .skip(1)
            .any(|s| s.start == JointKind::Corner);
        let c2 = (chain.continuity != Continuity::G1 && !cornered)
            .then(|| c2_spline(chain, accuracy))
            .flatten();
        let (form, knots, points) = match c2 {
            Some((knots, points, c2_error)) => {
                error = c2_error;
                (SplineForm::C2, knots, points)
            }
            None => {
                let Some((knots, points)) = bezier_chain_spline(&cubics) else {
                    continue;
                };
                (SplineForm::Bezier, knots, points)
            }
        };
        if points.iter().any(|p| !(p.x.is_finite() && p.y.is_finite())) {
            continue;
        }
        let mut spline = Spline {
            degree_of_curve: 3,
            knot_values: knots,
            control_points: points
                .iter()
                .map(|p| DxfPoint::new(p.x, p.y, 0.0))
                .collect(),
            ..Spline::default()
        };
        spline.set_is_planar(true);
        // A stroke closed in one piece is a closed spline (flag 1): its ends meet (a clamped
        // spline, not a periodic one).
        spline.set_is_closed(fit.closure.is_some_and(|c| c.whole));
        drawing.add_entity(Entity::new(EntityType::Spline(spline)));
        splines.push(DxfSplineReport {
            stroke: fit.stroke,
            cubics: counts,
            error,
            form,
        });
    }
    // Dots (taps) are POINT entities: exact, as a CAD user expects of a single position.
    for dot in &output.dots {
        let p = dot.point;
        if p.x.is_finite() && p.y.is_finite() {
            let point = ModelPoint::new(DxfPoint::new(p.x, p.y, 0.0));
            drawing.add_entity(Entity::new(EntityType::ModelPoint(point)));
        }
    }
    DxfExport {
        drawing,
        accuracy,
        splines,
    }
}

/// A C2 cubic B-spline within `accuracy` of the chain, with its knots (scaled to the chain's
/// length, so the parameter runs at about unit speed), control points and measured error:
/// the chain sampled densely ([`C2_CHORD_FRACTION`]), a plain least-squares B-spline fitted to
/// those points within [`C2_FIT_FRACTION`] of the accuracy with its ends on the chain's, then
/// measured both ways (the chain's points to the spline, and the spline at
/// [`C2_CHECKS_PER_SPAN`] points per span to the chain's polyline, plus that polyline's own
/// chord error). `None` where that misses the accuracy or cannot be built.
pub fn c2_spline(chain: &Chain, accuracy: f64) -> Option<(Vec<f64>, Vec<kurbo::Point>, f64)> {
    if !(accuracy.is_finite() && accuracy > 0.0) {
        return None;
    }
    let kappa_max = chain
        .segments
        .iter()
        .map(|s| s.segment.kappa0().abs().max(s.segment.kappa1().abs()))
        .fold(0.0, f64::max);
    let total: f64 = chain.segments.iter().map(|s| s.segment.length()).sum();
    let chord = C2_CHORD_FRACTION * accuracy;
    let spacing = if kappa_max > 0.0 {
        (8.0 * chord / kappa_max).sqrt()
    } else {
        total
    }
    .min(total / 8.0);
    if !(spacing > 0.0 && (total / spacing) < C2_MAX_POINTS as f64) {
        return None;
    }
    let mut points: Vec<Point> = Vec::new();
    for s in &chain.segments {
        for p in s.segment.samples(spacing) {
            if points.last() != Some(&p.point) {
                points.push(p.point);
            }
        }
    }
    let (first, last) = (*points.first()?, *points.last()?);
    let options = FitOptions::new(C2_FIT_FRACTION * accuracy)
        .with_fairing(false)
        .with_ends(Some(first), Some(last));
    let fit = fit_bspline(&points, &options).ok()?;
    if !fit.within_tolerance {
        return None;
    }
    // The spline between the chain's points, against the chain's polyline (near each check's
    // foot: the points' parameters on the spline are in order).
    let curve = &fit.curve;
    let knots = curve.knots();
    let mut back: f64 = 0.0;
    for w in knots.windows(2).filter(|w| w[1] > w[0]) {
        for k in 0..=C2_CHECKS_PER_SPAN {
            let u = w[0] + (w[1] - w[0]) * k as f64 / C2_CHECKS_PER_SPAN as f64;
            let q = curve.eval(u);
            let i = fit.params.partition_point(|&v| v < u).min(points.len() - 1);
            let lo = i.saturating_sub(3);
            let hi = (i + 3).min(points.len() - 1);
            let d = (lo..hi)
                .map(|j| crate::geom::distance_to_segment(q, points[j], points[j + 1]))
                .fold(f64::INFINITY, f64::min);
            back = back.max(d);
        }
    }
    let error = fit.max_deviation.max(back) + chord;
    if !(error <= accuracy) {
        return None;
    }
    let scaled: Vec<f64> = knots.iter().map(|k| k * total).collect();
    Some((scaled, curve.control_points().to_vec(), error))
}
