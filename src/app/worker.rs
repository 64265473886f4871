//! Fitting off the UI thread: [`FitWorker`] runs the pipeline on a background thread, [`Fits`]
//! holds the results the UI draws.
//!
//! Every job names the stroke ([`StrokeId`]) and the stroke's revision it was made for. The worker
//! skips queued jobs that a newer job for the same stroke has superseded, and [`Fits::accept`]
//! drops a result whose revision is no longer the stroke's: a fit never lands on a stroke that has
//! changed since it was asked for. The UI thread only sends jobs and polls results; it never
//! waits for the worker.

use std::collections::HashMap;
use std::sync::mpsc::{Receiver, Sender, TryRecvError, channel};
use std::thread::JoinHandle;

use super::document::{DocStroke, Document, StrokeId};
use crate::pipeline::{CurveFit, StrokeOutcome, fit_with_noise};
use crate::stroke::{Stroke, Units};

/// One stroke to fit.
#[derive(Clone, Debug)]
pub struct FitJob {
    /// The stroke.
    pub id: StrokeId,
    /// Its revision when the job was made.
    pub revision: u64,
    /// The samples.
    pub stroke: Stroke,
    /// Their units (for the default tolerance).
    pub units: Units,
    /// The pipeline options.
    pub options: crate::pipeline::PipelineOptions,
}

impl FitJob {
    /// The job for a document stroke.
    pub fn for_stroke(stroke: &DocStroke, units: Units) -> Self {
        FitJob {
            id: stroke.id,
            revision: stroke.revision,
            stroke: stroke.stroke.clone(),
            units,
            options: stroke.settings.pipeline_options(),
        }
    }

    /// Runs the pipeline (on whatever thread calls it).
    pub fn run(&self) -> FitResult {
        // A tap (a stroke within the tolerance of one point) has no curve to draw: its samples
        // show it.
        let outcome = match fit_with_noise(&self.stroke, 0, self.units, &self.options) {
            StrokeOutcome::Curves(curves) => Ok(curves),
            StrokeOutcome::Dot(_) => Ok(Vec::new()),
            StrokeOutcome::Failed(failure) => Err(failure.message),
        };
        FitResult {
            id: self.id,
            revision: self.revision,
            outcome,
        }
    }
}

/// A finished job.
#[derive(Clone, Debug)]
pub struct FitResult {
    /// The stroke.
    pub id: StrokeId,
    /// The revision it was computed for.
    pub revision: u64,
    /// The fitted pieces (their `stroke` field is 0: the app numbers strokes when it draws), or
    /// why the pipeline failed.
    pub outcome: Result<Vec<CurveFit>, String>,
}

/// The state of one stroke's fit.
#[derive(Clone, Debug)]
pub enum FitState {
    /// Asked for, not back yet.
    Pending,
    /// The fitted pieces.
    Done(Vec<CurveFit>),
    /// The pipeline's error message.
    Failed(String),
}

/// The latest fit of each stroke, with the revision it belongs to.
#[derive(Clone, Debug, Default)]
pub struct Fits {
    states: HashMap<StrokeId, (u64, FitState)>,
    /// Bumped whenever a fit lands or is forgotten, so views can cache what they derive.
    generation: u64,
}

impl Fits {
    /// The fit of a stroke at its current revision (`None`: never asked for, or out of date).
    pub fn get(&self, stroke: &DocStroke) -> Option<&FitState> {
        self.states
            .get(&stroke.id)
            .filter(|(revision, _)| *revision == stroke.revision)
            .map(|(_, state)| state)
    }

    /// Changes whenever what [`Fits::get`] returns may have changed.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// The jobs needed to bring every stroke of `doc` up to date, each marked pending.
    pub fn missing(&mut self, doc: &Document) -> Vec<FitJob> {
        let mut jobs = Vec::new();
        for stroke in doc.strokes() {
            if self.get(stroke).is_none() {
                self.states
                    .insert(stroke.id, (stroke.revision, FitState::Pending));
                jobs.push(FitJob::for_stroke(stroke, doc.units()));
            }
        }
        // Forget strokes that are gone (undo keeps them in the history, with their samples: a
        // redo refits them).
        let before = self.states.len();
        self.states
            .retain(|id, _| doc.strokes().iter().any(|s| s.id == *id));
        if !jobs.is_empty() || self.states.len() != before {
            self.generation += 1;
        }
        jobs
    }

    /// Takes a result in if it is for the stroke's current revision; returns whether it was.
    pub fn accept(&mut self, result: FitResult, doc: &Document) -> bool {
        let current = doc
            .find(result.id)
            .is_some_and(|(_, s)| s.revision == result.revision);
        if !current {
            return false;
        }
        let state = match result.outcome {
            Ok(curves) => FitState::Done(curves),
            Err(message) => FitState::Failed(message),
        };
        self.states.insert(result.id, (result.revision, state));
        self.generation += 1;
        true
    }

    /// Whether some stroke of `doc` is waiting for its fit.
    pub fn any_pending(&self, doc: &Document) -> bool {
        doc.strokes()
            .iter()
            .any(|s| matches!(self.get(s), None | Some(FitState::Pending)))
    }
}

/// A background thread that fits strokes; results come back through [`FitWorker::poll`].
pub struct FitWorker {
    jobs: Option<Sender<FitJob>>,
    results: Receiver<FitResult>,
    thread: Option<JoinHandle<()>>,
}

impl std::fmt::Debug for FitWorker {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FitWorker").finish_non_exhaustive()
    }
}

impl FitWorker {
    /// Starts the thread; `wake` is called after each result (the app asks egui to repaint).
    pub fn spawn(wake: Box<dyn Fn() + Send>) -> std::io::Result<Self> {
        let (job_tx, job_rx) = channel::<FitJob>();
        let (result_tx, result_rx) = channel();
        let thread = std::thread::Builder::new()
            .name("kansei-fit".into())
            .spawn(move || worker_loop(&job_rx, &result_tx, &*wake))?;
        Ok(FitWorker {
            jobs: Some(job_tx),
            results: result_rx,
            thread: Some(thread),
        })
    }

    /// Queues a job. Never blocks.
    pub fn send(&self, job: FitJob) {
        if let Some(jobs) = &self.jobs {
            // A send fails only when the thread has ended (it panicked): nothing then fits,
            // which the app shows as strokes pending; there is no one to report to here.
            let _ = jobs.send(job);
        }
    }

    /// The results that have arrived. Never blocks.
    pub fn poll(&self) -> Vec<FitResult> {
        let mut out = Vec::new();
        loop {
            match self.results.try_recv() {
                Ok(result) => out.push(result),
                Err(TryRecvError::Empty | TryRecvError::Disconnected) => return out,
            }
        }
    }
}

impl Drop for FitWorker {
    fn drop(&mut self) {
        // Closing the job channel ends the loop after the job in hand.
        self.jobs = None;
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// Runs jobs until the sender is dropped. Of several queued jobs for one stroke only the last
/// runs: the earlier ones are stale by construction.
fn worker_loop(jobs: &Receiver<FitJob>, results: &Sender<FitResult>, wake: &dyn Fn()) {
    while let Ok(first) = jobs.recv() {
        let mut batch = vec![first];
        batch.extend(jobs.try_iter());
        let batch = latest_per_stroke(batch);
        for job in batch {
            if results.send(job.run()).is_err() {
                return;
            }
            wake();
        }
    }
}

/// Keeps, for each stroke, only its last job, in the order those last jobs were queued.
pub fn latest_per_stroke(jobs: Vec<FitJob>) -> Vec<FitJob> {
    let mut last: HashMap<StrokeId, usize> = HashMap::new();
    for (i, job) in jobs.iter().enumerate() {
        last.insert(job.id, i);
    }
    jobs.into_iter()
        .enumerate()
        .filter(|(i, job)| last.get(&job.id) == Some(i))
        .map(|(_, job)| job)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::document::{Edit, FitSettings};
    use crate::geom::Point;

    fn arc() -> Stroke {
        Stroke::from_points((0..=60).map(|d| {
            let a = (d as f64).to_radians();
            Point::new(40.0 * a.cos(), 40.0 * a.sin())
        }))
    }

    fn doc_with_arc() -> (Document, StrokeId) {
        let mut doc = Document::default();
        let id = doc
            .apply(Edit::AddStroke {
                stroke: arc(),
                settings: FitSettings::default(),
            })
            .ok()
            .flatten()
            .map_or(StrokeId(u64::MAX), |id| id);
        (doc, id)
    }

    #[test]
    fn a_result_for_an_old_revision_is_dropped() {
        let (mut doc, id) = doc_with_arc();
        let mut fits = Fits::default();
        let jobs = fits.missing(&doc);
        assert_eq!(jobs.len(), 1);
        let old = jobs[0].run();
        // The settings change before the result lands.
        doc.apply(Edit::SetSettings {
            id,
            settings: FitSettings {
                tolerance: Some(0.5),
                ..FitSettings::default()
            },
        })
        .ok();
        assert!(!fits.accept(old, &doc));
        assert!(fits.get(&doc.strokes()[0]).is_none());
        let jobs = fits.missing(&doc);
        assert_eq!(jobs.len(), 1);
        assert!(matches!(
            fits.get(&doc.strokes()[0]),
            Some(FitState::Pending)
        ));
        assert!(fits.accept(jobs[0].run(), &doc));
        assert!(matches!(fits.get(&doc.strokes()[0]), Some(FitState::Done(c)) if !c.is_empty()));
        assert!(!fits.any_pending(&doc));
    }

    #[test]
    fn a_result_for_a_removed_stroke_is_dropped() {
        let (mut doc, id) = doc_with_arc();
        let mut fits = Fits::default();
        let job = fits.missing(&doc).remove(0);
        doc.apply(Edit::RemoveStroke(id)).ok();
        assert!(!fits.accept(job.run(), &doc));
    }

    #[test]
    fn only_the_latest_job_per_stroke_runs() {
        let (doc, _) = doc_with_arc();
        let base = FitJob::for_stroke(&doc.strokes()[0], doc.units());
        let job = |id: u64, revision: u64| FitJob {
            id: StrokeId(id),
            revision,
            ..base.clone()
        };
        let kept = latest_per_stroke(vec![job(1, 1), job(2, 2), job(1, 3), job(3, 4), job(2, 5)]);
        let ids: Vec<(u64, u64)> = kept.iter().map(|j| (j.id.0, j.revision)).collect();
        assert_eq!(ids, vec![(1, 3), (3, 4), (2, 5)]);
    }

    #[test]
    fn the_worker_thread_returns_the_fit() {
        let (doc, id) = doc_with_arc();
        let worker = FitWorker::spawn(Box::new(|| {}));
        let Ok(worker) = worker else {
            panic!("could not start the worker thread");
        };
        worker.send(FitJob::for_stroke(&doc.strokes()[0], doc.units()));
        // Blocking here is the test's choice; the app only polls.
        let mut results = Vec::new();
        while results.is_empty() {
            results = worker.poll();
            std::thread::yield_now();
        }
        assert_eq!(results[0].id, id);
        assert!(results[0].outcome.is_ok());
    }
}
