//! Properties of LAC segment evaluation: closed forms against quadrature, Fresnel integrals,
//! limits (circle, α → 0, α → 1), θ1 − θ0 = ∫κ, the rendering fast path, and the JSON record.

use kansei::geom::{Point, Vec2};
use kansei::lac::{LacError, LacSegment, StandardLac, quadrature};
use kurbo::common::GAUSS_LEGENDRE_COEFFS_16;
use serde_json::Value;
use std::f64::consts::PI;

const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/lac-reference/");

/// Accuracy promised by the evaluator, relative to the length.
const TOL: f64 = 1e-12;

fn seg(s: f64, alpha: Option<f64>, k0: f64, k1: f64) -> LacSegment {
    LacSegment::new(Point::new(0.3, -0.2), 0.4, s, alpha, k0, k1)
        .unwrap_or_else(|e| panic!("{s} {alpha:?} {k0} {k1}: {e}"))
}

/// A spread of segments: both directions of curvature change, both turning senses, κ = 0 ends,
/// curvature ratios up to 1e20, α on and near the special values.
fn zoo() -> Vec<LacSegment> {
    let mut v = Vec::new();
    for alpha in [
        -3.0,
        -1.0,
        -0.5,
        -1e-9,
        0.0,
        1e-9,
        0.5,
        1.0 - 1e-9,
        1.0,
        1.5,
        2.0,
        3.0,
    ] {
        for (k0, k1, s) in [
            (2.0, 0.5, 3.0),
            (0.5, 2.0, 3.0),
            (1.0, 1e-20, 40.0),
            (-1e-6, -1e-2, 1e3),
        ] {
            v.push(seg(s, Some(alpha), k0, k1));
        }
        if alpha < 0.0 {
            v.push(seg(2.0, Some(alpha), 0.4, 0.0));
            v.push(seg(2.0, Some(alpha), 0.0, -0.4));
        }
    }
    v.push(seg(5.0, None, 0.3, 0.3));
    v.push(seg(5.0, None, -1e-13, -1e-13));
    v.push(seg(5.0, None, 0.0, 0.0));
    v
}

/// ∫_a^b f by 16-point Gauss–Legendre on a mesh graded geometrically (ratio 1/2, 60 levels)
/// towards both ends, each graded panel split in 8: exponentially convergent even for the
/// algebraic end singularity of κ at a κ = 0 end.
fn graded_gl(f: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    let mut sum = 0.0;
    let mut w = 0.5 * (b - a);
    for _ in 0..60 {
        // [a + w/2, a + w] ∪ [b − w, b − w/2]; the innermost levels reach the ends.
        sum += gl(&f, a + 0.5 * w, a + w, 8) + gl(&f, b - w, b - 0.5 * w, 8);
        w *= 0.5;
    }
    sum + gl(&f, a, a + w, 1) + gl(&f, b - w, b, 1)
}

/// Composite 16-point Gauss–Legendre of f over [a, b] in n equal panels.
fn gl(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let h = (b - a) / n as f64;
    let mut sum = 0.0;
    for i in 0..n {
        let mid = a + (i as f64 + 0.5) * h;
        for &(w, x) in GAUSS_LEGENDRE_COEFFS_16 {
            sum += w * f(mid + 0.5 * h * x);
        }
    }
    0.5 * h * sum
}

#[test]
fn closed_forms_match_quadrature() {
    for alpha in [1.0, 2.0] {
        for lambda in [0.0, 1e-8, 0.2, 1.0, 5.0, 50.0] {
            let lac = StandardLac::new(alpha, lambda).expect("valid");
            for s in [1e-9, 1e-3, 0.3, 1.0, 4.0, 10.0] {
                let closed = lac.point(s).to_vec2();
                let quad = quadrature::integrate(&lac, 0.0, s);
                assert!(
                    (closed - quad).hypot() <= TOL * s,
                    "α {alpha} Λ {lambda} s {s}: {closed:?} vs {quad:?}"
                );
            }
        }
    }
}

/// α = 1: P = ((1 + Λs)^{1 + i/Λ} − 1)/(Λ + i), written out independently with powf.
/// α = 2: P = e^{−ik}/Λ [F(w) − F(1)], F(w) = e^{ikw}(w/(ik) + 1/k²), k = 1/Λ, w = √(1 + 2Λs).
#[test]
fn log_spiral_and_involute_textbook_forms() {
    let mul = |a: Vec2, b: Vec2| Vec2::new(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
    let cis = |t: f64| Vec2::new(t.cos(), t.sin());
    for lambda in [0.3, 1.0, 2.0] {
        let spiral = StandardLac::new(1.0, lambda).expect("valid");
        let involute = StandardLac::new(2.0, lambda).expect("valid");
        for s in [0.5, 1.0, 3.0] {
            let base = 1.0 + lambda * s;
            let num = base * cis(base.ln() / lambda) - Vec2::new(1.0, 0.0);
            let d = Vec2::new(lambda, 1.0);
            let want = Vec2::new(num.x * d.x + num.y * d.y, num.y * d.x - num.x * d.y) / d.hypot2();
            assert!(
                (spiral.point(s).to_vec2() - want).hypot() <= 1e-14 * (1.0 + base),
                "α=1 Λ {lambda} s {s}"
            );

            let k = 1.0 / lambda;
            let f = |w: f64| mul(cis(k * w), Vec2::new(1.0 / (k * k), -w / k));
            let w = (1.0 + 2.0 * lambda * s).sqrt();
            let want = mul(cis(-k), f(w) - f(1.0)) / lambda;
            assert!(
                (involute.point(s).to_vec2() - want).hypot() <= 1e-13 * (1.0 + k * k),
                "α=2 Λ {lambda} s {s}"
            );
            // And both are unit-speed curves with the closed-form θ: finite-difference tangent.
            for lac in [spiral, involute] {
                let h = 1e-5;
                let d = (lac.point(s + h) - lac.point(s - h)) / (2.0 * h);
                assert!((d - cis(lac.theta(s))).hypot() < 1e-9);
            }
        }
    }
}

/// α = −1 (clothoid) against the 25-digit Fresnel values of `lac_crosscheck.json`. With
/// Λ = 1/(π x1²) and the segment ending where the Fresnel argument is −x2 (0 ≤ x2 < x1):
/// length πx1(x1 − x2), κ1 = x2/x1 and
/// P = e^{iπx1²/2}·πx1·[(C(x1) − C(x2)) − i(S(x1) − S(x2))].
#[test]
fn clothoid_matches_fresnel_values() {
    let text =
        std::fs::read_to_string(format!("{DATA_DIR}lac_crosscheck.json")).unwrap_or_else(|e| {
            panic!(
                "{DATA_DIR}lac_crosscheck.json missing ({e}): it ships in fixtures/lac-reference/"
            )
        });
    let v: Value = serde_json::from_str(&text).expect("valid JSON");
    let parse = |e: &Value, k: &str| -> f64 {
        e[k].as_str()
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("{k} in {e}"))
    };
    let mut fres: Vec<(f64, f64, f64)> = vec![(0.0, 0.0, 0.0)];
    for e in v["fresnel_pi_over_2"].as_array().expect("fresnel table") {
        fres.push((parse(e, "x"), parse(e, "C"), parse(e, "S")));
    }
    assert!(fres.len() >= 12);
    let mut worst: f64 = 0.0;
    for &(x1, c1, s1) in &fres {
        for &(x2, c2, s2) in fres.iter().filter(|f| f.0 < x1) {
            let length = PI * x1 * (x1 - x2);
            let sg = LacSegment::new(Point::ORIGIN, 0.0, length, Some(-1.0), 1.0, x2 / x1)
                .expect("valid");
            let phase = 0.5 * PI * x1 * x1;
            let (sp, cp) = phase.sin_cos();
            let (re, im) = (PI * x1 * (c1 - c2), -PI * x1 * (s1 - s2));
            let want = Point::new(cp * re - sp * im, sp * re + cp * im);
            let err = (sg.end() - want).hypot() / length;
            worst = worst.max(err);
            assert!(
                err <= TOL,
                "x1 {x1} x2 {x2}: {:?} vs {want:?}: {err:e}",
                sg.end()
            );
            assert!(
                (sg.theta1() - 0.5 * (length + length * x2 / x1)).abs() <= 1e-12 * (1.0 + phase)
            );
        }
    }
    println!("clothoid vs Fresnel: max error / length {worst:e}");
}

#[test]
fn circle_limit() {
    for (k, s) in [(0.7, 3.0), (-2.0, 10.0), (1e-8, 1e3)] {
        let arc = seg(s, None, k, k);
        for alpha in [-1.5, 0.0, 0.5, 1.0, 2.0] {
            for eps in [1e-6, 1e-10] {
                let lac = seg(s, Some(alpha), k, k * (1.0 - eps));
                let dev = (lac.end() - arc.end()).hypot() / s;
                // The curvature differs by at most ε|κ|, so the end moves by ≤ ε|κ|S²/2.
                assert!(
                    dev <= eps * k.abs() * s + 1e-14,
                    "κ {k} α {alpha} ε {eps}: {dev:e}"
                );
                assert!((lac.theta1() - arc.theta1()).abs() <= eps * (k * s).abs() + 1e-14);
            }
        }
        // The arc itself: chord length 2 sin(κS/2)/κ, |center − P| = 1/|κ| everywhere.
        let chord = (arc.end() - arc.start()).hypot();
        assert!((chord - 2.0 * (0.5 * k * s).sin().abs() / k.abs()).abs() <= TOL * s);
    }
}

/// α near 0 and near 1 is continuous with the exact α = 0 and α = 1 (no cancellation blow-up).
#[test]
fn alpha_near_special_values() {
    for (k0, k1, s) in [(2.0, 0.5, 3.0), (0.5, 2.0, 3.0), (1.0, 1e-20, 40.0)] {
        for center in [0.0, 1.0] {
            let exact = seg(s, Some(center), k0, k1);
            for eps in [1e-6, 1e-9, 1e-13] {
                for a in [center - eps, center + eps] {
                    let near = seg(s, Some(a), k0, k1);
                    // |dP/dα| ≤ S·(turning span), far below 1e3·S here.
                    let bound = 1e3 * eps * s + TOL * s;
                    assert!(
                        (near.end() - exact.end()).hypot() <= bound,
                        "α {a}: {:?} vs {:?}",
                        near.end(),
                        exact.end()
                    );
                    assert!((near.theta1() - exact.theta1()).abs() <= 1e3 * eps + TOL);
                    assert!(
                        (near.kappa(0.3 * s) / exact.kappa(0.3 * s) - 1.0).abs() <= 1e3 * eps + TOL
                    );
                }
            }
        }
    }
}

/// θ1 − θ0 = ∫₀ˢ κ(s) ds, with κ from the record's own evaluation.
#[test]
fn turning_is_integral_of_curvature() {
    for sg in zoo() {
        let (k0, k1) = (sg.kappa0(), sg.kappa1());
        let turning = sg.theta1() - sg.theta0();
        if sg.alpha().is_none() {
            // θ1 − θ0 re-rounds θ0 + κS: a few ulp of θ0.
            assert!((turning - k0 * sg.length()).abs() <= 1e-15);
        } else if k0 == 0.0 || k1 == 0.0 {
            // κ^{−α} linear down to 0: ∫κ = κ_end·S·α/(α − 1) (κ_end the nonzero one).
            let alpha = sg.alpha().expect("checked");
            let want = (k0 + k1) * sg.length() * alpha / (alpha - 1.0);
            assert!(
                (turning - want).abs() <= TOL * (1.0 + want.abs()),
                "{sg:?}: {turning} vs {want}"
            );
        } else {
            let want = graded_gl(|s| sg.kappa(s), 0.0, sg.length());
            assert!(
                (turning - want).abs() <= TOL * (1.0 + want.abs()),
                "{sg:?}: {turning} vs {want}"
            );
        }
        // θ(s) is continuous with θ0, θ1 at the ends.
        assert_eq!(sg.theta(0.0), sg.theta0());
        assert!((sg.theta(sg.length()) - sg.theta1()).abs() <= 1e-15 * (1.0 + turning.abs()));
        assert_eq!(sg.kappa(0.0), k0);
        assert_eq!(sg.kappa(sg.length()), k1);
    }
}

/// The point is the integral of the unit tangent: finite differences of P match e^{iθ}, and the
/// curvature is dθ/ds.
#[test]
fn point_theta_kappa_are_consistent() {
    for sg in zoo() {
        let len = sg.length();
        for f in [0.1, 0.5, 0.9] {
            let s = f * len;
            // Central differences: error ≈ h²/6·|P‴| with |P‴| ≲ κ² + |κ′|; h = 1e-5·min(S, ρ)
            // keeps it ≲ 1e-10 relative, roundoff ≈ 1e-16/h ≲ 1e-9.
            let h = 1e-5 * len.min(1.0 / sg.kappa(s).abs().max(1e-300));
            let d = (sg.point(s + h) - sg.point(s - h)) / (2.0 * h);
            let t = Vec2::new(sg.theta(s).cos(), sg.theta(s).sin());
            assert!((d - t).hypot() < 1e-7, "{sg:?} at {s}: {d:?} vs {t:?}");
            let dk = (sg.theta(s + h) - sg.theta(s - h)) / (2.0 * h);
            assert!(
                (dk - sg.kappa(s)).abs() <= 1e-6 * sg.kappa(s).abs() + 1e-12,
                "{sg:?} at {s}: {dk} vs {}",
                sg.kappa(s)
            );
        }
    }
}

/// The rendering fast path agrees with single-point evaluation.
#[test]
fn samples_agree_with_single_point_evaluation() {
    for sg in zoo() {
        let len = sg.length();
        for spacing in [len / 7.0, len / 1000.0, 2.0 * len] {
            let pts: Vec<_> = sg.samples(spacing).collect();
            let n = (len / spacing).ceil().max(1.0) as usize;
            assert_eq!(pts.len(), n + 1);
            assert_eq!(pts[0].point, sg.start());
            assert_eq!(pts[n].point, sg.end());
            for (i, p) in pts.iter().enumerate() {
                assert!((p.s - len * i as f64 / n as f64).abs() <= 1e-15 * len);
                let q = sg.sample(p.s);
                assert!(
                    (p.point - q.point).hypot() <= TOL * len,
                    "{sg:?} #{i}: {:?} vs {:?}",
                    p.point,
                    q.point
                );
                assert_eq!(p.theta, q.theta);
                assert_eq!(p.kappa, q.kappa);
            }
            for w in pts.windows(2) {
                assert!(w[1].s - w[0].s <= spacing * (1.0 + 1e-12));
            }
        }
    }
}

#[test]
fn json_record_round_trip() {
    let sg = seg(2.0, Some(-0.5), 0.4, 0.0);
    let json = serde_json::to_value(sg).expect("serialises");
    let obj = json.as_object().expect("object");
    let mut keys: Vec<_> = obj.keys().map(String::as_str).collect();
    keys.sort_unstable();
    assert_eq!(
        keys,
        [
            "alpha", "end", "kappa0", "kappa1", "length", "start", "theta0", "theta1"
        ]
    );
    assert_eq!(json["start"], serde_json::json!([0.3, -0.2]));
    assert_eq!(json["end"][0].as_f64(), Some(sg.end().x));
    let back: LacSegment = serde_json::from_value(json.clone()).expect("reads back");
    assert_eq!(back, sg);
    // Arcs write alpha = null; derived fields may be omitted on input.
    let arc = LacSegment::new(Point::ORIGIN, 0.0, 1.0, None, 0.5, 0.5).expect("valid");
    let arc = serde_json::to_value(arc).expect("serialises");
    assert!(arc["alpha"].is_null());
    let minimal = r#"{"start":[0,0],"theta0":0,"length":1,"alpha":null,"kappa0":0.5,"kappa1":0.5}"#;
    let m: LacSegment = serde_json::from_str(minimal).expect("derived fields optional");
    assert_eq!(serde_json::to_value(m).expect("serialises"), arc);
    // A stored end that disagrees with the parameters is rejected.
    let mut bad = json.clone();
    bad["end"][0] = serde_json::json!(sg.end().x + 1e-6);
    let err = serde_json::from_value::<LacSegment>(bad).expect_err("end mismatch");
    assert!(err.to_string().contains("`end`"), "{err}");
    let mut bad = json;
    bad["theta1"] = serde_json::json!(sg.theta1() + 1e-6);
    assert!(serde_json::from_value::<LacSegment>(bad).is_err());
}

#[test]
fn validation_errors() {
    let p = Point::ORIGIN;
    assert_eq!(
        LacSegment::new(p, 0.0, 0.0, None, 0.0, 0.0),
        Err(LacError::NonPositiveLength { length: 0.0 })
    );
    assert_eq!(
        LacSegment::new(p, f64::NAN, 1.0, None, 0.0, 0.0),
        Err(LacError::NotFinite { field: "theta0" })
    );
    assert_eq!(
        LacSegment::new(p, 0.0, 1.0, Some(f64::INFINITY), 1.0, 0.5),
        Err(LacError::NotFinite { field: "alpha" })
    );
    assert_eq!(
        LacSegment::new(p, 0.0, 1.0, Some(1.0), 1.0, -0.5),
        Err(LacError::OppositeCurvatureSigns {
            kappa0: 1.0,
            kappa1: -0.5
        })
    );
    assert_eq!(
        LacSegment::new(p, 0.0, 1.0, None, 1.0, 0.5),
        Err(LacError::MissingAlpha {
            kappa0: 1.0,
            kappa1: 0.5
        })
    );
    assert_eq!(
        LacSegment::new(p, 0.0, 1.0, Some(2.0), 0.5, 0.5),
        Err(LacError::AlphaOnConstantCurvature {
            kappa: 0.5,
            alpha: 2.0
        })
    );
    assert_eq!(
        LacSegment::new(p, 0.0, 1.0, Some(0.0), 0.5, 0.0),
        Err(LacError::ZeroCurvatureNeedsNegativeAlpha { alpha: 0.0 })
    );
    assert!(matches!(
        LacSegment::new(p, 0.0, 1.0, Some(30.0), 1e150, 1e-150),
        Err(LacError::CurvatureRatioOutOfRange { .. })
    ));
    let bad = r#"{"start":[0,0],"theta0":0,"length":-1,"alpha":null,"kappa0":0,"kappa1":0}"#;
    assert!(serde_json::from_str::<LacSegment>(bad).is_err());
}
