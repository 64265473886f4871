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
//! motion, and a length's follows from the curvatures' by a scaling identity). Samples near a joint are handed to the
//! neighbour that is nearer after every accepted step: a joint slides along the data as the fit
//! moves it.
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
//! of the painting's smooth fit). And where a part fails whose first (last) segment leaves its corner
//! bending beyond the bound (a hook at a corner, κ = 12 /px on painting strokes), that segment's
//! other joint becomes a corner and it stays as the G1 chain has it, but for its tangents: a
//! segment between two corners has both free (a corner is G0), and where the G1 chain's curl
//! beyond the bound they are turned as the G1 chain's piece ends are (`soften_isolated`). One
//! that still curls beyond the bound at a free end after those turns hooks there, and says so:
//! it becomes the line between its ends where that holds its samples, else a line to the sample
//! next to the curl and a segment on from it, meeting at a new corner (`src/chain/unhook.rs`). On
//! the nine recorded fixture files 28 segments bent beyond the bound (4 tighter than half a
//! tolerance in radius) before the hooks were cut, none now, for 26 segments more (820 → 846,
//! most of them lines of a pixel or three at a painting stroke's reversal). A least-squares chain that
//! misses the tolerance by a little is first refitted towards the minimax fit of the same
//! segments (Lawson's reweighting, a few rounds). When the solved chain still leaves a
//! sample farther than the tolerance from its nearest segment, every segment that misses is cut
//! at its middle (a new joint with that point's curvature: the two halves are the same curve, so
//! the chain stays on its constraints) and the fit runs again, at most [`MAX_CUT_ROUNDS`] rounds and until
//! [`STALLED_ROUNDS`] rounds in a row bring the worst sample no nearer. When that is not enough,
//! a part has more than [`MAX_SEGMENTS`] segments, or a chain cannot be built at all, the part
//! keeps its G1 segments and the chain says [`Continuity::G1`].

use super::band::{Band, BandCholesky};
use super::band_lu::BandMatrix;
use super::fit::{
    Chain, ChainInput, ChainSegment, JointKind, nearest_deviation, soften_fits, tile_ranges,
};
use crate::bspline::project::Pieces;
use crate::geom::{Point, Vec2};
use crate::lac::alpha_search::SpanFitOptions;
use crate::lac::deviation::{deviation, deviation_near};
use crate::lac::{AlphaChoice, LacError, LacSegment};
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

/// Continuity at the smooth (non-corner) joints of a chain.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Continuity {
    /// Position and tangent (the seed paper's chains).
    G1,
    /// Position, tangent and curvature: the default (a curve the smooth fit cannot hold within
    /// its tolerance stays G1 and says so).
    #[default]
    G2,
    /// Position, tangent, curvature and its arc-length derivative dκ/ds: a continuous
    /// logarithmic curvature graph across the joint (compound rhythm).
    C3,
}

impl Continuity {
    /// Every mode's name, as the CLI, the service and the documents spell it.
    pub const NAMES: [&'static str; 3] = ["g1", "g2", "c3"];

    /// The mode's name (`g1`, `g2`, `c3`).
    pub fn name(self) -> &'static str {
        match self {
            Continuity::G1 => "g1",
            Continuity::G2 => "g2",
            Continuity::C3 => "c3",
        }
    }
}

impl std::str::FromStr for Continuity {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "g1" => Ok(Continuity::G1),
            "g2" => Ok(Continuity::G2),
            "c3" => Ok(Continuity::C3),
            _ => Err(format!(
                "continuity must be one of {}, got {s:?}",
                Continuity::NAMES.join(", ")
            )),
        }
    }
}

impl std::fmt::Display for Continuity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

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
/// segments) stayed G1, its cut rounds passing 40 on the way; at 60 it is G2 with 54, every
/// fixture curve G2 (the nine files 0.43 → 0.49 s), and the Prius line at 0.1 mm keeps its 35.
pub const MAX_SEGMENTS: usize = 60;

/// Rounds of cuts in a row that do not bring the worst sample nearer before the smooth fit of
/// a part gives up. A round's cuts can move the worst sample elsewhere before the next round
/// resolves it: on the fixture strokes 1 gave 157 of 254 curves G2 in 12 s, 2 gives 162 in 16 s.
pub const STALLED_ROUNDS: usize = 2;

/// Rounds of cutting (every segment that misses the tolerance, at its middle) before the
/// smooth fit gives up and the G1 chain is kept; it also gives up after [`STALLED_ROUNDS`]
/// rounds that do not bring the worst sample nearer. Six rounds can cut a segment into 64, as the G1 chain's
/// subdivision can ([`super::ChainOptions::max_depth`]).
pub const MAX_CUT_ROUNDS: usize = 6;

/// An unknown within this of its bound (α, a log-curvature, a log-length: all dimensionless)
/// is on it.
const BOUND_SLACK: f64 = 1e-9;

/// Iterations of one Levenberg–Marquardt solve. Each accepted step lowers the squared distances;
/// from the G1 chain, 10–20 steps reach the minimum to the stopping rule below.
const MAX_ITERATIONS: usize = 40;

/// The solve stops when an accepted step lowers the sum of squared distances by less than this
/// fraction (or the model predicts less): the distances then move by half a percent. On the
/// fixture strokes in g2 (with the consistent Jacobian of [`shooting_jacobian`]): 1e-3 gave 906
/// segments in 1.52 s, 3e-3 899 in 1.33 s, 1e-2 910 in 1.24 s, all 261 of 263 curves G2 with
/// a median rms distance of 0.26 tolerances (a Jacobian differenced against the distance
/// search's own foot points, at 1e-3: 926 segments, 0.28).
const RELATIVE_DECREASE: f64 = 1e-2;

/// The solve also stops when an accepted step lowers the sum of squared distances by less than
/// this fraction while every sample is within the tolerance: the chain then holds and the steps
/// left would move the distances by a percent or two.
const WITHIN_DECREASE: f64 = 5e-2;

/// Forward-difference step of the unknowns (angles in radians, logs of curvatures and lengths,
/// α): 1e-6 is √ε times the relative accuracy of the evaluation (~1e-12), the step that
/// balances truncation against rounding.
const DIFFERENCE_STEP: f64 = 1e-6;

/// Marquardt's damping starts at this multiple of the normal matrix's diagonal. Most solves
/// start near an answer (a cut chain, a minimax round, a second start), where a bolder first step
/// is refused: on the nine fixture files in g2, 1e-3 took 1.9 trials per Levenberg–Marquardt
/// iteration and 1.14 s for 819 segments, 3e-2 1.03 s for 824, 1e-1 1.04 s for 829, 3e-1 1.20 s
/// for 833. Scanned again with α in the log scale next to inflections: 1e-2 / 3e-2 / 1e-1 /
/// 3e-1 / 1 gave 798 / 803 / 783 / 794 / 813 segments, but 1e-1 took a quarter longer on the
/// median fixture stroke (4.3 ms against 3.4): kept at 3e-2. Scanned once more with the G1
/// chain refined as a start only (see `refine::STARTING_CONVERGED_RMS`), counting instructions
/// over the fixture strokes up to 600 samples (median per stroke, sum) and the nine files'
/// segments: 1e-3 25.2 M, 3 730 M, 797; 3e-3 28.9 M, 3 499 M, 792; 5e-3 25.6 M, 3 320 M, 799;
/// 1e-2 25.3 M, 3 366 M, 795; 3e-2 27.8 M, 3 476 M, 799: 1e-2.
const INITIAL_DAMPING: f64 = 1e-2;

/// Damping after a refused step is multiplied by a factor that starts at this and doubles with
/// each refusal in a row; after an accepted step it is scaled by max(1/3, 1 − (2ρ − 1)³), ρ the
/// ratio of the actual to the predicted decrease (Nielsen's rule): a step that did what the
/// model said lowers it, one that barely helped keeps it. A fixed ×4 / ÷3 made the fit alternate
/// refused and accepted steps (each refusal a projection onto the constraints).
const DAMPING_GROWTH: f64 = 2.0;

/// Beyond this damping the step is too short to matter: the solve has converged or is stuck.
const MAX_DAMPING: f64 = 1e8;

/// A diagonal entry of the normal matrix below this fraction of the largest is raised to it
/// before damping: an unknown the samples barely see (α of a near arc, the curvature at a
/// joint of a near line) is then held by the damping instead of moving freely inside the
/// constraints' null space, where its steps are as long as the linearisation allows and their
/// projections fail. Scanned over the fixture strokes in g2: 1e-9 left 260 of 263 curves G2 with
/// 1 019 segments in 5.5 s; 1e-5 … 1e-3 give 261 with 915–932 segments in 3.3–4.2 s (fewer
/// cuts); 1e-2 and above hold the unknowns too tightly (260 curves).
const DIAGONAL_FLOOR: f64 = 1e-4;

/// A fresh constraint Jacobian is reused for the next projection step while the last step cut
/// the violation at least by this factor (Newton converging, the Jacobian still good enough).
/// On the fixture strokes in g2: a fresh one every step 1.13 s, reuse below 0.03 1.10 s, 0.1
/// 0.99 s, 0.3 1.02 s (923 segments against 910–915: slower steps leave worse trials).
const FRESH_REUSE_RATE: f64 = 0.1;

/// Newton steps projecting a point onto the constraints. From the starting chain (the G1
/// chain with one curvature per joint) the steps converge linearly, a factor of 3 to 20 per
/// step (the bounds clamp some of them): 30 reach the constraints from a violation of the
/// order of the chain's extent (6 left 71 of 254 fixture curves short of them).
const PROJECTION_STEPS: usize = 30;

/// Chord steps projecting a Levenberg–Marquardt trial back onto the constraints (see
/// [`project`]): a trial a damped step away from the constraints converges in two or three; one
/// that does not within this many is refused like a step that raises the cost. On the nine
/// recorded fixture files, 6 gave 915 segments in 0.88 s, 12 gives 896 in 0.78 s.
const TRIAL_PROJECTION_STEPS: usize = 12;

/// Rounds of Lawson's reweighting (see [`minimax`]) a least-squares chain whose largest distance
/// misses the tolerance by at most [`MINIMAX_REACH`] gets before its segments are cut: the
/// samples of a whole-pixel grid lie up to half a pixel's diagonal from the true curve, right at
/// the noise floor's tolerance, and the least-squares fit of the true segments can miss it by a
/// little where a minimax fit of the same segments holds it.
const MINIMAX_ROUNDS: usize = 4;

/// Largest miss, in tolerances, that [`MINIMAX_ROUNDS`] try to recover: Lawson's iteration
/// lowers the largest distance by at most the gap between the least-squares and the minimax
/// fits, a few tens of percent.
const MINIMAX_REACH: f64 = 1.5;

/// Least factor (relative to the largest distance) by which a round of [`minimax`] multiplies a
/// sample's weight: a sample on the curve keeps a say in the next round instead of dropping
/// out for good.
const LAWSON_FLOOR: f64 = 0.05;

/// The joints of a chain in the shooting form (the fit's start and every Levenberg–Marquardt
/// trial) are met to this fraction of the tolerance, not exactly: the next step's linearised
/// constraints carry the gaps left (the KKT system's right-hand side), and the fit's answer is
/// laid out forward, joints meeting by construction and the end point to [`END_TOLERANCE`],
/// before any distance is reported. Exact trials took a Newton step per factor of 3 or so from a step's violation
/// (1e-3 … 1e-1 of the extent) down to 1e-10, most of the smooth fit's time. On the fixture
/// strokes in g2, gaps of 1e-4 of the extent gave 1.40 s for the nine files (1.81 s exact), 1e-3
/// 1.22 s, both with 261 of 263 curves G2; 1e-2 lost a curve. A tenth of the tolerance (over
/// an extent of 300 tolerances, 3e-4) gives 1.24 s.
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

/// The unknowns of a chain.
#[derive(Clone, Debug)]
struct Params {
    theta0: f64,
    /// Each segment's own start point and tangent angle (the shooting form, see [`Form`]).
    pose: Vec<(Point, f64)>,
    /// Log-magnitude of each joint's curvature (unused at zero joints).
    u: Vec<f64>,
    /// Log-length of each segment.
    v: Vec<f64>,
    /// α of each segment (unused where not free).
    alpha: Vec<f64>,
    /// The point the chain's end must meet: fixed at a corner, moved by [`Var::EndShift`] at the
    /// stroke's own end (see [`Layout::free_end`]).
    end: Point,
    /// The G1 chain's start and end points and the normals there, along which
    /// [`Var::StartShift`] and [`Var::EndShift`] move them.
    anchors: [(Point, Vec2); 2],
    /// The shifts of the start and the end along those normals.
    shift: [f64; 2],
}

/// One free unknown.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Var {
    Theta0,
    /// Segment k's start x, y and tangent angle (the shooting form).
    X(usize),
    Y(usize),
    Angle(usize),
    Joint(usize),
    Length(usize),
    Alpha(usize),
    /// The chain's start point across its tangent where it is free (see [`Layout::free_start`]):
    /// along the tangent it would slide beyond the first sample at no cost.
    StartShift,
    /// The chain's end point across its tangent where it is free.
    EndShift,
}

/// The chain's structure: which joints are zero, their signs, which α are free and within what.
#[derive(Clone, Debug)]
struct Layout {
    /// Per joint (n + 1): sign of the curvature, 0 at a zero joint.
    sigma: Vec<f64>,
    /// Per segment: its α range, `None` for a line (both joints zero) or a fixed α.
    alpha_bounds: Vec<Option<(f64, f64)>>,
    /// Per segment: the largest length.
    max_length: Vec<f64>,
    /// Per segment: the largest turning (radians, either sense; see [`MAX_EXTRA_TURNING`]).
    max_turning: Vec<f64>,
    /// Per segment: the joint kind at its start (the last segment's end is in `end_kind`).
    kinds: Vec<JointKind>,
    end_kind: JointKind,
    /// The α search record carried from the G1 segment each segment comes from.
    origin: Vec<usize>,
}

/// How the unknowns lay out a chain.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Form {
    /// Multiple shooting: every segment from its own start pose, the joints' positions and
    /// tangents as equality constraints. A parameter moves one or two segments only, so the
    /// problem is as well conditioned on a 50-segment chain as on a 2-segment one; this is the
    /// form the fit runs in.
    Shooting,
    /// Forward: the chain laid out from its start pose, continuity by construction; the end
    /// point the only position constraint. The fit's answer is moved into it by a few Newton
    /// steps at the end, so that joints meet exactly, not to a tolerance.
    Forward,
}

impl Layout {
    fn n(&self) -> usize {
        self.alpha_bounds.len()
    }

    /// Whether the chain's start point is an unknown: at the stroke's own start, where the
    /// B-spline's end carries the first sample's noise (a whole-pixel grid puts it up to half a
    /// pixel's diagonal from the curve drawn). A corner is shared with the neighbouring part and
    /// stays.
    fn free_start(&self) -> bool {
        self.kinds.first() == Some(&JointKind::Start)
    }

    /// Whether the chain's end point is an unknown (as [`Layout::free_start`]).
    fn free_end(&self) -> bool {
        self.end_kind == JointKind::End
    }

    /// The end point's unknown where it is free.
    fn end_vars(&self) -> Vec<Var> {
        if self.free_end() {
            vec![Var::EndShift]
        } else {
            Vec::new()
        }
    }

    /// The forward form's unknowns: the start angle, then [`Layout::shape_vars`], then the free
    /// end point's (the forward form lays the chain out from the start pose of the shooting
    /// form's first segment).
    fn vars(&self) -> Vec<Var> {
        let mut vars = vec![Var::Theta0];
        vars.extend(self.shape_vars());
        vars.extend(self.end_vars());
        vars
    }

    /// The unknowns both forms share: the joints' log-curvatures (but zero joints), the
    /// segments' log-lengths and their free α.
    fn shape_vars(&self) -> Vec<Var> {
        let mut vars = Vec::new();
        vars.extend(
            (0..=self.n())
                .filter(|&j| self.sigma[j] != 0.0)
                .map(Var::Joint),
        );
        vars.extend((0..self.n()).map(Var::Length));
        vars.extend(
            (0..self.n())
                .filter(|&k| self.alpha_bounds[k].is_some())
                .map(Var::Alpha),
        );
        vars
    }

    /// The shooting form's unknowns.
    fn shooting_vars(&self) -> Vec<Var> {
        let mut vars: Vec<Var> = (0..self.n()).map(Var::Angle).collect();
        if self.free_start() {
            vars.push(Var::StartShift);
        }
        vars.extend((1..self.n()).flat_map(|k| [Var::X(k), Var::Y(k)]));
        vars.extend(self.shape_vars());
        vars.extend(self.end_vars());
        vars
    }

    fn vars_of(&self, form: Form) -> Vec<Var> {
        match form {
            Form::Shooting => self.shooting_vars(),
            Form::Forward => self.vars(),
        }
    }

    /// Every segment from its own start pose.
    fn build_shooting(&self, x: &Params) -> Result<Vec<LacSegment>, LacError> {
        (0..self.n())
            .map(|k| self.segment(x, k, x.pose[k].0, x.pose[k].1))
            .collect()
    }

    fn build_form(&self, form: Form, x: &Params) -> Result<Vec<LacSegment>, LacError> {
        match form {
            Form::Shooting => self.build_shooting(x),
            Form::Forward => self.build(x, x.pose[0].0),
        }
    }

    /// The segments a change of `var` reshapes in the shooting form (none, `(1, 0)`, for the
    /// end point).
    fn shooting_reach(&self, var: Var) -> (usize, usize) {
        match var {
            Var::Theta0 => (0, 0),
            Var::EndShift => (1, 0),
            Var::StartShift => (0, 0),
            Var::X(k) | Var::Y(k) | Var::Angle(k) | Var::Length(k) | Var::Alpha(k) => (k, k),
            Var::Joint(j) => (j.saturating_sub(1), j.min(self.n() - 1)),
        }
    }

    fn kappa(&self, x: &Params, j: usize) -> f64 {
        if self.sigma[j] == 0.0 {
            0.0
        } else {
            self.sigma[j] * x.u[j].exp()
        }
    }

    /// Segment k of `x` starting at `start` with tangent angle `theta`.
    fn segment(
        &self,
        x: &Params,
        k: usize,
        start: Point,
        theta: f64,
    ) -> Result<LacSegment, LacError> {
        let (ka, kb) = (self.kappa(x, k), self.kappa(x, k + 1));
        let alpha = (ka != kb).then_some(x.alpha[k]);
        LacSegment::new(start, theta, x.v[k].exp(), alpha, ka, kb)
    }

    /// The whole chain of `x` from `start`.
    fn build(&self, x: &Params, start: Point) -> Result<Vec<LacSegment>, LacError> {
        let mut segments: Vec<LacSegment> = Vec::with_capacity(self.n());
        let (mut p, mut theta) = (start, x.theta0);
        for k in 0..self.n() {
            let seg = self.segment(x, k, p, theta)?;
            p = seg.end();
            theta = seg.theta1();
            segments.push(seg);
        }
        Ok(segments)
    }

    /// Segments `k0..=k1` of `x` rebuilt from the start pose of `segments[k0]`.
    fn rebuild(
        &self,
        x: &Params,
        segments: &[LacSegment],
        k0: usize,
        k1: usize,
    ) -> Result<Vec<LacSegment>, LacError> {
        let (mut p, mut theta) = (segments[k0].start(), segments[k0].theta0());
        let mut out = Vec::with_capacity(k1 + 1 - k0);
        for k in k0..=k1 {
            let seg = self.segment(x, k, p, theta)?;
            p = seg.end();
            theta = seg.theta1();
            out.push(seg);
        }
        Ok(out)
    }

    /// The segments a change of `var` reshapes (the rest before them stay, after them move
    /// rigidly).
    fn reach(&self, var: Var) -> (usize, usize) {
        match var {
            Var::Theta0 => (0, self.n() - 1),
            Var::EndShift => (1, 0),
            Var::StartShift => (0, self.n() - 1),
            Var::Joint(j) => (j.saturating_sub(1), j.min(self.n() - 1)),
            Var::Length(k) | Var::Alpha(k) | Var::X(k) | Var::Y(k) | Var::Angle(k) => (k, k),
        }
    }

    /// Whether a segment of `segments` (laid out by this layout) turns more than its
    /// [`MAX_EXTRA_TURNING`] bound.
    fn winds(&self, segments: &[LacSegment]) -> bool {
        segments
            .iter()
            .zip(&self.max_turning)
            .any(|(s, &max)| (s.theta1() - s.theta0()).abs() > max)
    }

    /// Interior joints whose dκ/ds is constrained (C3): the non-zero ones.
    fn c3_joints(&self) -> Vec<usize> {
        (1..self.n()).filter(|&j| self.sigma[j] != 0.0).collect()
    }

    /// Whether segment k's α is an unknown in the log scale w = −ln(−α) (α = −e^{−w}) rather
    /// than α itself: where the segment has a zero-curvature end (its α < 0 by its bounds).
    /// There the curvature leaves zero as s^{−1/α}, the shape is a power of the exponent −1/α,
    /// and a step in α moves it by 1/α² (25 times as much at α = −0.2 as at −1): a Gauss–Newton
    /// step that fits at α = −1.4 overshoots by far at −0.3. In w a step is a factor of α; a
    /// painting stroke's S whose α went from −1.35 to −0.2 in eight shrinking steps takes six.
    /// (For every α ≤ [`ZERO_END_ALPHA`] the nine recorded fixture files gave 11 segments fewer
    /// still, but a planted chain of three segments with a clothoid between two non-zero
    /// curvatures came back as four.)
    fn log_alpha(&self, x: &Params, k: usize) -> bool {
        (self.sigma[k] == 0.0 || self.sigma[k + 1] == 0.0) && x.alpha[k] < 0.0
    }

    /// Whether `var` sits on its bound in `x` with `direction` (the sign of a step) pointing
    /// beyond it.
    fn pushed_beyond(&self, var: Var, x: &Params, direction: f64, log_kappa: (f64, f64)) -> bool {
        let at = |value: f64, lo: f64, hi: f64| {
            (value >= hi - BOUND_SLACK && direction > 0.0)
                || (value <= lo + BOUND_SLACK && direction < 0.0)
        };
        match var {
            Var::Alpha(k) => self.alpha_bounds[k].is_some_and(|(lo, hi)| at(x.alpha[k], lo, hi)),
            Var::Joint(j) => at(x.u[j], log_kappa.0, log_kappa.1),
            Var::Length(k) => at(x.v[k], f64::NEG_INFINITY, self.max_length[k].ln()),
            _ => false,
        }
    }

    /// Clamps `x` into the box: α within its bounds, curvature within the cap, length within
    /// its largest.
    fn clamp(&self, x: &mut Params, (min_log_kappa, max_log_kappa): (f64, f64)) {
        for k in 0..self.n() {
            if let Some((lo, hi)) = self.alpha_bounds[k] {
                x.alpha[k] = x.alpha[k].clamp(lo, hi);
            }
            x.v[k] = x.v[k].min(self.max_length[k].ln());
        }
        for u in &mut x.u {
            *u = u.clamp(min_log_kappa, max_log_kappa);
        }
    }
}

fn get(layout: &Layout, x: &Params, var: Var) -> f64 {
    match var {
        Var::Theta0 => x.theta0,
        Var::X(k) => x.pose[k].0.x,
        Var::Y(k) => x.pose[k].0.y,
        Var::Angle(k) => x.pose[k].1,
        Var::Joint(j) => x.u[j],
        Var::Length(k) => x.v[k],
        Var::Alpha(k) if layout.log_alpha(x, k) => -(-x.alpha[k]).ln(),
        Var::Alpha(k) => x.alpha[k],
        Var::StartShift => x.shift[0],
        Var::EndShift => x.shift[1],
    }
}

fn set(layout: &Layout, x: &mut Params, var: Var, value: f64) {
    match var {
        Var::Theta0 => x.theta0 = value,
        Var::X(k) => x.pose[k].0.x = value,
        Var::Y(k) => x.pose[k].0.y = value,
        Var::Angle(k) => x.pose[k].1 = value,
        Var::Joint(j) => x.u[j] = value,
        Var::Length(k) => x.v[k] = value,
        Var::Alpha(k) if layout.log_alpha(x, k) => x.alpha[k] = -(-value).exp(),
        Var::Alpha(k) => x.alpha[k] = value,
        Var::StartShift => {
            x.shift[0] = value;
            x.pose[0].0 = x.anchors[0].0 + x.anchors[0].1 * value;
        }
        Var::EndShift => {
            x.shift[1] = value;
            x.end = x.anchors[1].0 + x.anchors[1].1 * value;
        }
    }
}

/// The left normal of tangent angle θ.
fn normal(theta: f64) -> Vec2 {
    let (s, c) = theta.sin_cos();
    Vec2::new(-s, c)
}

fn perp(v: Vec2) -> Vec2 {
    Vec2::new(-v.y, v.x)
}

/// The samples' signed distances to a chain, with their feet.
#[derive(Clone, Debug)]
struct Evaluation {
    segments: Vec<LacSegment>,
    /// Per segment, per assigned sample: signed distance (left of travel positive).
    residuals: Vec<Vec<f64>>,
    /// Per segment, per assigned sample: foot arc length.
    feet: Vec<Vec<f64>>,
    /// Per segment, per assigned sample: foot point and left normal there.
    foot_points: Vec<Vec<(Point, Vec2)>>,
    cost: f64,
}

struct Solver<'a> {
    points: &'a [Point],
    start: Point,
    scale: f64,
    chord_error: f64,
    /// Bounds of the joints' log-curvature magnitudes (see [`MIN_RADIUS_TOLERANCES`],
    /// [`MAX_RADIUS_EXTENTS`]).
    log_kappa: (f64, f64),
    c3: bool,
    /// How much looser than exact ([`END_TOLERANCE`], [`C3_TOLERANCE`]) a trial step's
    /// projection need meet the constraints (see [`TRIAL_GAP_TOLERANCES`]).
    trial_slack: f64,
    /// Per sample, the weight of its squared distance in the fit's cost (empty: all 1; see
    /// [`MINIMAX_ROUNDS`]).
    weights: Vec<f64>,
    /// Whether the fit is refitting for the largest distance ([`minimax`]): it then stops as
    /// soon as every sample is within the tolerance.
    minimax: bool,
    /// The part's tolerance (see [`WITHIN_DECREASE`]).
    tolerance: f64,
}

impl Solver<'_> {
    fn points_of(&self, list: &[usize]) -> Vec<Point> {
        list.iter().map(|&i| self.points[i]).collect()
    }

    /// The weight of sample `i`'s squared distance.
    fn weight(&self, i: usize) -> f64 {
        self.weights.get(i).copied().unwrap_or(1.0)
    }

    /// Distances of the assigned samples to `segments`, seeded at `near`'s feet where its
    /// segment holds the same samples.
    fn evaluate(
        &self,
        segments: Vec<LacSegment>,
        assign: &[Vec<usize>],
        near: Option<(&Evaluation, &[Vec<usize>])>,
    ) -> Evaluation {
        let n = segments.len();
        let mut e = Evaluation {
            residuals: Vec::with_capacity(n),
            feet: Vec::with_capacity(n),
            foot_points: Vec::with_capacity(n),
            cost: 0.0,
            segments,
        };
        for (k, list) in assign.iter().enumerate() {
            let seg = &e.segments[k];
            let pts = self.points_of(list);
            let mut d = match near {
                Some((old, old_assign)) if old_assign.get(k) == Some(list) => deviation_from(
                    seg,
                    &pts,
                    (&old.feet[k], old.segments[k].length()),
                    self.chord_error,
                ),
                _ => deviation(seg, &pts, self.chord_error),
            };
            let foot_points = if d.foot_points.len() == pts.len() {
                std::mem::take(&mut d.foot_points)
            } else {
                d.feet
                    .iter()
                    .map(|&s| {
                        let sample = seg.sample(s);
                        (sample.point, normal(sample.theta))
                    })
                    .collect()
            };
            let residuals: Vec<f64> = d
                .distances
                .iter()
                .zip(&d.sides)
                .map(|(dist, side)| if *side < 0.0 { -dist } else { *dist })
                .collect();
            // The residual's gradient direction: the normal at an interior foot, the direction
            // from the foot where the foot is a segment end (a sample beyond it).
            let foot_points: Vec<(Point, Vec2)> = foot_points
                .into_iter()
                .zip(pts.iter().zip(&residuals))
                .map(|((f, n), (q, r))| {
                    let v = *q - f;
                    if v.hypot() > 0.0 && *r != 0.0 {
                        (f, v / *r)
                    } else {
                        (f, n)
                    }
                })
                .collect();
            e.cost += residuals
                .iter()
                .zip(list)
                .map(|(r, &i)| self.weight(i) * r * r)
                .sum::<f64>();
            e.residuals.push(residuals);
            e.feet.push(d.feet);
            e.foot_points.push(foot_points);
        }
        e
    }

    /// The constraint values of a chain: end point minus the target (scaled by the extent);
    /// in the shooting form each joint's position and tangent gaps (the segment's end pose
    /// minus the next one's start pose in `x`); then for C3 the dκ/ds differences at
    /// `c3_joints`.
    fn constraints(
        &self,
        form: Form,
        segments: &[LacSegment],
        x: &Params,
        c3_joints: &[usize],
    ) -> DVector<f64> {
        let mut c = Vec::with_capacity(2 + 3 * segments.len() + c3_joints.len());
        let end = segments.last().map_or(self.start, |s| s.end());
        c.push((end.x - x.end.x) / self.scale);
        c.push((end.y - x.end.y) / self.scale);
        if form == Form::Shooting {
            for k in 1..segments.len() {
                let (p, theta) = x.pose[k];
                let before = &segments[k - 1];
                c.push((before.end().x - p.x) / self.scale);
                c.push((before.end().y - p.y) / self.scale);
                c.push(before.theta1() - theta);
            }
        }
        if self.c3 {
            for &j in c3_joints {
                c.push(c3_gap(&segments[j - 1], &segments[j]));
            }
        }
        DVector::from_vec(c)
    }

    /// Whether `c` (from [`Solver::constraints`] of an `n`-segment chain) is met to `slack`
    /// times [`END_TOLERANCE`] and [`C3_TOLERANCE`].
    fn constraints_met(&self, form: Form, n: usize, c: &DVector<f64>, slack: f64) -> bool {
        let positions = match form {
            Form::Shooting => 2 + 3 * n.saturating_sub(1),
            Form::Forward => 2,
        };
        c.iter().enumerate().all(|(i, v)| {
            v.abs()
                <= slack
                    * if i < positions {
                        END_TOLERANCE
                    } else {
                        C3_TOLERANCE
                    }
        })
    }
}

/// The C3 condition at a joint as a dimensionless gap: the difference of dκ/ds either side
/// relative to their magnitude (dκ/ds of both sides share the joint's curvature, so the gap is
/// the relative jump of the logarithmic curvature graph's ordinate there, to first order).
fn c3_gap(before: &LacSegment, after: &LacSegment) -> f64 {
    let a = before.dkappa_ds(before.length());
    let b = after.dkappa_ds(0.0);
    let scale = a.abs().max(b.abs());
    if scale > 0.0 && scale.is_finite() {
        (a - b) / scale
    } else {
        0.0
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
    let segments = &chain.segments;
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
    // Whether some part had joints to make smooth: otherwise every segment is the G1 chain's,
    // holding the same samples, and so is the chain's largest distance.
    let mut refitted = false;
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
        let fitted = smooth_part(&SmoothInput {
            chain: &part,
            ..*smooth
        });
        let fitted = match fitted {
            Ok(f) => f,
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
    // A segment between two corners (or a corner and the stroke's end) has both tangents free,
    // but kept the G1 chain's, which curl where the G1 joint bent beyond the bound: its ends are
    // turned as the G1 chain's piece ends are (see [`soften_tries`]).
    for segment in &mut out {
        refitted |= soften_isolated(smooth, segment, cap);
    }
    // The parts' ranges tiled as one piece: a segment holding no samples has the one-sample
    // range of the last sample before it, also at the start of a part.
    let tile = |out: &mut Vec<ChainSegment>| {
        let starts: Vec<Option<usize>> =
            out.iter().map(|s| s.params.map(|_| s.samples.0)).collect();
        for (s, range) in out
            .iter_mut()
            .zip(tile_ranges(&starts, smooth.input.samples))
        {
            s.samples = range;
        }
    };
    tile(&mut out);
    // One that still curls beyond the bound hooks there: it becomes a line, or a line and a
    // segment meeting at a corner (see `src/chain/unhook.rs`), each holding its share of the
    // segment's own samples (its tiled range); the ranges are tiled again after.
    let mut unhooked = Vec::with_capacity(out.len());
    for segment in out {
        let own: Vec<usize> = match segment.params {
            Some(_) => (0..smooth.input.points.len())
                .filter(|&i| {
                    (segment.samples.0..=segment.samples.1).contains(&smooth.input.indices[i])
                })
                .collect(),
            None => Vec::new(),
        };
        match super::unhook::unhook(smooth, &segment, &own, cap) {
            Some(replacement) => {
                refitted = true;
                unhooked.extend(replacement);
            }
            None => unhooked.push(segment),
        }
    }
    let mut out = unhooked;
    tile(&mut out);
    if !refitted {
        return Some(Chain {
            segments: out,
            continuity: smooth.continuity,
            ..chain.clone()
        });
    }
    // The whole chain's largest distance, each sample to its nearest segment: a part kept G1
    // carries the whole G1 chain's figure, and a sample may lie nearer a neighbouring part.
    let points = smooth.input.points;
    let lists: Vec<Vec<usize>> = out
        .iter()
        .map(|s| {
            (0..points.len())
                .filter(|&i| (s.samples.0..=s.samples.1).contains(&smooth.input.indices[i]))
                .collect()
        })
        .collect();
    let own: Vec<Vec<f64>> = out
        .iter()
        .zip(&lists)
        .map(|(s, list)| {
            let pts: Vec<Point> = list.iter().map(|&i| points[i]).collect();
            deviation(&s.segment, &pts, smooth.chord_error).distances
        })
        .collect();
    let segments: Vec<LacSegment> = out.iter().map(|s| s.segment).collect();
    let max_deviation = nearest_deviation(points, &segments, &lists, &own, smooth.chord_error);
    Some(Chain {
        segments: out,
        max_deviation,
        within_tolerance: max_deviation <= smooth.tolerance,
        refined: chain.refined,
        continuity: if all_smooth {
            smooth.continuity
        } else {
            Continuity::G1
        },
    })
}

/// Refits `s` with turned end tangents where both its ends are free (corners, or the stroke's
/// own ends) and one of them bends beyond `cap`: the first of [`soften_tries`] whose segment
/// (α searched again, within `cap`) holds its samples within the tolerance. Returns whether it
/// was refitted.
fn soften_isolated(smooth: &SmoothInput, s: &mut ChainSegment, cap: f64) -> bool {
    let bend = |seg: &LacSegment| seg.kappa0().abs().max(seg.kappa1().abs());
    let segment = s.segment;
    if !(s.start.tangent_free() && s.end.tangent_free())
        || bend(&segment) <= cap
        || s.params.is_none()
    {
        return false;
    }
    let input = smooth.input;
    let list: Vec<usize> = (0..input.points.len())
        .filter(|&i| (s.samples.0..=s.samples.1).contains(&input.indices[i]))
        .collect();
    if list.is_empty() {
        return false;
    }
    let points: Vec<Point> = list.iter().map(|&i| input.points[i]).collect();
    let options = SpanFitOptions {
        choice: smooth.alpha,
        max_curvature: cap,
        guess: segment.alpha(),
        // Only a segment within the tolerance is kept: a guess farther off is not searched on.
        abandon_above: smooth.tolerance,
        unreachable_above: smooth.tolerance,
        ..SpanFitOptions::new(smooth.chord_error)
    };
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
        smooth_alpha_uncertainty(smooth, &fit.segment, &list, &d.signed_distances(), &d.feet);
    s.alpha_bound = super::AlphaBound::of(fit.segment.alpha(), smooth.alpha);
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
    /// Otherwise (no chain meeting the constraints, or cuts that stopped helping).
    Other,
}

/// [`smooth_chain`] of a chain without forced corners.
fn smooth_part(smooth: &SmoothInput) -> Result<Chain, Missed> {
    let input = smooth.input;
    let chain = smooth.chain;
    let points = input.points;
    // Each G1 segment's local samples (points whose original index lies in its range); a
    // segment holding none repeats the index of the last sample before it, which may be the
    // previous part's.
    let mut assign: Vec<Vec<usize>> = chain
        .segments
        .iter()
        .map(|s| {
            if s.params.is_none() {
                return Vec::new();
            }
            (0..points.len())
                .filter(|&i| {
                    let o = input.indices[i];
                    o >= s.samples.0 && o <= s.samples.1
                })
                .collect()
        })
        .collect();
    // A sample on a range boundary (a segment without samples repeats its neighbour's index)
    // belongs to one segment only.
    let mut taken = vec![false; points.len()];
    for list in &mut assign {
        list.retain(|&i| !std::mem::replace(&mut taken[i], true));
    }
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
    let mut missed = Missed::Other;
    for start in [JointStart::Spline, JointStart::Chain] {
        match smooth_from(smooth, assign.clone(), start) {
            Ok(chain) => return Ok(chain),
            Err(Missed::Bound(j)) => {
                missed = Missed::Bound(j);
                break;
            }
            Err(_) => {}
        }
    }
    Err(missed)
}

/// Where the joints' curvatures of the starting chain come from (see [`start_layout`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum JointStart {
    /// The B-spline's curvature at the joint, where its sign agrees with the chain's.
    Spline,
    /// The G1 chain's two sides' geometric mean.
    Chain,
}

/// [`smooth_part`] from the joint curvatures of `start`.
fn smooth_from(
    smooth: &SmoothInput,
    mut assign: Vec<Vec<usize>>,
    joint_start: JointStart,
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
        tolerance: smooth.tolerance,
    };
    layout.clamp(&mut x, solver.log_kappa);
    let (mut best_worst, mut stalled) = (f64::INFINITY, 0);
    for round in 0..=MAX_CUT_ROUNDS {
        if layout.n() > MAX_SEGMENTS {
            return Err(Missed::Other);
        }
        let started = (round == 0).then(|| (x.clone(), assign.clone()));
        let mut evaluation =
            solve(&solver, &layout, &mut x, &mut assign, None).ok_or(Missed::Other)?;
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
        // Every sample within the tolerance of its own segment and of the whole chain: done.
        let held = |evaluation: &Evaluation, assign: &[Vec<usize>], own: &[Vec<f64>]| {
            let nearest = nearest_deviation(
                points,
                &evaluation.segments,
                assign,
                own,
                smooth.chord_error,
            );
            (nearest <= smooth.tolerance)
                .then(|| finish(smooth, &layout, evaluation, assign, nearest))
        };
        if worst <= smooth.tolerance {
            if let Some(chain) = held(&evaluation, &assign, &own) {
                return Ok(chain);
            }
        } else if worst <= MINIMAX_REACH * smooth.tolerance
            // A near miss is first fitted for its largest distance rather than cut (see
            // [`MINIMAX_ROUNDS`]).
            && let Some((evaluation, assign)) =
                minimax(&mut solver, &layout, &x, &assign, &evaluation)
            && let Some(chain) = held(&evaluation, &assign, &distances(&evaluation))
        {
            return Ok(chain);
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

/// The α of a second start (see [`smooth_from`]): each segment's G1 α where it lies inside the
/// segment's α bounds, the first start's elsewhere; `None` unless some segment of the fitted
/// `x` ended with its α on a bound while its G1 α lies inside.
fn g1_alpha_start(
    layout: &Layout,
    x: &Params,
    first: &Params,
    g1: &[ChainSegment],
) -> Option<Vec<f64>> {
    let mut alpha = first.alpha.clone();
    let mut stuck = false;
    for k in 0..layout.n() {
        let (Some((lo, hi)), Some(a)) = (
            layout.alpha_bounds[k],
            g1.get(layout.origin[k]).and_then(|s| s.segment.alpha()),
        ) else {
            continue;
        };
        if a > lo + BOUND_SLACK && a < hi - BOUND_SLACK {
            stuck |= x.alpha[k] <= lo + BOUND_SLACK || x.alpha[k] >= hi - BOUND_SLACK;
            alpha[k] = a;
        }
    }
    stuck.then_some(alpha)
}

/// The largest of an evaluation's distances.
fn largest_distance(e: &Evaluation) -> f64 {
    e.residuals
        .iter()
        .flatten()
        .fold(0.0_f64, |m, r| m.max(r.abs()))
}

/// Each segment's samples' distances (unsigned) in an evaluation.
fn distances(e: &Evaluation) -> Vec<Vec<f64>> {
    e.residuals
        .iter()
        .map(|r| r.iter().map(|v| v.abs()).collect())
        .collect()
}

/// The least-squares chain of `layout` at `x` refitted for its largest distance (Lawson's
/// iteration): each round multiplies every sample's weight by its distance (relative to the
/// largest, at least [`LAWSON_FLOOR`]) and solves again from the last answer, which moves the
/// chain towards the minimax fit of the same segments. The first round whose largest distance
/// is within the tolerance is returned with its assignment; `None` if none is within
/// [`MINIMAX_ROUNDS`]. The solver's weights are left uniform.
fn minimax(
    solver: &mut Solver,
    layout: &Layout,
    x: &Params,
    assign: &[Vec<usize>],
    evaluation: &Evaluation,
) -> Option<(Evaluation, Vec<Vec<usize>>)> {
    let (mut x, mut assign) = (x.clone(), assign.to_vec());
    solver.weights = vec![1.0; solver.points.len()];
    solver.minimax = true;
    let mut found = None;
    let mut last: Option<Evaluation> = None;
    for _ in 0..MINIMAX_ROUNDS {
        let e = last.as_ref().unwrap_or(evaluation);
        let worst = largest_distance(e);
        if !(worst > 0.0) {
            break;
        }
        for (residuals, list) in e.residuals.iter().zip(&assign) {
            for (r, &i) in residuals.iter().zip(list) {
                solver.weights[i] *= (r.abs() / worst).max(LAWSON_FLOOR);
            }
        }
        let total: f64 = solver.weights.iter().sum();
        let mean = total / solver.weights.len() as f64;
        if !(mean > 0.0 && mean.is_finite()) {
            break;
        }
        for w in &mut solver.weights {
            *w /= mean;
        }
        let before = assign.clone();
        let Some(next) = solve(solver, layout, &mut x, &mut assign, Some((e, &before))) else {
            break;
        };
        if largest_distance(&next) <= solver.tolerance {
            found = Some((next, assign));
            break;
        }
        last = Some(next);
    }
    solver.weights = Vec::new();
    solver.minimax = false;
    found
}

/// The largest own distance and the segment holding it.
fn worst_sample(own: &[Vec<f64>]) -> (f64, Option<usize>) {
    let mut best = (0.0, None);
    for (k, d) in own.iter().enumerate() {
        for &v in d {
            if v > best.0 || best.1.is_none() {
                best = (v.max(best.0), Some(k));
            }
        }
    }
    best
}

/// The layout and starting unknowns from the G1 chain (see the module documentation); `None`
/// where the α choice cannot make an inflection G2.
fn start_layout(
    smooth: &SmoothInput,
    assign: &mut Vec<Vec<usize>>,
    max_log_kappa: f64,
    joint_start: JointStart,
) -> Option<(Layout, Params)> {
    let segs: Vec<LacSegment> = smooth.chain.segments.iter().map(|s| s.segment).collect();
    let side = |s: &LacSegment| {
        let t = s.kappa0() + s.kappa1();
        if t > 0.0 {
            1.0
        } else if t < 0.0 {
            -1.0
        } else {
            0.0
        }
    };
    let n = segs.len();
    // The B-spline's curvature at each joint (its foot on the B-spline): the G1 chain's two
    // sides differ there, the B-spline, a C2 curve within the tolerance of the same samples, has
    // one value.
    let pieces = Pieces::new(smooth.input.curve.to_beziers());
    let spline_kappa = |j: usize| -> f64 {
        let (q, guess) = if j < n {
            (
                segs[j].start(),
                smooth.chain.segments[j].params.map(|p| p.0),
            )
        } else {
            (
                segs[n - 1].end(),
                smooth.chain.segments[n - 1].params.map(|p| p.1),
            )
        };
        let guess = guess.unwrap_or_else(|| pieces.domain().0);
        let foot = pieces.project_local(q, guess);
        let (_, d1, d2) = pieces.eval_derivs(foot.u);
        let speed = d1.hypot();
        if speed > 0.0 {
            d1.cross(d2) / (speed * speed * speed)
        } else {
            0.0
        }
    };
    let mut sigma = Vec::with_capacity(n + 1);
    let mut u = Vec::with_capacity(n + 1);
    for j in 0..=n {
        let (g1, s) = if j == 0 {
            (segs[0].kappa0().abs(), side(&segs[0]))
        } else if j == n {
            (segs[n - 1].kappa1().abs(), side(&segs[n - 1]))
        } else {
            let (a, b) = (segs[j - 1].kappa1().abs(), segs[j].kappa0().abs());
            let (sa, sb) = (side(&segs[j - 1]), side(&segs[j]));
            if sa * sb <= 0.0 {
                (0.0, 0.0)
            } else {
                let mean = match (a == 0.0, b == 0.0) {
                    (false, false) => (a * b).sqrt(),
                    (true, false) => b,
                    (false, true) => a,
                    (true, true) => 0.0,
                };
                (mean, sa)
            }
        };
        if g1 == 0.0 || s == 0.0 {
            sigma.push(0.0);
            u.push(0.0);
            continue;
        }
        let spline = match joint_start {
            JointStart::Spline => spline_kappa(j),
            JointStart::Chain => 0.0,
        };
        let magnitude = if spline * s > 0.0 { spline.abs() } else { g1 };
        sigma.push(s);
        u.push(magnitude.ln());
    }
    let mut layout = Layout {
        sigma,
        alpha_bounds: Vec::with_capacity(n),
        max_length: segs
            .iter()
            .map(|s| MAX_LENGTH_FACTOR * s.length())
            .collect(),
        max_turning: segs
            .iter()
            .map(|s| (s.theta1() - s.theta0()).abs() + MAX_EXTRA_TURNING)
            .collect(),
        kinds: smooth.chain.segments.iter().map(|s| s.start).collect(),
        end_kind: smooth.chain.segments[n - 1].end,
        origin: (0..n).collect(),
    };
    // Each segment's start pose, its angle continued from the one before (the G1 segments keep
    // theirs in (−π, π]).
    let mut pose = Vec::with_capacity(n);
    let mut theta = segs[0].theta0();
    for (k, seg) in segs.iter().enumerate() {
        if k > 0 {
            // The G1 chain's segments keep their own angles in (−π, π]; a smooth chain's run
            // on continuously.
            theta += crate::geom::wrap_angle(seg.theta0() - segs[k - 1].theta1());
        }
        pose.push((seg.start(), theta));
        theta += seg.theta1() - seg.theta0();
    }
    let mut x = Params {
        theta0: segs[0].theta0(),
        pose,
        u,
        v: segs.iter().map(|s| s.length().ln()).collect(),
        alpha: segs.iter().map(|s| s.alpha().unwrap_or(-1.0)).collect(),
        end: segs[n - 1].end(),
        anchors: [
            (segs[0].start(), normal(segs[0].theta0())),
            (segs[n - 1].end(), normal(segs[n - 1].theta1())),
        ],
        shift: [0.0; 2],
    };
    for k in 0..n {
        layout.alpha_bounds.push(None);
        set_alpha_bounds(smooth.alpha, &mut layout, &mut x, k)?;
        x.u.iter_mut().for_each(|u| *u = u.min(max_log_kappa));
        if let Some(bounds) = layout.alpha_bounds[k] {
            let target = segs[k].theta1() - segs[k].theta0();
            x.alpha[k] = alpha_for_turning(&layout, &x, k, target, bounds);
        }
    }
    // A segment that bends to the end where the smooth chain asks κ = 0 of it (an arc into an
    // inflection or a line) keeps its G1 shape but for a transition spiral at that end, as
    // long as a clothoid leaving the arc drifts from it by the tolerance: a G1 arc swept to zero
    // curvature over its whole length starts the fit far from the samples (half a pixel's
    // tolerance, an S of two 270° arcs drawn with a mouse: 17 px off, 12 segments after the
    // cuts; with the transitions 4).
    let mut k = 0;
    while k < layout.n() {
        let Some(seg) = segs.get(layout.origin[k]).copied() else {
            k += 1;
            continue;
        };
        let (zero_a, zero_b) = (layout.sigma[k] == 0.0, layout.sigma[k + 1] == 0.0);
        let bend = match (zero_a, zero_b) {
            (true, false) => seg.kappa0().abs(),
            (false, true) => seg.kappa1().abs(),
            _ => 0.0,
        };
        let transition = (TRANSITION_SHIFT * smooth.tolerance / bend).sqrt();
        if !(bend > 0.0 && transition < TRANSITION_SHARE * seg.length()) {
            k += 1;
            continue;
        }
        let at = if zero_a {
            transition
        } else {
            seg.length() - transition
        };
        let feet: Vec<f64> = {
            let pts: Vec<Point> = assign[k].iter().map(|&i| smooth.input.points[i]).collect();
            deviation(&seg, &pts, smooth.chord_error).feet
        };
        let pose = (seg.point(at), x.pose[k].1 + seg.theta(at) - seg.theta0());
        let kappa = seg.kappa(at);
        if kappa == 0.0 || !kappa.is_finite() {
            k += 1;
            continue;
        }
        split_at(&mut layout, &mut x, assign, k, (kappa, pose), at, &feet);
        // The part away from the zero joint keeps the G1 segment's α (any α: both its ends
        // curve); the transition starts as a clothoid.
        let (far, near) = if zero_a { (k + 1, k) } else { (k, k + 1) };
        x.alpha[far] = seg.alpha().unwrap_or(-1.0);
        x.alpha[near] = -1.0;
        for m in [k, k + 1] {
            set_alpha_bounds(smooth.alpha, &mut layout, &mut x, m)?;
        }
        k += 2;
    }
    // A curved segment between two zero joints is cut at its middle (it could only be a line).
    let mut k = 0;
    while k < layout.n() {
        let curved = segs
            .get(layout.origin[k])
            .is_some_and(|s| s.kappa0() != 0.0 || s.kappa1() != 0.0);
        if layout.sigma[k] == 0.0 && layout.sigma[k + 1] == 0.0 && curved {
            let seg = segs[layout.origin[k]];
            let half = 0.5 * seg.length();
            let mid = seg.kappa(half);
            if mid == 0.0 {
                return None;
            }
            let feet: Vec<f64> = {
                let pts: Vec<Point> = assign[k].iter().map(|&i| smooth.input.points[i]).collect();
                deviation(&seg, &pts, smooth.chord_error).feet
            };
            let pose = (
                seg.point(half),
                x.pose[k].1 + seg.theta(half) - seg.theta0(),
            );
            split_at(&mut layout, &mut x, assign, k, (mid, pose), half, &feet);
            for m in [k, k + 1] {
                set_alpha_bounds(smooth.alpha, &mut layout, &mut x, m)?;
            }
            k += 2;
        } else {
            k += 1;
        }
    }
    Some((layout, x))
}

/// A transition spiral of the starting chain (see [`start_layout`]) is as long as a clothoid
/// from the arc's curvature κ to zero whose shift from the arc, κL²/24, is the tolerance:
/// L = √(24·tolerance/κ).
const TRANSITION_SHIFT: f64 = 24.0;

/// A segment gets a transition at its zero end only where the transition is shorter than this
/// share of it (a shorter segment is a spiral to zero already, or nearly).
const TRANSITION_SHARE: f64 = 0.5;

/// Grid of α values over a segment's bounds on which [`alpha_for_turning`] looks for the
/// turning closest to its target before bisecting: the turning is monotone in α between the
/// same end curvatures over the same length in every case tried, the grid only guards the
/// bracket.
const TURNING_GRID: usize = 12;

/// Bisection steps of [`alpha_for_turning`]: 2⁻²⁰ of a grid cell.
const TURNING_BISECTIONS: usize = 20;

/// The α within `bounds` whose segment k (its joints' curvatures and length from `x`) turns
/// closest to `target`: the starting chain then keeps the G1 chain's tangent at every joint.
fn alpha_for_turning(
    layout: &Layout,
    x: &Params,
    k: usize,
    target: f64,
    bounds: (f64, f64),
) -> f64 {
    let (ka, kb) = (layout.kappa(x, k), layout.kappa(x, k + 1));
    let length = x.v[k].exp();
    let turning = |alpha: f64| -> Option<f64> {
        let alpha = (ka != kb).then_some(alpha);
        let seg = LacSegment::new(Point::ZERO, 0.0, length, alpha, ka, kb).ok()?;
        Some(seg.theta1() - target)
    };
    let (lo, hi) = bounds;
    let grid: Vec<(f64, f64)> = (0..=TURNING_GRID)
        .filter_map(|i| {
            let a = lo + (hi - lo) * i as f64 / TURNING_GRID as f64;
            turning(a).map(|t| (a, t))
        })
        .collect();
    let Some(&best) = grid.iter().min_by(|p, q| p.1.abs().total_cmp(&q.1.abs())) else {
        return x.alpha[k];
    };
    let bracket = grid
        .windows(2)
        .find(|w| w[0].1 * w[1].1 <= 0.0)
        .map(|w| (w[0], w[1]));
    let Some((mut a, mut b)) = bracket else {
        return best.0;
    };
    for _ in 0..TURNING_BISECTIONS {
        let mid = 0.5 * (a.0 + b.0);
        let Some(t) = turning(mid) else { break };
        if t * a.1 <= 0.0 {
            b = (mid, t);
        } else {
            a = (mid, t);
        }
    }
    if a.1.abs() <= b.1.abs() { a.0 } else { b.0 }
}

/// Sets segment k's α bounds from the choice and its zero ends; `None` when no α is allowed.
fn set_alpha_bounds(
    choice: AlphaChoice,
    layout: &mut Layout,
    x: &mut Params,
    k: usize,
) -> Option<()> {
    let zero_a = layout.sigma[k] == 0.0;
    let zero_b = layout.sigma[k + 1] == 0.0;
    if zero_a && zero_b {
        layout.alpha_bounds[k] = None;
        return Some(());
    }
    let (lo, hi) = match choice {
        AlphaChoice::Range { min, max } => (min, max),
        AlphaChoice::Fixed(a) => (a, a),
    };
    let hi = if zero_a || zero_b {
        hi.min(ZERO_END_ALPHA)
    } else {
        hi
    };
    if lo > hi {
        return None;
    }
    x.alpha[k] = x.alpha[k].clamp(lo, hi);
    layout.alpha_bounds[k] = (lo < hi).then_some((lo, hi));
    Some(())
}

/// Splits segment k at arc length `at` (curvature `kappa` there) into two segments of the same
/// α, handing its samples to the halves by their feet.
fn split_at(
    layout: &mut Layout,
    x: &mut Params,
    assign: &mut Vec<Vec<usize>>,
    k: usize,
    (kappa, pose): (f64, (Point, f64)),
    at: f64,
    feet: &[f64],
) {
    x.pose.insert(k + 1, pose);
    let length = x.v[k].exp();
    let sign = if kappa > 0.0 { 1.0 } else { -1.0 };
    layout.sigma.insert(k + 1, sign);
    x.u.insert(k + 1, kappa.abs().ln());
    x.v[k] = at.ln();
    x.v.insert(k + 1, (length - at).ln());
    x.alpha.insert(k + 1, x.alpha[k]);
    layout.alpha_bounds.insert(k + 1, layout.alpha_bounds[k]);
    let max = layout.max_length[k];
    layout.max_length.insert(k + 1, max);
    let max = layout.max_turning[k];
    layout.max_turning.insert(k + 1, max);
    layout.kinds.insert(k + 1, JointKind::Subdivision);
    let origin = layout.origin[k];
    layout.origin.insert(k + 1, origin);
    // As many samples as have their feet before the cut go to the first half, taken in stroke
    // order: the halves keep contiguous runs of samples (on a jagged stroke a sample's foot
    // can lie before its predecessor's), so their ranges tile the piece.
    let before = feet.iter().filter(|&&s| s < at).count();
    let mut first = std::mem::take(&mut assign[k]);
    let second = first.split_off(before.min(first.len()));
    assign[k] = first;
    assign.insert(k + 1, second);
}

/// Cuts segment k of the solved chain at its middle. A line (no curvature at its middle to give
/// the new joint, its ends held at κ = 0 by its neighbours) that misses the tolerance must bend:
/// the new joint bends towards its farthest sample, with the curvature of the arc through the
/// line's ends that reaches it (8d/L², d that sample's distance), and both halves become spirals
/// leaving κ = 0 (α ≤ [`ZERO_END_ALPHA`]). `None` where neither can be done (a line whose
/// samples all lie on it, or an α choice without a negative α).
fn cut(
    layout: &mut Layout,
    x: &mut Params,
    assign: &mut Vec<Vec<usize>>,
    evaluation: &Evaluation,
    k: usize,
    choice: AlphaChoice,
) -> Option<()> {
    let seg = evaluation.segments.get(k)?;
    let half = 0.5 * seg.length();
    let kappa = seg.kappa(half);
    if !kappa.is_finite() {
        return None;
    }
    let pose = (seg.point(half), seg.theta(half));
    if kappa != 0.0 {
        split_at(
            layout,
            x,
            assign,
            k,
            (kappa, pose),
            half,
            &evaluation.feet[k],
        );
        return Some(());
    }
    let farthest = evaluation
        .residuals
        .get(k)?
        .iter()
        .copied()
        .max_by(|a, b| a.abs().total_cmp(&b.abs()))?;
    let length = seg.length();
    let bend = 8.0 * farthest / (length * length);
    if bend == 0.0 || !bend.is_finite() {
        return None;
    }
    let mut trial = (layout.clone(), x.clone(), assign.clone());
    split_at(
        &mut trial.0,
        &mut trial.1,
        &mut trial.2,
        k,
        (bend, pose),
        half,
        &evaluation.feet[k],
    );
    set_alpha_bounds(choice, &mut trial.0, &mut trial.1, k)?;
    set_alpha_bounds(choice, &mut trial.0, &mut trial.1, k + 1)?;
    (*layout, *x, *assign) = trial;
    Some(())
}

/// Distance from `q` to `segment` (one sample).
fn distance(solver: &Solver, segment: &LacSegment, q: Point) -> f64 {
    deviation(segment, &[q], solver.chord_error).max
}

/// Distance from `q`, a sample next to a joint, to `segment` on one side of it: its foot
/// polished by Newton's method from the joint (`at_end`: the segment's end, else its start),
/// where a sample handed across a joint has its foot on either segment; searched along the
/// whole segment where the polish does not settle.
fn distance_at_joint(solver: &Solver, segment: &LacSegment, q: Point, at_end: bool) -> f64 {
    let seed = if at_end { segment.length() } else { 0.0 };
    deviation_near(segment, &[q], &[seed]).map_or_else(|| distance(solver, segment, q), |d| d.max)
}

/// The distances from `points` to `segment`, each foot polished by Newton's method from its foot
/// on a nearby segment (`old`: those feet and that segment's length; scaled to this one's), the
/// whole segment searched where the polish does not settle. A polished foot is a local nearest
/// point: its distance is never below the global one.
fn deviation_from(
    segment: &LacSegment,
    points: &[Point],
    (feet, length): (&[f64], f64),
    chord_error: f64,
) -> crate::lac::Deviation {
    let ratio = segment.length() / length;
    let seeds: Vec<f64> = feet.iter().map(|s| s * ratio).collect();
    deviation_near(segment, points, &seeds)
        .unwrap_or_else(|| deviation(segment, points, chord_error))
}

/// Hands the samples at each joint to the nearer of its two segments (keeping every segment at
/// least one sample it had); true when any moved.
fn reassign(solver: &Solver, segments: &[LacSegment], assign: &mut [Vec<usize>]) -> bool {
    let mut changed = false;
    // The distances to the segment before joint k + 1 (from its end) and after it (its start).
    let before = |k: usize, q: Point| distance_at_joint(solver, &segments[k], q, true);
    let after = |k: usize, q: Point| distance_at_joint(solver, &segments[k + 1], q, false);
    for k in 0..segments.len().saturating_sub(1) {
        while assign[k].len() > 1 {
            let Some(&i) = assign[k].last() else { break };
            let q = solver.points[i];
            if after(k, q) < before(k, q) {
                assign[k].pop();
                assign[k + 1].insert(0, i);
                changed = true;
            } else {
                break;
            }
        }
        while assign[k + 1].len() > 1 {
            let i = assign[k + 1][0];
            let q = solver.points[i];
            if before(k, q) < after(k, q) {
                assign[k + 1].remove(0);
                assign[k].push(i);
                changed = true;
            } else {
                break;
            }
        }
    }
    changed
}

/// [`reassign`] at the chain of `e`, and `e` evaluated again where a sample moved (each segment
/// that kept its samples from its old feet); true when any moved.
fn reassigned(solver: &Solver, e: &mut Evaluation, assign: &mut [Vec<usize>]) -> bool {
    let before = assign.to_vec();
    if !reassign(solver, &e.segments, assign) {
        return false;
    }
    *e = solver.evaluate(e.segments.clone(), assign, Some((&*e, &before)));
    true
}

/// The normal equations JᵀJ and Jᵀr of the residuals of `e` with Jacobian `jr` (rows segment
/// after segment): segment k's rows are nonzero only in the columns `reaching[k]`, so each row
/// adds its few products instead of a dense product over every column.
fn normal_equations(
    solver: &Solver,
    jr: &DMatrix<f64>,
    e: &Evaluation,
    assign: &[Vec<usize>],
    reaching: &[Vec<usize>],
) -> (DMatrix<f64>, DVector<f64>) {
    let m = jr.ncols();
    let mut a = DMatrix::zeros(m, m);
    let mut g = DVector::zeros(m);
    let mut row = 0;
    for ((residuals, columns), list) in e.residuals.iter().zip(reaching).zip(assign) {
        for (&r, &sample) in residuals.iter().zip(list) {
            let w = solver.weight(sample);
            for &j in columns {
                let v = w * jr[(row, j)];
                if v == 0.0 {
                    continue;
                }
                g[j] += v * r;
                for &i in columns {
                    a[(i, j)] += jr[(row, i)] * v;
                }
            }
            row += 1;
        }
    }
    (a, g)
}

/// Where each row of the KKT system (the unknowns `vars`, then the `nc` constraints in the order
/// of [`Solver::constraints`] in the shooting form) goes so that the system is banded: along the
/// chain, a joint's curvature, its position and tangent equations (and C3's), the pose of the
/// segment it starts, that segment's length and α; the end point's equations last. A segment's
/// residuals and a joint's equations then involve rows of two neighbouring segments only, a
/// bandwidth of about fifteen whatever the chain's length.
fn band_order(layout: &Layout, vars: &[Var], nc: usize, c3_joints: &[usize]) -> Vec<usize> {
    let n = layout.n();
    let m = vars.len();
    let joint_rows = 3 * n.saturating_sub(1);
    let mut keys: Vec<(f64, usize)> = vars
        .iter()
        .enumerate()
        .map(|(i, &var)| {
            let key = match var {
                Var::Theta0 => -1.0,
                Var::StartShift => 0.0,
                Var::EndShift => n as f64,
                Var::Joint(j) => j as f64 - 0.2,
                Var::X(k) | Var::Y(k) | Var::Angle(k) => k as f64,
                Var::Length(k) | Var::Alpha(k) => k as f64 + 0.5,
            };
            (key, i)
        })
        .collect();
    keys.extend((0..nc).map(|r| (constraint_key(r, n, joint_rows, c3_joints), m + r)));
    positions(keys)
}

/// Each index's place when `keys` (a key per index, `(key, index)`) are sorted by key, ties in
/// index order.
fn positions(mut keys: Vec<(f64, usize)>) -> Vec<usize> {
    keys.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)));
    let mut position = vec![0; keys.len()];
    for (p, &(_, i)) in keys.iter().enumerate() {
        position[i] = p;
    }
    position
}

/// The constraints' Jacobian in the forward form at its chain `segments`: a change of one
/// unknown reshapes at most two segments (differenced) and moves every later segment rigidly
/// with the end pose of the last reshaped one, so the chain's end moves by
/// δE + δθ·(Pₑ − E)^⊥ (E, θ that end pose); a C3 gap changes only where a reshaped segment meets
/// it. `None` where a differenced segment cannot be built.
fn forward_constraint_jacobian(
    solver: &Solver,
    layout: &Layout,
    x: &Params,
    segments: &[LacSegment],
    vars: &[Var],
    c3_joints: &[usize],
) -> Option<DMatrix<f64>> {
    let n = layout.n();
    let nc = 2 + if solver.c3 { c3_joints.len() } else { 0 };
    let mut jc = DMatrix::zeros(nc, vars.len());
    let end = segments[n - 1].end();
    for (col, &var) in vars.iter().enumerate() {
        if var == Var::Theta0 {
            let d = perp(end - x.pose[0].0) / solver.scale;
            jc[(0, col)] = d.x;
            jc[(1, col)] = d.y;
            continue;
        }
        if var == Var::EndShift {
            let d = x.anchors[1].1 / -solver.scale;
            jc[(0, col)] = d.x;
            jc[(1, col)] = d.y;
            continue;
        }
        let (k0, k1) = layout.reach(var);
        let mut xp = x.clone();
        set(layout, &mut xp, var, get(layout, x, var) + DIFFERENCE_STEP);
        let new = layout.rebuild(&xp, segments, k0, k1).ok()?;
        let last = &new[k1 - k0];
        let old_end = segments[k1].end();
        let d_end = (last.end() - old_end) / DIFFERENCE_STEP;
        let d_theta = (last.theta1() - segments[k1].theta1()) / DIFFERENCE_STEP;
        let d = (d_end + perp(end - old_end) * d_theta) / solver.scale;
        jc[(0, col)] = d.x;
        jc[(1, col)] = d.y;
        if solver.c3 {
            let pick = |k: usize| {
                if (k0..=k1).contains(&k) {
                    &new[k - k0]
                } else {
                    &segments[k]
                }
            };
            for (row, &j) in c3_joints.iter().enumerate() {
                if (k0..=k1).contains(&(j - 1)) || (k0..=k1).contains(&j) {
                    let before = c3_gap(&segments[j - 1], &segments[j]);
                    let after = c3_gap(pick(j - 1), pick(j));
                    jc[(2 + row, col)] = (after - before) / DIFFERENCE_STEP;
                }
            }
        }
    }
    Some(jc)
}

/// The Jacobians of the residuals and of the constraints in the shooting form: a change of
/// one unknown rebuilds one segment (two for a joint's curvature) from its own start pose; the
/// residual columns are differenced at the samples' feet, the constraint columns by
/// differencing [`Solver::constraints`] with those segments replaced.
fn shooting_jacobian(
    solver: &Solver,
    layout: &Layout,
    x: &Params,
    e: &Evaluation,
    vars: &[Var],
    c3_joints: &[usize],
) -> Option<(DMatrix<f64>, DMatrix<f64>)> {
    let mut offsets = Vec::with_capacity(e.residuals.len());
    let mut rows = 0;
    for r in &e.residuals {
        offsets.push(rows);
        rows += r.len();
    }
    let c0 = solver.constraints(Form::Shooting, &e.segments, x, c3_joints);
    let mut jr = DMatrix::zeros(rows, vars.len());
    let mut jc = DMatrix::zeros(c0.len(), vars.len());
    let mut segments = e.segments.clone();
    // Each foot evaluated as the differenced points will be: the stored foot points come from
    // the distance search's own integration, and a difference against them carries the two
    // integrations' disagreement divided by the step (seen: a length's column 2.3 where the
    // scaling identity ∂/∂v = (P − Pₖ) + Σ ∂/∂u, exact for a segment, gave 4.7 from the
    // joints' columns, each off by the same offset).
    let base: Vec<Vec<Point>> = e
        .segments
        .iter()
        .zip(&e.feet)
        .map(|(seg, feet)| crate::lac::deviation::points_at(seg, feet))
        .collect();
    // Without C3 rows, a length's column follows from the joints' (below): no construction.
    let scaled = |var: Var| matches!(var, Var::Length(_)) && !solver.c3;
    for (col, &var) in vars.iter().enumerate() {
        if scaled(var) {
            continue;
        }
        let (k0, k1) = layout.shooting_reach(var);
        let mut xp = x.clone();
        set(layout, &mut xp, var, get(layout, x, var) + DIFFERENCE_STEP);
        for k in k0..=k1 {
            // A pose moves its segment rigidly, each point by shift + turn·(P − Pₖ)^⊥ per unit
            // of the unknown: no construction, no integration, and exact.
            let rigid = match var {
                Var::X(j) if j == k => Some((Vec2::new(1.0, 0.0), 0.0)),
                Var::Y(j) if j == k => Some((Vec2::new(0.0, 1.0), 0.0)),
                Var::Angle(j) if j == k => Some((Vec2::ZERO, 1.0)),
                Var::StartShift => Some((x.anchors[0].1, 0.0)),
                _ => None,
            };
            let rows = e.foot_points[k].iter().zip(&base[k]).enumerate();
            let seg = if let Some((shift, turn)) = rigid {
                let start = e.segments[k].start();
                for (m, ((_, nrm), f)) in rows {
                    jr[(offsets[k] + m, col)] = -nrm.dot(shift + perp(*f - start) * turn);
                }
                e.segments[k].placed(xp.pose[k].0, xp.pose[k].1)
            } else {
                let seg = layout.segment(&xp, k, xp.pose[k].0, xp.pose[k].1).ok()?;
                let ratio = seg.length() / e.segments[k].length();
                let feet: Vec<f64> = e.feet[k].iter().map(|s| s * ratio).collect();
                let moved = crate::lac::deviation::points_at(&seg, &feet);
                for ((m, ((_, nrm), f)), p) in rows.zip(moved) {
                    jr[(offsets[k] + m, col)] = -nrm.dot((p - *f) / DIFFERENCE_STEP);
                }
                seg
            };
            segments[k] = seg;
        }
        let c1 = solver.constraints(Form::Shooting, &segments, &xp, c3_joints);
        jc.set_column(col, &((c1 - &c0) / DIFFERENCE_STEP));
        segments[k0..=k1].copy_from_slice(&e.segments[k0..=k1]);
    }
    // Lengthening segment k by dv while both its end curvatures shrink by e^{−dv} scales it by
    // e^{dv} about its start (a similarity keeps α): a point at a fixed fraction of the length
    // moves by (P − Pₖ)·dv, the turning not at all. So ∂/∂v = (P − Pₖ) + Σ ∂/∂u over its
    // non-zero end joints, whose columns hold segment k's own rows (its samples, its end's
    // equations) apart from the other segment's.
    let n = layout.n();
    for (col, &var) in vars.iter().enumerate() {
        let Var::Length(k) = var else { continue };
        if !scaled(var) {
            continue;
        }
        let joints: Vec<usize> = [k, k + 1]
            .into_iter()
            .filter_map(|j| vars.iter().position(|&v| v == Var::Joint(j)))
            .collect();
        let start = e.segments[k].start();
        for (m, ((_, nrm), f)) in e.foot_points[k].iter().zip(&base[k]).enumerate() {
            let row = offsets[k] + m;
            jr[(row, col)] =
                -nrm.dot(*f - start) + joints.iter().map(|&j| jr[(row, j)]).sum::<f64>();
        }
        let (rx, ry, angle) = end_rows(n, k);
        let lever = (e.segments[k].end() - start) / solver.scale;
        for (row, own) in [(rx, lever.x), (ry, lever.y)] {
            jc[(row, col)] = own + joints.iter().map(|&j| jc[(row, j)]).sum::<f64>();
        }
        if let Some(row) = angle {
            jc[(row, col)] = joints.iter().map(|&j| jc[(row, j)]).sum::<f64>();
        }
    }
    Some((jr, jc))
}

/// The rows of segment k's end in the shooting form's constraints ([`Solver::constraints`]):
/// its position equations' two rows and, but for the last segment (whose end is the target
/// point), its tangent equation's row.
fn end_rows(n: usize, k: usize) -> (usize, usize, Option<usize>) {
    if k + 1 == n {
        (0, 1, None)
    } else {
        (2 + 3 * k, 3 + 3 * k, Some(4 + 3 * k))
    }
}

/// The constraints' Jacobian alone at the chain `segments` of `x`.
fn constraint_jacobian(
    form: Form,
    solver: &Solver,
    layout: &Layout,
    x: &Params,
    segments: &[LacSegment],
    vars: &[Var],
    c3_joints: &[usize],
) -> Option<DMatrix<f64>> {
    match form {
        Form::Shooting => {
            let n = segments.len();
            let e = Evaluation {
                segments: segments.to_vec(),
                residuals: vec![Vec::new(); n],
                feet: vec![Vec::new(); n],
                foot_points: vec![Vec::new(); n],
                cost: 0.0,
            };
            shooting_jacobian(solver, layout, x, &e, vars, c3_joints).map(|(_, jc)| jc)
        }
        Form::Forward => forward_constraint_jacobian(solver, layout, x, segments, vars, c3_joints),
    }
}

/// `x` moved by `delta` over `vars`.
fn moved(layout: &Layout, x: &Params, vars: &[Var], delta: &DVector<f64>) -> Params {
    let mut out = x.clone();
    for (i, &var) in vars.iter().enumerate() {
        set(layout, &mut out, var, get(layout, x, var) + delta[i]);
    }
    out
}

/// Projects `x` onto the constraints of `form` by least-norm Newton steps; returns the chain
/// there, or `None` when the steps do not meet the constraints.
///
/// With `chord`, the constraint Jacobian of the point a trial stepped from is used throughout (a
/// chord method: a damped step away, it converges in two or three steps without differencing
/// the chain again). Where it does not converge, the fit projects the trial again without
/// `chord` (fresh Jacobians, a construction per unknown each) before refusing it: on the nine
/// recorded fixture files in g2 that gives 803 segments against 809 in the same time (with α in
/// the log scale next to inflections, see `Layout::log_alpha`; before it, fresh projections
/// took a third longer for more segments, 915 against 896, and trials were refused at once).
fn project(
    form: Form,
    solver: &Solver,
    layout: &Layout,
    x: &mut Params,
    c3_joints: &[usize],
    chord: Option<&DMatrix<f64>>,
) -> Option<Vec<LacSegment>> {
    let vars = layout.vars_of(form);
    let n = layout.n();
    let rows = constraint_order(form, n, solver.c3, c3_joints);
    // A chain in the shooting form (the start, every trial) need meet the joints only well
    // within the tolerance; the fit's answer is laid out forward exactly at the end (see
    // [`TRIAL_GAP_TOLERANCES`]).
    let slack = match form {
        Form::Shooting => solver.trial_slack,
        Form::Forward => 1.0,
    };
    let newton = |x: &mut Params,
                  fixed: Option<&DMatrix<f64>>,
                  steps: usize|
     -> Option<Vec<LacSegment>> {
        let chord = match fixed {
            Some(jc) => Some(LeastNorm::new(jc, &rows)?),
            None => None,
        };
        let mut previous: Option<f64> = None;
        // In the fresh mode, the last Jacobian's factor and whether it is still contracting.
        let mut kept: Option<LeastNorm> = None;
        for step in 0..=steps {
            layout.clamp(x, solver.log_kappa);
            let segments = layout.build_form(form, x).ok()?;
            if layout.winds(&segments) {
                return None;
            }
            let c = solver.constraints(form, &segments, x, c3_joints);
            if solver.constraints_met(form, n, &c, slack) {
                return Some(segments);
            }
            // The chord steps converge linearly: at the rate seen so far, would the steps
            // left reach the constraints? If not, refuse the trial now rather than after
            // every step.
            let size = c.amax();
            if fixed.is_some()
                && let Some(before) = previous
            {
                let rate = size / before;
                if !(rate < 1.0 && size * rate.powf((steps - step) as f64) <= slack * END_TOLERANCE)
                {
                    return None;
                }
            }
            // A fresh Jacobian is kept while its steps contract fast (Shamanskii's variant of
            // Newton): each new one costs a construction per unknown.
            if fixed.is_none()
                && let Some(before) = previous
                && !(size <= FRESH_REUSE_RATE * before)
            {
                kept = None;
            }
            previous = Some(size);
            let step = match (&chord, &kept) {
                (Some(chord), _) => chord.step(&c)?,
                (None, Some(factor)) => factor.step(&c)?,
                (None, _) => {
                    let mut jc =
                        constraint_jacobian(form, solver, layout, x, &segments, &vars, c3_joints)?;
                    // Unknowns on a bound stay there: a step the clamp would cut short
                    // turns Newton's quadratic convergence into a crawl.
                    for (i, &var) in vars.iter().enumerate() {
                        if layout.pushed_beyond(var, x, 1.0, solver.log_kappa)
                            || layout.pushed_beyond(var, x, -1.0, solver.log_kappa)
                        {
                            jc.column_mut(i).fill(0.0);
                        }
                    }
                    let factor = LeastNorm::new(&jc, &rows)?;
                    let step = factor.step(&c)?;
                    kept = Some(factor);
                    step
                }
            };
            *x = moved(layout, x, &vars, &step);
        }
        None
    };
    match chord {
        Some(_) => newton(x, chord, TRIAL_PROJECTION_STEPS),
        None => newton(x, None, PROJECTION_STEPS),
    }
}

/// Where each constraint row of `form` goes in an order along the chain (see [`band_order`]).
fn constraint_order(form: Form, n: usize, c3: bool, c3_joints: &[usize]) -> Vec<usize> {
    let joint_rows = match form {
        Form::Shooting => 3 * n.saturating_sub(1),
        Form::Forward => 0,
    };
    let nc = 2 + joint_rows + if c3 { c3_joints.len() } else { 0 };
    positions(
        (0..nc)
            .map(|r| (constraint_key(r, n, joint_rows, c3_joints), r))
            .collect(),
    )
}

/// A constraint row's place along the chain: the end point's after every joint, a joint's
/// equations (position, tangent, C3) at the joint.
fn constraint_key(r: usize, n: usize, joint_rows: usize, c3_joints: &[usize]) -> f64 {
    if r < 2 {
        n as f64
    } else if r < 2 + joint_rows {
        (1 + (r - 2) / 3) as f64 - 0.1
    } else {
        c3_joints
            .get(r - 2 - joint_rows)
            .map_or(n as f64, |&j| j as f64 - 0.1)
    }
}

/// Least-norm steps −Jᵀ(JJᵀ)⁻¹c onto linearised constraints J·δ = −c, J factored once. Ordered
/// along the chain ([`constraint_order`]), the Gram matrix JJᵀ is a band (two joints' equations
/// share unknowns only where they are neighbours): it is assembled from each column's few
/// nonzero rows and factored by [`Band`]'s Cholesky, where a dense product and factor cost
/// O(rows²·unknowns).
struct LeastNorm {
    /// Per unknown: its nonzero rows (in the band order) and entries.
    columns: Vec<Vec<(usize, f64)>>,
    /// Each constraint row's place in the band order.
    rows: Vec<usize>,
    gram: BandCholesky,
}

impl LeastNorm {
    /// `None` where JJᵀ is singular (a constraint no free unknown moves) or the sizes differ.
    fn new(jc: &DMatrix<f64>, rows: &[usize]) -> Option<Self> {
        let (nc, m) = jc.shape();
        if rows.len() != nc {
            return None;
        }
        let columns: Vec<Vec<(usize, f64)>> = (0..m)
            .map(|j| {
                (0..nc)
                    .filter(|&r| jc[(r, j)] != 0.0)
                    .map(|r| (rows[r], jc[(r, j)]))
                    .collect()
            })
            .collect();
        let width = columns
            .iter()
            .map(|col| {
                let lo = col.iter().map(|&(p, _)| p).min().unwrap_or(0);
                let hi = col.iter().map(|&(p, _)| p).max().unwrap_or(0);
                hi - lo
            })
            .max()
            .unwrap_or(0);
        let mut gram = Band::zeros(nc, width);
        for col in &columns {
            for (a, &(p, u)) in col.iter().enumerate() {
                for &(q, v) in &col[..=a] {
                    gram.add(p, q, u * v);
                }
            }
        }
        Some(LeastNorm {
            columns,
            rows: rows.to_vec(),
            gram: gram.factor()?,
        })
    }

    /// The step for the constraint values `c`; `None` where its length differs.
    fn step(&self, c: &DVector<f64>) -> Option<DVector<f64>> {
        if c.len() != self.rows.len() {
            return None;
        }
        let mut rhs = vec![0.0; c.len()];
        for (r, &p) in self.rows.iter().enumerate() {
            rhs[p] = c[r];
        }
        let y = self.gram.solve(&rhs);
        Some(DVector::from_iterator(
            self.columns.len(),
            self.columns
                .iter()
                .map(|col| -col.iter().map(|&(p, v)| v * y[p]).sum::<f64>()),
        ))
    }
}

/// The Levenberg–Marquardt fit in the shooting form from `x` and its evaluation `e`, moving
/// both (and the samples' assignment): each step solves the damped Gauss–Newton system with the
/// linearised constraints (KKT, Marquardt's scaling) and is projected back onto them; `None`
/// where no chain could be built.
fn levenberg_marquardt(
    solver: &Solver,
    layout: &Layout,
    x: &mut Params,
    assign: &mut [Vec<usize>],
    e: &mut Evaluation,
) -> Option<()> {
    let vars = layout.shooting_vars();
    let c3_joints = layout.c3_joints();
    let m = vars.len();
    // The unknowns that reach each segment: its residuals' only nonzero columns.
    let reaching: Vec<Vec<usize>> = (0..layout.n())
        .map(|k| {
            (0..m)
                .filter(|&i| {
                    let (k0, k1) = layout.shooting_reach(vars[i]);
                    (k0..=k1).contains(&k)
                })
                .collect()
        })
        .collect();
    // The KKT system's band order: the layout, and so the rows, stay fixed through the solve.
    let nc = constraint_order(Form::Shooting, layout.n(), solver.c3, &c3_joints).len();
    let position = band_order(layout, &vars, nc, &c3_joints);
    let mut lambda = INITIAL_DAMPING;
    let mut growth = DAMPING_GROWTH;
    for iteration in 0..MAX_ITERATIONS {
        let (jr, jc) = shooting_jacobian(solver, layout, x, e, &vars, &c3_joints)?;
        let c = solver.constraints(Form::Shooting, &e.segments, x, &c3_joints);
        if c.len() != nc {
            return None;
        }
        let (mut a, mut g) = normal_equations(solver, &jr, e, assign, &reaching);
        let floor = DIAGONAL_FLOOR * a.diagonal().max().max(f64::MIN_POSITIVE);
        // An unknown on its bound that the descent direction pushes beyond it is held there
        // (an active set): clamped after the step instead, it bends every step the model
        // predicts, and the damping rises until the steps are too short to matter. So is one
        // that the step itself pushes beyond (the joint equations can ask it of an unknown the
        // gradient alone would not move there: a stroke's end curvature on the cap, clamped
        // back from each trial, left the model eight times too hopeful, ρ ≈ 0.1, for ten
        // steps); the step is then solved again.
        let mut jc = jc;
        let mut held = vec![false; m];
        let hold = |i: usize,
                    held: &mut [bool],
                    a: &mut DMatrix<f64>,
                    g: &mut DVector<f64>,
                    jc: &mut DMatrix<f64>| {
            held[i] = true;
            a.row_mut(i).fill(0.0);
            a.column_mut(i).fill(0.0);
            a[(i, i)] = floor.max(1.0);
            g[i] = 0.0;
            jc.column_mut(i).fill(0.0);
        };
        for (i, &var) in vars.iter().enumerate() {
            if layout.pushed_beyond(var, x, -g[i], solver.log_kappa) {
                hold(i, &mut held, &mut a, &mut g, &mut jc);
            }
        }
        let mut accepted = None;
        'assemble: for _ in 0..=m {
            // The KKT system [A + λD, Jcᵀ; Jc, 0] in the band order, as its nonzero entries.
            let mut entries = Vec::new();
            for j in 0..m {
                for i in 0..m {
                    if a[(i, j)] != 0.0 || i == j {
                        entries.push((position[i], position[j], a[(i, j)]));
                    }
                }
                for r in 0..nc {
                    if jc[(r, j)] != 0.0 {
                        entries.push((position[m + r], position[j], jc[(r, j)]));
                        entries.push((position[j], position[m + r], jc[(r, j)]));
                    }
                }
            }
            let (lower, upper) = entries.iter().fold((0, 0), |(l, u), &(i, j, _)| {
                (l.max(i.saturating_sub(j)), u.max(j.saturating_sub(i)))
            });
            let mut rhs = vec![0.0; m + nc];
            for i in 0..m {
                rhs[position[i]] = -g[i];
            }
            for r in 0..nc {
                rhs[position[m + r]] = -c[r];
            }
            while lambda <= MAX_DAMPING {
                let mut kkt = BandMatrix::zeros(m + nc, lower, upper);
                for &(i, j, v) in &entries {
                    kkt.add(i, j, v);
                }
                for i in 0..m {
                    kkt.add(position[i], position[i], lambda * a[(i, i)].max(floor));
                }
                let Some(solution) = kkt.solve(&rhs) else {
                    lambda *= growth;
                    growth *= 2.0;
                    continue;
                };
                let delta = DVector::from_iterator(m, (0..m).map(|i| solution[position[i]]));
                let beyond: Vec<usize> = (0..m)
                    .filter(|&i| {
                        !held[i] && layout.pushed_beyond(vars[i], x, delta[i], solver.log_kappa)
                    })
                    .collect();
                if !beyond.is_empty() {
                    for i in beyond {
                        hold(i, &mut held, &mut a, &mut g, &mut jc);
                    }
                    continue 'assemble;
                }
                // The decrease of Σr² the Gauss–Newton model predicts for this step. Below the
                // stopping fraction the step could not continue the solve even if it were
                // accepted: converged (or damped to a standstill), without spending a
                // projection. A round of [`minimax`] takes its first step whatever it gains:
                // the reweighting moves the weighted cost's minimum by little (often under the
                // fraction: the round then ended where it began and the next reweighted the
                // same chain), but towards the largest distance, which is what the round is for.
                let predicted = -(2.0 * g.dot(&delta) + delta.dot(&(&a * &delta)));
                let stop_below = if solver.minimax && iteration == 0 {
                    0.0
                } else {
                    RELATIVE_DECREASE * e.cost
                };
                if !(predicted > stop_below) {
                    break;
                }
                let mut trial = moved(layout, x, &vars, &delta);
                let projected = project(
                    Form::Shooting,
                    solver,
                    layout,
                    &mut trial,
                    &c3_joints,
                    Some(&jc),
                )
                // Chord steps that do not reach the constraints: once more with fresh
                // Jacobians before the step is refused (see [`project`]).
                .or_else(|| {
                    trial = moved(layout, x, &vars, &delta);
                    project(Form::Shooting, solver, layout, &mut trial, &c3_joints, None)
                });
                let Some(segments) = projected else {
                    lambda *= growth;
                    growth *= 2.0;
                    continue;
                };
                let t = solver.evaluate(segments, assign, Some((e, assign)));
                if t.cost < e.cost {
                    let rho = ((e.cost - t.cost) / predicted).min(1.0);
                    lambda *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
                    growth = DAMPING_GROWTH;
                    accepted = Some((trial, t));
                    break;
                }
                lambda *= growth;
                growth *= 2.0;
            }
            break;
        }
        let Some((trial, t)) = accepted else {
            break;
        };
        let decrease = e.cost - t.cost;
        let before = e.cost;
        *x = trial;
        *e = t;
        let within = largest_distance(e) <= solver.tolerance;
        if solver.minimax && within {
            break;
        }
        if !reassigned(solver, e, assign)
            && (decrease <= RELATIVE_DECREASE * before
                || (decrease <= WITHIN_DECREASE * before && within))
        {
            break;
        }
    }
    Some(())
}

/// The constrained fit from `x` (shooting form, see [`Form`]), then the answer laid out forward
/// so that the joints meet exactly; the forward chain's evaluation, or `None` where no chain
/// meeting the constraints could be built. `x` keeps the shooting solution (the next cut starts
/// from it). `near`: an evaluation of a chain close to `x`'s with its assignment (the last
/// round's, in [`minimax`]), whose feet seed the first evaluation's where a segment holds the
/// same samples.
fn solve(
    solver: &Solver,
    layout: &Layout,
    x: &mut Params,
    assign: &mut [Vec<usize>],
    near: Option<(&Evaluation, &[Vec<usize>])>,
) -> Option<Evaluation> {
    let c3_joints = layout.c3_joints();
    let segments = match project(Form::Shooting, solver, layout, x, &c3_joints, None) {
        Some(segments) => segments,
        None => {
            // The G1 chain's joints are too far from a smooth chain's for the joint equations
            // (a tangent gap of 1.5 rad where no α ≤ 0 turns a segment ending at an inflection
            // as far as the G1 one did): the chain laid out forward from its start meets them by
            // construction and leaves only its end point to move. Its poses start the fit.
            let (mut forward, segments) = laid_forward(solver, layout, x, &c3_joints)?;
            forward.pose = segments.iter().map(|s| (s.start(), s.theta0())).collect();
            *x = forward;
            segments
        }
    };
    let mut e = solver.evaluate(segments, assign, near);
    reassigned(solver, &mut e, assign);
    levenberg_marquardt(solver, layout, x, assign, &mut e)?;
    let (_, segments) = laid_forward(solver, layout, x, &c3_joints)?;
    // The forward chain is the solution's to the joints' gaps (a tenth of the tolerance): each
    // foot is polished from the solution's own, not searched for again along the whole
    // segment. A polished foot is a local nearest point, its distance never below the global
    // one, so a chain found within the tolerance is within it.
    Some(solver.evaluate(segments, assign, Some((&e, assign))))
}

/// The chain of `x` laid out forward from its first pose, its end point brought onto the
/// target by [`project`]: the unknowns there and the chain; `None` where the projection fails.
fn laid_forward(
    solver: &Solver,
    layout: &Layout,
    x: &Params,
    c3_joints: &[usize],
) -> Option<(Params, Vec<LacSegment>)> {
    let mut forward = x.clone();
    forward.theta0 = forward.pose[0].1;
    // A free end is where the chain laid out forward ends: nothing to meet but C3's equations.
    if layout.free_end() {
        let laid = layout.build_form(Form::Forward, &forward).ok()?;
        forward.end = laid.last()?.end();
        if !solver.c3 {
            return Some((forward, laid));
        }
    }
    let segments = project(Form::Forward, solver, layout, &mut forward, c3_joints, None)?;
    Some((forward, segments))
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
            let params = assign[k].iter().map(|&i| input.params[i]).fold(
                None,
                |acc: Option<(f64, f64)>, u| {
                    Some(acc.map_or((u, u), |(lo, hi)| (lo.min(u), hi.max(u))))
                },
            );
            ChainSegment {
                segment: e.segments[k],
                samples: ranges[k],
                max_deviation: max,
                rms_deviation: rms,
                search: smooth.chain.segments[layout.origin[k]].search.clone(),
                alpha_bound: super::AlphaBound::of(e.segments[k].alpha(), smooth.alpha),
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
    let step = super::ALPHA_DIFFERENCE_STEP;
    let (minus, plus) = (signed(alpha - step), signed(alpha + step));
    super::alpha_uncertainty(residuals, minus.as_deref(), plus.as_deref())
}
