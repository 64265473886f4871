//! The sketch app (`kansei app`, feature `app`): draw with a pen, see the log-aesthetic chain
//! appear, study its curvature.
//!
//! ```text
//! document.rs  Document: strokes, their fit settings, undo/redo through Edit (no egui)
//! worker.rs    FitWorker: the pipeline on a background thread; Fits keyed by stroke revision
//! scene.rs     SceneData: the document and its fits as the renderer takes them; Selection
//! replay.rs    Replay: a drawing's strokes at their recorded speed
//! files.rs     open (any format the CLI reads), save, export, the recovery file
//! canvas.rs    Canvas: the render texture, pan/zoom, pointer → samples
//! chooser.rs   Chooser: the file chooser window (drawn by egui)
//! panels.rs    the side panels: fit settings, overlays, files, replay, the segment table
//! plots.rs     the selected segment's plots (egui_plot)
//! tablet.rs    TabletFeed: a live tablet (or a recording played as one) on its own thread
//! ```
//!
//! The UI emits [`Command`]s; [`KanseiApp::execute`] applies them. The document changes only
//! through [`Edit`]s, which keep the undo history; fits are computed off the UI
//! thread and drawn by the shared [`render`](crate::render) module.

pub mod canvas;
pub mod chooser;
pub mod document;
pub mod files;
pub mod panels;
pub mod plots;
pub mod replay;
pub mod scene;
pub mod tablet;
pub mod worker;

use std::path::{Path, PathBuf};

use eframe::egui;
use egui::{Key, KeyboardShortcut, Modifiers};

use crate::render::{Overlays, RenderOptions};
use canvas::Canvas;
use document::{Document, Edit, FitSettings, StrokeId};
use replay::Replay;
use scene::{SceneData, Selection};
use worker::{FitState, FitWorker, Fits};

/// Height of the plots under the canvas, points.
pub const PLOT_HEIGHT: f32 = 180.0;

/// Replay speed when the app starts (recorded speed).
pub const DEFAULT_REPLAY_SPEED: f64 = 1.0;

/// How the app starts.
#[derive(Clone, Debug, Default)]
pub struct AppOptions {
    /// A file to open.
    pub open: Option<PathBuf>,
    /// Where the recovery file lives (`None`: no autosave).
    pub recovery: Option<PathBuf>,
    /// Start replaying the opened file's strokes.
    pub replay: bool,
    /// Read a tablet (live, or a recording played as one).
    pub tablet: Option<tablet::TabletChoice>,
}

/// Everything the UI can ask for.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Change the document.
    Edit(Edit),
    /// Undo the last edit.
    Undo,
    /// Redo the last undone edit.
    Redo,
    /// Open a file, replacing the drawing (undoable).
    Open(PathBuf),
    /// Save the strokes as `kansei-stroke` at this path: over the drawing's own stroke file
    /// at once, over any other existing file only once the user confirms.
    Save(PathBuf),
    /// Export the fits to this path ([`files::export_path`] gives the file panel's): a new
    /// file at once, an existing one only once the user confirms, a stroke file never.
    Export(crate::export::Format, PathBuf),
    /// Replace the file the pending save or export asks about.
    ConfirmReplace,
    /// Leave the file the pending save or export asks about as it is.
    CancelReplace,
    /// Choose the file panel's path in a file chooser.
    Browse,
    /// Select a segment (or nothing).
    Select(Option<Selection>),
    /// Settings for the selected stroke (refit at once) or, with none selected, for new strokes.
    SetSettings(FitSettings),
    /// Fit the view to the drawing.
    FitView,
    /// Replay the strokes at their recorded speed.
    StartReplay,
    /// Stop the replay.
    StopReplay,
    /// Take the recovered drawing.
    Recover,
    /// Decline the recovered drawing (the recovery file is removed).
    DiscardRecovery,
}

/// A line of feedback under the canvas.
#[derive(Clone, Debug, PartialEq)]
pub struct Status {
    /// What to say.
    pub text: String,
    /// Whether it is an error.
    pub error: bool,
}

/// A save or export waiting for the user to confirm replacing an existing file.
#[derive(Clone, Debug, PartialEq)]
pub struct PendingReplace {
    /// The existing file.
    pub path: PathBuf,
    /// What would be written: `None` for the strokes (Save), else the export.
    pub export: Option<crate::export::Format>,
}

/// The state the panels edit that is not the document: what is shown and where files go.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewState {
    /// The overlays drawn.
    pub overlays: Overlays,
    /// The selected segment.
    pub selection: Option<Selection>,
    /// Settings for new strokes.
    pub new_stroke_settings: FitSettings,
    /// The path in the file panel: where Open reads and Save writes; exports go next to it
    /// with their own extensions ([`files::export_path`]).
    pub path: String,
    /// Replay speed factor.
    pub replay_speed: f64,
}

impl Default for ViewState {
    fn default() -> Self {
        ViewState {
            overlays: Overlays::default(),
            selection: None,
            new_stroke_settings: FitSettings::default(),
            path: String::new(),
            replay_speed: DEFAULT_REPLAY_SPEED,
        }
    }
}

/// The app: the document, its fits and the UI's state.
pub struct KanseiApp {
    doc: Document,
    fits: Fits,
    worker: Option<FitWorker>,
    /// What the panels edit.
    pub view: ViewState,
    canvas: Canvas,
    scene: SceneData,
    status: Option<Status>,
    recovery_path: Option<PathBuf>,
    recovered: Option<crate::stroke::StrokeFile>,
    /// The last change count written to the recovery file.
    autosaved: u64,
    /// The change count of the last save (nothing unsaved when equal to the document's).
    saved: u64,
    replay: Option<Replay>,
    tablet: Option<tablet::TabletFeed>,
    /// Fits the stroke being drawn while the pen moves (its own thread: never delays the fits
    /// of finished strokes).
    preview_worker: Option<FitWorker>,
    preview: Preview,
    /// The file chooser, while open.
    chooser: Option<chooser::Chooser>,
    /// The drawing's own `kansei-stroke` file (opened or last saved), which Save replaces
    /// without asking.
    file_path: Option<PathBuf>,
    /// The save or export asking whether to replace an existing file.
    pending_replace: Option<PendingReplace>,
    /// Tablet strokes waiting for a drawing whose units they can join (see
    /// [`KanseiApp::take_tablet_strokes`]).
    tablet_pending: Vec<crate::stroke::Stroke>,
    /// The selected segment's plot series, with the selection and scene key they were made for.
    plots: Option<(Selection, (u64, u64, u64), plots::SegmentPlots)>,
}

impl std::fmt::Debug for KanseiApp {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("KanseiApp")
            .field("strokes", &self.doc.strokes().len())
            .field("view", &self.view)
            .finish_non_exhaustive()
    }
}

impl KanseiApp {
    /// A new app; `ctx` is woken when a fit arrives.
    pub fn new(ctx: &egui::Context, options: AppOptions) -> Self {
        let wake_ctx = ctx.clone();
        let mut status = None;
        let worker = match FitWorker::spawn(Box::new(move || wake_ctx.request_repaint())) {
            Ok(worker) => Some(worker),
            Err(e) => {
                status = Some(Status {
                    text: format!("cannot start the fitting thread: {e}"),
                    error: true,
                });
                None
            }
        };
        let doc = Document::default();
        let fits = Fits::default();
        let scene = SceneData::build(&doc, &fits, None);
        let mut app = KanseiApp {
            doc,
            fits,
            worker,
            view: ViewState::default(),
            canvas: Canvas::default(),
            scene,
            status,
            recovery_path: options.recovery.clone(),
            recovered: None,
            autosaved: 0,
            saved: 0,
            replay: None,
            tablet: None,
            tablet_pending: Vec::new(),
            preview_worker: {
                let wake_ctx = ctx.clone();
                FitWorker::spawn(Box::new(move || wake_ctx.request_repaint())).ok()
            },
            preview: Preview::default(),
            chooser: None,
            file_path: None,
            pending_replace: None,
            plots: None,
        };
        if let Some(choice) = options.tablet {
            let wake_ctx = ctx.clone();
            app.tablet = Some(tablet::TabletFeed::start(
                choice,
                Box::new(move || wake_ctx.request_repaint()),
            ));
        }
        if let Some(path) = &options.recovery {
            match files::read_recovery(path) {
                Ok(file) => app.recovered = file,
                Err(e) => app.set_error(format!("recovery file unreadable: {e}")),
            }
        }
        if let Some(path) = options.open {
            app.view.path = path.display().to_string();
            app.execute(Command::Open(path));
            if options.replay {
                app.execute(Command::StartReplay);
            }
        }
        app
    }

    /// The document.
    pub fn document(&self) -> &Document {
        &self.doc
    }

    /// The fits.
    pub fn fits(&self) -> &Fits {
        &self.fits
    }

    /// The scene the canvas draws.
    pub fn scene(&self) -> &SceneData {
        &self.scene
    }

    /// The canvas (its last render, its view).
    pub fn canvas(&self) -> &Canvas {
        &self.canvas
    }

    /// The feedback line.
    pub fn status(&self) -> Option<&Status> {
        self.status.as_ref()
    }

    /// Whether a recovered drawing is on offer.
    pub fn recovery_offered(&self) -> bool {
        self.recovered.is_some()
    }

    /// Whether every stroke's fit is back.
    pub fn fits_settled(&self) -> bool {
        !self.fits.any_pending(&self.doc)
    }

    /// The options the canvas renders with.
    pub fn render_options(&self) -> RenderOptions {
        RenderOptions {
            highlight: self.scene.highlight(self.view.selection),
            ..RenderOptions::with_overlays(self.view.overlays)
        }
    }

    fn set_error(&mut self, text: String) {
        self.status = Some(Status { text, error: true });
    }

    fn set_info(&mut self, text: String) {
        self.status = Some(Status { text, error: false });
    }

    /// The settings of a stroke drawn now: those for new strokes, with the zoom it is drawn at
    /// (its screen tolerance preset is in screen pixels at that zoom).
    fn drawn_settings(&self) -> FitSettings {
        FitSettings {
            pixels_per_unit: self.canvas.view().map(|v| v.pixels_per_unit),
            ..self.view.new_stroke_settings
        }
    }

    /// The settings the panel shows: the selected stroke's, else those for new strokes.
    pub fn current_settings(&self) -> FitSettings {
        self.selected_stroke()
            .and_then(|id| self.doc.find(id))
            .map_or(self.view.new_stroke_settings, |(_, s)| s.settings)
    }

    fn selected_stroke(&self) -> Option<StrokeId> {
        self.view.selection.map(|s| s.stroke)
    }

    /// Applies one command.
    pub fn execute(&mut self, command: Command) {
        match command {
            Command::Edit(edit) => {
                if let Err(e) = self.doc.apply(edit) {
                    self.set_error(e.to_string());
                }
            }
            Command::Undo => {
                self.doc.undo();
            }
            Command::Redo => {
                self.doc.redo();
            }
            Command::Open(path) => self.open(&path),
            Command::Save(path) => {
                let own = self
                    .file_path
                    .as_deref()
                    .is_some_and(|own| same_file(own, &path));
                let overwrite = if own {
                    files::Overwrite::Allowed
                } else {
                    files::Overwrite::Never
                };
                self.save(path, overwrite);
            }
            Command::Export(format, path) => self.export(format, path, files::Overwrite::Never),
            Command::ConfirmReplace => match self.pending_replace.take() {
                Some(PendingReplace { path, export: None }) => {
                    self.save(path, files::Overwrite::Allowed);
                }
                Some(PendingReplace {
                    path,
                    export: Some(format),
                }) => self.export(format, path, files::Overwrite::Allowed),
                None => {}
            },
            Command::CancelReplace => {
                if let Some(pending) = self.pending_replace.take() {
                    self.set_info(format!("left {} as it was", pending.path.display()));
                }
            }
            Command::Select(selection) => self.view.selection = selection,
            Command::Browse => {
                // Start where the path field points: its folder and file name.
                self.chooser = Some(chooser::Chooser::new(Path::new(self.view.path.trim())));
            }
            Command::SetSettings(settings) => match self.selected_stroke() {
                Some(id) => {
                    if let Err(e) = self.doc.apply(Edit::SetSettings { id, settings }) {
                        self.set_error(e.to_string());
                    }
                }
                None => self.view.new_stroke_settings = settings,
            },
            Command::FitView => self.canvas.request_fit(),
            Command::StartReplay => {
                self.replay = Some(Replay::new(&self.scene_strokes()));
            }
            Command::StopReplay => self.replay = None,
            Command::Recover => {
                if let Some(file) = self.recovered.take() {
                    let edit = self.doc.replace_with(file, self.view.new_stroke_settings);
                    self.execute(Command::Edit(edit));
                    self.canvas.request_fit();
                    self.set_info("recovered the previous drawing".into());
                }
            }
            Command::DiscardRecovery => {
                self.recovered = None;
                if let Some(path) = self.recovery_path.clone()
                    && let Err(e) = files::discard_recovery(&path)
                {
                    self.set_error(e.to_string());
                }
            }
        }
        self.after_change();
    }

    fn scene_strokes(&self) -> Vec<crate::stroke::Stroke> {
        self.doc
            .strokes()
            .iter()
            .map(|s| s.stroke.clone())
            .collect()
    }

    /// The fits for export. The file's tolerance is the smallest any stroke was fitted to (so
    /// that export accuracies derived from it suit every stroke); a stroke fitted to another
    /// carries its own in the curve JSON. With no fits, the new-stroke setting.
    fn output(&self) -> crate::pipeline::FitOutput {
        // Rebuilt without a replay cut: exports hold every finished fit.
        let scene = SceneData::build(&self.doc, &self.fits, None);
        let tolerance = scene
            .curves
            .iter()
            .map(|c| c.tolerance)
            .min_by(f64::total_cmp)
            .unwrap_or_else(|| {
                self.view
                    .new_stroke_settings
                    .tolerance
                    .unwrap_or(self.doc.units().default_tolerance())
            });
        scene.output(tolerance)
    }

    /// The save or export asking whether to replace an existing file, if any.
    pub fn pending_replace(&self) -> Option<&PendingReplace> {
        self.pending_replace.as_ref()
    }

    /// Saves the strokes; an existing file that may not be replaced becomes a question.
    fn save(&mut self, path: PathBuf, overwrite: files::Overwrite) {
        match files::save(&path, &self.doc.to_file(), overwrite) {
            Ok(()) => {
                self.saved = self.doc.changes();
                self.set_info(format!("saved {}", path.display()));
                self.file_path = Some(path);
            }
            Err(crate::io::FileError::Exists { .. }) => {
                self.ask_replace(PendingReplace { path, export: None });
            }
            Err(e) => self.set_error(e.to_string()),
        }
    }

    /// Exports; an existing file that may not be replaced becomes a question, and the drawing's
    /// own stroke file is never the target.
    fn export(
        &mut self,
        format: crate::export::Format,
        path: PathBuf,
        overwrite: files::Overwrite,
    ) {
        if self
            .file_path
            .as_deref()
            .is_some_and(|own| same_file(own, &path))
        {
            self.set_error(format!(
                "{}: is the drawing's stroke file: an export never replaces it",
                path.display()
            ));
            return;
        }
        let result = files::export(
            &path,
            format,
            &self.doc.to_file(),
            &self.output(),
            &RenderOptions::with_overlays(self.view.overlays),
            overwrite,
        );
        match result {
            Ok(()) => self.set_info(format!("wrote {}", path.display())),
            Err(e) if e.is_exists() => self.ask_replace(PendingReplace {
                path,
                export: Some(format),
            }),
            Err(e) => self.set_error(e.to_string()),
        }
    }

    fn ask_replace(&mut self, pending: PendingReplace) {
        self.set_info(format!("{} exists: replace it?", pending.path.display()));
        self.pending_replace = Some(pending);
    }

    /// Opens a file; on failure the drawing is untouched and the status says why.
    fn open(&mut self, path: &Path) {
        match files::open(path) {
            Ok(file) => {
                let n = file.strokes.len();
                let edit = self.doc.replace_with(file, self.view.new_stroke_settings);
                match self.doc.apply(edit) {
                    Ok(_) => {
                        self.view.selection = None;
                        self.replay = None;
                        self.saved = self.doc.changes();
                        // A kansei-stroke file is the drawing's own: Save replaces it. A
                        // recording is not: saving over it asks first.
                        self.file_path =
                            (!crate::io::is_recording(path)).then(|| path.to_path_buf());
                        self.canvas.request_fit();
                        self.set_info(format!("opened {} ({n} strokes)", path.display()));
                    }
                    Err(e) => self.set_error(format!("{}: {e}", path.display())),
                }
            }
            Err(e) => self.set_error(format!("cannot open: {e}")),
        }
    }

    /// After any command or fit: queue missing fits, autosave, drop a selection that is gone,
    /// rebuild the scene if its inputs changed.
    fn after_change(&mut self) {
        let jobs = self.fits.missing(&self.doc);
        match &self.worker {
            Some(worker) => jobs.into_iter().for_each(|job| worker.send(job)),
            // No thread could be started: fit here (the UI waits, but still works).
            None => {
                for job in jobs {
                    let result = job.run();
                    self.fits.accept(result, &self.doc);
                }
            }
        }
        // While a recovered drawing is on offer its file is left alone; the drawing is written
        // once the offer is taken or declined.
        if self.doc.changes() != self.autosaved && self.recovered.is_none() {
            self.autosaved = self.doc.changes();
            if let Some(path) = &self.recovery_path
                && let Err(e) = files::write_recovery(path, &self.doc.to_file())
            {
                self.set_error(format!("autosave failed: {e}"));
            }
        }
        if self.view.selection.is_some() && self.scene.highlight(self.view.selection).is_none() {
            // Keep a selection whose stroke is still being refitted; drop one that is gone.
            let alive = self
                .selected_stroke()
                .is_some_and(|id| self.doc.find(id).is_some());
            if !alive {
                self.view.selection = None;
            }
        }
        if SceneData::key_of(&self.doc, &self.fits, self.replay.as_ref()) != self.scene.key {
            self.scene = SceneData::build(&self.doc, &self.fits, self.replay.as_ref());
        }
        self.update_plots();
    }

    /// Recomputes the plot series when the selection or the scene has changed.
    fn update_plots(&mut self) {
        let wanted = self.view.selection.map(|s| (s, self.scene.key));
        let have = self.plots.as_ref().map(|(s, key, _)| (*s, *key));
        if wanted == have {
            return;
        }
        self.plots = self.view.selection.and_then(|selection| {
            let (fit, segment) = self.scene.selected(Some(selection))?;
            Some((
                selection,
                self.scene.key,
                plots::SegmentPlots::of(fit, segment),
            ))
        });
    }

    /// Whether the file chooser is open.
    pub fn chooser_open(&self) -> bool {
        self.chooser.is_some()
    }

    /// The tablet's state, when one was asked for.
    pub fn tablet(&self) -> Option<&tablet::TabletFeed> {
        self.tablet.as_ref()
    }

    /// Moves the tablet's finished strokes into the drawing. Tablet samples are millimetres: a
    /// drawing in mm takes them as they are, one in px at the CSS 96 px per inch; a drawing in
    /// device units has no known scale, so they wait (and say so) until the drawing is one of
    /// those, rather than being dropped.
    fn take_tablet_strokes(&mut self) {
        let Some(feed) = &mut self.tablet else {
            return;
        };
        self.tablet_pending.extend(feed.poll());
        if self.tablet_pending.is_empty() {
            return;
        }
        let Some(scale) = mm_to(self.doc.units()) else {
            let text = format!(
                "{} tablet strokes wait: they are in mm and this drawing is in {} units",
                self.tablet_pending.len(),
                self.doc.units().name()
            );
            if self.status.as_ref().is_none_or(|s| s.text != text) {
                self.set_error(text);
            }
            return;
        };
        for mut stroke in std::mem::take(&mut self.tablet_pending) {
            for sample in &mut stroke.samples {
                sample.x *= scale;
                sample.y *= scale;
            }
            self.execute(Command::Edit(Edit::AddStroke {
                stroke,
                settings: self.drawn_settings(),
            }));
        }
    }

    /// Fits the stroke being drawn (pointer or tablet) as it grows: every
    /// [`PREVIEW_INTERVAL_S`] with at least [`PREVIEW_NEW_SAMPLES`] new samples, a job for the
    /// stroke so far goes to the preview worker (a newer job supersedes a queued one), and the
    /// newest result is drawn over the live stroke until the stroke ends and its real fit
    /// arrives.
    fn grow_preview(&mut self, now: f64) {
        let Some(worker) = &self.preview_worker else {
            return;
        };
        // A result for the current stroke replaces the drawn one.
        for result in worker.poll() {
            let current = result.revision >= self.preview.first;
            if self.preview.active && current && result.revision > self.preview.shown {
                self.preview.shown = result.revision;
                if let Ok(curves) = result.outcome {
                    self.canvas.preview = preview_lines(&curves);
                }
            }
        }
        let scale = mm_to(self.doc.units()).unwrap_or(1.0);
        let live = match (self.canvas.live_stroke(), &self.tablet) {
            (Some(stroke), _) => Some(stroke.clone()),
            (None, Some(feed)) => feed.live_stroke().map(|mut stroke| {
                for s in &mut stroke.samples {
                    s.x *= scale;
                    s.y *= scale;
                }
                stroke
            }),
            (None, None) => None,
        };
        let Some(stroke) = live else {
            if self.preview.active {
                // Results still on their way belong to this stroke: the next one starts after.
                self.preview = Preview {
                    first: self.preview.revision + 1,
                    revision: self.preview.revision,
                    ..Preview::default()
                };
                self.canvas.preview.clear();
            }
            return;
        };
        self.preview.active = true;
        let n = stroke.samples.len();
        let due = now - self.preview.sent_at >= PREVIEW_INTERVAL_S
            && n >= self.preview.sent_samples + PREVIEW_NEW_SAMPLES
            && n >= PREVIEW_MIN_SAMPLES;
        if due {
            self.preview.revision += 1;
            self.preview.sent_at = now;
            self.preview.sent_samples = n;
            worker.send(worker::FitJob {
                id: PREVIEW_STROKE,
                revision: self.preview.revision,
                stroke,
                units: self.doc.units(),
                options: self.drawn_settings().pipeline_options(),
            });
        }
    }

    /// Takes in the fits that have arrived and advances the replay.
    fn logic(&mut self, ctx: &egui::Context) {
        self.grow_preview(ctx.input(|i| i.time));
        if let Some(worker) = &self.worker {
            for result in worker.poll() {
                self.fits.accept(result, &self.doc);
            }
        }
        self.take_tablet_strokes();
        if let Some(feed) = &self.tablet {
            let scale = mm_to(self.doc.units()).unwrap_or(1.0);
            self.canvas.tablet_live = feed
                .live_points()
                .into_iter()
                .map(|p| crate::geom::Point::new(p.x * scale, p.y * scale))
                .collect();
        }
        if let Some(replay) = &mut self.replay {
            let dt = ctx.input(|i| f64::from(i.stable_dt));
            replay.advance(dt, self.view.replay_speed);
            if replay.is_done() {
                self.replay = None;
            } else {
                ctx.request_repaint();
            }
        }
        self.after_change();
    }

    /// The whole UI, inside `ui` (the eframe root, or a test harness).
    pub fn ui(&mut self, ui: &mut egui::Ui) {
        self.logic(ui.ctx());
        let mut commands = Vec::new();
        shortcuts(ui, &mut commands);

        egui::Panel::top("kansei-top").show(ui, |ui| {
            panels::top_bar(ui, &self.doc, self.replay.is_some(), &mut commands);
        });
        egui::Panel::bottom("kansei-status").show(ui, |ui| {
            panels::status_line(
                ui,
                self.status.as_ref(),
                &self.doc,
                &self.fits,
                self.tablet.as_ref(),
            );
        });
        egui::Panel::left("kansei-settings").show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                if let Some(file) = &self.recovered {
                    panels::recovery_offer(ui, file, &mut commands);
                    ui.separator();
                }
                let editing = self.selected_stroke().is_some();
                let fitted = self
                    .selected_stroke()
                    .and_then(|id| self.doc.find(id))
                    .and_then(|(_, stroke)| match self.fits.get(stroke) {
                        Some(worker::FitState::Done(curves)) => panels::FittedSummary::of(curves),
                        _ => None,
                    });
                panels::settings(
                    ui,
                    self.current_settings(),
                    self.doc.units(),
                    editing,
                    fitted,
                    &mut commands,
                );
                ui.separator();
                panels::overlays(ui, &mut self.view.overlays);
                ui.separator();
                panels::files(ui, &mut self.view.path, &mut commands);
                ui.separator();
                panels::replay(
                    ui,
                    &mut self.view.replay_speed,
                    self.replay.as_ref(),
                    &mut commands,
                );
            });
        });
        let selected = self.selected_stroke();
        egui::Panel::right("kansei-segments").show(ui, |ui| {
            if let Some(id) = selected
                && ui
                    .button("Delete stroke")
                    .on_hover_text(
                        "Remove the selected segment's stroke (Delete; undo brings it back)",
                    )
                    .clicked()
            {
                commands.push(Command::Edit(Edit::RemoveStroke(id)));
            }
            panels::segment_table(ui, &self.scene, self.view.selection, &mut commands);
        });
        // Delete removes the selected stroke, unless a text field has the keyboard.
        if let Some(id) = selected
            && !ui.ctx().egui_wants_keyboard_input()
            && ui.input(|i| i.key_pressed(Key::Delete))
        {
            commands.push(Command::Edit(Edit::RemoveStroke(id)));
        }
        if let Some((_, _, series)) = &self.plots {
            egui::Panel::bottom("kansei-plots").show(ui, |ui| {
                plots::show(ui, series, PLOT_HEIGHT);
            });
        }
        let options = self.render_options();
        egui::CentralPanel::default().show(ui, |ui| {
            let scene = self.scene.scene();
            let key = self.scene.hash_key();
            if let Some(stroke) = self.canvas.ui(ui, &scene, key, &options) {
                commands.push(Command::Edit(Edit::AddStroke {
                    stroke,
                    settings: self.drawn_settings(),
                }));
            }
            // A click selects the segment under it, or clears the selection.
            if let Some((p, radius)) = self.canvas.take_click() {
                commands.push(Command::Select(self.scene.pick(p, radius)));
            }
        });
        if let Some(pending) = &self.pending_replace {
            replace_question(ui.ctx(), pending, &mut commands);
        }
        if let Some(chooser) = &mut self.chooser
            && let Some(choice) = chooser.show(ui.ctx())
        {
            if let chooser::Choice::Chosen(path) = choice {
                self.view.path = path.display().to_string();
            }
            self.chooser = None;
        }
        for command in commands {
            self.execute(command);
        }
        if self.canvas.is_drawing()
            || !self.fits_settled()
            || self.tablet.as_ref().is_some_and(|t| t.is_drawing())
        {
            ui.ctx().request_repaint();
        }
    }

    /// Called when the window closes: a drawing with nothing unsaved needs no recovery.
    pub fn on_exit(&mut self) {
        if self.doc.changes() == self.saved
            && self.recovered.is_none()
            && let Some(path) = &self.recovery_path
        {
            let _ = files::discard_recovery(path);
        }
    }
}

/// The question before a save or export replaces an existing file: "Replace NAME?" with
/// Replace and Cancel.
fn replace_question(ctx: &egui::Context, pending: &PendingReplace, commands: &mut Vec<Command>) {
    let name = pending.path.file_name().map_or_else(
        || pending.path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    egui::Window::new("Replace the file?")
        .collapsible(false)
        .resizable(false)
        .anchor(egui::Align2::CENTER_CENTER, egui::Vec2::ZERO)
        .show(ctx, |ui| {
            ui.label(format!("Replace {name}?"));
            ui.label(
                egui::RichText::new(format!(
                    "{} exists; replacing it loses what it holds.",
                    pending.path.display()
                ))
                .small(),
            );
            ui.horizontal(|ui| {
                if ui.button("Replace").clicked() {
                    commands.push(Command::ConfirmReplace);
                }
                if ui.button("Cancel").clicked() {
                    commands.push(Command::CancelReplace);
                }
            });
        });
}

/// Whether `a` and `b` name the same file (the same path once resolved, or the same text when
/// either cannot be resolved).
fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// Undo: Ctrl+Z; redo: Ctrl+Shift+Z or Ctrl+Y.
/// Seconds between fits of the stroke being drawn.
pub const PREVIEW_INTERVAL_S: f64 = 0.1;

/// New samples needed before the stroke being drawn is fitted again.
pub const PREVIEW_NEW_SAMPLES: usize = 4;

/// Samples a stroke being drawn needs before its first fit.
pub const PREVIEW_MIN_SAMPLES: usize = 8;

/// The id the stroke being drawn has in the preview worker (no document stroke has it).
const PREVIEW_STROKE: StrokeId = StrokeId(u64::MAX);

/// Points per segment of the growing fit's polylines (a segment turns less than a half turn:
/// 48 points keep each chord within a degree of the curve's direction).
const PREVIEW_POINTS_PER_SEGMENT: f64 = 48.0;

/// The growing fit's state.
#[derive(Clone, Debug, Default)]
struct Preview {
    /// A stroke is being drawn.
    active: bool,
    /// The last job's revision (increasing over all strokes).
    revision: u64,
    /// The first revision of the stroke being drawn.
    first: u64,
    /// The revision drawn.
    shown: u64,
    /// When the last job was sent (egui time, seconds).
    sent_at: f64,
    /// Its sample count.
    sent_samples: usize,
}

/// The chain segments of `curves` as polylines with their α colours.
fn preview_lines(curves: &[crate::pipeline::CurveFit]) -> Vec<(Vec<crate::geom::Point>, [u8; 3])> {
    curves
        .iter()
        .filter_map(|c| c.chain.as_ref())
        .flat_map(|chain| chain.segments.iter())
        .map(|seg| {
            let spacing = seg.segment.length() / PREVIEW_POINTS_PER_SEGMENT;
            let points = seg.segment.samples(spacing).map(|s| s.point).collect();
            (points, crate::export::alpha_colour(seg.segment.alpha()))
        })
        .collect()
}

/// The factor from millimetres to `units` (`None` for device units, which have no known scale).
fn mm_to(units: crate::stroke::Units) -> Option<f64> {
    match units {
        crate::stroke::Units::Mm => Some(1.0),
        crate::stroke::Units::Px => Some(PX_PER_MM),
        crate::stroke::Units::Device => None,
    }
}

/// CSS pixels per millimetre (96 per inch).
pub const PX_PER_MM: f64 = 96.0 / 25.4;

fn shortcuts(ui: &mut egui::Ui, commands: &mut Vec<Command>) {
    let redo = [
        KeyboardShortcut::new(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z),
        KeyboardShortcut::new(Modifiers::COMMAND, Key::Y),
    ];
    let undo = KeyboardShortcut::new(Modifiers::COMMAND, Key::Z);
    ui.input_mut(|i| {
        // Redo first: Ctrl+Shift+Z also matches a shortcut test for Ctrl+Z with Shift ignored.
        if redo.iter().any(|s| i.consume_shortcut(s)) {
            commands.push(Command::Redo);
        } else if i.consume_shortcut(&undo) {
            commands.push(Command::Undo);
        }
    });
}

impl eframe::App for KanseiApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        KanseiApp::ui(self, ui);
    }

    fn on_exit(&mut self, _gl: Option<&eframe::glow::Context>) {
        KanseiApp::on_exit(self);
    }
}

/// Why the app could not run.
#[derive(Debug, thiserror::Error)]
pub enum AppError {
    /// The window could not be opened (no display, no OpenGL).
    #[error("cannot open the window: {0}")]
    Window(String),
}

/// Opens the window and runs until it is closed.
pub fn run(options: AppOptions) -> Result<(), AppError> {
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("kansei")
            .with_inner_size([1280.0, 800.0]),
        ..eframe::NativeOptions::default()
    };
    eframe::run_native(
        "kansei",
        native,
        Box::new(|cc| Ok(Box::new(KanseiApp::new(&cc.egui_ctx, options)))),
    )
    .map_err(|e| AppError::Window(e.to_string()))
}

/// Whether `state` is a finished fit (for tests and the status line).
pub fn is_done(state: Option<&FitState>) -> bool {
    matches!(state, Some(FitState::Done(_)))
}
