//! The scene's overlays, each a function drawing onto the pixmap through the [`View`]: samples,
//! B-spline, control polygon, LAC segments, highlight, curvature comb and split markers.

use super::colour::{
    BSPLINE, COMB, CONTROL_POLYGON, CORNER, EXTREMUM, HIGHLIGHT, INFLECTION, MARKER_OUTLINE,
    SAMPLE, segment_colour,
};
use super::options::RenderOptions;
use super::primitives::{MarkerShape, cubics, dot, marker, polyline, stroke};
use super::scene::Scene;
use super::view::View;
use crate::geom::{CubicBez, Point, Vec2};
use crate::lac::LacSegment;
use crate::split::SplitKind;
use kurbo::{Arc, PathEl};
use tiny_skia::{Path, Pixmap};

/// Spacing of the evaluated LAC points, pixels: a quarter pixel keeps the polyline's chord error
/// below 1/32 px for any curve whose radius is at least a pixel (sagitta h²/8r), invisible.
pub const SEGMENT_STEP_PX: f64 = 0.25;

/// Most points evaluated per LAC segment: beyond, the spacing widens (a segment hundreds of
/// thousands of pixels long is mostly off the image at that zoom).
pub const MAX_SEGMENT_POINTS: usize = 100_000;

/// Chord error of the Béziers approximating a circular arc, pixels.
pub const ARC_TOLERANCE_PX: f64 = 0.05;

/// Curvatures sampled per segment by [`auto_comb_scale`] (evenly in arc length, ends included).
pub const COMB_SCALE_SAMPLES: usize = 17;

/// [`auto_comb_scale`] gives the |κ| at this quantile a tooth of [`COMB_HEIGHT_FRACTION`] of the
/// scene's diagonal: the 95th percentile ignores the few sharp curls a sketch has, which would
/// otherwise flatten the rest of the comb.
pub const COMB_QUANTILE: f64 = 0.95;

/// Length of the reference tooth of [`auto_comb_scale`], as a fraction of the scene's diagonal.
pub const COMB_HEIGHT_FRACTION: f64 = 0.1;

/// Arc-length spacing (model units) at which a segment is evaluated in `view`:
/// [`SEGMENT_STEP_PX`] pixels, widened to keep at most [`MAX_SEGMENT_POINTS`] points.
pub fn segment_spacing(segment: &LacSegment, view: &View) -> f64 {
    let length = segment.length();
    (SEGMENT_STEP_PX / view.pixels_per_unit).max(length / (MAX_SEGMENT_POINTS - 1) as f64)
}

/// The path of `segment` in pixels: an LAC is evaluated exactly ([`LacSegment::samples`] at
/// [`segment_spacing`]); a circular arc (α = null, κ0 = κ1 ≠ 0) becomes kurbo's arc Béziers
/// within [`ARC_TOLERANCE_PX`]; a line its two ends.
pub fn segment_path(segment: &LacSegment, view: &View) -> Option<Path> {
    let kappa = segment.kappa0();
    if segment.alpha().is_some() || kappa != segment.kappa1() {
        let spacing = segment_spacing(segment, view);
        return polyline(segment.samples(spacing).map(|s| view.to_pixel(s.point)));
    }
    if kappa == 0.0 {
        return polyline([segment.start(), segment.end()].map(|p| view.to_pixel(p)));
    }
    // The centre lies 1/κ along the left normal (−sin θ0, cos θ0); the angle about it moves by
    // κ per unit length (dφ/ds = κ whichever the sign).
    let (sin, cos) = segment.theta0().sin_cos();
    let centre = segment.start() + Vec2::new(-sin, cos) / kappa;
    let radius = 1.0 / kappa.abs();
    let start_angle = (segment.start() - centre).atan2();
    let arc = Arc::new(
        centre,
        Vec2::new(radius, radius),
        start_angle,
        kappa * segment.length(),
        0.0,
    );
    let tolerance = ARC_TOLERANCE_PX / view.pixels_per_unit;
    let mut pieces = Vec::new();
    let mut pen = view.to_pixel(segment.start());
    for el in arc.append_iter(tolerance) {
        match el {
            PathEl::MoveTo(p) => pen = view.to_pixel(p),
            PathEl::CurveTo(a, b, c) => {
                let bez = CubicBez::new(pen, view.to_pixel(a), view.to_pixel(b), view.to_pixel(c));
                pen = bez.p3;
                pieces.push(bez);
            }
            PathEl::LineTo(p) | PathEl::QuadTo(_, p) => {
                let q = view.to_pixel(p);
                pieces.push(CubicBez::new(
                    pen,
                    pen.lerp(q, 1.0 / 3.0),
                    pen.lerp(q, 2.0 / 3.0),
                    q,
                ));
                pen = q;
            }
            PathEl::ClosePath => {}
        }
    }
    cubics(pieces)
}

/// Every LAC segment of the scene with its curve and chain index.
fn segments<'a>(scene: &'a Scene) -> impl Iterator<Item = (usize, usize, &'a LacSegment)> + 'a {
    scene.curves.iter().enumerate().flat_map(|(c, curve)| {
        curve
            .chain
            .iter()
            .flat_map(|chain| chain.segments.iter().enumerate())
            .map(move |(s, seg)| (c, s, &seg.segment))
    })
}

/// LAC segments coloured by α.
pub fn draw_segments(pixmap: &mut Pixmap, scene: &Scene, view: &View, options: &RenderOptions) {
    for (_, _, segment) in segments(scene) {
        if let Some(path) = segment_path(segment, view) {
            let colour = segment_colour(segment.alpha());
            stroke(pixmap, &path, colour, options.segment_width);
        }
    }
}

/// The highlighted segment's band (nothing if the index names no segment).
pub fn draw_highlight(pixmap: &mut Pixmap, scene: &Scene, view: &View, options: &RenderOptions) {
    let Some((c, s)) = options.highlight else {
        return;
    };
    let found = scene
        .curves
        .get(c)
        .and_then(|curve| curve.chain.as_ref())
        .and_then(|chain| chain.segments.get(s));
    if let Some(path) = found.and_then(|seg| segment_path(&seg.segment, view)) {
        stroke(pixmap, &path, HIGHLIGHT, options.highlight_width);
    }
}

/// The B-splines as pale halos.
pub fn draw_bspline(pixmap: &mut Pixmap, scene: &Scene, view: &View, options: &RenderOptions) {
    for curve in scene.curves {
        let pieces = curve.bspline.curve.to_beziers().into_iter().map(|p| {
            let b = p.bez;
            CubicBez::new(
                view.to_pixel(b.p0),
                view.to_pixel(b.p1),
                view.to_pixel(b.p2),
                view.to_pixel(b.p3),
            )
        });
        if let Some(path) = cubics(pieces) {
            stroke(pixmap, &path, BSPLINE, options.bspline_width);
        }
    }
}

/// The control polygons, with a square (side 3 × the line width) at each control point.
pub fn draw_control_polygon(
    pixmap: &mut Pixmap,
    scene: &Scene,
    view: &View,
    options: &RenderOptions,
) {
    let width = options.control_polygon_width;
    for curve in scene.curves {
        let points: Vec<Point> = curve
            .bspline
            .curve
            .control_points()
            .iter()
            .map(|&p| view.to_pixel(p))
            .collect();
        if let Some(path) = polyline(points.iter().copied()) {
            stroke(pixmap, &path, CONTROL_POLYGON, width);
        }
        for &p in &points {
            if let Some(path) = super::primitives::marker_path(MarkerShape::Square, p, 3.0 * width)
            {
                super::primitives::fill(pixmap, &path, CONTROL_POLYGON);
            }
        }
    }
}

/// The radius of a sample's dot: [`RenderOptions::sample_radius`] × (0.5 + pressure), the
/// pressure clamped to [0, 1]; without a (finite) pressure, the plain radius.
pub fn sample_radius(pressure: Option<f64>, radius: f64) -> f64 {
    match pressure.filter(|p| p.is_finite()) {
        Some(p) => radius * (0.5 + p.clamp(0.0, 1.0)),
        None => radius,
    }
}

/// The raw samples of every stroke.
pub fn draw_samples(pixmap: &mut Pixmap, scene: &Scene, view: &View, options: &RenderOptions) {
    for sample in scene.strokes.iter().flat_map(|s| s.samples.iter()) {
        let r = sample_radius(sample.pressure, options.sample_radius);
        dot(pixmap, view.to_pixel(sample.point()), r, SAMPLE);
    }
}

/// The split markers (see [`MarkerShape::for_split`]).
pub fn draw_splits(pixmap: &mut Pixmap, scene: &Scene, view: &View, options: &RenderOptions) {
    for split in scene.curves.iter().flat_map(|c| c.spans.splits.iter()) {
        let fill = match split.kind {
            SplitKind::Inflection => INFLECTION,
            SplitKind::CurvatureExtremum => EXTREMUM,
            SplitKind::Corner => CORNER,
            SplitKind::Start | SplitKind::End => MARKER_OUTLINE,
        };
        marker(
            pixmap,
            MarkerShape::for_split(split.kind),
            view.to_pixel(split.point),
            options.marker_size,
            fill,
            MARKER_OUTLINE,
        );
    }
}

/// The comb scale (model units²) that gives the [`COMB_QUANTILE`] of |κ| over the scene's LAC
/// segments ([`COMB_SCALE_SAMPLES`] per segment) a tooth of [`COMB_HEIGHT_FRACTION`] of the
/// diagonal of [`scene_bounds`](super::scene_bounds). `None` without segments or curvature.
pub fn auto_comb_scale(scene: &Scene) -> Option<f64> {
    let diagonal = super::scene_bounds(scene).map(|b| b.width().hypot(b.height()))?;
    let mut kappas: Vec<f64> = segments(scene)
        .flat_map(|(_, _, seg)| {
            (0..COMB_SCALE_SAMPLES).map(move |i| {
                let s = seg.length() * i as f64 / (COMB_SCALE_SAMPLES - 1) as f64;
                seg.kappa(s).abs()
            })
        })
        .filter(|k| k.is_finite())
        .collect();
    if kappas.is_empty() {
        return None;
    }
    kappas.sort_by(f64::total_cmp);
    // Nearest-rank quantile.
    let rank = ((COMB_QUANTILE * kappas.len() as f64).ceil() as usize).clamp(1, kappas.len());
    let reference = kappas[rank - 1];
    let scale = COMB_HEIGHT_FRACTION * diagonal / reference;
    (scale.is_finite() && scale > 0.0).then_some(scale)
}

/// The curvature comb of each chain: a tooth every [`RenderOptions::comb_spacing`] pixels,
/// from the curve along −κ·scale·n (n the left normal, so teeth stand on the convex side, away
/// from the centre of curvature), and the envelope through the teeth's tips.
pub fn draw_comb(pixmap: &mut Pixmap, scene: &Scene, view: &View, options: &RenderOptions) {
    let Some(scale) = options.comb_scale.or_else(|| auto_comb_scale(scene)) else {
        return;
    };
    let line = options.control_polygon_width.max(1.0);
    for curve in scene.curves {
        let Some(chain) = &curve.chain else {
            continue;
        };
        let mut envelope = Vec::new();
        let mut teeth = tiny_skia::PathBuilder::new();
        for seg in &chain.segments {
            let segment = &seg.segment;
            let spacing = (options.comb_spacing / view.pixels_per_unit)
                .max(segment.length() / (MAX_SEGMENT_POINTS - 1) as f64);
            for s in segment.samples(spacing) {
                let (sin, cos) = s.theta.sin_cos();
                let tip = s.point - Vec2::new(-sin, cos) * (s.kappa * scale);
                let (a, b) = (view.to_pixel(s.point), view.to_pixel(tip));
                if let (Some(a), Some(b)) =
                    (super::primitives::to_f32(a), super::primitives::to_f32(b))
                {
                    teeth.move_to(a.0, a.1);
                    teeth.line_to(b.0, b.1);
                }
                envelope.push(b);
            }
        }
        if let Some(path) = teeth.finish() {
            stroke(pixmap, &path, COMB, 0.5 * line);
        }
        if let Some(path) = polyline(envelope) {
            stroke(pixmap, &path, COMB, line);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_radius_follows_pressure() {
        assert_eq!(sample_radius(None, 2.0), 2.0);
        assert_eq!(sample_radius(Some(0.0), 2.0), 1.0);
        assert_eq!(sample_radius(Some(1.0), 2.0), 3.0);
        assert_eq!(sample_radius(Some(7.0), 2.0), 3.0);
        assert_eq!(sample_radius(Some(f64::NAN), 2.0), 2.0);
    }
}
