//! Locating the pen fields in a report descriptor: [`PenLayout::from_descriptor`].

use hidreport::{Field, FieldAttributes, Report, ReportDescriptor, VariableField};

use super::error::HidError;
use super::field::{FieldSpec, MAX_FIELD_BITS, PhysicalUnit};
use super::items::check_items;

/// HID usage page Generic Desktop (X, Y).
const PAGE_GENERIC_DESKTOP: u16 = 0x01;
/// HID usage page Digitizers (Tip Switch, In Range, Tip Pressure, tilts, ...).
const PAGE_DIGITIZER: u16 = 0x0D;
/// Wacom's vendor page: mirrors the Digitizers page usage for usage, and puts X and Y at
/// 0x130 and 0x131 (Linux `hid-wacom`: `WACOM_HID_UP_WACOMDIGITIZER`).
const PAGE_WACOM_DIGITIZER: u16 = 0xFF0D;
/// Generic Desktop X and Y.
const USAGE_GD_X: u16 = 0x30;
const USAGE_GD_Y: u16 = 0x31;
/// Wacom vendor page X and Y (`WACOM_HID_WD_X`, `WACOM_HID_WD_Y`).
const USAGE_WACOM_X: u16 = 0x130;
const USAGE_WACOM_Y: u16 = 0x131;
/// Digitizers page usages (HID Usage Tables, chapter 16).
const USAGE_FINGER: u16 = 0x22;
const USAGE_TIP_PRESSURE: u16 = 0x30;
const USAGE_IN_RANGE: u16 = 0x32;
const USAGE_INVERT: u16 = 0x3C;
const USAGE_X_TILT: u16 = 0x3D;
const USAGE_Y_TILT: u16 = 0x3E;
const USAGE_TIP_SWITCH: u16 = 0x42;
const USAGE_BARREL_SWITCH: u16 = 0x44;
const USAGE_ERASER: u16 = 0x45;
const USAGE_CONTACT_IDENTIFIER: u16 = 0x51;
const USAGE_SECONDARY_BARREL_SWITCH: u16 = 0x5A;

/// The pen fields of one input report. Absent fields are `None`; X and Y are always present.
#[derive(Clone, Debug, PartialEq)]
pub struct PenFields {
    /// The report ID (first byte of every report), or `None` for a device without report IDs.
    pub report_id: Option<u8>,
    /// The report's declared length in bytes, report ID included.
    pub report_len: usize,
    /// X, with a length unit.
    pub x: FieldSpec,
    /// Y, with a length unit.
    pub y: FieldSpec,
    /// Millimetres per physical unit of X (after the exponent).
    pub x_mm_per_unit: f64,
    /// Millimetres per physical unit of Y.
    pub y_mm_per_unit: f64,
    /// Tip Switch: the pen tip touches.
    pub tip: Option<FieldSpec>,
    /// In Range: the pen is in proximity.
    pub in_range: Option<FieldSpec>,
    /// Barrel Switch.
    pub barrel: Option<FieldSpec>,
    /// Secondary Barrel Switch.
    pub secondary_barrel: Option<FieldSpec>,
    /// Invert: the eraser end is towards the tablet.
    pub invert: Option<FieldSpec>,
    /// Eraser: the eraser end touches (the eraser's tip switch).
    pub eraser: Option<FieldSpec>,
    /// Tip Pressure.
    pub pressure: Option<FieldSpec>,
    /// X Tilt.
    pub tilt_x: Option<FieldSpec>,
    /// Y Tilt.
    pub tilt_y: Option<FieldSpec>,
}

/// Where the pen fields are in a device's input reports: built once from the report descriptor,
/// then used to decode every report ([`PenLayout::decode`](crate::capture::hid::PenLayout::decode)).
#[derive(Clone, Debug, PartialEq)]
pub struct PenLayout {
    /// One entry per pen input report (most pens have one).
    pub pens: Vec<PenFields>,
    /// Every input report ID the descriptor declares (pen or not); empty without report IDs.
    pub input_report_ids: Vec<u8>,
}

/// The role of a usage in a pen report.
#[derive(Clone, Copy, PartialEq)]
enum Role {
    X,
    Y,
    Tip,
    InRange,
    Barrel,
    SecondaryBarrel,
    Invert,
    Eraser,
    Pressure,
    TiltX,
    TiltY,
    ContactId,
}

/// The pen role of a usage, with Wacom's vendor page read as the Digitizers page.
fn role(page: u16, id: u16) -> Option<Role> {
    match (page, id) {
        (PAGE_GENERIC_DESKTOP, USAGE_GD_X) | (PAGE_WACOM_DIGITIZER, USAGE_WACOM_X) => Some(Role::X),
        (PAGE_GENERIC_DESKTOP, USAGE_GD_Y) | (PAGE_WACOM_DIGITIZER, USAGE_WACOM_Y) => Some(Role::Y),
        (PAGE_DIGITIZER | PAGE_WACOM_DIGITIZER, id) => match id {
            USAGE_TIP_SWITCH => Some(Role::Tip),
            USAGE_IN_RANGE => Some(Role::InRange),
            USAGE_BARREL_SWITCH => Some(Role::Barrel),
            USAGE_SECONDARY_BARREL_SWITCH => Some(Role::SecondaryBarrel),
            USAGE_INVERT => Some(Role::Invert),
            USAGE_ERASER => Some(Role::Eraser),
            USAGE_TIP_PRESSURE => Some(Role::Pressure),
            USAGE_X_TILT => Some(Role::TiltX),
            USAGE_Y_TILT => Some(Role::TiltY),
            USAGE_CONTACT_IDENTIFIER => Some(Role::ContactId),
            _ => None,
        },
        _ => None,
    }
}

fn is_digitizer_page(page: u16) -> bool {
    page == PAGE_DIGITIZER || page == PAGE_WACOM_DIGITIZER
}

/// The fields of one input report, by role (first occurrence wins).
#[derive(Default)]
struct Found {
    x: Option<FieldSpec>,
    y: Option<FieldSpec>,
    tip: Option<FieldSpec>,
    in_range: Option<FieldSpec>,
    barrel: Option<FieldSpec>,
    secondary_barrel: Option<FieldSpec>,
    invert: Option<FieldSpec>,
    eraser: Option<FieldSpec>,
    pressure: Option<FieldSpec>,
    tilt_x: Option<FieldSpec>,
    tilt_y: Option<FieldSpec>,
    touch: bool,
}

impl Found {
    fn slot(&mut self, role: Role) -> Option<&mut Option<FieldSpec>> {
        Some(match role {
            Role::X => &mut self.x,
            Role::Y => &mut self.y,
            Role::Tip => &mut self.tip,
            Role::InRange => &mut self.in_range,
            Role::Barrel => &mut self.barrel,
            Role::SecondaryBarrel => &mut self.secondary_barrel,
            Role::Invert => &mut self.invert,
            Role::Eraser => &mut self.eraser,
            Role::Pressure => &mut self.pressure,
            Role::TiltX => &mut self.tilt_x,
            Role::TiltY => &mut self.tilt_y,
            Role::ContactId => return None,
        })
    }
}

fn spec(v: &VariableField) -> FieldSpec {
    FieldSpec {
        bit_offset: v.bits.start,
        bit_size: v.bits.len(),
        logical_min: i64::from(i32::from(v.logical_minimum)),
        logical_max: i64::from(i32::from(v.logical_maximum)),
        physical_min: v.physical_minimum.map(|p| i64::from(i32::from(p))),
        physical_max: v.physical_maximum.map(|p| i64::from(i32::from(p))),
        unit: v.unit.map_or(0, u32::from),
        unit_exponent: v.unit_exponent.map_or(0, |e| i32::from(e.exponent())),
    }
}

impl PenLayout {
    /// Parses a report descriptor and locates the pen fields of every pen input report.
    ///
    /// A pen input report has absolute X and Y (Generic Desktop, or Wacom's 0xFF0D page at
    /// 0x130/0x131) and at least one of Tip Switch, In Range or Tip Pressure, and is not a touch
    /// contact (no Contact Identifier, not inside a Finger collection). X and Y must have a
    /// length unit (cm or inch) and a non-empty logical range, every field at most 32 bits.
    pub fn from_descriptor(descriptor: &[u8]) -> Result<Self, HidError> {
        let checked = check_items(descriptor)?;
        let rdesc = ReportDescriptor::try_from(checked.bytes.as_slice()).map_err(|e| match e {
            hidreport::ParserError::InvalidData { offset, message } => {
                HidError::DescriptorInvalid {
                    offset: checked.original_offset(offset),
                    message,
                }
            }
            other => HidError::DescriptorInvalid {
                offset: 0,
                message: other.to_string(),
            },
        })?;
        let mut pens = Vec::new();
        let mut input_report_ids = Vec::new();
        for report in rdesc.input_reports() {
            let report_id = report.report_id().as_ref().map(u8::from);
            input_report_ids.extend(report_id);
            let mut found = Found::default();
            for field in report.fields() {
                let Field::Variable(v) = field else {
                    continue;
                };
                let page = u16::from(v.usage.usage_page);
                let id = u16::from(v.usage.usage_id);
                let in_finger = v.collections.iter().any(|c| {
                    c.usages().iter().any(|u| {
                        is_digitizer_page(u16::from(u.usage_page))
                            && u16::from(u.usage_id) == USAGE_FINGER
                    })
                });
                let Some(role) = role(page, id) else {
                    continue;
                };
                if role == Role::ContactId || in_finger {
                    found.touch = true;
                    continue;
                }
                if matches!(role, Role::X | Role::Y) && v.is_relative() {
                    continue;
                }
                if let Some(slot) = found.slot(role)
                    && slot.is_none()
                {
                    *slot = Some(spec(v));
                }
            }
            let pen_usage =
                found.tip.is_some() || found.in_range.is_some() || found.pressure.is_some();
            if found.touch || !pen_usage {
                continue;
            }
            if let (Some(x), Some(y)) = (found.x.take(), found.y.take()) {
                pens.push(pen_fields(report_id, report.size_in_bytes(), x, y, found)?);
            }
        }
        if pens.is_empty() {
            return Err(HidError::NoPenReport);
        }
        Ok(PenLayout {
            pens,
            input_report_ids,
        })
    }

    /// Whether the device prefixes its reports with a report ID.
    pub fn uses_report_ids(&self) -> bool {
        !self.input_report_ids.is_empty()
    }
}

/// Checks the located fields and resolves their units.
fn pen_fields(
    report_id: Option<u8>,
    report_len: usize,
    x: FieldSpec,
    y: FieldSpec,
    found: Found,
) -> Result<PenFields, HidError> {
    let rid = report_id.unwrap_or(0);
    let bad = |field: &'static str, message: String| HidError::BadField {
        report_id: rid,
        field,
        message,
    };
    let named: [(&'static str, Option<&FieldSpec>); 11] = [
        ("X", Some(&x)),
        ("Y", Some(&y)),
        ("Tip Switch", found.tip.as_ref()),
        ("In Range", found.in_range.as_ref()),
        ("Barrel Switch", found.barrel.as_ref()),
        ("Secondary Barrel Switch", found.secondary_barrel.as_ref()),
        ("Invert", found.invert.as_ref()),
        ("Eraser", found.eraser.as_ref()),
        ("Tip Pressure", found.pressure.as_ref()),
        ("X Tilt", found.tilt_x.as_ref()),
        ("Y Tilt", found.tilt_y.as_ref()),
    ];
    for (name, f) in named {
        let Some(f) = f else { continue };
        if f.bit_size == 0 || f.bit_size > MAX_FIELD_BITS {
            return Err(bad(
                name,
                format!(
                    "{} bits; at most {MAX_FIELD_BITS} are supported",
                    f.bit_size
                ),
            ));
        }
        // Switches may declare 0..0 (some descriptors leave Logical Maximum unset for bits);
        // value fields need a range to scale.
        let is_value = matches!(name, "X" | "Y" | "Tip Pressure" | "X Tilt" | "Y Tilt");
        if is_value && f.logical_max <= f.logical_min {
            return Err(bad(
                name,
                format!("empty logical range {}..{}", f.logical_min, f.logical_max),
            ));
        }
        if is_value && f.unit_exponent.unsigned_abs() > MAX_UNIT_EXPONENT {
            return Err(bad(
                name,
                format!(
                    "unit exponent {} out of -{MAX_UNIT_EXPONENT}..={MAX_UNIT_EXPONENT}",
                    f.unit_exponent
                ),
            ));
        }
    }
    let mm_per_unit = |name: &'static str, f: &FieldSpec| match f.physical_unit() {
        PhysicalUnit::Length { mm_per_unit } => Ok(mm_per_unit),
        _ => Err(bad(
            name,
            format!(
                "unit {:#x} is not a length (cm or inch): no millimetres",
                f.unit
            ),
        )),
    };
    let x_mm_per_unit = mm_per_unit("X", &x)?;
    let y_mm_per_unit = mm_per_unit("Y", &y)?;
    Ok(PenFields {
        report_id,
        report_len,
        x,
        y,
        x_mm_per_unit,
        y_mm_per_unit,
        tip: found.tip,
        in_range: found.in_range,
        barrel: found.barrel,
        secondary_barrel: found.secondary_barrel,
        invert: found.invert,
        eraser: found.eraser,
        pressure: found.pressure,
        tilt_x: found.tilt_x,
        tilt_y: found.tilt_y,
    })
}

/// The largest |Unit Exponent| accepted on a value field: the item is a 4-bit nibble (-8..7)
/// on real devices; a larger one would scale into non-finite territory.
const MAX_UNIT_EXPONENT: u32 = 8;
