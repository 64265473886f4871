//! LAC segments as cubic Béziers within a stated error, through kurbo's curve fitting.
//!
//! [`LacCurve`] is the adapter that lets kurbo's fitter ([`kurbo::fit_to_bezpath`]) sample a
//! segment: the fitting parameter is the arc-length fraction t = s/S, so the derivative is
//! dP/dt = S·(cos θ(s), sin θ(s)) (an LAC is parametrised by arc length: |dP/ds| = 1).
//!
//! kurbo estimates its error from 20 samples per cubic; [`segment_beziers`] then *measures* the
//! distance between the cubics and the exact segment both ways (see [`bezier_error`]) and, when
//! the measure exceeds the accuracy asked for, halves that part of the segment by arc length and
//! fits each half again (at most [`MAX_SPLIT_DEPTH`] levels). The result carries the measured
//! error, so what a file states is what was checked.
//!
//! Lines become one exact cubic (control points at the thirds); arcs and spirals go through the
//! fitter. The SVG writer draws arcs and lines exactly with `A`/`L` instead.

use std::ops::Range;

use kurbo::{
    BezPath, CubicBez, CurveFitSample, ParamCurve, ParamCurveFit, ParamCurveNearest, PathEl,
};

use crate::geom::{Point, Vec2};
use crate::lac::LacSegment;

use super::svg::lac_spacing;

/// The default export accuracy as a fraction of the fitting tolerance: a tenth keeps the export
/// error an order of magnitude below the error the fit already allows, so the exported curve is,
/// for every purpose, the fitted one.
pub const DEFAULT_ACCURACY_FRACTION: f64 = 0.1;

/// How many times [`segment_beziers`] may halve a part of a segment whose fit measures beyond
/// the accuracy: 2¹² parts bound the work; a part still beyond it at that depth is kept as
/// fitted, and its measured error reported (not observed on the fixtures).
pub const MAX_SPLIT_DEPTH: usize = 12;

/// Points measured on each cubic when checking it against the segment (besides its ends, which
/// lie on the segment by construction). 32 points on a cubic that is within a tenth of the
/// tolerance of a monotone-curvature curve leave gaps far shorter than any feature of either.
pub const CHECK_POINTS_PER_CUBIC: usize = 32;

/// The exact segment is represented, for measuring, by a polyline within this fraction of the
/// accuracy of it ([`lac_spacing`]); that chord error is added to every cubic-to-segment
/// distance, so the measure is an upper bound at the measured points.
pub const REFERENCE_CHORD_FRACTION: f64 = 0.01;

/// Relative accuracy of kurbo's nearest-point search when measuring segment-to-cubic distances
/// (a fraction of the export accuracy).
const NEAREST_ACCURACY_FRACTION: f64 = 1e-3;

/// A [`LacSegment`], or the part of it between two arc lengths, seen by kurbo's curve fitter:
/// parameter t ∈ [0, 1] is the arc-length fraction of that part.
#[derive(Clone, Copy, Debug)]
pub struct LacCurve<'a> {
    segment: &'a LacSegment,
    s0: f64,
    s1: f64,
}

impl<'a> LacCurve<'a> {
    /// The adapter for the whole of `segment`.
    pub fn new(segment: &'a LacSegment) -> Self {
        LacCurve {
            segment,
            s0: 0.0,
            s1: segment.length(),
        }
    }

    /// The adapter for the part of `segment` between arc lengths `s0` and `s1` (clamped to the
    /// segment).
    pub fn part(segment: &'a LacSegment, s0: f64, s1: f64) -> Self {
        let clamp = |s: f64| s.clamp(0.0, segment.length());
        LacCurve {
            segment,
            s0: clamp(s0),
            s1: clamp(s1),
        }
    }

    /// Arc length on the segment of parameter `t`.
    fn arc_length(&self, t: f64) -> f64 {
        self.s0 + t * (self.s1 - self.s0)
    }
}

impl ParamCurveFit for LacCurve<'_> {
    /// The point and the derivative at t: an LAC has a continuous tangent everywhere (its
    /// curvature is finite), so `sign` (which side of a corner) does not matter.
    fn sample_pt_tangent(&self, t: f64, _sign: f64) -> CurveFitSample {
        let (p, tangent) = self.sample_pt_deriv(t);
        CurveFitSample { p, tangent }
    }

    /// P(s) and dP/dt = (s1 − s0)·(cos θ(s), sin θ(s)), s = s0 + t·(s1 − s0).
    fn sample_pt_deriv(&self, t: f64) -> (Point, Vec2) {
        let s = self.arc_length(t);
        (
            self.segment.point(s),
            Vec2::from_angle(self.segment.theta(s)) * (self.s1 - self.s0),
        )
    }

    /// None: the curvature of an LAC segment is finite and monotonic between its two finite end
    /// values, so it has neither cusps nor corners. (Its largest curvature is at an end, which
    /// kurbo asks us never to report.)
    fn break_cusp(&self, _range: Range<f64>) -> Option<f64> {
        None
    }
}

/// A segment as cubic Béziers, and how far they are from it.
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentBeziers {
    /// The cubics, joined end to end, from the segment's start to its end.
    pub cubics: Vec<CubicBez>,
    /// The measured distance between the cubics and the segment ([`bezier_error`]).
    pub error: f64,
}

/// The cubics of a kurbo path (its first move-to and its curve-tos; kurbo's fitter emits only
/// those, and a line-to becomes a cubic with control points at the thirds).
fn cubics_of(path: &BezPath) -> Vec<CubicBez> {
    let mut out = Vec::new();
    let mut pen = Point::ORIGIN;
    for el in path.elements() {
        match *el {
            PathEl::MoveTo(p) => pen = p,
            PathEl::LineTo(p) => {
                out.push(CubicBez::new(
                    pen,
                    pen.lerp(p, 1.0 / 3.0),
                    pen.lerp(p, 2.0 / 3.0),
                    p,
                ));
                pen = p;
            }
            PathEl::QuadTo(p1, p2) => {
                out.push(kurbo::QuadBez::new(pen, p1, p2).raise());
                pen = p2;
            }
            PathEl::CurveTo(p1, p2, p3) => {
                out.push(CubicBez::new(pen, p1, p2, p3));
                pen = p3;
            }
            PathEl::ClosePath => {}
        }
    }
    out
}

/// The line from `a` to `b` as a cubic (control points at the thirds: exact, uniform speed).
fn line_cubic(a: Point, b: Point) -> CubicBez {
    CubicBez::new(a, a.lerp(b, 1.0 / 3.0), a.lerp(b, 2.0 / 3.0), b)
}

/// Distance from `p` to the segment a–b.
fn distance_to_chord(p: Point, a: Point, b: Point) -> f64 {
    let ab = b - a;
    let len2 = ab.hypot2();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).hypot()
}

/// The exact segment for measuring: its points every [`lac_spacing`] (chord error
/// [`REFERENCE_CHORD_FRACTION`] × the accuracy), with their arc lengths.
struct Reference {
    s: Vec<f64>,
    points: Vec<Point>,
    chord: f64,
}

impl Reference {
    fn new(segment: &LacSegment, accuracy: f64) -> Self {
        let chord = REFERENCE_CHORD_FRACTION * accuracy;
        let (s, points) = segment
            .samples(lac_spacing(segment, chord))
            .map(|x| (x.s, x.point))
            .unzip();
        Reference { s, points, chord }
    }

    /// The polyline of the part between arc lengths `s0` and `s1`: its exact end points and the
    /// reference points strictly between.
    fn part(&self, segment: &LacSegment, s0: f64, s1: f64) -> Vec<Point> {
        let mut out = vec![segment.point(s0)];
        out.extend(
            self.s
                .iter()
                .zip(&self.points)
                .filter(|(s, _)| **s > s0 && **s < s1)
                .map(|(_, p)| *p),
        );
        out.push(segment.point(s1));
        out
    }
}

/// The two-sided distance between `cubics` and the part of `segment` whose polyline is
/// `reference` (see [`bezier_error`]).
fn measure(reference: &[Point], chord: f64, cubics: &[CubicBez], accuracy: f64) -> f64 {
    let nearest_accuracy = NEAREST_ACCURACY_FRACTION * accuracy;
    let mut worst: f64 = 0.0;
    for &p in reference {
        let d2 = cubics
            .iter()
            .map(|c| c.nearest(p, nearest_accuracy).distance_sq)
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(d2.sqrt());
    }
    for c in cubics {
        for i in 1..=CHECK_POINTS_PER_CUBIC {
            let q = c.eval(i as f64 / (CHECK_POINTS_PER_CUBIC + 1) as f64);
            let d = reference
                .windows(2)
                .map(|w| distance_to_chord(q, w[0], w[1]))
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d + chord);
        }
    }
    worst
}

/// The largest distance between `cubics` and `segment`, measured both ways:
///
/// * from the segment: its points every [`lac_spacing`] (chord error
///   [`REFERENCE_CHORD_FRACTION`] × `accuracy`) to the nearest cubic (kurbo's nearest point);
/// * from the cubics: [`CHECK_POINTS_PER_CUBIC`] points on each to that polyline, plus the
///   polyline's chord error (the polyline lies within it of the segment, so this bounds the
///   distance to the segment itself).
///
/// This is the two-sided (Hausdorff) distance at the measured points. `accuracy` only sets the
/// measuring resolution.
pub fn bezier_error(segment: &LacSegment, cubics: &[CubicBez], accuracy: f64) -> f64 {
    let reference = Reference::new(segment, accuracy);
    measure(&reference.points, reference.chord, cubics, accuracy)
}

/// Fits the part of `segment` between arc lengths `s0` and `s1`, appending its cubics to `out`;
/// returns their measured error. A part kurbo's fit misses (measured beyond `accuracy`) is
/// halved by arc length, down to [`MAX_SPLIT_DEPTH`] levels.
fn fit_part(
    segment: &LacSegment,
    reference: &Reference,
    (s0, s1): (f64, f64),
    accuracy: f64,
    depth: usize,
    out: &mut Vec<CubicBez>,
) -> f64 {
    let source = LacCurve::part(segment, s0, s1);
    let mut cubics = cubics_of(&kurbo::fit_to_bezpath(&source, accuracy));
    let (a, b) = (segment.point(s0), segment.point(s1));
    if let Some(first) = cubics.first_mut() {
        first.p0 = a;
    }
    if let Some(last) = cubics.last_mut() {
        last.p3 = b;
    }
    if cubics.is_empty() {
        cubics.push(line_cubic(a, b));
    }
    let error = measure(
        &reference.part(segment, s0, s1),
        reference.chord,
        &cubics,
        accuracy,
    );
    if error <= accuracy || depth >= MAX_SPLIT_DEPTH {
        out.extend(cubics);
        return error;
    }
    let mid = 0.5 * (s0 + s1);
    let left = fit_part(segment, reference, (s0, mid), accuracy, depth + 1, out);
    let right = fit_part(segment, reference, (mid, s1), accuracy, depth + 1, out);
    left.max(right)
}

/// `segment` as cubic Béziers within `accuracy` of it (measured; see the module documentation).
///
/// A line is one exact cubic (error 0). Otherwise kurbo's [`kurbo::fit_to_bezpath`] fits the
/// segment (recursive halving by arc length; its optimising sibling `fit_to_bezpath_opt` can
/// panic in kurbo 0.13, kurbo issue #601). kurbo judges its fit from 20 samples per cubic,
/// which a hook (curvature falling by orders of magnitude within the first percent of the
/// length) can fool; so the result is measured ([`bezier_error`]), and a part measured beyond
/// the accuracy is halved and fitted again. The ends are the segment's exact end points, so
/// consecutive segments share their joints bit for bit. A non-positive or non-finite
/// `accuracy` is replaced by [`FALLBACK_ACCURACY_FRACTION`] of the segment's length.
pub fn segment_beziers(segment: &LacSegment, accuracy: f64) -> SegmentBeziers {
    if segment.kappa0() == 0.0 && segment.kappa1() == 0.0 {
        return SegmentBeziers {
            cubics: vec![line_cubic(segment.start(), segment.end())],
            error: 0.0,
        };
    }
    let accuracy = if accuracy.is_finite() && accuracy > 0.0 {
        accuracy
    } else {
        FALLBACK_ACCURACY_FRACTION * segment.length()
    };
    let reference = Reference::new(segment, accuracy);
    let mut cubics = Vec::new();
    let error = fit_part(
        segment,
        &reference,
        (0.0, segment.length()),
        accuracy,
        0,
        &mut cubics,
    );
    SegmentBeziers { cubics, error }
}

/// The accuracy used when the one given is not a positive number: this fraction of the
/// segment's length (a thousandth: invisible at the size the segment is drawn).
pub const FALLBACK_ACCURACY_FRACTION: f64 = 1e-3;
