//! LAC evaluation against the high-precision reference tables in
//! `fixtures/lac-reference/` (30-digit mpmath, see `lac_reference.md` there).
//!
//! Every row (α, Λ, s, x, y, θ, κ) of the standard form (origin, tangent +x, ρ(0) = 1) is mapped
//! onto a canonical record: start (0, 0), θ0 = 0, length s, κ0 = 1, κ1 = κ(s). Positions must agree
//! to 1e-12 of the length, θ to 1e-12 rad, κ to 1e-12 relative.

use kansei::geom::Point;
use kansei::lac::{LacSegment, StandardLac};
use serde_json::Value;
use std::f64::consts::PI;

const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/lac-reference/");

/// The accuracy the evaluator promises, relative to the length (positions), in radians (θ) and
/// relative (κ).
const TOL: f64 = 1e-12;

#[derive(Clone, Copy, Debug)]
struct Row {
    alpha: f64,
    lambda: f64,
    s: f64,
    x: f64,
    y: f64,
    theta: f64,
    kappa: f64,
}

fn load(name: &str) -> Vec<Row> {
    let path = format!("{DATA_DIR}{name}");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "LAC reference data {path} is missing ({e}). It ships in the \
             repository (fixtures/lac-reference/)."
        )
    });
    let v: Value = serde_json::from_str(&text).expect("reference table is valid JSON");
    let f = |r: &Value, k: &str| r[k].as_f64().unwrap_or_else(|| panic!("field {k} in {r}"));
    v.as_array()
        .expect("table is a JSON array")
        .iter()
        .map(|r| Row {
            alpha: f(r, "alpha"),
            lambda: f(r, "lambda"),
            s: f(r, "s"),
            x: f(r, "x"),
            y: f(r, "y"),
            theta: f(r, "theta"),
            kappa: f(r, "kappa"),
        })
        .collect()
}

fn rel_kappa_err(got: f64, want: f64) -> f64 {
    if want == 0.0 {
        got.abs()
    } else {
        ((got - want) / want).abs()
    }
}

#[derive(Default, Debug)]
struct Worst {
    pos: f64,
    theta: f64,
    kappa: f64,
}

impl Worst {
    fn add(&mut self, what: &str, row: &Row, length: f64, p: Point, theta: f64, kappa: f64) {
        let ep = (p - Point::new(row.x, row.y)).hypot() / length;
        let et = (theta - row.theta).abs();
        let ek = rel_kappa_err(kappa, row.kappa);
        assert!(
            ep <= TOL && et <= TOL && ek <= TOL,
            "{what}: row {row:?}: got ({}, {}), θ {theta}, κ {kappa}: errors pos/len {ep:e}, θ {et:e}, κ {ek:e}",
            p.x,
            p.y
        );
        self.pos = self.pos.max(ep);
        self.theta = self.theta.max(et);
        self.kappa = self.kappa.max(ek);
    }
}

/// The segment record of the standard form over [0, row.s].
fn row_segment(row: &Row) -> LacSegment {
    LacSegment::new(Point::ORIGIN, 0.0, row.s, Some(row.alpha), 1.0, row.kappa)
        .unwrap_or_else(|e| panic!("row {row:?}: {e}"))
}

fn check_table(name: &str) -> (Worst, usize) {
    let rows = load(name);
    let mut worst = Worst::default();
    let mut n = 0;
    // 1. One record per row: its derived end and θ1.
    for row in rows.iter().filter(|r| r.s > 0.0) {
        let seg = row_segment(row);
        worst.add(
            "record end",
            row,
            row.s,
            seg.end(),
            seg.theta1(),
            seg.kappa(row.s),
        );
        n += 1;
    }
    // 2. Per (α, Λ): one record over the longest s, evaluated at every row's s; and the standard
    //    form itself.
    let mut i = 0;
    while i < rows.len() {
        let (a, l) = (rows[i].alpha, rows[i].lambda);
        let group: Vec<Row> = rows[i..]
            .iter()
            .take_while(|r| r.alpha == a && r.lambda == l)
            .copied()
            .collect();
        i += group.len();
        let last = group.last().expect("group is not empty");
        let seg = row_segment(last);
        let std = StandardLac::new(a, l).expect("valid standard form");
        for row in &group {
            let smp = seg.sample(row.s);
            worst.add(
                "record interior",
                row,
                last.s,
                smp.point,
                smp.theta,
                smp.kappa,
            );
            worst.add(
                "standard form",
                row,
                last.s,
                std.point(row.s),
                std.theta(row.s),
                std.kappa(row.s),
            );
        }
        // 3. The same records read backwards (curvature increasing along travel, sign flipped).
        for row in group.iter().filter(|r| r.s > 0.0) {
            let rev = LacSegment::new(
                Point::new(row.x, row.y),
                row.theta + PI,
                row.s,
                Some(a),
                -row.kappa,
                -1.0,
            )
            .expect("reversed record is valid");
            let origin = Row {
                x: 0.0,
                y: 0.0,
                theta: 0.0,
                kappa: 1.0,
                ..*row
            };
            worst.add(
                "reversed end",
                &origin,
                row.s,
                rev.end(),
                rev.theta1() - PI,
                -rev.kappa1(),
            );
            for inner in group.iter().filter(|r| r.s <= row.s) {
                let smp = rev.sample(row.s - inner.s);
                worst.add(
                    "reversed interior",
                    inner,
                    row.s,
                    smp.point,
                    smp.theta - PI,
                    -smp.kappa,
                );
            }
        }
    }
    (worst, n)
}

#[test]
fn lambda_one_table() {
    let (w, n) = check_table("lac_reference.json");
    assert_eq!(n, 170, "179 rows minus 9 at s = 0");
    println!("lac_reference.json: max errors {w:?}");
}

#[test]
fn stress_table() {
    let (w, n) = check_table("lac_reference_stress.json");
    assert_eq!(n, 90);
    println!("lac_reference_stress.json: max errors {w:?}");
}

/// Rigid motions and mirroring of the record move the curve rigidly.
#[test]
fn invariance_under_rigid_motion_and_mirror() {
    let rows = load("lac_reference_stress.json");
    for row in rows.iter().filter(|r| r.s > 0.0) {
        let base = row_segment(row);
        let (x0, y0, phi) = (3.5, -1.25, 2.2);
        let moved = LacSegment::new(
            Point::new(x0, y0),
            phi,
            row.s,
            Some(row.alpha),
            1.0,
            row.kappa,
        )
        .expect("valid");
        let mirrored = LacSegment::new(
            Point::new(x0, y0),
            phi,
            row.s,
            Some(row.alpha),
            -1.0,
            -row.kappa,
        )
        .expect("valid");
        let (sp, cp) = phi.sin_cos();
        for k in 0..=8 {
            let s = row.s * k as f64 / 8.0;
            let p = base.point(s).to_vec2();
            let want = Point::new(x0 + cp * p.x - sp * p.y, y0 + sp * p.x + cp * p.y);
            assert!(
                (moved.point(s) - want).hypot() <= TOL * row.s,
                "{row:?} s={s}"
            );
            assert!((moved.theta(s) - phi - base.theta(s)).abs() <= TOL);
            let wantm = Point::new(x0 + cp * p.x + sp * p.y, y0 + sp * p.x - cp * p.y);
            assert!(
                (mirrored.point(s) - wantm).hypot() <= TOL * row.s,
                "{row:?} s={s}"
            );
            assert!((mirrored.theta(s) - phi + base.theta(s)).abs() <= TOL);
            assert_eq!(mirrored.kappa(s), -base.kappa(s));
        }
        // Scaling by c: P′(s′) = c·P(s′/c), κ′ = κ/c.
        let c = 7.0;
        let scaled = LacSegment::new(
            Point::ORIGIN,
            0.0,
            c * row.s,
            Some(row.alpha),
            1.0 / c,
            row.kappa / c,
        )
        .expect("valid");
        let want = Point::new(c * row.x, c * row.y);
        assert!((scaled.end() - want).hypot() <= TOL * c * row.s, "{row:?}");
        assert!((scaled.theta1() - row.theta).abs() <= TOL);
    }
}
