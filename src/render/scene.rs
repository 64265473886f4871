//! What is drawn ([`Scene`]), its extent ([`scene_bounds`]) and the entry point [`render`].

use super::colour::color;
use super::error::RenderError;
use super::legend::{draw_legend, draw_scale_bar};
use super::options::RenderOptions;
use super::overlays::{
    draw_bspline, draw_comb, draw_control_polygon, draw_highlight, draw_joints, draw_samples,
    draw_segments, draw_splits,
};
use super::view::View;
use crate::geom::{Point, Rect};
use crate::pipeline::CurveFit;
use crate::stroke::{Stroke, Units};
use kurbo::ParamCurveExtrema;
use tiny_skia::Pixmap;

/// Points per LAC segment that [`scene_bounds`] takes (evenly in arc length, ends included). A
/// segment of a chain turns little (it follows one monotonic-curvature span of the B-spline,
/// which the box already holds exactly) and lies within the fitting tolerance of it, so a few
/// points suffice; the view's margin absorbs the rest.
pub const BOUNDS_POINTS_PER_SEGMENT: usize = 9;

/// The strokes and their fits, in the strokes' units.
#[derive(Clone, Copy, Debug)]
pub struct Scene<'a> {
    /// The raw strokes (their samples).
    pub strokes: &'a [Stroke],
    /// The fitted pieces (as in [`FitOutput::curves`](crate::pipeline::FitOutput::curves));
    /// [`CurveFit::stroke`] indexes `strokes`.
    pub curves: &'a [CurveFit],
    /// Units of both (labels the scale bar).
    pub units: Units,
}

impl<'a> Scene<'a> {
    /// A scene of `strokes` and their `curves`.
    pub fn new(strokes: &'a [Stroke], curves: &'a [CurveFit], units: Units) -> Self {
        Scene {
            strokes,
            curves,
            units,
        }
    }
}

fn finite(p: Point) -> bool {
    p.x.is_finite() && p.y.is_finite()
}

/// The box holding every finite sample, every B-spline (its exact extrema) and every LAC
/// segment ([`BOUNDS_POINTS_PER_SEGMENT`] points each). The control polygon is left out (it can
/// stray far from the curve). `None` for an empty scene.
pub fn scene_bounds(scene: &Scene) -> Option<Rect> {
    let mut bounds: Option<Rect> = None;
    let mut add = |r: Rect| bounds = Some(bounds.map_or(r, |b| b.union(r)));
    for p in scene.strokes.iter().flat_map(|s| s.samples.iter()) {
        let p = p.point();
        if finite(p) {
            add(Rect::from_points(p, p));
        }
    }
    for curve in scene.curves {
        for piece in curve.bspline.curve.to_beziers() {
            let b = piece.bez;
            if [b.p0, b.p1, b.p2, b.p3].into_iter().all(finite) {
                add(b.bounding_box());
            }
        }
        for seg in curve.chain.iter().flat_map(|c| c.segments.iter()) {
            let spacing = seg.segment.length() / (BOUNDS_POINTS_PER_SEGMENT - 1) as f64;
            for s in seg.segment.samples(spacing) {
                if finite(s.point) {
                    add(Rect::from_points(s.point, s.point));
                }
            }
        }
    }
    bounds
}

/// Draws `scene` through `view`. Layers, bottom to top: background, highlight band, curvature
/// comb, B-spline halo, control polygon, samples, LAC segments, split markers, legend, scale bar
/// (each as [`RenderOptions::overlays`] says). The result is premultiplied RGBA8
/// ([`Pixmap::data`]), ready for an egui texture or [`Pixmap::encode_png`].
///
/// Fails on an empty, oversized or non-finite view ([`View::validate`]) and on bad sizes in
/// `options` ([`RenderOptions::validate`]); non-finite data is skipped, never drawn.
pub fn render(scene: &Scene, view: &View, options: &RenderOptions) -> Result<Pixmap, RenderError> {
    view.validate()?;
    options.validate()?;
    let (width, height) = (view.width, view.height);
    let mut pixmap = Pixmap::new(width, height).ok_or(RenderError::Allocation { width, height })?;
    pixmap.fill(color(options.background));
    let o = options.overlays;
    draw_highlight(&mut pixmap, scene, view, options);
    if o.comb {
        draw_comb(&mut pixmap, scene, view, options);
    }
    if o.bspline {
        draw_bspline(&mut pixmap, scene, view, options);
    }
    if o.control_polygon {
        draw_control_polygon(&mut pixmap, scene, view, options);
    }
    if o.samples {
        draw_samples(&mut pixmap, scene, view, options);
    }
    if o.segments {
        draw_segments(&mut pixmap, scene, view, options);
    }
    if o.joints {
        draw_joints(&mut pixmap, scene, view, options);
    }
    if o.splits {
        draw_splits(&mut pixmap, scene, view, options);
    }
    if o.legend {
        draw_legend(&mut pixmap, options);
    }
    if o.scale_bar {
        draw_scale_bar(&mut pixmap, view, scene.units, options);
    }
    Ok(pixmap)
}

/// [`render`], encoded as PNG by tiny-skia's encoder (8-bit RGBA, straight alpha).
pub fn render_png(
    scene: &Scene,
    view: &View,
    options: &RenderOptions,
) -> Result<Vec<u8>, RenderError> {
    render(scene, view, options)?
        .encode_png()
        .map_err(|e| RenderError::Png(e.to_string()))
}
