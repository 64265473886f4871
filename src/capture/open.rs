//! Opening a live tablet by the name `kansei devices` prints: [`open_live`].

use std::path::Path;

use super::live_evdev;
use super::live_hid;
use super::source::{PenSource, SourceError};

/// Opens the tablet `device` names (a `/dev/hidraw*` node opens it as raw HID, any other node
/// through evdev), or with `None` the first HID digitizer found, else the first evdev tablet.
pub fn open_live(device: Option<&str>) -> Result<Box<dyn PenSource>, SourceError> {
    if device.is_none_or(|d| d.contains("hidraw")) {
        let hid = live_hid::list();
        if let Some(t) = hid
            .iter()
            .find(|t| device.is_none_or(|d| t.info.node.as_deref() == Some(d)))
        {
            return Ok(Box::new(live_hid::LiveHid::open(t)?));
        }
    }
    match device {
        Some(d) if !d.contains("hidraw") => {
            Ok(Box::new(live_evdev::LiveEvdev::open(Path::new(d))?))
        }
        Some(d) => Err(SourceError::NotFound(format!(
            "{d}: not a HID pen tablet (see `kansei devices`)"
        ))),
        None => {
            let evdev = live_evdev::list();
            let Some(t) = evdev.first() else {
                return Err(SourceError::NotFound(
                    "no pen tablet found (see `kansei devices`)".into(),
                ));
            };
            let node = t.info.node.clone().unwrap_or_default();
            Ok(Box::new(live_evdev::LiveEvdev::open(Path::new(&node))?))
        }
    }
}
