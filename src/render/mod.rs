//! Raster drawing of a scene (strokes and their fits) with tiny-skia: the PNG export
//! (`kansei fit --png`), the app's canvas texture and the golden image tests share it.
//!
//! ```text
//! view.rs        View: the model → pixel transform (fit, to_pixel, to_model, pan, zoom)
//! colour.rs      the palette; LAC colours are the SVG's alpha_colour
//! options.rs     Overlays (what is drawn) and RenderOptions (sizes in pixels, with defaults)
//! primitives.rs  polylines, Béziers, dots and marker shapes
//! overlays.rs    samples, B-spline, control polygon, segments, highlight, comb, split markers
//! text.rs        a tiny stroke font for the legend and scale-bar labels
//! legend.rs      the α legend and the scale bar
//! scene.rs       Scene, scene_bounds and the entry point render
//! error.rs       RenderError
//! ```
//!
//! LAC segments are evaluated exactly ([`LacSegment::samples`](crate::lac::LacSegment::samples)
//! at [`segment_spacing`]: within [`SEGMENT_CHORD_ERROR_PX`] of the curve, at most
//! [`SEGMENT_STEP_PX`] apart), not through the B-spline; circular arcs and lines (α = null) are
//! drawn as arcs and lines.
//!
//! ```
//! use kansei::geom::Point;
//! use kansei::pipeline::{PipelineOptions, fit_file};
//! use kansei::render::{RenderOptions, Scene, View, render, scene_bounds};
//! use kansei::stroke::{Stroke, StrokeFile, Units};
//!
//! let arc = Stroke::from_points((0..=90).map(|d| {
//!     let a = (d as f64).to_radians();
//!     Point::new(50.0 * a.cos(), 50.0 * a.sin())
//! }));
//! let file = StrokeFile::new(Units::Mm, vec![arc]);
//! let out = fit_file(&file, &PipelineOptions::default()).unwrap();
//! let scene = Scene::new(&file.strokes, &out.curves, file.units);
//! let view = View::fit(scene_bounds(&scene).unwrap(), 320, 200, 20.0);
//! let pixmap = render(&scene, &view, &RenderOptions::default()).unwrap();
//! assert_eq!((pixmap.width(), pixmap.height()), (320, 200));
//! ```

mod colour;
mod error;
mod legend;
mod options;
mod overlays;
mod primitives;
mod quick_look;
mod scene;
mod text;
mod view;

pub use colour::{
    ALPHA_BLUE_END, ALPHA_BLUE_RGB, ALPHA_RED_END, ALPHA_RED_RGB, ALPHA_ZERO_RGB, BACKGROUND,
    BSPLINE, COMB, CONTROL_POLYGON, CORNER, EXTREMUM, HIGHLIGHT, INFLECTION, INK, MARKER_OUTLINE,
    NO_ALPHA_RGB, PANEL, Rgba, SAMPLE, alpha_colour, segment_colour,
};
pub use error::{MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE, RenderError};
pub use legend::{
    LEGEND_TICKS, LegendLayout, RAMP_WIDTH_EM, SCALE_BAR_FRACTION, draw_legend, draw_scale_bar,
    legend_layout, scale_bar_label, scale_bar_length,
};
pub use options::{Overlays, RenderOptions};
pub use overlays::{
    ARC_TOLERANCE_PX, COMB_HEIGHT_FRACTION, COMB_MAX_TOOTH_FRACTION, COMB_QUANTILE,
    COMB_SCALE_SAMPLES, CULL_PAD_PX, MAX_SEGMENT_POINTS, SEGMENT_CHORD_ERROR_PX,
    SEGMENT_MAX_TURNING, SEGMENT_MIN_STEP_PX, SEGMENT_STEP_PX, auto_comb_scale, comb_tooth,
    sample_radius, segment_may_show, segment_path, segment_spacing,
};
pub use primitives::{MarkerShape, PIXEL_COORD_LIMIT};
pub use quick_look::{OVERLAY_NAMES, QUICK_LOOK_MARGIN_PX, quick_look_png};
pub use scene::{BOUNDS_POINTS_PER_SEGMENT, Scene, render, render_png, scene_bounds};
pub use text::{GLYPH_ADVANCE, GLYPH_GRID, GLYPH_WIDTH, draw_text, glyph, text_width};
pub use view::{FALLBACK_PIXELS_PER_UNIT, MIN_FIT_EXTENT_PX, View};

/// Re-exported so users need not depend on tiny-skia themselves to name the result.
pub use tiny_skia::Pixmap;
