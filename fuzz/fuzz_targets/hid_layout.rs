//! A fuzzed descriptor and fuzzed reports together, through `recording_to_strokes`: the layouts
//! `hid_descriptor` only builds (odd units and exponents, signed and 32-bit fields, no report
//! IDs) are also decoded, cut into strokes and validated, which text mutation of a
//! hid-recorder file (`hid_recorder`) rarely reaches. Input: a little-endian u16 descriptor
//! length, the descriptor, then reports as <length byte><bytes>, 5 ms apart.
#![no_main]

use kansei::capture::recorder::Recording;
use kansei::capture::replay::recording_to_strokes;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((len, rest)) = data.split_first_chunk::<2>() else {
        return;
    };
    let len = usize::from(u16::from_le_bytes(*len));
    let Some((descriptor, mut tail)) = rest.split_at_checked(len) else {
        return;
    };
    let mut recording = Recording {
        descriptor: descriptor.to_vec(),
        ..Recording::default()
    };
    let mut t = 0.0;
    while let Some((&n, after)) = tail.split_first() {
        let (report, after) = after.split_at(usize::from(n).min(after.len()));
        tail = after;
        if !report.is_empty() {
            recording.reports.push((t, report.to_vec()));
        }
        t += 0.005;
    }
    let _ = recording_to_strokes(&recording);
});
