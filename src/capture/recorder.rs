//! The hid-recorder text format (hid-tools / hidutils `hid-recorder`, replayed by `hid-replay`):
//!
//! ```text
//! # free-text comments, the pretty-printed descriptor, hid-tools' decode of each report
//! R: <length> <descriptor bytes in hex>
//! N: <device name>
//! P: <physical path>
//! I: <bus> <vendor id> <product id>
//! D: <device index>                       (recordings of several devices)
//! E: <seconds.micros> <length> <report bytes in hex>
//! ```
//!
//! [`Recording::parse`] keeps the first device (index 0). A missing or malformed descriptor is an
//! error naming the line; a malformed report line, an unknown line or another device's line is
//! skipped and counted as a warning with its line number.

use thiserror::Error;

/// Longest report accepted on an `E:` line. HID reports of real digitizers are tens of bytes;
/// USB high-speed interrupt transfers top out at 3 × 1024 bytes per microframe, so 4096 is
/// above anything a device sends, and bounds what a garbage line can make us hold.
pub const MAX_REPORT_BYTES: usize = 4096;
/// Warnings kept with their text; later ones are only counted.
pub const MAX_KEPT_WARNINGS: usize = 100;

/// Why a recording could not be read.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum RecorderError {
    /// No `R:` line for device 0.
    #[error("no report descriptor (`R:` line) in the recording")]
    MissingDescriptor,
    /// The `R:` line does not parse.
    #[error("line {line}: bad report descriptor: {message}")]
    BadDescriptor {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A second `R:` line for the same device.
    #[error("line {line}: a second report descriptor for the same device")]
    DuplicateDescriptor {
        /// 1-based line number.
        line: usize,
    },
}

/// A skipped line.
#[derive(Clone, Debug, PartialEq)]
pub struct LineWarning {
    /// 1-based line number.
    pub line: usize,
    /// Why it was skipped.
    pub message: String,
}

/// A parsed hid-recorder file: device 0's descriptor, header and reports.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Recording {
    /// The report descriptor bytes.
    pub descriptor: Vec<u8>,
    /// The device name (`N:`), if given.
    pub name: Option<String>,
    /// Bus, vendor ID and product ID (`I:`), if given.
    pub id: Option<(u16, u16, u16)>,
    /// Every well-formed `E:` line: (seconds since the recording started, report bytes).
    pub reports: Vec<(f64, Vec<u8>)>,
    /// 1-based line number of each report, parallel to `reports`.
    pub report_lines: Vec<usize>,
    /// The first [`MAX_KEPT_WARNINGS`] skipped lines.
    pub warnings: Vec<LineWarning>,
    /// How many lines were skipped (may exceed `warnings.len()`).
    pub warning_count: usize,
}

impl Recording {
    /// Parses hid-recorder text. Never panics; see the module documentation for what is an
    /// error and what a counted warning.
    pub fn parse(text: &str) -> Result<Recording, RecorderError> {
        let mut rec = Recording::default();
        let mut device = 0u64;
        let mut have_descriptor = false;
        for (i, raw_line) in text.lines().enumerate() {
            let line_no = i + 1;
            let line = raw_line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let (tag, rest) = match line.split_once(':') {
                Some((tag, rest)) if tag.len() == 1 => (tag, rest.trim()),
                _ => {
                    rec.warn(line_no, "not a hid-recorder line".into());
                    continue;
                }
            };
            if tag == "D" {
                match rest.parse::<u64>() {
                    Ok(d) => device = d,
                    Err(_) => rec.warn(line_no, format!("bad device index {rest:?}")),
                }
                continue;
            }
            if device != 0 {
                rec.warn(
                    line_no,
                    format!("line of device {device} ignored: only device 0 is read"),
                );
                continue;
            }
            match tag {
                "R" => {
                    if have_descriptor {
                        return Err(RecorderError::DuplicateDescriptor { line: line_no });
                    }
                    rec.descriptor = parse_sized_hex(rest, super::hid::items::MAX_DESCRIPTOR_BYTES)
                        .map_err(|message| RecorderError::BadDescriptor {
                            line: line_no,
                            message,
                        })?;
                    have_descriptor = true;
                }
                "N" => rec.name = Some(rest.to_owned()),
                "I" => match parse_id(rest) {
                    Some(id) => rec.id = Some(id),
                    None => rec.warn(line_no, format!("bad device ID line {rest:?}")),
                },
                "P" => {}
                "E" => match parse_event(rest) {
                    Ok((t, bytes)) => {
                        rec.reports.push((t, bytes));
                        rec.report_lines.push(line_no);
                    }
                    Err(message) => rec.warn(line_no, message),
                },
                _ => rec.warn(line_no, format!("unknown line type {tag:?}")),
            }
        }
        if !have_descriptor {
            return Err(RecorderError::MissingDescriptor);
        }
        Ok(rec)
    }

    fn warn(&mut self, line: usize, message: String) {
        self.warning_count += 1;
        if self.warnings.len() < MAX_KEPT_WARNINGS {
            self.warnings.push(LineWarning { line, message });
        }
    }
}

/// `<length> <hex> <hex> ...`: the bytes, checked against the length and `max`.
fn parse_sized_hex(text: &str, max: usize) -> Result<Vec<u8>, String> {
    let mut parts = text.split_ascii_whitespace();
    let len_text = parts.next().ok_or("no length")?;
    let len: usize = len_text
        .parse()
        .map_err(|_| format!("length {len_text:?} is not a number"))?;
    if len > max {
        return Err(format!("length {len} exceeds the {max}-byte limit"));
    }
    let mut bytes = Vec::with_capacity(len);
    for (i, h) in parts.enumerate() {
        if bytes.len() == len {
            return Err(format!("more than the {len} bytes announced"));
        }
        let b = u8::from_str_radix(h, 16)
            .ok()
            .filter(|_| h.len() == 2)
            .ok_or_else(|| format!("byte {i}: {h:?} is not a two-digit hex byte"))?;
        bytes.push(b);
    }
    if bytes.len() != len {
        return Err(format!("{} bytes, {len} announced", bytes.len()));
    }
    Ok(bytes)
}

/// `<seconds> <length> <hex> ...` of an `E:` line.
fn parse_event(text: &str) -> Result<(f64, Vec<u8>), String> {
    let (t_text, rest) = text
        .split_once(|c: char| c.is_ascii_whitespace())
        .ok_or("no report bytes")?;
    let t: f64 = t_text
        .parse()
        .map_err(|_| format!("time {t_text:?} is not a number"))?;
    if !(t.is_finite() && t >= 0.0) {
        return Err(format!(
            "time {t_text:?} is not a finite non-negative number"
        ));
    }
    let bytes = parse_sized_hex(rest.trim(), MAX_REPORT_BYTES)?;
    if bytes.is_empty() {
        return Err("empty report".into());
    }
    Ok((t, bytes))
}

/// `<bus> <vendor> <product>` in hex.
fn parse_id(text: &str) -> Option<(u16, u16, u16)> {
    let mut parts = text.split_ascii_whitespace();
    let mut next = || u16::from_str_radix(parts.next()?, 16).ok();
    let id = (next()?, next()?, next()?);
    parts.next().is_none().then_some(id)
}
