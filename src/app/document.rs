//! The drawing as the app edits it: [`Document`], changed only through [`Edit`]s, which it keeps
//! on an undo stack.
//!
//! A document holds strokes, each with the [`FitSettings`] it is fitted with and a stable
//! [`StrokeId`]. Fits are not part of the document's history: they are derived, and the app keeps
//! them apart ([`Fits`](super::worker::Fits)), keyed by id and by the stroke's *revision*, a number
//! that changes whenever the stroke or its settings change, so that a fit computed for an older
//! revision can be recognised and dropped.
//!
//! Undo and redo: applying an edit returns its inverse; [`Document::apply`] pushes that inverse on
//! the undo stack and clears the redo stack, [`Document::undo`] applies the top inverse and pushes
//! *its* inverse on the redo stack. Undo followed by redo gives back the same strokes and settings
//! (tested in this module).

use crate::chain::{ChainOptions, Continuity};
use crate::lac::AlphaChoice;
use crate::pipeline::PipelineOptions;
use crate::stroke::{Stroke, StrokeFile, Units};

/// A stroke's identity, stable across edits (indices shift when strokes are removed).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct StrokeId(pub u64);

/// The fitting knobs the panel exposes, per stroke.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitSettings {
    /// Tolerance in the document's units (the panel's `custom`). Default `None`: the screen
    /// preset at the zoom the stroke was drawn at ([`FitSettings::base_tolerance`]), or for a
    /// stroke read from a file the unit's default ([`Units::default_tolerance`]), either raised
    /// to the stroke's noise floor.
    pub tolerance: Option<f64>,
    /// α per segment. Default the range [−3, 3] ([`AlphaChoice::default`]).
    pub alpha: AlphaChoice,
    /// Corner turning angle, degrees. Default 70 (as [`PipelineOptions::default`]).
    pub corner_angle: f64,
    /// Continuity at the chain's smooth joints (default as [`ChainOptions::default`]).
    pub continuity: Continuity,
    /// How closely a stroke drawn in the app is followed, in screen pixels at the zoom it was
    /// drawn at (used when `tolerance` is `None` and the stroke has `pixels_per_unit`). Default
    /// [`ScreenTolerance::Normal`].
    pub screen: ScreenTolerance,
    /// Screen pixels per document unit when the stroke was drawn (`None` for strokes read from
    /// a file, which get the unit's default).
    pub pixels_per_unit: Option<f64>,
    /// Fit a stroke that comes back to its start as one closed curve (as
    /// [`PipelineOptions::close`], default on: the CLI's `--close auto`).
    pub close: bool,
}

/// Tolerance presets for strokes drawn in the app, in screen pixels at the zoom they were drawn
/// at: what the designer could see of the difference. Each stroke's noise floor may raise it
/// further (a mouse's whole pixels: 0.71 px).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ScreenTolerance {
    /// Half a pixel: every visible wobble is kept.
    Tight,
    /// One and a half pixels: the line's own width; the default.
    #[default]
    Normal,
    /// Four pixels: the gesture, not its tremor.
    Loose,
}

impl ScreenTolerance {
    /// Every preset, tightest first.
    pub const ALL: [ScreenTolerance; 3] = [
        ScreenTolerance::Tight,
        ScreenTolerance::Normal,
        ScreenTolerance::Loose,
    ];

    /// The preset's screen pixels.
    pub const fn pixels(self) -> f64 {
        match self {
            ScreenTolerance::Tight => 0.5,
            ScreenTolerance::Normal => 1.5,
            ScreenTolerance::Loose => 4.0,
        }
    }

    /// The preset's name in the panel.
    pub const fn name(self) -> &'static str {
        match self {
            ScreenTolerance::Tight => "tight",
            ScreenTolerance::Normal => "normal",
            ScreenTolerance::Loose => "loose",
        }
    }
}

impl Default for FitSettings {
    fn default() -> Self {
        let pipeline = PipelineOptions::default();
        FitSettings {
            tolerance: pipeline.tolerance,
            alpha: pipeline.chain.alpha,
            corner_angle: pipeline.corner_angle,
            continuity: pipeline.chain.continuity,
            screen: ScreenTolerance::default(),
            pixels_per_unit: None,
            close: pipeline.close,
        }
    }
}

impl FitSettings {
    /// The pipeline options these settings stand for.
    pub fn pipeline_options(&self) -> PipelineOptions {
        PipelineOptions {
            tolerance: self.tolerance,
            base_tolerance: self.base_tolerance(),
            corner_angle: self.corner_angle,
            chain: ChainOptions {
                alpha: self.alpha,
                continuity: self.continuity,
                ..ChainOptions::default()
            },
            close: self.close,
            ..PipelineOptions::default()
        }
    }

    /// The tolerance a stroke drawn in the app starts from: the preset's screen pixels at the
    /// zoom it was drawn at (`None` for a stroke read from a file).
    pub fn base_tolerance(&self) -> Option<f64> {
        self.pixels_per_unit
            .filter(|k| k.is_finite() && *k > 0.0)
            .map(|k| self.screen.pixels() / k)
    }

    /// Whether the pipeline accepts these settings: a positive finite tolerance (when given),
    /// a finite non-empty α range, a finite corner angle.
    pub fn is_valid(&self) -> bool {
        self.tolerance.is_none_or(|t| t.is_finite() && t > 0.0)
            && self.alpha.validate().is_ok()
            && self.corner_angle.is_finite()
    }
}

/// One stroke of the document.
#[derive(Clone, Debug, PartialEq)]
pub struct DocStroke {
    /// Its identity.
    pub id: StrokeId,
    /// Bumped by every edit of the stroke or its settings; fits name the revision they were
    /// computed for.
    pub revision: u64,
    /// The samples.
    pub stroke: Stroke,
    /// How it is fitted.
    pub settings: FitSettings,
}

/// A change to the document. Every change goes through [`Document::apply`].
#[derive(Clone, Debug, PartialEq)]
pub enum Edit {
    /// Append a stroke, fitted with the given settings.
    AddStroke {
        /// The samples.
        stroke: Stroke,
        /// Its settings.
        settings: FitSettings,
    },
    /// Put a stroke back at `index` (the inverse of [`Edit::RemoveStroke`]).
    InsertStroke {
        /// Where.
        index: usize,
        /// The stroke, with its id.
        stroke: DocStroke,
    },
    /// Remove the stroke with this id.
    RemoveStroke(StrokeId),
    /// Change a stroke's settings.
    SetSettings {
        /// Which stroke.
        id: StrokeId,
        /// The new settings.
        settings: FitSettings,
    },
    /// Replace the whole drawing (opening a file, clearing).
    Replace {
        /// The units of the new drawing.
        units: Units,
        /// The new strokes.
        strokes: Vec<DocStroke>,
    },
}

/// Why an edit was refused. The document is unchanged.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EditError {
    /// No stroke has this id.
    #[error("no stroke with id {0}")]
    NoStroke(u64),
    /// The index is past the end.
    #[error("stroke index {index} is past the end ({len} strokes)")]
    BadIndex {
        /// The index.
        index: usize,
        /// How many strokes there are.
        len: usize,
    },
    /// The settings are not usable (see [`FitSettings::is_valid`]).
    #[error("invalid fit settings: {0:?}")]
    BadSettings(FitSettings),
    /// The stroke fails [`Stroke::validate`].
    #[error("{0}")]
    BadStroke(String),
}

/// The drawing: strokes in drawing order, their units, and the undo/redo history.
#[derive(Clone, Debug)]
pub struct Document {
    units: Units,
    strokes: Vec<DocStroke>,
    next_id: u64,
    next_revision: u64,
    changes: u64,
    undo: Vec<Edit>,
    redo: Vec<Edit>,
}

impl Default for Document {
    /// An empty drawing in millimetres (what a tablet gives).
    fn default() -> Self {
        Document::new(Units::Mm)
    }
}

impl Document {
    /// An empty drawing in `units`.
    pub fn new(units: Units) -> Self {
        Document {
            units,
            strokes: Vec::new(),
            next_id: 0,
            next_revision: 0,
            changes: 0,
            undo: Vec::new(),
            redo: Vec::new(),
        }
    }

    /// The units of the strokes.
    pub fn units(&self) -> Units {
        self.units
    }

    /// The strokes in drawing order.
    pub fn strokes(&self) -> &[DocStroke] {
        &self.strokes
    }

    /// The stroke with this id and its index.
    pub fn find(&self, id: StrokeId) -> Option<(usize, &DocStroke)> {
        self.strokes.iter().enumerate().find(|(_, s)| s.id == id)
    }

    /// Counts the changes made so far (edits, undos, redos): equal counts, same drawing.
    pub fn changes(&self) -> u64 {
        self.changes
    }

    /// Whether [`Document::undo`] has something to undo.
    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty()
    }

    /// Whether [`Document::redo`] has something to redo.
    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// The strokes as a `kansei-stroke` file.
    pub fn to_file(&self) -> StrokeFile {
        StrokeFile::new(
            self.units,
            self.strokes.iter().map(|s| s.stroke.clone()).collect(),
        )
    }

    /// The edit that replaces the drawing by `file`'s strokes, each with `settings`.
    pub fn replace_with(&mut self, file: StrokeFile, settings: FitSettings) -> Edit {
        let strokes = file
            .strokes
            .into_iter()
            .map(|stroke| self.new_stroke(stroke, settings))
            .collect();
        Edit::Replace {
            units: file.units,
            strokes,
        }
    }

    /// Applies `edit`, recording its inverse for undo and forgetting what could be redone.
    /// Returns the id of the stroke the edit concerns (the new stroke for
    /// [`Edit::AddStroke`]), if any.
    pub fn apply(&mut self, edit: Edit) -> Result<Option<StrokeId>, EditError> {
        let (inverse, id) = self.perform(edit)?;
        self.undo.push(inverse);
        self.redo.clear();
        Ok(id)
    }

    /// Undoes the last edit; false when there is none.
    pub fn undo(&mut self) -> bool {
        self.step_history(true)
    }

    /// Redoes the last undone edit; false when there is none.
    pub fn redo(&mut self) -> bool {
        self.step_history(false)
    }

    fn step_history(&mut self, undo: bool) -> bool {
        let edit = if undo {
            self.undo.pop()
        } else {
            self.redo.pop()
        };
        let Some(edit) = edit else {
            return false;
        };
        // The history only holds inverses of edits that were applied, so each applies again;
        // should one not, it goes back where it was and nothing has changed.
        let (done, back) = match self.perform(edit.clone()) {
            Ok((inverse, _)) => (true, inverse),
            Err(_) => (false, edit),
        };
        let stack = if undo == done {
            &mut self.redo
        } else {
            &mut self.undo
        };
        stack.push(back);
        done
    }

    fn new_stroke(&mut self, stroke: Stroke, settings: FitSettings) -> DocStroke {
        let id = StrokeId(self.next_id);
        self.next_id += 1;
        DocStroke {
            id,
            revision: self.bump_revision(),
            stroke,
            settings,
        }
    }

    fn bump_revision(&mut self) -> u64 {
        self.next_revision += 1;
        self.next_revision
    }

    fn index_of(&self, id: StrokeId) -> Result<usize, EditError> {
        self.find(id)
            .map(|(i, _)| i)
            .ok_or(EditError::NoStroke(id.0))
    }

    /// Applies an edit without touching the history; returns its inverse.
    fn perform(&mut self, edit: Edit) -> Result<(Edit, Option<StrokeId>), EditError> {
        let done = self.perform_unrecorded(edit)?;
        self.changes += 1;
        Ok(done)
    }

    fn perform_unrecorded(&mut self, edit: Edit) -> Result<(Edit, Option<StrokeId>), EditError> {
        match edit {
            Edit::AddStroke { stroke, settings } => {
                if !settings.is_valid() {
                    return Err(EditError::BadSettings(settings));
                }
                stroke
                    .validate(self.strokes.len())
                    .map_err(|e| EditError::BadStroke(e.to_string()))?;
                let stroke = self.new_stroke(stroke, settings);
                let id = stroke.id;
                self.strokes.push(stroke);
                Ok((Edit::RemoveStroke(id), Some(id)))
            }
            Edit::InsertStroke { index, mut stroke } => {
                if index > self.strokes.len() {
                    return Err(EditError::BadIndex {
                        index,
                        len: self.strokes.len(),
                    });
                }
                let id = stroke.id;
                // A stroke coming back is fitted afresh: fits of its old revision were dropped.
                stroke.revision = self.bump_revision();
                self.next_id = self.next_id.max(id.0 + 1);
                self.strokes.insert(index, stroke);
                Ok((Edit::RemoveStroke(id), Some(id)))
            }
            Edit::RemoveStroke(id) => {
                let index = self.index_of(id)?;
                let stroke = self.strokes.remove(index);
                Ok((Edit::InsertStroke { index, stroke }, Some(id)))
            }
            Edit::SetSettings { id, settings } => {
                if !settings.is_valid() {
                    return Err(EditError::BadSettings(settings));
                }
                let index = self.index_of(id)?;
                let revision = self.bump_revision();
                let stroke = &mut self.strokes[index];
                let old = std::mem::replace(&mut stroke.settings, settings);
                stroke.revision = revision;
                Ok((Edit::SetSettings { id, settings: old }, Some(id)))
            }
            Edit::Replace { units, mut strokes } => {
                for s in &mut strokes {
                    s.revision = self.bump_revision();
                    self.next_id = self.next_id.max(s.id.0 + 1);
                }
                let old_units = std::mem::replace(&mut self.units, units);
                let old = std::mem::replace(&mut self.strokes, strokes);
                Ok((
                    Edit::Replace {
                        units: old_units,
                        strokes: old,
                    },
                    None,
                ))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Point;

    fn line(n: usize, dy: f64) -> Stroke {
        Stroke::from_points((0..n).map(|i| Point::new(i as f64, dy + 0.1 * (i * i) as f64)))
    }

    /// What undo/redo must preserve: the strokes and settings, not revisions.
    fn content(doc: &Document) -> Vec<(StrokeId, Stroke, FitSettings)> {
        doc.strokes()
            .iter()
            .map(|s| (s.id, s.stroke.clone(), s.settings))
            .collect()
    }

    #[test]
    fn undo_then_redo_restores_every_state() {
        let mut doc = Document::default();
        let mut states = vec![content(&doc)];
        let a = doc
            .apply(Edit::AddStroke {
                stroke: line(10, 0.0),
                settings: FitSettings::default(),
            })
            .ok()
            .flatten();
        states.push(content(&doc));
        doc.apply(Edit::AddStroke {
            stroke: line(12, 5.0),
            settings: FitSettings::default(),
        })
        .ok();
        states.push(content(&doc));
        let id = a.map_or(StrokeId(u64::MAX), |id| id);
        doc.apply(Edit::SetSettings {
            id,
            settings: FitSettings {
                alpha: AlphaChoice::Fixed(-1.0),
                ..FitSettings::default()
            },
        })
        .ok();
        states.push(content(&doc));
        doc.apply(Edit::RemoveStroke(id)).ok();
        states.push(content(&doc));
        let file = StrokeFile::new(Units::Px, vec![line(5, 1.0)]);
        let replace = doc.replace_with(file, FitSettings::default());
        doc.apply(replace).ok();
        states.push(content(&doc));
        assert_eq!(doc.units(), Units::Px);

        // Walk back to the start, checking each state, then forward again.
        for expected in states.iter().rev().skip(1) {
            assert!(doc.undo());
            assert_eq!(&content(&doc), expected);
        }
        assert!(!doc.undo());
        assert_eq!(doc.units(), Units::Mm);
        for expected in states.iter().skip(1) {
            assert!(doc.redo());
            assert_eq!(&content(&doc), expected);
        }
        assert!(!doc.redo());
    }

    #[test]
    fn a_new_edit_clears_redo() {
        let mut doc = Document::default();
        for dy in [0.0, 3.0] {
            doc.apply(Edit::AddStroke {
                stroke: line(8, dy),
                settings: FitSettings::default(),
            })
            .ok();
        }
        assert!(doc.undo());
        assert!(doc.can_redo());
        doc.apply(Edit::AddStroke {
            stroke: line(9, 7.0),
            settings: FitSettings::default(),
        })
        .ok();
        assert!(!doc.can_redo());
        assert_eq!(doc.strokes().len(), 2);
    }

    #[test]
    fn revisions_change_with_every_edit_of_a_stroke() {
        let mut doc = Document::default();
        let id = doc
            .apply(Edit::AddStroke {
                stroke: line(8, 0.0),
                settings: FitSettings::default(),
            })
            .ok()
            .flatten()
            .map_or(StrokeId(u64::MAX), |id| id);
        let r0 = doc.strokes()[0].revision;
        doc.apply(Edit::SetSettings {
            id,
            settings: FitSettings {
                corner_angle: 45.0,
                ..FitSettings::default()
            },
        })
        .ok();
        let r1 = doc.strokes()[0].revision;
        assert_ne!(r0, r1);
        assert!(doc.undo());
        let r2 = doc.strokes()[0].revision;
        assert!(r2 != r0 && r2 != r1, "an undone setting is a new revision");
    }

    #[test]
    fn refused_edits_change_nothing() {
        let mut doc = Document::default();
        let bad = Stroke::from_points([Point::new(1.0, 1.0), Point::new(f64::NAN, 1.0)]);
        let err = doc.apply(Edit::AddStroke {
            stroke: bad,
            settings: FitSettings::default(),
        });
        assert!(matches!(err, Err(EditError::BadStroke(_))));
        let err = doc.apply(Edit::AddStroke {
            stroke: line(5, 0.0),
            settings: FitSettings {
                tolerance: Some(f64::NAN),
                ..FitSettings::default()
            },
        });
        assert!(matches!(err, Err(EditError::BadSettings(_))));
        assert!(matches!(
            doc.apply(Edit::RemoveStroke(StrokeId(3))),
            Err(EditError::NoStroke(3))
        ));
        assert!(doc.strokes().is_empty());
        assert!(!doc.can_undo());
    }
}
