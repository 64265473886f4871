//! The scene's overlays, each a function drawing onto the pixmap through the [`View`]: samples,
//! B-spline, control polygon, LAC segments, highlight, curvature comb and split markers.

use super::colour::{
    BSPLINE, COMB, CONTROL_POLYGON, CORNER, EXTREMUM, HIGHLIGHT, INFLECTION, INK, MARKER_OUTLINE,
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

/// Longest step between evaluated LAC points, pixels: a straight-ish segment still gets a point
/// every two pixels.
pub const SEGMENT_STEP_PX: f64 = 2.0;

/// Largest distance between the drawn polyline and the exact LAC, pixels: a twentieth of a
/// pixel is invisible (anti-aliasing resolves about a sixteenth of a pixel's coverage).
pub const SEGMENT_CHORD_ERROR_PX: f64 = 0.05;

/// Shortest step between evaluated LAC points, pixels: it binds only where the radius of
/// curvature is under half a pixel, where the curl is a blob of a pixel or two whatever its
/// shape and finer steps only cost.
pub const SEGMENT_MIN_STEP_PX: f64 = 0.25;

/// Largest turning of the LAC between two evaluated points, radians: keeps the sagitta bound
/// of [`segment_spacing`] valid (it needs the turning per step well below π).
pub const SEGMENT_MAX_TURNING: f64 = 0.5;

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

/// Longest comb tooth drawn, as a fraction of the scene's diagonal: a tight curl's tooth (its κ
/// far above the quantile) is cut to this length instead of crossing the whole image.
pub const COMB_MAX_TOOTH_FRACTION: f64 = 0.3;

/// Size in pixels of the cross drawn on the tip of a comb tooth cut to
/// [`COMB_MAX_TOOTH_FRACTION`] (each arm's length): the mark that says the curvature there is
/// off the comb's scale.
pub const COMB_CLIP_MARK_PX: f64 = 8.0;

/// Length of the reference tooth of [`auto_comb_scale`], as a fraction of the scene's diagonal.
pub const COMB_HEIGHT_FRACTION: f64 = 0.1;

/// Pixels beyond a stroke's half width that culling keeps (anti-aliasing reaches about a pixel
/// past the geometry).
pub const CULL_PAD_PX: f64 = 2.0;

/// Distance in pixels from `p` to the image rectangle of `view` (0 inside; NaN for NaN).
fn distance_to_image(view: &View, p: Point) -> f64 {
    let dx = (-p.x).max(p.x - f64::from(view.width)).max(0.0);
    let dy = (-p.y).max(p.y - f64::from(view.height)).max(0.0);
    dx.hypot(dy)
}

/// Whether `segment` may show within `pad_px` pixels of the image (false only when it surely
/// does not). A curve of length L from A to B lies in the ellipse with foci A and B and major
/// axis L, hence in the disc of radius L/2 about the midpoint of AB; that disc is tested. Culling
/// keeps a zoomed-in view from evaluating the whole scene at pixel-sized steps.
pub fn segment_may_show(segment: &LacSegment, view: &View, pad_px: f64) -> bool {
    let mid = view.to_pixel(segment.start().midpoint(segment.end()));
    let radius = 0.5 * segment.length() * view.pixels_per_unit + pad_px;
    distance_to_image(view, mid) <= radius
}

/// Whether a cubic (in pixels) may show within `pad_px` pixels of the image: its control
/// points' box (which holds the curve) is tested.
fn cubic_may_show(bez: &CubicBez, view: &View, pad_px: f64) -> bool {
    let (w, h) = (f64::from(view.width), f64::from(view.height));
    let xs = [bez.p0.x, bez.p1.x, bez.p2.x, bez.p3.x];
    let ys = [bez.p0.y, bez.p1.y, bez.p2.y, bez.p3.y];
    let (x0, x1) = (
        xs.iter().copied().fold(f64::INFINITY, f64::min),
        xs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    let (y0, y1) = (
        ys.iter().copied().fold(f64::INFINITY, f64::min),
        ys.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    x1 >= -pad_px && x0 <= w + pad_px && y1 >= -pad_px && y0 <= h + pad_px
}

/// Arc-length spacing (model units) at which a segment is evaluated in `view`.
///
/// A step h on a curve with |κ| ≤ κ_max (monotonic along an LAC, so κ_max is the larger end) that
/// turns by less than π stays within the sagitta (1 − cos(κ_max·h/2))/κ_max ≤ κ_max·h²/8 of its
/// chord. So h = √(8·e/κ_max) with e = [`SEGMENT_CHORD_ERROR_PX`] in model units, at most
/// [`SEGMENT_MAX_TURNING`]/κ_max and [`SEGMENT_STEP_PX`] pixels, at least
/// [`SEGMENT_MIN_STEP_PX`] pixels (the other bounds are given up only inside curls of radius
/// below half a pixel), and widened to keep at most [`MAX_SEGMENT_POINTS`] points.
pub fn segment_spacing(segment: &LacSegment, view: &View) -> f64 {
    let length = segment.length();
    let k = view.pixels_per_unit;
    let kappa_max = segment.kappa0().abs().max(segment.kappa1().abs());
    let mut h = SEGMENT_STEP_PX / k;
    if kappa_max > 0.0 {
        let e = SEGMENT_CHORD_ERROR_PX / k;
        h = h
            .min((8.0 * e / kappa_max).sqrt())
            .min(SEGMENT_MAX_TURNING / kappa_max);
    }
    h.max(SEGMENT_MIN_STEP_PX / k)
        .max(length / (MAX_SEGMENT_POINTS - 1) as f64)
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
    // An arc whose sagitta κL²/8 is within the drawing tolerance is drawn as its chord: its
    // centre would lie 1/κ away (seen: 5e17 px for a refitted line with κ = 1.9e-18), where
    // the angles about it lose every digit of the arc's position.
    let sagitta_px = kappa.abs() * segment.length().powi(2) / 8.0 * view.pixels_per_unit;
    if kappa == 0.0 || sagitta_px <= ARC_TOLERANCE_PX {
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
    let pad = 0.5 * options.segment_width + CULL_PAD_PX;
    for (_, _, segment) in segments(scene) {
        if !segment_may_show(segment, view, pad) {
            continue;
        }
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
    let pad = 0.5 * options.highlight_width + CULL_PAD_PX;
    let shown = found.filter(|seg| segment_may_show(&seg.segment, view, pad));
    if let Some(path) = shown.and_then(|seg| segment_path(&seg.segment, view)) {
        stroke(pixmap, &path, HIGHLIGHT, options.highlight_width);
    }
}

/// The B-splines as pale halos.
pub fn draw_bspline(pixmap: &mut Pixmap, scene: &Scene, view: &View, options: &RenderOptions) {
    let pad = 0.5 * options.bspline_width + CULL_PAD_PX;
    for curve in scene.curves {
        let pieces = curve
            .bspline
            .curve
            .to_beziers()
            .into_iter()
            .map(|p| {
                let b = p.bez;
                CubicBez::new(
                    view.to_pixel(b.p0),
                    view.to_pixel(b.p1),
                    view.to_pixel(b.p2),
                    view.to_pixel(b.p3),
                )
            })
            .filter(|b| cubic_may_show(b, view, pad));
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
            SplitKind::Start | SplitKind::End | SplitKind::Seam => MARKER_OUTLINE,
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

/// Relative curvature jump up to which a joint is drawn as curvature-continuous: the G2
/// statement of the chain itself (its joints share one curvature, to rounding).
pub const CONTINUOUS_JUMP: f64 = 1e-9;

/// Half-length of a joint's bar, in marker sizes.
const JOINT_BAR_HALF: f64 = 0.7;

/// Width of a joint's bar, pixels.
const JOINT_BAR_WIDTH: f64 = 2.5;

/// The LAC joints: where two segments of a chain meet, a bar across the chain (along the
/// normal), ink where the curvature is continuous ([`CONTINUOUS_JUMP`]) and red where it jumps.
pub fn draw_joints(pixmap: &mut Pixmap, scene: &Scene, view: &View, options: &RenderOptions) {
    let half = JOINT_BAR_HALF * options.marker_size;
    for chain in scene.curves.iter().filter_map(|c| c.chain.as_ref()) {
        for w in chain.segments.windows(2) {
            let (a, b) = (&w[0].segment, &w[1].segment);
            let p = view.to_pixel(b.start());
            // The bar lies along the normal; in pixels y grows downwards, which only mirrors
            // it: a normal stays a normal.
            let (sin, cos) = b.theta0().sin_cos();
            let n = Vec2::new(-sin, cos) * half;
            let continuous = crate::export::relative_jump(a.kappa1(), b.kappa0())
                .is_some_and(|j| j <= CONTINUOUS_JUMP);
            let colour = if continuous { INK } else { CORNER };
            if let Some(path) = polyline([p - n, p + n]) {
                stroke(pixmap, &path, colour, JOINT_BAR_WIDTH);
            }
        }
    }
}

/// The comb scale (model units²) that gives the [`COMB_QUANTILE`] of |κ| over the scene's LAC
/// segments ([`COMB_SCALE_SAMPLES`] per segment) a tooth of [`COMB_HEIGHT_FRACTION`] of the
/// diagonal of [`scene_bounds`](super::scene_bounds). `None` without segments or curvature.
pub fn auto_comb_scale(scene: &Scene) -> Option<f64> {
    comb_scale_for(comb_curvatures(scene)?, scene_diagonal(scene)?, false)
}

/// The diagonal of [`scene_bounds`](super::scene_bounds).
fn scene_diagonal(scene: &Scene) -> Option<f64> {
    super::scene_bounds(scene).map(|b| b.width().hypot(b.height()))
}

/// The |κ| of the scene's LAC segments ([`COMB_SCALE_SAMPLES`] per segment) at the
/// [`COMB_QUANTILE`] and at the median (`None` without segments or curvature).
fn comb_curvatures(scene: &Scene) -> Option<(f64, f64)> {
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
    // Nearest-rank quantiles.
    let at =
        |q: f64| kappas[((q * kappas.len() as f64).ceil() as usize).clamp(1, kappas.len()) - 1];
    Some((at(COMB_QUANTILE), at(0.5)))
}

/// [`auto_comb_scale`] for a scene of this diagonal, from its [`comb_curvatures`] (quantile,
/// median); with `log`, the scale that gives the quantile's tooth the same height on the
/// logarithmic comb ([`comb_tooth`]).
fn comb_scale_for((reference, median): (f64, f64), diagonal: f64, log: bool) -> Option<f64> {
    let height = COMB_HEIGHT_FRACTION * diagonal;
    let unit_tooth = comb_tooth(reference, 1.0, log.then_some(median)).abs();
    let scale = height / unit_tooth;
    (scale.is_finite() && scale > 0.0).then_some(scale)
}

/// The signed length of a comb tooth of curvature `kappa` at `scale` (model units²): `κ·scale`,
/// or on the logarithmic comb (`log_reference` κ_m) `sign(κ)·scale·κ_m·ln(1 + |κ|/κ_m)`, equal
/// to the linear tooth to first order for |κ| ≪ κ_m. A reference that is not a positive finite
/// number gives the linear tooth.
pub fn comb_tooth(kappa: f64, scale: f64, log_reference: Option<f64>) -> f64 {
    match log_reference.filter(|r| r.is_finite() && *r > 0.0) {
        Some(r) => kappa.signum() * scale * r * (kappa.abs() / r).ln_1p(),
        None => kappa * scale,
    }
}

/// The curvature comb of each chain: a tooth every [`RenderOptions::comb_spacing`] pixels,
/// from the curve along −κ·scale·n (n the left normal, so teeth stand on the convex side, away
/// from the centre of curvature), at most [`COMB_MAX_TOOTH_FRACTION`] of the scene's diagonal
/// long (a cut tooth carries a cross on its tip, [`COMB_CLIP_MARK_PX`]), and the envelope
/// through the teeth's tips.
pub fn draw_comb(pixmap: &mut Pixmap, scene: &Scene, view: &View, options: &RenderOptions) {
    let Some(diagonal) = scene_diagonal(scene) else {
        return;
    };
    // The scene's curvatures, once: the log comb's reference and the automatic scale.
    let needed = options.overlays.comb_log || options.comb_scale.is_none();
    let curvatures = needed.then(|| comb_curvatures(scene)).flatten();
    let log = curvatures
        .filter(|_| options.overlays.comb_log)
        .map(|(_, median)| median);
    let Some(scale) = options
        .comb_scale
        .or_else(|| curvatures.and_then(|c| comb_scale_for(c, diagonal, log.is_some())))
    else {
        return;
    };
    let max_tooth = COMB_MAX_TOOTH_FRACTION * diagonal;
    let line = options.control_polygon_width.max(1.0);
    for curve in scene.curves {
        let Some(chain) = &curve.chain else {
            continue;
        };
        let mut envelope = Vec::new();
        let mut teeth = tiny_skia::PathBuilder::new();
        for seg in &chain.segments {
            let segment = &seg.segment;
            let tip = |s: crate::lac::LacSample| {
                let (sin, cos) = s.theta.sin_cos();
                let tooth = comb_tooth(s.kappa, scale, log).clamp(-max_tooth, max_tooth);
                s.point - Vec2::new(-sin, cos) * tooth
            };
            let pad = max_tooth * view.pixels_per_unit + CULL_PAD_PX;
            if !segment_may_show(segment, view, pad) {
                // Off the image: keep the envelope's legs to the neighbours (they may cross the
                // image), but break it across this segment.
                envelope.push(view.to_pixel(tip(segment.sample(0.0))));
                envelope.push(Point::new(f64::NAN, f64::NAN));
                envelope.push(view.to_pixel(tip(segment.sample(segment.length()))));
                continue;
            }
            let spacing = (options.comb_spacing / view.pixels_per_unit)
                .max(segment.length() / (MAX_SEGMENT_POINTS - 1) as f64);
            for s in segment.samples(spacing) {
                let (a, b) = (view.to_pixel(s.point), view.to_pixel(tip(s)));
                if let (Some(a), Some(b)) =
                    (super::primitives::to_f32(a), super::primitives::to_f32(b))
                {
                    teeth.move_to(a.0, a.1);
                    teeth.line_to(b.0, b.1);
                }
                // A tooth cut to the longest length gets a cross on its tip: the curvature there
                // is off the comb's scale (a needle), not as drawn.
                if comb_tooth(s.kappa, scale, log).abs() > max_tooth {
                    let (sin, cos) = s.theta.sin_cos();
                    let reach = 0.5 * COMB_CLIP_MARK_PX / view.pixels_per_unit / 2f64.sqrt();
                    let (t, n) = (Vec2::new(cos, sin), Vec2::new(-sin, cos));
                    for arm in [(t + n) * reach, (t - n) * reach] {
                        let (p, q) = (view.to_pixel(tip(s) - arm), view.to_pixel(tip(s) + arm));
                        if let (Some(p), Some(q)) =
                            (super::primitives::to_f32(p), super::primitives::to_f32(q))
                        {
                            teeth.move_to(p.0, p.1);
                            teeth.line_to(q.0, q.1);
                        }
                    }
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
