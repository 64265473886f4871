//! Curvature-continuous chains: one curvature per joint (G2) and, on request, one dκ/ds per joint
//! as well (C3, the compound rhythm of Ziatdinov, Miura et al.).
//!
//! ## Two forms of the same chain
//! A chain of n segments is fixed by one signed curvature per joint, κⱼ = σⱼ·e^{uⱼ}
//! (j = 0..n, the sign σⱼ fixed and the log-magnitude uⱼ free, or κⱼ = 0 held fixed at an
//! *inflection joint*, below), and per segment its length Sₖ = e^{vₖ} and its αₖ. Segment k is
//! the LAC with end curvatures κₖ, κₖ₊₁: the curvature of two neighbours at their joint is the
//! one number κₖ₊₁, so G2 holds exactly, not to a tolerance. Where the segments sit is said in
//! one of two ways:
//!
//! * *forward*: the chain is laid out from its start point P₀ and start angle θ₀,
//!   each segment from the end pose of the one before. Position and tangent continuity hold by
//!   construction too; the only position constraint left is the end point Pₑ. There are
//!   1 + (n + 1) + 2n unknowns, one per interior joint fewer than a G1 chain's, as G2 requires.
//!   But every joint turns the rest of the chain: a parameter near the start swings the end,
//!   and the fit crawls: the chain drifts from its samples before it converges.
//! * *shooting*: every segment has its own start pose (Pₖ, θₖ), and the joints' positions and
//!   tangents are equality constraints (three per joint, two for Pₑ). A parameter moves one
//!   segment, two for a joint's curvature: as well conditioned on fifty segments as on two.
//!
//! P₀ and Pₑ are fixed where they are corners (shared with the neighbouring piece or part). At
//! the stroke's own start and end each moves across its tangent by one unknown: the B-spline's
//! end that the G1 chain starts from carries the first sample's noise (on a whole-pixel grid up
//! to half a pixel's diagonal off the curve drawn), and pinned there a smooth chain, with one
//! unknown per joint fewer than a G1 one, pays for it along its whole first segment. Along the
//! tangent an end would slide beyond the last sample at no cost, so it does not move that way.
//!
//! The fit runs in the shooting form; its answer is then moved into the forward form by a few
//! Newton steps on the end point, so that joints meet exactly in the final chain.
//!
//! ## The fit: constrained Levenberg–Marquardt
//! The unknowns minimise Σ rᵢ², rᵢ the signed distance from sample i to its segment, subject to
//! the constraints and, for C3, to dκ/ds⁻ = dκ/ds⁺ at every interior joint with κ ≠ 0. Each step
//! solves the damped Gauss–Newton system with the linearised constraints (a KKT system,
//! Marquardt's scaling with a floor, Nielsen's damping update; an unknown on its bound that the
//! step would push beyond it is held; ordered along the chain, the system is banded and solved in
//! time linear in the segments) and is projected back onto the constraints by least-norm
//! Newton steps with the step's own constraint Jacobian (a chord method; a trial they do not
//! bring onto the constraints is projected again with fresh Jacobians, and refused like one that
//! raises the cost where those fail too), so every iterate is a
//! chain whose joints meet to a tenth of the tolerance (the answer's joints meet exactly once it
//! is laid out forward). The Jacobian: a change of one unknown rebuilds its one or two
//! segments, differenced at the samples' foot points (a pose's columns are those of a rigid
//! motion, and a length's follows from the curvatures' by a scaling identity). Samples near a joint
//! are handed to the neighbour that is nearer after every accepted step: a joint slides along the
//! data as the fit moves it. In the polish towards the least-squares chain, a sample past its
//! segment's end at a joint is measured against the segment's second-order extension there,
//! which the next segment follows to third order at a G2 joint: its distance then changes
//! smoothly as the joint slides past it, where against the end point it has a kink that kept
//! the polish to about a sample per step (`solver.rs`, `EndPose`).
//!
//! Starting point: the G1 chain (its joints' poses, lengths and α). A joint's curvature starts
//! at the B-spline's there (the G1 chain's two sides differ, the C2 B-spline within the
//! tolerance of the same samples has one value), each α at the one that keeps the G1 segment's
//! turning. A G1 segment that bends into a joint the smooth chain holds at κ = 0 (an arc into an
//! inflection) keeps its shape but for a transition spiral at that end, as long as a clothoid
//! whose shift from the arc is the tolerance. Where the first fit ends with an α pressed on its
//! bound while the G1 chain's α lies inside, the fit from the G1 α is run as well and the lower
//! cost kept (a local minimum: a planted S of two clothoids on a pixel grid came back as four
//! segments at α = −3). Where the fit cannot start from there (the first projection onto the
//! constraints fails: 16 parts of the fixture strokes) or does not end within the tolerance for
//! another reason than the curvature bound (below), it is run again with each joint's curvature
//! at the geometric mean of the G1 chain's two sides. Where
//! the joint equations cannot be met from the G1 chain's poses, the chain is laid out forward from
//! its start instead (the joints then meet by construction and only the end point must be moved
//! there) and its poses start the fit. A part of one segment has no joint to make smooth and is
//! kept as it is.
//!
//! ## Inflections and lines
//! A log-aesthetic segment with α ≥ 0 cannot reach κ = 0 at a finite point, so where the chain
//! changes the sign of its curvature the joint is held at κ = 0 and the segments on both sides
//! take α ≤ [`ZERO_END_ALPHA`] (α = −1, the clothoid, is inside that range): what a user gets
//! there is a spiral leaving the inflection, never a tiny segment with a huge curvature. A line
//! of the G1 chain stays a line and its neighbours meet it with κ = 0. A segment between two
//! inflections would have to be a line; it is cut at its middle first. Where the α range allows
//! no negative α (`--alpha 1`, say), an inflection cannot be G2 and the chain stays G1.
//!
//! ## Tolerance and honesty
//! A joint may not bend tighter than a radius of [`MIN_RADIUS_TOLERANCES`] tolerances, nor turn
//! more than [`MAX_TURN_PER_SAMPLE`] between two samples (a tighter bend is a corner the samples
//! cannot tell from a curve), and a segment may not grow beyond [`MAX_LENGTH_FACTOR`] times its
//! starting length nor turn more than [`MAX_EXTRA_TURNING`] beyond its starting turning. A G1
//! joint that bends beyond those bounds (a hook, a needle) becomes a
//! corner of the smooth chain, and the parts between such corners are fitted on their own,
//! between fixed end points. So does a joint the fit presses against the curvature bound while
//! it still misses the tolerance (the G1 joint nearest it), as soon as a round of the fit ends
//! so: the samples ask for a tighter bend there than a smooth chain may make (on the fixture
//! strokes, 18 such corners made 16 more curves G2 throughout; cutting more segments or starting
//! again from other joint curvatures first never found a smooth chain there, and took a third
//! of the painting's smooth fit). And where a part fails whose first (last) segment leaves its
//! corner bending beyond the bound (a hook at a corner, κ = 12 /px on painting strokes), that
//! segment's other joint becomes a corner and it stays as the G1 chain has it, but for its
//! tangents: a segment between two corners has both free (a corner is G0), and where the G1 chain's
//! curl beyond the bound they are turned as the G1 chain's piece ends are (`soften_isolated`). One
//! that still curls beyond the bound at a free end after those turns hooks there, and says so: it
//! becomes the line between its ends where that holds its samples, else a line to the sample next
//! to the curl and a segment on from it, meeting at a new corner (`src/chain/smooth/unhook.rs`).
//! This removes the tight bends for a few more short segments (measured in
//! `docs/performance-history.md`, chain constants). A least-squares chain that misses
//! the tolerance by a little is first refitted towards the minimax fit of the same segments
//! (Lawson's reweighting, a few rounds). When the solved chain still leaves a sample farther than
//! the tolerance from its own segment, every segment that misses is cut at its middle (a new
//! joint with that point's curvature: the two halves are the same curve, so the chain stays on its
//! constraints) and the fit runs again, at most [`MAX_CUT_ROUNDS`] rounds and until
//! [`STALLED_ROUNDS`] rounds in a row bring the worst sample no nearer. When that is not enough, a
//! part has more than [`MAX_SEGMENTS`] segments, or a chain cannot be built at all, the part keeps
//! its G1 segments and the chain says [`Continuity::G1`].
//!
//! ## Files
//! This file holds the bounds and the parts' orchestration (corners, cut rounds); `part.rs` one
//! part's fit from its starts, `removal.rs` the joint removals, `settle.rs` whether a solved chain
//! holds and its polish, `ends.rs` tails and softened isolated ends, `finish.rs` the record;
//! `layout.rs` the unknowns and the two forms, `start.rs` the starting chain and the cuts,
//! `solver.rs` the residuals, joint equations and the samples' assignment, `jacobian.rs` the
//! differenced Jacobians, `normal.rs` the normal equations over their pattern, `project.rs` the
//! projection onto the constraints, `lm.rs` the constrained Levenberg–Marquardt solve and the
//! minimax rounds (damping from `chain::solve::damping`). A segment that still hooks at a corner
//! is cut in `unhook.rs`.

use crate::chain::assign::{own_points, retile};
use crate::chain::measure::measured_deviation;
use crate::chain::record::{Chain, ChainInput, ChainSegment, Continuity, JointKind, SeamPose};
use crate::lac::AlphaChoice;
use crate::lac::alpha_search::SpanFitOptions;
use ends::{curvature_cap, soften_isolated, without_end_tail};
use part::{Missed, smooth_part};

mod ends;
mod finish;
mod jacobian;
mod layout;
mod lm;
mod normal;
mod part;
mod project;
mod removal;
mod settle;
mod solver;
mod start;
mod unhook;

/// Largest α of a segment with a zero-curvature end. ρ^α must reach 0 there, which needs α < 0;
/// close to 0 the segment's curvature leaves zero so steeply (κ ∝ s^{−1/α}) that its evaluation
/// loses accuracy, and no drawn inflection looks like that. −0.05 keeps the whole practical
/// range (the clothoid −1, and the −3..0 the α search offers) open.
pub const ZERO_END_ALPHA: f64 = -0.05;

pub use crate::chain::measure::MIN_RADIUS_TOLERANCES;

/// Largest turning between two consecutive samples (radians) a smooth chain may claim: the
/// curvature at a joint is at most this over the piece's median sample spacing. Beyond a quarter
/// turn between two samples they cannot tell a tight curve from a corner; the G1 chain's needles
/// (κ = 11.8 /px on a spring sampled every 5 px: 59 rad per sample) are what the bound removes,
/// and a G1 joint beyond it becomes a corner. Measured in `docs/performance-history.md` (chain
/// constants).
pub const MAX_TURN_PER_SAMPLE: f64 = std::f64::consts::FRAC_PI_2;

/// Largest radius of curvature at a joint, in extents of the piece: flatter than that is a
/// line to any tolerance, and the log-curvature must stay finite (e^u underflows to κ = 0,
/// which only an inflection joint may have).
pub const MAX_RADIUS_EXTENTS: f64 = 1e6;

/// Largest length of a segment as a multiple of its starting length: a segment that grows
/// beyond that has left its samples (a spiral winding between two samples), and the step is
/// refused.
pub const MAX_LENGTH_FACTOR: f64 = 10.0;

/// Largest turning of a segment beyond its starting (G1) segment's, radians: a chain whose
/// segment winds further has left its samples (a projection onto the joint equations from a far
/// start went through spirals of α = −3 turning 50 rad on a 12-sample stroke, each of them a
/// quadrature of two dozen panels), and the projection refuses it like one that does not
/// converge. Half a turn more than the samples' own segment is beyond any drawn curve.
pub const MAX_EXTRA_TURNING: f64 = std::f64::consts::PI;

/// Most segments of a chain the smooth fit solves (beyond, the G1 chain is kept). Its KKT
/// system (about nine rows per segment: six unknowns, three joint equations) is solved in band
/// order (a bandwidth of about fifteen whatever the length), so its cost grows linearly with
/// the segments; the limit bounds the cut rounds' work on a part the smooth fit
/// cannot hold. At 40 a long part of the scribble fixture (95 samples that turn fast, 29 G1
/// segments) stayed G1, its cut rounds passing 40 on the way; at 60 it was G2 with 54, every
/// fixture curve G2 (its timings are in `docs/performance-history.md`, chain constants), and the
/// Prius line at 0.1 mm kept its 35.
/// Since the exact series next to curvature zeros (`lac::deviation`) that part takes 59, one
/// under 60: the limit is 80, a margin that changes no fixture output and no instruction count
/// over the fixture strokes up to 600 samples (a part that fails costs more rounds before it
/// gives up; none does on the fixtures).
pub const MAX_SEGMENTS: usize = 80;

/// Rounds of cuts in a row that do not bring the worst sample nearer before the smooth fit of
/// a part gives up. A round's cuts can move the worst sample elsewhere before the next round
/// resolves it. Measured in `docs/performance-history.md` (chain constants).
pub const STALLED_ROUNDS: usize = 2;

/// Rounds of cutting (every segment that misses the tolerance, at its middle) before the
/// smooth fit gives up and the G1 chain is kept; it also gives up after [`STALLED_ROUNDS`]
/// rounds that do not bring the worst sample nearer. Six rounds can cut a segment into 64, as the
/// G1 chain's subdivision can ([`super::ChainOptions::max_depth`]).
pub const MAX_CUT_ROUNDS: usize = 6;

/// An unknown within this of its bound (α, a log-curvature, a log-length: all dimensionless)
/// is on it.
const BOUND_SLACK: f64 = 1e-9;

/// Largest miss, in tolerances, that [`MINIMAX_ROUNDS`] try to recover: Lawson's iteration
/// lowers the largest distance by at most the gap between the least-squares and the minimax
/// fits, a few tens of percent.
const MINIMAX_REACH: f64 = 1.5;

/// The joints of a chain in the shooting form (the fit's start and every Levenberg–Marquardt
/// trial) are met to this fraction of the tolerance, not exactly: the next step's linearised
/// constraints carry the gaps left (the KKT system's right-hand side), and the fit's answer is
/// laid out forward, joints meeting by construction and the end point to [`END_TOLERANCE`],
/// before any distance is reported. Exact trials took a Newton step per factor of 3 or so from a
/// step's violation (1e-3 … 1e-1 of the extent) down to 1e-10, most of the smooth fit's time. On
/// the fixture strokes in g2, gaps of 1e-4 of the extent gave 1.40 s for the nine files (1.81 s
/// exact), 1e-3 1.22 s, both with 261 of 263 curves G2; 1e-2 lost a curve. A tenth of the tolerance
/// (over an extent of 300 tolerances, 3e-4) gives 1.24 s.
const TRIAL_GAP_TOLERANCES: f64 = 0.1;

/// The end point is met to this fraction of the piece's extent (rounding of the integration is
/// ~1e-13 of a segment's length).
const END_TOLERANCE: f64 = 1e-10;

/// A C3 joint's dκ/ds is met to this fraction of its magnitude (the issue asks for 1e-9 relative
/// or better on the curvature; dκ/ds is one derivative more, from the same closed form).
const C3_TOLERANCE: f64 = 1e-9;

/// Where the smooth fit starts and what it keeps.
pub(crate) struct SmoothInput<'a> {
    /// The piece's chain input.
    pub input: &'a ChainInput<'a>,
    /// The G1 chain to start from.
    pub chain: &'a Chain,
    /// The tolerance.
    pub tolerance: f64,
    /// Chord error of the distance evaluations.
    pub chord_error: f64,
    /// α allowed per segment.
    pub alpha: AlphaChoice,
    /// G2 or C3 (G1 returns the chain unchanged).
    pub continuity: Continuity,
}

impl SmoothInput<'_> {
    /// The α search of a segment refitted between free tangents (softened, or cut at a hook):
    /// within the curvature bound `cap`, walking from `guess`, and abandoned beyond the tolerance
    /// (only a segment within it is kept: a guess farther off is not searched on).
    pub(super) fn soften_options(&self, cap: f64, guess: Option<f64>) -> SpanFitOptions {
        SpanFitOptions {
            choice: self.alpha,
            max_curvature: cap,
            guess,
            abandon_above: self.tolerance,
            unreachable_above: self.tolerance,
            ..SpanFitOptions::new(self.chord_error)
        }
    }
}

/// Most samples a tail of the G1 chain may hold at the stroke's end (`without_end_tail`): a
/// hook's (`unhook::MAX_HOOK_SAMPLES`) and the two samples it turns from, beyond which a
/// run of tight segments is a drawn curl, not an artefact of the stroke's end.
pub const MAX_TAIL_SAMPLES: usize = unhook::MAX_HOOK_SAMPLES + 2;

/// Segments on each side of a joined segment that a joint removal's solve moves with it (the
/// smooth fit's removal of joints it can do without); the rest of the part stays, and so do the
/// curvatures of the joints at the window's ends: a try costs a few segments' solve, not the
/// whole part's (up to 54 segments on the scribble). The polish after the removals solves the
/// whole part again. Against whole-part tries 2 keeps the segments for less work; measured in
/// `docs/performance-history.md` (chain constants).
pub const REMOVAL_REACH: usize = 2;

/// The chain `chain` refitted with the continuity of `smooth.continuity` (see the module
/// documentation); `None` where it cannot be done within the tolerance (the G1 chain stands).
pub(crate) fn smooth_chain(smooth: &SmoothInput) -> Option<Chain> {
    let chain = smooth.chain;
    if smooth.continuity == Continuity::G1 || chain.segments.is_empty() {
        return None;
    }
    // A closed chain's seam holds one curvature on both sides: the G1 chain's there, fitted to
    // the samples on each side with the seam's tangent held (their geometric mean), rather than
    // the seam's B-spline estimate, which follows the samples' noise (3 % off on a mouse
    // circle, where a held curvature that far off cost 8 px). `seam.kappa` is unused beyond.
    let seam_input;
    let seam_smooth;
    let smooth = match (
        smooth.input.seam,
        chain.segments.first(),
        chain.segments.last(),
    ) {
        (Some(seam), Some(first), Some(last))
            if first.start == JointKind::Seam && last.end == JointKind::Seam =>
        {
            // Where the two sides bend opposite ways, or one is straight there (a figure eight
            // started at its crossing, a superellipse at the middle of a side), the seam is an
            // inflection: held at κ = 0 like any inflection joint.
            let (a, b) = (first.segment.kappa0(), last.segment.kappa1());
            let kappa = if a * b > 0.0 {
                a.signum() * (a * b).sqrt()
            } else {
                0.0
            };
            seam_input = ChainInput {
                seam: Some(SeamPose { kappa, ..seam }),
                ..*smooth.input
            };
            seam_smooth = SmoothInput {
                input: &seam_input,
                ..*smooth
            };
            &seam_smooth
        }
        _ => smooth,
    };
    // A joint where the G1 chain bends tighter than the samples resolve (a hook, a fast tight
    // turn: beyond the curvature bound) cannot be smooth under that bound: it becomes a corner,
    // and the parts between such joints are fitted on their own, each from and to its fixed
    // end points.
    let cap = curvature_cap(smooth.input.points, smooth.tolerance);
    // A tangle of the G1 chain at the stroke's end goes first (see [`without_end_tail`]).
    let trimmed = without_end_tail(&chain.segments, cap);
    let segments = trimmed.as_ref().unwrap_or(&chain.segments);
    let mut cuts: Vec<usize> = (1..segments.len())
        .filter(|&j| {
            segments[j - 1]
                .segment
                .kappa1()
                .abs()
                .max(segments[j].segment.kappa0().abs())
                > cap
        })
        .collect();
    cuts.push(segments.len());
    let mut out: Vec<ChainSegment> = Vec::with_capacity(segments.len());
    let mut max_deviation: f64 = 0.0;
    let mut all_smooth = true;
    // The weakest continuity a smoothed part reached (C3 asked, G2 where C3 could not hold).
    let mut weakest = smooth.continuity;
    // Whether some part had joints to make smooth: otherwise every segment is the G1 chain's,
    // holding the same samples, and so is the chain's largest distance.
    let mut refitted = trimmed.is_some();
    let mut from = 0;
    let mut next = 0;
    while next < cuts.len() {
        let to = cuts[next];
        refitted |= to - from > 1;
        let mut part = Chain {
            segments: segments[from..to].to_vec(),
            max_deviation: chain.max_deviation,
            within_tolerance: chain.within_tolerance,
            refined: chain.refined,
            continuity: chain.continuity,
        };
        if from > 0 {
            part.segments[0].start = JointKind::Corner;
        }
        if to < segments.len()
            && let Some(last) = part.segments.last_mut()
        {
            last.end = JointKind::Corner;
        }
        // A part that cannot be made C3 (on request) is made G2 where it can: a user asking
        // for more continuity never gets less than the default gives (the G1 chain). The
        // cuts below follow the weakest mode's miss.
        let mut fitted = smooth_part(&SmoothInput {
            chain: &part,
            ..*smooth
        });
        let mut reached = smooth.continuity;
        if fitted.is_err() && smooth.continuity == Continuity::C3 {
            fitted = smooth_part(&SmoothInput {
                chain: &part,
                continuity: Continuity::G2,
                ..*smooth
            });
            reached = Continuity::G2;
        }
        let fitted = match fitted {
            Ok(f) => {
                weakest = weakest.min(reached);
                f
            }
            // The fit pressed a joint against the curvature bound and still missed: the samples
            // bend there tighter than a smooth chain may, as at the joints cut above. It becomes
            // a corner and the part is fitted as two.
            Err(Missed::Bound(j)) if j > 0 && j < part.segments.len() => {
                cuts.insert(next, from + j);
                continue;
            }
            // A part whose first (last) segment leaves its corner bending beyond the bound (a
            // hook at a corner: κ = 12 /px on painting strokes) cannot start (end) smooth there:
            // that segment's other joint becomes a corner, and it stays as the G1 chain has it.
            Err(_) if part.segments.len() >= 2 && part.segments[0].segment.kappa0().abs() > cap => {
                cuts.insert(next, from + 1);
                continue;
            }
            Err(_)
                if part.segments.len() >= 2
                    && part.segments[part.segments.len() - 1]
                        .segment
                        .kappa1()
                        .abs()
                        > cap =>
            {
                cuts.insert(next, to - 1);
                continue;
            }
            Err(_) => {
                all_smooth = false;
                part
            }
        };
        max_deviation = max_deviation.max(fitted.max_deviation);
        out.extend(fitted.segments);
        from = to;
        next += 1;
    }
    if cuts.len() == 1 && !all_smooth {
        return None;
    }
    // The parts' ranges tiled as one piece: a segment holding no samples has the one-sample
    // range of the last sample before it, also at the start of a part.
    retile(&mut out, smooth.input.samples);
    // A segment between two corners (or a corner and the stroke's end) has both tangents free,
    // but kept the G1 chain's, which curl where the G1 joint bent beyond the bound: its ends are
    // turned as the G1 chain's piece ends are (see [`soften_tries`]). One that still curls
    // hooks there: it becomes a line, or a line and a segment meeting at a corner (see
    // `src/chain/smooth/unhook.rs`). Both hold the segment's own samples (its tiled range); the ranges
    // are tiled again after.
    let mut straightened = Vec::with_capacity(out.len());
    let lists = own_points(smooth.input, &out);
    for (mut segment, own) in out.into_iter().zip(lists) {
        let bend = segment
            .segment
            .kappa0()
            .abs()
            .max(segment.segment.kappa1().abs());
        if !(segment.start.tangent_free() && segment.end.tangent_free() && bend > cap) {
            straightened.push(segment);
            continue;
        }
        if soften_isolated(smooth, &mut segment, &own, cap) {
            refitted = true;
            straightened.push(segment);
        } else if let Some(replacement) = unhook::unhook(smooth, &segment, &own, cap) {
            refitted = true;
            straightened.extend(replacement);
        } else {
            straightened.push(segment);
        }
    }
    let mut out = straightened;
    retile(&mut out, smooth.input.samples);
    if !refitted {
        return Some(Chain {
            segments: out,
            continuity: weakest,
            ..chain.clone()
        });
    }
    // The whole chain's largest distance, each sample to its own segment (the honest measure):
    // a part kept G1 carries the whole G1 chain's figure.
    let lists = own_points(smooth.input, &out);
    let max_deviation = measured_deviation(smooth.input, &out, &lists, smooth.chord_error);
    Some(Chain {
        segments: out,
        max_deviation,
        within_tolerance: max_deviation <= smooth.tolerance,
        refined: chain.refined,
        continuity: if all_smooth { weakest } else { Continuity::G1 },
    })
}
