//! The app's files: opening any stroke format the CLI reads ([`crate::io::read_strokes`]),
//! saving `kansei-stroke`, exporting `kansei-curve` JSON, the quick-look SVG, a DXF and a PNG,
//! and the recovery file.
//!
//! No write replaces an existing file unless asked to ([`Overwrite::Allowed`]): the app asks the
//! user first ("Replace …?"), except when saving the drawing over its own stroke file. An export
//! goes to its own path, the path field's name with the export's extension
//! ([`export_path`]), and never replaces a `kansei-stroke` file, asked or not.
//!
//! The recovery file is the drawing as `kansei-stroke` JSON, rewritten atomically (a temporary
//! file and a rename, [`write_atomic`]) after every change, so that killing the app loses no
//! finished stroke. On the next start the app offers it back.

use std::path::{Path, PathBuf};

use crate::export::{EmptyDrawing, Format, FormatError, FormatOptions, PngOptions, SvgLayers};
use crate::io::{FileError, read_strokes, write_atomic, write_new};
use crate::pipeline::FitOutput;
use crate::render::{RenderError, RenderOptions};
use crate::stroke::StrokeFile;

/// File name of the recovery file inside its directory.
pub const RECOVERY_FILE_NAME: &str = "recovery.kansei-stroke.json";

/// Margin around the drawing in an exported PNG, pixels.
pub const PNG_MARGIN_PX: f64 = 24.0;

/// Size of an exported PNG, pixels (the render module's defaults suit it).
pub const PNG_SIZE: (u32, u32) = crate::export::DEFAULT_PNG_SIZE;

/// Largest file [`is_stroke_file`] reads to find out (a stroke file is rarely more than a few
/// MB; a larger file is taken to be one, to be safe).
const STROKE_FILE_CHECK_BYTES: u64 = 256 << 20;

/// Whether a write may replace an existing file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Overwrite {
    /// An existing file is left as it is: the write fails with [`FileError::Exists`].
    Never,
    /// An existing file is replaced (the user said so).
    Allowed,
}

/// Why an export failed.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// The file could not be written (or exists: [`FileError::Exists`]).
    #[error(transparent)]
    File(#[from] FileError),
    /// The export could not be produced.
    #[error("{}: {message}", path.display())]
    Export {
        /// The export's file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// The image could not be drawn.
    #[error("{}: {source}", path.display())]
    Render {
        /// The image file.
        path: PathBuf,
        /// The cause.
        source: RenderError,
    },
    /// Nothing to draw.
    #[error("nothing to export: the drawing is empty")]
    Empty,
    /// The target is a `kansei-stroke` file (a drawing), which an export never replaces.
    #[error("{}: is a stroke file (a drawing): an export never replaces one", path.display())]
    StrokeFile {
        /// The stroke file.
        path: PathBuf,
    },
}

impl ExportError {
    /// Whether the export failed only because its file exists (then the app asks).
    pub fn is_exists(&self) -> bool {
        matches!(self, ExportError::File(FileError::Exists { .. }))
    }
}

/// Where an export in `format` goes for the path `base` (the file panel's path, usually the
/// drawing's file): the same directory and name with the export's extension instead of the
/// file's own (`waves.json` → `waves.svg`, `waves.curve.json`, …; `sketch.kansei-stroke.json`
/// → `sketch.svg`). `None` when `base` names no file (empty, or a folder).
pub fn export_path(base: &Path, format: Format) -> Option<PathBuf> {
    if base.as_os_str().is_empty() || base.is_dir() {
        return None;
    }
    let name = base.file_name()?.to_string_lossy().into_owned();
    let lower = name.to_ascii_lowercase();
    let stem = [".kansei-stroke.json", ".curve.json"]
        .iter()
        .find(|suffix| lower.ends_with(*suffix) && lower.len() > suffix.len())
        .map(|suffix| name[..name.len() - suffix.len()].to_owned())
        .or_else(|| {
            Path::new(&name)
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
        })
        .unwrap_or(name);
    Some(base.with_file_name(format!("{stem}.{}", format.extension())))
}

/// Whether `path` is a `kansei-stroke` file (a drawing), which no export replaces.
pub fn is_stroke_file(path: &Path) -> bool {
    let Ok(meta) = std::fs::metadata(path) else {
        return false;
    };
    if !meta.is_file() {
        return false;
    }
    if meta.len() > STROKE_FILE_CHECK_BYTES {
        return true;
    }
    std::fs::read_to_string(path)
        .ok()
        .and_then(|text| serde_json::from_str::<serde_json::Value>(&text).ok())
        .is_some_and(|v| v.get("format").and_then(|f| f.as_str()) == Some("kansei-stroke"))
}

/// Where the recovery file goes by default: `$XDG_STATE_HOME/kansei/`, else
/// `~/.local/state/kansei/`; `None` when neither variable is set.
pub fn default_recovery_path() -> Option<PathBuf> {
    let dir = std::env::var_os("XDG_STATE_HOME")
        .filter(|d| !d.is_empty())
        .map(PathBuf::from)
        .or_else(|| {
            std::env::var_os("HOME")
                .filter(|d| !d.is_empty())
                .map(|home| PathBuf::from(home).join(".local").join("state"))
        })?;
    Some(dir.join("kansei").join(RECOVERY_FILE_NAME))
}

/// Reads strokes from any supported file (see [`read_strokes`]).
pub fn open(path: &Path) -> Result<StrokeFile, FileError> {
    read_strokes(path)
}

/// Writes `bytes` to `path`, replacing an existing file only when `overwrite` allows.
fn write(path: &Path, bytes: &[u8], overwrite: Overwrite) -> Result<(), FileError> {
    match overwrite {
        Overwrite::Never => write_new(path, bytes),
        Overwrite::Allowed => write_atomic(path, bytes),
    }
}

/// Writes the strokes as `kansei-stroke` JSON, atomically; an existing file is replaced only
/// when `overwrite` allows.
pub fn save(path: &Path, file: &StrokeFile, overwrite: Overwrite) -> Result<(), FileError> {
    write(path, file.to_json().as_bytes(), overwrite)
}

/// Writes the recovery file; an empty drawing removes it instead (nothing to recover).
pub fn write_recovery(path: &Path, file: &StrokeFile) -> Result<(), FileError> {
    if file.strokes.is_empty() {
        return match std::fs::remove_file(path) {
            Ok(()) => Ok(()),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
            Err(source) => Err(FileError::Io {
                path: path.to_owned(),
                source,
            }),
        };
    }
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        // The recovery file's own directory (under $XDG_STATE_HOME) is the app's to make.
        std::fs::create_dir_all(dir).map_err(|source| FileError::Io {
            path: dir.to_owned(),
            source,
        })?;
    }
    save(path, file, Overwrite::Allowed)
}

/// The recovery file's drawing, if there is one with strokes. A recovery file that does not
/// read is reported as an error (it is left in place for the user to look at).
pub fn read_recovery(path: &Path) -> Result<Option<StrokeFile>, FileError> {
    if !path.exists() {
        return Ok(None);
    }
    let file = read_strokes(path)?;
    Ok((!file.strokes.is_empty()).then_some(file))
}

/// Removes the recovery file (the user declined it, or the drawing was saved and the app closed).
pub fn discard_recovery(path: &Path) -> Result<(), FileError> {
    write_recovery(path, &StrokeFile::new(crate::stroke::Units::Mm, Vec::new()))
}

/// The options of the app's exports ([`Format::export`]): the curve JSON as `kansei fit`
/// writes it; the SVG of the fits (exact lines and arcs, spirals as cubics within the default
/// export accuracy) with the samples as a layer; DXF splines (within the default export
/// accuracy); a PNG of [`PNG_SIZE`] of the whole drawing, [`PNG_MARGIN_PX`] around it, drawn
/// with `png` (the canvas's overlays), an empty drawing refused.
pub fn export_options(png: &RenderOptions) -> FormatOptions {
    FormatOptions {
        svg_layers: SvgLayers::SAMPLES,
        png: PngOptions::default()
            .with_size(PNG_SIZE)
            .with_margin(PNG_MARGIN_PX)
            .with_render(*png)
            .with_empty(EmptyDrawing::Refuse),
        ..FormatOptions::default()
    }
}

/// The bytes of an export in `format` with the app's options ([`export_options`]; `path` only
/// names the file in errors).
pub fn export_bytes(
    path: &Path,
    format: Format,
    file: &StrokeFile,
    output: &FitOutput,
    png: &RenderOptions,
) -> Result<Vec<u8>, ExportError> {
    match format.export(file, output, &export_options(png)) {
        Ok(exported) => Ok(exported.bytes),
        Err(FormatError::EmptyDrawing) => Err(ExportError::Empty),
        Err(FormatError::Render(source)) => Err(ExportError::Render {
            path: path.to_owned(),
            source,
        }),
        Err(e @ (FormatError::Dxf(_) | FormatError::Json(_))) => Err(ExportError::Export {
            path: path.to_owned(),
            message: e.to_string(),
        }),
    }
}

/// Writes an export in `format` ([`export_bytes`]) to `path`. An existing file is replaced only
/// when `overwrite` allows, and a `kansei-stroke` file never is ([`ExportError::StrokeFile`]).
pub fn export(
    path: &Path,
    format: Format,
    file: &StrokeFile,
    output: &FitOutput,
    png: &RenderOptions,
    overwrite: Overwrite,
) -> Result<(), ExportError> {
    let bytes = export_bytes(path, format, file, output, png)?;
    if is_stroke_file(path) {
        return Err(ExportError::StrokeFile {
            path: path.to_owned(),
        });
    }
    Ok(write(path, &bytes, overwrite)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Point;
    use crate::stroke::{Stroke, Units};

    fn temp_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("kansei-app-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    #[test]
    fn recovery_round_trip_and_removal() {
        let dir = temp_dir("recovery");
        let path = dir.join(RECOVERY_FILE_NAME);
        assert!(matches!(read_recovery(&path), Ok(None)));
        let stroke = Stroke::from_points((0..20).map(|i| Point::new(i as f64, (i * i) as f64)));
        let file = StrokeFile::new(Units::Px, vec![stroke]);
        assert!(write_recovery(&path, &file).is_ok());
        let back = read_recovery(&path);
        assert!(matches!(&back, Ok(Some(f)) if *f == file), "{back:?}");
        // No temporary file is left behind by the atomic write.
        let names: Vec<_> = std::fs::read_dir(&dir)
            .map(|d| d.filter_map(Result::ok).map(|e| e.file_name()).collect())
            .unwrap_or_default();
        assert_eq!(names, vec![std::ffi::OsString::from(RECOVERY_FILE_NAME)]);
        assert!(discard_recovery(&path).is_ok());
        assert!(!path.exists());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_broken_recovery_file_is_an_error_not_a_panic() {
        let dir = temp_dir("broken");
        let path = dir.join(RECOVERY_FILE_NAME);
        let _ = std::fs::create_dir_all(&dir);
        let _ = std::fs::write(
            &path,
            "{\"format\": \"kansei-stroke\", \"version\": 1, \"units\"",
        );
        let result = read_recovery(&path);
        assert!(
            matches!(&result, Err(e) if e.to_string().contains(RECOVERY_FILE_NAME)),
            "{result:?}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
