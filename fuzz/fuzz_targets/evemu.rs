//! Any UTF-8 text through `kansei::capture::evemu::read`: returns Ok or Err, never panics or hangs.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let _ = kansei::capture::evemu::read(text);
});
