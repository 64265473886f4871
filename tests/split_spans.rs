//! Integration tests of the split stage: closed forms, joints, noise thresholds, invariance, the
//! monotonic-span property on deterministic pseudo-random splines, and errors.

use kansei::geom::{
    CubicBez, ParamBez, ParamCurve, ParamCurveDeriv, Point, Vec2, curvature_from_derivs,
};
use kansei::split::{CurvatureSign, Spans, SplitError, SplitKind, SplitOptions, split_spans};

fn piece(p: [(f64, f64); 4], u0: f64, u1: f64) -> ParamBez {
    ParamBez {
        bez: CubicBez::new(p[0], p[1], p[2], p[3]),
        u0,
        u1,
    }
}

/// The Bézier pieces of the uniform cubic B-spline with control points `ctrl` (knot spans
/// `[i, i + 1]`).
fn uniform_bspline(ctrl: &[Point]) -> Vec<ParamBez> {
    ctrl.windows(4)
        .enumerate()
        .map(|(i, w)| {
            let [a, b, c, d] = [
                w[0].to_vec2(),
                w[1].to_vec2(),
                w[2].to_vec2(),
                w[3].to_vec2(),
            ];
            let bez = CubicBez::new(
                ((a + b * 4.0 + c) / 6.0).to_point(),
                ((b * 2.0 + c) / 3.0).to_point(),
                ((b + c * 2.0) / 3.0).to_point(),
                ((b + c * 4.0 + d) / 6.0).to_point(),
            );
            ParamBez {
                bez,
                u0: i as f64,
                u1: (i + 1) as f64,
            }
        })
        .collect()
}

/// Curvature of the chain at global parameter `u`, straight from kurbo's derivatives.
fn kappa_at(pieces: &[ParamBez], u: f64) -> f64 {
    let p = pieces
        .iter()
        .find(|p| u <= p.u1)
        .unwrap_or(&pieces[pieces.len() - 1]);
    kappa_local(&p.bez, p.local(u))
}

fn kappa_local(bez: &CubicBez, t: f64) -> f64 {
    let d1 = bez.deriv();
    curvature_from_derivs(d1.eval(t).to_vec2(), d1.deriv().eval(t).to_vec2())
}

fn interior(spans: &Spans) -> Vec<(SplitKind, f64)> {
    spans.splits[1..spans.splits.len() - 1]
        .iter()
        .map(|s| (s.kind, s.u))
        .collect()
}

fn split(pieces: &[ParamBez]) -> Spans {
    split_spans(pieces, &SplitOptions::default()).expect("valid input")
}

/// Deterministic xorshift64* generator for the property tests.
struct Rng(u64);
impl Rng {
    fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}

/// A pseudo-random stroke-like B-spline: a random walk with bounded turning per step.
fn random_spline(seed: u64, n: usize) -> Vec<ParamBez> {
    let mut rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    let mut p = Point::new(rng.range(-10.0, 10.0), rng.range(-10.0, 10.0));
    let mut heading = rng.range(0.0, std::f64::consts::TAU);
    let mut ctrl = vec![p];
    for _ in 1..n {
        heading += rng.range(-1.3, 1.3);
        p += Vec2::new(heading.cos(), heading.sin()) * rng.range(0.5, 3.0);
        ctrl.push(p);
    }
    uniform_bspline(&ctrl)
}

#[test]
fn symmetric_s_splits_at_its_exact_inflection() {
    // Point-symmetric about its midpoint: the inflection is exactly at t = 1/2.
    let pieces = [piece(
        [(0.0, 0.0), (1.0, 1.0), (2.0, -1.0), (3.0, 0.0)],
        0.0,
        1.0,
    )];
    let s = split(&pieces);
    let inflections: Vec<f64> = s
        .splits
        .iter()
        .filter(|p| p.kind == SplitKind::Inflection)
        .map(|p| p.u)
        .collect();
    assert_eq!(inflections.len(), 1, "{:?}", s.splits);
    assert!((inflections[0] - 0.5).abs() < 1e-15);
    // The curve first turns clockwise, then counter-clockwise; the curvature maxima of the two lobes are mirror
    // images of each other about u = 1/2.
    let signs: Vec<CurvatureSign> = s.spans.iter().map(|sp| sp.sign).collect();
    let before: Vec<_> = s
        .spans
        .iter()
        .filter(|sp| sp.u1 <= 0.5)
        .map(|sp| sp.sign)
        .collect();
    let after: Vec<_> = s
        .spans
        .iter()
        .filter(|sp| sp.u0 >= 0.5)
        .map(|sp| sp.sign)
        .collect();
    assert_eq!(before.len() + after.len(), signs.len());
    assert!(
        before.iter().all(|&g| g == CurvatureSign::Negative),
        "{signs:?}"
    );
    assert!(
        after.iter().all(|&g| g == CurvatureSign::Positive),
        "{signs:?}"
    );
    let inner = interior(&s);
    for (a, b) in inner.iter().zip(inner.iter().rev()) {
        assert_eq!(a.0, b.0);
        assert!((a.1 + b.1 - 1.0).abs() < 1e-12, "{inner:?}");
    }
}

#[test]
fn asymmetric_inflection_at_one_third_with_a_global_parameter() {
    // γ = (1 − 3t)(2 − t)/2 for these legs (see curvature.rs): inflection at t = 1/3, so at
    // u = 2 + 3 · 1/3 = 3 on the span [2, 5].
    let pieces = [piece(
        [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (2.0, -0.5)],
        2.0,
        5.0,
    )];
    let s = split(&pieces);
    let infl: Vec<_> = s
        .splits
        .iter()
        .filter(|p| p.kind == SplitKind::Inflection)
        .collect();
    assert_eq!(infl.len(), 1, "{:?}", s.splits);
    assert!((infl[0].u - 3.0).abs() < 1e-14);
    assert!(infl[0].curvature.abs() < 1e-12);
    assert!((infl[0].point - pieces[0].bez.eval(1.0 / 3.0)).hypot() < 1e-14);
}

#[test]
fn symmetric_arch_has_one_extremum_at_the_middle() {
    let pieces = [piece(
        [(0.0, 0.0), (1.0, 2.0), (3.0, 2.0), (4.0, 0.0)],
        0.0,
        1.0,
    )];
    let s = split(&pieces);
    assert_eq!(interior(&s).len(), 1, "{:?}", s.splits);
    let (kind, u) = interior(&s)[0];
    assert_eq!(kind, SplitKind::CurvatureExtremum);
    assert!((u - 0.5).abs() < 1e-14);
    // The arch turns clockwise (y up): both spans negative, |κ| rising then falling.
    assert!(s.spans.iter().all(|sp| sp.sign == CurvatureSign::Negative));
    assert!(s.splits[1].curvature.abs() > s.splits[0].curvature.abs());
    assert!(s.splits[1].curvature.abs() > s.splits[2].curvature.abs());
}

#[test]
fn parabola_vertex_is_found_exactly() {
    // y = x² for x ∈ [−1, 3] (quadratic Bézier Q = (−1,1), (1,−3), (3,9), degree-elevated);
    // x = −1 + 4t so the vertex is at t = 1/4, u = 2 + 4/4 = 3 on [2, 6], with κ = 2.
    let (q0, q1, q2) = (
        Point::new(-1.0, 1.0),
        Point::new(1.0, -3.0),
        Point::new(3.0, 9.0),
    );
    let bez = CubicBez::new(q0, q0.lerp(q1, 2.0 / 3.0), q2.lerp(q1, 2.0 / 3.0), q2);
    let s = split(&[ParamBez {
        bez,
        u0: 2.0,
        u1: 6.0,
    }]);
    assert_eq!(interior(&s).len(), 1, "{:?}", s.splits);
    let vertex = s.splits[1];
    assert_eq!(vertex.kind, SplitKind::CurvatureExtremum);
    assert!((vertex.u - 3.0).abs() < 1e-13);
    assert!((vertex.curvature - 2.0).abs() < 1e-12);
    assert!((vertex.point - Point::ORIGIN).hypot() < 1e-14);
    assert!(s.spans.iter().all(|sp| sp.sign == CurvatureSign::Positive));
}

#[test]
fn extremum_exactly_at_a_joint_is_one_split() {
    // The symmetric arch cut at its apex: h vanishes at t = 1 of the first piece and t = 0 of
    // the second. One split, at the joint.
    let arch = CubicBez::new((0.0, 0.0), (1.0, 2.0), (3.0, 2.0), (4.0, 0.0));
    let pieces = [
        ParamBez {
            bez: arch.subsegment(0.0..0.5),
            u0: 0.0,
            u1: 1.0,
        },
        ParamBez {
            bez: arch.subsegment(0.5..1.0),
            u0: 1.0,
            u1: 2.0,
        },
    ];
    let s = split(&pieces);
    assert_eq!(
        interior(&s),
        [(SplitKind::CurvatureExtremum, 1.0)],
        "{:?}",
        s.splits
    );
    // Each span is exactly one input piece, passed through unchanged.
    assert_eq!(s.spans[0].pieces, [pieces[0]]);
    assert_eq!(s.spans[1].pieces, [pieces[1]]);
}

#[test]
fn extremum_at_a_c2_joint_with_a_jump_in_dkappa() {
    // A symmetric uniform B-spline: the joint u = 1 is the axis of symmetry, so |κ| is extremal
    // there, while d|κ|/du is non-zero on both sides (κ is only C0 in u: it needs x‴).
    let ctrl = [(0.0, 0.0), (1.0, 1.0), (2.0, 1.5), (3.0, 1.0), (4.0, 0.0)].map(Point::from);
    let pieces = uniform_bspline(&ctrl);
    let step = 1e-5;
    let left = (kappa_at(&pieces, 1.0).abs() - kappa_at(&pieces, 1.0 - step).abs()) / step;
    let right = (kappa_at(&pieces, 1.0 + step).abs() - kappa_at(&pieces, 1.0).abs()) / step;
    assert!(
        left > 1e-3 && right < -1e-3,
        "one-sided slopes {left}, {right}: not a jump case"
    );
    let s = split(&pieces);
    let at_joint: Vec<_> = interior(&s)
        .into_iter()
        .filter(|&(_, u)| (u - 1.0).abs() < 1e-6)
        .collect();
    assert_eq!(
        at_joint,
        [(SplitKind::CurvatureExtremum, 1.0)],
        "{:?}",
        s.splits
    );
}

#[test]
fn joint_that_is_not_an_extremum_is_not_a_split() {
    // A plain arch cut off-centre: |κ| keeps rising through the joint.
    let arch = CubicBez::new((0.0, 0.0), (1.0, 2.0), (3.0, 2.0), (4.0, 0.0));
    let pieces = [
        ParamBez {
            bez: arch.subsegment(0.0..0.3),
            u0: 0.0,
            u1: 0.3,
        },
        ParamBez {
            bez: arch.subsegment(0.3..1.0),
            u0: 0.3,
            u1: 1.0,
        },
    ];
    let s = split(&pieces);
    assert_eq!(interior(&s).len(), 1, "{:?}", s.splits);
    assert!((interior(&s)[0].1 - 0.5).abs() < 1e-12);
    // The first span spans both input pieces: the whole first piece and part of the second.
    assert_eq!(s.spans[0].pieces.len(), 2);
    assert_eq!(s.spans[0].pieces[0], pieces[0]);
}

/// A parabolic arch (B-spline, 8 units wide, 4 high) with control point `index` raised by `bump`.
fn bumped_arch(index: usize, bump: f64) -> Vec<ParamBez> {
    let ctrl: Vec<Point> = (0..9)
        .map(|i| {
            let x = i as f64;
            let raise = if i == index { bump } else { 0.0 };
            Point::new(x, 4.0 - 0.25 * (x - 4.0) * (x - 4.0) + raise)
        })
        .collect();
    uniform_bspline(&ctrl)
}

#[test]
fn tiny_curvature_ripple_is_dropped_real_extremum_kept() {
    let raw = SplitOptions::default().with_extremum_relative(0.0);
    // Without the bump the arch has exactly one curvature extremum (the apex, u = 3).
    let clean = split_spans(&bumped_arch(6, 0.0), &raw).expect("valid");
    assert_eq!(interior(&clean).len(), 1, "{:?}", clean.splits);
    assert!((interior(&clean)[0].1 - 3.0).abs() < 1e-12);
    // Raising one control point by 2.5 % of the height adds a max/min pair whose |κ| differ by
    // about 4 %: resolved at threshold 0…
    let rippled = bumped_arch(6, 0.1);
    let fine = split_spans(&rippled, &raw).expect("valid");
    assert_eq!(interior(&fine).len(), 3, "{:?}", fine.splits);
    let (a, b) = (
        fine.splits[2].curvature.abs(),
        fine.splits[3].curvature.abs(),
    );
    assert!((a - b).abs() < 0.05 * a.max(b), "{a} vs {b}");
    // …and dropped by the default 5 % threshold, keeping the apex.
    let coarse = split(&rippled);
    assert_eq!(
        interior(&coarse),
        [(SplitKind::CurvatureExtremum, 3.0)],
        "{:?}",
        coarse.splits
    );
    // The same happens for a bump next to the apex (5 % of the height, |κ| pair 5 % apart).
    let near_apex = bumped_arch(4, 0.2);
    assert_eq!(
        interior(&split_spans(&near_apex, &raw).expect("valid")).len(),
        5
    );
    assert_eq!(interior(&split(&near_apex)).len(), 1);
    // A bump whose max/min pair differs by ~20 % is a real feature and survives the default.
    let bumpy = split(&bumped_arch(5, 0.2));
    assert_eq!(interior(&bumpy).len(), 3, "{:?}", bumpy.splits);
    let (c, d) = (
        bumpy.splits[1].curvature.abs(),
        bumpy.splits[2].curvature.abs(),
    );
    assert!((c - d).abs() > 0.15 * c.max(d));
}

#[test]
fn near_straight_wiggles_do_not_flood_inflections() {
    // A straight B-spline (10 m long in mm) whose control points wiggle by ±1 µm.
    let ctrl: Vec<Point> = (0..14)
        .map(|i| Point::new(i as f64 * 1000.0, if i % 2 == 0 { 1e-3 } else { -1e-3 }))
        .collect();
    let pieces = uniform_bspline(&ctrl);
    let none = SplitOptions::default()
        .with_extremum_relative(0.0)
        .with_straight_relative(0.0)
        .with_straight_turning(0.0);
    let raw = split_spans(&pieces, &none).expect("valid");
    let raw_inflections = raw
        .splits
        .iter()
        .filter(|p| p.kind == SplitKind::Inflection)
        .count();
    assert!(raw_inflections >= 8, "{:?}", raw.splits);
    let s = split(&pieces);
    assert_eq!(s.splits.len(), 2, "{:?}", s.splits);
    assert_eq!(s.spans[0].sign, CurvatureSign::Zero);
    assert!(s.straight_curvature > 0.0);
}

#[test]
fn straight_stretch_between_two_bends_keeps_its_real_inflection_only() {
    // Bend left, long near-straight stretch with tiny wiggles, bend right: one real inflection.
    let mut ctrl = vec![
        Point::new(0.0, -3.0),
        Point::new(1.0, -1.0),
        Point::new(2.0, 0.0),
    ];
    for i in 3..12 {
        ctrl.push(Point::new(i as f64, if i % 2 == 0 { 1e-5 } else { -1e-5 }));
    }
    ctrl.extend([
        Point::new(12.0, 0.0),
        Point::new(13.0, 1.0),
        Point::new(14.0, 3.0),
    ]);
    let pieces = uniform_bspline(&ctrl);
    let s = split(&pieces);
    let inflections = s
        .splits
        .iter()
        .filter(|p| p.kind == SplitKind::Inflection)
        .count();
    assert_eq!(inflections, 1, "{:?}", s.splits);
    assert!(s.spans.iter().any(|sp| sp.sign == CurvatureSign::Positive));
    assert!(s.spans.iter().any(|sp| sp.sign == CurvatureSign::Negative));
}

#[test]
fn exactly_straight_chain_is_one_zero_span() {
    // Collinear control points with uneven spacing: κ ≡ 0, g and h vanish identically.
    let ctrl = [0.0, 1.0, 3.0, 3.5, 6.0, 7.0].map(|x| Point::new(x, 2.0 * x + 1.0));
    let pieces = uniform_bspline(&ctrl);
    for options in [
        SplitOptions::default(),
        SplitOptions::default()
            .with_extremum_relative(0.0)
            .with_straight_turning(0.0),
    ] {
        let s = split_spans(&pieces, &options).expect("valid");
        assert_eq!(s.splits.len(), 2, "{:?}", s.splits);
        assert_eq!(s.spans[0].sign, CurvatureSign::Zero);
        assert_eq!(s.spans[0].pieces, pieces);
    }
}

fn transform(pieces: &[ParamBez], angle: f64, scale: f64, offset: Vec2) -> Vec<ParamBez> {
    let (sin, cos) = angle.sin_cos();
    let map = |p: Point| {
        Point::new(
            scale * (cos * p.x - sin * p.y) + offset.x,
            scale * (sin * p.x + cos * p.y) + offset.y,
        )
    };
    pieces
        .iter()
        .map(|p| ParamBez {
            bez: CubicBez::new(map(p.bez.p0), map(p.bez.p1), map(p.bez.p2), map(p.bez.p3)),
            ..*p
        })
        .collect()
}

#[test]
fn similarity_transforms_do_not_change_the_split() {
    for seed in 0..12 {
        let pieces = random_spline(seed, 10);
        let Ok(base) = split_spans(&pieces, &SplitOptions::default()) else {
            continue;
        };
        for (angle, scale, offset) in [
            (0.7, 3.7, Vec2::new(100.0, -50.0)),
            (-2.1, 0.013, Vec2::new(-1e4, 3e3)),
        ] {
            let moved = split_spans(
                &transform(&pieces, angle, scale, offset),
                &SplitOptions::default(),
            )
            .expect("valid");
            let (a, b) = (interior(&base), interior(&moved));
            assert_eq!(a.len(), b.len(), "seed {seed}: {a:?} vs {b:?}");
            for (x, y) in a.iter().zip(&b) {
                assert_eq!(x.0, y.0, "seed {seed}");
                assert!((x.1 - y.1).abs() < 1e-9, "seed {seed}: {a:?} vs {b:?}");
            }
            for (x, y) in base.spans.iter().zip(&moved.spans) {
                assert_eq!(x.sign, y.sign, "seed {seed}");
            }
            // Curvature scales by 1/scale.
            for (x, y) in base.splits.iter().zip(&moved.splits) {
                assert!(
                    (x.curvature - y.curvature * scale).abs() <= 1e-9 * x.curvature.abs().max(1.0)
                );
            }
        }
    }
}

/// Samples every span densely and checks one sign and monotonic `|κ|` up to `slack(peak, straight)`
/// (`peak` the span's largest sampled |κ|); returns how many regular splines were checked and the
/// total number of spans.
fn check_random_splines(options: &SplitOptions, slack: impl Fn(f64, f64) -> f64) -> (usize, usize) {
    let (mut checked, mut spans) = (0, 0);
    for seed in 0..40 {
        let pieces = random_spline(seed, 6 + (seed as usize % 7));
        let s = match split_spans(&pieces, options) {
            Ok(s) => s,
            Err(SplitError::Singular { .. }) => continue,
            Err(e) => panic!("seed {seed}: {e}"),
        };
        checked += 1;
        spans += s.spans.len();
        check_structure(&pieces, &s, seed);
        for span in &s.spans {
            let samples: Vec<f64> = span
                .pieces
                .iter()
                .flat_map(|p| (0..=200).map(move |j| kappa_local(&p.bez, j as f64 / 200.0)))
                .collect();
            let peak = samples.iter().fold(0.0f64, |m, k| m.max(k.abs()));
            let slack = slack(peak, s.straight_curvature);
            let increasing = samples[samples.len() - 1].abs() >= samples[0].abs();
            let mut best = if increasing { 0.0 } else { f64::INFINITY };
            for &k in &samples {
                if increasing {
                    assert!(
                        k.abs() >= best - slack,
                        "seed {seed}: |κ| falls in a rising span {span:?}"
                    );
                    best = best.max(k.abs());
                } else {
                    assert!(
                        k.abs() <= best + slack,
                        "seed {seed}: |κ| rises in a falling span {span:?}"
                    );
                    best = best.min(k.abs());
                }
                let signed_ok = match span.sign {
                    CurvatureSign::Positive => k >= -slack,
                    CurvatureSign::Negative => k <= slack,
                    CurvatureSign::Zero => k.abs() <= 2.0 * slack,
                };
                assert!(signed_ok, "seed {seed}: κ = {k} in a {:?} span", span.sign);
            }
        }
    }
    (checked, spans)
}

#[test]
fn spans_are_monotonic_and_single_signed_on_random_splines() {
    // Default thresholds: monotonic and single-signed up to the documented threshold.
    let options = SplitOptions::default();
    let (checked, spans) = check_random_splines(&options, |peak, straight| {
        (options.extremum_relative * peak).max(straight) + 1e-9 * peak
    });
    assert!(checked >= 30, "only {checked} regular random splines");
    assert!(
        spans >= 3 * checked,
        "too few spans ({spans}) for the check to mean anything"
    );
    // No thresholds: every extremum and joint is kept, and the spans are monotonic up to rounding
    // (this checks that the root isolation misses nothing).
    let raw = SplitOptions::default()
        .with_extremum_relative(0.0)
        .with_straight_relative(0.0)
        .with_straight_turning(0.0);
    let (_, raw_spans) = check_random_splines(&raw, |peak, _| 1e-9 * peak);
    assert!(
        raw_spans > spans,
        "thresholds dropped nothing: {raw_spans} vs {spans}"
    );
}

/// Structural invariants of any result.
fn check_structure(pieces: &[ParamBez], s: &Spans, seed: u64) {
    let (first, last) = (&s.splits[0], &s.splits[s.splits.len() - 1]);
    assert_eq!(first.kind, SplitKind::Start);
    assert_eq!(last.kind, SplitKind::End);
    assert_eq!(first.u, pieces[0].u0);
    assert_eq!(last.u, pieces[pieces.len() - 1].u1);
    assert_eq!(s.spans.len() + 1, s.splits.len());
    for (i, span) in s.spans.iter().enumerate() {
        let (a, b) = (&s.splits[i], &s.splits[i + 1]);
        assert!(a.u < b.u, "seed {seed}: splits not increasing");
        assert_eq!(
            (span.u0, span.u1, span.start, span.end),
            (a.u, b.u, a.kind, b.kind)
        );
        let subs = &span.pieces;
        assert!(!subs.is_empty());
        assert_eq!(subs[0].u0, span.u0);
        assert_eq!(subs[subs.len() - 1].u1, span.u1);
        assert_eq!(subs[0].bez.p0, a.point);
        assert_eq!(subs[subs.len() - 1].bez.p3, b.point);
        for w in subs.windows(2) {
            assert_eq!(w[0].u1, w[1].u0);
            assert!((w[0].bez.p3 - w[1].bez.p0).hypot() < 1e-12);
        }
        for sub in subs {
            assert!(sub.u0 < sub.u1);
            // Each sub-Bézier traces the input curve over its parameter range.
            for j in 0..=4 {
                let t = j as f64 / 4.0;
                let u = sub.global(t);
                let p = pieces
                    .iter()
                    .find(|p| u <= p.u1)
                    .unwrap_or(&pieces[pieces.len() - 1]);
                let d = (sub.bez.eval(t) - p.bez.eval(p.local(u))).hypot();
                assert!(d < 1e-9, "seed {seed}: sub-Bézier off the curve by {d}");
            }
        }
        if i > 0 {
            let kinds_agree = match (s.spans[i - 1].sign, span.sign) {
                (CurvatureSign::Positive, CurvatureSign::Negative)
                | (CurvatureSign::Negative, CurvatureSign::Positive) => {
                    a.kind == SplitKind::Inflection
                }
                _ => a.kind == SplitKind::CurvatureExtremum,
            };
            assert!(kinds_agree, "seed {seed}: kind {:?} between spans", a.kind);
        }
    }
}

#[test]
fn errors_are_typed() {
    let good = piece([(0.0, 0.0), (1.0, 2.0), (3.0, 2.0), (4.0, 0.0)], 0.0, 1.0);
    let o = SplitOptions::default();
    assert_eq!(split_spans(&[], &o), Err(SplitError::Empty));
    let nan = piece(
        [(0.0, 0.0), (f64::NAN, 2.0), (3.0, 2.0), (4.0, 0.0)],
        0.0,
        1.0,
    );
    assert_eq!(
        split_spans(&[good, nan], &o),
        Err(SplitError::NonFinite { piece: 1 })
    );
    let inf_u = ParamBez {
        u1: f64::INFINITY,
        ..good
    };
    assert_eq!(
        split_spans(&[inf_u], &o),
        Err(SplitError::NonFinite { piece: 0 })
    );
    let reversed = ParamBez {
        u0: 1.0,
        u1: 0.0,
        ..good
    };
    assert!(matches!(
        split_spans(&[reversed], &o),
        Err(SplitError::EmptyParameterRange { piece: 0, .. })
    ));
    let next = piece([(4.0, 0.0), (5.0, -2.0), (7.0, -2.0), (8.0, 0.0)], 1.0, 2.0);
    assert!(split_spans(&[good, next], &o).is_ok());
    let u_gap = ParamBez {
        u0: 1.1,
        u1: 2.0,
        ..next
    };
    assert!(matches!(
        split_spans(&[good, u_gap], &o),
        Err(SplitError::ParameterGap { piece: 1, .. })
    ));
    let moved = piece([(4.0, 0.1), (5.0, -2.0), (7.0, -2.0), (8.0, 0.0)], 1.0, 2.0);
    assert!(matches!(
        split_spans(&[good, moved], &o),
        Err(SplitError::PositionGap { piece: 1, .. })
    ));
    let point = piece([(1.0, 1.0); 4], 0.0, 1.0);
    assert_eq!(
        split_spans(&[point], &o),
        Err(SplitError::Singular { piece: 0 })
    );
    let cusp = piece([(0.0, 0.0), (1.0, 1.0), (0.0, 1.0), (1.0, 0.0)], 0.0, 1.0);
    assert_eq!(
        split_spans(&[cusp], &o),
        Err(SplitError::Singular { piece: 0 })
    );
    let bad = o.with_extremum_relative(2.0);
    assert!(matches!(
        split_spans(&[good], &bad),
        Err(SplitError::InvalidOption {
            name: "extremum_relative",
            ..
        })
    ));
}

#[test]
fn split_kind_serialises_in_snake_case() {
    let json = serde_json::to_string(&[
        SplitKind::CurvatureExtremum,
        SplitKind::Start,
        SplitKind::Inflection,
    ])
    .expect("serialise");
    assert_eq!(json, r#"["curvature_extremum","start","inflection"]"#);
    let back: SplitKind = serde_json::from_str(r#""corner""#).expect("deserialise");
    assert_eq!(back, SplitKind::Corner);
    assert_eq!(
        serde_json::to_string(&CurvatureSign::Zero).expect("serialise"),
        r#""zero""#
    );
}
