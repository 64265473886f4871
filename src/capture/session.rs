//! The capture loop: a [`PenSource`] through the [`StrokeBuilder`] into a [`StrokeWriter`]
//! (and optionally a [`RawWriter`]), each stroke written as it ends: [`run_capture`].
//!
//! Strokes are cut exactly as [`StrokeBuilder`] cuts them (one per contact run, a change of tool
//! within contact starts a new one). To see each stroke as soon as it ends, the loop finishes its
//! builder at every point where the builder itself would end a run (a report without contact, or
//! a contact report with the other tool) and starts a fresh one; the strokes are the same as
//! feeding the whole stream to one builder ([`crate::capture::replay`]).
//!
//! The loop stops at the end of the source, when `stop` is set (Ctrl-C), when the duration is
//! reached (by report time or by wall-clock time since the loop started, whichever comes first), or when the source
//! fails (an unplugged tablet). In every case but the end of a recording, the stroke in progress
//! is written after the finished ones ([`StrokeWriter::save_with_partial`]), if it has two
//! distinct positions.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use crate::capture::source::{Decoded, Next, PenSource, SourceError};
use crate::capture::stroke_builder::{BuilderStats, StrokeBuilder, Tool};
use crate::capture::writer::{RawWriter, StrokeWriter, WriteError};

/// Why a capture ended.
#[derive(Debug)]
pub enum EndReason {
    /// The source ran out (end of a recording).
    SourceEnded,
    /// `--duration` reached.
    Duration,
    /// The stop flag was set (Ctrl-C).
    Interrupted,
    /// The source failed; the strokes so far and the one in progress were saved.
    SourceError(SourceError),
}

/// What a capture did.
#[derive(Debug)]
pub struct CaptureSummary {
    /// Why it ended.
    pub end: EndReason,
    /// Reports read.
    pub reports: usize,
    /// Pen reports among them.
    pub pen_reports: usize,
    /// Reports that did not decode (skipped).
    pub decode_errors: usize,
    /// Strokes in the output file, the partial one included.
    pub strokes: usize,
    /// Whether a stroke in progress was saved at the end.
    pub partial_saved: bool,
    /// Runs and samples the builder dropped.
    pub builder: BuilderStats,
}

/// Stop conditions of [`run_capture`].
#[derive(Clone, Copy, Debug, Default)]
pub struct CaptureLimits {
    /// Stop after this many seconds (report time or wall clock, whichever reaches it first).
    pub duration: Option<f64>,
}

/// Tracks the run in progress and hands out each stroke when it ends.
#[derive(Default)]
struct Cutter {
    builder: StrokeBuilder,
    tool: Option<Tool>,
    stats: BuilderStats,
}

impl Cutter {
    /// Ends the builder's run: the finished stroke, if it was kept.
    fn flush(&mut self) -> Option<crate::capture::stroke_builder::BuiltStroke> {
        self.tool = None;
        let (mut built, stats) = std::mem::take(&mut self.builder).finish();
        self.stats.short_runs_dropped += stats.short_runs_dropped;
        self.stats.backwards_samples_dropped += stats.backwards_samples_dropped;
        built.pop()
    }

    /// Feeds one report; a stroke when the report ended one.
    fn push(
        &mut self,
        t: f64,
        report: &crate::capture::hid::PenReport,
    ) -> Option<crate::capture::stroke_builder::BuiltStroke> {
        let tool = if report.is_eraser() {
            Tool::Eraser
        } else {
            Tool::Pen
        };
        let ends = !report.contact || self.tool.is_some_and(|current| current != tool);
        let done = if ends { self.flush() } else { None };
        if report.contact {
            self.builder.push(t, report);
            self.tool = Some(tool);
        }
        done
    }
}

/// Runs a capture; see the module documentation. Write errors end it with an error (the file
/// on disk then still holds every stroke written before).
pub fn run_capture(
    source: &mut dyn PenSource,
    writer: &mut StrokeWriter,
    mut raw: Option<&mut RawWriter>,
    stop: &AtomicBool,
    limits: CaptureLimits,
    mut on_stroke: impl FnMut(usize, &crate::stroke::Stroke),
) -> Result<CaptureSummary, WriteError> {
    let started = Instant::now();
    let mut cutter = Cutter::default();
    let mut summary = CaptureSummary {
        end: EndReason::SourceEnded,
        reports: 0,
        pen_reports: 0,
        decode_errors: 0,
        strokes: 0,
        partial_saved: false,
        builder: BuilderStats::default(),
    };
    let over = |t: f64| limits.duration.is_some_and(|d| t >= d);
    let end = loop {
        if stop.load(Ordering::Relaxed) {
            break EndReason::Interrupted;
        }
        let event = match source.next() {
            Ok(Next::Event(e)) => e,
            Ok(Next::Idle) => {
                if over(started.elapsed().as_secs_f64()) {
                    break EndReason::Duration;
                }
                continue;
            }
            Ok(Next::End) => break EndReason::SourceEnded,
            Err(e) => break EndReason::SourceError(e),
        };
        if over(event.t) || over(started.elapsed().as_secs_f64()) {
            break EndReason::Duration;
        }
        summary.reports += 1;
        if let (Some(w), Some(bytes)) = (raw.as_deref_mut(), &event.raw) {
            w.report(event.t, bytes)?;
        }
        match &event.decoded {
            Decoded::Pen(report) => {
                summary.pen_reports += 1;
                if let Some(done) = cutter.push(event.t, report) {
                    on_stroke(writer.strokes().len(), &done.stroke);
                    writer.push(done)?;
                }
            }
            Decoded::Other => {}
            Decoded::Error(_) => summary.decode_errors += 1,
        }
    };
    let last = cutter.flush();
    match (&end, last) {
        (_, None) => {}
        (EndReason::SourceEnded, Some(done)) => {
            on_stroke(writer.strokes().len(), &done.stroke);
            writer.push(done)?;
        }
        (_, Some(partial)) => {
            on_stroke(writer.strokes().len(), &partial.stroke);
            writer.save_with_partial(Some(partial))?;
            summary.partial_saved = true;
        }
    }
    summary.end = end;
    summary.strokes = writer.strokes().len() + usize::from(summary.partial_saved);
    summary.builder = cutter.stats;
    Ok(summary)
}
