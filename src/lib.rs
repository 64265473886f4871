//! # kansei: pen strokes to log-aesthetic curves
//!
//! The pipeline (Miura et al., "Input of log-aesthetic curves with a pen tablet"):
//! 1. [`stroke`]: samples (x, y, time, pressure, tilt), read from `kansei-stroke` JSON or, through
//!    [`capture`], from HID recordings (decoded from the device's report descriptor), evemu and
//!    InkML.
//! 2. [`prepare`]: duplicates merged, the pen's dwell and hooks dropped, the stroke cut at corners;
//!    [`closure`]: a stroke that comes back to its start is fitted as one closed curve (its
//!    overshoot or second round folded onto the loop, its seam as smooth as its joints).
//! 3. [`bspline`]: least-squares cubic B-spline, segments added until every sample is within the
//!    tolerance of the curve, then faired.
//! 4. [`split`]: Bézier pieces split at inflections and curvature extrema into spans of
//!    monotonic curvature.
//! 5. [`chain`]: one log-aesthetic segment ([`lac`]) per span with the best α, refined
//!    (Levenberg–Marquardt) into a G1 chain within the tolerance, then by default refitted with
//!    one curvature per joint (G2; C3 on request, or the G1 chain kept).
//! 6. [`export`]: `kansei-curve` JSON (with JSON Schemas), SVG and DXF within a stated error
//!    of the exact curves; [`render`]: raster images (PNG, the app's canvas) drawn with tiny-skia.
//!
//! [`pipeline`] composes the stages; [`io`] reads strokes from every supported file and writes
//! outputs atomically, never creating directories or replacing a file by accident; [`cli`] is
//! the command line; `app` (feature `app`) is the sketch app, `kansei app`: draw, watch the
//! chain appear, study its curvature; `serve` (feature `serve`) is the fitting service,
//! `kansei serve`: an HTTP API and a pen page for any tablet in a browser.
//!
//! ```
//! use kansei::pipeline::{PipelineOptions, fit_file};
//! use kansei::stroke::{Stroke, StrokeFile, Units};
//! use kansei::geom::Point;
//!
//! // A quarter circle of radius 50 mm, sampled every degree.
//! let arc = Stroke::from_points((0..=90).map(|d| {
//!     let a = (d as f64).to_radians();
//!     Point::new(50.0 * a.cos(), 50.0 * a.sin())
//! }));
//! let file = StrokeFile::new(Units::Mm, vec![arc]);
//! let out = fit_file(&file, &PipelineOptions::default()).unwrap();
//! assert_eq!(out.curves.len(), 1);
//! assert!(out.curves[0].bspline.max_deviation <= 0.1);
//! ```

#[cfg(feature = "app")]
pub mod app;
pub mod bspline;
pub mod capture;
pub mod chain;
pub mod cli;
pub mod closure;
pub mod export;
pub mod geom;
pub mod io;
pub mod lac;
pub mod pipeline;
pub mod prepare;
pub mod render;
#[cfg(feature = "serve")]
pub mod serve;
pub mod split;
pub mod stroke;
