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
//!   and the fit crawls (a 200 px spring drifted 30 px from its samples).
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
//! to the curl and a segment on from it, meeting at a new corner (`src/chain/unhook.rs`). On the
//! nine recorded fixture files 28 segments bent beyond the bound (4 tighter than half a tolerance
//! in radius) before the hooks were cut, none now, for 26 segments more (820 → 846, most of them
//! lines of a pixel or three at a painting stroke's reversal). A least-squares chain that misses
//! the tolerance by a little is first refitted towards the minimax fit of the same segments
//! (Lawson's reweighting, a few rounds). When the solved chain still leaves a sample farther than
//! the tolerance from its nearest segment, every segment that misses is cut at its middle (a new
//! joint with that point's curvature: the two halves are the same curve, so the chain stays on its
//! constraints) and the fit runs again, at most [`MAX_CUT_ROUNDS`] rounds and until
//! [`STALLED_ROUNDS`] rounds in a row bring the worst sample no nearer. When that is not enough, a
//! part has more than [`MAX_SEGMENTS`] segments, or a chain cannot be built at all, the part keeps
//! its G1 segments and the chain says [`Continuity::G1`].
//!
//! ## Files
//! This file holds the parts' orchestration (corners, cut rounds, minimax, the record);
//! `layout.rs` the unknowns and the two forms, `solver.rs` the residuals, joint equations and
//! the samples' assignment, `start.rs` the starting chain and the cuts, `jacobian.rs` the
//! differenced Jacobians, `lm.rs` the constrained Levenberg–Marquardt solve with its projections
//! and the minimax rounds. A segment that still hooks at a corner is cut in `../unhook.rs`.

use super::assign::{own_points, param_interval, retile, tile_ranges};
use super::measure::{measured_deviation, nearest_deviation};
use super::record::{Chain, ChainInput, ChainSegment, Continuity, JointKind};
use super::soften::soften_fits;
use super::solve::band::{Band, BandCholesky};
use super::solve::band_lu::BandMatrix;
use crate::bspline::project::Pieces;
use crate::geom::{Point, Vec2};
use crate::lac::alpha_search::SpanFitOptions;
use crate::lac::deviation::{deviation, deviation_near};
use crate::lac::{AlphaChoice, LacError, LacSegment};
use nalgebra::DVector;

mod jacobian;
mod layout;
mod lm;
mod solver;
mod start;
mod unhook;

use jacobian::*;
use layout::*;
use lm::*;
use solver::*;
use start::*;

/// Largest α of a segment with a zero-curvature end. ρ^α must reach 0 there, which needs α < 0;
/// close to 0 the segment's curvature leaves zero so steeply (κ ∝ s^{−1/α}) that its evaluation
/// loses accuracy, and no drawn inflection looks like that. −0.05 keeps the whole practical
/// range (the clothoid −1, and the −3..0 the α search offers) open.
pub const ZERO_END_ALPHA: f64 = -0.05;

/// Smallest radius of curvature of a smooth chain, in tolerances: a bend tighter than half a
/// tolerance turns inside a disc the samples cannot tell from a corner; the G1 chain's needles
/// (κ = 75 /px on a three-sample segment at 0.5 px) were exactly that.
pub const MIN_RADIUS_TOLERANCES: f64 = 0.5;

/// Largest turning between two consecutive samples (radians) a smooth chain may claim: the
/// curvature at a joint is at most this over the piece's median sample spacing. Beyond a quarter
/// turn between two samples they cannot tell a tight curve from a corner; the G1 chain's needles
/// (κ = 11.8 /px on a spring sampled every 5 px: 59 rad per sample) are what the bound removes,
/// and a G1 joint beyond it becomes a corner. On the fixture strokes 1 rad gave 162 of 254
/// curves G2 (109 such corners), π/2 gives 185 (97), 3 rad 202 (71).
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
/// fixture curve G2 (the nine files 0.43 → 0.49 s), and the Prius line at 0.1 mm kept its 35.
/// Since the exact series next to curvature zeros (`lac::deviation`) that part takes 59, one
/// under 60: the limit is 80, a margin that changes no fixture output and no instruction count
/// over the fixture strokes up to 600 samples (a part that fails costs more rounds before it
/// gives up; none does on the fixtures).
pub const MAX_SEGMENTS: usize = 80;

/// Rounds of cuts in a row that do not bring the worst sample nearer before the smooth fit of
/// a part gives up. A round's cuts can move the worst sample elsewhere before the next round
/// resolves it: on the fixture strokes 1 gave 157 of 254 curves G2 in 12 s, 2 gives 162 in 16 s.
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

/// The chain `chain` refitted with the continuity of `smooth.continuity` (see the module
/// documentation); `None` where it cannot be done within the tolerance (the G1 chain stands).
pub(crate) fn smooth_chain(smooth: &SmoothInput) -> Option<Chain> {
    let chain = smooth.chain;
    if smooth.continuity == Continuity::G1 || chain.segments.is_empty() {
        return None;
    }
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
    // `src/chain/unhook.rs`). Both hold the segment's own samples (its tiled range); the ranges
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
    // The whole chain's largest distance, each sample to its nearest segment: a part kept G1
    // carries the whole G1 chain's figure, and a sample may lie nearer a neighbouring part.
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

/// Most samples a tail of the G1 chain may hold at the stroke's end (`without_end_tail`): a
/// hook's (`unhook::MAX_HOOK_SAMPLES`) and the two samples it turns from, beyond which a
/// run of tight segments is a drawn curl, not an artefact of the stroke's end.
pub const MAX_TAIL_SAMPLES: usize = unhook::MAX_HOOK_SAMPLES + 2;

/// `segments` (a G1 chain) without its end tail, where it has one: at the stroke's own end,
/// the run of segments that each touch a joint bending beyond `cap` (a joint the smooth chain
/// would make a corner) and together hold at most [`MAX_TAIL_SAMPLES`] samples. The segment
/// before the run is extended along its own law to the chain's end (see [`extended`]) and
/// takes the run's samples; the smooth fit then moves its end (a free end moves across its
/// tangent only, so the samples must be within its reach from the start). The G1 chain's
/// subdivisions and biarc repairs at a free end, where the B-spline's end follows the last
/// samples' noise, can leave such a tangle: a planted chain on whole pixels ended in six arcs
/// of 0.1–0.9 px bending up to 18 /px over its last four samples, one drawn with tablet noise
/// in two bending to 65 and 31.6 /mm over its last three; each such joint became a corner of
/// the smooth chain and the segments after it stayed. Over the random planted sweep the tablet
/// cases 178 → 179 as planted, the fixture files' segments as they were (0.5 % more
/// instructions). `None` where there is no tail, or the segment cannot be extended.
fn without_end_tail(segments: &[ChainSegment], cap: f64) -> Option<Vec<ChainSegment>> {
    let n = segments.len();
    if segments.last()?.end != JointKind::End {
        return None;
    }
    // Joint j (1..n) bends beyond the cap.
    let cut = |j: usize| {
        j > 0
            && j < n
            && segments[j - 1]
                .segment
                .kappa1()
                .abs()
                .max(segments[j].segment.kappa0().abs())
                > cap
    };
    let mut t = n;
    while t > 1
        && (cut(t - 1) || cut(t))
        && segments[n - 1]
            .samples
            .1
            .saturating_sub(segments[t - 1].samples.0)
            < MAX_TAIL_SAMPLES
    {
        t -= 1;
    }
    if t == n {
        return None;
    }
    let end = segments[n - 1].segment.end();
    let mut kept = segments[..t].to_vec();
    let last = kept.last_mut()?;
    let reach = last.segment.end().distance(end);
    last.segment = extended(&last.segment, last.segment.length() + reach)?;
    last.samples.1 = segments[n - 1].samples.1;
    last.end = JointKind::End;
    Some(kept)
}

/// `segment` continued along its own law to the length `length` (ρ^α affine in arc length, or
/// ρ exponential for α = 0; an arc or a line as it is); `None` for a spiral with a zero
/// curvature at either end (left as it is: a curvature that ends at zero cannot go on, and the
/// rare spiral leaving zero is not worth a special case) and where the law runs out before
/// `length` (a curvature falling to zero within it, for α < 0).
fn extended(segment: &LacSegment, length: f64) -> Option<LacSegment> {
    let (k0, k1, l) = (segment.kappa0(), segment.kappa1(), segment.length());
    let kappa = match segment.alpha() {
        _ if k0 == k1 => k1,
        _ if k0 == 0.0 || k1 == 0.0 || !(l > 0.0) => return None,
        Some(alpha) if alpha != 0.0 => {
            let (r0, r1) = ((1.0 / k0.abs()).powf(alpha), (1.0 / k1.abs()).powf(alpha));
            let r = r0 + (r1 - r0) * length / l;
            if !(r > 0.0) {
                return None;
            }
            k1.signum() / r.powf(1.0 / alpha)
        }
        _ => k1 * (k1 / k0).abs().powf(length / l - 1.0),
    };
    if !kappa.is_finite() {
        return None;
    }
    LacSegment::new(
        segment.start(),
        segment.theta0(),
        length,
        segment.alpha(),
        k0,
        kappa,
    )
    .ok()
}

/// Refits `s`, a segment between two free ends (corners, or the stroke's own ends) curling
/// beyond `cap` at one of them, with turned end tangents: the first of [`soften_tries`] whose
/// segment (α searched again, within `cap`) holds its own samples `list` within the tolerance.
/// Returns whether it was refitted.
fn soften_isolated(smooth: &SmoothInput, s: &mut ChainSegment, list: &[usize], cap: f64) -> bool {
    let segment = s.segment;
    if list.is_empty() {
        return false;
    }
    let input = smooth.input;
    let points: Vec<Point> = list.iter().map(|&i| input.points[i]).collect();
    let options = smooth.soften_options(cap, segment.alpha());
    let at_start = segment.kappa0().abs() >= segment.kappa1().abs();
    let (a, b) = (
        (segment.start(), segment.theta0()),
        (segment.end(), segment.theta1()),
    );
    let Some((_, fit)) =
        soften_fits(a, b, at_start, true, &points, options, smooth.tolerance).next()
    else {
        return false;
    };
    let d = &fit.deviation;
    s.alpha_uncertainty =
        smooth_alpha_uncertainty(smooth, &fit.segment, list, &d.signed_distances(), &d.feet);
    s.alpha_bound = crate::chain::AlphaBound::of(fit.segment.alpha(), smooth.alpha);
    s.alpha_source =
        crate::chain::AlphaSource::of_g1(fit.segment.alpha(), &fit.search, smooth.alpha);
    s.segment = fit.segment;
    s.max_deviation = d.max;
    s.rms_deviation = d.rms;
    s.search = fit.search;
    true
}

/// The largest curvature a smooth chain of these samples may have at a joint (see
/// [`MIN_RADIUS_TOLERANCES`], [`MAX_TURN_PER_SAMPLE`]).
fn curvature_cap(points: &[Point], tolerance: f64) -> f64 {
    let mut steps: Vec<f64> = points.windows(2).map(|w| w[0].distance(w[1])).collect();
    steps.sort_by(f64::total_cmp);
    let spacing = steps.get(steps.len() / 2).copied().unwrap_or(0.0);
    (1.0 / (MIN_RADIUS_TOLERANCES * tolerance))
        .min(MAX_TURN_PER_SAMPLE / spacing.max(f64::MIN_POSITIVE))
}

/// Why a part's smooth fit failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Missed {
    /// It missed the tolerance with a joint's curvature on the bound
    /// ([`MIN_RADIUS_TOLERANCES`], [`MAX_TURN_PER_SAMPLE`]): the G1 joint (index in the part,
    /// 1..n) nearest it.
    Bound(usize),
    /// A round's solve gave no chain: its start met neither the joint equations nor, laid out
    /// forward, the part's end (see [`Solver::lay_out_from_start`]).
    Unstarted,
    /// Otherwise (no chain meeting the constraints, or cuts that stopped helping).
    Other,
}

/// [`smooth_chain`] of a chain without forced corners.
fn smooth_part(smooth: &SmoothInput) -> Result<Chain, Missed> {
    let input = smooth.input;
    let chain = smooth.chain;
    // Each G1 segment's own samples (a sample on a range boundary, which a segment without
    // samples repeats, belongs to one segment only).
    let assign = own_points(input, &chain.segments);
    // One segment has no joint to make smooth: it is its own G2 (and C3) chain.
    if chain.segments.len() == 1 {
        return Ok(Chain {
            continuity: smooth.continuity,
            ..chain.clone()
        });
    }
    // The joints' curvatures start at the B-spline's; where the fit cannot start or finish from
    // there, at the G1 chain's own (the two sides' geometric mean). A miss against the curvature
    // bound is the samples' (the joint becomes a corner, see [`smooth_chain`]): on the fixture
    // strokes the second start never held where the first missed so, in 11 tries.
    // Where neither start holds (nor misses against the bound) and the first could not lay a
    // round's chain out ([`Missed::Unstarted`]), the first is tried once more with its chain
    // laid out forward from the start itself ([`Solver::lay_out_from_start`]): at 0.5 px, below
    // the hey stroke's noise floor, a part of 14 segments failed both starts so and stayed G1.
    // A first start that failed otherwise would fail the same way again.
    let mut first = None;
    for (start, from_start) in [
        (JointStart::Spline, false),
        (JointStart::Chain, false),
        (JointStart::Spline, true),
    ] {
        if from_start && first != Some(Missed::Unstarted) {
            break;
        }
        match smooth_from(smooth, assign.clone(), start, from_start) {
            Ok(chain) => return Ok(chain),
            Err(missed @ Missed::Bound(_)) => return Err(missed),
            Err(missed) => {
                first.get_or_insert(missed);
            }
        }
    }
    Err(Missed::Other)
}

/// Where the joints' curvatures of the starting chain come from (see [`start_layout`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum JointStart {
    /// The B-spline's curvature at the joint, where its sign agrees with the chain's.
    Spline,
    /// The G1 chain's two sides' geometric mean.
    Chain,
}

/// [`smooth_part`] from the joint curvatures of `start` (`lay_out_from_start`: see
/// [`Solver::lay_out_from_start`]).
fn smooth_from(
    smooth: &SmoothInput,
    mut assign: Vec<Vec<usize>>,
    joint_start: JointStart,
    lay_out_from_start: bool,
) -> Result<Chain, Missed> {
    let points = smooth.input.points;
    let chain = smooth.chain;
    let max_log_kappa = curvature_cap(points, smooth.tolerance).ln();
    let extent = points
        .iter()
        .map(|p| p.distance(points[0]))
        .fold(smooth.tolerance, f64::max);
    let min_log_kappa = -(MAX_RADIUS_EXTENTS * extent).ln();
    let (mut layout, mut x) =
        start_layout(smooth, &mut assign, max_log_kappa, joint_start).ok_or(Missed::Other)?;
    let start = chain.segments[0].segment.start();
    let end = chain.segments.last().ok_or(Missed::Other)?.segment.end();
    let extent = points
        .iter()
        .map(|p| p.distance(start))
        .fold(start.distance(end), f64::max);
    let mut solver = Solver {
        points,
        start,
        scale: extent.max(smooth.tolerance),
        chord_error: smooth.chord_error,
        log_kappa: (min_log_kappa, max_log_kappa),
        c3: smooth.continuity == Continuity::C3,
        trial_slack: (TRIAL_GAP_TOLERANCES * smooth.tolerance / extent.max(smooth.tolerance))
            .max(END_TOLERANCE)
            / END_TOLERANCE,
        weights: Vec::new(),
        minimax: false,
        polish: false,
        tolerance: smooth.tolerance,
        window: None,
        lay_out_from_start,
        extend: std::cell::Cell::new(false),
    };
    layout.clamp(&mut x, solver.log_kappa);
    let (mut best_worst, mut stalled) = (f64::INFINITY, 0);
    for round in 0..=MAX_CUT_ROUNDS {
        if layout.n() > MAX_SEGMENTS {
            return Err(Missed::Other);
        }
        let started = (round == 0).then(|| (x.clone(), assign.clone()));
        let mut evaluation =
            solve(&solver, &layout, &mut x, &mut assign, None).ok_or(Missed::Unstarted)?;
        // The starting α match the G1 chain's turning (see [`start_layout`]); where the fit
        // ended with such an α pressed on its bound while the G1 chain's own α lies inside,
        // it may sit in a local minimum that the G1 α avoids (a planted S of two clothoids on a
        // pixel grid: α −3 against the planted −1, a third more cost): the fit from the G1 α
        // is tried too and the lower cost kept (also where the first holds the tolerance: its
        // curvature profile can be 13 % off the planted one).
        if let Some((mut other, mut other_assign)) = started
            && let Some(g1_alpha) = g1_alpha_start(&layout, &x, &other, &chain.segments)
        {
            other.alpha = g1_alpha;
            if let Some(e) = solve(&solver, &layout, &mut other, &mut other_assign, None)
                && e.cost < evaluation.cost
            {
                (evaluation, x, assign) = (e, other, other_assign);
            }
        }
        let own = distances(&evaluation);
        let (worst, _) = worst_sample(&own);
        if let Some(refit) = holding(
            smooth,
            &mut solver,
            &layout,
            (&x, &assign, &evaluation),
            worst,
        ) {
            let (e, a, z) = match &refit {
                Some((e, a, z)) => (e, a.as_slice(), z),
                None => (&evaluation, assign.as_slice(), &x),
            };
            let answer = settled(smooth, &mut solver, (&layout, z, a, e), refit.is_none());
            return Ok(answer.record(smooth));
        }
        if let missed @ Missed::Bound(_) = on_bound(&layout, &x, &chain.segments, max_log_kappa) {
            return Err(missed);
        }
        if worst < best_worst {
            best_worst = worst;
            stalled = 0;
        } else {
            stalled += 1;
            if stalled >= STALLED_ROUNDS {
                return Err(on_bound(&layout, &x, &chain.segments, max_log_kappa));
            }
        }
        // Every segment that misses the tolerance is cut, the last first (a cut shifts the
        // indices after it).
        let missing: Vec<usize> = (0..own.len())
            .filter(|&k| own[k].iter().any(|&d| d > smooth.tolerance))
            .collect();
        if missing.is_empty() {
            return Err(Missed::Other);
        }
        for &k in missing.iter().rev() {
            cut(
                &mut layout,
                &mut x,
                &mut assign,
                &evaluation,
                k,
                smooth.alpha,
            )
            .ok_or(Missed::Other)?;
        }
    }
    Err(on_bound(&layout, &x, &chain.segments, max_log_kappa))
}

/// The solved chain with fewer joints, where one holds the tolerance: the fewest segments in
/// the continuity mode, which the G1 chain that starts the fit does not decide (its segments
/// are fitted to the samples' positions and tangents one by one). A joint can go where the
/// curvature runs monotonically through it (one log-aesthetic segment can then span both
/// neighbours; at a curvature extremum none can), tried in the order of the two sides' α
/// difference (a straight log curvature graph through the joint first). Each removal is solved
/// afresh from the joined chain (a near miss refitted towards its minimax fit, as the cut rounds
/// do) and kept where every sample is within the tolerance. A joint that could not go is tried
/// again only after a removal next to it (a removal reshapes its neighbourhood; elsewhere the
/// chain moves little), so a part of n segments costs about n solves, not n per removal.
/// Where no joint can go as it stands, the curvature's shape is changed where the samples
/// cannot show it, so that joints can go: a flat point made a zero joint ([`flat_points`]), a
/// bump between two inflections flattened ([`bumps`]), an inflection next to a part's end
/// dropped ([`end_flips`]); each is tried like a removal and, where it failed, again only after
/// a removal next to it. `None` where no joint can go.
fn fewer_joints(
    smooth: &SmoothInput,
    solver: &mut Solver,
    layout: &Layout,
    x: &Params,
    assign: &[Vec<usize>],
    evaluation: &Evaluation,
) -> Option<Solved> {
    let (mut layout, mut x, mut assign) = (layout.clone(), x.clone(), assign.to_vec());
    let mut kept = evaluation.clone();
    let mut removed_any = false;
    // Per joint: tried and kept. A removal changes the chain near it only, so a joint that
    // could not go is tried again only once a neighbouring segment has changed.
    let mut failed = vec![false; layout.n() + 1];
    // Per joint: a flat point or bump made there did not hold (the same locality).
    let mut failed_move = vec![false; layout.n() + 1];
    'fewer: loop {
        let n = layout.n();
        let mut joints: Vec<(f64, usize)> = (1..n)
            .filter(|&j| !failed[j])
            .filter(|&j| {
                let (a, m, b) = (
                    layout.kappa(&x, j - 1),
                    layout.kappa(&x, j),
                    layout.kappa(&x, j + 1),
                );
                let sign = layout.sigma[j];
                sign != 0.0
                    && layout.sigma[j - 1] != -sign
                    && layout.sigma[j + 1] != -sign
                    && (m - a) * (b - m) >= 0.0
            })
            .map(|j| ((x.alpha[j - 1] - x.alpha[j]).abs(), j))
            .collect();
        joints.sort_by(|p, q| p.0.total_cmp(&q.0));
        for (_, j) in joints {
            failed[j] = true;
            let Some(found) = removed(
                smooth,
                solver,
                (&layout, &x, assign.as_slice(), &kept),
                None,
                &[j],
            ) else {
                continue;
            };
            removed_any = true;
            (layout, x, assign, kept) = (found.layout, found.x, found.assign, found.evaluation);
            dropped(&mut failed, &[j]);
            dropped(&mut failed_move, &[j]);
            continue 'fewer;
        }
        // No joint can go as it is: where the curvature falls towards zero and rises again
        // without changing sign (a flat point), the joint at its least is made a zero joint and
        // its neighbours go with it (see [`flat_points`]).
        // And where it changes sign twice within the noise (a bump), the bump's joint takes
        // the curvature of the curve around it and its two zero joints go (see [`bumps`]).
        let moves = flat_points(&layout, &x, &kept.segments, smooth.tolerance)
            .into_iter()
            .chain(bumps(&layout, &x, &kept.segments, smooth.tolerance))
            .chain(end_flips(&layout, &x, &kept.segments, smooth.tolerance));
        for (reset, drops) in moves {
            let at = reset.joint();
            if failed_move[at] {
                continue;
            }
            failed_move[at] = true;
            let found = removed(
                smooth,
                solver,
                (&layout, &x, assign.as_slice(), &kept),
                Some(reset),
                &drops,
            );
            let Some(found) = found else {
                continue;
            };
            removed_any = true;
            (layout, x, assign, kept) = (found.layout, found.x, found.assign, found.evaluation);
            dropped(&mut failed, &drops);
            dropped(&mut failed_move, &drops);
            continue 'fewer;
        }
        break;
    }
    removed_any.then_some(Solved {
        layout,
        x,
        assign,
        evaluation: kept,
    })
}

/// Per-joint flags of [`fewer_joints`] once the joints `drops` (in decreasing order) went: their
/// entries removed, and those of the joined segments' joints cleared (their neighbourhood
/// changed, so what failed there may hold now).
fn dropped(flags: &mut Vec<bool>, drops: &[usize]) {
    for &d in drops {
        if d < flags.len() {
            flags.remove(d);
        }
    }
    let (Some(&low), Some(&high)) = (drops.iter().min(), drops.iter().max()) else {
        return;
    };
    // The joined segments run from joint low − 1 to joint high + 1 − drops.len().
    let end = (high + 1).saturating_sub(drops.len());
    for f in flags.iter_mut().take(end + 1).skip(low.saturating_sub(1)) {
        *f = false;
    }
}

/// The solved chain `(layout, x, assign, kept)` with the joints `drops` removed (in decreasing
/// order, each joining the segments on its two sides) and, first, the joint of `reset` made a
/// zero joint or given its curvature, solved locally ([`REMOVAL_REACH`] segments each side of
/// the joined ones move, the rest of the part stays and keeps its samples' distances): the
/// solved chain where it holds the tolerance (or does after minimax rounds, see [`holding`]).
/// `None` otherwise.
fn removed(
    smooth: &SmoothInput,
    solver: &mut Solver,
    (layout, x, assign, kept): (&Layout, &Params, &[Vec<usize>], &Evaluation),
    reset: Option<Reset>,
    drops: &[usize],
) -> Option<Solved> {
    let (mut l, mut y, mut a) = (layout.clone(), x.clone(), assign.to_vec());
    if let Some(reset) = reset {
        let j = match reset {
            Reset::Zero(j) => {
                l.sigma[j] = 0.0;
                j
            }
            Reset::Curvature(j, kappa) => {
                l.sigma[j] = kappa.signum();
                y.u[j] = kappa.abs().ln();
                j
            }
        };
        let n = l.n();
        for k in (j.saturating_sub(1)..=j).filter(|&k| k < n) {
            set_alpha_bounds(smooth.alpha, &mut l, &mut y, k)?;
        }
    }
    // The evaluation near the joined chain: `kept` without the segments the drops take out.
    let mut near: Option<Evaluation> = None;
    let mut near_assign = assign.to_vec();
    for &j in drops {
        join_at(smooth.alpha, &mut l, &mut y, &mut a, &kept.segments, j)?;
        near = Some(without(near.as_ref().unwrap_or(kept), j));
        near_assign.remove(j);
    }
    let near = near?;
    l.clamp(&mut y, solver.log_kappa);
    // The joined segments: the last drop's left one to the first drop's, less the drops after it.
    let low = drops.iter().min()?.checked_sub(1)?;
    let high = drops.iter().max()?.checked_sub(drops.len())?;
    let window = (
        low.saturating_sub(REMOVAL_REACH),
        (high + REMOVAL_REACH).min(l.n() - 1),
    );
    solver.window = (window != (0, l.n() - 1)).then_some(window);
    let mut tried = None;
    if let Some(e) = solve(solver, &l, &mut y, &mut a, Some((&near, &near_assign))) {
        let worst = worst_sample(&distances(&e)).0;
        if let Some(refit) = holding(smooth, solver, &l, (&y, &a, &e), worst) {
            tried = Some(refit.unwrap_or((e, a, y)));
        }
    }
    solver.window = None;
    let (e, a, y) = tried?;
    Some(Solved {
        layout: l,
        x: y,
        assign: a,
        evaluation: e,
    })
}

/// Flat points of the chain `x` (its segments `segments`): interior joints j whose curvature is
/// smaller in magnitude than at both neighbouring joints, all three of one sign (the curvature
/// falls towards zero and rises again without an inflection), each with the joints that go when
/// it is made a zero joint: its two neighbours (one where the other is the part's end), in
/// decreasing index. No log-aesthetic segment spans a curvature extremum, so the chain keeps a
/// joint on each side of a small non-zero least where a zero there needs none: a planted chain
/// falling to κ = 0 and rising again on the same side, drawn on whole pixels, came back as four
/// segments for two. Only a least within the noise of zero is tried: a curvature m over the two
/// segments around the joint bends them by m·L²/8 off their chord, and where that exceeds the
/// tolerance the samples show the curvature. Ordered by the curvature at j relative to its
/// neighbours', the nearest to zero first.
///
/// Measured over the fixture strokes up to 600 samples and the nine files (g2): 650 → 649 and
/// 780 → 779 segments for 3 % more instructions (4 766 → 4 906 M); the random planted sweep
/// 168 → 169 of 200 on whole pixels, the rest as it was. Also trying each neighbour alone: 776
/// segments on the nine files for 9 % more; without the noise test, 25 % more.
fn flat_points(
    layout: &Layout,
    x: &Params,
    segments: &[LacSegment],
    tolerance: f64,
) -> Vec<(Reset, Vec<usize>)> {
    let n = layout.n();
    let found = (1..n)
        .filter_map(|j| {
            let sign = layout.sigma[j];
            if sign == 0.0 || layout.sigma[j - 1] != sign || layout.sigma[j + 1] != sign {
                return None;
            }
            let (a, m, b) = (
                layout.kappa(x, j - 1).abs(),
                layout.kappa(x, j).abs(),
                layout.kappa(x, j + 1).abs(),
            );
            if !(m < a && m < b) {
                return None;
            }
            let span = segments[j - 1].length() + segments[j].length();
            if !(sagitta(m, span) <= tolerance) {
                return None;
            }
            let drops = match (j >= 2, j + 1 < n) {
                (true, true) => vec![j + 1, j - 1],
                (false, true) => vec![j + 1],
                (true, false) => vec![j - 1],
                (false, false) => return None,
            };
            Some((m / a.min(b), Reset::Zero(j), drops))
        })
        .collect();
    ordered(found)
}

/// How far a curvature of magnitude `kappa` over a stretch of `length` bends it off its chord:
/// the sagitta κ·L²/8 (to first order). A shape move ([`flat_points`], [`bumps`],
/// [`end_flips`]) is tried only where the curvature it takes away bends its stretch by no
/// more than the tolerance: beyond it the samples show the curvature.
fn sagitta(kappa: f64, length: f64) -> f64 {
    kappa.abs() * length * length / 8.0
}

/// Shape moves (a [`Reset`] and the joints that go with it) ordered by their key, the smallest
/// first.
fn ordered(mut found: Vec<(f64, Reset, Vec<usize>)>) -> Vec<(Reset, Vec<usize>)> {
    found.sort_by(|p, q| p.0.total_cmp(&q.0));
    found
        .into_iter()
        .map(|(_, reset, drops)| (reset, drops))
        .collect()
}

/// End flips of the chain `x` (its segments `segments`): a part's first or last segment that
/// leaves a zero joint with the other sign than the segment beyond that joint (an inflection
/// next to the part's end), each with the end it makes a zero joint and the inflection that
/// goes. Only a flip within the noise is tried: the end's curvature m over the segment's length
/// L bends it by at most m·L²/8 off its chord.
fn end_flips(
    layout: &Layout,
    x: &Params,
    segments: &[LacSegment],
    tolerance: f64,
) -> Vec<(Reset, Vec<usize>)> {
    let n = layout.n();
    if n < 2 {
        return Vec::new();
    }
    // (end joint, the inflection next to it, the joint beyond, the end's segment)
    let ends = [(0, 1, 2, 0), (n, n - 1, n - 2, n - 1)];
    ends.into_iter()
        .filter(|&(end, zero, beyond, k)| {
            let sign = layout.sigma[end];
            sign != 0.0
                && layout.sigma[zero] == 0.0
                && layout.sigma[beyond] == -sign
                && sagitta(layout.kappa(x, end), segments[k].length()) <= tolerance
        })
        .map(|(end, zero, _, _)| (Reset::Zero(end), vec![zero]))
        .collect()
}

/// What a joint-removal try sets first (see [`removed`]).
#[derive(Clone, Copy, Debug)]
enum Reset {
    /// The joint becomes a zero joint (a flat point, see [`flat_points`]).
    Zero(usize),
    /// The joint takes this curvature, sign included (a bump, see [`bumps`]).
    Curvature(usize, f64),
}

impl Reset {
    /// The joint it sets.
    fn joint(self) -> usize {
        match self {
            Reset::Zero(j) | Reset::Curvature(j, _) => j,
        }
    }
}

/// Bumps of the chain `x` (its segments `segments`): interior joints j between two zero joints
/// j ± 1 whose curvature has the other sign than at j ± 2, which share theirs (the curvature
/// changes sign twice and comes back), each with the curvature it takes when the bump goes (the
/// geometric mean of the curvatures at j ± 2) and the zero joints that go with it, in
/// decreasing index. A whole-pixel staircase can read as a wiggle: a planted chain of one sign
/// came back with a bump of κ = 0.054 /px over 1.2 px between two spirals through zero, its
/// curvature profile 33 % off the planted curve's. Each inflection holds a joint that no removal
/// can take (no log-aesthetic segment changes sign). Only a bump within the noise is tried: its
/// largest curvature m over its two segments bends them by m·L²/8 off their chord, and where
/// that exceeds the tolerance the samples show it. Ordered by that bend, the smallest first.
///
/// Measured with the flat points (g2, `REPS=1 FLOOR=1 valgrind --tool=callgrind
/// target/release/examples/fit_fixture_strokes`): the fixture strokes up to 600 samples 649 →
/// 638 segments for 2 % more instructions (4 906 → 5 013 M), the nine files 779 → 759, at the
/// unit's tolerance 1 223 → 1 123; that planted chain 7 → 5 segments, the sweep's passes as they
/// were.
fn bumps(
    layout: &Layout,
    x: &Params,
    segments: &[LacSegment],
    tolerance: f64,
) -> Vec<(Reset, Vec<usize>)> {
    let n = layout.n();
    let found = (2..n.saturating_sub(1))
        .filter_map(|j| {
            let outside = layout.sigma[j - 2];
            if outside == 0.0
                || layout.sigma[j + 2] != outside
                || layout.sigma[j] != -outside
                || layout.sigma[j - 1] != 0.0
                || layout.sigma[j + 1] != 0.0
            {
                return None;
            }
            let span = segments[j - 1].length() + segments[j].length();
            let bend = sagitta(layout.kappa(x, j), span);
            if !(bend <= tolerance) {
                return None;
            }
            let kappa = outside
                * (layout.kappa(x, j - 2) * layout.kappa(x, j + 2))
                    .abs()
                    .sqrt();
            Some((bend, Reset::Curvature(j, kappa), vec![j + 1, j - 1]))
        })
        .collect();
    ordered(found)
}

/// `e` with segment `j` taken out (its entries of every list), as the evaluation near a chain
/// whose segments j − 1 and j were joined: the segments before and after keep their places.
fn without(e: &Evaluation, j: usize) -> Evaluation {
    let drop = |k: &usize| *k != j;
    let keep = |len: usize| (0..len).filter(drop);
    Evaluation {
        segments: keep(e.segments.len()).map(|k| e.segments[k]).collect(),
        residuals: keep(e.residuals.len())
            .map(|k| e.residuals[k].clone())
            .collect(),
        feet: keep(e.feet.len()).map(|k| e.feet[k].clone()).collect(),
        foot_points: keep(e.foot_points.len())
            .map(|k| e.foot_points[k].clone())
            .collect(),
        cost: e.cost,
    }
}

/// Whether the solved chain `e` of `x` (its samples assigned as `assign`, the largest distance
/// `worst`) holds the tolerance: `Some(None)` where it does as solved; where it misses by at
/// most [`MINIMAX_REACH`] and its minimax refit ([`minimax`]: a near miss is first fitted for its
/// largest distance rather than cut, see [`MINIMAX_ROUNDS`]) holds, `Some` of that round's
/// evaluation, assignment and unknowns. `None` where neither holds.
#[allow(clippy::type_complexity)]
fn holding(
    smooth: &SmoothInput,
    solver: &mut Solver,
    layout: &Layout,
    (x, assign, e): (&Params, &[Vec<usize>], &Evaluation),
    worst: f64,
) -> Option<Option<(Evaluation, Vec<Vec<usize>>, Params)>> {
    if worst <= smooth.tolerance {
        return holds(smooth, e).then_some(None);
    }
    if !(worst <= MINIMAX_REACH * smooth.tolerance) {
        return None;
    }
    let (e, a, z) = minimax(solver, layout, x, assign, e)?;
    holds(smooth, &e).then_some(Some((e, a, z)))
}

/// Whether every sample of `e` is within the tolerance of its own segment, and so of the whole
/// chain: a sample's distance to its own segment bounds its distance to the chain from above
/// ([`nearest_deviation`] measures the chain's for the record, [`Solved::record`], once a
/// part's answer is chosen). A distance that is not a number never holds.
fn holds(smooth: &SmoothInput, e: &Evaluation) -> bool {
    e.residuals
        .iter()
        .flatten()
        .all(|r| r.abs() <= smooth.tolerance)
}

/// The part's answer from the solved chain of `x` that holds the tolerance: its joints
/// removed where they can go ([`fewer_joints`]), then polished ([`polished`]). A chain that held
/// only after its minimax rounds (`least_squares` false) is polished only where a removal
/// changed it: its own least-squares fit is the one that missed. (A removal that held only after
/// minimax rounds is polished: the least-squares solve from its minimax chain can find another
/// minimum that holds; on the random sweep one more jittered case as planted, for a tenth more
/// instructions on the fixture strokes than without.)
fn settled(
    smooth: &SmoothInput,
    solver: &mut Solver,
    (layout, x, assign, evaluation): (&Layout, &Params, &[Vec<usize>], &Evaluation),
    least_squares: bool,
) -> Solved {
    let as_solved = || Solved {
        layout: layout.clone(),
        x: x.clone(),
        assign: assign.to_vec(),
        evaluation: evaluation.clone(),
    };
    match fewer_joints(smooth, solver, layout, x, assign, evaluation) {
        Some(s) => {
            polished(smooth, solver, (&s.layout, &s.x, &s.assign, &s.evaluation)).unwrap_or(s)
        }
        None if least_squares => {
            polished(smooth, solver, (layout, x, assign, evaluation)).unwrap_or_else(as_solved)
        }
        None => as_solved(),
    }
}

/// A solved chain: its layout, unknowns, the samples' assignment and its evaluation. Where it
/// holds the tolerance ([`holds`]), its record ([`Solved::record`]: the samples' distances to
/// the whole chain and each α's standard error) is made only for the part's answer, not for
/// every chain the removals and the polish pass on the way (on painting stroke 7, a stroke at
/// the median ratio to the G1 chain, the records of the chains passed on had been a twentieth
/// of its smooth fit).
struct Solved {
    layout: Layout,
    x: Params,
    assign: Vec<Vec<usize>>,
    evaluation: Evaluation,
}

impl Solved {
    /// The chain record, with the largest distance from a sample to its nearest segment.
    fn record(&self, smooth: &SmoothInput) -> Chain {
        let (e, assign) = (&self.evaluation, &self.assign);
        let nearest = nearest_deviation(
            smooth.input.points,
            &e.segments,
            assign,
            &distances(e),
            smooth.chord_error,
        );
        finish(smooth, &self.layout, e, assign, nearest)
    }
}

/// The solved chain of `x` (which holds the tolerance) polished towards its least-squares
/// minimum, where that lowers its squared distances and still holds the tolerance (a polish
/// whose steps end beyond the tolerance ends at its last chain within it, see
/// [`levenberg_marquardt`]); `None` where it does not (the chain as solved is then the
/// answer): the solve that found it stops as soon as a step gains little while every sample is
/// within the tolerance ([`WITHIN_DECREASE`]), and the cuts, minimax rounds and removals that
/// led to it aim at the tolerance, not at the lowest deviation.
fn polished(
    smooth: &SmoothInput,
    solver: &mut Solver,
    (layout, x, assign, evaluation): (&Layout, &Params, &[Vec<usize>], &Evaluation),
) -> Option<Solved> {
    let (mut y, mut a) = (x.clone(), assign.to_vec());
    solver.polish = true;
    let e = solve(solver, layout, &mut y, &mut a, Some((evaluation, assign)));
    solver.polish = false;
    let e = e?;
    // Unweighted: a removal's evaluation may be a minimax round's, whose cost is weighted.
    let squares = |e: &Evaluation| e.residuals.iter().flatten().map(|r| r * r).sum::<f64>();
    if !(squares(&e) < squares(evaluation)) {
        return None;
    }
    holds(smooth, &e).then(|| Solved {
        layout: layout.clone(),
        x: y,
        assign: a,
        evaluation: e,
    })
}

/// Segments on each side of a joined segment that a joint removal's solve moves with it (the
/// smooth fit's removal of joints it can do without); the rest of the part stays, and so do the
/// curvatures of the joints at the window's ends: a try costs a few segments' solve, not the
/// whole part's (up to 54 segments on the scribble). The polish after the removals solves the
/// whole part again. Over the fixture strokes up to 600 samples, against whole-part tries (650
/// segments, 5 389 M instructions): 1 gave 651 segments for 4 569 M, 2 650 for 4 766 M, 3 660;
/// a whole-part try after a local miss (1 or 2) 648 for 5 629 M or 5 183 M (of 33 tries in
/// parts longer than the window, 18 held locally, 3 more as whole parts, 12 neither). The
/// random planted sweep is as it was.
pub const REMOVAL_REACH: usize = 2;

/// Relative margin within which a joint's log-curvature counts as on its upper bound.
const ON_BOUND: f64 = 1e-9;

/// The failure of a fit that ended at `x`: [`Missed::Bound`] with the G1 joint nearest the
/// interior joint whose curvature sits on the upper bound (the largest such G1 joint's own bend
/// where the bound is reached inside a G1 segment), else [`Missed::Other`].
fn on_bound(layout: &Layout, x: &Params, g1: &[ChainSegment], max_log_kappa: f64) -> Missed {
    let n = layout.n();
    let bend = |j: usize| -> f64 {
        // A G1 joint's own bend: the larger curvature of its two sides.
        match (g1.get(j.wrapping_sub(1)), g1.get(j)) {
            (Some(a), Some(b)) => a.segment.kappa1().abs().max(b.segment.kappa0().abs()),
            _ => 0.0,
        }
    };
    let mut best: Option<(f64, usize)> = None;
    for j in 1..n {
        if layout.sigma[j] == 0.0
            || x.u[j] < max_log_kappa - ON_BOUND * max_log_kappa.abs().max(1.0)
        {
            continue;
        }
        let (before, after) = (layout.origin[j - 1], layout.origin[j]);
        // A joint between G1 segments is that G1 joint; one cut inside a G1 segment stands for
        // the segment's end that bends more.
        let candidate = if before == after && bend(after + 1) > bend(after) {
            after + 1
        } else {
            after
        };
        if candidate == 0 || candidate >= g1.len() {
            continue;
        }
        let b = bend(candidate);
        if best.is_none_or(|(m, _)| b > m) {
            best = Some((b, candidate));
        }
    }
    best.map_or(Missed::Other, |(_, j)| Missed::Bound(j))
}

/// The chain record of a solved smooth chain.
fn finish(
    smooth: &SmoothInput,
    layout: &Layout,
    e: &Evaluation,
    assign: &[Vec<usize>],
    max_deviation: f64,
) -> Chain {
    let input = smooth.input;
    let starts: Vec<Option<usize>> = assign
        .iter()
        .map(|l| l.iter().map(|&i| input.indices[i]).min())
        .collect();
    // The part's own sample range: a part between corners inside the piece must not reach
    // its neighbours' samples.
    let part = match (
        smooth.chain.segments.iter().find(|s| s.params.is_some()),
        smooth.chain.segments.last(),
    ) {
        (Some(first), Some(last)) => (first.samples.0, last.samples.1),
        _ => input.samples,
    };
    let ranges = tile_ranges(&starts, part);
    let n = layout.n();
    let segments = (0..n)
        .map(|k| {
            let r = &e.residuals[k];
            let max = r.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            let rms = if r.is_empty() {
                0.0
            } else {
                (r.iter().map(|v| v * v).sum::<f64>() / r.len() as f64).sqrt()
            };
            let params = param_interval(input.params, &assign[k]);
            ChainSegment {
                segment: e.segments[k],
                samples: ranges[k],
                max_deviation: max,
                rms_deviation: rms,
                search: smooth.chain.segments[layout.origin[k]].search.clone(),
                alpha_source: crate::chain::AlphaSource::of_smooth(
                    e.segments[k].alpha(),
                    smooth.alpha,
                ),
                alpha_bound: crate::chain::AlphaBound::of(e.segments[k].alpha(), smooth.alpha),
                alpha_uncertainty: smooth_alpha_uncertainty(
                    smooth,
                    &e.segments[k],
                    &assign[k],
                    r,
                    &e.feet[k],
                ),
                start: layout.kinds[k],
                end: if k + 1 < n {
                    layout.kinds[k + 1]
                } else {
                    layout.end_kind
                },
                params,
            }
        })
        .collect();
    Chain {
        segments,
        max_deviation,
        within_tolerance: max_deviation <= smooth.tolerance,
        refined: smooth.chain.refined,
        continuity: smooth.continuity,
    }
}

/// The standard error of a smooth segment's α given its end points and tangents (as for the G1
/// chain's segments, [`super::alpha_evidence`]): the segment rebuilt through them at α ± h by
/// the Yoshida–Saito construction, its samples' signed distances differenced. Its end
/// curvatures then move with α, which the G2 chain does not allow: the figure says how well the
/// samples tell α with the joints' positions and tangents held, not the chain's own conditional.
/// `None` for no α or a fixed one, or where the constructions fail.
pub(super) fn smooth_alpha_uncertainty(
    smooth: &SmoothInput,
    segment: &LacSegment,
    samples: &[usize],
    residuals: &[f64],
    feet: &[f64],
) -> Option<f64> {
    let alpha = segment.alpha()?;
    if matches!(smooth.alpha, AlphaChoice::Fixed(_)) {
        return None;
    }
    let points: Vec<Point> = samples.iter().map(|&i| smooth.input.points[i]).collect();
    let tangent = |theta: f64| Vec2::new(theta.cos(), theta.sin());
    let signed = |x: f64| -> Option<Vec<f64>> {
        let probe = crate::lac::yoshida_saito::fit_g1_near(
            segment.start(),
            tangent(segment.theta0()),
            segment.end(),
            tangent(segment.theta1()),
            x,
            Some(segment),
        )
        .ok()?;
        // The probe is the segment a step of α away: its feet are polished from the
        // segment's own.
        let d = deviation_from(
            &probe,
            &points,
            (feet, segment.length()),
            smooth.chord_error,
        );
        Some(d.signed_distances())
    };
    let step = crate::chain::ALPHA_DIFFERENCE_STEP;
    let (minus, plus) = (signed(alpha - step), signed(alpha + step));
    crate::chain::alpha_uncertainty(residuals, minus.as_deref(), plus.as_deref())
}
