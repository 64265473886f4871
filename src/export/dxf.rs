//! The DXF export: one cubic `SPLINE` entity per fitted piece, written with the `dxf` crate.
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
//! Numbers are written by the `dxf` crate with 12 decimals (an absolute rounding of at most
//! 5·10⁻¹³ in the data's units, negligible beside any accuracy).
//!
//! The header says `$ACADVER` AC1015 (R2000: the oldest version with `$INSUNITS`; SPLINE needs
//! R13) and `$INSUNITS` 4 (millimetres) for mm data, 0 (unitless) for px and device counts.

use dxf::entities::{Entity, EntityType, ModelPoint, Spline};
use dxf::enums::{AcadVersion, Units as DxfUnits};
use dxf::{Drawing, Point as DxfPoint};
use kurbo::{CubicBez, ParamCurveArclen};

use crate::pipeline::FitOutput;
use crate::stroke::Units;

use super::bezier::segment_beziers;
use super::svg::export_accuracy;

/// Relative accuracy of the cubics' arc lengths used as knots (they only set the parameter
/// speed, never the shape).
const KNOT_ARCLEN_ACCURACY: f64 = 1e-9;

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
        let Some((knots, points)) = bezier_chain_spline(&cubics) else {
            continue;
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
        drawing.add_entity(Entity::new(EntityType::Spline(spline)));
        splines.push(DxfSplineReport {
            stroke: fit.stroke,
            cubics: counts,
            error,
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
