//! Crash-safe output of a capture.
//!
//! [`StrokeWriter`] keeps the strokes finished so far and, after each one, **rewrites the whole
//! `kansei-stroke` file atomically**: the JSON goes to a temporary file of its own next to
//! `<out>` ([`crate::io::write_durable`]), which is `fsync`ed, renamed over `<out>`, and the
//! directory is `fsync`ed. A reader (or a crash, a Ctrl-C, an unplugged
//! tablet, a power cut after the rename) therefore only ever sees a complete, valid file holding
//! every stroke finished so far. Rewriting is O(strokes so far) per stroke: a sketching session
//! of a few hundred strokes of a few hundred samples is a few MB, written once per pen lift,
//! which is far below the time between strokes. On an interruption the capture loop calls
//! [`StrokeWriter::save_with_partial`] to add the stroke in progress.
//!
//! [`RawWriter`] writes the reports in the hid-recorder format (`R:`, `N:`, `I:`, then one
//! `E: <seconds> <length> <hex>` line per report), flushed to the OS after every report, so that
//! a crash of kansei loses nothing (a power cut may lose what the OS had not written yet).
//! `kansei replay` and `kansei fit` read it back.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use serde_json::json;
use thiserror::Error;

use crate::capture::source::DeviceInfo;
use crate::capture::stroke_builder::{BuiltStroke, Tool};
use crate::stroke::{Stroke, StrokeError, StrokeFile};

/// Why a capture's output could not be written.
#[derive(Debug, Error)]
pub enum WriteError {
    /// A file operation failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The output could not be written (its directory is missing, the disk is full...).
    #[error(transparent)]
    File(#[from] crate::io::FileError),
    /// The strokes fail validation (a bug, or values beyond the format's limits).
    #[error("captured strokes: {0}")]
    Stroke(#[from] StrokeError),
}

fn io_error(path: &Path) -> impl Fn(std::io::Error) -> WriteError + '_ {
    move |source| WriteError::Io {
        path: path.to_owned(),
        source,
    }
}

/// Writes `bytes` straight into `path` when it names something other than a regular file or a
/// directory (a device such as `/dev/null`, a FIFO): `Some` with the outcome, `None` when `path`
/// is a regular file or absent and the caller should write through a temporary file and a rename.
/// Renaming onto a device would replace the device node itself (as root, `--out /dev/null` once
/// turned the machine's /dev/null into a regular file).
pub fn write_special(path: &Path, bytes: &[u8]) -> Option<std::io::Result<()>> {
    let kind = std::fs::metadata(path).ok()?.file_type();
    if kind.is_file() || kind.is_dir() {
        return None;
    }
    Some(
        std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .and_then(|mut f| f.write_all(bytes)),
    )
}

/// Writes `bytes` to `path` through a temporary file of its own, with `fsync` of the file and of
/// its directory around the rename: after it returns, `path` holds `bytes` even across a power
/// cut, and at no time does `path` hold a partial file. A device or FIFO is written in place
/// ([`write_special`]). The directory must exist. See [`crate::io::write_durable`].
pub fn write_durable(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    Ok(crate::io::write_durable(path, bytes)?)
}

/// The `kansei-stroke` output of a capture; see the module documentation.
#[derive(Debug)]
pub struct StrokeWriter {
    path: PathBuf,
    file: StrokeFile,
    tools: Vec<Tool>,
    info: DeviceInfo,
}

impl StrokeWriter {
    /// Starts the output at `path` and writes it at once with no strokes, so that a bad path
    /// fails before the first stroke is drawn.
    pub fn create(path: &Path, info: &DeviceInfo, source: &str) -> Result<Self, WriteError> {
        let mut file = StrokeFile::new(info.units, Vec::new());
        file.source = Some(source.to_owned());
        let mut w = StrokeWriter {
            path: path.to_owned(),
            file,
            tools: Vec::new(),
            info: info.clone(),
        };
        w.save(None)?;
        Ok(w)
    }

    /// The strokes written so far.
    pub fn strokes(&self) -> &[Stroke] {
        &self.file.strokes
    }

    /// The output path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Adds a finished stroke and rewrites the file.
    pub fn push(&mut self, built: BuiltStroke) -> Result<(), WriteError> {
        self.file.strokes.push(built.stroke);
        self.tools.push(built.tool);
        self.save(None)
    }

    /// Rewrites the file with the finished strokes and, after them, `partial` (the stroke in
    /// progress when the capture was interrupted), which is not kept for later writes.
    pub fn save_with_partial(&mut self, partial: Option<BuiltStroke>) -> Result<(), WriteError> {
        self.save(partial)
    }

    fn save(&mut self, partial: Option<BuiltStroke>) -> Result<(), WriteError> {
        let mut tools = self.tools.clone();
        let mut file = self.file.clone();
        if let Some(p) = partial {
            file.strokes.push(p.stroke);
            tools.push(p.tool);
        }
        let eraser_strokes: Vec<usize> = (tools.iter().enumerate())
            .filter(|(_, t)| **t == Tool::Eraser)
            .map(|(i, _)| i)
            .collect();
        let mut device = self.info.to_json();
        device.insert("eraser_strokes".into(), json!(eraser_strokes));
        file.device = Some(serde_json::Value::Object(device));
        file.validate()?;
        write_durable(&self.path, file.to_json().as_bytes())
    }
}

/// A hid-recorder file written as reports arrive; see the module documentation.
#[derive(Debug)]
pub struct RawWriter {
    path: PathBuf,
    out: BufWriter<File>,
}

impl RawWriter {
    /// Creates `path` and writes the header: the descriptor (`R:`), name (`N:`) and IDs (`I:`).
    pub fn create(path: &Path, descriptor: &[u8], info: &DeviceInfo) -> Result<Self, WriteError> {
        let file = File::create(path).map_err(io_error(path))?;
        let mut w = RawWriter {
            path: path.to_owned(),
            out: BufWriter::new(file),
        };
        let mut header = String::from("# recorded by kansei capture\n");
        header.push_str(&format!("R: {} {}\n", descriptor.len(), hex(descriptor)));
        if let Some(name) = &info.name {
            header.push_str(&format!("N: {}\n", name.replace('\n', " ")));
        }
        if let (Some(bus), Some(v), Some(p)) = (info.bus, info.vendor_id, info.product_id) {
            header.push_str(&format!("I: {bus:x} {v:04x} {p:04x}\n"));
        }
        w.write_line(&header)?;
        Ok(w)
    }

    /// Appends one report read at `t` seconds and flushes it to the OS.
    pub fn report(&mut self, t: f64, bytes: &[u8]) -> Result<(), WriteError> {
        self.write_line(&format!("E: {t:.6} {} {}\n", bytes.len(), hex(bytes)))
    }

    fn write_line(&mut self, text: &str) -> Result<(), WriteError> {
        let path = &self.path;
        self.out
            .write_all(text.as_bytes())
            .map_err(io_error(path))?;
        self.out.flush().map_err(io_error(path))
    }
}

fn hex(bytes: &[u8]) -> String {
    let parts: Vec<String> = bytes.iter().map(|b| format!("{b:02x}")).collect();
    parts.join(" ")
}
