//! Curvature-continuous chains (`Continuity::G2`, `C3`) against planted G2 chains.
//!
//! A planted chain of log-aesthetic segments joined with equal curvature is sampled as a pen
//! would draw it (light noise) or as a mouse would (whole-pixel coordinates); the smooth fit must
//! give a chain whose joints are curvature-continuous to rounding (1e-9 relative), every sample
//! within the tolerance, and a curve close to the planted one itself (not only to its samples).

mod common;

use common::planted::{distances_to, jittered, planted, samples};
use kansei::chain::{Chain, Continuity};
use kansei::geom::{Point, Vec2};
use kansei::lac::LacSegment;
use kansei::pipeline::{PipelineOptions, StrokeOutcome, fit_stroke, fit_with_noise};
use kansei::stroke::Stroke;

/// Relative curvature jump accepted at a G2 joint: the joint's curvature is one parameter
/// shared by both segments, so only the evaluation's rounding separates the two sides.
const G2_JUMP: f64 = 1e-9;

fn fit(stroke: &Stroke, tolerance: f64, continuity: Continuity) -> Vec<Chain> {
    let mut options = PipelineOptions::default();
    options.chain.continuity = continuity;
    fit_stroke(stroke, 0, tolerance, &options)
        .expect("fit")
        .into_iter()
        .map(|f| f.chain.expect("a chain"))
        .collect()
}

/// Largest relative curvature jump at the chain's interior joints.
fn largest_jump(chain: &Chain) -> f64 {
    chain
        .segments
        .windows(2)
        .map(|w| {
            let (a, b) = (w[0].segment.kappa1(), w[1].segment.kappa0());
            let scale = a.abs().max(b.abs());
            if scale == 0.0 {
                0.0
            } else {
                (a - b).abs() / scale
            }
        })
        .fold(0.0, f64::max)
}

/// The fitted chain's points against the planted chain: the largest distance.
fn distance_from_planted(chain: &Chain, truth: &[LacSegment]) -> f64 {
    let points = chain
        .segments
        .iter()
        .flat_map(|s| s.segment.samples(1.0).map(|p| p.point).collect::<Vec<_>>());
    distances_to(truth, points).into_iter().fold(0.0, f64::max)
}

fn check(name: &str, truth: &[LacSegment], stroke: &Stroke, tolerance: f64, near: f64) {
    let chains = fit(stroke, tolerance, Continuity::G2);
    assert_eq!(chains.len(), 1, "{name}: one piece");
    let chain = &chains[0];
    assert_eq!(
        chain.continuity,
        Continuity::G2,
        "{name}: the smooth fit held"
    );
    assert!(
        chain.within_tolerance && chain.max_deviation <= tolerance,
        "{name}: deviation {}",
        chain.max_deviation
    );
    let jump = largest_jump(chain);
    assert!(
        jump <= G2_JUMP,
        "{name}: curvature jump {jump} with {} segments",
        chain.segments.len()
    );
    // Position and tangent are continuous too (the chain is laid out forward).
    for w in chain.segments.windows(2) {
        let gap = w[0].segment.end().distance(w[1].segment.start());
        assert!(
            gap <= 1e-9 * (1.0 + w[1].segment.start().to_vec2().hypot()),
            "{name}: gap {gap}"
        );
        let turn = (w[0].segment.theta1() - w[1].segment.theta0()).sin().abs();
        assert!(turn <= 1e-9, "{name}: tangent break {turn}");
    }
    let off = distance_from_planted(chain, truth);
    assert!(off <= near, "{name}: {off} from the planted chain");
}

#[test]
fn a_planted_c_with_light_noise_comes_back_curvature_continuous() {
    let truth = planted(
        0.004,
        &[(150.0, Some(0.5), 0.02), (120.0, Some(-1.0), 0.006)],
    );
    let stroke = jittered(&truth, 300, 0.05, 3);
    check("C, noise 0.05", &truth, &stroke, 0.5, 0.5);
}

#[test]
fn a_planted_s_through_an_inflection_comes_back_curvature_continuous() {
    let truth = planted(
        0.015,
        &[(120.0, Some(-1.0), 0.0), (120.0, Some(-1.0), -0.015)],
    );
    let stroke = jittered(&truth, 300, 0.05, 7);
    check("S, noise 0.05", &truth, &stroke, 0.5, 0.5);
}

#[test]
fn a_planted_c_on_a_pixel_grid_comes_back_curvature_continuous() {
    let truth = planted(
        0.004,
        &[(150.0, Some(0.5), 0.02), (120.0, Some(-1.0), 0.006)],
    );
    let stroke = samples(&truth, 270, |p| {
        Point::new((p.x + 100.3).round(), (p.y + 50.6).round())
    });
    let shifted: Vec<LacSegment> = truth
        .iter()
        .map(|s| {
            LacSegment::new(
                s.start() + Vec2::new(100.3, 50.6),
                s.theta0(),
                s.length(),
                s.alpha(),
                s.kappa0(),
                s.kappa1(),
            )
            .expect("shifted")
        })
        .collect();
    // The grid moves samples by up to 0.71 px: at a 1 px tolerance the chain stays within it
    // of its samples, so within 1.71 px of the planted curve.
    check("C, whole pixels", &shifted, &stroke, 1.0, 1.71);
}

/// The stroke's own ends move across their tangents only: a smooth chain whose first sample sits
/// half a pixel off the drawn curve (a whole-pixel grid) may shift its start to fit it, but never
/// slides beyond the first or last sample along the curve.
#[test]
fn a_smooth_chain_starts_and_ends_at_its_first_and_last_samples() {
    let truth = planted(
        0.015,
        &[(120.0, Some(-1.0), 0.0), (120.0, Some(-1.0), -0.015)],
    );
    for (n, offset) in [(100, (100.3, 50.6)), (300, (7.8, 3.2)), (900, (40.5, 40.5))] {
        let stroke = samples(&truth, n, |p| {
            Point::new((p.x + offset.0).round(), (p.y + offset.1).round())
        });
        let tolerance = 0.75;
        let chains = fit(&stroke, tolerance, Continuity::G2);
        assert_eq!(chains.len(), 1);
        let chain = &chains[0];
        assert_eq!(chain.continuity, Continuity::G2, "{n}");
        let first = stroke.samples[0].point();
        let last = stroke.samples[stroke.samples.len() - 1].point();
        let (start, end) = (
            chain.segments[0].segment.start(),
            chain.segments[chain.segments.len() - 1].segment.end(),
        );
        // The end points lie within the tolerance of the end samples (the samples' own distance
        // to the chain is within it, and an end does not move along the curve).
        assert!(
            start.distance(first) <= tolerance,
            "{n}: start {start:?} first {first:?}"
        );
        assert!(
            end.distance(last) <= tolerance,
            "{n}: end {end:?} last {last:?}"
        );
        assert!(chain.within_tolerance, "{n}");
    }
}

#[test]
fn g1_is_the_seed_papers_chain_and_g2_never_loses_the_tolerance() {
    // The same stroke in both modes: G1 is untouched by the smooth fit; G2 holds the tolerance.
    let truth = planted(
        0.004,
        &[(150.0, Some(0.5), 0.02), (120.0, Some(-1.0), 0.006)],
    );
    let stroke = jittered(&truth, 300, 0.2, 9);
    for continuity in [Continuity::G1, Continuity::G2, Continuity::C3] {
        for chain in fit(&stroke, 0.5, continuity) {
            if continuity == Continuity::G1 {
                assert_eq!(chain.continuity, Continuity::G1);
            }
            assert!(
                chain.within_tolerance,
                "{continuity}: deviation {}",
                chain.max_deviation
            );
        }
    }
}

#[test]
fn continuity_names_round_trip() {
    for name in Continuity::NAMES {
        let c: Continuity = name.parse().expect("a name");
        assert_eq!(c.name(), name);
    }
    assert!("g3".parse::<Continuity>().is_err());
}

#[test]
fn a_planted_compound_rhythm_comes_back_with_continuous_dkappa_ds() {
    // Seed 002's compound rhythm: α = −1 with κ 0.004 → 0.012 over 150, then α = 1 from the same
    // κ and the same dκ/ds over 100 (its end curvature solved from that slope).
    let first = LacSegment::new(Point::ZERO, 0.0, 150.0, Some(-1.0), 0.004, 0.012).expect("first");
    let slope = first.dkappa_ds(first.length());
    let (alpha, length, kappa) = (1.0f64, 100.0, 0.012f64);
    // ρ^α linear in s with c = −α·(dκ/ds)/κ^(1+α) (κ > 0).
    let c = -alpha * slope / kappa.powf(1.0 + alpha);
    let rho_end = ((1.0 / kappa).powf(alpha) + c * length).powf(1.0 / alpha);
    let second = LacSegment::new(
        first.end(),
        first.theta1(),
        length,
        Some(alpha),
        kappa,
        1.0 / rho_end,
    )
    .expect("second");
    let planted_gap = (second.dkappa_ds(0.0) - slope).abs() / slope.abs();
    assert!(planted_gap < 1e-12, "planted C3: {planted_gap}");
    let truth = [first, second];
    let stroke = jittered(&truth, 300, 0.05, 13);
    let chains = fit(&stroke, 0.5, Continuity::C3);
    assert_eq!(chains.len(), 1);
    let chain = &chains[0];
    assert_eq!(chain.continuity, Continuity::C3, "the smooth fit held");
    assert!(chain.within_tolerance, "deviation {}", chain.max_deviation);
    assert!(largest_jump(chain) <= G2_JUMP);
    for w in chain.segments.windows(2) {
        let (a, b) = (
            w[0].segment.dkappa_ds(w[0].segment.length()),
            w[1].segment.dkappa_ds(0.0),
        );
        let gap = (a - b).abs() / a.abs().max(b.abs());
        assert!(gap <= 1e-8, "dκ/ds {a} against {b}");
    }
    let off = distance_from_planted(chain, &truth);
    assert!(off <= 0.5, "{off} from the planted curve");
}

#[test]
fn every_recorded_stroke_in_g2_holds_its_tolerance_its_continuity_and_the_curvature_bound() {
    // The issue asks for every curve G2 (all 263 are: the long scribble part that stayed G1
    // needs 59 segments, within `MAX_SEGMENTS`).
    let reached = recorded_strokes_hold(Continuity::G2);
    assert!(
        reached.iter().all(|&c| c == Continuity::G2),
        "{} of {} curves G2 throughout",
        reached.iter().filter(|&&c| c == Continuity::G2).count(),
        reached.len()
    );
}

#[test]
fn a_part_whose_start_cannot_meet_its_joint_equations_is_laid_out_from_that_start() {
    // At 0.5 px, below the hey stroke's noise floor (0.72 px), a part of 14 segments starts too
    // far from a smooth chain for the joint equations' Newton steps: a segment winds beyond its
    // bound. Laid out forward from where the failed steps had left it, the chain wound too, from
    // both starts, and the part stayed G1, its seven smooth joints' curvatures jumping by 10 to
    // 170 %; laid out from the starting chain itself (the third try), it meets them.
    let reached = recorded_strokes_hold_in(
        Continuity::G2,
        Some(0.5),
        &["perfect-freehand-hey".to_string()],
    );
    assert!(
        reached.iter().all(|&c| c == Continuity::G2),
        "{} of {} curves G2 throughout",
        reached.iter().filter(|&&c| c == Continuity::G2).count(),
        reached.len()
    );
}

#[test]
fn every_recorded_stroke_in_c3_is_at_least_g2_and_c3_where_it_says_so() {
    // Compound rhythm on request: a part that cannot be made C3 is made G2, never left at the
    // G1 chain (37 of the 263 fixture curves were, with 94 more corners than in g2, and five
    // segments curling beyond the bound, before C3 fell back to G2 part by part).
    let reached = recorded_strokes_hold(Continuity::C3);
    assert!(
        reached.iter().all(|&c| c >= Continuity::G2),
        "{} of {} curves below G2",
        reached.iter().filter(|&&c| c < Continuity::G2).count(),
        reached.len()
    );
    assert!(reached.contains(&Continuity::C3), "no curve C3");
}

/// Fits every recorded fixture stroke in `continuity` and asserts what holds for every curve,
/// whatever the smooth fit manages: no curve loses its tolerance, every joint keeps position
/// continuity, no segment bends beyond the smooth chain's curvature bound, and a curve that says
/// G2 (C3) is curvature- (and dκ/ds-) continuous at every smooth joint (corners excepted: there
/// the samples turn faster than they resolve). Returns each curve's continuity.
fn recorded_strokes_hold(continuity: Continuity) -> Vec<Continuity> {
    recorded_strokes_hold_in(continuity, None, &common::fixture_names())
}

/// [`recorded_strokes_hold`] for the fixture files `names`, at `tolerance` where one is given
/// (else each stroke's own).
fn recorded_strokes_hold_in(
    continuity: Continuity,
    tolerance: Option<f64>,
    names: &[String],
) -> Vec<Continuity> {
    let mut options = PipelineOptions::default();
    options.chain.continuity = continuity;
    options.tolerance = tolerance;
    let mut reached = Vec::new();
    for name in names {
        let name = name.as_str();
        let file = common::fixture(name);
        let out = kansei::pipeline::fit_file(&file, &options).expect("options are valid");
        assert!(out.failures.is_empty(), "{name}: {:?}", out.failures);
        for curve in &out.curves {
            let Some(chain) = &curve.chain else { continue };
            reached.push(chain.continuity);
            assert!(
                chain.within_tolerance && chain.max_deviation <= curve.tolerance,
                "{name} {continuity}: deviation {} > {}",
                chain.max_deviation,
                curve.tolerance
            );
            for w in chain.segments.windows(2) {
                let gap = w[0].segment.end().distance(w[1].segment.start());
                let scale = 1.0 + w[1].segment.start().to_vec2().hypot();
                assert!(gap <= 1e-9 * scale, "{name}: a joint {gap} apart");
            }
            // No segment bends tighter than the smooth chain's bound: a hook at a corner is a
            // corner (and a line), not a curl (28 fixture segments did in g2 before, 26 of them
            // the painting's).
            let cap = curvature_bound(&curve.points, curve.tolerance);
            for s in &chain.segments {
                let bend = s.segment.kappa0().abs().max(s.segment.kappa1().abs());
                assert!(
                    bend <= cap * (1.0 + BOUND_ROUNDING),
                    "{name} {continuity} stroke {} samples {:?}: κ = {bend} beyond the bound {cap}",
                    curve.stroke,
                    s.samples
                );
            }
            if chain.continuity < Continuity::G2 {
                continue;
            }
            for joint in kansei::export::JointRecord::of_chain(&chain.segments) {
                if joint.kind != kansei::export::JointContinuity::Smooth {
                    continue;
                }
                let jump = joint.curvature_jump.expect("a finite jump");
                assert!(
                    jump <= G2_JUMP,
                    "{name}: {} curve with a jump {jump}",
                    chain.continuity
                );
                // dκ/ds is not finite where a segment leaves κ = 0 with α in (−1, 0): no jump
                // is measured there.
                if chain.continuity == Continuity::C3
                    && let Some(jump) = joint.dkappa_ds_jump
                {
                    assert!(jump <= C3_JUMP, "{name}: C3 curve with a dκ/ds jump {jump}");
                }
            }
        }
    }
    assert!(!reached.is_empty());
    reached
}

/// Largest relative dκ/ds jump at a C3 joint: the fit meets dκ/ds to 1e-9 of its magnitude
/// (`C3_TOLERANCE`), the final layout rounds it by a little more (measured at most 4e-10 over
/// the fixture strokes).
const C3_JUMP: f64 = 1e-8;

/// Relative rounding allowed above the curvature bound: the fit holds a joint's log-curvature
/// at the bound's logarithm, and the exponential rounds.
const BOUND_ROUNDING: f64 = 1e-9;

/// The smooth chain's curvature bound on a piece's distinct sample positions (see
/// `kansei::chain::smooth::MIN_RADIUS_TOLERANCES` and `MAX_TURN_PER_SAMPLE`): a radius of half a
/// tolerance, and a quarter turn between two samples at their median spacing.
fn curvature_bound(points: &[Point], tolerance: f64) -> f64 {
    let mut steps: Vec<f64> = points.windows(2).map(|w| w[0].distance(w[1])).collect();
    steps.sort_by(f64::total_cmp);
    let spacing = steps.get(steps.len() / 2).copied().unwrap_or(0.0);
    (1.0 / (kansei::chain::smooth::MIN_RADIUS_TOLERANCES * tolerance))
        .min(kansei::chain::smooth::MAX_TURN_PER_SAMPLE / spacing.max(f64::MIN_POSITIVE))
}

/// Asserts that no segment of `stroke` of the fixture file `name`, fitted with the defaults in
/// each of `modes`, bends tighter than half its tolerance in radius.
fn assert_no_needle(name: &str, stroke: usize, modes: &[Continuity]) {
    let file = common::fixture(name);
    for &continuity in modes {
        let mut options = PipelineOptions::default();
        options.chain.continuity = continuity;
        let StrokeOutcome::Curves(curves) =
            fit_with_noise(&file.strokes[stroke], stroke, file.units, &options)
        else {
            panic!("curves");
        };
        for curve in curves {
            let chain = curve.chain.expect("a chain");
            assert!(chain.within_tolerance, "{name} {continuity}");
            for s in &chain.segments {
                let bend = s.segment.kappa0().abs().max(s.segment.kappa1().abs());
                assert!(
                    bend <= 1.0 / (0.5 * curve.tolerance),
                    "{name} {continuity}: a segment of {} bends to κ = {bend} at tolerance {}",
                    s.segment.length(),
                    curve.tolerance
                );
            }
        }
    }
}

#[test]
fn a_start_hook_leaves_no_needle() {
    // Stroke 16 of the recorded painting: the pen lands, moves 3 px one way and comes back along
    // a near line. The chain starts at the reversal; the B-spline's end tangent there points
    // back along the hook, and a segment kept to it turned 3 rad within its first 0.02 px
    // (κ = 44.7 /px at a tolerance of 1 px). No segment may bend tighter than half a tolerance
    // in radius to turn back into the line, in either mode.
    assert_no_needle(
        "libmypaint-painting30sec",
        16,
        &[Continuity::G1, Continuity::G2],
    );
}

#[test]
fn a_segment_between_corners_of_the_smooth_chain_leaves_no_needle() {
    // The perfect-freehand "he": where the G1 chain bends beyond the bound the smooth chain
    // makes a corner, and the segment between two such corners kept the G1 chain's tangents,
    // one of them curling to κ = 41 /px at a tolerance of 1.08 px. Both its tangents are free
    // (a corner is G0): turned, it holds its samples within the bound.
    assert_no_needle("perfect-freehand-he2", 0, &[Continuity::G2]);
}

#[test]
fn a_smooth_chain_never_loses_a_tolerance_its_g1_chain_holds() {
    // The guarantee before the continuity: wherever the G1 chain of a piece holds its tolerance,
    // so does that piece in g2 and c3 (a jiggle of the synthetic fixtures came back 1.32 px off
    // at 0.71 in g2, its G1 chain within 0.41: the G1 chain that starts a smooth fit, refined
    // less, had missed, and the smooth fit kept the miss).
    let mut files = common::synthetic_fixtures();
    files.extend(
        ["google-ink-spring", "perfect-freehand-corners"]
            .map(|name| (name.to_string(), common::fixture(name))),
    );
    for (name, file) in &files {
        let fit_in = |continuity: Continuity| {
            let mut options = PipelineOptions::default();
            options.chain.continuity = continuity;
            kansei::pipeline::fit_file(file, &options).expect("options are valid")
        };
        let g1 = fit_in(Continuity::G1);
        for continuity in [Continuity::G2, Continuity::C3] {
            let smooth = fit_in(continuity);
            assert_eq!(
                smooth.curves.len(),
                g1.curves.len(),
                "{name}: the same pieces"
            );
            for (a, b) in g1.curves.iter().zip(&smooth.curves) {
                assert_eq!((a.stroke, a.samples), (b.stroke, b.samples), "{name}");
                let (Some(a_chain), Some(b_chain)) = (&a.chain, &b.chain) else {
                    continue;
                };
                if a_chain.within_tolerance {
                    assert!(
                        b_chain.within_tolerance && b_chain.max_deviation <= b.tolerance,
                        "{name} stroke {} {:?} in {continuity}: {} > {} (G1 {})",
                        b.stroke,
                        b.samples,
                        b_chain.max_deviation,
                        b.tolerance,
                        a_chain.max_deviation
                    );
                }
            }
        }
    }
}
