//! A tiny stroke font: the digits, a few signs and the lower-case letters that the legend and the
//! scale bar need (`0-9 . − + = / α` and `a c d e i l m n p r v x`), drawn as tiny-skia strokes.
//!
//! tiny-skia has no text. A stroke font of ~25 glyphs is ~100 lines, needs no font file, no licence
//! beside the project's own and no rasteriser crate, renders the same on every machine (it is
//! ordinary anti-aliased path stroking), and stays legible from 8 px up; a general font stack
//! (a rasteriser crate plus a bundled OFL font) would be the right call only if arbitrary text
//! were drawn, which it is not (the app draws its own text with egui).
//!
//! Glyphs are polylines on a grid [`GLYPH_GRID`] units tall (the cap height; y down, baseline at
//! y = 6, x-height 4 units), [`GLYPH_WIDTH`] wide, advancing by [`GLYPH_ADVANCE`].

use tiny_skia::{Color, LineCap, LineJoin, Paint, PathBuilder, Pixmap, Stroke, Transform};

/// Cap height of the glyph grid, in grid units: a glyph drawn at text size `h` pixels is scaled by
/// `h / GLYPH_GRID`.
pub const GLYPH_GRID: f64 = 6.0;
/// Width of a glyph's box, grid units.
pub const GLYPH_WIDTH: f64 = 4.0;
/// Horizontal advance from one glyph to the next, grid units (the width plus a gap of two).
pub const GLYPH_ADVANCE: f64 = 6.0;
/// Stroke width as a fraction of the text size: 1/7 of the cap height reads as a regular weight.
pub const STROKE_FRACTION: f64 = 1.0 / 7.0;
/// Thinnest stroke drawn, pixels: thinner anti-aliased lines fade out.
pub const MIN_STROKE_PX: f64 = 1.0;

type Polyline = &'static [(f32, f32)];

/// The polylines of `c`, `None` for a character the font does not have (a space has none and is
/// known: `Some(&[])`).
pub fn glyph(c: char) -> Option<&'static [Polyline]> {
    let g: &'static [Polyline] = match c {
        ' ' => &[],
        '0' => &[&[
            (1.0, 0.0),
            (3.0, 0.0),
            (4.0, 1.0),
            (4.0, 5.0),
            (3.0, 6.0),
            (1.0, 6.0),
            (0.0, 5.0),
            (0.0, 1.0),
            (1.0, 0.0),
        ]],
        '1' => &[
            &[(1.0, 1.0), (2.0, 0.0), (2.0, 6.0)],
            &[(1.0, 6.0), (3.0, 6.0)],
        ],
        '2' => &[&[
            (0.0, 1.0),
            (1.0, 0.0),
            (3.0, 0.0),
            (4.0, 1.0),
            (4.0, 2.0),
            (0.0, 6.0),
            (4.0, 6.0),
        ]],
        '3' => &[&[
            (0.0, 0.0),
            (4.0, 0.0),
            (2.0, 2.5),
            (3.0, 2.5),
            (4.0, 3.5),
            (4.0, 5.0),
            (3.0, 6.0),
            (1.0, 6.0),
            (0.0, 5.0),
        ]],
        '4' => &[&[(3.0, 6.0), (3.0, 0.0), (0.0, 4.0), (4.0, 4.0)]],
        '5' => &[&[
            (4.0, 0.0),
            (0.0, 0.0),
            (0.0, 2.5),
            (3.0, 2.5),
            (4.0, 3.5),
            (4.0, 5.0),
            (3.0, 6.0),
            (0.0, 6.0),
        ]],
        '6' => &[&[
            (3.0, 0.0),
            (1.0, 0.0),
            (0.0, 1.0),
            (0.0, 5.0),
            (1.0, 6.0),
            (3.0, 6.0),
            (4.0, 5.0),
            (4.0, 3.5),
            (3.0, 2.5),
            (0.0, 2.5),
        ]],
        '7' => &[&[(0.0, 0.0), (4.0, 0.0), (1.5, 6.0)]],
        '8' => &[&[
            (1.0, 0.0),
            (3.0, 0.0),
            (4.0, 1.0),
            (4.0, 2.0),
            (3.0, 3.0),
            (1.0, 3.0),
            (0.0, 4.0),
            (0.0, 5.0),
            (1.0, 6.0),
            (3.0, 6.0),
            (4.0, 5.0),
            (4.0, 4.0),
            (3.0, 3.0),
            (1.0, 3.0),
            (0.0, 2.0),
            (0.0, 1.0),
            (1.0, 0.0),
        ]],
        '9' => &[&[
            (4.0, 3.5),
            (1.0, 3.5),
            (0.0, 2.5),
            (0.0, 1.0),
            (1.0, 0.0),
            (3.0, 0.0),
            (4.0, 1.0),
            (4.0, 5.0),
            (3.0, 6.0),
            (1.0, 6.0),
        ]],
        '-' | '−' => &[&[(0.5, 3.5), (3.5, 3.5)]],
        '+' => &[&[(2.0, 2.0), (2.0, 5.0)], &[(0.5, 3.5), (3.5, 3.5)]],
        '=' => &[&[(0.5, 2.5), (3.5, 2.5)], &[(0.5, 4.5), (3.5, 4.5)]],
        // A zero-length stroke with round caps is a dot.
        '.' => &[&[(2.0, 6.0), (2.0, 6.0)]],
        '/' => &[&[(0.0, 6.0), (4.0, 0.0)]],
        'α' => &[&[
            (4.5, 2.0),
            (3.0, 5.0),
            (2.0, 6.0),
            (1.0, 6.0),
            (0.0, 5.0),
            (0.0, 3.0),
            (1.0, 2.0),
            (2.0, 2.0),
            (3.0, 3.0),
            (4.0, 6.0),
        ]],
        'a' => &[
            &[(4.0, 2.0), (4.0, 6.0)],
            &[
                (4.0, 3.0),
                (3.0, 2.0),
                (1.0, 2.0),
                (0.0, 3.0),
                (0.0, 5.0),
                (1.0, 6.0),
                (3.0, 6.0),
                (4.0, 5.0),
            ],
        ],
        'c' => &[&[
            (4.0, 2.0),
            (1.0, 2.0),
            (0.0, 3.0),
            (0.0, 5.0),
            (1.0, 6.0),
            (4.0, 6.0),
        ]],
        'd' => &[
            &[(4.0, 0.0), (4.0, 6.0)],
            &[
                (4.0, 5.0),
                (3.0, 6.0),
                (1.0, 6.0),
                (0.0, 5.0),
                (0.0, 3.0),
                (1.0, 2.0),
                (3.0, 2.0),
                (4.0, 3.0),
            ],
        ],
        'e' => &[&[
            (0.0, 4.0),
            (4.0, 4.0),
            (4.0, 3.0),
            (3.0, 2.0),
            (1.0, 2.0),
            (0.0, 3.0),
            (0.0, 5.0),
            (1.0, 6.0),
            (4.0, 6.0),
        ]],
        'i' => &[&[(2.0, 2.0), (2.0, 6.0)], &[(2.0, 0.5), (2.0, 0.5)]],
        'l' => &[&[(2.0, 0.0), (2.0, 6.0)]],
        'm' => &[
            &[(0.0, 6.0), (0.0, 2.0)],
            &[(0.0, 3.0), (1.0, 2.0), (2.0, 3.0), (2.0, 6.0)],
            &[(2.0, 3.0), (3.0, 2.0), (4.0, 3.0), (4.0, 6.0)],
        ],
        'n' => &[
            &[(0.0, 2.0), (0.0, 6.0)],
            &[(0.0, 3.0), (1.0, 2.0), (3.0, 2.0), (4.0, 3.0), (4.0, 6.0)],
        ],
        'p' => &[
            &[(0.0, 8.0), (0.0, 2.0)],
            &[
                (0.0, 3.0),
                (1.0, 2.0),
                (3.0, 2.0),
                (4.0, 3.0),
                (4.0, 5.0),
                (3.0, 6.0),
                (1.0, 6.0),
                (0.0, 5.0),
            ],
        ],
        'r' => &[
            &[(0.0, 2.0), (0.0, 6.0)],
            &[(0.0, 4.0), (2.0, 2.0), (4.0, 2.0)],
        ],
        'v' => &[&[(0.0, 2.0), (2.0, 6.0), (4.0, 2.0)]],
        'x' => &[&[(0.0, 2.0), (4.0, 6.0)], &[(4.0, 2.0), (0.0, 6.0)]],
        _ => return None,
    };
    Some(g)
}

/// Width in pixels of `text` drawn at cap height `size` (the last glyph's box, not its advance).
pub fn text_width(text: &str, size: f64) -> f64 {
    let n = text.chars().count();
    if n == 0 {
        return 0.0;
    }
    size / GLYPH_GRID * ((n - 1) as f64 * GLYPH_ADVANCE + GLYPH_WIDTH)
}

/// Stroke width for text of cap height `size` pixels.
pub fn stroke_width(size: f64) -> f64 {
    (size * STROKE_FRACTION).max(MIN_STROKE_PX)
}

/// Draws `text` with its baseline's left end at (`x`, `y`) pixels, cap height `size` pixels.
/// Characters the font lacks ([`glyph`] gives `None`) are drawn as an empty box, so they show.
pub fn draw_text(pixmap: &mut Pixmap, text: &str, x: f64, y: f64, size: f64, colour: Color) {
    let k = size / GLYPH_GRID;
    let mut path = PathBuilder::new();
    const MISSING: &[Polyline] = &[&[(0.0, 0.0), (4.0, 0.0), (4.0, 6.0), (0.0, 6.0), (0.0, 0.0)]];
    for (i, c) in text.chars().enumerate() {
        let left = x + i as f64 * GLYPH_ADVANCE * k;
        for line in glyph(c).unwrap_or(MISSING) {
            for (j, &(gx, gy)) in line.iter().enumerate() {
                let px = (left + f64::from(gx) * k) as f32;
                let py = (y + (f64::from(gy) - GLYPH_GRID) * k) as f32;
                if j == 0 {
                    path.move_to(px, py);
                } else {
                    path.line_to(px, py);
                }
            }
        }
    }
    let Some(path) = path.finish() else {
        return;
    };
    let mut paint = Paint::default();
    paint.set_color(colour);
    paint.anti_alias = true;
    let stroke = Stroke {
        width: stroke_width(size) as f32,
        line_cap: LineCap::Round,
        line_join: LineJoin::Round,
        ..Stroke::default()
    };
    pixmap.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_needed_character_has_a_glyph_inside_its_box() {
        for c in "0123456789.-−+=/α acdeilmnprvx".chars() {
            let g = glyph(c).unwrap_or_else(|| panic!("no glyph for {c:?}"));
            for &(x, y) in g.iter().flat_map(|l| l.iter()) {
                // Descender of p down to 8, α's tail to 4.5.
                assert!(
                    (0.0..=4.5).contains(&x) && (0.0..=8.0).contains(&y),
                    "{c:?}"
                );
            }
        }
        assert!(glyph('Q').is_none());
    }

    #[test]
    fn text_is_drawn_inside_its_measured_box() {
        let mut pixmap = Pixmap::new(80, 30).expect("80×30 pixmap");
        let size = 12.0;
        draw_text(&mut pixmap, "10 mm", 5.0, 20.0, size, Color::BLACK);
        let w = text_width("10 mm", size);
        let pad = stroke_width(size);
        let mut inked = 0;
        for (i, p) in pixmap.pixels().iter().enumerate() {
            if p.alpha() > 0 {
                inked += 1;
                let (x, y) = ((i % 80) as f64 + 0.5, (i / 80) as f64 + 0.5);
                assert!(x >= 5.0 - pad && x <= 5.0 + w + pad, "x {x}");
                assert!(y >= 20.0 - size - pad && y <= 20.0 + pad, "y {y}");
            }
        }
        assert!(inked > 50, "{inked} pixels inked");
    }
}
