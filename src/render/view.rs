//! The one model → pixel transform shared by every overlay.
//!
//! A model point p (the stroke's units, y down like the stroke data and like the image) maps to
//!
//! ```text
//! pixel(p) = (p − center)·k + (width/2, height/2),     k = pixels_per_unit,
//! model(q) = (q − (width/2, height/2))/k + center,
//! ```
//!
//! in continuous pixel coordinates: pixel (i, j) covers [i, i + 1) × [j, j + 1), so the image
//! spans [0, width] × [0, height] and its centre is (width/2, height/2). No axis is flipped.

use super::error::{MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE, RenderError};
use crate::geom::{Point, Rect, Vec2};

/// Scale used by [`View::fit`] when the bounds give none (a single point, or nothing finite):
/// one pixel per unit.
pub const FALLBACK_PIXELS_PER_UNIT: f64 = 1.0;

/// Least room [`View::fit`] leaves for the scene, pixels, when the margins eat the whole image.
pub const MIN_FIT_EXTENT_PX: f64 = 1.0;

/// Where the model sits in the image (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// The model point at the image centre.
    pub center: Point,
    /// Pixels per model unit (the zoom).
    pub pixels_per_unit: f64,
}

impl View {
    /// The view of `width` × `height` pixels that shows all of `bounds` as large as possible
    /// with at least `margin_px` pixels free on every side, centred. A degenerate extent (a
    /// horizontal or vertical line) is fitted along the other axis; a single point, or bounds
    /// that are not finite, get [`FALLBACK_PIXELS_PER_UNIT`] (and the origin as centre when not
    /// finite). A margin that leaves less than [`MIN_FIT_EXTENT_PX`] is shrunk to leave that.
    pub fn fit(bounds: Rect, width: u32, height: u32, margin_px: f64) -> View {
        let b = bounds.abs();
        let finite = [b.x0, b.y0, b.x1, b.y1].iter().all(|v| v.is_finite());
        if !finite {
            return View {
                width,
                height,
                center: Point::ORIGIN,
                pixels_per_unit: FALLBACK_PIXELS_PER_UNIT,
            };
        }
        let margin = if margin_px.is_finite() {
            margin_px.max(0.0)
        } else {
            0.0
        };
        let room = |side: u32| (f64::from(side) - 2.0 * margin).max(MIN_FIT_EXTENT_PX);
        let scale = |room: f64, extent: f64| (extent > 0.0).then(|| room / extent);
        let k = match (
            scale(room(width), b.width()),
            scale(room(height), b.height()),
        ) {
            (Some(a), Some(c)) => a.min(c),
            (Some(a), None) | (None, Some(a)) => a,
            (None, None) => FALLBACK_PIXELS_PER_UNIT,
        };
        View {
            width,
            height,
            center: b.center(),
            pixels_per_unit: if k.is_finite() && k > 0.0 {
                k
            } else {
                FALLBACK_PIXELS_PER_UNIT
            },
        }
    }

    /// The pixel position of model point `p`.
    pub fn to_pixel(&self, p: Point) -> Point {
        let k = self.pixels_per_unit;
        Point::new(
            (p.x - self.center.x) * k + 0.5 * f64::from(self.width),
            (p.y - self.center.y) * k + 0.5 * f64::from(self.height),
        )
    }

    /// The model point at pixel position `px` (the inverse of [`View::to_pixel`]).
    pub fn to_model(&self, px: Point) -> Point {
        let k = self.pixels_per_unit;
        Point::new(
            (px.x - 0.5 * f64::from(self.width)) / k + self.center.x,
            (px.y - 0.5 * f64::from(self.height)) / k + self.center.y,
        )
    }

    /// Model units per pixel.
    pub fn units_per_pixel(&self) -> f64 {
        1.0 / self.pixels_per_unit
    }

    /// The model rectangle the image shows.
    pub fn visible(&self) -> Rect {
        Rect::from_points(
            self.to_model(Point::ORIGIN),
            self.to_model(Point::new(f64::from(self.width), f64::from(self.height))),
        )
    }

    /// The view moved so the scene follows a drag of `delta_px` pixels.
    pub fn panned(&self, delta_px: Vec2) -> View {
        View {
            center: self.center - delta_px / self.pixels_per_unit,
            ..*self
        }
    }

    /// The view zoomed by `factor` (> 1: closer) about pixel `anchor_px`, whose model point stays
    /// where it is on the image.
    pub fn zoomed(&self, factor: f64, anchor_px: Point) -> View {
        let anchor = self.to_model(anchor_px);
        let k = self.pixels_per_unit * factor;
        // centre' = anchor − (anchor_px − image centre)/k'.
        let offset =
            anchor_px - Point::new(0.5 * f64::from(self.width), 0.5 * f64::from(self.height));
        View {
            center: anchor - offset / k,
            pixels_per_unit: k,
            ..*self
        }
    }

    /// Checks what [`render`](super::render) needs: a non-empty image within [`MAX_IMAGE_SIDE`]
    /// and [`MAX_IMAGE_PIXELS`], a finite centre and a positive finite scale.
    pub fn validate(&self) -> Result<(), RenderError> {
        let (width, height) = (self.width, self.height);
        if width == 0 || height == 0 {
            return Err(RenderError::EmptyImage { width, height });
        }
        if width > MAX_IMAGE_SIDE
            || height > MAX_IMAGE_SIDE
            || u64::from(width) * u64::from(height) > MAX_IMAGE_PIXELS
        {
            return Err(RenderError::TooLarge { width, height });
        }
        let k = self.pixels_per_unit;
        if !(self.center.x.is_finite() && self.center.y.is_finite() && k.is_finite() && k > 0.0) {
            return Err(RenderError::BadView {
                center: self.center,
                pixels_per_unit: k,
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_centres_and_fills_the_limiting_axis() {
        let v = View::fit(Rect::new(10.0, 20.0, 110.0, 70.0), 300, 200, 50.0);
        // Width limits: (300 − 100)/100 = 2 px per unit; height would allow (200 − 100)/50 = 2.
        assert_eq!(v.pixels_per_unit, 2.0);
        assert_eq!(v.center, Point::new(60.0, 45.0));
        assert_eq!(v.to_pixel(Point::new(10.0, 20.0)), Point::new(50.0, 50.0));
        assert_eq!(
            v.to_pixel(Point::new(110.0, 70.0)),
            Point::new(250.0, 150.0)
        );
    }

    #[test]
    fn fit_of_degenerate_bounds() {
        // A vertical line: fitted along y.
        let v = View::fit(Rect::new(5.0, 0.0, 5.0, 10.0), 100, 120, 10.0);
        assert_eq!(v.pixels_per_unit, 10.0);
        // A point, and nothing finite.
        let v = View::fit(Rect::new(5.0, 5.0, 5.0, 5.0), 100, 120, 10.0);
        assert_eq!(v.pixels_per_unit, FALLBACK_PIXELS_PER_UNIT);
        let v = View::fit(Rect::new(f64::NAN, 0.0, 1.0, 1.0), 100, 120, 10.0);
        assert!(v.validate().is_ok());
        // Margins wider than the image.
        let v = View::fit(Rect::new(0.0, 0.0, 1.0, 1.0), 10, 10, 100.0);
        assert_eq!(v.pixels_per_unit, MIN_FIT_EXTENT_PX);
    }

    #[test]
    fn zoom_keeps_the_anchor_and_pan_moves_by_the_drag() {
        let v = View::fit(Rect::new(0.0, 0.0, 40.0, 30.0), 400, 300, 0.0);
        let anchor = Point::new(123.0, 45.0);
        let z = v.zoomed(2.5, anchor);
        assert!((z.to_pixel(v.to_model(anchor)) - anchor).hypot() < 1e-9);
        let p = Point::new(7.0, 8.0);
        let d = Vec2::new(13.0, -4.0);
        assert!((v.panned(d).to_pixel(p) - (v.to_pixel(p) + d)).hypot() < 1e-9);
    }

    #[test]
    fn validate_rejects_empty_oversized_and_non_finite_views() {
        let ok = View::fit(Rect::new(0.0, 0.0, 1.0, 1.0), 10, 10, 0.0);
        assert!(ok.validate().is_ok());
        let e = View { width: 0, ..ok }.validate();
        assert!(matches!(e, Err(RenderError::EmptyImage { .. })));
        let e = View {
            width: MAX_IMAGE_SIDE + 1,
            ..ok
        }
        .validate();
        assert!(matches!(e, Err(RenderError::TooLarge { .. })));
        let e = View {
            width: MAX_IMAGE_SIDE,
            height: MAX_IMAGE_SIDE,
            ..ok
        }
        .validate();
        assert!(matches!(e, Err(RenderError::TooLarge { .. })));
        for k in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e = View {
                pixels_per_unit: k,
                ..ok
            }
            .validate();
            assert!(matches!(e, Err(RenderError::BadView { .. })), "{k}");
        }
        let e = View {
            center: Point::new(f64::NAN, 0.0),
            ..ok
        }
        .validate();
        assert!(matches!(e, Err(RenderError::BadView { .. })));
    }
}
