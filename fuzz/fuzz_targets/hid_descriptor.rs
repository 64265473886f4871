//! Any byte string as a HID report descriptor: `PenLayout::from_descriptor` returns Ok or Err.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = kansei::capture::hid::PenLayout::from_descriptor(data);
});
