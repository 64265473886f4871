//! The SVG export: each stroke's LAC chains as one `<path>` within a stated error of the exact
//! curve, with per-segment metadata; optional layers for the raw samples, the B-spline, the
//! chain coloured by α and the split points.
//!
//! ```text
//! <metadata>          <kansei:export units tolerance accuracy error .../>
//! <g id="samples">    (optional) one <circle> per sample
//! <g id="bspline">    (optional) one <path> of `C` commands per B-spline, exact (a B-spline
//!                     span is a cubic Bézier)
//! <g id="curves">     one <path> per stroke: id stroke-N, data-stroke, data-samples (its first
//!                     and last fitted sample), data-pieces, data-error. A stroke is cut into
//!                     pieces at corners; each piece is a subpath of the one `d`, except that a
//!                     piece starting exactly where the previous one ended continues it without
//!                     a new `M`. The path's <metadata> holds one <kansei:segment> per LAC
//!                     segment of its pieces: piece (index in the fit's curves, as in the
//!                     kansei-curve JSON), index (in that piece's chain), alpha, length, kappa0,
//!                     kappa1, max-deviation (to the samples), samples, element (L, A or C),
//!                     commands, error (of the export)
//! <g id="alpha">      (optional) the same commands, one <path> per segment, coloured by α
//!                     ([`alpha_colour`])
//! <g id="splits">     (optional) one <rect> square per split point
//! ```
//!
//! How a segment is written:
//! * a line (κ0 = κ1 = 0): one `L`, exact;
//! * a circular arc (κ0 = κ1 ≠ 0): `A` commands of radius 1/|κ|, each turning at most
//!   [`MAX_ARC_TURNING`], exact (sweep flag 1 for κ > 0: the angle increases, as SVG counts it
//!   in the data's own coordinates); an arc within [`ARC_AS_LINE_FRACTION`] of the accuracy of
//!   its chord is a line instead;
//! * a log-aesthetic spiral: cubic Béziers from kurbo's curve fitting ([`segment_beziers`]),
//!   measured within [`SvgOptions::accuracy`] of the exact segment.
//!
//! Coordinates are written as the data's own (no y flip; SVG's y axis points down, so a y-up
//! drawing appears mirrored top to bottom); the document says so in a comment. The `viewBox` is
//! in the data's units: the bounding box of everything drawn plus [`SvgOptions::margin`]; the
//! `width`/`height` are in millimetres for mm data (so the drawing has its real size), unitless
//! (CSS pixels) for px data, absent for device counts. Every number is written with `{}`
//! (shortest round-trip form, so parsing it back gives the same `f64`); the only text is fixed
//! markup, so nothing needs escaping; elements with a non-finite coordinate are left out.

use std::fmt::Write as _;

use crate::geom::{Point, Vec2};
use crate::lac::LacSegment;
use crate::pipeline::FitOutput;
use crate::stroke::{StrokeFile, Units};
use kurbo::{CubicBez, ParamCurveExtrema, Rect};

use super::bezier::{DEFAULT_ACCURACY_FRACTION, segment_beziers};

/// A circular arc whose sagitta (distance from its chord) is at most this fraction of the
/// accuracy is written as a line: its radius is then so large compared with its chord (about
/// 10⁵ times for a 30 mm arc at an accuracy of 0.01 mm) that readers reconstructing the centre
/// from the end points lose most digits, and the line is within a thousandth of the accuracy.
pub const ARC_AS_LINE_FRACTION: f64 = 1e-3;

/// The XML namespace of kansei's SVG metadata elements.
pub const SVG_METADATA_NAMESPACE: &str = "urn:kansei:svg-metadata:1";

/// Largest turning (radians) of one `A` command: a quarter turn keeps the large-arc flag 0 and
/// the end points far apart compared with the radius, so a reader reconstructs the centre
/// without the ill-conditioning of a half-turn arc (whose two candidate centres coincide).
pub const MAX_ARC_TURNING: f64 = std::f64::consts::FRAC_PI_2;

/// The polylines that bound an arc when sizing the `viewBox` deviate from the exact
/// segments by at most this fraction of
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

/// The arc-length spacing at which `segment` is sampled so that the polyline
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

/// The optional SVG layers drawn beside the chain.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SvgLayers {
    /// The raw samples. Default false.
    pub samples: bool,
    /// The B-splines. Default false.
    pub bspline: bool,
    /// The chain once more, one path per segment coloured by α. Default false.
    pub alpha: bool,
    /// The split points. Default false.
    pub splits: bool,
}

impl SvgLayers {
    /// The layer names [`SvgLayers::named`] takes, as `kansei fit --svg-layers` and the
    /// service's `layers` do.
    pub const NAMES: [&'static str; 4] = ["samples", "bspline", "alpha", "splits"];

    /// No extra layer: the chain alone.
    pub const NONE: SvgLayers = SvgLayers {
        samples: false,
        bspline: false,
        alpha: false,
        splits: false,
    };

    /// The samples alone (the app's export).
    pub const SAMPLES: SvgLayers = SvgLayers {
        samples: true,
        ..SvgLayers::NONE
    };

    /// The layers named in `names` (of [`SvgLayers::NAMES`]; other names are ignored), the rest
    /// off.
    pub fn named(names: &[String]) -> Self {
        let on = |name: &str| names.iter().any(|l| l == name);
        SvgLayers {
            samples: on("samples"),
            bspline: on("bspline"),
            alpha: on("alpha"),
            splits: on("splits"),
        }
    }
}

/// Options of [`svg_document`]; lengths are in the data's units. Defaults per unit:
/// [`SvgOptions::for_units`]; `Default` is that of millimetres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SvgOptions {
    /// Largest distance between the written curve and the exact LAC chain. Default `None`:
    /// [`DEFAULT_ACCURACY_FRACTION`] (a tenth) of the fitting tolerance.
    pub accuracy: Option<f64>,
    /// Width of the curves (the B-spline halo is twice as wide). mm: 0.25 (a fine pen); px: 1;
    /// device: 50 (0.25 mm at 200 lines/mm).
    pub line_width: f64,
    /// Space around the bounding box of everything drawn. mm: 5; px: 20; device: 1000.
    pub margin: f64,
    /// Radius of a sample's dot: 0.6 × the default line width of the units.
    pub sample_radius: f64,
    /// Side of a split point's square: 4 × the default line width of the units.
    pub split_size: f64,
    /// Draw the raw samples (needs the stroke file). Default false.
    pub show_samples: bool,
    /// Draw the B-splines. Default false.
    pub show_bspline: bool,
    /// Draw the chain once more, one path per segment coloured by α. Default false.
    pub show_alpha: bool,
    /// Draw the split points. Default false.
    pub show_splits: bool,
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
            accuracy: None,
            line_width,
            margin,
            sample_radius: 0.6 * line_width,
            split_size: 4.0 * line_width,
            show_samples: false,
            show_bspline: false,
            show_alpha: false,
            show_splits: false,
        }
    }

    /// Sets [`SvgOptions::accuracy`].
    pub const fn with_accuracy(mut self, accuracy: f64) -> Self {
        self.accuracy = Some(accuracy);
        self
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

    /// Sets the four optional layers (samples, B-spline, α, splits).
    pub const fn with_layers(
        mut self,
        samples: bool,
        bspline: bool,
        alpha: bool,
        splits: bool,
    ) -> Self {
        self.show_samples = samples;
        self.show_bspline = bspline;
        self.show_alpha = alpha;
        self.show_splits = splits;
        self
    }

    /// Sets the four optional layers from `layers`.
    pub const fn with_layer_set(self, layers: SvgLayers) -> Self {
        self.with_layers(layers.samples, layers.bspline, layers.alpha, layers.splits)
    }

    /// Sets the optional layers by name (`samples`, `bspline`, `alpha`, `splits`, as
    /// `kansei fit --svg-layers` and the service's `layers` take them); other names are ignored.
    pub fn with_layer_names(self, names: &[String]) -> Self {
        self.with_layer_set(SvgLayers::named(names))
    }

    /// The options with every length that is not a finite non-negative number (line width: not
    /// positive) replaced by the default of `units`.
    fn sanitized(self, units: Units) -> Self {
        let d = SvgOptions::for_units(units);
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

/// The export accuracy for a fit at `tolerance`: `requested` when it is a positive number, else
/// [`DEFAULT_ACCURACY_FRACTION`] × `tolerance`.
pub fn export_accuracy(requested: Option<f64>, tolerance: f64) -> f64 {
    requested
        .filter(|a| a.is_finite() && *a > 0.0)
        .unwrap_or(DEFAULT_ACCURACY_FRACTION * tolerance)
}

/// How a segment was written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SvgElement {
    /// One exact `L`.
    Line,
    /// Exact `A` commands.
    Arc,
    /// Cubic Béziers (`C`) within the accuracy.
    Cubic,
}

impl SvgElement {
    /// The SVG command letter.
    pub const fn letter(self) -> char {
        match self {
            SvgElement::Line => 'L',
            SvgElement::Arc => 'A',
            SvgElement::Cubic => 'C',
        }
    }
}

/// What was written for one segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SvgSegmentReport {
    /// The kind of path command.
    pub element: SvgElement,
    /// How many commands (cubics, arcs, or 1 for a line).
    pub commands: usize,
    /// Measured distance between the written commands and the exact segment (0 for exact
    /// lines and arcs).
    pub error: f64,
}

/// What was written for one fitted piece: a run of commands inside its stroke's `<path>`.
#[derive(Clone, Debug, PartialEq)]
pub struct SvgPieceReport {
    /// Index of the piece in the fit's curves ([`FitOutput::curves`], and the `curves` of the
    /// kansei-curve JSON).
    pub piece: usize,
    /// Whether the piece opens a subpath with its own `M`; `false` when it starts exactly where
    /// the previous piece of the path ended and continues that subpath.
    pub move_to: bool,
    /// Its segments, in order (segments with a non-finite number are left out).
    pub segments: Vec<SvgSegmentReport>,
}

/// What was written for one stroke: one `<path>` of the `curves` layer.
#[derive(Clone, Debug, PartialEq)]
pub struct SvgPathReport {
    /// Index of the stroke.
    pub stroke: usize,
    /// Its pieces, in the order of the fit's curves.
    pub pieces: Vec<SvgPieceReport>,
}

impl SvgPathReport {
    /// The largest measured error over the path's segments.
    pub fn max_error(&self) -> f64 {
        self.pieces
            .iter()
            .flat_map(|p| &p.segments)
            .map(|s| s.error)
            .fold(0.0, f64::max)
    }
}

/// An SVG document and what it holds.
#[derive(Clone, Debug, PartialEq)]
pub struct SvgExport {
    /// The document.
    pub svg: String,
    /// The accuracy the curves were written to.
    pub accuracy: f64,
    /// One report per `<path>` of the `curves` layer, in document order: one per stroke with at
    /// least one fitted piece that has a chain.
    pub paths: Vec<SvgPathReport>,
}

impl SvgExport {
    /// The largest measured error over every segment.
    pub fn max_error(&self) -> f64 {
        self.paths
            .iter()
            .map(SvgPathReport::max_error)
            .fold(0.0, f64::max)
    }
}

/// A bounding box grown element by element.
#[derive(Clone, Copy, Debug)]
struct Bounds(Option<Rect>);

impl Bounds {
    /// Adds the box of half-size `pad` around `p` (skipped unless finite).
    fn add(&mut self, p: Point, pad: f64) {
        if finite(p) {
            self.add_rect(Rect::new(p.x - pad, p.y - pad, p.x + pad, p.y + pad), 0.0);
        }
    }

    /// Adds `r` grown by `pad` on every side.
    fn add_rect(&mut self, r: Rect, pad: f64) {
        let r = r.inflate(pad, pad);
        self.0 = Some(self.0.map_or(r, |b| b.union(r)));
    }
}

fn finite(p: Point) -> bool {
    p.x.is_finite() && p.y.is_finite()
}

fn cubic_finite(c: &CubicBez) -> bool {
    [c.p0, c.p1, c.p2, c.p3].into_iter().all(finite)
}

/// Appends " x y" (shortest round-trip decimals).
fn push_xy(out: &mut String, p: Point) {
    // Writing into a String cannot fail.
    let _ = write!(out, " {} {}", p.x, p.y);
}

/// Appends " C x1 y1 x2 y2 x3 y3".
fn push_cubic(out: &mut String, c: &CubicBez) {
    out.push_str(" C");
    for p in [c.p1, c.p2, c.p3] {
        push_xy(out, p);
    }
}

/// The largest distance between a circular-arc segment and its chord:
/// r·(1 − cos(φ/2)) = 2r·sin²(φ/4), φ the turning, r the radius (for φ ≤ π; beyond, at least r).
fn arc_sagitta(segment: &LacSegment) -> f64 {
    let kappa = segment.kappa0().abs();
    let turning = kappa * segment.length();
    if turning >= std::f64::consts::PI {
        return 1.0 / kappa;
    }
    2.0 * (0.25 * turning).sin().powi(2) / kappa
}

/// Units in the last place of an arc's turning κ·S within which its rest modulo a full turn
/// counts as none (the product and the modulo round by a few).
const ARC_TURNING_ROUNDING_ULPS: f64 = 8.0;

/// Appends the `A` commands of a circular-arc segment and returns their count: arcs of at most
/// [`MAX_ARC_TURNING`] each, evenly spaced. An arc turning a full circle or more is drawn as one
/// full circle (four quarter turns back to its start) and then the rest of its turning modulo
/// 2π: every further turn retraces the same circle, so the ink is the segment's and the count
/// stays at most eight however many times the segment winds (its length is in the metadata).
fn push_arcs(d: &mut String, segment: &LacSegment) -> usize {
    let kappa = segment.kappa0();
    let radius = 1.0 / kappa.abs();
    let sweep = u8::from(kappa > 0.0);
    let length = segment.length();
    let turning = (kappa * length).abs();
    let mut count = 0;
    let arc_to = |d: &mut String, count: &mut usize, p: Point| {
        let _ = write!(d, " A {radius} {radius} 0 0 {sweep}");
        push_xy(d, p);
        *count += 1;
    };
    let (rest, from) = if turning >= std::f64::consts::TAU {
        let quarter = MAX_ARC_TURNING * radius;
        for i in 1..4 {
            arc_to(d, &mut count, segment.point(quarter * f64::from(i)));
        }
        let rest = turning % std::f64::consts::TAU;
        // A rest within the turning's own rounding of 0 or of a full turn is none: the circle
        // then closes at the segment's end.
        let rounding = ARC_TURNING_ROUNDING_ULPS * f64::EPSILON * turning;
        if rest <= rounding || rest >= std::f64::consts::TAU - rounding {
            arc_to(d, &mut count, segment.end());
            return count;
        }
        arc_to(d, &mut count, segment.start());
        (rest, length - rest * radius)
    } else {
        (turning, 0.0)
    };
    // At least one arc; at most four (a rest below a full turn in quarter turns).
    let n = ((rest / MAX_ARC_TURNING).ceil() as usize).clamp(1, 4);
    for i in 1..=n {
        let end = if i == n {
            segment.end()
        } else {
            segment.point(from + (length - from) * i as f64 / n as f64)
        };
        arc_to(d, &mut count, end);
    }
    count
}

/// One segment's path commands (without the initial move-to), and its report.
fn segment_commands(
    segment: &LacSegment,
    accuracy: f64,
    bounds: &mut Bounds,
    pad: f64,
) -> Option<(String, SvgSegmentReport)> {
    let mut d = String::new();
    let (k0, k1) = (segment.kappa0(), segment.kappa1());
    // A line, or an arc so nearly straight that its radius is ill-conditioned: a line, within a
    // thousandth of the accuracy.
    let straight = k0 == 0.0 && k1 == 0.0;
    let report =
        if straight || (k0 == k1 && arc_sagitta(segment) <= ARC_AS_LINE_FRACTION * accuracy) {
            d.push_str(" L");
            push_xy(&mut d, segment.end());
            bounds.add(segment.start(), pad);
            bounds.add(segment.end(), pad);
            SvgSegmentReport {
                element: SvgElement::Line,
                commands: 1,
                error: if straight { 0.0 } else { arc_sagitta(segment) },
            }
        } else if k0 == k1 {
            let n = push_arcs(&mut d, segment);
            let chord = LAC_CHORD_ERROR_FRACTION * pad;
            if (k0 * segment.length()).abs() >= std::f64::consts::TAU {
                // The whole circle is drawn: its box bounds the ink.
                let r = 1.0 / k0;
                let c = segment.start()
                    + Vec2::new(-segment.theta0().sin(), segment.theta0().cos()) * r;
                bounds.add_rect(
                    Rect::new(c.x - r.abs(), c.y - r.abs(), c.x + r.abs(), c.y + r.abs()),
                    pad,
                );
            } else {
                for s in segment.samples(lac_spacing(segment, chord)) {
                    bounds.add(s.point, pad + chord);
                }
            }
            SvgSegmentReport {
                element: SvgElement::Arc,
                commands: n,
                error: 0.0,
            }
        } else {
            let fit = segment_beziers(segment, accuracy);
            for c in &fit.cubics {
                push_cubic(&mut d, c);
                bounds.add_rect(c.bounding_box(), pad);
            }
            SvgSegmentReport {
                element: SvgElement::Cubic,
                commands: fit.cubics.len(),
                error: fit.error,
            }
        };
    // A non-finite number anywhere (a degenerate segment) leaves the segment out.
    if d.contains("NaN") || d.contains("inf") {
        return None;
    }
    Some((d, report))
}

/// The path data (`d`) of a chain of segments written to `accuracy`, starting with a move-to
/// the first segment's start, and what was written for each segment (segments with a
/// non-finite number are left out). [`svg_document`] writes this for every piece (as a
/// subpath of its stroke's path).
pub fn chain_path_data(segments: &[LacSegment], accuracy: f64) -> (String, Vec<SvgSegmentReport>) {
    let mut bounds = Bounds(None);
    let mut d = String::new();
    let mut reports = Vec::new();
    if let Some(first) = segments.first().filter(|s| finite(s.start())) {
        d.push('M');
        push_xy(&mut d, first.start());
        for s in segments {
            if let Some((commands, report)) = segment_commands(s, accuracy, &mut bounds, 0.0) {
                d.push_str(&commands);
                reports.push(report);
            }
        }
    }
    (d, reports)
}

/// The `<kansei:segment>` element of segment `index` of piece `piece`.
fn segment_metadata(
    piece: usize,
    index: usize,
    chain_segment: &crate::chain::ChainSegment,
    report: &SvgSegmentReport,
) -> String {
    let s = &chain_segment.segment;
    let alpha = s
        .alpha()
        .map_or_else(|| "null".to_owned(), |a| a.to_string());
    format!(
        "<kansei:segment piece=\"{piece}\" index=\"{index}\" alpha=\"{alpha}\" length=\"{}\" \
         kappa0=\"{}\" kappa1=\"{}\" max-deviation=\"{}\" samples=\"{} {}\" element=\"{}\" commands=\"{}\" \
         error=\"{}\"/>\n",
        s.length(),
        s.kappa0(),
        s.kappa1(),
        chain_segment.max_deviation,
        chain_segment.samples.0,
        chain_segment.samples.1,
        report.element.letter(),
        report.commands,
        report.error
    )
}

/// The fit's pieces (indices into [`FitOutput::curves`]) grouped by stroke: strokes in the order
/// of their first piece, pieces in the fit's order.
fn pieces_by_stroke(output: &FitOutput) -> Vec<(usize, Vec<usize>)> {
    let mut groups: Vec<(usize, Vec<usize>)> = Vec::new();
    for (piece, fit) in output.curves.iter().enumerate() {
        // Pieces of a stroke are consecutive in a pipeline's output, so the last group is
        // nearly always the one; the search covers outputs assembled otherwise (the app's).
        match groups.iter_mut().rev().find(|(s, _)| *s == fit.stroke) {
            Some((_, members)) => members.push(piece),
            None => groups.push((fit.stroke, vec![piece])),
        }
    }
    groups
}

/// Writes the SVG of a fit (see the module documentation). `strokes` supplies the raw samples
/// for the optional samples layer (without it the layer is empty).
pub fn svg_document(
    output: &FitOutput,
    strokes: Option<&StrokeFile>,
    options: &SvgOptions,
) -> SvgExport {
    let o = options.sanitized(output.units);
    let accuracy = export_accuracy(o.accuracy, output.tolerance);
    let width = o.line_width;
    let halo = 2.0 * width;
    let mut bounds = Bounds(None);
    let mut paths = Vec::new();

    let mut curves = format!(
        "<g id=\"curves\" fill=\"none\" stroke=\"#000000\" stroke-width=\"{width}\" \
         stroke-linejoin=\"round\" stroke-linecap=\"round\">\n"
    );
    let mut alpha_layer = format!(
        "<g id=\"alpha\" fill=\"none\" stroke-width=\"{width}\" stroke-linejoin=\"round\" \
         stroke-linecap=\"round\">\n"
    );
    for (stroke, members) in pieces_by_stroke(output) {
        let mut d = String::new();
        let mut metadata = String::new();
        let mut piece_reports = Vec::new();
        let mut samples: Option<(usize, usize)> = None;
        // Where the path's pen is: `None` before the first move-to and after a segment left out.
        let mut pen: Option<Point> = None;
        // A closed stroke drawn as one subpath ends with `Z` (its last segment ends exactly
        // where the subpath starts).
        let (mut subpaths, mut closed) = (0, false);
        for piece in members {
            let fit = &output.curves[piece];
            let Some(chain) = fit.chain.as_ref() else {
                continue;
            };
            let Some(first) = chain.segments.first() else {
                continue;
            };
            let start = first.segment.start();
            if !finite(start) {
                continue;
            }
            // A piece continues the subpath only when it starts exactly where it ended (the
            // written numbers then repeat a point already written): any gap, however small,
            // would bend the piece's first command away from its exact segment.
            let move_to = pen != Some(start);
            if move_to {
                subpaths += 1;
                d.push_str(if d.is_empty() { "M" } else { " M" });
                push_xy(&mut d, start);
                pen = Some(start);
            }
            let mut reports = Vec::new();
            for (i, cs) in chain.segments.iter().enumerate() {
                let seg_start = cs.segment.start();
                let Some((commands, report)) =
                    segment_commands(&cs.segment, accuracy, &mut bounds, 0.5 * width)
                else {
                    pen = None;
                    continue;
                };
                // After a segment left out, the next one opens a subpath at its own start.
                let Some(from) = pen.or_else(|| finite(seg_start).then_some(seg_start)) else {
                    continue;
                };
                if pen.is_none() {
                    d.push_str(" M");
                    push_xy(&mut d, from);
                }
                d.push_str(&commands);
                metadata.push_str(&segment_metadata(piece, i, cs, &report));
                if o.show_alpha {
                    let [r, g, b] = alpha_colour(cs.segment.alpha());
                    let mut seg_d = String::from("M");
                    push_xy(&mut seg_d, from);
                    let _ = writeln!(
                        alpha_layer,
                        "<path d=\"{seg_d}{commands}\" stroke=\"#{r:02x}{g:02x}{b:02x}\" \
                         data-stroke=\"{stroke}\" data-piece=\"{piece}\" data-segment=\"{i}\"/>"
                    );
                }
                pen = Some(cs.segment.end());
                reports.push(report);
            }
            closed = fit.closure.is_some();
            samples = Some(samples.map_or(fit.samples, |(a, b)| {
                (a.min(fit.samples.0), b.max(fit.samples.1))
            }));
            piece_reports.push(SvgPieceReport {
                piece,
                move_to,
                segments: reports,
            });
        }
        let Some((first_sample, last_sample)) = samples else {
            continue;
        };
        if closed && subpaths == 1 && pen.is_some() {
            d.push_str(" Z");
        }
        let report = SvgPathReport {
            stroke,
            pieces: piece_reports,
        };
        let _ = write!(
            curves,
            "<path id=\"stroke-{stroke}\" data-stroke=\"{stroke}\" \
             data-samples=\"{first_sample} {last_sample}\" data-pieces=\"{}\" \
             data-error=\"{}\" d=\"{d}\">\n<metadata>\n{metadata}</metadata>\n</path>\n",
            report.pieces.len(),
            report.max_error()
        );
        paths.push(report);
    }
    curves.push_str("</g>\n");
    alpha_layer.push_str("</g>\n");
    // Dots (taps) are drawn as discs of the line's width, each its own element naming its
    // stroke: the round end cap a pen leaves when it touches down and lifts in one place.
    let mut dots = String::new();
    for dot in output.dots.iter().filter(|d| finite(d.point)) {
        bounds.add(dot.point, 0.5 * width);
        let _ = writeln!(
            dots,
            "<circle id=\"dot-{}\" data-stroke=\"{}\" cx=\"{}\" cy=\"{}\" r=\"{}\"/>",
            dot.stroke,
            dot.stroke,
            dot.point.x,
            dot.point.y,
            0.5 * width
        );
    }
    if !dots.is_empty() {
        curves.push_str("<g id=\"dots\" fill=\"#000000\" stroke=\"none\">\n");
        curves.push_str(&dots);
        curves.push_str("</g>\n");
    }

    let mut body = String::new();
    if o.show_samples {
        body.push_str("<g id=\"samples\" fill=\"#7f7f7f\" stroke=\"none\">\n");
        let samples = strokes
            .iter()
            .flat_map(|f| &f.strokes)
            .flat_map(|s| &s.samples);
        for p in samples.map(|s| s.point()).filter(|p| finite(*p)) {
            bounds.add(p, o.sample_radius);
            let _ = writeln!(
                body,
                "<circle cx=\"{}\" cy=\"{}\" r=\"{}\"/>",
                p.x, p.y, o.sample_radius
            );
        }
        body.push_str("</g>\n");
    }
    if o.show_bspline {
        let _ = writeln!(
            body,
            "<g id=\"bspline\" fill=\"none\" stroke=\"#2ca02c\" stroke-opacity=\"0.45\" \
             stroke-width=\"{halo}\" stroke-linejoin=\"round\" stroke-linecap=\"round\">"
        );
        for fit in &output.curves {
            let mut d = String::new();
            let mut pen: Option<Point> = None;
            for piece in fit.bspline.curve.to_beziers() {
                let b = piece.bez;
                if !cubic_finite(&b) {
                    pen = None;
                    continue;
                }
                bounds.add_rect(b.bounding_box(), 0.5 * halo);
                if pen != Some(b.p0) {
                    d.push_str(if d.is_empty() { "M" } else { " M" });
                    push_xy(&mut d, b.p0);
                }
                push_cubic(&mut d, &b);
                pen = Some(b.p3);
            }
            if !d.is_empty() {
                let _ = writeln!(body, "<path d=\"{d}\"/>");
            }
        }
        body.push_str("</g>\n");
    }
    body.push_str(&curves);
    if o.show_alpha {
        body.push_str(&alpha_layer);
    }
    if o.show_splits {
        body.push_str("<g id=\"splits\" fill=\"#ff7f0e\" stroke=\"none\">\n");
        let half = 0.5 * o.split_size;
        let splits = output.curves.iter().flat_map(|c| &c.spans.splits);
        for p in splits.map(|s| s.point).filter(|p| finite(*p)) {
            bounds.add(p, half);
            let _ = writeln!(
                body,
                "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/>",
                p.x - half,
                p.y - half,
                o.split_size,
                o.split_size
            );
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
    let size = match output.units {
        Units::Mm => format!(" width=\"{w}mm\" height=\"{h}mm\""),
        Units::Px => format!(" width=\"{w}\" height=\"{h}\""),
        Units::Device => String::new(),
    };
    let export = SvgExport {
        svg: String::new(),
        accuracy,
        paths,
    };
    let mut svg = String::with_capacity(body.len() + 1024);
    svg.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        svg,
        "<!-- kansei: log-aesthetic curve chains. Coordinates are the data's own, in {units}; the \
         y axis is not flipped: SVG's y points down, so a y-up drawing appears mirrored top to \
         bottom. Lines and circular arcs are exact (L, A); spirals are cubic Beziers within \
         {within} {units} of the exact curve. -->",
        units = output.units.name(),
        // The accuracy asked for, or the measured error where a segment beyond the exporter's
        // work bound misses it: the comment states what holds.
        within = accuracy.max(export.max_error())
    );
    let _ = writeln!(
        svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:kansei=\"{SVG_METADATA_NAMESPACE}\" \
         version=\"1.1\" viewBox=\"{} {} {w} {h}\"{size}>",
        view.x0, view.y0
    );
    let _ = writeln!(
        svg,
        "<metadata>\n<kansei:export units=\"{}\" tolerance=\"{}\" accuracy=\"{accuracy}\" \
         error=\"{}\"/>\n</metadata>",
        output.units.name(),
        output.tolerance,
        export.max_error()
    );
    svg.push_str(&body);
    svg.push_str("</svg>\n");
    SvgExport { svg, ..export }
}
