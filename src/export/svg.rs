//! A quick-look SVG of a fit: raw samples, the least-squares B-spline, the LAC segments coloured
//! by α, and the split points, one `<g>` layer each.
//!
//! ```text
//! <g id="samples">  one <circle> per sample
//! <g id="bspline">  one <path> of cubic `C` commands per B-spline (drawn wide and pale, so it
//!                   shows as a halo around the LAC chain and any disagreement stands out)
//! <g id="lac">      one <path> polyline per LAC segment, stroke coloured by α ([`alpha_colour`]),
//!                   with data-alpha, data-length, data-kappa0, data-kappa1
//! <g id="splits">   one <rect> square per split point
//! ```
//!
//! Coordinates are written as the data's own (no y flip; SVG's y axis points down, so a y-up
//! drawing appears mirrored top to bottom); the document says so in a comment. The `viewBox` is
//! the bounding box of everything drawn plus [`SvgOptions::margin`]. Every number is written with
//! `{}` (shortest round-trip form), the only text is fixed markup, so nothing needs escaping;
//! elements with a non-finite coordinate are left out.

use crate::geom::{ParamBez, Point};
use crate::lac::LacSegment;
use crate::stroke::Units;
use kurbo::{ParamCurveExtrema, Rect};

/// The LAC polylines deviate from the exact segments by at most this fraction of
/// [`SvgOptions::line_width`]: a tenth of the line width is hidden inside the drawn line at any
/// zoom, and keeps the point count modest (step h = √(8·e/κ_max), e the chord error).
pub const LAC_CHORD_ERROR_FRACTION: f64 = 0.1;

/// Upper bound on the points of one LAC polyline. A segment whose curvature is huge compared
/// with the line width (a tight curl drawn in coordinates of another scale) would otherwise ask
/// for millions of points; beyond this cap its chord error exceeds the bound, which a quick look
/// can afford.
pub const MAX_POINTS_PER_SEGMENT: usize = 100_000;

/// Largest turning of the LAC between two polyline points (radians): keeps the sagitta bound
/// κ_max·h²/8 valid (it needs the turning per step well below π) even for curls smaller than the
/// chord error.
pub const MAX_TURNING_PER_STEP: f64 = 1.0;

/// α at and below which an LAC is drawn in full [`ALPHA_BLUE_RGB`].
pub const ALPHA_BLUE_END: f64 = -2.0;
/// α at and above which an LAC is drawn in full [`ALPHA_RED_RGB`].
pub const ALPHA_RED_END: f64 = 2.0;
/// Colour of α ≤ [`ALPHA_BLUE_END`] (ColorBrewer RdBu's blue end).
pub const ALPHA_BLUE_RGB: [u8; 3] = [33, 102, 172];
/// Colour of α = 0.
pub const ALPHA_ZERO_RGB: [u8; 3] = [128, 128, 128];
/// Colour of α ≥ [`ALPHA_RED_END`] (ColorBrewer RdBu's red end).
pub const ALPHA_RED_RGB: [u8; 3] = [178, 24, 43];
/// Colour of circular arcs and lines (α = null).
pub const NO_ALPHA_RGB: [u8; 3] = [0, 0, 0];

/// What to draw, in the data's coordinates (all in the same units).
#[derive(Clone, Copy, Debug, Default)]
pub struct SvgLayers<'a> {
    /// Raw samples, one vector per stroke (or piece of stroke).
    pub samples: &'a [Vec<Point>],
    /// B-splines, each as its consecutive Bézier pieces.
    pub bsplines: &'a [Vec<ParamBez>],
    /// LAC segments (of all chains).
    pub segments: &'a [LacSegment],
    /// Split points.
    pub splits: &'a [Point],
}

/// Options of [`quick_look_svg`]; lengths are in the data's units. Defaults per unit:
/// [`SvgOptions::for_units`]; `Default` is that of millimetres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SvgOptions {
    /// Width of the LAC lines (the B-spline halo is twice as wide). mm: 0.25 (a fine pen);
    /// px: 1; device: 50 (0.25 mm at 200 lines/mm).
    pub line_width: f64,
    /// Space around the bounding box of everything drawn. mm: 5; px: 20; device: 1000.
    pub margin: f64,
    /// Radius of a sample's dot: 0.6 × the default line width of the units.
    pub sample_radius: f64,
    /// Side of a split point's square: 4 × the default line width of the units.
    pub split_size: f64,
    /// Draw the samples. Default true.
    pub show_samples: bool,
    /// Draw the B-splines. Default true.
    pub show_bspline: bool,
    /// Draw the LAC segments. Default true.
    pub show_lac: bool,
    /// Draw the split points. Default true.
    pub show_splits: bool,
    /// Units of the data: `mm` gives the SVG a physical size in millimetres, `px` a size in
    /// pixels; `device` counts get no `width`/`height` (a viewer scales the `viewBox` to fit).
    pub units: Units,
}

impl SvgOptions {
    /// The defaults for data in `units` (see the fields).
    pub const fn for_units(units: Units) -> Self {
        let (line_width, margin) = match units {
            Units::Mm => (0.25, 5.0),
            Units::Px => (1.0, 20.0),
            Units::Device => (50.0, 1000.0),
        };
        SvgOptions {
            line_width,
            margin,
            sample_radius: 0.6 * line_width,
            split_size: 4.0 * line_width,
            show_samples: true,
            show_bspline: true,
            show_lac: true,
            show_splits: true,
            units,
        }
    }

    /// Sets [`SvgOptions::line_width`].
    pub const fn with_line_width(mut self, line_width: f64) -> Self {
        self.line_width = line_width;
        self
    }

    /// Sets [`SvgOptions::margin`].
    pub const fn with_margin(mut self, margin: f64) -> Self {
        self.margin = margin;
        self
    }

    /// Sets the four `show_*` flags (samples, B-spline, LAC, splits).
    pub const fn with_layers(
        mut self,
        samples: bool,
        bspline: bool,
        lac: bool,
        splits: bool,
    ) -> Self {
        self.show_samples = samples;
        self.show_bspline = bspline;
        self.show_lac = lac;
        self.show_splits = splits;
        self
    }

    /// The largest distance between a drawn LAC polyline and the exact segment:
    /// [`LAC_CHORD_ERROR_FRACTION`] × `line_width`.
    pub fn chord_error(&self) -> f64 {
        LAC_CHORD_ERROR_FRACTION * self.line_width
    }

    /// The options with every length that is not a finite non-negative number (line width: not
    /// positive) replaced by the default of the units.
    fn sanitized(self) -> Self {
        let d = SvgOptions::for_units(self.units);
        let ok = |v: f64, default: f64| {
            if v.is_finite() && v >= 0.0 {
                v
            } else {
                default
            }
        };
        SvgOptions {
            line_width: if self.line_width.is_finite() && self.line_width > 0.0 {
                self.line_width
            } else {
                d.line_width
            },
            margin: ok(self.margin, d.margin),
            sample_radius: ok(self.sample_radius, d.sample_radius),
            split_size: ok(self.split_size, d.split_size),
            ..self
        }
    }
}

impl Default for SvgOptions {
    fn default() -> Self {
        SvgOptions::for_units(Units::Mm)
    }
}

/// The arc-length spacing at which [`quick_look_svg`] samples `segment` so that the polyline
/// stays within `chord_error` of it.
///
/// A step of arc length h on a curve with |κ| ≤ κ_max (monotonic along an LAC, so κ_max is the
/// larger end) and turning below π deviates from its chord by at most the sagitta of the circle
/// of curvature κ_max: (1 − cos(κ_max·h/2))/κ_max ≤ κ_max·h²/8. So h = √(8·e/κ_max), further
/// limited to [`MAX_TURNING_PER_STEP`]/κ_max and to the whole length, and widened so the segment
/// gets at most [`MAX_POINTS_PER_SEGMENT`] points. Lines get their two ends.
pub fn lac_spacing(segment: &LacSegment, chord_error: f64) -> f64 {
    let length = segment.length();
    let kappa_max = segment.kappa0().abs().max(segment.kappa1().abs());
    if !(kappa_max > 0.0) || !(chord_error > 0.0) {
        return length;
    }
    let h = (8.0 * chord_error / kappa_max)
        .sqrt()
        .min(MAX_TURNING_PER_STEP / kappa_max)
        .min(length);
    // MAX − 1 steps give MAX points; one step less absorbs the rounding of ⌈length/h⌉.
    h.max(length / (MAX_POINTS_PER_SEGMENT - 2) as f64)
}

/// The stroke colour of an LAC of slope `alpha`: a diverging map, linear in sRGB from
/// [`ALPHA_BLUE_RGB`] at α ≤ [`ALPHA_BLUE_END`] through [`ALPHA_ZERO_RGB`] (grey) at α = 0 to
/// [`ALPHA_RED_RGB`] at α ≥ [`ALPHA_RED_END`]; [`NO_ALPHA_RGB`] (black) for arcs and lines
/// (`None`) and for a non-finite α.
pub fn alpha_colour(alpha: Option<f64>) -> [u8; 3] {
    let Some(alpha) = alpha.filter(|a| a.is_finite()) else {
        return NO_ALPHA_RGB;
    };
    let (end, t) = if alpha < 0.0 {
        (ALPHA_BLUE_RGB, (alpha / ALPHA_BLUE_END).min(1.0))
    } else {
        (ALPHA_RED_RGB, (alpha / ALPHA_RED_END).min(1.0))
    };
    let mix = |i: usize| {
        let (a, b) = (f64::from(ALPHA_ZERO_RGB[i]), f64::from(end[i]));
        // a + t·(b − a) lies between two u8 values, so the conversion is exact after rounding.
        (a + t * (b - a)).round() as u8
    };
    [mix(0), mix(1), mix(2)]
}

/// A bounding box grown element by element.
#[derive(Clone, Copy, Debug)]
struct Bounds(Option<Rect>);

impl Bounds {
    /// Adds the box of half-size `pad` around `p` (skipped unless finite).
    fn add(&mut self, p: Point, pad: f64) {
        if finite(p) {
            self.add_rect(Rect::new(p.x - pad, p.y - pad, p.x + pad, p.y + pad));
        }
    }

    fn add_rect(&mut self, r: Rect) {
        self.0 = Some(self.0.map_or(r, |b| b.union(r)));
    }
}

fn finite(p: Point) -> bool {
    p.x.is_finite() && p.y.is_finite()
}

/// Appends "x y" (shortest round-trip decimals).
fn push_xy(out: &mut String, p: Point) {
    out.push_str(&format!("{} {}", p.x, p.y));
}

/// A LAC segment's polyline, as drawn.
fn lac_polyline(segment: &LacSegment, chord_error: f64) -> Vec<Point> {
    segment
        .samples(lac_spacing(segment, chord_error))
        .map(|s| s.point)
        .collect()
}

/// Writes the quick-look SVG of `layers` (see the module documentation).
pub fn quick_look_svg(layers: &SvgLayers, options: &SvgOptions) -> String {
    let o = options.sanitized();
    let width = o.line_width;
    let halo = 2.0 * width;
    let chord_error = o.chord_error();
    let mut bounds = Bounds(None);

    // Content first (to know the bounds), then the document around it.
    let mut body = String::new();
    if o.show_samples {
        body.push_str("<g id=\"samples\" fill=\"#7f7f7f\" stroke=\"none\">\n");
        for p in layers.samples.iter().flatten().filter(|p| finite(**p)) {
            bounds.add(*p, o.sample_radius);
            body.push_str(&format!(
                "<circle cx=\"{}\" cy=\"{}\" r=\"{}\"/>\n",
                p.x, p.y, o.sample_radius
            ));
        }
        body.push_str("</g>\n");
    }
    if o.show_bspline {
        body.push_str(&format!(
            "<g id=\"bspline\" fill=\"none\" stroke=\"#2ca02c\" stroke-opacity=\"0.45\" \
             stroke-width=\"{halo}\" stroke-linejoin=\"round\" stroke-linecap=\"round\">\n"
        ));
        for spline in layers.bsplines {
            let mut d = String::new();
            let mut pen: Option<Point> = None;
            for piece in spline {
                let b = piece.bez;
                if ![b.p0, b.p1, b.p2, b.p3].into_iter().all(finite) {
                    pen = None;
                    continue;
                }
                let r = b.bounding_box();
                bounds.add_rect(Rect::new(
                    r.x0 - 0.5 * halo,
                    r.y0 - 0.5 * halo,
                    r.x1 + 0.5 * halo,
                    r.y1 + 0.5 * halo,
                ));
                if pen != Some(b.p0) {
                    d.push_str(if d.is_empty() { "M" } else { " M" });
                    push_xy(&mut d, b.p0);
                }
                d.push_str(" C");
                for p in [b.p1, b.p2, b.p3] {
                    d.push(' ');
                    push_xy(&mut d, p);
                }
                pen = Some(b.p3);
            }
            if !d.is_empty() {
                body.push_str(&format!("<path d=\"{d}\"/>\n"));
            }
        }
        body.push_str("</g>\n");
    }
    if o.show_lac {
        body.push_str(&format!(
            "<g id=\"lac\" fill=\"none\" stroke-width=\"{width}\" stroke-linejoin=\"round\" \
             stroke-linecap=\"round\">\n"
        ));
        for segment in layers.segments {
            let mut d = String::new();
            for (i, p) in lac_polyline(segment, chord_error).into_iter().enumerate() {
                bounds.add(p, 0.5 * width);
                d.push_str(if i == 0 { "M" } else { " L" });
                push_xy(&mut d, p);
            }
            let [r, g, b] = alpha_colour(segment.alpha());
            let alpha = segment
                .alpha()
                .map_or_else(|| "null".to_string(), |a| a.to_string());
            body.push_str(&format!(
                "<path d=\"{d}\" stroke=\"#{r:02x}{g:02x}{b:02x}\" data-alpha=\"{alpha}\" \
                 data-length=\"{}\" data-kappa0=\"{}\" data-kappa1=\"{}\"/>\n",
                segment.length(),
                segment.kappa0(),
                segment.kappa1()
            ));
        }
        body.push_str("</g>\n");
    }
    if o.show_splits {
        body.push_str("<g id=\"splits\" fill=\"#ff7f0e\" stroke=\"none\">\n");
        let half = 0.5 * o.split_size;
        for p in layers.splits.iter().filter(|p| finite(**p)) {
            bounds.add(*p, half);
            body.push_str(&format!(
                "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/>\n",
                p.x - half,
                p.y - half,
                o.split_size,
                o.split_size
            ));
        }
        body.push_str("</g>\n");
    }

    // Nothing drawn: a unit box at the origin.
    let content = bounds.0.unwrap_or(Rect::new(0.0, 0.0, 1.0, 1.0));
    let mut view = content.inflate(o.margin, o.margin);
    // A single point drawn with zero size and no margin: give the view a unit extent.
    if !(view.width() > 0.0) {
        view = Rect::new(view.x0 - 0.5, view.y0, view.x1 + 0.5, view.y1);
    }
    if !(view.height() > 0.0) {
        view = Rect::new(view.x0, view.y0 - 0.5, view.x1, view.y1 + 0.5);
    }
    let (w, h) = (view.width(), view.height());
    let size = match o.units {
        Units::Mm => format!(" width=\"{w}mm\" height=\"{h}mm\""),
        Units::Px => format!(" width=\"{w}\" height=\"{h}\""),
        Units::Device => String::new(),
    };
    let mut svg = String::with_capacity(body.len() + 512);
    svg.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    svg.push_str(&format!(
        "<!-- kansei quick look. Coordinates are the data's own, in {units}; the y axis is not \
         flipped: SVG's y points down, so a y-up drawing appears mirrored top to bottom. \
         Layers: samples (dots), bspline (pale halo), lac (coloured by alpha: blue < 0, grey 0, \
         red >= 2, black arc or line), splits (squares). -->\n",
        units = o.units.name()
    ));
    svg.push_str(&format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" viewBox=\"{} {} {w} {h}\"{size}>\n",
        view.x0, view.y0
    ));
    svg.push_str(&body);
    svg.push_str("</svg>\n");
    svg
}
