//! Files in and out, for the command line, the app and any other front end: [`read_strokes`]
//! reads strokes from every supported format (chosen by extension), and [`write_atomic`],
//! [`write_durable`] and [`write_new`] write outputs so that no reader ever sees half a file
//! and no file is written over by accident.
//!
//! The writers' rules:
//! - The output's directory must exist: nothing is created on the way (a mistyped directory is
//!   an error naming it, not a new tree of folders). [`create_output_dir`] makes the one
//!   directory `kansei fit` fills with several inputs' outputs, under a parent that exists.
//! - The bytes go to a temporary file of their own in the same directory, named
//!   `.NAME.kansei-PID-N.tmp` and created with create-new semantics (never an existing file,
//!   whatever its name), then renamed over `NAME`. On failure the temporary file is removed.
//! - A device or FIFO (`/dev/null`, `/dev/stdout`) is written in place
//!   ([`crate::capture::writer::write_special`]): renaming onto it would replace the node.
//! - [`write_new`] refuses to replace an existing file ([`FileError::Exists`]), atomically: the
//!   temporary file is hard-linked to the name, which fails if the name is taken.

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use thiserror::Error;

use crate::capture::evemu::{EvemuError, EvemuRecording, EvemuStats};
use crate::stroke::{StrokeError, StrokeFile};

/// Why a file could not be read or written; every variant names the file.
#[derive(Debug, Error)]
pub enum FileError {
    /// A file operation failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The output's directory does not exist (outputs never create directories on the way).
    #[error("{}: cannot write: the directory {} does not exist", path.display(), dir.display())]
    NoDirectory {
        /// The file to be written.
        path: PathBuf,
        /// Its missing directory.
        dir: PathBuf,
    },
    /// The output's directory is something else (a file).
    #[error("{}: cannot write: {} is not a directory", path.display(), dir.display())]
    NotADirectory {
        /// The file to be written.
        path: PathBuf,
        /// What stands where its directory should be.
        dir: PathBuf,
    },
    /// [`write_new`]: the file exists and was left as it is.
    #[error("{}: the file exists (not replaced)", path.display())]
    Exists {
        /// The existing file.
        path: PathBuf,
    },
    /// A `kansei-stroke` file was refused.
    #[error("{}: {source}", path.display())]
    Stroke {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: StrokeError,
    },
    /// A recording (hid-recorder, InkML, evemu, Quick Draw) could not be read.
    #[error("{}: {message}", path.display())]
    Recording {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// An evemu events file without a header, and no device description next to it.
    #[error(
        "{}: an evemu events file without a \"# EVEMU\" header needs its device description \
         (N:, I:, A: lines) in a sibling file, and there is none: {} does not exist",
        path.display(),
        tried.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", nor ")
    )]
    MissingDescription {
        /// The events file.
        path: PathBuf,
        /// The description files looked for, most specific first.
        tried: Vec<PathBuf>,
    },
}

impl FileError {
    fn io(path: &Path) -> impl Fn(std::io::Error) -> FileError + '_ {
        move |source| FileError::Io {
            path: path.to_owned(),
            source,
        }
    }
}

/// Skipped lines printed with their numbers per kind of warning; the rest are counted.
const WARNED_LINES: usize = 3;

/// Reads strokes from any supported file, chosen by extension: hid-recorder `.hid`, W3C
/// `.inkml`, Quick Draw `.ndjson`, evemu `.events`/`.evemu` (with a sibling `.desc` when it has
/// no header, see [`evemu_description_candidates`]), and `kansei-stroke` JSON (anything else;
/// the document is checked, each stroke is left to the pipeline, which validates it on its own
/// so that one bad stroke costs only itself: [`StrokeFile::read_json`]). What was skipped or noted on the way is printed on stderr; see
/// [`read_strokes_with_notes`] to have it instead.
pub fn read_strokes(path: &Path) -> Result<StrokeFile, FileError> {
    let (file, notes) = read_strokes_with_notes(path)?;
    for note in notes {
        eprintln!("{note}");
    }
    Ok(file)
}

/// [`read_strokes`], returning the warnings and notes (lines such as `warning: PATH: 2 lines
/// that do not parse skipped`) with the strokes instead of printing them.
pub fn read_strokes_with_notes(path: &Path) -> Result<(StrokeFile, Vec<String>), FileError> {
    let text = std::fs::read_to_string(path).map_err(FileError::io(path))?;
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let recording = |message: String| FileError::Recording {
        path: path.to_owned(),
        message,
    };
    let mut notes = Vec::new();
    let file = match extension.as_deref() {
        Some("hid") => {
            let (file, stats) =
                crate::capture::replay::replay_text(&text).map_err(|e| recording(e.to_string()))?;
            if stats.warnings() > 0 {
                notes.push(format!(
                    "warning: {}: {} reports or lines skipped",
                    path.display(),
                    stats.warnings()
                ));
                for w in stats.first_recorder_warnings.iter().take(WARNED_LINES) {
                    notes.push(format!("  line {}: {}", w.line, w.message));
                }
                for (line, error) in stats.first_decode_errors.iter().take(WARNED_LINES) {
                    notes.push(format!("  line {line}: {error}"));
                }
            }
            file
        }
        Some("inkml") => {
            crate::capture::inkml::read(&text).map_err(|e| recording(e.to_string()))?
        }
        Some("ndjson") => {
            crate::capture::quickdraw::read(&text).map_err(|e| recording(e.to_string()))?
        }
        Some("events") | Some("evemu") => {
            let (file, stats) = read_evemu(path, &text)?;
            let erasers = stats.eraser.iter().filter(|&&e| e).count();
            if erasers > 0 {
                notes.push(format!(
                    "note: {}: {erasers} eraser strokes",
                    path.display()
                ));
            }
            evemu_notes(path, &stats, &mut notes);
            file
        }
        _ => StrokeFile::read_json(&text).map_err(|source| FileError::Stroke {
            path: path.to_owned(),
            source,
        })?,
    };
    Ok((file, notes))
}

/// Whether [`read_strokes`] reads `path` as a recording (by its extension: `.hid`, `.inkml`,
/// `.ndjson`, `.events`, `.evemu`) rather than as `kansei-stroke` JSON.
pub fn is_recording(path: &Path) -> bool {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .is_some_and(|e| RECORDING_EXTENSIONS.contains(&e.as_str()))
}

/// The extensions [`read_strokes`] reads as recordings.
const RECORDING_EXTENSIONS: [&str; 5] = ["hid", "inkml", "ndjson", "events", "evemu"];

/// An evemu recording: with its `# EVEMU` header, as it is; without one (old recordings, as in
/// the evemu-devices collection), its events with the device description of the first sibling
/// `.desc` file [`evemu_description_candidates`] names.
fn read_evemu(path: &Path, text: &str) -> Result<(StrokeFile, EvemuStats), FileError> {
    let recording = |path: &Path| {
        let path = path.to_owned();
        move |e: EvemuError| FileError::Recording {
            path: path.clone(),
            message: e.to_string(),
        }
    };
    let rec = match EvemuRecording::parse(text) {
        Err(EvemuError::NotEvemu(_)) => {
            let tried = evemu_description_candidates(path);
            let Some(desc) = tried.iter().find(|p| p.is_file()) else {
                return Err(FileError::MissingDescription {
                    path: path.to_owned(),
                    tried,
                });
            };
            let desc_text = std::fs::read_to_string(desc).map_err(FileError::io(desc))?;
            let description =
                EvemuRecording::parse_description(&desc_text).map_err(recording(desc))?;
            let name = desc
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            description
                .with_events(text, &name)
                .map_err(recording(path))?
        }
        other => other.map_err(recording(path))?,
    };
    crate::capture::evemu::replay(&rec).map_err(recording(path))
}

/// Where the device description of a header-less evemu events file may be, most specific
/// first, following the evemu-devices collection's naming (`NAME.desc` describes the device,
/// `NAME.events` or `NAME.DESC.events` hold recordings, e.g. `Wacom Intuos4 6x9.desc` for
/// `Wacom Intuos4 6x9.stylus-drag.events`): the file's name with its extension replaced by
/// `.desc`, then with each further dot-separated tag (one without spaces) taken off.
pub fn evemu_description_candidates(path: &Path) -> Vec<PathBuf> {
    let Some(stem) = path.file_stem().map(|s| s.to_string_lossy().into_owned()) else {
        return Vec::new();
    };
    let mut stem = stem.as_str();
    let mut candidates = Vec::new();
    loop {
        if !stem.is_empty() {
            candidates.push(path.with_file_name(format!("{stem}.desc")));
        }
        match stem.rsplit_once('.') {
            Some((rest, tag)) if !rest.is_empty() && !tag.contains(char::is_whitespace) => {
                stem = rest;
            }
            _ => return candidates,
        }
    }
}

/// An evemu recording's skipped lines, values and frames, each count with its first lines.
fn evemu_notes(path: &Path, stats: &EvemuStats, notes: &mut Vec<String>) {
    use crate::capture::evemu::EvemuProblem;
    let kinds = [
        (stats.garbage_lines, "lines that do not parse"),
        (stats.out_of_range, "values out of their axis range"),
        (stats.dropped_frames, "frames dropped (SYN_DROPPED)"),
    ];
    let kind = |p: &EvemuProblem| match p {
        EvemuProblem::Garbage => 0,
        EvemuProblem::OutOfRange(_) => 1,
        EvemuProblem::Dropped => 2,
    };
    for (k, (count, what)) in kinds.into_iter().enumerate() {
        if count == 0 {
            continue;
        }
        notes.push(format!(
            "warning: {}: {count} {what} skipped",
            path.display()
        ));
        let first = stats.warnings.iter().filter(|w| kind(&w.problem) == k);
        for w in first.take(WARNED_LINES) {
            notes.push(format!("  line {}: {}", w.line, w.problem));
        }
    }
}

/// The directory `path` goes into (`.` for a bare file name), checked to exist.
fn existing_parent(path: &Path) -> Result<&Path, FileError> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => Ok(dir),
        Ok(_) => Err(FileError::NotADirectory {
            path: path.to_owned(),
            dir: dir.to_owned(),
        }),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Err(FileError::NoDirectory {
            path: path.to_owned(),
            dir: dir.to_owned(),
        }),
        Err(source) => Err(FileError::Io {
            path: dir.to_owned(),
            source,
        }),
    }
}

/// Whether `a` and `b` name the same file: the same path, or the same canonical path (for a
/// file that does not exist yet, its directory's canonical path and its name), so that
/// `out.json`, `./out.json` and a link to it are one file.
pub fn same_file(a: &Path, b: &Path) -> bool {
    if a == b {
        return true;
    }
    let canonical = |p: &Path| -> Option<std::path::PathBuf> {
        std::fs::canonicalize(p).ok().or_else(|| {
            let parent = p
                .parent()
                .filter(|d| !d.as_os_str().is_empty())
                .unwrap_or(Path::new("."));
            Some(std::fs::canonicalize(parent).ok()?.join(p.file_name()?))
        })
    };
    matches!((canonical(a), canonical(b)), (Some(x), Some(y)) if x == y)
}

/// Checks that `path` can be an output: its directory exists. `kansei fit` calls it for every
/// output before it writes anything, so that a mistyped directory leaves no other output
/// behind.
pub fn check_output(path: &Path) -> Result<(), FileError> {
    existing_parent(path).map(|_| ())
}

/// Makes the directory `dir` (one level: its parent must exist), or accepts it if it exists.
/// `kansei fit` with several inputs writes one output per input into it.
pub fn create_output_dir(dir: &Path) -> Result<(), FileError> {
    if dir.is_dir() {
        return Ok(());
    }
    existing_parent(dir)?;
    match std::fs::create_dir(dir) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && dir.is_dir() => Ok(()),
        Err(source) => Err(FileError::Io {
            path: dir.to_owned(),
            source,
        }),
    }
}

/// Number of the next temporary file of this process (with the process ID, a unique name).
static TEMPORARY: AtomicU64 = AtomicU64::new(0);

/// Attempts at a free temporary name before giving up (another process would have to hold
/// every one of them).
const TEMPORARY_ATTEMPTS: usize = 100;

/// A temporary file next to `path`, created new (never an existing file), with `bytes` written
/// (and synced when `sync`), and the permissions of the file it will replace, if any. It is
/// removed again on failure.
struct Temporary {
    path: PathBuf,
    kept: bool,
}

impl Temporary {
    fn write(path: &Path, dir: &Path, bytes: &[u8], sync: bool) -> Result<Self, FileError> {
        let name = path.file_name().ok_or_else(|| FileError::Io {
            path: path.to_owned(),
            source: std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file name"),
        })?;
        let mut attempt = 0;
        let (file, tmp) = loop {
            let n = TEMPORARY.fetch_add(1, Ordering::Relaxed);
            let mut tmp_name = std::ffi::OsString::from(".");
            tmp_name.push(name);
            tmp_name.push(format!(".kansei-{}-{n}.tmp", std::process::id()));
            let tmp = dir.join(tmp_name);
            match OpenOptions::new().write(true).create_new(true).open(&tmp) {
                Ok(file) => break (file, tmp),
                Err(e)
                    if e.kind() == std::io::ErrorKind::AlreadyExists
                        && attempt + 1 < TEMPORARY_ATTEMPTS =>
                {
                    attempt += 1;
                }
                Err(source) => return Err(FileError::Io { path: tmp, source }),
            }
        };
        let temporary = Temporary {
            path: tmp,
            kept: false,
        };
        temporary.fill(file, path, bytes, sync)?;
        Ok(temporary)
    }

    fn fill(&self, mut file: File, path: &Path, bytes: &[u8], sync: bool) -> Result<(), FileError> {
        let io = FileError::io(&self.path);
        file.write_all(bytes).map_err(&io)?;
        if sync {
            file.sync_all().map_err(&io)?;
        }
        // The replaced file's permissions carry over (best effort: a file that cannot be
        // looked at gets the defaults).
        if let Ok(m) = std::fs::metadata(path)
            && m.is_file()
        {
            let _ = file.set_permissions(m.permissions());
        }
        Ok(())
    }

    /// Renames the temporary file over `path`.
    fn rename_over(mut self, path: &Path) -> Result<(), FileError> {
        std::fs::rename(&self.path, path).map_err(FileError::io(path))?;
        self.kept = true;
        Ok(())
    }

    /// Gives the temporary file the name `path` if that name is free.
    fn link_as_new(self, path: &Path) -> Result<(), FileError> {
        match std::fs::hard_link(&self.path, path) {
            Ok(()) => Ok(()),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Err(FileError::Exists {
                path: path.to_owned(),
            }),
            // No hard links here (some file systems): create the name new and copy into it.
            Err(_) => {
                let bytes = std::fs::read(&self.path).map_err(FileError::io(&self.path))?;
                let mut f = match OpenOptions::new().write(true).create_new(true).open(path) {
                    Ok(f) => f,
                    Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                        return Err(FileError::Exists {
                            path: path.to_owned(),
                        });
                    }
                    Err(source) => {
                        return Err(FileError::Io {
                            path: path.to_owned(),
                            source,
                        });
                    }
                };
                let written = f.write_all(&bytes);
                if let Err(source) = written {
                    drop(f);
                    let _ = std::fs::remove_file(path);
                    return Err(FileError::Io {
                        path: path.to_owned(),
                        source,
                    });
                }
                Ok(())
            }
        }
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        if !self.kept {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

fn replace(path: &Path, bytes: &[u8], sync: bool) -> Result<(), FileError> {
    if let Some(done) = crate::capture::writer::write_special(path, bytes) {
        return done.map_err(FileError::io(path));
    }
    let dir = existing_parent(path)?;
    Temporary::write(path, dir, bytes, sync)?.rename_over(path)?;
    if sync {
        // The rename is durable once the directory is synced. Some file systems refuse to
        // fsync a directory; the file itself is complete either way, so that is not reported.
        if let Ok(d) = File::open(dir) {
            let _ = d.sync_all();
        }
    }
    Ok(())
}

/// Writes `bytes` to `path` (replacing it if it exists) through a temporary file and a rename,
/// so a reader never sees half a file; see the [module documentation](self) for the rules.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), FileError> {
    replace(path, bytes, false)
}

/// [`write_atomic`] with `fsync` of the file and of its directory around the rename: after it
/// returns, `path` holds `bytes` even across a power cut.
pub fn write_durable(path: &Path, bytes: &[u8]) -> Result<(), FileError> {
    replace(path, bytes, true)
}

/// Writes `bytes` to `path`, which must not exist: an existing file is left as it is and the
/// error is [`FileError::Exists`] (checked atomically, so a file that appears meanwhile is not
/// replaced either). A device or FIFO is written in place like [`write_atomic`] does.
pub fn write_new(path: &Path, bytes: &[u8]) -> Result<(), FileError> {
    if let Some(done) = crate::capture::writer::write_special(path, bytes) {
        return done.map_err(FileError::io(path));
    }
    let dir = existing_parent(path)?;
    if std::fs::symlink_metadata(path).is_ok() {
        return Err(FileError::Exists {
            path: path.to_owned(),
        });
    }
    Temporary::write(path, dir, bytes, false)?.link_as_new(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("kansei-io-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let _ = std::fs::create_dir_all(&dir);
        dir
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .map(|d| {
                d.filter_map(Result::ok)
                    .map(|e| e.file_name().to_string_lossy().into_owned())
                    .collect()
            })
            .unwrap_or_default();
        v.sort();
        v
    }

    #[test]
    fn a_file_named_like_the_old_temporary_is_left_alone() {
        let dir = temp_dir("tmp-name");
        let out = dir.join("out.json");
        let precious = dir.join("out.json.tmp");
        std::fs::write(&precious, "the user's own file").expect("write");
        write_atomic(&out, b"one").expect("first write");
        write_atomic(&out, b"two").expect("second write");
        assert_eq!(std::fs::read(&out).expect("read"), b"two");
        assert_eq!(
            std::fs::read_to_string(&precious).expect("read"),
            "the user's own file"
        );
        assert_eq!(names(&dir), ["out.json", "out.json.tmp"]);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_missing_directory_is_named_and_nothing_is_created() {
        let dir = temp_dir("no-dir");
        let out = dir.join("missing").join("deeper").join("x.svg");
        for result in [
            write_atomic(&out, b"x"),
            write_durable(&out, b"x"),
            write_new(&out, b"x"),
        ] {
            let e = result.expect_err("no directory");
            let text = e.to_string();
            assert!(
                matches!(e, FileError::NoDirectory { .. }) && text.contains("deeper"),
                "{text}"
            );
        }
        assert!(names(&dir).is_empty());
        // A file where the directory should be.
        std::fs::write(dir.join("missing"), "a file").expect("write");
        let e = write_atomic(&dir.join("missing").join("x.svg"), b"x").expect_err("a file");
        assert!(matches!(e, FileError::NotADirectory { .. }), "{e}");
        // One level is made, under a parent that exists.
        assert!(create_output_dir(&dir.join("out")).is_ok());
        assert!(create_output_dir(&dir.join("out")).is_ok());
        assert!(matches!(
            create_output_dir(&dir.join("a").join("b")),
            Err(FileError::NoDirectory { .. })
        ));
        assert_eq!(names(&dir), ["missing", "out"]);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn write_new_never_replaces_and_a_failed_write_leaves_no_temporary() {
        let dir = temp_dir("new");
        let out = dir.join("x.svg");
        write_new(&out, b"first").expect("new");
        let e = write_new(&out, b"second").expect_err("exists");
        assert!(matches!(e, FileError::Exists { .. }), "{e}");
        assert_eq!(std::fs::read(&out).expect("read"), b"first");
        // Renaming over a directory fails; the temporary file goes.
        std::fs::create_dir(dir.join("sub")).expect("dir");
        assert!(write_atomic(&dir.join("sub"), b"x").is_err());
        assert_eq!(names(&dir), ["sub", "x.svg"]);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[cfg(unix)]
    #[test]
    fn a_replaced_file_keeps_its_permissions() {
        use std::os::unix::fs::PermissionsExt;
        let dir = temp_dir("mode");
        let out = dir.join("x.json");
        std::fs::write(&out, "old").expect("write");
        std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o640)).expect("chmod");
        write_atomic(&out, b"new").expect("write");
        let mode = std::fs::metadata(&out).expect("meta").permissions().mode();
        assert_eq!(mode & 0o777, 0o640);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn description_candidates_follow_the_collections_naming() {
        let p = Path::new("/r/Wacom Intuos4 6x9.stylus-drag.events");
        assert_eq!(
            evemu_description_candidates(p),
            [
                PathBuf::from("/r/Wacom Intuos4 6x9.stylus-drag.desc"),
                PathBuf::from("/r/Wacom Intuos4 6x9.desc"),
            ]
        );
        assert_eq!(
            evemu_description_candidates(Path::new("pen.evemu")),
            [PathBuf::from("pen.desc")]
        );
        // A dot inside a name with spaces is not a tag.
        assert_eq!(
            evemu_description_candidates(Path::new("Pen 1.5 mm.events")),
            [PathBuf::from("Pen 1.5 mm.desc")]
        );
    }
}
