//! Any UTF-8 text through `StrokeFile::from_json`; an accepted file must also re-serialise.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(file) = kansei::stroke::StrokeFile::from_json(text) {
        let _ = file.to_json();
    }
});
