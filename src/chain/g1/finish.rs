//! The G1 chain's record: placeholder α searched again, each segment's sample range, distances
//! and α evidence, and the chain's largest distance.

use super::Fitter;
use super::state::State;
use crate::chain::alpha_evidence::{
    ALPHA_DIFFERENCE_STEP, AlphaBound, AlphaSource, alpha_uncertainty,
};
use crate::chain::assign::{param_interval, tile_ranges};
use crate::chain::measure::own_deviation;
use crate::chain::record::{Chain, ChainError, ChainSegment, Continuity};
use crate::lac::{AlphaChoice, AlphaSearch, LacSegment};

impl<'a> Fitter<'a> {
    /// The output segments with their sample ranges and deviations.
    ///
    /// Sample ranges tile the piece in order: every segment holds a run of consecutive samples
    /// (its samples' parameters are non-decreasing along the stroke, see [`Fitter::new`]), and
    /// its range runs from the first of them (the piece's first sample for the first segment)
    /// to the sample before the next segment's first (the piece's last for the last segment),
    /// so merged duplicates belong to the segment of the sample they were merged into. A
    /// segment that holds no sample (it bridges the gap between two consecutive samples; its
    /// `params` is `None`) has the one-sample range of the sample before it, shared with the
    /// segment before it (with the next one's first if it is the first segment).
    ///
    /// A segment's `max_deviation` is over the samples it holds; the chain's is the largest of
    /// each sample's distance to its own segment ([`own_deviation`]), so that
    /// `within_tolerance` and `max_deviation` state the guarantee itself, with no other pass of
    /// a stroke that comes back near itself standing in for a segment that left its samples.
    pub(super) fn finish(
        &self,
        state: &State,
        mut searches: Vec<AlphaSearch>,
    ) -> Result<Chain, ChainError> {
        let n = state.len();
        // A spiral whose α no search chose (a placeholder where a search found nothing, or a
        // line or arc the refinement bent since) is searched now between its final joints; the
        // searched α is kept where it fits the samples no worse than the one it replaces, or
        // within the tolerance.
        let mut state = state.clone();
        for k in 0..n {
            let placeholder = searches[k].evaluations == 0
                && state.segment(k).is_ok_and(|seg| seg.alpha().is_some());
            if !placeholder {
                continue;
            }
            let before = state
                .evaluate(k, self.resolution.chord_error)
                .map(|e| e.max);
            let mut trial = state.clone();
            let mut trial_searches = searches.clone();
            self.research(&mut trial, &mut trial_searches, k);
            let after = trial
                .evaluate(k, self.resolution.chord_error)
                .map(|e| e.max);
            if let (Ok(after), before) = (after, before)
                && trial_searches[k].evaluations > 0
                && before.map_or(true, |b| after <= b.max(self.resolution.tolerance))
            {
                state = trial;
                searches = trial_searches;
            }
        }
        let state = &state;
        let mut segments = Vec::with_capacity(n);
        let evaluated = (0..n)
            .map(|k| state.evaluate(k, self.resolution.chord_error))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|source| ChainError::Span {
                u0: 0.0,
                u1: 0.0,
                source,
            })?;
        // Each segment's first original sample index (None when it holds none).
        let starts: Vec<Option<usize>> = (0..n)
            .map(|k| {
                state.samples[k]
                    .iter()
                    .map(|&i| self.input.indices[i])
                    .min()
            })
            .collect();
        let ranges = tile_ranges(&starts, self.input.samples);
        for (k, (search, evaluated)) in searches.into_iter().zip(&evaluated).enumerate() {
            let distances = &evaluated.residuals[..state.samples[k].len()];
            let rms = if distances.is_empty() {
                0.0
            } else {
                (distances.iter().map(|r| r * r).sum::<f64>() / distances.len() as f64).sqrt()
            };
            let params = param_interval(&self.params, &state.samples[k]);
            let range = ranges[k];
            let alpha = evaluated.segment.alpha();
            segments.push(ChainSegment {
                segment: evaluated.segment,
                samples: range,
                max_deviation: evaluated.max,
                rms_deviation: rms,
                alpha_source: AlphaSource::of_g1(alpha, &search, self.options.alpha),
                search,
                start: state.joints[k].kind,
                end: state.joints[k + 1].kind,
                params,
                alpha_bound: AlphaBound::of(alpha, self.options.alpha),
                alpha_uncertainty: self.alpha_uncertainty(state, k, evaluated),
            });
        }
        let max_deviation = self.chain_deviation(state, &evaluated);
        Ok(Chain {
            segments,
            max_deviation,
            within_tolerance: max_deviation <= self.resolution.tolerance,
            refined: self.options.refine,
            continuity: Continuity::G1,
        })
    }

    /// The standard error of segment `k`'s α given its joints: its samples' distances at α ± h,
    /// the segment rebuilt through the same joints ([`alpha_uncertainty`]). `None` for no α or
    /// a fixed one.
    pub(super) fn alpha_uncertainty(
        &self,
        state: &State,
        k: usize,
        evaluated: &super::state::Evaluated,
    ) -> Option<f64> {
        let alpha = evaluated.segment.alpha()?;
        if matches!(self.options.alpha, AlphaChoice::Fixed(_)) {
            return None;
        }
        let (a, b) = (state.joints[k], state.joints[k + 1]);
        let n = state.samples[k].len();
        let probe = |x: f64| {
            state
                .sample_residuals_with(k, &a, &b, x, evaluated)
                .ok()
                .filter(|r| r.len() >= n)
        };
        let (minus, plus) = (
            probe(alpha - ALPHA_DIFFERENCE_STEP),
            probe(alpha + ALPHA_DIFFERENCE_STEP),
        );
        alpha_uncertainty(
            &evaluated.residuals[..n],
            minus.as_deref().map(|r| &r[..n]),
            plus.as_deref().map(|r| &r[..n]),
        )
    }

    /// The largest distance from a sample to the chain (see [`own_deviation`]).
    pub(super) fn chain_deviation(
        &self,
        state: &State,
        evaluated: &[super::state::Evaluated],
    ) -> f64 {
        let segments: Vec<LacSegment> = evaluated.iter().map(|e| e.segment).collect();
        let own: Vec<Vec<f64>> = evaluated
            .iter()
            .zip(&state.samples)
            .map(|(e, list)| e.residuals[..list.len()].iter().map(|r| r.abs()).collect())
            .collect();
        own_deviation(
            self.input.points,
            &segments,
            &state.samples,
            &own,
            self.resolution.chord_error,
        )
    }
}
