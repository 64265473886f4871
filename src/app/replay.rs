//! Replaying a drawing's strokes at their recorded speed, as if drawn live: [`Replay`].
//!
//! Each sample gets a time on one clock: with recorded times (`t`) that increase from stroke to
//! stroke, the recorded times less the first; otherwise each stroke follows the previous one
//! after [`STROKE_GAP_S`], and samples without a time come every [`UNTIMED_SAMPLE_S`]. The replay
//! clock advances by the frame time multiplied by the speed.

use crate::stroke::Stroke;

/// Pause between strokes when the recording does not say, seconds: a quick pen lift.
pub const STROKE_GAP_S: f64 = 0.3;

/// Interval between samples without a recorded time, seconds: a 200 Hz tablet.
pub const UNTIMED_SAMPLE_S: f64 = 1.0 / 200.0;

/// Slowest and fastest replay speeds the panel offers.
pub const SPEED_RANGE: (f64, f64) = (0.1, 10.0);

/// A replay in progress.
#[derive(Clone, Debug, PartialEq)]
pub struct Replay {
    /// For each stroke, the clock time of each sample.
    times: Vec<Vec<f64>>,
    /// The replay clock, seconds.
    clock: f64,
    /// Frames advanced so far (changes whenever what is shown may change).
    frame: u64,
}

impl Replay {
    /// A replay of `strokes` from the start.
    pub fn new(strokes: &[Stroke]) -> Self {
        Replay {
            times: schedule(strokes),
            clock: 0.0,
            frame: 0,
        }
    }

    /// Advances the clock by `dt` seconds of wall time at `speed`.
    pub fn advance(&mut self, dt: f64, speed: f64) {
        let speed = speed.clamp(SPEED_RANGE.0, SPEED_RANGE.1);
        if dt.is_finite() && dt > 0.0 {
            self.clock += dt * speed;
            self.frame += 1;
        }
    }

    /// How many samples of stroke `index` have been drawn.
    pub fn visible_samples(&self, index: usize) -> usize {
        self.times
            .get(index)
            .map_or(0, |t| t.partition_point(|&ti| ti <= self.clock))
    }

    /// Whether every sample has been drawn.
    pub fn is_done(&self) -> bool {
        self.times
            .iter()
            .all(|t| t.last().is_none_or(|&last| last <= self.clock))
    }

    /// The replay clock, seconds.
    pub fn clock(&self) -> f64 {
        self.clock
    }

    /// The clock time at which the last sample is drawn.
    pub fn duration(&self) -> f64 {
        self.times
            .iter()
            .filter_map(|t| t.last().copied())
            .fold(0.0, f64::max)
    }

    /// Frames advanced so far.
    pub fn frame(&self) -> u64 {
        self.frame
    }
}

/// The clock time of every sample (see the module documentation).
fn schedule(strokes: &[Stroke]) -> Vec<Vec<f64>> {
    let recorded: Option<Vec<Vec<f64>>> = strokes
        .iter()
        .map(|s| s.samples.iter().map(|x| x.t).collect::<Option<Vec<f64>>>())
        .collect();
    if let Some(recorded) = recorded {
        let increasing = recorded
            .windows(2)
            .all(|w| match (w[0].last(), w[1].first()) {
                (Some(a), Some(b)) => b >= a,
                _ => true,
            });
        let first = recorded.iter().find_map(|t| t.first().copied());
        if let (true, Some(first)) = (increasing, first) {
            return recorded
                .into_iter()
                .map(|t| t.into_iter().map(|ti| ti - first).collect())
                .collect();
        }
    }
    // Stroke after stroke: each keeps its own recorded rhythm when it has one.
    let mut start = 0.0;
    strokes
        .iter()
        .map(|s| {
            let t0 = s.samples.first().and_then(|x| x.t);
            let times: Vec<f64> = s
                .samples
                .iter()
                .enumerate()
                .map(|(i, x)| match (x.t, t0) {
                    (Some(t), Some(t0)) => start + (t - t0),
                    _ => start + i as f64 * UNTIMED_SAMPLE_S,
                })
                .collect();
            start = times.last().copied().unwrap_or(start) + STROKE_GAP_S;
            times
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stroke::Sample;

    fn timed(t0: f64, n: usize, dt: f64) -> Stroke {
        Stroke::new(
            (0..n)
                .map(|i| Sample::new(i as f64, 0.0).with_t(t0 + i as f64 * dt))
                .collect(),
        )
    }

    #[test]
    fn recorded_times_are_kept_and_speed_scales_the_clock() {
        let strokes = [timed(10.0, 11, 0.01), timed(11.0, 5, 0.01)];
        let mut replay = Replay::new(&strokes);
        assert!((replay.duration() - 1.04).abs() < 1e-12);
        replay.advance(0.0275, 2.0); // clock 0.055 s: samples 0..=5 of the first stroke.
        assert_eq!(replay.visible_samples(0), 6);
        assert_eq!(replay.visible_samples(1), 0);
        replay.advance(0.5, 2.0); // clock 1.055 s: everything.
        assert_eq!(replay.visible_samples(1), 5);
        assert!(replay.is_done());
    }

    #[test]
    fn untimed_strokes_follow_each_other() {
        let untimed = Stroke::from_points((0..4).map(|i| crate::geom::Point::new(i as f64, 1.0)));
        // The second stroke's times restart: the recording is not one clock.
        let strokes = [untimed.clone(), timed(0.0, 3, 0.1), untimed];
        let times = schedule(&strokes);
        let end0 = 3.0 * UNTIMED_SAMPLE_S;
        assert_eq!(times[0].last().copied(), Some(end0));
        assert!((times[1][0] - (end0 + STROKE_GAP_S)).abs() < 1e-12);
        assert!((times[1][2] - (end0 + STROKE_GAP_S + 0.2)).abs() < 1e-12);
        assert!((times[2][0] - (times[1][2] + STROKE_GAP_S)).abs() < 1e-12);
    }
}
