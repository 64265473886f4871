//! Where timed pen reports come from: the [`PenSource`] trait, shared by live devices
//! (`live_hid`, `live_evdev`, feature `live`) and by [`RecordingSource`], which replays a
//! hid-recorder [`Recording`]. Live capture and replay therefore go through the same decoding
//! ([`PenLayout::decode`]) and the same stroke cutting ([`crate::capture::session`]).
//!
//! Also here: the permission diagnosis for device nodes ([`SourceError::Permission`]) and the
//! udev rules that grant access ([`UDEV_RULE_HIDRAW`], [`UDEV_RULE_INPUT`]).

use std::path::PathBuf;

use serde_json::json;
use thiserror::Error;

use crate::capture::hid::{HidError, PenFields, PenLayout, PenReport};
use crate::capture::recorder::Recording;
use crate::stroke::Units;

/// A udev rule giving the logged-in user access to a HID tablet's hidraw node (the vendor ID
/// shown is Wacom's, 056a; replace it with the tablet's, as `kansei devices` prints it).
pub const UDEV_RULE_HIDRAW: &str =
    r#"SUBSYSTEM=="hidraw", ATTRS{idVendor}=="056a", MODE="0660", TAG+="uaccess""#;
/// A udev rule giving the logged-in user access to every tablet's evdev node.
pub const UDEV_RULE_INPUT: &str =
    r#"SUBSYSTEM=="input", ENV{ID_INPUT_TABLET}=="1", TAG+="uaccess""#;

/// How to install the rules, printed after a permission error.
pub fn udev_help(vendor: Option<u16>) -> String {
    let hidraw = match vendor {
        Some(v) => UDEV_RULE_HIDRAW.replace("056a", &format!("{v:04x}")),
        None => UDEV_RULE_HIDRAW.to_owned(),
    };
    format!(
        "to grant access, put these lines in /etc/udev/rules.d/70-kansei-tablet.rules:\n  \
         {hidraw}\n  {UDEV_RULE_INPUT}\nthen run `sudo udevadm control --reload && sudo udevadm \
         trigger` and re-plug the tablet (or run kansei as a member of the `input` group)"
    )
}

/// Why a source could not be opened or read.
#[derive(Debug, Error)]
pub enum SourceError {
    /// The device node exists but this user may not open it.
    #[error("cannot open {}: {message} (errno {errno})\n{}", node.display(), udev_help(*vendor))]
    Permission {
        /// The device node.
        node: PathBuf,
        /// The OS error number (EACCES = 13, EPERM = 1).
        errno: i32,
        /// The OS error text.
        message: String,
        /// The device's USB vendor ID, when known (put into the udev rule).
        vendor: Option<u16>,
    },
    /// The device node could not be opened for another reason.
    #[error("cannot open {}: {message}", node.display())]
    Open {
        /// The device node.
        node: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// Reading failed: the device was unplugged, or the recording source was told to fail.
    #[error("reading {}: {message}", node.display())]
    Read {
        /// The device node (or recording).
        node: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// The device's report descriptor declares no usable pen.
    #[error("{}: report descriptor: {source}", node.display())]
    Descriptor {
        /// The device node (or recording).
        node: PathBuf,
        /// The cause.
        source: HidError,
    },
    /// No tablet matched.
    #[error("{0}")]
    NotFound(String),
    /// A replay speed that is not a positive number.
    #[error("replay speed must be a positive number, got {0}")]
    Speed(f64),
}

impl SourceError {
    /// Classifies an `open` failure of `node`: permission errors become
    /// [`SourceError::Permission`] with the errno and the udev rule.
    pub fn from_open(node: impl Into<PathBuf>, e: &std::io::Error, vendor: Option<u16>) -> Self {
        let node = node.into();
        if e.kind() == std::io::ErrorKind::PermissionDenied {
            SourceError::Permission {
                node,
                errno: e.raw_os_error().unwrap_or(0),
                message: e.to_string(),
                vendor,
            }
        } else {
            SourceError::Open {
                node,
                message: e.to_string(),
            }
        }
    }
}

/// How a source talks to the tablet.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interface {
    /// HID reports from `/dev/hidraw*`, decoded with the report descriptor.
    Hid,
    /// Linux input events from `/dev/input/event*`.
    Evdev,
    /// A hid-recorder recording replayed.
    Recording,
}

impl Interface {
    /// The name used in the `device` object of the stroke file.
    pub const fn name(self) -> &'static str {
        match self {
            Interface::Hid => "hid",
            Interface::Evdev => "evdev",
            Interface::Recording => "hid-recording",
        }
    }
}

/// What is known about a tablet: identity, active area, pressure and tilt.
#[derive(Clone, Debug, PartialEq)]
pub struct DeviceInfo {
    /// How it is read.
    pub interface: Interface,
    /// The device node (`/dev/hidraw3`, `/dev/input/event7`) or recording path.
    pub node: Option<String>,
    /// The device name.
    pub name: Option<String>,
    /// Bus type (3 = USB, 5 = Bluetooth), when known.
    pub bus: Option<u16>,
    /// USB vendor ID.
    pub vendor_id: Option<u16>,
    /// USB product ID.
    pub product_id: Option<u16>,
    /// Active area width, mm (`None` when the device gives no physical size).
    pub width_mm: Option<f64>,
    /// Active area height, mm.
    pub height_mm: Option<f64>,
    /// Pressure levels (logical range + 1), `None` without a pressure axis.
    pub pressure_levels: Option<i64>,
    /// Whether the pen reports tilt.
    pub tilt: bool,
    /// Whether the pen has an eraser end.
    pub eraser: bool,
    /// Units of the samples: [`Units::Mm`], or [`Units::Device`] for an evdev tablet without
    /// axis resolution.
    pub units: Units,
}

impl DeviceInfo {
    /// A device about which nothing is known but its interface and its coordinates' units.
    pub fn unknown(interface: Interface, units: Units) -> Self {
        DeviceInfo {
            interface,
            node: None,
            name: None,
            bus: None,
            vendor_id: None,
            product_id: None,
            width_mm: None,
            height_mm: None,
            pressure_levels: None,
            tilt: false,
            eraser: false,
            units,
        }
    }

    /// The description of a HID pen layout (its first pen report), other fields empty.
    pub fn from_layout(interface: Interface, layout: &PenLayout) -> Self {
        let mut info = DeviceInfo::unknown(interface, Units::Mm);
        if let Some(pen) = layout.pens.first() {
            info.fill_from_pen(pen);
        }
        info
    }

    fn fill_from_pen(&mut self, pen: &PenFields) {
        let extent = |f: &crate::capture::hid::FieldSpec, mm: f64| {
            (f.to_physical(f.logical_max) - f.to_physical(f.logical_min)) * mm
        };
        self.width_mm = Some(extent(&pen.x, pen.x_mm_per_unit));
        self.height_mm = Some(extent(&pen.y, pen.y_mm_per_unit));
        self.pressure_levels = pen
            .pressure
            .as_ref()
            .map(|p| p.logical_max - p.logical_min + 1);
        self.tilt = pen.tilt_x.is_some() || pen.tilt_y.is_some();
        self.eraser = pen.invert.is_some() || pen.eraser.is_some();
    }

    /// The `device` object of a `kansei-stroke` file (same keys as
    /// [`crate::capture::replay::recording_to_strokes`] writes, plus `node`).
    pub fn to_json(&self) -> serde_json::Map<String, serde_json::Value> {
        let mut m = serde_json::Map::new();
        m.insert("interface".into(), json!(self.interface.name()));
        m.insert("name".into(), json!(self.name));
        if let Some(node) = &self.node {
            m.insert("node".into(), json!(node));
        }
        if let Some(bus) = self.bus {
            m.insert("bus".into(), json!(bus));
        }
        if let Some(v) = self.vendor_id {
            m.insert("vendor_id".into(), json!(format!("{v:04x}")));
        }
        if let Some(p) = self.product_id {
            m.insert("product_id".into(), json!(format!("{p:04x}")));
        }
        m.insert("width_mm".into(), json!(self.width_mm));
        m.insert("height_mm".into(), json!(self.height_mm));
        m.insert("pressure_levels".into(), json!(self.pressure_levels));
        m.insert("tilt".into(), json!(self.tilt));
        m.insert("eraser".into(), json!(self.eraser));
        m.insert("y_axis".into(), json!("down"));
        m
    }

    /// One line for `kansei devices`: node, IDs, name, size, pressure, tilt.
    pub fn summary(&self) -> String {
        let id = match (self.vendor_id, self.product_id) {
            (Some(v), Some(p)) => format!("{v:04x}:{p:04x}"),
            _ => "????:????".to_owned(),
        };
        let size = match (self.width_mm, self.height_mm) {
            (Some(w), Some(h)) => format!("{w:.1} × {h:.1} mm"),
            _ => "size unknown (no resolution)".to_owned(),
        };
        let pressure = match self.pressure_levels {
            Some(n) => format!("{n} pressure levels"),
            None => "no pressure".to_owned(),
        };
        format!(
            "{:<20} {:<6} {id}  {:?}  {size}, {pressure}, {}{}",
            self.node.as_deref().unwrap_or("-"),
            self.interface.name(),
            self.name.as_deref().unwrap_or("(unnamed)"),
            if self.tilt { "tilt" } else { "no tilt" },
            if self.eraser { ", eraser" } else { "" },
        )
    }
}

/// What a report decoded to.
#[derive(Clone, Debug, PartialEq)]
pub enum Decoded {
    /// A pen report.
    Pen(PenReport),
    /// An input report without pen data (battery, pad buttons, ...).
    Other,
    /// A report that did not decode (skipped and counted).
    Error(HidError),
}

/// One report read from a source.
#[derive(Clone, Debug, PartialEq)]
pub struct SourceEvent {
    /// Seconds since the capture started (recordings: the recording's own times).
    pub t: f64,
    /// The report bytes as read, for HID sources (written to `--raw`).
    pub raw: Option<Vec<u8>>,
    /// The decoded report.
    pub decoded: Decoded,
}

/// What [`PenSource::next`] returns.
#[derive(Clone, Debug, PartialEq)]
pub enum Next {
    /// A report.
    Event(SourceEvent),
    /// Nothing arrived within the source's poll interval (about 0.1 s); the capture loop checks
    /// its stop conditions and asks again.
    Idle,
    /// The source has no more reports (end of a recording).
    End,
}

/// A stream of timed pen reports: a live tablet or a recording.
pub trait PenSource {
    /// The next report, [`Next::Idle`] after a poll interval without one, or [`Next::End`].
    /// An error (a tablet unplugged) ends the capture; the stroke in progress is saved.
    fn next(&mut self) -> Result<Next, SourceError>;
    /// The tablet.
    fn info(&self) -> &DeviceInfo;
    /// The HID report descriptor, for HID sources (needed to write a hid-recorder file).
    fn descriptor(&self) -> Option<&[u8]> {
        None
    }
}

/// A [`Recording`] replayed as a [`PenSource`], decoding each report with the recording's
/// descriptor, at the recording's times (as fast as it is read: no real-time pacing).
#[derive(Clone, Debug)]
pub struct RecordingSource {
    recording: Recording,
    layout: PenLayout,
    info: DeviceInfo,
    next_report: usize,
    fail_after: Option<usize>,
}

impl RecordingSource {
    /// A source over `recording`; an error when its descriptor has no pen. `label` names the
    /// recording in errors and in [`DeviceInfo::node`].
    pub fn new(recording: Recording, label: &str) -> Result<Self, SourceError> {
        let layout = PenLayout::from_descriptor(&recording.descriptor).map_err(|source| {
            SourceError::Descriptor {
                node: label.into(),
                source,
            }
        })?;
        let mut info = DeviceInfo::from_layout(Interface::Recording, &layout);
        info.node = Some(label.to_owned());
        info.name = recording.name.clone();
        if let Some((bus, vendor, product)) = recording.id {
            info.bus = Some(bus);
            info.vendor_id = Some(vendor);
            info.product_id = Some(product);
        }
        Ok(RecordingSource {
            recording,
            layout,
            info,
            next_report: 0,
            fail_after: None,
        })
    }

    /// Makes [`PenSource::next`] fail with [`SourceError::Read`] after `reports` reports, as
    /// an unplugged tablet would: for testing what a capture keeps when interrupted.
    pub fn fail_after(mut self, reports: usize) -> Self {
        self.fail_after = Some(reports);
        self
    }
}

impl PenSource for RecordingSource {
    fn next(&mut self) -> Result<Next, SourceError> {
        if self.fail_after == Some(self.next_report) {
            return Err(SourceError::Read {
                node: self.info.node.clone().unwrap_or_default().into(),
                message: format!("simulated failure after {} reports", self.next_report),
            });
        }
        let Some((t, bytes)) = self.recording.reports.get(self.next_report) else {
            return Ok(Next::End);
        };
        self.next_report += 1;
        let decoded = match self.layout.decode(bytes) {
            Ok(Some(report)) => Decoded::Pen(report),
            Ok(None) => Decoded::Other,
            Err(e) => Decoded::Error(e),
        };
        Ok(Next::Event(SourceEvent {
            t: *t,
            raw: Some(bytes.clone()),
            decoded,
        }))
    }

    fn info(&self) -> &DeviceInfo {
        &self.info
    }

    fn descriptor(&self) -> Option<&[u8]> {
        Some(&self.recording.descriptor)
    }
}
