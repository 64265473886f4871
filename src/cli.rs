//! The `kansei` command line: argument parsing and the commands, kept in the library so that
//! `main.rs` is a few lines and the commands are testable.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::{Args, Parser, Subcommand};

use crate::export::{
    ExportOptions, Format, FormatError, FormatOptions, JsonLayout, PngOptions, SvgLayers,
};
use crate::io::{read_strokes, write_atomic};
use crate::lac::AlphaChoice;
use crate::pipeline::{FitOutput, PipelineOptions, fit_files};
use crate::render::{Overlays, RenderOptions};
use crate::stroke::StrokeFile;

/// kansei: pen strokes to log-aesthetic curves.
#[derive(Debug, Parser)]
#[command(name = "kansei", version, about)]
pub struct Cli {
    /// The command.
    #[command(subcommand)]
    pub command: Command,
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Fit strokes: B-spline, split at inflections and curvature extrema; writes kansei-curve
    /// JSON.
    Fit(FitArgs),
    /// Time the B-spline and split stages over stroke files.
    Bench(BenchArgs),
    /// Convert a recording (hid-recorder `.hid`, or any input `fit` reads) to kansei-stroke JSON.
    Replay(ReplayArgs),
    /// List pen tablets (hidraw and evdev): IDs, size, pressure levels, tilt, access.
    Devices,
    /// Capture strokes from a tablet into kansei-stroke JSON, each stroke written as it ends.
    Capture(CaptureArgs),
    /// The sketch app: draw, see the log-aesthetic chain appear, study its curvature.
    #[cfg(feature = "app")]
    App(AppArgs),
    /// The fitting service: an HTTP API (fit, export, stream) and a pen page for any tablet in
    /// a browser (docs/service.md).
    #[cfg(feature = "serve")]
    Serve(crate::serve::ServeArgs),
}

/// `kansei app`.
#[cfg(feature = "app")]
#[derive(Debug, Args)]
pub struct AppArgs {
    /// A file to open (any format `fit` reads).
    pub file: Option<PathBuf>,
    /// Replay the file's strokes at their recorded speed once it is open.
    #[arg(long, requires = "file")]
    pub replay: bool,
    /// The recovery file, rewritten after every stroke
    /// [default: $XDG_STATE_HOME/kansei/recovery.kansei-stroke.json].
    #[arg(long)]
    pub recovery: Option<PathBuf>,
    /// Draw with a live tablet: its node as `kansei devices` lists it, or nothing for the first
    /// one found. Pressure and tilt come with the samples.
    #[arg(long, num_args = 0..=1, default_missing_value = "", conflicts_with = "tablet_replay")]
    pub tablet: Option<String>,
    /// Play a hid-recorder recording (`.hid`) into the canvas as if it were the live tablet
    /// (the same decoding and stroke cutting as a live tablet).
    #[arg(long)]
    pub tablet_replay: Option<PathBuf>,
    /// Pace of `--tablet-replay` (1 = as recorded).
    #[arg(
        long,
        default_value_t = 1.0,
        requires = "tablet_replay",
        allow_negative_numbers = true
    )]
    pub tablet_speed: f64,
}

/// `kansei capture`.
#[derive(Debug, Args)]
pub struct CaptureArgs {
    /// The tablet's node as `kansei devices` lists it (`/dev/hidraw3`, `/dev/input/event7`)
    /// [default: the first HID tablet, else the first evdev tablet].
    #[arg(long)]
    pub device: Option<String>,
    /// Where to write the kansei-stroke JSON (rewritten atomically after every stroke).
    #[arg(long)]
    pub out: PathBuf,
    /// Also record the raw HID reports here, in hid-recorder format (HID tablets only).
    #[arg(long)]
    pub raw: Option<PathBuf>,
    /// Stop after this many seconds [default: until Ctrl-C or the tablet is unplugged].
    #[arg(long, allow_negative_numbers = true)]
    pub duration: Option<f64>,
    /// Testing: capture from a hid-recorder recording instead of a tablet.
    #[arg(long, hide = true, conflicts_with = "device")]
    pub from_recording: Option<PathBuf>,
    /// Testing: with --from-recording, fail after this many reports as an unplugged tablet.
    #[arg(long, hide = true, requires = "from_recording")]
    pub fail_after_reports: Option<usize>,
    /// Testing: with --from-recording, deliver the reports at this times their recorded pace
    /// (a tablet being drawn on, so that a signal can arrive mid-stroke).
    #[arg(
        long,
        hide = true,
        requires = "from_recording",
        allow_negative_numbers = true
    )]
    pub pace: Option<f64>,
}

/// `kansei replay`.
#[derive(Debug, Args)]
pub struct ReplayArgs {
    /// The recording.
    pub input: PathBuf,
    /// Where to write the kansei-stroke JSON.
    #[arg(long)]
    pub out: PathBuf,
}

/// Options shared by `fit` and `bench`.
#[derive(Debug, Args, Clone)]
pub struct FitSettings {
    /// Largest distance from any sample to the curve, in the file's units [default: per stroke,
    /// mm 0.1, px 0.5, device 20, raised to the stroke's noise floor]. Below a stroke's floor the
    /// fit follows the noise (with a warning); above its default, loosening never adds segments.
    #[arg(long, allow_negative_numbers = true)]
    pub tolerance: Option<f64>,
    /// Turning angle (degrees, 0 to 180) above which the stroke is cut at a corner.
    #[arg(long, default_value_t = 70.0, allow_negative_numbers = true, value_parser = parse_corner_angle)]
    pub corner_angle: f64,
    /// Keep the pen's landing and lifting as drawn (hooks and dwell) instead of dropping them.
    #[arg(long)]
    pub keep_hooks: bool,
    /// Give every segment this α (e.g. −1: clothoids only).
    #[arg(long, allow_negative_numbers = true, conflicts_with = "alpha_range")]
    pub alpha: Option<f64>,
    /// Search α in MIN:MAX [default: -3:3].
    #[arg(long, value_parser = crate::lac::parse_alpha_range, allow_hyphen_values = true)]
    pub alpha_range: Option<(f64, f64)>,
    /// Continuity at smooth joints: g1 (position and tangent), g2 (and curvature; a curve the
    /// smooth fit cannot hold within the tolerance stays g1) or c3 (and dκ/ds).
    #[arg(long, default_value = "g2")]
    pub continuity: crate::chain::Continuity,
    /// Strokes that come back to their start: auto (fitted as one closed curve, its seam as
    /// continuous as its other joints; see docs/pipeline.md) or never (fitted open).
    #[arg(long, default_value = "auto", value_parser = parse_close)]
    pub close: crate::closure::Close,
}

/// Parses `--close`.
fn parse_close(text: &str) -> Result<crate::closure::Close, String> {
    text.parse()
}

/// Parses `WIDTHxHEIGHT` (or `WIDTH×HEIGHT`) into a pixel size; the render checks the range.
fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once(['x', 'X', '×'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT, got {text:?}"))?;
    let parse = |x: &str| x.trim().parse::<u32>().map_err(|e| format!("{x:?}: {e}"));
    let (w, h) = (parse(w)?, parse(h)?);
    // The render's own limits, checked here so that a bad size is a usage error (exit 2).
    use crate::render::{MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE};
    if w == 0 || h == 0 {
        return Err(format!(
            "the image must be at least 1×1 pixels, got {w}×{h}"
        ));
    }
    if w > MAX_IMAGE_SIDE || h > MAX_IMAGE_SIDE || u64::from(w) * u64::from(h) > MAX_IMAGE_PIXELS {
        return Err(format!(
            "the image {w}×{h} is too large (at most {MAX_IMAGE_SIDE} pixels a side and \
             {MAX_IMAGE_PIXELS} pixels)"
        ));
    }
    Ok((w, h))
}

/// Parses a corner angle: degrees from 0 (every turn is a corner) to 180 (none is).
fn parse_corner_angle(text: &str) -> Result<f64, String> {
    let angle: f64 = text.trim().parse().map_err(|e| format!("{text:?}: {e}"))?;
    if (0.0..=180.0).contains(&angle) {
        Ok(angle)
    } else {
        Err(format!(
            "the corner angle is in degrees from 0 to 180, got {angle}"
        ))
    }
}

impl FitSettings {
    fn options(&self) -> PipelineOptions {
        let mut options = PipelineOptions {
            tolerance: self.tolerance,
            corner_angle: self.corner_angle,
            keep_hooks: self.keep_hooks,
            close: self.close == crate::closure::Close::Auto,
            ..PipelineOptions::default()
        };
        options.chain.continuity = self.continuity;
        if let Some(alpha) = self.alpha {
            options.chain.alpha = AlphaChoice::Fixed(alpha);
        } else if let Some((min, max)) = self.alpha_range {
            options.chain.alpha = AlphaChoice::Range { min, max };
        }
        options
    }
}

/// `kansei fit`.
#[derive(Debug, Args)]
pub struct FitArgs {
    /// Strokes to fit, each file read by its extension: hid-recorder `.hid`, W3C InkML
    /// `.inkml`, evemu `.events`/`.evemu`, Quick Draw `.ndjson`, and `kansei-stroke` JSON
    /// (anything else).
    #[arg(required = true)]
    pub inputs: Vec<PathBuf>,
    /// Threads fitting the strokes of all inputs [default: every core].
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Write kansei-curve JSON here instead of stdout. With several inputs, or naming a
    /// directory that exists, a directory that receives `<input stem>.curve.json` for each.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Also write an SVG: one path per stroke, lines and arcs exact, spirals as cubic
    /// Béziers within --export-accuracy. With several inputs, or naming a directory that
    /// exists, a directory that receives `<input stem>.svg` for each.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Extra SVG layers, comma-separated: samples, bspline, alpha (segments coloured by α),
    /// splits.
    #[arg(long, value_delimiter = ',', value_parser = SvgLayers::NAMES)]
    pub svg_layers: Vec<String>,
    /// Also write a DXF: one degree-3 SPLINE per fitted piece, within --export-accuracy. With
    /// several inputs, or naming a directory that exists, a directory that receives
    /// `<input stem>.dxf` for each.
    #[arg(long)]
    pub dxf: Option<PathBuf>,
    /// Largest distance between the exported SVG/DXF curves and the exact LAC chain, in the
    /// file's units [default: a tenth of the tolerance].
    #[arg(long, alias = "svg-accuracy", allow_negative_numbers = true)]
    pub export_accuracy: Option<f64>,
    /// Also write a PNG (by default samples, B-spline, split markers, LAC segments coloured by
    /// α, LAC joints, legend, scale bar; see --png-layers), drawn by the `render` module. With several
    /// inputs, or naming a directory that exists, a directory that receives `<input stem>.png`
    /// for each.
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// The PNG's overlays, comma-separated, drawn instead of the default set (samples, bspline,
    /// splits, segments, joints, legend, scale-bar): any of samples, bspline, control-polygon,
    /// splits, segments, joints, comb, comb-log (the comb on a logarithmic scale), legend,
    /// scale-bar.
    #[arg(long, value_delimiter = ',', value_parser = crate::render::OVERLAY_NAMES)]
    pub png_layers: Option<Vec<String>>,
    /// Size of the PNG, WIDTHxHEIGHT pixels.
    #[arg(long, value_parser = parse_size, default_value = "1600x1000")]
    pub size: (u32, u32),
    /// Include each segment's logarithmic curvature graphs (LAC and B-spline) in the JSON.
    #[arg(long)]
    pub lcg: bool,
    /// Fitting settings.
    #[command(flatten)]
    pub settings: FitSettings,
}

/// `kansei bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// kansei-stroke JSON files (default: every file in fixtures/strokes, of the working
    /// directory or else of the checkout kansei was built from).
    pub inputs: Vec<PathBuf>,
    /// Tolerances to measure, in each file's units (repeat the flag) [default: the unit's
    /// default and twice it].
    #[arg(long = "tolerance", allow_negative_numbers = true)]
    pub tolerances: Vec<f64>,
    /// Timed repetitions per stroke; the median is reported.
    #[arg(long, default_value_t = 15)]
    pub repeat: usize,
}

/// A command's failure, naming the file it concerns.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A file could not be read (strokes, recordings) or written (outputs); see
    /// [`crate::io`].
    #[error(transparent)]
    File(#[from] crate::io::FileError),
    /// The pipeline failed.
    #[error("{path}: {source}")]
    Pipeline {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: crate::pipeline::PipelineError,
    },
    /// A recording could not be read.
    #[error("{path}: {message}")]
    Capture {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// An export could not be produced.
    #[error("{path}: {message}")]
    Export {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// An image could not be drawn.
    #[error("{path}: {source}")]
    Render {
        /// The image file.
        path: PathBuf,
        /// The cause.
        source: crate::render::RenderError,
    },
    /// Bad arguments.
    #[error("{0}")]
    Usage(String),
    /// Some inputs could not be read (each was reported as it was met); the others were
    /// fitted and written.
    #[error("{unreadable} of {inputs} inputs could not be read (each named above)")]
    Unreadable {
        /// Inputs that could not be read.
        unreadable: usize,
        /// Inputs given.
        inputs: usize,
    },
    /// Some strokes could not be fitted; everything else was written, with an error record
    /// for each of those strokes.
    #[error(
        "{failed} of {strokes} strokes could not be fitted (their error records are in the output)"
    )]
    StrokesFailed {
        /// Strokes without a fit.
        failed: usize,
        /// Strokes read.
        strokes: usize,
    },
    /// The app could not run (no display, no OpenGL).
    #[cfg(feature = "app")]
    #[error("{0}")]
    App(#[from] crate::app::AppError),
}

/// Exit status of `kansei` when everything worked.
pub const EXIT_OK: u8 = 0;
/// Exit status when a file could not be read or written (or a device opened, the app started).
pub const EXIT_FILE: u8 = 1;
/// Exit status for a usage error: an option value kansei refuses, as for clap's own errors.
pub const EXIT_USAGE: u8 = 2;
/// Exit status when some strokes could not be fitted; everything else was written.
pub const EXIT_STROKES_FAILED: u8 = 3;

impl CliError {
    /// The process exit status for this error ([`EXIT_FILE`], [`EXIT_USAGE`] or
    /// [`EXIT_STROKES_FAILED`]).
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Usage(_) => EXIT_USAGE,
            CliError::StrokesFailed { .. } => EXIT_STROKES_FAILED,
            _ => EXIT_FILE,
        }
    }
}

/// Runs a parsed command line, writing results to `out`.
pub fn run(cli: Cli, out: &mut dyn std::io::Write) -> Result<(), CliError> {
    match cli.command {
        Command::Fit(args) => fit(&args, out),
        Command::Bench(args) => bench(&args, out),
        Command::Replay(args) => {
            let file = read_strokes(&args.input)?;
            write_atomic(&args.out, file.to_json().as_bytes())?;
            let samples: usize = file.strokes.iter().map(|s| s.samples.len()).sum();
            writeln!(
                out,
                "{}: {} strokes, {samples} samples ({}) -> {}",
                args.input.display(),
                file.strokes.len(),
                file.units.name(),
                args.out.display()
            )
            .map_err(|source| CliError::Io {
                path: "<stdout>".into(),
                source,
            })
        }
        Command::Devices => devices(out),
        Command::Capture(args) => capture(&args, out),
        #[cfg(feature = "app")]
        Command::App(args) => {
            let tablet = match (args.tablet, args.tablet_replay) {
                (_, Some(path)) => {
                    if !(args.tablet_speed.is_finite() && args.tablet_speed > 0.0) {
                        return Err(CliError::Usage(format!(
                            "--tablet-speed must be a positive number, got {}",
                            args.tablet_speed
                        )));
                    }
                    Some(crate::app::tablet::TabletChoice::Recording {
                        path,
                        speed: args.tablet_speed,
                    })
                }
                (Some(device), None) => Some(crate::app::tablet::TabletChoice::Live(
                    Some(device).filter(|d| !d.is_empty()),
                )),
                (None, None) => None,
            };
            crate::app::run(crate::app::AppOptions {
                open: args.file,
                recovery: args
                    .recovery
                    .or_else(crate::app::files::default_recovery_path),
                replay: args.replay,
                tablet,
            })?;
            Ok(())
        }
        #[cfg(feature = "serve")]
        Command::Serve(args) => {
            let addr = args.addr;
            crate::serve::run(args.options().map_err(CliError::Usage)?).map_err(|e| match e {
                crate::serve::ServeError::Options(message) => CliError::Usage(message),
                crate::serve::ServeError::Bind { source, .. }
                | crate::serve::ServeError::Io(source) => CliError::Io {
                    path: addr.to_string().into(),
                    source,
                },
            })
        }
    }
}

fn stdout_error(source: std::io::Error) -> CliError {
    CliError::Io {
        path: "<stdout>".into(),
        source,
    }
}

/// `kansei devices`: every tablet, or a sentence saying there is none (not an error).
#[cfg(feature = "live")]
fn devices(out: &mut dyn std::io::Write) -> Result<(), CliError> {
    use crate::capture::{live_evdev, live_hid};
    let hid = live_hid::list();
    let evdev = live_evdev::list();
    if hid.is_empty() && evdev.is_empty() {
        writeln!(
            out,
            "no pen tablets found (looked for HID digitizers in /dev/hidraw* and evdev devices \
             with ABS_X, ABS_Y and BTN_TOOL_PEN in /dev/input)"
        )
        .map_err(stdout_error)?;
        return Ok(());
    }
    let mut denied = None;
    let rows = (hid.iter().map(|t| (&t.info, &t.access)))
        .chain(evdev.iter().map(|t| (&t.info, &t.access)));
    for (info, access) in rows {
        writeln!(out, "{}", info.summary()).map_err(stdout_error)?;
        if let Err(reason) = access {
            writeln!(out, "    {reason}").map_err(stdout_error)?;
            denied = Some(info.vendor_id);
        }
    }
    if let Some(vendor) = denied {
        writeln!(out, "{}", crate::capture::source::udev_help(vendor)).map_err(stdout_error)?;
    }
    Ok(())
}

/// `kansei devices` without the `live` feature.
#[cfg(not(feature = "live"))]
fn devices(out: &mut dyn std::io::Write) -> Result<(), CliError> {
    writeln!(
        out,
        "no pen tablets found: kansei was built without the `live` feature (no device access)"
    )
    .map_err(stdout_error)
}

/// Opens the tablet `--device` names, or the first one found.
#[cfg(feature = "live")]
fn open_live(device: Option<&str>) -> Result<Box<dyn crate::capture::source::PenSource>, CliError> {
    crate::capture::open::open_live(device).map_err(|e| CliError::Capture {
        path: device.unwrap_or("tablet").into(),
        message: e.to_string(),
    })
}

/// Without the `live` feature there is no device to open.
#[cfg(not(feature = "live"))]
fn open_live(
    _device: Option<&str>,
) -> Result<Box<dyn crate::capture::source::PenSource>, CliError> {
    Err(CliError::Usage(
        "kansei was built without the `live` feature: no tablet access".into(),
    ))
}

/// Set by the Ctrl-C/SIGTERM/SIGHUP handler; the capture loop polls it at least every 0.1 s.
static STOP: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// `kansei capture`.
fn capture(args: &CaptureArgs, out: &mut dyn std::io::Write) -> Result<(), CliError> {
    use crate::capture::session::{CaptureLimits, EndReason, run_capture};
    use crate::capture::source::RecordingSource;
    use crate::capture::writer::{RawWriter, StrokeWriter};
    if let Some(d) = args.duration
        && !(d.is_finite() && d > 0.0)
    {
        return Err(CliError::Usage(format!(
            "--duration must be a positive number of seconds, got {d}"
        )));
    }
    let mut source: Box<dyn crate::capture::source::PenSource> = match &args.from_recording {
        Some(path) => {
            let text = std::fs::read_to_string(path).map_err(|source| CliError::Io {
                path: path.clone(),
                source,
            })?;
            let capture_error = |message: String| CliError::Capture {
                path: path.clone(),
                message,
            };
            let recording = crate::capture::recorder::Recording::parse(&text)
                .map_err(|e| capture_error(e.to_string()))?;
            let mut s = RecordingSource::new(recording, &path.display().to_string())
                .map_err(|e| capture_error(e.to_string()))?;
            if let Some(n) = args.fail_after_reports {
                s = s.fail_after(n);
            }
            match args.pace {
                Some(speed) => Box::new(
                    crate::capture::paced::Paced::new(s, speed)
                        .map_err(|e| capture_error(e.to_string()))?,
                ),
                None => Box::new(s),
            }
        }
        None => open_live(args.device.as_deref())?,
    };
    let info = source.info().clone();
    let write_error = |e: crate::capture::writer::WriteError| match e {
        crate::capture::writer::WriteError::File(e) => CliError::File(e),
        e => CliError::Capture {
            path: args.out.clone(),
            message: e.to_string(),
        },
    };
    let label = format!(
        "kansei capture ({}): {}",
        info.interface.name(),
        info.name.as_deref().unwrap_or("unnamed device")
    );
    let mut writer = StrokeWriter::create(&args.out, &info, &label).map_err(write_error)?;
    let mut raw = match (&args.raw, source.descriptor()) {
        (None, _) => None,
        (Some(path), Some(descriptor)) => Some(
            RawWriter::create(path, descriptor, &info).map_err(|e| CliError::Capture {
                path: path.clone(),
                message: e.to_string(),
            })?,
        ),
        (Some(_), None) => {
            return Err(CliError::Usage(
                "--raw records HID reports: the tablet was opened through evdev, which has none"
                    .into(),
            ));
        }
    };
    install_ctrlc();
    writeln!(
        out,
        "capturing from {} -> {} (Ctrl-C to stop)",
        info.summary(),
        args.out.display()
    )
    .map_err(stdout_error)?;
    let limits = CaptureLimits {
        duration: args.duration,
    };
    let summary = run_capture(
        source.as_mut(),
        &mut writer,
        raw.as_mut(),
        &STOP,
        limits,
        |i, stroke| {
            eprintln!("stroke {}: {} samples", i + 1, stroke.samples.len());
        },
    )
    .map_err(write_error)?;
    writeln!(
        out,
        "{} strokes{} from {} reports -> {}",
        summary.strokes,
        if summary.partial_saved {
            " (the last one interrupted)"
        } else {
            ""
        },
        summary.reports,
        args.out.display()
    )
    .map_err(stdout_error)?;
    if summary.decode_errors > 0 {
        eprintln!("warning: {} reports did not decode", summary.decode_errors);
    }
    match summary.end {
        EndReason::SourceError(e) => Err(CliError::Capture {
            path: info.node.unwrap_or_default().into(),
            message: format!(
                "{e}; the strokes so far are saved in {}",
                args.out.display()
            ),
        }),
        _ => Ok(()),
    }
}

/// Ctrl-C (SIGINT), SIGTERM and SIGHUP set [`STOP`] (the `ctrlc` crate with its `termination`
/// feature): the capture then writes the stroke in progress and exits normally.
#[cfg(feature = "live")]
fn install_ctrlc() {
    if let Err(e) = ctrlc::set_handler(|| STOP.store(true, std::sync::atomic::Ordering::Relaxed)) {
        eprintln!(
            "warning: no Ctrl-C/SIGTERM handler ({e}): a signal will lose the stroke in progress"
        );
    }
}

/// Without the `live` feature there is no Ctrl-C handler: Ctrl-C ends the process, and only
/// the stroke in progress is lost (finished strokes are already on disk).
#[cfg(not(feature = "live"))]
fn install_ctrlc() {}

fn fit(args: &FitArgs, out: &mut dyn std::io::Write) -> Result<(), CliError> {
    let options = args.settings.options();
    if let Some(t) = options.tolerance
        && !(t.is_finite() && t > 0.0)
    {
        return Err(CliError::Usage(format!(
            "--tolerance must be a positive number, got {t}"
        )));
    }
    if let Some(alpha) = args.settings.alpha
        && !alpha.is_finite()
    {
        return Err(CliError::Usage(format!(
            "--alpha must be a finite number, got {alpha}"
        )));
    }
    if let Some(a) = args.export_accuracy
        && !(a.is_finite() && a > 0.0)
    {
        return Err(CliError::Usage(format!(
            "--export-accuracy must be a positive number, got {a}"
        )));
    }
    let several = args.inputs.len() > 1;
    // An output naming a directory that exists receives `<stem>.<extension>` there, with one
    // input as with several.
    let target = |input: &Path, path: &PathBuf, extension: &str| -> PathBuf {
        if several || path.is_dir() {
            let stem = input
                .file_stem()
                .map(|s| s.to_string_lossy())
                .unwrap_or_default();
            path.join(format!("{stem}.{extension}"))
        } else {
            path.clone()
        }
    };
    if args.jobs == Some(0) {
        return Err(CliError::Usage("--jobs must be at least 1".into()));
    }
    // No output may replace an input, nor another output: refused before anything is written.
    let mut planned: Vec<(PathBuf, &Path, Format)> = Vec::new();
    for input in &args.inputs {
        let outputs = [
            (&args.json, Format::Json),
            (&args.svg, Format::Svg),
            (&args.dxf, Format::Dxf),
            (&args.png, Format::Png),
        ];
        for (path, format) in outputs {
            let Some(path) = path else { continue };
            let path = target(input, path, format.extension());
            if let Some(replaced) = args.inputs.iter().find(|i| crate::io::same_file(i, &path)) {
                return Err(CliError::Usage(format!(
                    "{} would replace the input {}: choose another output path",
                    path.display(),
                    replaced.display()
                )));
            }
            if let Some((_, other, was)) = planned
                .iter()
                .find(|(p, _, _)| crate::io::same_file(p, &path))
            {
                return Err(CliError::Usage(format!(
                    "the {} of {} and the {} of {} would both be written to {}: give the \
                     outputs distinct paths (inputs of the same name in one run: separate runs)",
                    was.extension(),
                    other.display(),
                    format.extension(),
                    input.display(),
                    path.display()
                )));
            }
            planned.push((path, input, format));
        }
    }
    // Every output's directory is checked (with several inputs, made) before anything is
    // written: a mistyped directory leaves no other output behind.
    for dir in [&args.json, &args.svg, &args.dxf, &args.png]
        .into_iter()
        .flatten()
    {
        if several {
            crate::io::create_output_dir(dir)?;
        } else {
            crate::io::check_output(dir)?;
        }
    }
    // Every input is read first; one that cannot be read is reported and the others are still
    // fitted and written (the run then exits 1, counting them: each is named once).
    let mut unreadable = 0;
    let mut read = Vec::new();
    for input in &args.inputs {
        match read_strokes(input) {
            Ok(file) => read.push((input, file)),
            Err(e) => {
                eprintln!("error: {e}");
                unreadable += 1;
            }
        }
    }
    // All strokes of all files share one queue over every core (or --jobs threads).
    let threads = args.jobs.unwrap_or_else(|| {
        std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
    });
    let files: Vec<&StrokeFile> = read.iter().map(|(_, f)| f).collect();
    let outputs = fit_files(&files, &options, threads, &progress_reporter()).map_err(|source| {
        CliError::Pipeline {
            path: args.inputs.first().cloned().unwrap_or_default(),
            source,
        }
    })?;
    let formats = FormatOptions {
        json: ExportOptions { lcg: args.lcg },
        json_layout: JsonLayout::Pretty,
        accuracy: args.export_accuracy,
        svg_layers: SvgLayers::named(&args.svg_layers),
        png: PngOptions::default()
            .with_size(args.size)
            .with_render(RenderOptions::with_overlays(
                args.png_layers
                    .as_deref()
                    .map_or_else(Overlays::default, Overlays::named),
            )),
    };
    let (mut failed, mut strokes) = (0, 0);
    for ((input, file), output) in read.iter().zip(outputs) {
        let (input, file) = (*input, file);
        for f in &output.failures {
            eprintln!("error: {}: {}", input.display(), f.message);
        }
        failed += output.failures.len();
        strokes += file.strokes.len();
        warn_below_noise_floor(input, &output);
        for c in &output.curves {
            let lac = c
                .chain
                .as_ref()
                .map(|ch| (ch.within_tolerance, ch.max_deviation));
            for (what, ok, deviation) in [
                (
                    "B-spline",
                    c.bspline.within_tolerance,
                    c.bspline.max_deviation,
                ),
                (
                    "LAC chain",
                    lac.is_none_or(|l| l.0),
                    lac.map_or(0.0, |l| l.1),
                ),
            ] {
                if !ok {
                    eprintln!(
                        "warning: {}: stroke {}, samples {}..={}: {what} deviates {deviation:.4e} > tolerance {:e}",
                        input.display(),
                        c.stroke,
                        c.samples.0,
                        c.samples.1,
                        c.tolerance
                    );
                }
            }
        }
        for (format, path) in [
            (Format::Svg, &args.svg),
            (Format::Dxf, &args.dxf),
            (Format::Png, &args.png),
        ] {
            if let Some(path) = path {
                let path = target(input, path, format.extension());
                let bytes = export(format, file, &output, &formats, &path)?;
                write_atomic(&path, &bytes)?;
            }
        }
        match &args.json {
            None => {
                // Several documents on stdout: one a line.
                let layout = if several {
                    JsonLayout::Compact
                } else {
                    JsonLayout::Pretty
                };
                let options = FormatOptions {
                    json_layout: layout,
                    ..formats
                };
                let stdout = Path::new("<stdout>");
                let bytes = export(Format::Json, file, &output, &options, stdout)?;
                out.write_all(&bytes)
                    .and_then(|()| out.write_all(b"\n"))
                    .map_err(|source| CliError::Io {
                        path: stdout.into(),
                        source,
                    })?;
            }
            Some(path) => {
                let path = target(input, path, Format::Json.extension());
                let bytes = export(Format::Json, file, &output, &formats, &path)?;
                write_atomic(&path, &bytes)?;
            }
        }
    }
    if unreadable > 0 {
        return Err(CliError::Unreadable {
            unreadable,
            inputs: args.inputs.len(),
        });
    }
    if failed > 0 {
        return Err(CliError::StrokesFailed { failed, strokes });
    }
    Ok(())
}

/// Strokes a batch must have before its progress is shown.
const PROGRESS_MIN_STROKES: usize = 200;

/// `fit`'s progress on stderr, `fitted N/M strokes` on one line rewritten about every percent, when
/// stderr is a terminal and the batch is long; nothing otherwise.
fn progress_reporter() -> impl Fn(usize, usize) + Sync {
    use std::io::IsTerminal;
    let terminal = std::io::stderr().is_terminal();
    move |done: usize, total: usize| {
        if !terminal || total < PROGRESS_MIN_STROKES {
            return;
        }
        if done.is_multiple_of((total / 100).max(1)) || done == total {
            let end = if done == total { "\n" } else { "" };
            eprint!("\rfitted {done}/{total} strokes{end}");
        }
    }
}

/// The bytes of `output` in `format` for the file `path` (named in errors and warnings). Says on
/// stderr when an SVG's or DXF's measured error exceeds the accuracy asked for (a segment
/// beyond the exporter's work bounds; see [`crate::export::segment_beziers`]): the file is still
/// written, and states each segment's error.
fn export(
    format: Format,
    file: &StrokeFile,
    output: &FitOutput,
    options: &FormatOptions,
    path: &Path,
) -> Result<Vec<u8>, CliError> {
    let exported = format.export(file, output, options).map_err(|e| match e {
        FormatError::Render(source) => CliError::Render {
            path: path.to_owned(),
            source,
        },
        other => CliError::Export {
            path: path.to_owned(),
            message: other.to_string(),
        },
    })?;
    if let Some(beyond) = exported.beyond_accuracy() {
        eprintln!(
            "warning: {}: largest export error {:.4e} exceeds the accuracy {:.4e}",
            path.display(),
            beyond.max_error,
            beyond.accuracy
        );
    }
    Ok(exported.bytes)
}

/// A benchmark row's label and how it derives the tolerance from a file's unit default.
type ToleranceSetting = (String, Box<dyn Fn(f64) -> f64>);

/// Per-configuration figures gathered by `bench`.
#[derive(Default)]
struct BenchTally {
    per_stroke: Vec<f64>,
    per_sample: Vec<f64>,
    segments: usize,
    spans: usize,
}

impl BenchTally {
    fn median(v: &mut [f64]) -> f64 {
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(0.0)
    }
}

fn bench(args: &BenchArgs, out: &mut dyn std::io::Write) -> Result<(), CliError> {
    if let Some(t) = args
        .tolerances
        .iter()
        .find(|t| !(t.is_finite() && **t > 0.0))
    {
        return Err(CliError::Usage(format!(
            "--tolerance must be a positive number, got {t}"
        )));
    }
    let inputs = if args.inputs.is_empty() {
        // The working directory's fixtures (a checkout's root), else those of the checkout the
        // binary was built from.
        let local = Path::new("fixtures/strokes");
        let dir = if local.is_dir() {
            local.to_owned()
        } else {
            Path::new(env!("CARGO_MANIFEST_DIR")).join(local)
        };
        let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
            .map_err(|source| CliError::Io {
                path: dir.clone(),
                source,
            })?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|e| e == "json"))
            .collect();
        v.sort();
        v
    } else {
        args.inputs.clone()
    };
    let files: Vec<(PathBuf, StrokeFile)> = inputs
        .iter()
        .map(|p| read_strokes(p).map(|f| (p.clone(), f)))
        .collect::<Result<_, _>>()?;
    let repeat = args.repeat.max(1);
    let io = |source| CliError::Io {
        path: "<stdout>".into(),
        source,
    };
    writeln!(
        out,
        "kansei bench: prepare + B-spline + split per stroke, median of {repeat} runs; peer = the \
         seed's method (segments added one by one, no fairing), timed in the same run"
    )
    .map_err(io)?;
    writeln!(
        out,
        "{:>11} {:>7} {:>7} | {:>11} {:>10} {:>8} {:>8} | {:>11} {:>8} {:>8} | {:>10}",
        "tolerance",
        "strokes",
        "samples",
        "µs/stroke",
        "ns/sample",
        "seg/strk",
        "spn/strk",
        "peer µs/st",
        "seg/strk",
        "spn/strk",
        "peer/ours"
    )
    .map_err(io)?;
    let settings: Vec<ToleranceSetting> = if args.tolerances.is_empty() {
        vec![
            ("1×default".to_owned(), Box::new(|base| base)),
            ("2×default".to_owned(), Box::new(|base| 2.0 * base)),
        ]
    } else {
        args.tolerances
            .iter()
            .map(|&t| {
                (
                    format!("{t}"),
                    Box::new(move |_| t) as Box<dyn Fn(f64) -> f64>,
                )
            })
            .collect()
    };
    for (label, tolerance_of) in settings {
        let (mut ours, mut peer) = (BenchTally::default(), BenchTally::default());
        let (mut strokes, mut samples) = (0usize, 0usize);
        let mut ratios = Vec::new();
        for (path, file) in &files {
            let tolerance = tolerance_of(file.units.default_tolerance());
            // The B-spline and split stages only (as the header says); the LAC stage is timed
            // by `cargo bench --bench lac`.
            let configs = [
                PipelineOptions::splits_only().with_tolerance(tolerance),
                PipelineOptions::splits_only()
                    .with_tolerance(tolerance)
                    .seed_method(),
            ];
            for (i, stroke) in file.strokes.iter().enumerate() {
                let mut medians = [0.0; 2];
                for (c, (options, tally)) in configs.iter().zip([&mut ours, &mut peer]).enumerate()
                {
                    let mut times = Vec::with_capacity(repeat);
                    let mut fits = Vec::new();
                    for _ in 0..repeat {
                        let start = Instant::now();
                        let r = crate::pipeline::fit_stroke(stroke, i, tolerance, options);
                        times.push(start.elapsed().as_secs_f64());
                        fits = r.map_err(|source| CliError::Pipeline {
                            path: path.clone(),
                            source,
                        })?;
                    }
                    let median = BenchTally::median(&mut times);
                    medians[c] = median;
                    tally.per_stroke.push(median);
                    tally
                        .per_sample
                        .push(median / stroke.samples.len().max(1) as f64);
                    tally.segments += fits
                        .iter()
                        .map(|f| f.bspline.curve.segment_count())
                        .sum::<usize>();
                    tally.spans += fits.iter().map(|f| f.spans.spans.len()).sum::<usize>();
                }
                ratios.push(medians[1] / medians[0]);
                strokes += 1;
                samples += stroke.samples.len();
            }
        }
        let per = |n: usize| n as f64 / strokes.max(1) as f64;
        writeln!(
            out,
            "{:>11} {:>7} {:>7} | {:>11.1} {:>10.0} {:>8.2} {:>8.2} | {:>11.1} {:>8.2} {:>8.2} | {:>10.2}",
            label,
            strokes,
            samples,
            BenchTally::median(&mut ours.per_stroke) * 1e6,
            BenchTally::median(&mut ours.per_sample) * 1e9,
            per(ours.segments),
            per(ours.spans),
            BenchTally::median(&mut peer.per_stroke) * 1e6,
            per(peer.segments),
            per(peer.spans),
            BenchTally::median(&mut ratios),
        )
        .map_err(io)?;
    }
    Ok(())
}

/// Warns once per file when a given tolerance lies below some strokes' noise floor: the fit
/// then follows the samples' noise (more segments, curvature that is the noise's).
fn warn_below_noise_floor(input: &std::path::Path, output: &crate::pipeline::FitOutput) {
    if let Some(below) = output.below_floor() {
        eprintln!(
            "warning: {}: {below}; without --tolerance each stroke is fitted to its floor",
            input.display()
        );
    }
}
