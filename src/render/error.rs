//! Why a render was refused.

use crate::geom::Point;

/// Largest image side accepted, pixels: 16384 is the largest texture side common GPUs (and so
/// egui) take, and far beyond any screen or print preview.
pub const MAX_IMAGE_SIDE: u32 = 16_384;

/// Largest image accepted, pixels: 64 Mpx is 256 MB of RGBA, the most a render should ever
/// allocate (a 16384 × 4096 banner; not 16384²).
pub const MAX_IMAGE_PIXELS: u64 = 1 << 26;

/// A render that cannot be drawn.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum RenderError {
    /// Width or height is zero.
    #[error("the image must be at least 1×1 pixels, got {width}×{height}")]
    EmptyImage {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
    },
    /// A side beyond [`MAX_IMAGE_SIDE`] or an area beyond [`MAX_IMAGE_PIXELS`].
    #[error(
        "the image {width}×{height} is too large (at most {MAX_IMAGE_SIDE} pixels a side and {MAX_IMAGE_PIXELS} pixels)"
    )]
    TooLarge {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
    },
    /// The view's centre is not finite or its scale is not a positive finite number.
    #[error(
        "the view must have a finite centre and a positive finite scale, got centre ({}, {}) at {pixels_per_unit} pixels per unit",
        center.x,
        center.y
    )]
    BadView {
        /// The view's centre.
        center: Point,
        /// The view's scale.
        pixels_per_unit: f64,
    },
    /// A size in [`RenderOptions`](super::RenderOptions) is not a finite non-negative number (or
    /// the comb scale is not finite).
    #[error("render option {name} must be a finite non-negative number, got {value}")]
    BadOption {
        /// The field.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// The pixel buffer could not be allocated.
    #[error("could not allocate a {width}×{height} image")]
    Allocation {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
    },
    /// tiny-skia's PNG encoder failed.
    #[error("PNG encoding failed: {0}")]
    Png(String),
}
