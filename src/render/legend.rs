//! The α colour legend (top right) and the scale bar (bottom left), in pixels, sized by
//! [`RenderOptions::text_size`].

use super::colour::{
    ALPHA_BLUE_END, ALPHA_RED_END, INK, NO_ALPHA_RGB, PANEL, Rgba, color, segment_colour,
};
use super::options::RenderOptions;
use super::primitives::{fill, polyline, stroke};
use super::text::{draw_text, text_width};
use super::view::View;
use crate::geom::{Point, Rect};
use crate::stroke::Units;
use tiny_skia::{PathBuilder, Pixmap};

/// α values labelled under the legend's ramp (its ends are the colour map's saturation points).
pub const LEGEND_TICKS: [f64; 5] = [ALPHA_BLUE_END, -1.0, 0.0, 1.0, ALPHA_RED_END];

/// Width of the legend's colour ramp, in text sizes.
pub const RAMP_WIDTH_EM: f64 = 10.0;

/// The scale bar is at most this fraction of the image width long.
pub const SCALE_BAR_FRACTION: f64 = 0.2;

/// A tick label: "−2", "0", "1.5" (a true minus sign, shortest decimals).
fn tick_label(v: f64) -> String {
    let text = format!("{}", v.abs());
    if v < 0.0 { format!("−{text}") } else { text }
}

fn rect(pixmap: &mut Pixmap, x: f64, y: f64, w: f64, h: f64, rgba: Rgba) {
    if let Some(r) = tiny_skia::Rect::from_xywh(x as f32, y as f32, w as f32, h as f32) {
        fill(pixmap, &PathBuilder::from_rect(r), rgba);
    }
}

/// Where the legend sits, pixels ([`legend_layout`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LegendLayout {
    /// The panel (white, framed).
    pub panel: Rect,
    /// The colour ramp: α runs linearly from [`ALPHA_BLUE_END`] at `ramp.x0` to
    /// [`ALPHA_RED_END`] at `ramp.x1`; its corners are whole pixels.
    pub ramp: Rect,
}

/// The legend's layout for an image `image_width` pixels wide with text of cap height
/// `text_size` (`None` for a non-positive size: no legend).
pub fn legend_layout(image_width: u32, text_size: f64) -> Option<LegendLayout> {
    let t = text_size;
    if !(t > 0.0 && t.is_finite()) {
        return None;
    }
    let (pad, gap) = (0.6 * t, 0.5 * t);
    let ramp_w = (RAMP_WIDTH_EM * t).round().max(1.0);
    let ramp_h = (0.9 * t).round().max(1.0);
    // The end labels are centred on the ramp's ends and overhang them by half their width.
    let label_half = 0.5 * text_width(&tick_label(ALPHA_BLUE_END), t);
    let ramp_left = (text_width("α", t) + gap).max(label_half);
    let inner_w =
        (ramp_left + ramp_w + label_half).max(2.0 * t + gap + text_width(SWATCH_LABEL, t));
    let panel_w = inner_w + 2.0 * pad;
    // Rows: ramp, gap, tick labels, gap, swatch.
    let panel_h = pad + ramp_h + gap + t + 1.5 * gap + t + pad;
    let x0 = f64::from(image_width) - pad - panel_w;
    let y0 = pad;
    let ramp_x = (x0 + pad + ramp_left).round();
    let ramp_y = (y0 + pad).round();
    Some(LegendLayout {
        panel: Rect::new(x0, y0, x0 + panel_w, y0 + panel_h),
        ramp: Rect::new(ramp_x, ramp_y, ramp_x + ramp_w, ramp_y + ramp_h),
    })
}

/// Label of the legend's black swatch.
const SWATCH_LABEL: &str = "arc/line";

/// Draws the legend ([`legend_layout`]): a panel at the top right with the α ramp
/// ([`alpha_colour`] at the centre of each pixel column), its tick labels ([`LEGEND_TICKS`]),
/// the symbol α, and a black swatch labelled "arc/line" (α = null).
///
/// [`alpha_colour`]: super::colour::alpha_colour
pub fn draw_legend(pixmap: &mut Pixmap, options: &RenderOptions) {
    let t = options.text_size;
    let Some(layout) = legend_layout(pixmap.width(), t) else {
        return;
    };
    let (pad, gap) = (0.6 * t, 0.5 * t);
    let swatch = SWATCH_LABEL;
    let p = layout.panel;
    let (x0, y0, panel_w, panel_h) = (p.x0, p.y0, p.width(), p.height());
    let (ramp_x, ramp_y) = (layout.ramp.x0, layout.ramp.y0);
    let (ramp_w, ramp_h) = (layout.ramp.width(), layout.ramp.height());
    rect(pixmap, x0, y0, panel_w, panel_h, PANEL);
    if let Some(frame) = polyline(
        [
            (x0, y0),
            (x0 + panel_w, y0),
            (x0 + panel_w, y0 + panel_h),
            (x0, y0 + panel_h),
            (x0, y0),
        ]
        .map(|(x, y)| Point::new(x, y)),
    ) {
        stroke(pixmap, &frame, INK, 1.0);
    }

    // α and the ramp.
    draw_text(
        pixmap,
        "α",
        x0 + pad,
        ramp_y + 0.5 * (ramp_h + t),
        t,
        color(INK),
    );
    let columns = ramp_w as usize;
    for i in 0..columns {
        let a = ALPHA_BLUE_END + (ALPHA_RED_END - ALPHA_BLUE_END) * (i as f64 + 0.5) / ramp_w;
        rect(
            pixmap,
            ramp_x + i as f64,
            ramp_y,
            1.0,
            ramp_h,
            segment_colour(Some(a)),
        );
    }
    let label_y = ramp_y + ramp_h + gap + t;
    for v in LEGEND_TICKS {
        let x = ramp_x + ramp_w * (v - ALPHA_BLUE_END) / (ALPHA_RED_END - ALPHA_BLUE_END);
        if let Some(tick) = polyline([
            Point::new(x, ramp_y + ramp_h),
            Point::new(x, ramp_y + ramp_h + 0.3 * gap),
        ]) {
            stroke(pixmap, &tick, INK, 1.0);
        }
        let label = tick_label(v);
        draw_text(
            pixmap,
            &label,
            x - 0.5 * text_width(&label, t),
            label_y,
            t,
            color(INK),
        );
    }

    // The arc/line swatch.
    let row_y = label_y + 1.5 * gap + 0.5 * t;
    let [r, g, b] = NO_ALPHA_RGB;
    if let Some(line) = polyline([
        Point::new(x0 + pad, row_y),
        Point::new(x0 + pad + 2.0 * t, row_y),
    ]) {
        stroke(
            pixmap,
            &line,
            [r, g, b, 255],
            options.segment_width.max(1.0),
        );
    }
    draw_text(
        pixmap,
        swatch,
        x0 + pad + 2.0 * t + gap,
        row_y + 0.5 * t,
        t,
        color(INK),
    );
}

/// The scale bar's length in model units: the largest 1, 2 or 5 × 10ᵏ whose pixel length is at
/// most [`SCALE_BAR_FRACTION`] of the image width, with the exponent k (for the label's
/// decimals). `None` if the view gives no finite length.
pub fn scale_bar_length(view: &View) -> Option<(f64, i32)> {
    let max_units = SCALE_BAR_FRACTION * f64::from(view.width) / view.pixels_per_unit;
    if !(max_units.is_finite() && max_units > 0.0) {
        return None;
    }
    let k = max_units.log10().floor();
    let decade = 10f64.powf(k);
    let m = max_units / decade;
    // Rounding can put m a hair below 1 or at 10: clamp to the decade's own steps.
    let step = if m >= 5.0 {
        5.0
    } else if m >= 2.0 {
        2.0
    } else {
        1.0
    };
    let length = step * decade;
    (length.is_finite() && length > 0.0).then_some((length, k as i32))
}

/// The scale bar's label: the length with as many decimals as its exponent needs, and the units.
pub fn scale_bar_label(length: f64, exponent: i32, units: Units) -> String {
    let decimals = usize::try_from(-exponent).unwrap_or(0);
    format!("{length:.decimals$} {}", units.name())
}

/// Draws the scale bar at the bottom left: a bar of [`scale_bar_length`] with end ticks, its
/// label above.
pub fn draw_scale_bar(pixmap: &mut Pixmap, view: &View, units: Units, options: &RenderOptions) {
    let t = options.text_size;
    let Some((length, exponent)) = scale_bar_length(view) else {
        return;
    };
    let px = length * view.pixels_per_unit;
    let pad = 0.8 * t.max(1.0);
    let x0 = pad;
    let y = f64::from(view.height) - pad;
    let tick = 0.4 * t.max(1.0);
    let bar = polyline(
        [(x0, y - tick), (x0, y), (x0 + px, y), (x0 + px, y - tick)].map(|(x, y)| Point::new(x, y)),
    );
    if let Some(bar) = bar {
        stroke(pixmap, &bar, INK, (0.15 * t).max(1.5));
    }
    if t > 0.0 {
        let label = scale_bar_label(length, exponent, units);
        let w = text_width(&label, t);
        draw_text(
            pixmap,
            &label,
            x0 + 0.5 * (px - w).max(0.0),
            y - tick - 0.4 * t,
            t,
            color(INK),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn view(ppu: f64) -> View {
        View {
            width: 1000,
            height: 500,
            center: Point::ORIGIN,
            pixels_per_unit: ppu,
        }
    }

    #[test]
    fn scale_bar_is_a_round_length_within_a_fifth_of_the_width() {
        // 200 px available.
        for (ppu, want) in [
            (1.0, 200.0),
            (3.0, 50.0),
            (0.7, 200.0),
            (15.0, 10.0),
            (250.0, 0.5),
        ] {
            let (len, _) = scale_bar_length(&view(ppu)).expect("a length");
            assert!((len - want).abs() < 1e-12 * want, "{ppu}: {len}");
            assert!(len * ppu <= 200.0 + 1e-9);
            assert!(len * ppu > 80.0, "more than 2/5 of the room: {}", len * ppu);
        }
        assert_eq!(scale_bar_label(10.0, 1, Units::Mm), "10 mm");
        assert_eq!(scale_bar_label(0.5, -1, Units::Mm), "0.5 mm");
        assert_eq!(scale_bar_label(0.01 + 1e-18, -2, Units::Px), "0.01 px");
        assert_eq!(tick_label(-2.0), "−2");
    }
}
