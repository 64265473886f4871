//! The panels around the canvas. Each shows state and pushes [`Command`]s; none computes or
//! changes the document itself (the overlay toggles are view state and are edited in place).

use std::path::PathBuf;

use eframe::egui;
use egui::{DragValue, RichText, ScrollArea, Ui};

use super::Command;
use super::document::{Document, FitSettings, ScreenTolerance};
use super::files::export_path;
use super::replay::{Replay, SPEED_RANGE};
use super::scene::{SceneData, Selection};
use super::worker::{FitState, Fits};
use crate::chain::Continuity;
use crate::export::{Format, relative_jump};
use crate::lac::AlphaChoice;
use crate::render::Overlays;
use crate::stroke::{StrokeFile, Units};

/// Largest α the panel offers: past the range where LACs are used (−3..3) with room to spare.
pub const ALPHA_LIMIT: f64 = 10.0;

/// Corner angles the panel offers, degrees: 5 (almost every turn is a corner) to 180 (none).
pub const CORNER_ANGLE_RANGE: (f64, f64) = (5.0, 180.0);

/// The menu row: undo, redo, fit view.
pub fn top_bar(ui: &mut Ui, doc: &Document, replaying: bool, commands: &mut Vec<Command>) {
    ui.horizontal(|ui| {
        ui.strong("kansei");
        ui.separator();
        if ui
            .add_enabled(doc.can_undo(), egui::Button::new("Undo"))
            .clicked()
        {
            commands.push(Command::Undo);
        }
        if ui
            .add_enabled(doc.can_redo(), egui::Button::new("Redo"))
            .clicked()
        {
            commands.push(Command::Redo);
        }
        if ui.button("Fit view").clicked() {
            commands.push(Command::FitView);
        }
        if replaying {
            ui.label("replaying…");
        }
    });
}

/// The feedback line: the last message, stroke and fit counts.
pub fn status_line(
    ui: &mut Ui,
    status: Option<&super::Status>,
    doc: &Document,
    fits: &Fits,
    tablet: Option<&super::tablet::TabletFeed>,
) {
    ui.horizontal(|ui| {
        if let Some(feed) = tablet {
            let failed = matches!(feed.state(), super::tablet::FeedState::Failed(_));
            if failed {
                ui.colored_label(ui.visuals().error_fg_color, feed.summary());
            } else {
                ui.label(feed.summary());
            }
            ui.separator();
        }
        let pending = doc
            .strokes()
            .iter()
            .filter(|s| matches!(fits.get(s), None | Some(FitState::Pending)))
            .count();
        let failed: Vec<String> = doc
            .strokes()
            .iter()
            .enumerate()
            .filter_map(|(i, s)| match fits.get(s) {
                Some(FitState::Failed(why)) => Some(format!("stroke {}: {why}", i + 1)),
                _ => None,
            })
            .collect();
        ui.label(format!(
            "{} strokes ({}), {pending} fitting",
            doc.strokes().len(),
            doc.units().name()
        ));
        for why in failed.iter().take(1) {
            ui.separator();
            ui.colored_label(ui.visuals().warn_fg_color, why);
        }
        if let Some(status) = status {
            ui.separator();
            if status.error {
                ui.colored_label(ui.visuals().error_fg_color, &status.text);
            } else {
                ui.label(&status.text);
            }
        }
    });
}

/// The offer of a recovered drawing.
pub fn recovery_offer(ui: &mut Ui, file: &StrokeFile, commands: &mut Vec<Command>) {
    ui.label(RichText::new("Unsaved drawing from last time").strong());
    ui.label(format!("{} strokes", file.strokes.len()));
    ui.horizontal(|ui| {
        if ui.button("Recover").clicked() {
            commands.push(Command::Recover);
        }
        if ui.button("Discard").clicked() {
            commands.push(Command::DiscardRecovery);
        }
    });
}

/// Tolerance, α (range or fixed) and corner angle. With a stroke selected they are that
/// stroke's and every change refits it at once; otherwise they are those of new strokes.
pub fn settings(
    ui: &mut Ui,
    current: FitSettings,
    units: Units,
    editing_selected: bool,
    fitted: Option<FittedSummary>,
    commands: &mut Vec<Command>,
) {
    ui.heading("Fit");
    ui.label(if editing_selected {
        "selected stroke"
    } else {
        "new strokes"
    });
    let mut s = current;
    // The tolerance: a screen preset (the noise floor may raise it) or a number of units.
    let mut custom = s.tolerance.is_some();
    ui.horizontal(|ui| {
        ui.label("tolerance");
        for preset in ScreenTolerance::ALL {
            let chosen = !custom && s.screen == preset;
            if ui
                .selectable_label(chosen, preset.name())
                .on_hover_text(format!(
                    "{} screen px at the zoom the stroke was drawn at, raised to its noise floor",
                    preset.pixels()
                ))
                .clicked()
            {
                s.screen = preset;
                custom = false;
            }
        }
        if ui.selectable_label(custom, "custom").clicked() {
            custom = true;
        }
    });
    if custom {
        let mut tolerance = s
            .tolerance
            .or(fitted.map(|f| f.tolerance))
            .unwrap_or(units.default_tolerance());
        ui.horizontal(|ui| {
            let label = ui.label("custom");
            let step = units.default_tolerance() / 10.0;
            ui.add(
                DragValue::new(&mut tolerance)
                    .speed(step)
                    .range(step..=f64::MAX)
                    .suffix(format!(" {}", units.name())),
            )
            .labelled_by(label.id);
        });
        s.tolerance = Some(tolerance);
    } else {
        s.tolerance = None;
    }
    // One line either way, so that selecting a stroke does not move the controls below.
    ui.label(match fitted {
        Some(f) => format!(
            "fitted to {:.3} {} (noise floor {:.3}): {} segment{}",
            f.tolerance,
            units.name(),
            f.floor,
            f.segments,
            if f.segments == 1 { "" } else { "s" }
        ),
        None if custom => "raised to no stroke's noise floor".to_owned(),
        None => format!(
            "{} screen px where drawn, or the noise floor",
            s.screen.pixels()
        ),
    });

    let mut fixed = matches!(s.alpha, AlphaChoice::Fixed(_));
    ui.horizontal(|ui| {
        ui.label("α");
        ui.radio_value(&mut fixed, false, "range");
        ui.radio_value(&mut fixed, true, "fixed");
    });
    let middle = s.alpha.middle();
    s.alpha = match (fixed, s.alpha) {
        (true, AlphaChoice::Fixed(a)) => {
            let mut a = a;
            ui.horizontal(|ui| {
                let label = ui.label("α =");
                ui.add(
                    DragValue::new(&mut a)
                        .speed(0.05)
                        .range(-ALPHA_LIMIT..=ALPHA_LIMIT),
                )
                .labelled_by(label.id);
            });
            AlphaChoice::Fixed(a)
        }
        (true, AlphaChoice::Range { .. }) => AlphaChoice::Fixed(middle),
        (false, AlphaChoice::Range { min, max }) => {
            let (mut min, mut max) = (min, max);
            ui.horizontal(|ui| {
                let from = ui.label("from");
                ui.add(
                    DragValue::new(&mut min)
                        .speed(0.05)
                        .range(-ALPHA_LIMIT..=max),
                )
                .labelled_by(from.id);
                let to = ui.label("to");
                ui.add(
                    DragValue::new(&mut max)
                        .speed(0.05)
                        .range(min..=ALPHA_LIMIT),
                )
                .labelled_by(to.id);
            });
            AlphaChoice::Range { min, max }
        }
        // Back to a range: the default one, widened to hold the fixed α.
        (false, AlphaChoice::Fixed(a)) => match AlphaChoice::default() {
            AlphaChoice::Range { min, max } => AlphaChoice::Range {
                min: min.min(a),
                max: max.max(a),
            },
            fixed => fixed,
        },
    };
    ui.horizontal(|ui| {
        let label = ui.label("corner angle");
        ui.add(
            DragValue::new(&mut s.corner_angle)
                .speed(1.0)
                .range(CORNER_ANGLE_RANGE.0..=CORNER_ANGLE_RANGE.1)
                .suffix("°"),
        )
        .labelled_by(label.id);
    });
    ui.horizontal(|ui| {
        ui.label("continuity").on_hover_text(
            "G1: position and tangent meet at the joints; G2: the curvature too; C3: its \
             derivative too (compound rhythm; a part that cannot hold it is made G2). A curve \
             the smooth fit cannot hold within the tolerance stays G1: the segment table's \
             joint jumps say which.",
        );
        for c in [Continuity::G1, Continuity::G2, Continuity::C3] {
            ui.radio_value(&mut s.continuity, c, c.name().to_uppercase());
        }
    });
    ui.checkbox(&mut s.close, "close closed strokes")
        .on_hover_text(
            "A stroke that comes back to its start (stops near it, runs past it, goes round \
         again) becomes one closed curve, its seam as smooth as its joints; off, it is fitted \
         open (the CLI's --close never).",
        );
    if ui.button("defaults").clicked() {
        s = FitSettings::default();
    }
    if s != current && s.is_valid() {
        commands.push(Command::SetSettings(s));
    }
}

/// The overlay toggles (view state, edited in place).
pub fn overlays(ui: &mut Ui, o: &mut Overlays) {
    ui.heading("Show");
    ui.checkbox(&mut o.samples, "samples");
    ui.checkbox(&mut o.bspline, "B-spline");
    ui.checkbox(&mut o.control_polygon, "control polygon");
    ui.checkbox(&mut o.splits, "split points");
    ui.checkbox(&mut o.segments, "LAC segments");
    ui.checkbox(&mut o.joints, "LAC joints");
    ui.checkbox(&mut o.comb, "curvature comb");
    ui.checkbox(&mut o.comb_log, "comb on a log scale");
    ui.checkbox(&mut o.legend, "α legend");
    ui.checkbox(&mut o.scale_bar, "scale bar");
}

/// A path field with open, save and export buttons. Open and Save use the path; each export
/// goes to its own file next to it ([`export_path`]), named in the button's hover text.
pub fn files(ui: &mut Ui, path: &mut String, commands: &mut Vec<Command>) {
    ui.heading("File");
    ui.horizontal(|ui| {
        if ui
            .button("Browse…")
            .on_hover_text("Choose the path in a file chooser")
            .clicked()
        {
            commands.push(Command::Browse);
        }
        ui.add(egui::TextEdit::singleline(path).hint_text("path"));
    });
    let target = PathBuf::from(path.trim());
    let has_path = !path.trim().is_empty();
    ui.horizontal_wrapped(|ui| {
        type Make = fn(PathBuf) -> Command;
        let buttons: [(&str, Make); 2] = [("Open", Command::Open), ("Save", Command::Save)];
        for (label, make) in buttons {
            if ui.add_enabled(has_path, egui::Button::new(label)).clicked() {
                commands.push(make(target.clone()));
            }
        }
        for format in Format::ALL {
            let to = export_path(&target, format);
            let label = format!("Export {}", format.name());
            let button = ui.add_enabled(to.is_some(), egui::Button::new(label));
            let button = match &to {
                Some(to) => button.on_hover_text(format!("Write {}", to.display())),
                None => button.on_disabled_hover_text("Type a file name in the path field"),
            };
            if button.clicked()
                && let Some(to) = to
            {
                commands.push(Command::Export(format, to));
            }
        }
    });
}

/// Replay controls: start/stop and the speed.
pub fn replay(ui: &mut Ui, speed: &mut f64, replay: Option<&Replay>, commands: &mut Vec<Command>) {
    ui.heading("Replay");
    ui.horizontal(|ui| match replay {
        None => {
            if ui.button("Replay").clicked() {
                commands.push(Command::StartReplay);
            }
        }
        Some(r) => {
            if ui.button("Stop").clicked() {
                commands.push(Command::StopReplay);
            }
            ui.label(format!("{:.1} / {:.1} s", r.clock(), r.duration()));
        }
    });
    ui.add(
        egui::Slider::new(speed, SPEED_RANGE.0..=SPEED_RANGE.1)
            .logarithmic(true)
            .text("speed"),
    );
}

/// The table of every segment: α, length, κ0, κ1, max deviation, and the relative curvature
/// jump at its end joint (0 where the chain is G2 there; blank at a piece's end). A click
/// selects the row.
pub fn segment_table(
    ui: &mut Ui,
    scene: &SceneData,
    selected: Option<Selection>,
    commands: &mut Vec<Command>,
) {
    let count = scene.segments().count();
    ui.heading(format!("Segments ({count})"));
    ScrollArea::vertical().show(ui, |ui| {
        egui::Grid::new("segments")
            .striped(true)
            .num_columns(7)
            .show(ui, |ui| {
                for head in ["segment", "α", "length", "κ0", "κ1", "max dev", "κ jump"] {
                    ui.strong(head);
                }
                ui.end_row();
                let rows: Vec<_> = scene.segments().collect();
                for (i, &(selection, stroke, seg)) in rows.iter().enumerate() {
                    let name = segment_name(stroke, selection);
                    let is_selected = selected == Some(selection);
                    if ui.selectable_label(is_selected, name).clicked() {
                        commands.push(Command::Select((!is_selected).then_some(selection)));
                    }
                    let s = &seg.segment;
                    ui.label(alpha_text(seg)).on_hover_text(
                        "α ± its standard error; \"bound\": on the range's end (the search met \
                         its wall); \"?\": the samples do not determine it (a near arc or \
                         line, too few samples)",
                    );
                    ui.label(format!("{:.3}", s.length()));
                    ui.label(format!("{:.4}", s.kappa0()));
                    ui.label(format!("{:.4}", s.kappa1()));
                    ui.label(format!("{:.4}", seg.max_deviation));
                    // The next row continues the same chain: the joint between them.
                    let jump = rows.get(i + 1).and_then(|&(next, _, following)| {
                        (next.stroke == selection.stroke
                            && next.piece == selection.piece
                            && next.segment == selection.segment + 1)
                            .then(|| relative_jump(s.kappa1(), following.segment.kappa0()))
                            .flatten()
                    });
                    ui.label(jump.map_or(String::new(), |j| format!("{:.0} %", 100.0 * j)))
                        .on_hover_text(
                            "relative curvature jump at the joint to the next segment \
                             (0 % where the chain is G2)",
                        );
                    ui.end_row();
                }
            });
    });
}

/// A row's name: stroke, piece and segment, counted from 1.
pub fn segment_name(stroke: usize, s: Selection) -> String {
    format!("{}.{}.{}", stroke + 1, s.piece + 1, s.segment + 1)
}

/// A segment's α as the table shows it: `arc/line` without one, the value with its standard
/// error where estimated, and a mark where it sits on the range's bound (`bound`) or the samples
/// do not determine it (`?`, also where too few samples gave no estimate); a fixed α unmarked.
pub fn alpha_text(seg: &crate::chain::ChainSegment) -> String {
    let Some(alpha) = seg.segment.alpha() else {
        return "arc/line".into();
    };
    let value = match seg.alpha_uncertainty.filter(|u| u.is_finite()) {
        Some(u) => format!("{alpha:.2} ± {u:.2}"),
        None => format!("{alpha:.3}"),
    };
    if seg.alpha_bound.is_some() {
        format!("{value} bound")
    } else if seg.alpha_source != Some(crate::chain::AlphaSource::Fixed) && !seg.alpha_determined()
    {
        format!("{value} ?")
    } else {
        value
    }
}

/// What the selected stroke's fit came to, shown under its tolerance settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FittedSummary {
    /// The tolerance it was fitted to, in the document's units.
    pub tolerance: f64,
    /// Its noise floor.
    pub floor: f64,
    /// Its segments, over all pieces.
    pub segments: usize,
}

impl FittedSummary {
    /// The summary of a stroke's fitted pieces (`None` without pieces).
    pub fn of(curves: &[crate::pipeline::CurveFit]) -> Option<FittedSummary> {
        let first = curves.first()?;
        Some(FittedSummary {
            tolerance: first.tolerance,
            floor: first.noise.map_or(0.0, |n| n.floor),
            segments: curves
                .iter()
                .filter_map(|c| c.chain.as_ref())
                .map(|c| c.segments.len())
                .sum(),
        })
    }
}
