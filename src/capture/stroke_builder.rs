//! Cutting a stream of timed pen reports into strokes: [`StrokeBuilder`].
//!
//! A stroke is one contact run: from the first report with [`PenReport::contact`] to the last
//! before a report without it. Contact is the Tip Switch or, for the eraser end, the Eraser
//! switch (many pens report an eraser touch with Eraser set and Tip Switch clear); a descriptor
//! with neither switch falls back to pressure above its minimum (see [`PenLayout::decode`]).
//! Eraser strokes (Invert or Eraser set when the run starts) are kept and marked
//! [`Tool::Eraser`]; a change of tool within contact starts a new stroke. Hover reports,
//! including those with In Range clear that some tablets interleave while hovering, only end a
//! run when they lack contact.
//!
//! A run is kept when it has at least two distinct positions (what [`Stroke::validate`]
//! requires); shorter runs are dropped and counted. A report whose time is earlier than the
//! previous sample of its run is dropped and counted, so that times never decrease.
//!
//! [`PenLayout::decode`]: crate::capture::hid::PenLayout::decode

use crate::capture::hid::PenReport;
use crate::stroke::{Sample, Stroke};

/// Which end of the pen drew a stroke.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tool {
    /// The tip.
    Pen,
    /// The eraser end.
    Eraser,
}

/// A finished stroke with what the builder knows about it.
#[derive(Clone, Debug, PartialEq)]
pub struct BuiltStroke {
    /// The samples: millimetres, seconds, pressure 0..1, tilt in degrees.
    pub stroke: Stroke,
    /// The end of the pen that drew it.
    pub tool: Tool,
}

/// What the builder dropped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BuilderStats {
    /// Contact runs with fewer than two distinct positions.
    pub short_runs_dropped: usize,
    /// Samples dropped because their time was earlier than the previous sample's.
    pub backwards_samples_dropped: usize,
}

/// Accumulates timed pen reports into strokes; see the module documentation.
#[derive(Debug, Default)]
pub struct StrokeBuilder {
    current: Option<BuiltStroke>,
    done: Vec<BuiltStroke>,
    stats: BuilderStats,
}

impl StrokeBuilder {
    /// An empty builder.
    pub fn new() -> Self {
        StrokeBuilder::default()
    }

    /// Feeds one report taken at `t` seconds.
    pub fn push(&mut self, t: f64, report: &PenReport) {
        if !report.contact {
            self.end_run();
            return;
        }
        let tool = if report.is_eraser() {
            Tool::Eraser
        } else {
            Tool::Pen
        };
        if self.current.as_ref().is_some_and(|run| run.tool != tool) {
            self.end_run();
        }
        let run = self.current.get_or_insert_with(|| BuiltStroke {
            stroke: Stroke::default(),
            tool,
        });
        if let Some(prev) = run.stroke.samples.last().and_then(|s| s.t)
            && !(t >= prev)
        {
            self.stats.backwards_samples_dropped += 1;
            return;
        }
        run.stroke.samples.push(Sample {
            x: report.x_mm,
            y: report.y_mm,
            t: Some(t),
            pressure: report.pressure,
            tilt_x: report.tilt_x_deg,
            tilt_y: report.tilt_y_deg,
        });
    }

    /// Ends the run in progress, if any (as a report without contact would).
    pub fn end_run(&mut self) {
        let Some(run) = self.current.take() else {
            return;
        };
        let first = run.stroke.samples.first().map(Sample::point);
        let moved = run.stroke.samples.iter().any(|s| Some(s.point()) != first);
        if moved {
            self.done.push(run);
        } else {
            self.stats.short_runs_dropped += 1;
        }
    }

    /// The strokes finished so far, in order, taken out of the builder (a live consumer calls
    /// this after every batch of reports; the run in progress stays).
    pub fn take_finished(&mut self) -> Vec<BuiltStroke> {
        std::mem::take(&mut self.done)
    }

    /// The run in progress, if any (for drawing it while the pen moves).
    pub fn current(&self) -> Option<&BuiltStroke> {
        self.current.as_ref()
    }

    /// What was dropped so far.
    pub fn stats(&self) -> BuilderStats {
        self.stats
    }

    /// Ends the run in progress and returns the strokes in order, with the drop counts.
    pub fn finish(mut self) -> (Vec<BuiltStroke>, BuilderStats) {
        self.end_run();
        (self.done, self.stats)
    }
}
