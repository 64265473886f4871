//! Decoding one input report with a [`PenLayout`]: [`PenLayout::decode`] into a [`PenReport`].

use super::error::HidError;
use super::field::{FieldSpec, PhysicalUnit};
use super::layout::{PenFields, PenLayout};

/// One decoded pen report: the pen's state, position in millimetres from the tablet's origin
/// (x to the right, y down, as the device reports), pressure 0..1 and tilt in degrees, with the
/// raw logical values beside them.
#[derive(Clone, Debug, PartialEq)]
pub struct PenReport {
    /// Report ID (0 when the device uses none).
    pub report_id: u8,
    /// In Range: the pen is in proximity. `true` when the report has no In Range field (a pen
    /// report then only comes while the pen is near).
    pub in_range: bool,
    /// Tip Switch: the tip touches.
    pub tip: bool,
    /// Barrel Switch and Secondary Barrel Switch.
    pub barrel: [bool; 2],
    /// Invert: the eraser end faces the tablet.
    pub invert: bool,
    /// Eraser: the eraser end touches (on many pens the eraser's contact, with no Tip Switch).
    pub eraser: bool,
    /// Whether the pen touches the surface: Tip Switch or Eraser; on a descriptor with neither
    /// switch, Tip Pressure above its minimum.
    pub contact: bool,
    /// X, millimetres.
    pub x_mm: f64,
    /// Y, millimetres.
    pub y_mm: f64,
    /// Tip Pressure, 0..1 over the logical range (a value outside it is refused), when the
    /// report has it.
    pub pressure: Option<f64>,
    /// X Tilt, degrees, when the report has it.
    pub tilt_x_deg: Option<f64>,
    /// Y Tilt, degrees, when the report has it.
    pub tilt_y_deg: Option<f64>,
    /// X, logical value.
    pub raw_x: i64,
    /// Y, logical value.
    pub raw_y: i64,
    /// Tip Pressure, logical value.
    pub raw_pressure: Option<i64>,
    /// X Tilt, logical value.
    pub raw_tilt_x: Option<i64>,
    /// Y Tilt, logical value.
    pub raw_tilt_y: Option<i64>,
}

impl PenReport {
    /// Whether the eraser end is in use: Invert (eraser end near) or Eraser (eraser touching).
    pub fn is_eraser(&self) -> bool {
        self.invert || self.eraser
    }
}

impl PenLayout {
    /// The pen fields for a report: by its first byte when the device uses report IDs.
    /// `Ok(None)` for a declared input report that is not a pen report (e.g. battery).
    fn fields_for(&self, report: &[u8]) -> Result<Option<&PenFields>, HidError> {
        let Some(&first) = report.first() else {
            return Err(HidError::EmptyReport);
        };
        if !self.uses_report_ids() {
            return Ok(self.pens.first());
        }
        if !self.input_report_ids.contains(&first) {
            return Err(HidError::UnknownReportId { report_id: first });
        }
        Ok(self.pens.iter().find(|p| p.report_id == Some(first)))
    }

    /// Decodes one input report (report ID byte first, when the device uses IDs).
    ///
    /// `Ok(None)` for an input report the descriptor declares but that carries no pen data;
    /// errors for an empty report, an undeclared report ID, a report too short for a pen
    /// field (naming the field and the missing byte), or a pen field whose logical value lies
    /// outside its declared Logical Minimum..=Maximum ([`HidError::OutOfRange`], naming the
    /// field and the value; a switch declaring the empty range 0..0 is not checked). Bytes past
    /// the last pen field are not required. Pure: a function of the layout and the bytes.
    pub fn decode(&self, report: &[u8]) -> Result<Option<PenReport>, HidError> {
        let Some(pen) = self.fields_for(report)? else {
            return Ok(None);
        };
        let report_id = pen.report_id.unwrap_or(0);
        let read = |name: &'static str, f: &FieldSpec| {
            let value = f.extract(report).ok_or(HidError::ReportTruncated {
                report_id,
                field: name,
                needed_byte: f.last_byte(),
                len: report.len(),
            })?;
            // Switches may declare an empty range (0..0, see `PenLayout::from_descriptor`):
            // any value is then on or off. Every other field must keep to its range.
            let checked = f.logical_max > f.logical_min;
            if checked && !(f.logical_min..=f.logical_max).contains(&value) {
                return Err(HidError::OutOfRange {
                    report_id,
                    field: name,
                    byte: f.bit_offset / 8,
                    value,
                    min: f.logical_min,
                    max: f.logical_max,
                });
            }
            Ok(value)
        };
        let opt = |name: &'static str, f: &Option<FieldSpec>| {
            f.as_ref().map(|f| read(name, f)).transpose()
        };
        let switch = |name: &'static str, f: &Option<FieldSpec>| {
            Ok::<bool, HidError>(opt(name, f)?.is_some_and(|v| v != 0))
        };

        let raw_x = read("X", &pen.x)?;
        let raw_y = read("Y", &pen.y)?;
        let tip = switch("Tip Switch", &pen.tip)?;
        let in_range = match opt("In Range", &pen.in_range)? {
            Some(v) => v != 0,
            None => true,
        };
        let barrel = [
            switch("Barrel Switch", &pen.barrel)?,
            switch("Secondary Barrel Switch", &pen.secondary_barrel)?,
        ];
        let invert = switch("Invert", &pen.invert)?;
        let eraser = switch("Eraser", &pen.eraser)?;
        let raw_pressure = opt("Tip Pressure", &pen.pressure)?;
        let raw_tilt_x = opt("X Tilt", &pen.tilt_x)?;
        let raw_tilt_y = opt("Y Tilt", &pen.tilt_y)?;

        let pressure = pen
            .pressure
            .as_ref()
            .zip(raw_pressure)
            .map(|(f, v)| f.normalised(v));
        let contact = if pen.tip.is_some() || pen.eraser.is_some() {
            tip || eraser
        } else {
            match (&pen.pressure, raw_pressure) {
                (Some(f), Some(v)) => v > f.logical_min,
                _ => false,
            }
        };
        let finite = |name: &'static str, f: &FieldSpec, v: f64| {
            if v.is_finite() {
                Ok(v)
            } else {
                Err(HidError::BadValue {
                    report_id,
                    field: name,
                    byte: f.bit_offset / 8,
                    message: format!("converts to {v}"),
                })
            }
        };
        let x_mm = finite("X", &pen.x, pen.x.to_physical(raw_x) * pen.x_mm_per_unit)?;
        let y_mm = finite("Y", &pen.y, pen.y.to_physical(raw_y) * pen.y_mm_per_unit)?;
        let tilt = |name: &'static str, f: &Option<FieldSpec>, raw: Option<i64>| match (f, raw) {
            (Some(f), Some(v)) => finite(name, f, f.to_physical(v) * deg_per_unit(f)).map(Some),
            _ => Ok(None),
        };
        Ok(Some(PenReport {
            report_id,
            in_range,
            tip,
            barrel,
            invert,
            eraser,
            contact,
            x_mm,
            y_mm,
            pressure,
            tilt_x_deg: tilt("X Tilt", &pen.tilt_x, raw_tilt_x)?,
            tilt_y_deg: tilt("Y Tilt", &pen.tilt_y, raw_tilt_y)?,
            raw_x,
            raw_y,
            raw_pressure,
            raw_tilt_x,
            raw_tilt_y,
        }))
    }
}

/// Degrees per physical unit of a tilt: from its unit, or 1 when it declares no angle unit (the
/// logical value is then taken as degrees, as the Windows pen guidelines prescribe for tilt).
fn deg_per_unit(f: &FieldSpec) -> f64 {
    match f.physical_unit() {
        PhysicalUnit::Angle { deg_per_unit } => deg_per_unit,
        _ => 1.0,
    }
}
