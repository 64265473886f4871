//! Synthetic strokes with known answers, and fixture loading by name.
#![allow(dead_code)]

pub mod adversarial;
pub mod browser;
pub mod export;
pub mod http;
pub mod lac;
pub mod loops;
pub mod planted;

use kansei::geom::Point;
use kansei::stroke::{Sample, Stroke, StrokeFile};

/// A small deterministic generator (the adversarial generator's SplitMix64), so noisy strokes
/// are the same on every run.
pub struct Rng(adversarial::SplitMix);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(adversarial::SplitMix::new(seed))
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }
    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0.unit()
    }
    /// Standard normal (Box–Muller).
    pub fn normal(&mut self) -> f64 {
        let u1 = self.uniform().max(1e-300);
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }
}

/// Samples `f(s)` for `n + 1` evenly spaced `s` in [a, b], with Gaussian noise of deviation
/// `sigma` on each coordinate.
pub fn sample_curve(
    f: impl Fn(f64) -> Point,
    a: f64,
    b: f64,
    n: usize,
    sigma: f64,
    seed: u64,
) -> Stroke {
    let mut rng = Rng::new(seed);
    let samples = (0..=n)
        .map(|i| {
            let s = a + (b - a) * i as f64 / n as f64;
            let p = f(s);
            let x = p.x + sigma * rng.normal();
            let y = p.y + sigma * rng.normal();
            Sample::new(x, y).with_t(i as f64 * 0.005)
        })
        .collect();
    Stroke::new(samples)
}

/// The S-curve y = 20·sin(x/40), x ∈ [−48, 48] mm: one inflection at the origin, |κ| monotonic
/// on each side (its maxima are at x = ±20π ≈ ±62.8, outside the range).
pub fn s_curve(x: f64) -> Point {
    Point::new(x, 20.0 * (x / 40.0).sin())
}

/// The ellipse arc (50 cos t, 20 sin t), t ∈ [−1, 1]: one curvature maximum, at (50, 0).
pub fn ellipse(t: f64) -> Point {
    Point::new(50.0 * t.cos(), 20.0 * t.sin())
}

/// Rotates by `angle`, scales by `scale`, then translates by `shift`.
pub fn transform(stroke: &Stroke, angle: f64, scale: f64, shift: (f64, f64)) -> Stroke {
    let (s, c) = angle.sin_cos();
    Stroke::new(
        stroke
            .samples
            .iter()
            .map(|p| {
                let mut q = *p;
                q.x = scale * (c * p.x - s * p.y) + shift.0;
                q.y = scale * (s * p.x + c * p.y) + shift.1;
                q
            })
            .collect(),
    )
}

/// The fixture stroke files, by name (`fixtures/strokes/<name>.json`).
pub fn fixture(name: &str) -> StrokeFile {
    let path = format!(
        "{}/fixtures/strokes/{name}.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    StrokeFile::from_json(&text).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// Every fixture stroke file's name.
pub fn fixture_names() -> Vec<String> {
    json_stems("strokes")
}

/// The synthetic stroke files (`fixtures/synthetic/`), each read: name and file.
pub fn synthetic_fixtures() -> Vec<(String, StrokeFile)> {
    json_stems("synthetic")
        .into_iter()
        .map(|name| {
            let path = format!(
                "{}/fixtures/synthetic/{name}.json",
                env!("CARGO_MANIFEST_DIR")
            );
            let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
            let file = StrokeFile::from_json(&text).unwrap_or_else(|e| panic!("{path}: {e}"));
            (name, file)
        })
        .collect()
}

/// The stems of the `.json` files of `fixtures/<folder>`, sorted.
fn json_stems(folder: &str) -> Vec<String> {
    let dir = format!("{}/fixtures/{folder}", env!("CARGO_MANIFEST_DIR"));
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{dir}: {e}"))
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .filter_map(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .collect();
    names.sort();
    names
}

/// Runs a command to completion and asserts that it succeeded, showing its stderr if not.
pub fn run_ok(command: &mut std::process::Command) -> std::process::Output {
    let out = command.output().expect("the command runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}
