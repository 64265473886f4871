//! What the canvas draws, gathered from the document and its fits: [`SceneData`], rebuilt only
//! when either changes, and the [`Selection`] of one segment.

use super::document::{Document, StrokeId};
use super::replay::Replay;
use super::worker::{FitState, Fits};
use crate::chain::ChainSegment;
use crate::pipeline::{CurveFit, FitOutput};
use crate::render::Scene;
use crate::stroke::{Stroke, Units};

/// A click's distance to a segment is measured on the segment traced at this fraction of the
/// pick radius: far finer than a pointer can aim.
const PICK_CHORD_FRACTION: f64 = 0.1;

/// One selected segment: a stroke, a piece of its fit, a segment of that piece's chain.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Selection {
    /// The stroke.
    pub stroke: StrokeId,
    /// The piece (the stroke is cut at corners).
    pub piece: usize,
    /// The segment of the piece's chain.
    pub segment: usize,
}

/// The strokes and fits in the form [`render`](crate::render::render) takes.
#[derive(Clone, Debug)]
pub struct SceneData {
    /// Units of the strokes.
    pub units: Units,
    /// The strokes, in document order.
    pub strokes: Vec<Stroke>,
    /// The fitted pieces of every stroke whose fit is done; `stroke` indexes `strokes`.
    pub curves: Vec<CurveFit>,
    /// For each curve, its stroke's id and its piece number within that stroke.
    pub owners: Vec<(StrokeId, usize)>,
    /// (document changes, fits generation, replay frame) when built.
    pub key: (u64, u64, u64),
}

impl SceneData {
    /// The scene of `doc` with the fits that are done. During a replay, strokes are cut to what
    /// has been "drawn" so far and only finished strokes show their fits.
    pub fn build(doc: &Document, fits: &Fits, replay: Option<&Replay>) -> Self {
        let mut strokes = Vec::with_capacity(doc.strokes().len());
        let mut curves = Vec::new();
        let mut owners = Vec::new();
        for (i, s) in doc.strokes().iter().enumerate() {
            let shown = replay.map_or(s.stroke.samples.len(), |r| r.visible_samples(i));
            let complete = shown >= s.stroke.samples.len();
            strokes.push(if complete {
                s.stroke.clone()
            } else {
                Stroke::new(s.stroke.samples[..shown].to_vec())
            });
            if let (true, Some(FitState::Done(pieces))) = (complete, fits.get(s)) {
                for (k, piece) in pieces.iter().enumerate() {
                    let mut piece = piece.clone();
                    piece.stroke = i;
                    curves.push(piece);
                    owners.push((s.id, k));
                }
            }
        }
        SceneData {
            units: doc.units(),
            strokes,
            curves,
            owners,
            key: Self::key_of(doc, fits, replay),
        }
    }

    /// The key a scene built now would have.
    pub fn key_of(doc: &Document, fits: &Fits, replay: Option<&Replay>) -> (u64, u64, u64) {
        (
            doc.changes(),
            fits.generation(),
            replay.map_or(0, Replay::frame),
        )
    }

    /// A single number that changes with the key (for the canvas's cache).
    pub fn hash_key(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        self.key.hash(&mut h);
        h.finish()
    }

    /// The borrowed scene for the renderer.
    pub fn scene(&self) -> Scene<'_> {
        Scene::new(&self.strokes, &self.curves, self.units)
    }

    /// The curve index and segment index of a selection, for the renderer's highlight.
    pub fn highlight(&self, selection: Option<Selection>) -> Option<(usize, usize)> {
        let s = selection?;
        let curve = self
            .owners
            .iter()
            .position(|&(id, piece)| id == s.stroke && piece == s.piece)?;
        let chain = self.curves[curve].chain.as_ref()?;
        (s.segment < chain.segments.len()).then_some((curve, s.segment))
    }

    /// The selected segment with its curve.
    pub fn selected(&self, selection: Option<Selection>) -> Option<(&CurveFit, &ChainSegment)> {
        let (curve, segment) = self.highlight(selection)?;
        let fit = &self.curves[curve];
        Some((fit, fit.chain.as_ref()?.segments.get(segment)?))
    }

    /// Every segment with its selection, in drawing order.
    pub fn segments(&self) -> impl Iterator<Item = (Selection, usize, &ChainSegment)> {
        self.curves
            .iter()
            .zip(&self.owners)
            .filter_map(|(c, &(id, piece))| c.chain.as_ref().map(|ch| (c.stroke, id, piece, ch)))
            .flat_map(|(stroke, id, piece, chain)| {
                chain.segments.iter().enumerate().map(move |(k, seg)| {
                    (
                        Selection {
                            stroke: id,
                            piece,
                            segment: k,
                        },
                        stroke,
                        seg,
                    )
                })
            })
    }

    /// The segment nearest to `p` within `radius` (model units), if any: what a click at `p`
    /// selects. Distances are to the segment traced at a tenth of `radius`.
    pub fn pick(&self, p: crate::geom::Point, radius: f64) -> Option<Selection> {
        if !(radius > 0.0 && p.x.is_finite() && p.y.is_finite()) {
            return None;
        }
        let chord = PICK_CHORD_FRACTION * radius;
        self.segments()
            .map(|(selection, _, seg)| {
                let d = crate::lac::rough_deviation(&seg.segment, &[p], chord);
                (selection, d.max)
            })
            .filter(|(_, d)| *d <= radius)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(selection, _)| selection)
    }

    /// The fits as the pipeline's output, for export (`tolerance`: the one reported).
    pub fn output(&self, tolerance: f64) -> FitOutput {
        FitOutput::with_curves(self.units, tolerance, self.curves.clone())
    }
}
