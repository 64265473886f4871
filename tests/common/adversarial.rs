//! Small adversarial strokes, as a browser pen on a whole-pixel grid draws them, and an
//! independent check of what the pipeline makes of them.
//!
//! Self-contained (no `super::` items): the `fit_stroke` fuzz target includes this file by path.
//!
//! The generator is deterministic (SplitMix64 from a seed). Its classes are the ones that broke
//! the pipeline on real handwriting: pixel-grid random walks, exact reversals along a line (out
//! and back, once or several times), zigzags, jiggle in place (moves within 1–2 px), small
//! circles (radius 2–20 px) rounded to whole pixels, near-duplicate samples (differences of
//! 1e-12 relative), collinear runs, and strokes of very few distinct points (2 to 5). Most cases
//! are in px at the default 0.5 px; some are scaled to mm at 0.1 mm, some use other tolerances.
//!
//! [`check`] measures each represented sample's distance to its own segment (the honest measure:
//! the segment whose range holds it, or one next to it at a joint; see
//! [`own_segment_deviation`]), by evaluating every segment densely (see [`chain_polyline`] for
//! the bound), and checks the report against
//! it: the chain's `within_tolerance` and `max_deviation`, the segments' ranges tiling their
//! piece, and every α accounted for by its record (`alpha_source`: a search's pick is the
//! search's answer; no α without a source, no source without an α).
#![allow(dead_code)]

use kansei::chain::AlphaSource;
use kansei::geom::Point;
use kansei::lac::LacSegment;
use kansei::pipeline::{CurveFit, PipelineError};
use kansei::stroke::{Sample, Stroke, Units};

/// SplitMix64.
pub struct SplitMix(u64);

impl SplitMix {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Self {
        SplitMix(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform integer in `lo..=hi`.
    pub fn int(&mut self, lo: i64, hi: i64) -> i64 {
        lo + (self.next_u64() % (hi - lo + 1) as u64) as i64
    }

    /// Uniform in `lo..hi`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}

/// The classes of the generator.
pub const CLASSES: [&str; 8] = [
    "pixel-grid",
    "reversal",
    "zigzag",
    "jiggle",
    "circle",
    "near-duplicate",
    "collinear",
    "few-distinct",
];

/// One generated stroke and the tolerance to fit it to.
#[derive(Clone, Debug)]
pub struct Case {
    /// Class (one of [`CLASSES`]) and number within it.
    pub name: String,
    /// The stroke.
    pub stroke: Stroke,
    /// Its units.
    pub units: Units,
    /// Fitting tolerance.
    pub tolerance: f64,
}

/// Integer directions for lines on the pixel grid.
const DIRECTIONS: [(i64, i64); 8] = [
    (1, 0),
    (0, 1),
    (1, 1),
    (1, -1),
    (2, 1),
    (1, 2),
    (3, -1),
    (-2, 3),
];

/// Points of one stroke of class `class` (whole-pixel coordinates except the near-duplicates).
pub fn points_of(class: &str, rng: &mut SplitMix) -> Vec<Point> {
    let origin = (rng.int(50, 900) as f64, rng.int(50, 700) as f64);
    let at = |x: f64, y: f64| Point::new(origin.0 + x, origin.1 + y);
    let n = rng.int(20, 45) as usize;
    let mut pts = Vec::with_capacity(n);
    match class {
        "pixel-grid" => {
            let (mut x, mut y) = (0i64, 0i64);
            // A walk with a drift, so it goes somewhere, and steps of 0 to 2 px.
            let drift = DIRECTIONS[rng.int(0, 7) as usize];
            for _ in 0..n {
                pts.push(at(x as f64, y as f64));
                if rng.unit() < 0.4 {
                    x += drift.0.signum();
                    y += drift.1.signum();
                } else {
                    x += rng.int(-1, 1) * rng.int(1, 2);
                    y += rng.int(-1, 1);
                }
            }
        }
        "reversal" => {
            let d = DIRECTIONS[rng.int(0, 7) as usize];
            let length = rng.int(3, 20);
            let reversals = rng.int(1, 4);
            let step = rng.int(1, 2);
            let mut k = 0i64;
            let mut dir = step;
            let mut turns = 0;
            while turns <= reversals && pts.len() < 4 * n {
                pts.push(at((k * d.0) as f64, (k * d.1) as f64));
                // Sometimes the pen rests at the apex.
                if (k == length || (k == 0 && turns > 0)) && rng.unit() < 0.3 {
                    pts.push(at((k * d.0) as f64, (k * d.1) as f64));
                }
                k += dir;
                if k >= length || k <= 0 {
                    k = k.clamp(0, length);
                    dir = -dir;
                    turns += 1;
                }
            }
            pts.push(at((k * d.0) as f64, (k * d.1) as f64));
        }
        "zigzag" => {
            let amplitude = rng.int(1, 6) as f64;
            let period = rng.int(2, 6) as usize;
            let dx = rng.int(1, 3) as f64;
            for i in 0..n {
                let phase = (i % period) as f64 / period as f64;
                let y = if phase < 0.5 { amplitude } else { -amplitude };
                pts.push(at(i as f64 * dx, y.round()));
            }
        }
        "jiggle" => {
            let reach = rng.int(1, 2);
            for _ in 0..n {
                pts.push(at(
                    rng.int(-reach, reach) as f64,
                    rng.int(-reach, reach) as f64,
                ));
            }
            // Half of them then leave in a short line.
            if rng.unit() < 0.5 {
                let d = DIRECTIONS[rng.int(0, 7) as usize];
                for k in 1..rng.int(3, 12) {
                    pts.push(at((k * d.0) as f64, (k * d.1) as f64));
                }
            }
        }
        "circle" => {
            let r = rng.range(2.0, 20.0);
            let turn = rng.range(0.5, 1.2) * std::f64::consts::TAU;
            let a0 = rng.range(0.0, std::f64::consts::TAU);
            for i in 0..n {
                let a = a0 + turn * i as f64 / (n - 1) as f64;
                pts.push(at((r * a.cos()).round(), (r * a.sin()).round()));
            }
        }
        "near-duplicate" => {
            // A smooth arc or line, each sample followed by copies moved by ~1e-12 relative.
            let r = rng.range(10.0, 200.0);
            let turn = rng.range(0.0, 2.0);
            for i in 0..n {
                let t = i as f64 / (n - 1) as f64;
                let p = if turn < 0.3 {
                    at(60.0 * t, 0.0)
                } else {
                    let a = turn * t;
                    at(r * a.sin(), r * (1.0 - a.cos()))
                };
                pts.push(p);
                for _ in 0..rng.int(0, 3) {
                    let e = 1e-12 * p.x.abs().max(p.y.abs()) * rng.range(0.1, 3.0);
                    pts.push(Point::new(p.x + e, p.y - e * rng.unit()));
                }
            }
        }
        "collinear" => {
            // Runs along a line with uneven spacing, one or two turns between runs.
            let runs = rng.int(1, 3);
            let (mut x, mut y) = (0i64, 0i64);
            for _ in 0..runs {
                let d = DIRECTIONS[rng.int(0, 7) as usize];
                for _ in 0..n / runs as usize {
                    pts.push(at(x as f64, y as f64));
                    let k = rng.int(0, 3);
                    x += k * d.0;
                    y += k * d.1;
                }
            }
            pts.push(at(x as f64, y as f64));
        }
        "few-distinct" => {
            let m = rng.int(2, 5) as usize;
            let spots: Vec<Point> = (0..m)
                .map(|_| at(rng.int(-6, 6) as f64, rng.int(-6, 6) as f64))
                .collect();
            // In order, each repeated, sometimes visiting an earlier spot again.
            for (i, p) in spots.iter().enumerate() {
                for _ in 0..rng.int(1, 6) {
                    pts.push(*p);
                }
                if i > 0 && rng.unit() < 0.3 {
                    pts.push(spots[rng.int(0, i as i64 - 1) as usize]);
                }
            }
        }
        other => panic!("no class {other}"),
    }
    pts
}

/// `per_class` cases of every class from `seed`: 70 % in px at 0.5, 10 % scaled to mm
/// (1 px = 0.1 mm) at 0.1 mm, the rest in px at 0.25, 1 or 2.
pub fn cases(per_class: usize, seed: u64) -> Vec<Case> {
    let mut rng = SplitMix::new(seed);
    let mut out = Vec::new();
    for class in CLASSES {
        for i in 0..per_class {
            let pts = points_of(class, &mut rng);
            let pick = rng.unit();
            let (units, tolerance, scale) = if pick < 0.7 {
                (Units::Px, 0.5, 1.0)
            } else if pick < 0.8 {
                (Units::Mm, 0.1, 0.1)
            } else {
                let t = [0.25, 1.0, 2.0][rng.int(0, 2) as usize];
                (Units::Px, t, 1.0)
            };
            let samples = pts
                .iter()
                .enumerate()
                .map(|(k, p)| Sample::new(p.x * scale, p.y * scale).with_t(k as f64 * 0.008))
                .collect();
            out.push(Case {
                name: format!("{class}-{i}"),
                stroke: Stroke::new(samples),
                units,
                tolerance,
            });
        }
    }
    out
}

/// What [`check`] found wrong with one stroke's fit.
#[derive(Clone, Debug, Default)]
pub struct Breaks {
    /// The pipeline returned an error (its message).
    pub error: Option<String>,
    /// A curve says `within_tolerance` while a sample is farther than the tolerance, or its
    /// `max_deviation` is not the true largest distance (messages).
    pub guarantee: Vec<String>,
    /// Curves that miss the tolerance and say so (not a break: reported honestly).
    pub reported_misses: usize,
    /// Segment ranges that do not tile their piece (messages).
    pub tiling: Vec<String>,
    /// Segments whose α its record does not account for (messages): an α without a source, a
    /// source without an α, or a search's pick that is not the search's answer.
    pub unsourced: Vec<String>,
}

impl Breaks {
    /// Whether nothing broke.
    pub fn ok(&self) -> bool {
        self.error.is_none()
            && self.guarantee.is_empty()
            && self.tiling.is_empty()
            && self.unsourced.is_empty()
    }
}

/// Chord error of the dense evaluation, as a fraction of the tolerance.
pub const CHECK_CHORD_FRACTION: f64 = 1e-3;

/// Most points per segment in the dense evaluation (the bound is then coarser, and stated).
const MAX_POINTS_PER_SEGMENT: usize = 20_000;

/// The chain's segments as one polyline per segment, with the largest distance `δ` between the
/// polyline and the curve: vertices are exact points of the segment ([`LacSegment::point`]),
/// spaced `h` apart in arc length, and a curve of curvature at most κ (a log-aesthetic segment's
/// |κ| is monotonic, so κ = max(|κ0|, |κ1|)) stays within κh²/8 of the chord of an arc of length
/// h. So for any point q, |dist(q, polyline) − dist(q, curve)| ≤ δ.
pub fn chain_polyline(segments: &[&LacSegment], chord: f64) -> (Vec<Vec<Point>>, f64) {
    let mut delta: f64 = 0.0;
    let lines = segments
        .iter()
        .map(|seg| {
            let kappa = seg.kappa0().abs().max(seg.kappa1().abs());
            let length = seg.length();
            let h = if kappa > 0.0 {
                (8.0 * chord / kappa).sqrt()
            } else {
                length
            };
            let n = ((length / h).ceil() as usize).clamp(1, MAX_POINTS_PER_SEGMENT);
            let h = length / n as f64;
            delta = delta.max(kappa * h * h / 8.0);
            (0..=n)
                .map(|i| seg.point(length * i as f64 / n as f64))
                .collect()
        })
        .collect();
    (lines, delta)
}

/// Distance from `q` to a polyline.
pub fn polyline_distance(q: Point, line: &[Point]) -> f64 {
    if line.len() == 1 {
        return q.distance(line[0]);
    }
    line.windows(2)
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            let ab = b - a;
            let len2 = ab.hypot2();
            let f = if len2 > 0.0 {
                ((q - a).dot(ab) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            q.distance(a + ab * f)
        })
        .fold(f64::INFINITY, f64::min)
}

/// The largest distance from a sample of the piece `piece` to its own segment (the first
/// segment holding samples whose range holds it), or to a segment next to that one (a sample at
/// a joint lies where both meet): the honest measure the record states, computed here on the
/// segments' polylines `lines` ([`chain_polyline`]), not by the fitter. Another pass of the chain
/// that comes near a sample does not count.
pub fn own_segment_deviation(
    chain: &kansei::chain::Chain,
    lines: &[Vec<Point>],
    samples: &[kansei::stroke::Sample],
    (a, b): (usize, usize),
) -> f64 {
    let mut worst: f64 = 0.0;
    for i in a..=b {
        let q = samples[i].point();
        let own = chain
            .segments
            .iter()
            .position(|s| s.params.is_some() && (s.samples.0..=s.samples.1).contains(&i))
            .or_else(|| {
                chain
                    .segments
                    .iter()
                    .position(|s| (s.samples.0..=s.samples.1).contains(&i))
            })
            .unwrap_or(0);
        let near = own.saturating_sub(1)..=(own + 1).min(lines.len() - 1);
        let d = lines[near]
            .iter()
            .map(|l| polyline_distance(q, l))
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(d);
    }
    worst
}

/// Checks one stroke's fit (see the module doc). `result` is what `fit_stroke` returned.
pub fn check(case: &Case, result: &Result<Vec<CurveFit>, PipelineError>) -> Breaks {
    let mut breaks = Breaks::default();
    let curves = match result {
        Ok(c) => c,
        Err(e) => {
            breaks.error = Some(e.to_string());
            return breaks;
        }
    };
    let tol = case.tolerance;
    let samples = &case.stroke.samples;
    for fit in curves {
        let Some(chain) = &fit.chain else { continue };
        let segs: Vec<&LacSegment> = chain.segments.iter().map(|s| &s.segment).collect();
        let (lines, delta) = chain_polyline(&segs, CHECK_CHORD_FRACTION * tol);
        // Rounding of the fitter's own exact foot points and of the coordinates.
        let scale = samples
            .iter()
            .map(|s| s.x.abs().max(s.y.abs()))
            .fold(1.0, f64::max);
        let slack = delta + CHECK_CHORD_FRACTION * tol + 1e-9 * scale;
        let (a, b) = fit.samples;
        let worst = own_segment_deviation(chain, &lines, samples, (a, b));
        if chain.within_tolerance && worst - slack > tol {
            breaks.guarantee.push(format!(
                "samples {a}..={b}: within_tolerance but a sample is {worst} > {tol} from the chain"
            ));
        }
        if (worst - chain.max_deviation).abs() > slack {
            breaks.guarantee.push(format!(
                "samples {a}..={b}: max_deviation {} but the true largest distance is {worst}",
                chain.max_deviation
            ));
        }
        if !chain.within_tolerance {
            breaks.reported_misses += 1;
        }
        // A closed stroke: a curve that is the whole loop ends where it starts, and the samples
        // folded onto the loop lie within the allowance of the chain (nearest point of the
        // whole chain: a bound below the ordered measure the record states, which may not be
        // smaller).
        if let Some(closure) = fit.closure {
            if closure.whole {
                let (first, last) = (segs[0], segs[segs.len() - 1]);
                if first.start().distance(last.end()) > slack {
                    breaks.guarantee.push(format!(
                        "samples {a}..={b}: closed, but ends {} from its start",
                        first.start().distance(last.end())
                    ));
                }
            }
            if let Some((f, l)) = closure.folded {
                // Against every piece of the stroke: the folded samples lie over the loop's
                // start, on its first piece.
                let every: Vec<&LacSegment> = curves
                    .iter()
                    .filter_map(|c| c.chain.as_ref())
                    .flat_map(|c| c.segments.iter().map(|s| &s.segment))
                    .collect();
                let (all_lines, all_delta) = chain_polyline(&every, CHECK_CHORD_FRACTION * tol);
                let slack = slack + all_delta;
                let nearest = samples[f..=l.min(samples.len() - 1)]
                    .iter()
                    .map(|q| {
                        all_lines
                            .iter()
                            .map(|line| polyline_distance(q.point(), line))
                            .fold(f64::INFINITY, f64::min)
                    })
                    .fold(0.0, f64::max);
                let allowed = kansei::closure::FOLDED_TOLERANCES * tol;
                if nearest - slack > allowed || closure.folded_deviation + slack < nearest {
                    breaks.guarantee.push(format!(
                        "samples {a}..={b}: folded {f}..={l} lie {nearest} from the curves, \
                         reported {}",
                        closure.folded_deviation
                    ));
                }
            }
        }
        // Ranges: the first starts the piece, the last ends it, each starts after the one before.
        let ranges: Vec<(usize, usize)> = chain.segments.iter().map(|s| s.samples).collect();
        if ranges.first().map(|r| r.0) != Some(a) || ranges.last().map(|r| r.1) != Some(b) {
            breaks
                .tiling
                .push(format!("piece {a}..={b}: segments cover {ranges:?}"));
        }
        // Segments holding samples continue where the one before ended; a segment holding none
        // (`params: None`) has the one-sample range of the last sample before it.
        let mut previous: Option<usize> = None;
        for (k, s) in chain.segments.iter().enumerate() {
            let (f, l) = s.samples;
            let ok = if s.params.is_some() {
                f == previous.map_or(a, |p| p + 1) && l >= f
            } else {
                f == l && f == previous.unwrap_or(a)
            };
            if !ok {
                breaks.tiling.push(format!(
                    "piece {a}..={b}: segment {k} has {:?} after {previous:?} ({ranges:?})",
                    s.samples
                ));
            }
            if s.params.is_some() {
                previous = Some(l);
            }
        }
        for (k, s) in chain.segments.iter().enumerate() {
            let alpha = s.segment.alpha();
            let accounted = match (alpha, s.alpha_source) {
                (None, None) => true,
                (Some(alpha), Some(AlphaSource::Search)) => {
                    s.search.evaluations > 0
                        && s.search.alpha.is_some_and(|found| {
                            (alpha - found).abs() <= kansei::lac::alpha_search::ALPHA_TOLERANCE
                        })
                }
                (Some(_), Some(_)) => true,
                _ => false,
            };
            if !accounted {
                breaks.unsourced.push(format!(
                    "piece {a}..={b} segment {k}: alpha {alpha:?} with source {:?} \
                     (search {:?}, {} evaluations)",
                    s.alpha_source, s.search.alpha, s.search.evaluations
                ));
            }
        }
    }
    breaks
}

/// Most samples a stroke decoded by [`stroke_from_bytes`] has: the classes that broke the
/// pipeline were 20–45 samples.
pub const MAX_FUZZ_SAMPLES: usize = 96;

/// The `fit_stroke` fuzz target's decoding of bytes into a stroke and a tolerance (px units).
/// Byte 0 picks the grid (1 px, 1/4 px, or 0.005: device-like steps) and the tolerance (0.5,
/// 0.25, 1, 0.1); each following byte pair is a move of −8..7 grid steps per axis, from
/// (400, 300), so repeats, reversals, zigzags and collinear runs all come out of small moves.
/// `None` for empty input.
pub fn stroke_from_bytes(data: &[u8]) -> Option<(Stroke, f64)> {
    let (&head, moves) = data.split_first()?;
    let grid = [1.0, 0.25, 0.005][usize::from(head % 3)];
    let tolerance = [0.5, 0.25, 1.0, 0.1][usize::from((head / 3) % 4)];
    let mut p = Point::new(400.0, 300.0);
    let mut points = vec![p];
    if head >= CLOSING_HEAD {
        return closing_stroke(moves, grid, tolerance);
    }
    if head >= TURNING_HEAD {
        // The pen's heading turns by the first byte of each pair and it moves by the second:
        // repeated turns draw circles, loops, spirals and circles gone round past their start,
        // rounded to the grid.
        let (mut q, mut heading) = (p, 0.0_f64);
        for pair in moves.chunks_exact(2).take(MAX_FUZZ_SAMPLES - 1) {
            heading += f64::from(i16::from(pair[0] & 0x0f) - 8) * TURN_STEP;
            let length = f64::from(1 + (pair[1] & 0x0f)) * TURNING_STEP_LENGTH;
            q = Point::new(q.x + length * heading.cos(), q.y + length * heading.sin());
            p = Point::new((q.x / grid).round() * grid, (q.y / grid).round() * grid);
            points.push(p);
        }
        return Some((Stroke::from_points(points), tolerance));
    }
    for pair in moves.chunks_exact(2).take(MAX_FUZZ_SAMPLES - 1) {
        let step = |b: u8| f64::from(i16::from(b & 0x0f) - 8) * grid;
        p = Point::new(p.x + step(pair[0]), p.y + step(pair[1]));
        points.push(p);
    }
    Some((Stroke::from_points(points), tolerance))
}

/// Head bytes from this one on decode a closed shape ([`stroke_from_bytes`], `closing_stroke`):
/// an ellipse drawn from just short of one turn to two, its radius wobbling by the bytes,
/// rounded to the grid: strokes that come back to their start, to close.
pub const CLOSING_HEAD: u8 = 0xf8;

/// The closed shapes of [`CLOSING_HEAD`]: the first byte sets the radius (20..140 px) and the
/// aspect (0.4..1), the second the turns drawn (0.97, 1, 1.05, 1.3 or 2), every further byte one
/// sample's radial wobble (up to half the tolerance either way), the samples spread evenly over
/// the turns.
fn closing_stroke(moves: &[u8], grid: f64, tolerance: f64) -> Option<(Stroke, f64)> {
    let (&shape, rest) = moves.split_first()?;
    let (&extent, wobble) = rest.split_first()?;
    let radius = 20.0 + 8.0 * f64::from(shape & 0x0f);
    let aspect = 0.4 + 0.04 * f64::from(shape >> 4);
    let turns = [0.97, 1.0, 1.05, 1.3, 2.0][usize::from(extent % 5)];
    let n = wobble.len().min(MAX_FUZZ_SAMPLES - 1);
    if n < 2 {
        return None;
    }
    let points = wobble[..n].iter().enumerate().map(|(k, &b)| {
        let t = std::f64::consts::TAU * turns * k as f64 / (n - 1) as f64;
        let r = radius + 0.5 * tolerance * (f64::from(b) - 127.5) / 127.5;
        let q = Point::new(400.0 + r * t.cos(), 300.0 + aspect * r * t.sin());
        Point::new((q.x / grid).round() * grid, (q.y / grid).round() * grid)
    });
    Some((Stroke::from_points(points), tolerance))
}

/// Head bytes from this one on decode their moves as turns and steps ([`stroke_from_bytes`]):
/// strokes that come back near themselves. (Every recorded regression input has a smaller head,
/// so they decode as they did.)
pub const TURNING_HEAD: u8 = 0xf0;

/// Turn per unit of a turning move's first byte (radians): −8..7 units, up to a third of a
/// radian a sample, so a few dozen samples close a circle.
const TURN_STEP: f64 = 0.045;

/// Step per unit of a turning move's second byte (px): 1..16 units.
const TURNING_STEP_LENGTH: f64 = 1.5;
