//! A hid-recorder recording through the HID decoder and the stroke builder into a
//! `kansei-stroke` file: [`recording_to_strokes`].

use serde_json::json;
use thiserror::Error;

use crate::capture::hid::{HidError, PenFields, PenLayout};
use crate::capture::recorder::{LineWarning, RecorderError, Recording};
use crate::capture::stroke_builder::{StrokeBuilder, Tool};
use crate::stroke::{StrokeError, StrokeFile, Units};

/// Report decoding errors kept with their line numbers; later ones are only counted.
pub const MAX_KEPT_DECODE_ERRORS: usize = 100;

/// Why a recording could not be replayed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum CaptureError {
    /// The recording's text does not parse.
    #[error(transparent)]
    Recorder(#[from] RecorderError),
    /// The report descriptor has no usable pen report.
    #[error("report descriptor: {0}")]
    Descriptor(#[from] HidError),
    /// The strokes built fail validation (a bug, or values beyond the stroke format's limits).
    #[error("replayed strokes: {0}")]
    Stroke(#[from] StrokeError),
}

/// What a replay saw and skipped.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReplayStats {
    /// Reports in the recording.
    pub reports: usize,
    /// Reports decoded as pen reports.
    pub pen_reports: usize,
    /// Declared input reports that carry no pen data (battery, buttons, ...).
    pub other_reports: usize,
    /// Reports that did not decode (unknown report ID, truncated, ...): skipped.
    pub decode_errors: usize,
    /// The first [`MAX_KEPT_DECODE_ERRORS`] decoding errors with the recording's line number.
    pub first_decode_errors: Vec<(usize, HidError)>,
    /// Lines the recorder parser skipped.
    pub recorder_warnings: usize,
    /// The first of them ([`crate::capture::recorder::MAX_KEPT_WARNINGS`]), with line numbers.
    pub first_recorder_warnings: Vec<LineWarning>,
    /// The tool of each stroke, parallel to the file's strokes.
    pub tools: Vec<Tool>,
    /// Contact runs dropped for having fewer than two distinct positions.
    pub short_runs_dropped: usize,
    /// Samples dropped because time went backwards.
    pub backwards_samples_dropped: usize,
}

impl ReplayStats {
    /// Every skipped line or report and every dropped run or sample.
    pub fn warnings(&self) -> usize {
        self.decode_errors
            + self.recorder_warnings
            + self.short_runs_dropped
            + self.backwards_samples_dropped
    }
}

/// Decodes every report of `recording` and cuts the pen reports into strokes.
///
/// The file is in [`Units::Mm`], positions from the tablet's origin as the device reports them
/// (x right, y down), times in seconds from the recording's start. Its `device` object holds
/// the name, USB IDs, the active area in mm, pressure levels, tilt support, the y-axis direction
/// and the indices of eraser strokes (`eraser_strokes`); [`ReplayStats::tools`] gives the same
/// per stroke. Reports that do not decode are skipped and counted; a descriptor without a pen is
/// an error.
pub fn recording_to_strokes(
    recording: &Recording,
) -> Result<(StrokeFile, ReplayStats), CaptureError> {
    let layout = PenLayout::from_descriptor(&recording.descriptor)?;
    let mut stats = ReplayStats {
        reports: recording.reports.len(),
        recorder_warnings: recording.warning_count,
        first_recorder_warnings: recording.warnings.clone(),
        ..ReplayStats::default()
    };
    let mut builder = StrokeBuilder::new();
    for (i, (t, bytes)) in recording.reports.iter().enumerate() {
        match layout.decode(bytes) {
            Ok(Some(report)) => {
                stats.pen_reports += 1;
                builder.push(*t, &report);
            }
            Ok(None) => stats.other_reports += 1,
            Err(e) => {
                stats.decode_errors += 1;
                if stats.first_decode_errors.len() < MAX_KEPT_DECODE_ERRORS {
                    let line = recording.report_lines.get(i).copied().unwrap_or(0);
                    stats.first_decode_errors.push((line, e));
                }
            }
        }
    }
    let (built, builder_stats) = builder.finish();
    stats.short_runs_dropped = builder_stats.short_runs_dropped;
    stats.backwards_samples_dropped = builder_stats.backwards_samples_dropped;
    stats.tools = built.iter().map(|b| b.tool).collect();
    let eraser_strokes: Vec<usize> = (stats.tools.iter().enumerate())
        .filter(|(_, tool)| **tool == Tool::Eraser)
        .map(|(i, _)| i)
        .collect();
    let mut file = StrokeFile::new(Units::Mm, built.into_iter().map(|b| b.stroke).collect());
    file.source = Some(match &recording.name {
        Some(name) => format!("hid-recorder: {name}"),
        None => "hid-recorder".to_owned(),
    });
    let mut device = layout.pens.first().map(device_info).unwrap_or_default();
    device.insert("name".into(), json!(recording.name));
    if let Some((bus, vendor, product)) = recording.id {
        device.insert("bus".into(), json!(bus));
        device.insert("vendor_id".into(), json!(format!("{vendor:04x}")));
        device.insert("product_id".into(), json!(format!("{product:04x}")));
    }
    device.insert("eraser_strokes".into(), json!(eraser_strokes));
    file.device = Some(serde_json::Value::Object(device));
    file.validate()?;
    Ok((file, stats))
}

/// Parses hid-recorder text and replays it ([`Recording::parse`], [`recording_to_strokes`]).
pub fn replay_text(text: &str) -> Result<(StrokeFile, ReplayStats), CaptureError> {
    recording_to_strokes(&Recording::parse(text)?)
}

/// The device description of a pen report's fields.
fn device_info(pen: &PenFields) -> serde_json::Map<String, serde_json::Value> {
    let extent = |f: &crate::capture::hid::FieldSpec, mm: f64| {
        (f.to_physical(f.logical_max) - f.to_physical(f.logical_min)) * mm
    };
    let mut m = serde_json::Map::new();
    m.insert("interface".into(), json!("hid"));
    m.insert("width_mm".into(), json!(extent(&pen.x, pen.x_mm_per_unit)));
    m.insert("height_mm".into(), json!(extent(&pen.y, pen.y_mm_per_unit)));
    let levels = pen
        .pressure
        .as_ref()
        .map(|p| p.logical_max - p.logical_min + 1);
    m.insert("pressure_levels".into(), json!(levels));
    m.insert(
        "tilt".into(),
        json!(pen.tilt_x.is_some() || pen.tilt_y.is_some()),
    );
    m.insert(
        "eraser".into(),
        json!(pen.invert.is_some() || pen.eraser.is_some()),
    );
    m.insert("y_axis".into(), json!("down"));
    m
}
