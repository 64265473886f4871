//! Any UTF-8 text as a hid-recorder recording through `replay_text` (parse, decode, build).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let _ = kansei::capture::replay::replay_text(text);
});
