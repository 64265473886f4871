//! Drawing primitives in pixel coordinates: polylines, cubic paths, dots and marker shapes, on
//! top of tiny-skia (anti-aliased, source-over).

use super::colour::{Rgba, color};
use crate::geom::{CubicBez, Point};
use crate::split::SplitKind;
use tiny_skia::{FillRule, LineCap, LineJoin, Paint, Path, PathBuilder, Pixmap, Stroke, Transform};

/// Pixel coordinates beyond ±this are not drawn (a polyline breaks there): tiny-skia works in
/// f32, whose spacing at 10⁶ is 1/16 px, and anything that far off the image is invisible anyway.
pub const PIXEL_COORD_LIMIT: f64 = 1e6;

/// The shape of a split marker.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MarkerShape {
    /// An open ring: the start or end of a piece.
    Ring,
    /// A diamond: an inflection.
    Diamond,
    /// A triangle pointing up: a curvature extremum.
    Triangle,
    /// A square: a corner.
    Square,
}

impl MarkerShape {
    /// The marker of a split of kind `kind`.
    pub fn for_split(kind: SplitKind) -> MarkerShape {
        match kind {
            SplitKind::Start | SplitKind::End | SplitKind::Seam => MarkerShape::Ring,
            SplitKind::Inflection => MarkerShape::Diamond,
            SplitKind::CurvatureExtremum => MarkerShape::Triangle,
            SplitKind::Corner => MarkerShape::Square,
        }
    }
}

/// `p` as tiny-skia coordinates, if finite and within [`PIXEL_COORD_LIMIT`].
pub fn to_f32(p: Point) -> Option<(f32, f32)> {
    let ok = |v: f64| v.is_finite() && v.abs() <= PIXEL_COORD_LIMIT;
    (ok(p.x) && ok(p.y)).then_some((p.x as f32, p.y as f32))
}

/// A path through `points` (pixels), broken wherever a point is unusable ([`to_f32`]). A lone
/// point becomes a zero-length line, which round caps draw as a dot.
pub fn polyline(points: impl IntoIterator<Item = Point>) -> Option<Path> {
    let mut path = PathBuilder::new();
    let mut pen_down = false;
    for p in points {
        match to_f32(p) {
            Some((x, y)) if pen_down => path.line_to(x, y),
            Some((x, y)) => {
                path.move_to(x, y);
                pen_down = true;
            }
            None => pen_down = false,
        }
    }
    path.finish()
}

/// A path of consecutive cubic Béziers (pixels); a piece with an unusable point is left out and
/// the next starts afresh.
pub fn cubics(pieces: impl IntoIterator<Item = CubicBez>) -> Option<Path> {
    let mut path = PathBuilder::new();
    let mut pen: Option<Point> = None;
    for b in pieces {
        let (Some(p0), Some(p1), Some(p2), Some(p3)) =
            (to_f32(b.p0), to_f32(b.p1), to_f32(b.p2), to_f32(b.p3))
        else {
            pen = None;
            continue;
        };
        if pen != Some(b.p0) {
            path.move_to(p0.0, p0.1);
        }
        path.cubic_to(p1.0, p1.1, p2.0, p2.1, p3.0, p3.1);
        pen = Some(b.p3);
    }
    path.finish()
}

fn paint(rgba: Rgba) -> Paint<'static> {
    let mut paint = Paint::default();
    paint.set_color(color(rgba));
    paint.anti_alias = true;
    paint
}

/// Strokes `path` `width` pixels wide with round caps and joins (nothing for width 0).
pub fn stroke(pixmap: &mut Pixmap, path: &Path, rgba: Rgba, width: f64) {
    if !(width > 0.0) {
        return;
    }
    let stroke = Stroke {
        width: width as f32,
        line_cap: LineCap::Round,
        line_join: LineJoin::Round,
        ..Stroke::default()
    };
    pixmap.stroke_path(path, &paint(rgba), &stroke, Transform::identity(), None);
}

/// Fills `path` (non-zero rule).
pub fn fill(pixmap: &mut Pixmap, path: &Path, rgba: Rgba) {
    pixmap.fill_path(
        path,
        &paint(rgba),
        FillRule::Winding,
        Transform::identity(),
        None,
    );
}

/// A filled disc of `radius` pixels at `centre` (nothing for radius 0 or an unusable centre).
pub fn dot(pixmap: &mut Pixmap, centre: Point, radius: f64, rgba: Rgba) {
    let Some((x, y)) = to_f32(centre) else {
        return;
    };
    if let Some(path) = PathBuilder::from_circle(x, y, radius as f32) {
        fill(pixmap, &path, rgba);
    }
}

/// The outline of `shape` of size `size` pixels centred at `centre` (see
/// [`RenderOptions::marker_size`](super::RenderOptions::marker_size)).
pub fn marker_path(shape: MarkerShape, centre: Point, size: f64) -> Option<Path> {
    let (x, y) = to_f32(centre)?;
    let h = (0.5 * size) as f32;
    match shape {
        MarkerShape::Ring => PathBuilder::from_circle(x, y, h),
        MarkerShape::Square => {
            PathBuilder::from_rect(tiny_skia::Rect::from_xywh(x - h, y - h, 2.0 * h, 2.0 * h)?)
                .into()
        }
        MarkerShape::Diamond | MarkerShape::Triangle => {
            let corners: &[(f32, f32)] = if shape == MarkerShape::Diamond {
                &[(0.0, -1.0), (1.0, 0.0), (0.0, 1.0), (-1.0, 0.0)]
            } else {
                // Equilateral, centred on its centroid, side = size.
                &[(0.0, -1.1547), (1.0, 0.5774), (-1.0, 0.5774)]
            };
            let mut path = PathBuilder::new();
            for (i, &(dx, dy)) in corners.iter().enumerate() {
                if i == 0 {
                    path.move_to(x + dx * h, y + dy * h);
                } else {
                    path.line_to(x + dx * h, y + dy * h);
                }
            }
            path.close();
            path.finish()
        }
    }
}

/// A split marker: `fill` inside an outline of `outline` colour; rings are drawn open.
pub fn marker(
    pixmap: &mut Pixmap,
    shape: MarkerShape,
    centre: Point,
    size: f64,
    fill_rgba: Rgba,
    outline: Rgba,
) {
    let Some(path) = marker_path(shape, centre, size) else {
        return;
    };
    // The outline is an eighth of the size: visible, yet thin enough to keep the shape readable.
    let line = (size / 8.0).max(1.0);
    if shape != MarkerShape::Ring {
        fill(pixmap, &path, fill_rgba);
    }
    stroke(pixmap, &path, outline, line);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polyline_breaks_at_unusable_points() {
        let pts = [
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(f64::NAN, 0.0),
            Point::new(2e6, 0.0),
            Point::new(10.0, 10.0),
            Point::new(0.0, 10.0),
        ];
        let path = polyline(pts).expect("two pieces");
        let moves = path
            .segments()
            .filter(|s| matches!(s, tiny_skia::PathSegment::MoveTo(_)))
            .count();
        assert_eq!(moves, 2);
        assert!(polyline([Point::new(f64::INFINITY, 0.0)]).is_none());
    }

    #[test]
    fn marker_shapes_fit_their_size() {
        let c = Point::new(50.0, 50.0);
        for shape in [
            MarkerShape::Ring,
            MarkerShape::Diamond,
            MarkerShape::Triangle,
            MarkerShape::Square,
        ] {
            let b = marker_path(shape, c, 10.0).expect("a shape").bounds();
            // The triangle's apex sits 2/√3·5 ≈ 5.77 above its centroid.
            assert!(b.left() >= 44.9 && b.right() <= 55.1, "{shape:?} {b:?}");
            assert!(b.top() >= 44.2 && b.bottom() <= 55.1, "{shape:?} {b:?}");
        }
        assert_eq!(
            MarkerShape::for_split(SplitKind::Corner),
            MarkerShape::Square
        );
    }
}
