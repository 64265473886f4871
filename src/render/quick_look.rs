//! The quick-look picture of a fitted file, as `kansei fit --png` and the service's
//! `/v1/export/png` draw it: the whole scene in view, overlays chosen by name.

use super::{Overlays, RenderError, RenderOptions, Scene, View, render_png, scene_bounds};
use crate::pipeline::FitOutput;
use crate::stroke::StrokeFile;

/// Margin around the scene, pixels: room for the scale bar below and the split markers at the
/// edges.
pub const QUICK_LOOK_MARGIN_PX: f64 = 48.0;

/// The overlay names [`Overlays::named`] takes, each an [`Overlays`] field.
pub const OVERLAY_NAMES: [&str; 10] = [
    "samples",
    "bspline",
    "control-polygon",
    "splits",
    "segments",
    "joints",
    "comb",
    "comb-log",
    "legend",
    "scale-bar",
];

impl Overlays {
    /// The overlays named in `layers` (names of [`OVERLAY_NAMES`]; others are ignored), the
    /// rest off.
    pub fn named(layers: &[String]) -> Overlays {
        let on = |name: &str| layers.iter().any(|l| l == name);
        Overlays {
            samples: on("samples"),
            bspline: on("bspline"),
            control_polygon: on("control-polygon"),
            splits: on("splits"),
            segments: on("segments"),
            joints: on("joints"),
            comb: on("comb"),
            comb_log: on("comb-log"),
            legend: on("legend"),
            scale_bar: on("scale-bar"),
        }
    }
}

/// The PNG of a fitted file: the whole scene in view ([`View::fit`] with a margin of
/// [`QUICK_LOOK_MARGIN_PX`]), drawn with `options`.
pub fn quick_look_png(
    file: &StrokeFile,
    output: &FitOutput,
    (width, height): (u32, u32),
    options: &RenderOptions,
) -> Result<Vec<u8>, RenderError> {
    let scene = Scene::new(&file.strokes, &output.curves, file.units);
    let bounds = scene_bounds(&scene).unwrap_or_default();
    let view = View::fit(bounds, width, height, QUICK_LOOK_MARGIN_PX);
    render_png(&scene, &view, options)
}
