//! Closed strokes: whether a stroke meant a closed curve, where its loop ends, the pose of the
//! seam where the curve closes, and the samples drawn over the loop a second time.
//!
//! A designer's closed stroke rarely ends exactly where it began: it stops short, runs past
//! its start, or goes round again. [`find_closure`] reads the stroke's prepared pieces (after
//! duplicates, dwell and hooks) as one polyline and looks for the first time it comes back to
//! its first point:
//!
//! * it must first have left the start by more than twice the closing radius, and come back
//!   within the closing radius r = [`CLOSE_TOLERANCES`]·tolerance + [`CLOSE_SHARE`]·L (L the
//!   length drawn so far): a gap wider than r stays open, a "C";
//! * the loop up to there must be wider than [`MIN_WIDTH_TOLERANCES`] tolerances across (the
//!   smaller principal spread of its points): a line drawn there and back is not a loop;
//! * where the direction there agrees with the start's within the corner angle, the stroke
//!   closes smoothly ([`ClosureKind::Smooth`]): the loop ends where the return pass reaches the
//!   line through the start across its direction, and whatever follows (an overshoot, a
//!   second round) is folded onto the loop: measured against it, never fitted a second time;
//! * where the directions disagree and the stroke ends there, it closes at a corner (a
//!   teardrop's tip, [`ClosureKind::Corner`]); where they disagree and the stroke goes on, the
//!   return was a crossing (the middle of a figure eight) and the search goes on.
//!
//! The pipeline then fits the loop as a closed curve: a smooth closure's chain starts and ends
//! at the seam's pose ([`seam_pose`]: point, tangent and curvature of a B-spline through the
//! samples on both sides of the start), which the smooth fit holds on both sides
//! ([`crate::chain::JointKind::Seam`]); a corner closure's chain starts and ends at the first
//! sample. Where the folded samples do not lie within the tolerance of the closed curve (the
//! second round was drawn elsewhere, a tail leaves the loop), the stroke is fitted open.

use crate::bspline::project::Pieces;
use crate::bspline::{FitOptions, fit_bspline};
use crate::chain::{ChainSegment, Resolution, SeamPose, distance_on};
use crate::geom::{Point, Vec2, cumulative_lengths};
use crate::prepare::{Piece, PieceEnd};

/// The closing radius's part in tolerances: a stroke that ends within three tolerances of its
/// start (plus [`CLOSE_SHARE`] of its length) ends there, as far as its samples can tell.
pub const CLOSE_TOLERANCES: f64 = 3.0;

/// The closing radius's part in the loop's length: a gap of 3 % of the perimeter (19 px on a
/// circle of radius 100 px) reads as a closed shape drawn quickly; a "C" leaves a gap of a
/// quarter or more.
pub const CLOSE_SHARE: f64 = 0.03;

/// Narrowest loop, in tolerances across (the square root of the smaller eigenvalue of its
/// points' covariance): a stroke that comes back along its own way (a line drawn there and
/// back) encloses nothing a closed curve would add.
pub const MIN_WIDTH_TOLERANCES: f64 = 2.0;

/// Fewest distinct points of a loop: fewer cannot tell a closed curve from a scribble.
pub const MIN_LOOP_POINTS: usize = 8;

/// The direction at a point is read over this many tolerances of arc length (or
/// [`TANGENT_SHARE`] of the loop, whichever is longer): beyond the samples' noise, well within
/// the curve's bends.
pub const TANGENT_TOLERANCES: f64 = 3.0;

/// See [`TANGENT_TOLERANCES`].
pub const TANGENT_SHARE: f64 = 0.02;

/// The seam's pose is read from a B-spline through the samples within this share of the loop's
/// length on either side of the start.
pub const SEAM_WINDOW_SHARE: f64 = 0.125;

/// Whether strokes that come back to their start are closed: the CLI's and the service's
/// `close` (`auto`, the default, or `never`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Close {
    /// A stroke that comes back to its start ([`find_closure`]) is fitted as a closed curve.
    #[default]
    Auto,
    /// Every stroke is fitted open.
    Never,
}

impl Close {
    /// The names, as the CLI and the service spell them.
    pub const NAMES: [&'static str; 2] = ["auto", "never"];
}

impl std::str::FromStr for Close {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        match text {
            "auto" => Ok(Close::Auto),
            "never" => Ok(Close::Never),
            other => Err(format!("close is auto or never, got {other:?}")),
        }
    }
}

/// How a stroke closes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ClosureKind {
    /// The stroke comes back along its start's direction: one closed curve with a seam as
    /// continuous as its other joints.
    Smooth,
    /// The stroke comes back at an angle and ends there: the curve closes at a corner.
    Corner,
}

/// Where a stroke closes ([`find_closure`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closure {
    /// How it closes.
    pub kind: ClosureKind,
    /// The loop's last point: its piece and its index in that piece's points.
    pub last: (usize, usize),
    /// The samples after the loop (original indices, inclusive): an overshoot past the start
    /// or a second round, drawn over the loop. `None` where the stroke ends with the loop.
    pub folded: Option<(usize, usize)>,
    /// The loop's length along its points, with the gap back to the start.
    pub length: f64,
    /// The gap from the loop's last point back to the start.
    pub gap: f64,
}

/// How a stroke's curves close, carried on its last curve
/// ([`crate::pipeline::CurveFit::closure`]); the `closure` of a `kansei-curve` entry.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ClosureRecord {
    /// Whether this curve alone is the closed loop (the stroke closed in one piece); otherwise
    /// it ends where the stroke's first piece starts.
    pub whole: bool,
    /// How it closes.
    pub kind: ClosureKind,
    /// The samples drawn over the loop a second time (see [`Closure::folded`]).
    pub folded: Option<(usize, usize)>,
    /// The largest distance from a folded sample to the closed curve (0 without any).
    pub folded_deviation: f64,
    /// The distance from the loop's last sample to its first: the gap the closed curve
    /// bridges where the stroke stopped short of its start (at most the closing radius, see
    /// the module documentation), a sample's spacing where it ran past.
    pub gap: f64,
}

/// The stroke's pieces as one polyline: each point, and where it comes from (piece, index).
fn flatten(pieces: &[Piece]) -> (Vec<Point>, Vec<(usize, usize)>) {
    let mut points = Vec::new();
    let mut from = Vec::new();
    for (p, piece) in pieces.iter().enumerate() {
        // A corner is the last point of one piece and the first of the next.
        let skip = usize::from(p > 0);
        for (i, &q) in piece.points.iter().enumerate().skip(skip) {
            points.push(q);
            from.push((p, i));
        }
    }
    (points, from)
}

/// The unit direction of travel at point `i` of `points`, read over `reach` of arc length
/// ahead (`ahead`) or behind; `None` where the polyline is shorter than that on that side.
fn direction(points: &[Point], lengths: &[f64], i: usize, reach: f64, ahead: bool) -> Option<Vec2> {
    let other = if ahead {
        (i + 1..points.len()).find(|&k| lengths[k] - lengths[i] >= reach)?
    } else {
        (0..i).rev().find(|&k| lengths[i] - lengths[k] >= reach)?
    };
    let d = if ahead {
        points[other] - points[i]
    } else {
        points[i] - points[other]
    };
    let norm = d.hypot();
    (norm > 0.0).then(|| d / norm)
}

/// The square root of the smaller eigenvalue of the covariance of `points`: how wide the
/// point set is across its main direction.
fn width(points: &[Point]) -> f64 {
    let n = points.len() as f64;
    if n < 2.0 {
        return 0.0;
    }
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |(x, y), p| (x + p.x, y + p.y));
    let (mx, my) = (sx / n, sy / n);
    let (mut xx, mut xy, mut yy) = (0.0, 0.0, 0.0);
    for p in points {
        let (dx, dy) = (p.x - mx, p.y - my);
        xx += dx * dx;
        xy += dx * dy;
        yy += dy * dy;
    }
    let (xx, xy, yy) = (xx / n, xy / n, yy / n);
    let half_trace = 0.5 * (xx + yy);
    let spread = (0.25 * (xx - yy) * (xx - yy) + xy * xy).sqrt();
    (half_trace - spread).max(0.0).sqrt()
}

/// Whether and where the stroke of `pieces` closes (see the module documentation), at
/// `tolerance` and the corner angle `corner_angle` (radians).
pub fn find_closure(pieces: &[Piece], tolerance: f64, corner_angle: f64) -> Option<Closure> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return None;
    }
    let (points, from) = flatten(pieces);
    let m = points.len();
    if m < MIN_LOOP_POINTS {
        return None;
    }
    let lengths = cumulative_lengths(&points);
    let radius = |length: f64| CLOSE_TOLERANCES * tolerance + CLOSE_SHARE * length;
    let reach = |length: f64| (TANGENT_TOLERANCES * tolerance).max(TANGENT_SHARE * length);
    let start = points[0];
    let away = |i: usize| points[i].distance(start);
    // The stroke has left its start once it is farther than twice the closing radius.
    let left = (1..m).find(|&i| away(i) > 2.0 * radius(lengths[i]))?;
    let mut i = left + 1;
    while i < m {
        if away(i) > radius(lengths[i]) {
            i += 1;
            continue;
        }
        // A run of points within the closing radius: its nearest to the start is the return.
        let run_start = i;
        while i + 1 < m && away(i + 1) <= radius(lengths[i + 1]) {
            i += 1;
        }
        let run_end = i;
        i += 1;
        let j = (run_start..=run_end)
            .min_by(|&a, &b| away(a).total_cmp(&away(b)))
            .unwrap_or(run_start);
        if j + 1 < MIN_LOOP_POINTS || width(&points[..=j]) < MIN_WIDTH_TOLERANCES * tolerance {
            continue;
        }
        let loop_length = lengths[j] + away(j);
        let r = reach(loop_length);
        let Some(t0) = direction(&points, &lengths, 0, r, true) else {
            continue;
        };
        let tj = direction(&points, &lengths, j, r, true)
            .or_else(|| direction(&points, &lengths, j, r, false));
        let Some(tj) = tj else { continue };
        let angle = t0.cross(tj).atan2(t0.dot(tj)).abs();
        let ends_here = run_end + 1 == m;
        if angle <= corner_angle {
            // The loop ends where the return pass reaches the line through the start across
            // its direction: the last point before it.
            let before = |k: usize| (points[k] - start).dot(t0) < 0.0;
            let mut e = if before(j) { j } else { j - 1 };
            while e < run_end && before(e + 1) {
                e += 1;
            }
            // What follows must lie over the loop: any curve within the tolerance of the
            // loop's points lies within it of their polyline, so a point farther than
            // the folded allowance and a tolerance from it cannot be folded (a scribble going
            // on past its start), and no fit is spent on it.
            let allowance = (FOLDED_TOLERANCES + 1.0) * tolerance;
            if !follows_loop(&points[..=e], &points[e + 1..], allowance) {
                continue;
            }
            return Some(closure(
                ClosureKind::Smooth,
                pieces,
                &from,
                e,
                (lengths[e] + away(e), away(e)),
            ));
        }
        if ends_here {
            return Some(closure(
                ClosureKind::Corner,
                pieces,
                &from,
                m - 1,
                (lengths[m - 1] + away(m - 1), away(m - 1)),
            ));
        }
    }
    None
}

/// For each point of `after`, in order, its partner on the closed polyline `loop_points` (its
/// last point joined back to its first): the nearest edge among those a little ahead of the last
/// point's partner ([`PARTNER_REACH_SHARE`] of the loop), as the index of the edge's first
/// point, and the distance to it. Ordered so, a second round maps onto the first and a point
/// never finds a partner on another part of the loop that passes near it. The first point's
/// partner is among the loop's first edges (what follows a loop starts past its start).
fn ordered_partners<'a>(
    loop_points: &'a [Point],
    after: impl IntoIterator<Item = &'a Point> + 'a,
) -> impl Iterator<Item = (usize, f64)> + 'a {
    let m = loop_points.len();
    let reach = ((PARTNER_REACH_SHARE * m as f64) as usize).max(2);
    let mut partner = 0;
    after.into_iter().map(move |&q| {
        let (best, distance) = (0..=reach)
            .map(|d| {
                let i = (partner + d) % m;
                let (a, b) = (loop_points[i], loop_points[(i + 1) % m]);
                (i, crate::geom::distance_to_segment(q, a, b))
            })
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .unwrap_or((partner, f64::INFINITY));
        partner = best;
        (best, distance)
    })
}

/// Whether every point of `after` lies within `allowance` of the closed polyline `loop_points`
/// (each near its [`ordered_partners`] edge).
fn follows_loop(loop_points: &[Point], after: &[Point], allowance: f64) -> bool {
    if loop_points.len() < 2 {
        return after.is_empty();
    }
    ordered_partners(loop_points, after).all(|(_, distance)| distance <= allowance)
}

/// The closure whose loop ends at flattened point `e`.
fn closure(
    kind: ClosureKind,
    pieces: &[Piece],
    from: &[(usize, usize)],
    e: usize,
    (length, gap): (f64, f64),
) -> Closure {
    let last = from[e];
    let stroke_last = pieces.last().map_or(0, |p| p.samples.1);
    let piece = &pieces[last.0];
    let folded = (e + 1 < from.len()).then(|| (piece.indices[last.1] + 1, stroke_last));
    Closure {
        kind,
        last,
        folded: folded.filter(|(a, b)| a <= b),
        length,
        gap,
    }
}

/// The pieces of a closed stroke: those after the loop's last point dropped, the last one cut
/// there, and the first's start and the last's end marked [`PieceEnd::Seam`] (both held where
/// the curve closes: the seam's point, or the first sample at a corner closure).
pub fn close_pieces(mut pieces: Vec<Piece>, closure: &Closure) -> Vec<Piece> {
    let (p, i) = closure.last;
    pieces.truncate(p + 1);
    let end = PieceEnd::Seam;
    if let Some(last) = pieces.last_mut() {
        if closure.folded.is_some() {
            last.points.truncate(i + 1);
            last.indices.truncate(i + 1);
            last.samples.1 = last.indices[i.min(last.indices.len() - 1)];
        }
        last.end = end;
    }
    if let Some(first) = pieces.first_mut() {
        first.start = end;
    }
    pieces
}

/// The seam's pose of a smooth closure: the point, tangent and curvature at the first sample's
/// foot on a B-spline through the loop's last points and its first ones (within
/// [`SEAM_WINDOW_SHARE`] of its length of the start, and within the first and last pieces), in
/// that order, so that the seam is read from both of its sides. `None` where those points are
/// too few or the B-spline cannot be fitted.
pub fn seam_pose(pieces: &[Piece], closure: &Closure, tolerance: f64) -> Option<SeamPose> {
    let (first, last) = (pieces.first()?, pieces.last()?);
    let window = SEAM_WINDOW_SHARE * closure.length;
    let head_lengths = cumulative_lengths(&first.points);
    let head: Vec<Point> = first
        .points
        .iter()
        .zip(&head_lengths)
        .take_while(|(_, l)| **l <= window)
        .map(|(p, _)| *p)
        .collect();
    let tail_lengths = cumulative_lengths(&last.points);
    let total = tail_lengths.last().copied().unwrap_or(0.0);
    let single = pieces.len() == 1;
    let tail: Vec<Point> = last
        .points
        .iter()
        .zip(&tail_lengths)
        // On a loop of one piece, the tail must not reach back into the head.
        .filter(|(_, l)| total - **l <= window && !(single && **l <= window))
        .map(|(p, _)| *p)
        .collect();
    if head.len() < 2 || tail.len() < 2 {
        return None;
    }
    // The first sample's index in the window: the tail, then the head.
    let start = tail.len();
    let mut points = tail;
    points.extend(head);
    let fit = fit_bspline(&points, &FitOptions::new(tolerance)).ok()?;
    let at = *fit.params.get(start)?;
    let curve = Pieces::new(fit.curve.to_beziers());
    let foot = curve.project_local(first.points[0], at);
    let (point, d1, d2) = curve.eval_derivs(foot.u);
    let speed = d1.hypot();
    if !(speed > 0.0) {
        return None;
    }
    let kappa = d1.cross(d2) / (speed * speed * speed);
    let theta = d1.y.atan2(d1.x);
    (point.x.is_finite() && point.y.is_finite() && kappa.is_finite()).then_some(SeamPose {
        point,
        theta,
        kappa,
    })
}

/// How far, in tolerances, the folded samples may lie from the closed curve fitted to the
/// loop's: a second round drawn over the first carries its own noise, up to a tolerance on the
/// other side of the shape (a mouse's whole-pixel rounding puts one round 0.7 px on one side
/// and the next 0.7 px on the other); farther, the rounds are two shapes and the stroke is
/// fitted open.
pub const FOLDED_TOLERANCES: f64 = 2.0;

/// Edges of the loop ahead of a point's last partner among which its next partner is sought
/// ([`ordered_partners`]), as a share of the loop's points: far more than the pen moves
/// between two samples, far less than a loop.
const PARTNER_REACH_SHARE: f64 = 0.125;

/// The largest distance from a folded sample ([`Closure::folded`]) to the closed curve, each
/// measured as the honest measure measures a sample (its own segment, or a neighbour): a
/// folded sample's own segment is the one holding the first point of its partner edge on the
/// loop, the nearest edge among those a little ahead of the last folded sample's partner (in
/// order round the loop: a second round maps onto the first). `samples`: the stroke's sample
/// positions by original index; `pieces`: the closed curve's pieces in order; `chains`: each
/// piece's fitted segments. 0 without folded samples; +∞ where a folded sample finds no segment.
pub fn folded_deviation(
    samples: &[Point],
    closure: &Closure,
    pieces: &[Piece],
    chains: &[&[ChainSegment]],
    tolerance: f64,
) -> f64 {
    let Some((a, b)) = closure.folded else {
        return 0.0;
    };
    let (points, from) = flatten(pieces);
    if points.len() < 2 || b >= samples.len() || a > b || pieces.len() != chains.len() {
        return f64::INFINITY;
    }
    // Every segment of the closed curve in order.
    let segments: Vec<&ChainSegment> = chains.iter().flat_map(|c| c.iter()).collect();
    let n = segments.len();
    if n == 0 {
        return f64::INFINITY;
    }
    let holding = |index: usize| {
        segments
            .iter()
            .position(|s| s.samples.0 <= index && index <= s.samples.1)
    };
    let chord_error = Resolution::new(tolerance).chord_error;
    let mut worst: f64 = 0.0;
    let mut traces: Vec<Option<Vec<(f64, Point)>>> = vec![None; n];
    for (q, (partner, _)) in samples[a..=b]
        .iter()
        .zip(ordered_partners(&points, &samples[a..=b]))
    {
        let (p, i) = from[partner];
        let Some(own) = holding(pieces[p].indices[i]) else {
            return f64::INFINITY;
        };
        // Measured as the chain's own measure measures a sample: its own segment or a
        // neighbour, each afresh (a segment of a closed chain may turn more than half a turn).
        let nearest = [own + n - 1, own, own + 1]
            .into_iter()
            .map(|k| {
                distance_on(
                    &segments[k % n].segment,
                    &mut traces[k % n],
                    *q,
                    chord_error,
                )
            })
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(nearest);
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    fn piece(points: Vec<Point>) -> Piece {
        let n = points.len();
        Piece {
            points,
            indices: (0..n).collect(),
            samples: (0, n - 1),
            start: PieceEnd::StrokeEnd,
            end: PieceEnd::StrokeEnd,
        }
    }

    /// `f` at n + 1 parameters evenly over [0, 2π].
    fn one_turn(n: usize, f: impl Fn(f64) -> Point) -> Vec<Point> {
        (0..=n).map(|i| f(TAU * i as f64 / n as f64)).collect()
    }

    /// A circle from (radius, 0), `per_turn` samples a turn (not a whole number: no sample of
    /// the second round lies exactly on the first).
    fn circle(turns: f64, per_turn: f64, radius: f64) -> Vec<Point> {
        let n = (turns * per_turn).round() as usize;
        (0..=n)
            .map(|i| {
                let t = TAU * i as f64 / per_turn;
                Point::new(radius * t.cos(), radius * t.sin())
            })
            .collect()
    }

    /// A circle drawn 1.1 turns closes smoothly after one turn; the tenth of a turn past the
    /// start is folded.
    #[test]
    fn an_overshoot_circle_closes_smoothly_after_one_turn() {
        // Sample 100 lies just before the start (2π − 0.019), 101 just past it.
        let pieces = vec![piece(circle(1.1, 100.3, 100.0))];
        let c = find_closure(&pieces, 0.5, 70f64.to_radians()).expect("closed");
        assert_eq!(c.kind, ClosureKind::Smooth);
        assert_eq!(c.last, (0, 100));
        assert_eq!(c.folded, Some((101, 110)));
        assert!((c.length - TAU * 100.0).abs() < 0.01 * TAU * 100.0);
        let closed = close_pieces(pieces, &c);
        assert_eq!(closed[0].points.len(), 101);
        assert_eq!(
            (closed[0].start, closed[0].end),
            (PieceEnd::Seam, PieceEnd::Seam)
        );
        let pose = seam_pose(&closed, &c, 0.5).expect("pose");
        assert!(pose.point.distance(Point::new(100.0, 0.0)) < 0.5);
        assert!((pose.theta - std::f64::consts::FRAC_PI_2).abs() < 0.02);
        assert!((pose.kappa - 0.01).abs() < 0.001, "{}", pose.kappa);
    }

    /// Short of its start by less than the closing radius, a circle closes; by a quarter turn
    /// (a "C"), it does not.
    #[test]
    fn a_small_gap_closes_and_a_c_does_not() {
        let near = vec![piece(circle(0.98, 100.3, 100.0))];
        let c = find_closure(&near, 0.5, 70f64.to_radians()).expect("closed");
        assert_eq!((c.kind, c.folded), (ClosureKind::Smooth, None));
        let c_shape = vec![piece(circle(0.75, 100.3, 100.0))];
        assert_eq!(find_closure(&c_shape, 0.5, 70f64.to_radians()), None);
    }

    /// A line drawn there and back comes back to its start, but encloses nothing.
    #[test]
    fn a_line_drawn_there_and_back_stays_open() {
        let mut points: Vec<Point> = (0..=50).map(|i| Point::new(i as f64, 0.0)).collect();
        points.extend((0..50).rev().map(|i| Point::new(i as f64, 0.2)));
        assert_eq!(
            find_closure(&[piece(points)], 0.5, 70f64.to_radians()),
            None
        );
    }

    /// A teardrop ends at its start at an angle: a corner closure.
    #[test]
    fn a_teardrop_closes_at_a_corner() {
        // x = cos t, y = sin t·sin(t/2): leaves its tip at 135° and comes back at 45°.
        let n = 200;
        let points = one_turn(n, |t| {
            Point::new(100.0 * t.cos(), 100.0 * t.sin() * (0.5 * t).sin())
        });
        let c = find_closure(&[piece(points)], 0.5, 70f64.to_radians()).expect("closed");
        assert_eq!(c.kind, ClosureKind::Corner);
        assert_eq!((c.last, c.folded), ((0, n), None));
    }

    /// The middle of a figure eight is a crossing, not a closure; its end is.
    #[test]
    fn a_figure_eight_crossing_is_not_its_closure() {
        let n = 200;
        // Gerono's lemniscate from its crossing.
        let points = one_turn(n, |t| {
            Point::new(100.0 * t.sin(), 100.0 * t.sin() * t.cos())
        });
        let c = find_closure(&[piece(points)], 0.5, 70f64.to_radians()).expect("closed");
        assert_eq!(c.kind, ClosureKind::Smooth);
        assert!(c.last.1 >= n - 2, "{:?}", c.last);
    }
}
