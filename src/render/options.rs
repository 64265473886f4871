//! What [`render`](super::render) draws, and how thick. Sizes are in pixels (they do not change
//! with the zoom); the defaults suit a 1600 × 1000 image on a ~100 dpi screen.

use super::colour::{BACKGROUND, Rgba};
use super::error::RenderError;

/// Which overlays are drawn. Default: samples, B-spline, splits, segments, joints, legend and
/// scale bar on; control polygon and comb off (they clutter a first look).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Overlays {
    /// Raw samples, dots sized by pressure where the stroke has it.
    pub samples: bool,
    /// The B-spline, a pale wide halo.
    pub bspline: bool,
    /// The B-spline's control polygon and control points.
    pub control_polygon: bool,
    /// Split markers: ring (start/end), diamond (inflection), triangle (curvature extremum),
    /// square (corner).
    pub splits: bool,
    /// LAC segments coloured by α; arcs and lines (α = null) black.
    pub segments: bool,
    /// LAC joints: a bar across the chain where two segments meet (the split markers sit on the
    /// B-spline, where the chain started from), ink where the curvature is continuous (G2),
    /// red where it jumps.
    pub joints: bool,
    /// Curvature comb of the LAC segments.
    pub comb: bool,
    /// The comb's teeth on a logarithmic scale (`comb-log`): a tooth of curvature κ is
    /// `scale·κ_m·ln(1 + |κ|/κ_m)` long (κ_m the scene's median |κ|), as the linear comb for
    /// small curvature, while a needle a hundred times the rest stays on the drawing.
    pub comb_log: bool,
    /// Colour legend of α (top right).
    pub legend: bool,
    /// Scale bar (bottom left), labelled in the scene's units.
    pub scale_bar: bool,
}

impl Overlays {
    /// Every overlay.
    pub const ALL: Overlays = Overlays {
        samples: true,
        bspline: true,
        control_polygon: true,
        splits: true,
        segments: true,
        joints: true,
        comb: true,
        comb_log: true,
        legend: true,
        scale_bar: true,
    };
    /// No overlay (the background only).
    pub const NONE: Overlays = Overlays {
        samples: false,
        bspline: false,
        control_polygon: false,
        splits: false,
        segments: false,
        joints: false,
        comb: false,
        comb_log: false,
        legend: false,
        scale_bar: false,
    };
}

impl Default for Overlays {
    fn default() -> Self {
        Overlays {
            samples: true,
            bspline: true,
            control_polygon: false,
            splits: true,
            segments: true,
            joints: true,
            comb: false,
            comb_log: false,
            legend: true,
            scale_bar: true,
        }
    }
}

/// Options of [`render`](super::render).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    /// What to draw. Default [`Overlays::default`].
    pub overlays: Overlays,
    /// A segment to highlight: (index in the scene's curves, index in that curve's chain). Drawn
    /// as a wide gold band under everything, whether or not the segments are shown; an index
    /// that names no segment draws nothing. Default `None`.
    pub highlight: Option<(usize, usize)>,
    /// Background colour (straight alpha; transparent is allowed). Default opaque white.
    pub background: Rgba,
    /// LAC segment line width. Default 2.5 px.
    pub segment_width: f64,
    /// B-spline halo width. Default 7 px.
    pub bspline_width: f64,
    /// Control polygon line width. Default 1 px (control points: squares of 3 × that).
    pub control_polygon_width: f64,
    /// Sample dot radius at pressure 0.5 (and without pressure); a sample of pressure p gets
    /// radius × (0.5 + p), so 0 → half, 1 → one and a half. Default 2 px.
    pub sample_radius: f64,
    /// Split marker size (the diameter of the ring, the diagonal of the diamond, the side of the
    /// square and triangle). Default 9 px.
    pub marker_size: f64,
    /// Curvature comb scale, model units² (a tooth of curvature κ is κ × scale long). Default
    /// `None`: chosen from the scene by [`auto_comb_scale`](super::auto_comb_scale), so the 95th
    /// percentile of |κ| gets a tooth a tenth of the scene's diagonal.
    pub comb_scale: Option<f64>,
    /// Spacing of the comb's teeth along the curve. Default 6 px.
    pub comb_spacing: f64,
    /// Width of the highlight band. Default 12 px.
    pub highlight_width: f64,
    /// Cap height of the legend and scale-bar text. Default 13 px.
    pub text_size: f64,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            overlays: Overlays::default(),
            highlight: None,
            background: BACKGROUND,
            segment_width: 2.5,
            bspline_width: 7.0,
            control_polygon_width: 1.0,
            sample_radius: 2.0,
            marker_size: 9.0,
            comb_scale: None,
            comb_spacing: 6.0,
            highlight_width: 12.0,
            text_size: 13.0,
        }
    }
}

impl RenderOptions {
    /// The default options with these overlays.
    pub fn with_overlays(overlays: Overlays) -> Self {
        RenderOptions {
            overlays,
            ..RenderOptions::default()
        }
    }

    /// The options with every pixel size multiplied by `factor` (e.g. a screen's scale factor;
    /// the comb scale, in model units, is kept).
    pub fn scaled(self, factor: f64) -> Self {
        RenderOptions {
            segment_width: self.segment_width * factor,
            bspline_width: self.bspline_width * factor,
            control_polygon_width: self.control_polygon_width * factor,
            sample_radius: self.sample_radius * factor,
            marker_size: self.marker_size * factor,
            comb_spacing: self.comb_spacing * factor,
            highlight_width: self.highlight_width * factor,
            text_size: self.text_size * factor,
            ..self
        }
    }

    /// Checks that every size is a finite non-negative number (the comb spacing positive, the
    /// comb scale finite).
    pub fn validate(&self) -> Result<(), RenderError> {
        let sizes = [
            ("segment_width", self.segment_width),
            ("bspline_width", self.bspline_width),
            ("control_polygon_width", self.control_polygon_width),
            ("sample_radius", self.sample_radius),
            ("marker_size", self.marker_size),
            ("highlight_width", self.highlight_width),
            ("text_size", self.text_size),
        ];
        for (name, value) in sizes {
            if !(value.is_finite() && value >= 0.0) {
                return Err(RenderError::BadOption { name, value });
            }
        }
        if !(self.comb_spacing.is_finite() && self.comb_spacing > 0.0) {
            return Err(RenderError::BadOption {
                name: "comb_spacing",
                value: self.comb_spacing,
            });
        }
        if let Some(value) = self.comb_scale
            && !value.is_finite()
        {
            return Err(RenderError::BadOption {
                name: "comb_scale",
                value,
            });
        }
        Ok(())
    }
}
