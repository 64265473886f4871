//! What the endpoints compute, on a worker: the request body read strictly
//! ([`read_request`]: the first bad stroke refuses it, with the command line's message), the
//! fit, and its document or export. Plain functions of bytes and options, so that the stream
//! and the HTTP endpoints give the same answers.

use crate::export::{ExportOptions, Format, FormatError, FormatOptions, JsonLayout};
use crate::pipeline::{FitOutput, PipelineOptions, fit_file};
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

/// `output`, the fit of `file`, in `format` ([`Format::export`], as `kansei fit` writes it
/// with the same options): a DXF or JSON that cannot be written is a `500`, a PNG that cannot be
/// drawn (a size beyond the render's limits) a `400`.
pub fn export(
    format: Format,
    file: &StrokeFile,
    output: &FitOutput,
    options: &FormatOptions,
) -> Result<Vec<u8>, ApiError> {
    match format.export(file, output, options) {
        Ok(exported) => Ok(exported.bytes),
        Err(e @ FormatError::Dxf(_)) => Err(ApiError::internal(format!(
            "the DXF could not be written: {e}"
        ))),
        Err(FormatError::Json(e)) => Err(ApiError::internal(format!(
            "the document could not be written: {e}"
        ))),
        Err(e @ (FormatError::Render(_) | FormatError::EmptyDrawing)) => {
            Err(ApiError::bad_request(e.to_string()))
        }
    }
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
    let options = FormatOptions {
        json: ExportOptions { lcg },
        json_layout: JsonLayout::Compact,
        ..FormatOptions::default()
    };
    let bytes = export(Format::Json, &file, &output, &options)?;
    String::from_utf8(bytes)
        .map_err(|e| ApiError::internal(format!("the document could not be written: {e}")))
}
