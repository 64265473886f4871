//! Live evdev tablets through `/dev/input/event*` (feature `live`): [`list`] and [`LiveEvdev`].
//!
//! A device is a tablet when it has `ABS_X`, `ABS_Y` and `BTN_TOOL_PEN`. Events are framed into
//! [`PenReport`](crate::capture::hid::PenReport)s by [`EvdevPen`] and go through the same
//! stroke builder as HID reports. Times are the kernel's event timestamps, in seconds since the
//! first event read. Nodes this user cannot open are still listed when sysfs
//! (`/sys/class/input/<node>/device/capabilities/key`) shows `BTN_TOOL_PEN`, with the errno.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

use evdev::{AbsoluteAxisCode, KeyCode};

use crate::capture::evdev_frames::{
    AbsAxis, BTN_TOOL_PEN, EvdevAxes, EvdevOutcome, EvdevPen, FrameEnd,
};
use crate::capture::hid::HidError;
use crate::capture::source::{
    Decoded, DeviceInfo, Interface, Next, PenSource, SourceError, SourceEvent,
};
use crate::stroke::Units;

/// Sleep between polls of the non-blocking device while no event is pending.
const POLL_SLEEP: Duration = Duration::from_millis(5);
/// Polls without events before [`Next::Idle`] is returned (20 × 5 ms = 0.1 s).
const POLLS_PER_IDLE: u32 = 20;

/// An evdev tablet found by [`list`].
#[derive(Clone, Debug)]
pub struct EvdevTablet {
    /// Identity, size, pressure, tilt.
    pub info: DeviceInfo,
    /// The pen axes (zeroed when the node could not be opened).
    pub axes: EvdevAxes,
    /// `Err` with the reason when this user cannot open the node.
    pub access: Result<(), String>,
}

fn axes_of(dev: &evdev::Device) -> Option<EvdevAxes> {
    let keys = dev.supported_keys()?;
    if !keys.contains(KeyCode::BTN_TOOL_PEN) {
        return None;
    }
    let mut axes = EvdevAxes::default();
    let (mut x, mut y) = (false, false);
    for (code, info) in dev.get_absinfo().ok()? {
        let a = AbsAxis {
            min: info.minimum(),
            max: info.maximum(),
            resolution: info.resolution(),
        };
        match code {
            AbsoluteAxisCode::ABS_X => {
                axes.x = a;
                x = true;
            }
            AbsoluteAxisCode::ABS_Y => {
                axes.y = a;
                y = true;
            }
            AbsoluteAxisCode::ABS_PRESSURE => axes.pressure = Some(a),
            AbsoluteAxisCode::ABS_TILT_X => axes.tilt_x = Some(a),
            AbsoluteAxisCode::ABS_TILT_Y => axes.tilt_y = Some(a),
            _ => {}
        }
    }
    (x && y).then_some(axes)
}

fn info_of(node: &Path, dev: &evdev::Device, axes: &EvdevAxes) -> DeviceInfo {
    let id = dev.input_id();
    let size = axes.size_mm();
    DeviceInfo {
        interface: Interface::Evdev,
        node: Some(node.display().to_string()),
        name: dev.name().map(str::to_owned),
        bus: Some(id.bus_type().0),
        vendor_id: Some(id.vendor()),
        product_id: Some(id.product()),
        width_mm: size.map(|s| s.0),
        height_mm: size.map(|s| s.1),
        pressure_levels: axes
            .pressure
            .map(|p| i64::from(p.max) - i64::from(p.min) + 1),
        tilt: axes.tilt_x.is_some() || axes.tilt_y.is_some(),
        eraser: dev
            .supported_keys()
            .is_some_and(|k| k.contains(KeyCode::BTN_TOOL_RUBBER)),
        units: axes.units(),
    }
}

/// Whether sysfs says the event node `name` (`event7`) has `BTN_TOOL_PEN`: the `key` capability
/// is a bitmap in hex words, most significant first, of the platform's `long` (64 bits here).
fn sysfs_has_pen(name: &str) -> bool {
    let Ok(text) =
        std::fs::read_to_string(format!("/sys/class/input/{name}/device/capabilities/key"))
    else {
        return false;
    };
    let words: Vec<u64> = text
        .split_whitespace()
        .rev()
        .filter_map(|w| u64::from_str_radix(w, 16).ok())
        .collect();
    let bit = usize::from(BTN_TOOL_PEN);
    words
        .get(bit / 64)
        .is_some_and(|w| w >> (bit % 64) & 1 == 1)
}

fn sysfs_name(name: &str) -> Option<String> {
    std::fs::read_to_string(format!("/sys/class/input/{name}/device/name"))
        .ok()
        .map(|s| s.trim().to_owned())
}

/// Every evdev tablet, including those this user cannot open (with the reason).
pub fn list() -> Vec<EvdevTablet> {
    let Ok(dir) = std::fs::read_dir("/dev/input") else {
        return Vec::new();
    };
    let mut nodes: Vec<PathBuf> = dir
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("event"))
        })
        .collect();
    nodes.sort_by_key(|p| {
        let n = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
        n.trim_start_matches("event")
            .parse::<u32>()
            .unwrap_or(u32::MAX)
    });
    let mut out = Vec::new();
    for node in nodes {
        let name = node
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or("")
            .to_owned();
        match evdev::Device::open(&node) {
            Ok(dev) => {
                if let Some(axes) = axes_of(&dev) {
                    out.push(EvdevTablet {
                        info: info_of(&node, &dev, &axes),
                        axes,
                        access: Ok(()),
                    });
                }
            }
            Err(e) if sysfs_has_pen(&name) => {
                let reason = format!("no access: {e} (errno {})", e.raw_os_error().unwrap_or(0));
                out.push(EvdevTablet {
                    info: DeviceInfo {
                        node: Some(node.display().to_string()),
                        name: sysfs_name(&name),
                        ..DeviceInfo::unknown(Interface::Evdev, Units::Device)
                    },
                    axes: EvdevAxes::default(),
                    access: Err(reason),
                });
            }
            Err(_) => {}
        }
    }
    out
}

/// An open evdev tablet.
pub struct LiveEvdev {
    device: evdev::Device,
    pen: EvdevPen,
    info: DeviceInfo,
    node: PathBuf,
    first: Option<SystemTime>,
    pending: VecDeque<SourceEvent>,
}

impl std::fmt::Debug for LiveEvdev {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LiveEvdev")
            .field("info", &self.info)
            .finish()
    }
}

impl LiveEvdev {
    /// Opens the tablet at `node` (non-blocking reads).
    pub fn open(node: &Path) -> Result<Self, SourceError> {
        let device =
            evdev::Device::open(node).map_err(|e| SourceError::from_open(node, &e, None))?;
        let axes = axes_of(&device).ok_or_else(|| {
            SourceError::NotFound(format!(
                "{}: not a pen tablet (no ABS_X, ABS_Y and BTN_TOOL_PEN)",
                node.display()
            ))
        })?;
        device
            .set_nonblocking(true)
            .map_err(|e| SourceError::from_open(node, &e, None))?;
        let info = info_of(node, &device, &axes);
        Ok(LiveEvdev {
            device,
            pen: EvdevPen::new(axes),
            info,
            node: node.to_owned(),
            first: None,
            pending: VecDeque::new(),
        })
    }
}

impl PenSource for LiveEvdev {
    fn next(&mut self) -> Result<Next, SourceError> {
        for _ in 0..POLLS_PER_IDLE {
            if let Some(e) = self.pending.pop_front() {
                return Ok(Next::Event(e));
            }
            let events = match self.device.fetch_events() {
                Ok(events) => events,
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                    std::thread::sleep(POLL_SLEEP);
                    continue;
                }
                Err(e) => {
                    return Err(SourceError::Read {
                        node: self.node.clone(),
                        message: format!("{e} (errno {})", e.raw_os_error().unwrap_or(0)),
                    });
                }
            };
            for event in events {
                let stamp = event.timestamp();
                let first = *self.first.get_or_insert(stamp);
                let t = stamp.duration_since(first).map_or(0.0, |d| d.as_secs_f64());
                let decoded = match self
                    .pen
                    .feed(event.event_type().0, event.code(), event.value())
                {
                    EvdevOutcome::Frame(FrameEnd::Report(report)) => Decoded::Pen(report),
                    // Counted by the capture loop as a report that did not decode; its frame
                    // gives no sample.
                    EvdevOutcome::OutOfRange(o) => Decoded::Error(HidError::OutOfRange {
                        report_id: 0,
                        field: o.axis,
                        byte: 0,
                        value: i64::from(o.value),
                        min: i64::from(o.min),
                        max: i64::from(o.max),
                    }),
                    _ => continue,
                };
                self.pending.push_back(SourceEvent {
                    t,
                    raw: None,
                    decoded,
                });
            }
        }
        Ok(self.pending.pop_front().map_or(Next::Idle, Next::Event))
    }

    fn info(&self) -> &DeviceInfo {
        &self.info
    }
}
