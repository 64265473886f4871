//! Shapes that come back near themselves, drawn as a pen or a mouse would, with their truth: the
//! closed and self-crossing strokes of issue 44 (circles, ellipses, superellipses and smooth
//! blobs from 0.9 to 2 turns, figure eights open and closed, cursive loops, spirals), judged
//! against the shape they were drawn from, not their samples.

use std::f64::consts::{PI, TAU};

use kansei::chain::Chain;
use kansei::geom::Point;
use kansei::lac::LacSegment;
use kansei::stroke::{Sample, Stroke, Units};

use super::Rng;
use super::adversarial::polyline_distance;

/// The shape classes, in the order [`shapes`] draws them.
pub const CLASSES: [&str; 8] = [
    "circle",
    "ellipse",
    "superellipse",
    "blob",
    "eight-open",
    "eight-closed",
    "cursive",
    "spiral",
];

/// One drawn shape: its truth as a dense polyline with the curvature at each point, and its
/// samples.
pub struct Shape {
    /// `<class>-<i>-<kind>`.
    pub name: String,
    /// One of [`CLASSES`].
    pub class: &'static str,
    /// Points of the shape every small step of arc length, with their signed curvature.
    pub truth: Vec<(Point, f64)>,
    /// The samples.
    pub stroke: Stroke,
    /// Px for the mouse, mm for the tablet.
    pub units: Units,
    /// Whether the shape returns to its start (a closed curve was meant).
    pub closed: bool,
    /// Total turning of the shape, in turns.
    pub turns: f64,
}

/// A plane curve on a parameter interval.
type Curve = Box<dyn Fn(f64) -> Point>;

/// The curve `f` of `class` on `[0, t1]`, from `rng`, with whether it is closed and its turns.
fn draw(class: &str, rng: &mut Rng) -> (Curve, f64, bool) {
    let centre = Point::new(400.0, 300.0);
    let phase = rng.uniform() * TAU;
    let turns = 0.9 + 1.1 * rng.uniform();
    match class {
        "circle" => {
            let r = 40.0 + 110.0 * rng.uniform();
            let f = move |t: f64| {
                centre + kurbo::Vec2::new(r * (t + phase).cos(), r * (t + phase).sin())
            };
            (Box::new(f), TAU * turns, turns >= 1.0)
        }
        "ellipse" => {
            let a = 60.0 + 90.0 * rng.uniform();
            let b = a * (0.4 + 0.4 * rng.uniform());
            let f = move |t: f64| centre + kurbo::Vec2::new(a * t.cos(), b * t.sin());
            (Box::new(f), TAU * turns, turns >= 1.0)
        }
        "superellipse" => {
            let a = 60.0 + 90.0 * rng.uniform();
            let b = a * (0.6 + 0.4 * rng.uniform());
            // |x/a|^4 + |y/b|^4 = 1: flat sides, rounded corners.
            let e = 0.5;
            let f = move |t: f64| {
                let (c, s) = (t.cos(), t.sin());
                centre
                    + kurbo::Vec2::new(
                        a * c.signum() * c.abs().powf(e),
                        b * s.signum() * s.abs().powf(e),
                    )
            };
            let turns = 0.95 + 0.35 * rng.uniform();
            (Box::new(f), TAU * turns, turns >= 1.0)
        }
        "blob" => {
            let r = 60.0 + 60.0 * rng.uniform();
            let (c, d) = (rng.uniform() * TAU, rng.uniform() * TAU);
            let f = move |t: f64| {
                let rr = r * (1.0 + 0.12 * (2.0 * t + c).sin() + 0.06 * (3.0 * t + d).sin());
                centre + kurbo::Vec2::new(rr * t.cos(), rr * t.sin())
            };
            (Box::new(f), TAU * turns, turns >= 1.0)
        }
        "eight-open" | "eight-closed" => {
            let a = 100.0 + 60.0 * rng.uniform();
            let b = a * (0.5 + 0.3 * rng.uniform());
            // Gerono's lemniscate from its crossing, turning through both lobes.
            let f = move |t: f64| centre + kurbo::Vec2::new(a * t.sin(), b * t.sin() * t.cos());
            let closed = class == "eight-closed";
            let end = if closed {
                TAU * (1.0 + 0.04 * rng.uniform())
            } else {
                TAU * (0.75 + 0.15 * rng.uniform())
            };
            // Start a little after the crossing, where the curvature is not zero.
            (Box::new(move |t| f(t + 0.3)), end, closed)
        }
        "cursive" => {
            // A prolate cycloid: the loops of a cursive "l" or "e", one to three of them.
            let a = 20.0 + 10.0 * rng.uniform();
            let b = a * (1.5 + 0.5 * rng.uniform());
            let loops = 1.0 + (rng.uniform() * 2.99).floor();
            let f = move |t: f64| {
                Point::new(
                    200.0 + a * t - b * (t - PI / 2.0).sin(),
                    300.0 - b * (t - PI / 2.0).cos(),
                )
            };
            (Box::new(f), TAU * loops + PI, false)
        }
        "spiral" => {
            let r0 = 15.0 + 15.0 * rng.uniform();
            let c = 6.0 + 6.0 * rng.uniform();
            let turns = 1.5 + rng.uniform();
            let f = move |t: f64| {
                let r = r0 + c * t;
                centre + kurbo::Vec2::new(r * (t + phase).cos(), r * (t + phase).sin())
            };
            (Box::new(f), TAU * turns, false)
        }
        other => panic!("no class {other}"),
    }
}

/// Dense points of `f` on `[0, t1]` with their curvature (central differences of `f`).
fn dense(f: &Curve, t1: f64) -> Vec<(Point, f64)> {
    let n = 4000;
    let h = 1e-4;
    (0..=n)
        .map(|i| {
            let t = t1 * i as f64 / n as f64;
            let (p0, p, p1) = (f(t - h), f(t), f(t + h));
            let d1 = (p1 - p0) / (2.0 * h);
            let d2 = ((p1 - p) - (p - p0)) / (h * h);
            let k = (d1.x * d2.y - d1.y * d2.x) / d1.hypot().powi(3);
            (p, k)
        })
        .collect()
}

/// `truth` resampled at a pen's speed: a step along the curve of about `step`, slower (shorter
/// steps) where it bends, varying along the stroke as a hand's speed does.
fn resample(truth: &[(Point, f64)], step: f64, rng: &mut Rng) -> Vec<Point> {
    let phase = rng.uniform() * TAU;
    let mut out = vec![truth[0].0];
    let mut travelled = 0.0;
    let mut next = step;
    let total: f64 = truth.windows(2).map(|w| w[0].0.distance(w[1].0)).sum();
    for w in truth.windows(2) {
        let d = w[0].0.distance(w[1].0);
        travelled += d;
        if travelled >= next {
            out.push(w[1].0);
            let speed = (0.75 + 0.25 * (TAU * 2.0 * travelled / total + phase).sin())
                / (1.0 + 10.0 * w[1].1.abs() * step);
            next = travelled + step * speed.max(0.2);
        }
    }
    if let Some(last) = truth.last()
        && out.last().is_some_and(|p| p.distance(last.0) > 0.2 * step)
    {
        out.push(last.0);
    }
    out
}

/// `per_class` shapes of every class from `seed`, each drawn twice: with a mouse (whole
/// pixels, a sample every 2 to 4 px) and on a tablet (in mm at 0.1 mm a pixel, a sample every
/// 0.3 mm, 0.02 mm of Gaussian noise).
pub fn shapes(per_class: usize, seed: u64) -> Vec<Shape> {
    let mut rng = Rng::new(seed);
    let mut out = Vec::new();
    for class in CLASSES {
        for i in 0..per_class {
            let (f, t1, closed) = draw(class, &mut rng);
            let truth = dense(&f, t1);
            let turning: f64 = {
                let angles: Vec<f64> = truth
                    .windows(2)
                    .map(|w| (w[1].0.y - w[0].0.y).atan2(w[1].0.x - w[0].0.x))
                    .collect();
                angles
                    .windows(2)
                    .map(|w| kansei::geom::wrap_angle(w[1] - w[0]))
                    .sum::<f64>()
                    .abs()
                    / TAU
            };
            let mouse_step = 2.0 + 2.0 * rng.uniform();
            let mouse: Vec<Point> = resample(&truth, mouse_step, &mut rng)
                .into_iter()
                .map(|p| Point::new(p.x.round(), p.y.round()))
                .collect();
            out.push(shape(
                format!("{class}-{i}-mouse"),
                class,
                truth.clone(),
                &mouse,
                Units::Px,
                closed,
                turning,
            ));
            let mm: Vec<(Point, f64)> = truth
                .iter()
                .map(|&(p, k)| (Point::new(0.1 * p.x, 0.1 * p.y), k / 0.1))
                .collect();
            let tablet: Vec<Point> = resample(&mm, 0.3, &mut rng)
                .into_iter()
                .map(|p| Point::new(p.x + 0.02 * rng.normal(), p.y + 0.02 * rng.normal()))
                .collect();
            out.push(shape(
                format!("{class}-{i}-tablet"),
                class,
                mm,
                &tablet,
                Units::Mm,
                closed,
                turning,
            ));
        }
    }
    out
}

fn shape(
    name: String,
    class: &'static str,
    truth: Vec<(Point, f64)>,
    points: &[Point],
    units: Units,
    closed: bool,
    turns: f64,
) -> Shape {
    let samples = points
        .iter()
        .enumerate()
        .map(|(k, p)| Sample::new(p.x, p.y).with_t(k as f64 * 0.008))
        .collect();
    Shape {
        name,
        class,
        truth,
        stroke: Stroke::new(samples),
        units,
        closed,
        turns,
    }
}

/// The shape's truth as its fit should follow it: one round of a closed shape drawn past its
/// start where the fit came back closed (`closed_fit`: the rounds after the first are folded
/// onto it, and the closed curve is one round long), else all of it.
pub fn truth_for(shape: &Shape, closed_fit: bool) -> Vec<(Point, f64)> {
    let periodic = matches!(shape.class, "circle" | "ellipse" | "superellipse" | "blob");
    if !(closed_fit && periodic && shape.turns > 1.0) {
        return shape.truth.clone();
    }
    // One round: where the shape has turned a whole turn (an ellipse's length per turn is not
    // even, so a share of the length would not do).
    let mut turned = 0.0;
    let mut out = vec![shape.truth[0], shape.truth[1]];
    for w in shape.truth.windows(3) {
        let (a, b) = (w[1].0 - w[0].0, w[2].0 - w[1].0);
        turned += a.cross(b).atan2(a.dot(b));
        if turned.abs() > std::f64::consts::TAU {
            break;
        }
        out.push(w[2]);
    }
    out
}

/// Points of the chains' segments every `step` of arc length, with their curvature.
pub fn chain_points(chains: &[Chain], step: f64) -> Vec<(Point, f64)> {
    let segments: Vec<LacSegment> = chains
        .iter()
        .flat_map(|c| c.segments.iter().map(|s| s.segment))
        .collect();
    super::planted::dense(segments, step)
}

/// The points of a dense polyline with curvatures.
fn points(line: &[(Point, f64)]) -> Vec<Point> {
    line.iter().map(|p| p.0).collect()
}

/// The largest distance from the samples of `stroke` to the shape: how far the drawing itself
/// strays from the shape (a mouse's rounding, a tablet's noise), which the chain, within the
/// tolerance of the samples, may add to its own distance from the shape.
pub fn sample_error(stroke: &kansei::stroke::Stroke, truth: &[(Point, f64)]) -> f64 {
    let truth = points(truth);
    stroke
        .samples
        .iter()
        .map(|s| polyline_distance(s.point(), &truth))
        .fold(0.0, f64::max)
}

/// The largest distance from the chains to the truth and from the truth to the chains.
pub fn two_way_distance(chains: &[Chain], truth: &[(Point, f64)]) -> (f64, f64) {
    let length: f64 = truth.windows(2).map(|w| w[0].0.distance(w[1].0)).sum();
    let fitted = chain_points(chains, length / 3000.0);
    let (truth_line, fitted_line) = (points(truth), points(&fitted));
    let there = fitted
        .iter()
        .map(|p| polyline_distance(p.0, &truth_line))
        .fold(0.0, f64::max);
    let back = truth
        .iter()
        .step_by(2)
        .map(|p| polyline_distance(p.0, &fitted_line))
        .fold(0.0, f64::max);
    (there, back)
}

/// The curvature profile's error: mean |κ_fit − κ_true| over mean |κ_true| along the shape, κ_fit
/// taken at the chain's point matched to each point of the shape in order (the nearest point
/// within a window ahead of the last match: a loop's other pass is never its own).
pub fn profile_error(chains: &[Chain], truth: &[(Point, f64)]) -> f64 {
    let length: f64 = truth.windows(2).map(|w| w[0].0.distance(w[1].0)).sum();
    let fitted = chain_points(chains, length / 8000.0);
    if fitted.is_empty() {
        return f64::INFINITY;
    }
    // A window of a twentieth of the chain: far more than the chain moves ahead per point of
    // the shape, far less than a loop.
    let window = (fitted.len() / 20).max(2);
    let (mut diff, mut scale, mut j) = (0.0, 0.0, 0usize);
    for &(p, k) in truth.iter().step_by(2) {
        let end = (j + window).min(fitted.len());
        let (_, best) = (j..end)
            .map(|m| (fitted[m].0.distance(p), m))
            .fold((f64::INFINITY, j), |a, b| if b.0 < a.0 { b } else { a });
        j = best;
        diff += (fitted[j].1 - k).abs();
        scale += k.abs();
    }
    diff / scale
}
