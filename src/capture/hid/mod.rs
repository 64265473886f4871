//! HID pen decoding driven by the report descriptor.
//!
//! [`PenLayout::from_descriptor`] parses the descriptor (with the `hidreport` crate, after a
//! structural check of its own, [`items`]) and locates, per pen input report, the bit position,
//! logical and physical ranges and units of Tip Switch, In Range, Barrel Switches, Invert,
//! Eraser, X, Y, Tip Pressure and the tilts. Wacom's vendor page 0xFF0D is read as the Digitizers
//! page, its X and Y at 0x130 and 0x131. [`PenLayout::decode`] then turns report bytes into a
//! [`PenReport`]: millimetres, pressure 0..1, tilt in degrees, and the raw logical values.
//! Everything here is a pure function of (descriptor, report bytes).

mod error;
mod field;
pub mod items;
mod layout;
mod report;

pub use error::HidError;
pub use field::{FieldSpec, MAX_FIELD_BITS, PhysicalUnit};
pub use layout::{PenFields, PenLayout};
pub use report::PenReport;
