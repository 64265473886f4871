//! The app's files: opening any stroke format the CLI reads, saving `kansei-stroke`, exporting
//! `kansei-curve` JSON, the quick-look SVG and a PNG, and the recovery file.
//!
//! The recovery file is the drawing as `kansei-stroke` JSON, rewritten atomically (a temporary
//! file and a rename, [`write_atomic`]) after every change, so that killing the app loses no
//! finished stroke. On the next start the app offers it back.

use std::path::{Path, PathBuf};

use crate::cli::{CliError, read_strokes, write_atomic};
use crate::export::{CurveFile, DxfOptions, SvgOptions, dxf_drawing, svg_document};
use crate::pipeline::FitOutput;
use crate::render::{RenderOptions, Scene, View, render_png, scene_bounds};
use crate::stroke::StrokeFile;

/// File name of the recovery file inside its directory.
pub const RECOVERY_FILE_NAME: &str = "recovery.kansei-stroke.json";

/// Margin around the drawing in an exported PNG, pixels.
pub const PNG_MARGIN_PX: f64 = 24.0;

/// Size of an exported PNG, pixels (the render module's defaults suit it).
pub const PNG_SIZE: (u32, u32) = (1600, 1000);

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
pub fn open(path: &Path) -> Result<StrokeFile, CliError> {
    read_strokes(path)
}

/// Writes the strokes as `kansei-stroke` JSON, atomically.
pub fn save(path: &Path, file: &StrokeFile) -> Result<(), CliError> {
    write_atomic(path, file.to_json().as_bytes())
}

/// Writes the recovery file; an empty drawing removes it instead (nothing to recover).
pub fn write_recovery(path: &Path, file: &StrokeFile) -> Result<(), CliError> {
    if file.strokes.is_empty() {
        return match std::fs::remove_file(path) {
            Ok(()) => Ok(()),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
            Err(source) => Err(CliError::Io {
                path: path.to_owned(),
                source,
            }),
        };
    }
    save(path, file)
}

/// The recovery file's drawing, if there is one with strokes. A recovery file that does not
/// read is reported as an error (it is left in place for the user to look at).
pub fn read_recovery(path: &Path) -> Result<Option<StrokeFile>, CliError> {
    if !path.exists() {
        return Ok(None);
    }
    let file = read_strokes(path)?;
    Ok((!file.strokes.is_empty()).then_some(file))
}

/// Removes the recovery file (the user declined it, or the drawing was saved and the app closed).
pub fn discard_recovery(path: &Path) -> Result<(), CliError> {
    write_recovery(path, &StrokeFile::new(crate::stroke::Units::Mm, Vec::new()))
}

/// Writes the fits as `kansei-curve` JSON.
pub fn export_json(path: &Path, output: &FitOutput) -> Result<(), CliError> {
    write_atomic(path, CurveFile::from_output(output).to_json().as_bytes())
}

/// Writes the SVG of the fits (exact lines and arcs, spirals as cubics within the default export
/// accuracy), with the samples as a layer.
pub fn export_svg(path: &Path, file: &StrokeFile, output: &FitOutput) -> Result<(), CliError> {
    let options = SvgOptions::for_units(file.units).with_layers(true, false, false, false);
    let svg = svg_document(output, Some(file), &options);
    write_atomic(path, svg.svg.as_bytes())
}

/// Writes the fits as DXF splines (within the default export accuracy).
pub fn export_dxf(path: &Path, output: &FitOutput) -> Result<(), CliError> {
    let bytes = dxf_drawing(output, &DxfOptions::default())
        .to_bytes()
        .map_err(|e| CliError::Export {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
    write_atomic(path, &bytes)
}

/// Writes a PNG of the whole drawing with `options` (the canvas's overlays).
pub fn export_png(
    path: &Path,
    file: &StrokeFile,
    output: &FitOutput,
    options: &RenderOptions,
) -> Result<(), CliError> {
    let scene = Scene::new(&file.strokes, &output.curves, file.units);
    let Some(bounds) = scene_bounds(&scene) else {
        return Err(CliError::Usage(
            "nothing to export: the drawing is empty".into(),
        ));
    };
    let view = View::fit(bounds, PNG_SIZE.0, PNG_SIZE.1, PNG_MARGIN_PX);
    let png = render_png(&scene, &view, options).map_err(|source| CliError::Render {
        path: path.to_owned(),
        source,
    })?;
    write_atomic(path, &png)
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
