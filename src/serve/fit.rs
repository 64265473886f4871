//! What the endpoints compute, on a worker: the request body read strictly
//! ([`read_request`]: the first bad stroke refuses it, with the command line's message), the
//! fit, and its document or export. Plain functions of bytes and options, so that the stream
//! and the HTTP endpoints give the same answers.

use crate::export::{CurveFile, DxfOptions, ExportOptions, SvgOptions, dxf_drawing, svg_document};
use crate::pipeline::{FitOutput, PipelineOptions, fit_file};
use crate::render::RenderOptions;
use crate::stroke::{Stroke, StrokeFile};

use super::error::ApiError;
use super::options::ServeOptions;

/// The request limits a body is held to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RequestLimits {
    /// Most strokes.
    pub max_strokes: usize,
    /// Most samples per stroke.
    pub max_samples_per_stroke: usize,
}

impl RequestLimits {
    /// The limits of `options`.
    pub fn of(options: &ServeOptions) -> Self {
        RequestLimits {
            max_strokes: options.max_strokes,
            max_samples_per_stroke: options.max_samples_per_stroke,
        }
    }

    /// `413` when `file` holds too many strokes, or a stroke too many samples.
    pub fn check(&self, file: &StrokeFile) -> Result<(), ApiError> {
        if file.strokes.len() > self.max_strokes {
            return Err(ApiError::too_large(format!(
                "{} strokes, more than the {} a request may hold",
                file.strokes.len(),
                self.max_strokes
            )));
        }
        self.check_strokes(&file.strokes)
    }

    /// `413` when a stroke holds too many samples.
    pub fn check_strokes(&self, strokes: &[Stroke]) -> Result<(), ApiError> {
        for (i, s) in strokes.iter().enumerate() {
            if s.samples.len() > self.max_samples_per_stroke {
                return Err(ApiError::too_large(format!(
                    "stroke {i}: {} samples, more than the {} a stroke may hold",
                    s.samples.len(),
                    self.max_samples_per_stroke
                )));
            }
        }
        Ok(())
    }
}

/// Reads a `kansei-stroke` v1 body strictly, as [`StrokeFile::from_json`] does (syntax, format,
/// version, then every stroke: the first bad one refuses the body, `400` with the command
/// line's message naming stroke, sample and field), with the limits checked in between (`413`).
pub fn read_request(body: &[u8], limits: &RequestLimits) -> Result<StrokeFile, ApiError> {
    let text = std::str::from_utf8(body)
        .map_err(|e| ApiError::bad_request(format!("the body is not UTF-8 text: {e}")))?;
    let file = StrokeFile::read_json(text).map_err(|e| ApiError::bad_request(e.to_string()))?;
    limits.check(&file)?;
    file.validate()
        .map_err(|e| ApiError::bad_request(e.to_string()))?;
    Ok(file)
}

/// Fits a validated file.
pub fn fit(file: &StrokeFile, options: &PipelineOptions) -> Result<FitOutput, ApiError> {
    fit_file(file, options).map_err(|e| ApiError::bad_request(e.to_string()))
}

/// The `kansei-curve` document of a fit, as `kansei fit` writes it.
pub fn curve_json(output: &FitOutput, lcg: bool) -> String {
    CurveFile::from_output_with(output, &ExportOptions { lcg }).to_json()
}

/// The SVG export (as `kansei fit --svg` with `--svg-layers layers`).
pub fn svg(
    file: &StrokeFile,
    output: &FitOutput,
    accuracy: Option<f64>,
    layers: &[String],
) -> String {
    let options = SvgOptions {
        accuracy,
        ..SvgOptions::for_units(file.units)
    }
    .with_layer_names(layers);
    svg_document(output, Some(file), &options).svg
}

/// The DXF export (as `kansei fit --dxf`).
pub fn dxf(output: &FitOutput, accuracy: Option<f64>) -> Result<Vec<u8>, ApiError> {
    dxf_drawing(output, &DxfOptions { accuracy })
        .to_bytes()
        .map_err(|e| ApiError::internal(format!("the DXF could not be written: {e}")))
}

/// The PNG export, as `kansei fit --png` draws it ([`crate::render::quick_look_png`]).
pub fn png(
    file: &StrokeFile,
    output: &FitOutput,
    size: (u32, u32),
    options: &RenderOptions,
) -> Result<Vec<u8>, ApiError> {
    crate::render::quick_look_png(file, output, size, options)
        .map_err(|e| ApiError::bad_request(e.to_string()))
}

/// The compact `kansei-curve` document of one stroke of `units`, as `/v1/fit` fits a file
/// holding that stroke alone (the stream's previews and final fits): the limits checked
/// (`413`), the stroke validated (`400`, the command line's message for stroke 0), fitted.
pub fn stroke_document(
    samples: Vec<crate::stroke::Sample>,
    units: crate::stroke::Units,
    options: &PipelineOptions,
    lcg: bool,
    limits: &RequestLimits,
) -> Result<String, ApiError> {
    let file = StrokeFile::new(units, vec![Stroke::new(samples)]);
    limits.check(&file)?;
    file.validate()
        .map_err(|e| ApiError::bad_request(e.to_string()))?;
    let output = fit(&file, options)?;
    let doc = CurveFile::from_output_with(&output, &ExportOptions { lcg });
    serde_json::to_string(&doc)
        .map_err(|e| ApiError::internal(format!("the document could not be written: {e}")))
}
