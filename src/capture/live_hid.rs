//! Live HID tablets through `/dev/hidraw*` (feature `live`): [`list`] and [`LiveHid`].
//!
//! Devices come from `hidapi`'s pure-Rust Linux backend (`linux-native-basic-udev`: sysfs, no
//! libudev). A device is a tablet when one of its top-level collections is on the Digitizers
//! page (0x0D) or Wacom's vendor page (0xFF0D) and its report descriptor has a pen report
//! ([`PenLayout::from_descriptor`]). The descriptor is read from sysfs
//! (`/sys/class/hidraw/<node>/device/report_descriptor`, readable by everyone), so listing needs
//! no access to the node; reading falls back to `get_report_descriptor` on the opened device.
//! Reports are timestamped on arrival (seconds since the capture opened the device).

use std::ffi::CString;
use std::path::Path;
use std::time::Instant;

use crate::capture::hid::PenLayout;
use crate::capture::source::{
    Decoded, DeviceInfo, Interface, Next, PenSource, SourceError, SourceEvent,
};

/// The Digitizers usage page.
pub const PAGE_DIGITIZER: u16 = 0x0D;
/// Wacom's vendor-defined digitizer page.
pub const PAGE_WACOM_DIGITIZER: u16 = 0xFF0D;
/// How long [`LiveHid::next`](PenSource::next) waits for a report before returning
/// [`Next::Idle`], in milliseconds.
pub const POLL_MS: i32 = 100;
/// Largest report read (HID reports of pens are tens of bytes).
const REPORT_BUFFER: usize = crate::capture::recorder::MAX_REPORT_BYTES;

/// A HID tablet found by [`list`].
#[derive(Clone, Debug)]
pub struct HidTablet {
    /// Identity, size, pressure, tilt.
    pub info: DeviceInfo,
    /// The report descriptor.
    pub descriptor: Vec<u8>,
    /// `Err` with the reason when this user cannot open the node.
    pub access: Result<(), String>,
}

/// The report descriptor of a hidraw node, from sysfs.
fn sysfs_descriptor(node: &str) -> Option<Vec<u8>> {
    let name = Path::new(node).file_name()?.to_str()?;
    std::fs::read(format!("/sys/class/hidraw/{name}/device/report_descriptor")).ok()
}

/// Checks that `node` can be opened read-write (what hidapi does), naming the errno if not.
fn check_access(node: &str, vendor: Option<u16>) -> Result<(), SourceError> {
    std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .open(node)
        .map(drop)
        .map_err(|e| SourceError::from_open(node, &e, vendor))
}

/// Every HID tablet (see the module documentation). An empty list when hidapi cannot start
/// (no `/sys`, as in some containers).
pub fn list() -> Vec<HidTablet> {
    let Ok(api) = hidapi::HidApi::new() else {
        return Vec::new();
    };
    let mut seen: Vec<String> = Vec::new();
    let mut out = Vec::new();
    for d in api.device_list() {
        if !matches!(d.usage_page(), PAGE_DIGITIZER | PAGE_WACOM_DIGITIZER) {
            continue;
        }
        let node = d.path().to_string_lossy().into_owned();
        if seen.contains(&node) {
            continue;
        }
        seen.push(node.clone());
        let descriptor = match sysfs_descriptor(&node) {
            Some(desc) => desc,
            None => {
                let mut buf = vec![0u8; crate::capture::hid::items::MAX_DESCRIPTOR_BYTES];
                match d
                    .open_device(&api)
                    .and_then(|dev| dev.get_report_descriptor(&mut buf))
                {
                    Ok(n) => buf[..n.min(buf.len())].to_vec(),
                    Err(_) => continue,
                }
            }
        };
        let Ok(layout) = PenLayout::from_descriptor(&descriptor) else {
            continue;
        };
        let mut info = DeviceInfo::from_layout(Interface::Hid, &layout);
        info.node = Some(node.clone());
        info.name = d.product_string().map(str::to_owned);
        info.vendor_id = Some(d.vendor_id());
        info.product_id = Some(d.product_id());
        info.bus = kernel_bus(d.bus_type());
        let access = check_access(&node, info.vendor_id).map_err(|e| match e {
            SourceError::Permission { errno, message, .. } => {
                format!("no access: {message} (errno {errno})")
            }
            other => other.to_string(),
        });
        out.push(HidTablet {
            info,
            descriptor,
            access,
        });
    }
    out
}

/// hidapi's bus type as the kernel's `BUS_*` number (what hid-recorder's `I:` line holds).
fn kernel_bus(bus: hidapi::BusType) -> Option<u16> {
    match bus {
        hidapi::BusType::Usb => Some(0x03),
        hidapi::BusType::Bluetooth => Some(0x05),
        hidapi::BusType::I2c => Some(0x18),
        hidapi::BusType::Spi => Some(0x1c),
        hidapi::BusType::Unknown => None,
    }
}

/// An open HID tablet.
pub struct LiveHid {
    device: hidapi::HidDevice,
    layout: PenLayout,
    descriptor: Vec<u8>,
    info: DeviceInfo,
    started: Instant,
    buffer: Vec<u8>,
}

impl std::fmt::Debug for LiveHid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LiveHid").field("info", &self.info).finish()
    }
}

impl LiveHid {
    /// Opens the tablet [`list`] found at `tablet.info.node`.
    pub fn open(tablet: &HidTablet) -> Result<Self, SourceError> {
        let node = tablet.info.node.clone().unwrap_or_default();
        check_access(&node, tablet.info.vendor_id)?;
        let open_error = |message: String| SourceError::Open {
            node: node.clone().into(),
            message,
        };
        let api = hidapi::HidApi::new().map_err(|e| open_error(e.to_string()))?;
        let path = CString::new(node.clone()).map_err(|e| open_error(e.to_string()))?;
        let device = api
            .open_path(&path)
            .map_err(|e| open_error(e.to_string()))?;
        let layout = PenLayout::from_descriptor(&tablet.descriptor).map_err(|source| {
            SourceError::Descriptor {
                node: node.clone().into(),
                source,
            }
        })?;
        Ok(LiveHid {
            device,
            layout,
            descriptor: tablet.descriptor.clone(),
            info: tablet.info.clone(),
            started: Instant::now(),
            buffer: vec![0; REPORT_BUFFER],
        })
    }
}

impl PenSource for LiveHid {
    fn next(&mut self) -> Result<Next, SourceError> {
        let n = self
            .device
            .read_timeout(&mut self.buffer, POLL_MS)
            .map_err(|e| SourceError::Read {
                node: self.info.node.clone().unwrap_or_default().into(),
                message: e.to_string(),
            })?;
        if n == 0 {
            return Ok(Next::Idle);
        }
        let t = self.started.elapsed().as_secs_f64();
        let bytes = self.buffer[..n.min(self.buffer.len())].to_vec();
        let decoded = match self.layout.decode(&bytes) {
            Ok(Some(report)) => Decoded::Pen(report),
            Ok(None) => Decoded::Other,
            Err(e) => Decoded::Error(e),
        };
        Ok(Next::Event(SourceEvent {
            t,
            raw: Some(bytes),
            decoded,
        }))
    }

    fn info(&self) -> &DeviceInfo {
        &self.info
    }

    fn descriptor(&self) -> Option<&[u8]> {
        Some(&self.descriptor)
    }
}
