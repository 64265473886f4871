//! The log-aesthetic chain of one piece of stroke: LAC segments over the spans of monotonic
//! curvature, curvature-continuous (G2) at every smooth joint by default, G1 or C3 on request.
//!
//! In: a fitted piece of stroke ([`ChainInput`]: its samples, their B-spline parameters, the
//! spans) and the tolerance. Out: a [`Chain`] of [`ChainSegment`]s. The stages, each a room of
//! its own, imports pointing one way (down this list):
//!
//! - [`record`]: the data handed from stage to stage; [`alpha_evidence`]: what an α's record says.
//! - `assign`: which samples each segment represents; `measure`: every distance the chain is
//!   judged by, at one resolution; `soften`: ends turned towards their chords; `solve`: the
//!   banded factorisations.
//! - `g1`: the seed paper's G1 chain (segments over the spans, refined, cut, merged).
//! - [`smooth`]: the G1 chain refitted with one curvature per joint (G2), and its derivative (C3).
//! - `polyline`: the last resort of a chain that misses its tolerance; [`stray`]: a loop between
//!   samples.
//!
//! [`fit_chain`] runs them in that order. Fewer segments are better, as the seed paper's future
//! work asks.

pub mod alpha_evidence;
mod assign;
mod g1;
mod measure;
mod polyline;
pub mod record;
pub mod smooth;
mod soften;
mod solve;
pub mod stray;

pub use alpha_evidence::{
    ALPHA_BOUND_TOLERANCE, ALPHA_DIFFERENCE_STEP, AlphaBound, AlphaSource, UNDETERMINED_ALPHA,
    alpha_uncertainty,
};
pub use record::{
    Chain, ChainError, ChainInput, ChainOptions, ChainSegment, Continuity, JointKind, SeamPose,
};

pub(crate) use measure::{Resolution, distance_on};
use smooth::{SmoothInput, smooth_chain};

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
    let (chain, resolution) = g1::fit_g1(input, tolerance, options)?;
    // Where every cut left a segment beyond the tolerance, its samples zigzag at the
    // tolerance's scale: they are joined by lines (see `polyline`).
    let last_resort = |chain: Chain| {
        polyline::join_missing(input, &chain, tolerance, resolution.chord_error).unwrap_or(chain)
    };
    if options.continuity == Continuity::G1 {
        return Ok(last_resort(chain));
    }
    // The G1 chain that starts a smooth fit is refined less (`STARTING_CONVERGED_RMS`); where it
    // ends beyond the tolerance, the G1 chain refined to convergence may not (a jiggle of the
    // synthetic fixtures, see docs/performance-history.md, chain constants),
    // and a smooth fit from a chain beyond the tolerance starts where the guarantee is already
    // lost. The better of the two starts it.
    let chain = if chain.within_tolerance {
        chain
    } else {
        let strict = fit_chain(
            input,
            tolerance,
            &ChainOptions {
                continuity: Continuity::G1,
                ..*options
            },
        );
        match strict {
            Ok(strict) if strict.max_deviation < chain.max_deviation => strict,
            _ => chain,
        }
    };
    let smooth = smooth_chain(&SmoothInput {
        input,
        chain: &chain,
        tolerance,
        chord_error: resolution.chord_error,
        alpha: options.alpha,
        continuity: options.continuity,
    });
    // A smooth chain farther from its samples than the G1 chain it started from is not taken
    // (the guarantee before the continuity), nor one that runs a loop between its samples where
    // the G1 chain does not (see [`stray`]).
    Ok(last_resort(match smooth {
        Some(smooth)
            if (smooth.within_tolerance
                || !chain.within_tolerance && smooth.max_deviation <= chain.max_deviation)
                && (!stray::loops(input, &smooth, tolerance)
                    || stray::loops(input, &chain, tolerance)) =>
        {
            smooth
        }
        _ => chain,
    }))
}
