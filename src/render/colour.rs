//! The palette. LAC segments use [`alpha_colour`], the same map as the SVG export (re-used from
//! [`crate::export`], so a PNG and an SVG of one fit agree colour for colour); the overlays get
//! fixed colours from the Tableau 10 palette (distinct, and none of them on the α map's
//! blue–grey–red axis except where noted).

pub use crate::export::{
    ALPHA_BLUE_END, ALPHA_BLUE_RGB, ALPHA_RED_END, ALPHA_RED_RGB, ALPHA_ZERO_RGB, NO_ALPHA_RGB,
    alpha_colour,
};
use tiny_skia::Color;

/// An sRGB colour with straight (not premultiplied) alpha, `[r, g, b, a]`.
pub type Rgba = [u8; 4];

/// Default background: opaque white.
pub const BACKGROUND: Rgba = [255, 255, 255, 255];
/// Raw samples: grey, slightly translucent so dense samples read as a band.
pub const SAMPLE: Rgba = [127, 127, 127, 200];
/// The B-spline: a pale green halo under the LAC chain (as in the SVG), so any disagreement
/// between the two stands out.
pub const BSPLINE: Rgba = [44, 160, 44, 115];
/// The control polygon and its vertices: translucent steel blue.
pub const CONTROL_POLYGON: Rgba = [31, 119, 180, 170];
/// The curvature comb: teeth and envelope, translucent purple.
pub const COMB: Rgba = [148, 103, 189, 170];
/// Highlighted segment: a wide translucent gold band under it.
pub const HIGHLIGHT: Rgba = [255, 200, 0, 150];
/// Split markers' outline (and the start/end rings).
pub const MARKER_OUTLINE: Rgba = [40, 40, 40, 255];
/// Fill of inflection markers (diamonds).
pub const INFLECTION: Rgba = [23, 190, 207, 255];
/// Fill of curvature-extremum markers (triangles).
pub const EXTREMUM: Rgba = [255, 127, 14, 255];
/// Fill of corner markers (squares).
pub const CORNER: Rgba = [214, 39, 40, 255];
/// Text, scale bar and legend frame.
pub const INK: Rgba = [30, 30, 30, 255];
/// The legend's panel: white, mostly opaque, so it stays legible over curves.
pub const PANEL: Rgba = [255, 255, 255, 220];

/// `rgba` as a tiny-skia colour.
pub fn color(rgba: Rgba) -> Color {
    let [r, g, b, a] = rgba;
    Color::from_rgba8(r, g, b, a)
}

/// The opaque colour of an LAC of slope `alpha` ([`alpha_colour`]).
pub fn segment_colour(alpha: Option<f64>) -> Rgba {
    let [r, g, b] = alpha_colour(alpha);
    [r, g, b, 255]
}
