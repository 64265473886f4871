use serde::Serialize;

use crate::bspline::BSpline;
use crate::bspline::project::Pieces;
use crate::geom::{Point, Vec2};
use crate::lac::{AlphaChoice, AlphaSearch, LacError, LacSegment, SpanFit, biarc, fit_span};
use crate::split::{Spans, SplitKind};

/// Distances to a segment are computed on a polyline whose chord error is this fraction of the
/// tolerance: a thousandth leaves every tolerance decision exact in practice.
const CHORD_ERROR_FRACTION: f64 = 1e-3;

/// A span holding fewer samples than this is fitted against points of its B-spline instead
/// (evenly spaced in the parameter): with one or two samples the α search has nothing to choose
/// by, and a short span's shape is the B-spline's anyway.
const MIN_SPAN_SAMPLES: usize = 3;

/// Number of B-spline points standing in for the samples of a short span.
const SPAN_REFERENCE_POINTS: usize = 8;

/// Options of [`fit_chain`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainOptions {
    /// α allowed per segment. Default: the range [−3, 3] ([`AlphaChoice::default`]).
    pub alpha: AlphaChoice,
    /// How many times a span may be halved to meet the tolerance. Default 6 (64 segments per
    /// span at most): beyond that the B-spline's own error, not the segment's, is what remains.
    pub max_depth: usize,
    /// Merge neighbours that one segment covers within the tolerance. Default true.
    pub merge: bool,
}

impl Default for ChainOptions {
    fn default() -> Self {
        ChainOptions {
            alpha: AlphaChoice::default(),
            max_depth: 6,
            merge: true,
        }
    }
}

/// What a joint between segments (or an end of the chain) is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum JointKind {
    /// The start of the piece.
    Start,
    /// The end of the piece.
    End,
    /// A corner shared with the neighbouring piece.
    Corner,
    /// An inflection of the B-spline.
    Inflection,
    /// A curvature extremum of the B-spline.
    CurvatureExtremum,
    /// A joint added to meet the tolerance.
    Subdivision,
}

impl From<SplitKind> for JointKind {
    fn from(k: SplitKind) -> Self {
        match k {
            SplitKind::Start => JointKind::Start,
            SplitKind::End => JointKind::End,
            SplitKind::Corner => JointKind::Corner,
            SplitKind::Inflection => JointKind::Inflection,
            SplitKind::CurvatureExtremum => JointKind::CurvatureExtremum,
        }
    }
}

/// One segment of the chain.
#[derive(Clone, Debug)]
pub struct ChainSegment {
    /// The log-aesthetic segment.
    pub segment: LacSegment,
    /// Inclusive range of the stroke's sample indices it represents.
    pub samples: (usize, usize),
    /// Largest distance from those samples to the segment.
    pub max_deviation: f64,
    /// Root mean square of those distances.
    pub rms_deviation: f64,
    /// The α search that chose it.
    pub search: AlphaSearch,
    /// What its start joint is.
    pub start: JointKind,
    /// What its end joint is.
    pub end: JointKind,
    /// Its B-spline parameter interval.
    pub u: (f64, f64),
}

/// The chain of one piece.
#[derive(Clone, Debug)]
pub struct Chain {
    /// The segments, in order.
    pub segments: Vec<ChainSegment>,
    /// Largest sample distance over all segments.
    pub max_deviation: f64,
    /// Whether every sample is within the tolerance.
    pub within_tolerance: bool,
}

/// Why a chain could not be built.
#[derive(Debug, thiserror::Error)]
pub enum ChainError {
    /// The input is inconsistent (lengths differ, no spans).
    #[error("inconsistent chain input: {0}")]
    Input(&'static str),
    /// No segment could join a span's G1 data, even subdivided.
    #[error("span u = {u0}..{u1}: {source}")]
    Span {
        /// Start parameter.
        u0: f64,
        /// End parameter.
        u1: f64,
        /// The cause.
        source: LacError,
    },
}

/// What [`fit_chain`] works from.
#[derive(Clone, Copy, Debug)]
pub struct ChainInput<'a> {
    /// Distinct sample positions, in stroke order.
    pub points: &'a [Point],
    /// Each point's B-spline parameter (its foot point).
    pub params: &'a [f64],
    /// Each point's original sample index.
    pub indices: &'a [usize],
    /// The inclusive original sample range of the piece.
    pub samples: (usize, usize),
    /// The B-spline.
    pub curve: &'a BSpline,
    /// Its spans.
    pub spans: &'a Spans,
}

/// Fits the chain (see the module doc).
pub fn fit_chain(
    input: &ChainInput,
    tolerance: f64,
    options: &ChainOptions,
) -> Result<Chain, ChainError> {
    if input.points.len() != input.params.len() || input.points.len() != input.indices.len() {
        return Err(ChainError::Input(
            "points, params and indices differ in length",
        ));
    }
    if input.spans.spans.is_empty() {
        return Err(ChainError::Input("no spans"));
    }
    options
        .alpha
        .validate()
        .map_err(|source| ChainError::Span {
            u0: 0.0,
            u1: 0.0,
            source,
        })?;
    let fitter = Fitter::new(input, tolerance, options);
    let mut segments = Vec::new();
    for span in &input.spans.spans {
        fitter.fit_interval(
            span.u0,
            span.u1,
            span.start.into(),
            span.end.into(),
            0,
            &mut segments,
        )?;
    }
    if options.merge {
        fitter.merge(&mut segments);
    }
    fitter.assign_sample_ranges(&mut segments);
    let max_deviation = segments.iter().map(|s| s.max_deviation).fold(0.0, f64::max);
    Ok(Chain {
        segments,
        max_deviation,
        within_tolerance: max_deviation <= tolerance,
    })
}

/// The state shared by the fitting steps.
struct Fitter<'a> {
    input: &'a ChainInput<'a>,
    pieces: Pieces,
    /// Point indices sorted by parameter.
    order: Vec<usize>,
    tolerance: f64,
    options: &'a ChainOptions,
}

impl<'a> Fitter<'a> {
    fn new(input: &'a ChainInput<'a>, tolerance: f64, options: &'a ChainOptions) -> Self {
        let mut order: Vec<usize> = (0..input.points.len()).collect();
        order.sort_by(|&i, &j| input.params[i].total_cmp(&input.params[j]).then(i.cmp(&j)));
        Fitter {
            input,
            pieces: Pieces::new(input.curve.to_beziers()),
            order,
            tolerance,
            options,
        }
    }

    /// Position and unit tangent of the B-spline at `u`.
    fn g1(&self, u: f64) -> (Point, Vec2) {
        let (p, d1, _) = self.pieces.eval_derivs(u);
        (p, d1.normalize())
    }

    /// The samples whose parameter lies in `[u0, u1)` (`[u0, u1]` at the end of the curve), in
    /// parameter order.
    fn samples_in(&self, u0: f64, u1: f64) -> Vec<Point> {
        let end = self.pieces.domain().1;
        self.order
            .iter()
            .map(|&i| (self.input.params[i], self.input.points[i]))
            .filter(|&(u, _)| u >= u0 && (u < u1 || (u1 >= end && u <= u1)))
            .map(|(_, p)| p)
            .collect()
    }

    /// Fits one segment on `[u0, u1]` against its samples (or B-spline points when it has too
    /// few); the deviation is always measured on the real samples.
    fn fit_one(&self, u0: f64, u1: f64) -> Result<SpanFit, LacError> {
        let (a, ta) = self.g1(u0);
        let (b, tb) = self.g1(u1);
        let samples = self.samples_in(u0, u1);
        let chord = CHORD_ERROR_FRACTION * self.tolerance;
        if samples.len() >= MIN_SPAN_SAMPLES {
            return fit_span(a, ta, b, tb, &samples, self.options.alpha, chord);
        }
        let reference: Vec<Point> = (0..SPAN_REFERENCE_POINTS)
            .map(|i| {
                let f = (i as f64 + 0.5) / SPAN_REFERENCE_POINTS as f64;
                self.pieces.eval_derivs(u0 + f * (u1 - u0)).0
            })
            .collect();
        let mut fit = fit_span(a, ta, b, tb, &reference, self.options.alpha, chord)?;
        fit.deviation = crate::lac::deviation(&fit.segment, &samples, chord);
        Ok(fit)
    }

    /// Fits `[u0, u1]`, halving it while the tolerance fails, and appends the segments.
    fn fit_interval(
        &self,
        u0: f64,
        u1: f64,
        start: JointKind,
        end: JointKind,
        depth: usize,
        out: &mut Vec<ChainSegment>,
    ) -> Result<(), ChainError> {
        let fit = self.fit_one(u0, u1);
        let good = matches!(&fit, Ok(f) if f.deviation.max <= self.tolerance);
        if good || depth >= self.options.max_depth {
            match fit {
                Ok(fit) => out.push(segment_of(fit, start, end, (u0, u1))),
                // No log-aesthetic segment joins this (tiny, sharply turning) span: two circular
                // arcs always do, keeping the chain G1.
                Err(_) => out.extend(self.biarc_segments(u0, u1, start, end)?),
            }
            return Ok(());
        }
        let um = 0.5 * (u0 + u1);
        self.fit_interval(u0, um, start, JointKind::Subdivision, depth + 1, out)?;
        self.fit_interval(um, u1, JointKind::Subdivision, end, depth + 1, out)
    }

    /// The biarc on `[u0, u1]` as two chain segments (their joint is a subdivision).
    fn biarc_segments(
        &self,
        u0: f64,
        u1: f64,
        start: JointKind,
        end: JointKind,
    ) -> Result<[ChainSegment; 2], ChainError> {
        let (a, ta) = self.g1(u0);
        let (b, tb) = self.g1(u1);
        let [s0, s1] = biarc(a, ta, b, tb).map_err(|source| ChainError::Span { u0, u1, source })?;
        let samples = self.samples_in(u0, u1);
        let chord = CHORD_ERROR_FRACTION * self.tolerance;
        let um = 0.5 * (u0 + u1);
        // Each sample's distance to the biarc is the smaller of its distances to the two arcs;
        // both segments report the biarc's figures (the joint's split of the samples is moot).
        let (d0, d1) = (
            crate::lac::deviation(&s0, &samples, chord),
            crate::lac::deviation(&s1, &samples, chord),
        );
        let distances: Vec<f64> = d0
            .distances
            .iter()
            .zip(&d1.distances)
            .map(|(a, b)| a.min(*b))
            .collect();
        let max = distances.iter().copied().fold(0.0, f64::max);
        let rms = if distances.is_empty() {
            0.0
        } else {
            (distances.iter().map(|x| x * x).sum::<f64>() / distances.len() as f64).sqrt()
        };
        let make = |segment: LacSegment, start, end, u| {
            let deviation = crate::lac::Deviation {
                distances: Vec::new(),
                feet: Vec::new(),
                max,
                rms,
            };
            segment_of(
                SpanFit {
                    segment,
                    deviation,
                    search: AlphaSearch::default(),
                },
                start,
                end,
                u,
            )
        };
        let (first, second) = (
            make(s0, start, JointKind::Subdivision, (u0, um)),
            make(s1, JointKind::Subdivision, end, (um, u1)),
        );
        Ok([first, second])
    }

    /// Merges neighbours across curvature extrema and subdivision joints while one segment
    /// covers both within the tolerance.
    fn merge(&self, segments: &mut Vec<ChainSegment>) {
        let mut i = 0;
        while i + 1 < segments.len() {
            let joint = segments[i].end;
            let mergeable = matches!(joint, JointKind::CurvatureExtremum | JointKind::Subdivision);
            if mergeable {
                let (u0, u1) = (segments[i].u.0, segments[i + 1].u.1);
                if let Ok(fit) = self.fit_one(u0, u1)
                    && fit.deviation.max <= self.tolerance
                {
                    let merged = segment_of(fit, segments[i].start, segments[i + 1].end, (u0, u1));
                    segments.splice(i..=i + 1, [merged]);
                    // The merged segment may now merge with its left neighbour.
                    i = i.saturating_sub(1);
                    continue;
                }
            }
            i += 1;
        }
    }

    /// Sets each segment's original sample range from the samples its interval holds; the
    /// chain's ends take the piece's ends.
    fn assign_sample_ranges(&self, segments: &mut [ChainSegment]) {
        let n = segments.len();
        let mut previous_end = self.input.samples.0;
        for (k, seg) in segments.iter_mut().enumerate() {
            let end_of_curve = k + 1 == n;
            let held: Vec<usize> = self
                .order
                .iter()
                .filter(|&&i| {
                    let u = self.input.params[i];
                    u >= seg.u.0 && (u < seg.u.1 || (end_of_curve && u <= seg.u.1))
                })
                .map(|&i| self.input.indices[i])
                .collect();
            let first = if k == 0 {
                self.input.samples.0
            } else {
                held.iter().copied().min().unwrap_or(previous_end)
            };
            let last = if end_of_curve {
                self.input.samples.1
            } else {
                held.iter().copied().max().unwrap_or(first)
            };
            seg.samples = (first, last.max(first));
            previous_end = seg.samples.1;
        }
    }
}

fn segment_of(fit: SpanFit, start: JointKind, end: JointKind, u: (f64, f64)) -> ChainSegment {
    ChainSegment {
        max_deviation: fit.deviation.max,
        rms_deviation: fit.deviation.rms,
        segment: fit.segment,
        samples: (0, 0),
        search: fit.search,
        start,
        end,
        u,
    }
}
