//! A source replayed in real time: [`Paced`].
//!
//! A recording read through [`Paced`] delivers each report when the wall clock reaches its
//! recorded time (divided by a speed factor), so whatever consumes it (the app's tablet feed)
//! sees the same timing as from the tablet that was recorded. Waits longer than
//! [`IDLE_INTERVAL`] return [`Next::Idle`] instead of blocking, as a live source does when the
//! pen is away, so that a consumer polling a stop flag stays responsive.

use std::time::{Duration, Instant};

use super::source::{DeviceInfo, Next, PenSource, SourceError, SourceEvent};

/// Longest single wait before [`Next::Idle`] is returned (a live source's poll interval).
pub const IDLE_INTERVAL: Duration = Duration::from_millis(100);

/// `inner` replayed at `speed` × its recorded pace (see the module documentation).
#[derive(Debug)]
pub struct Paced<S> {
    inner: S,
    speed: f64,
    /// Wall time and recorded time of the first report.
    origin: Option<(Instant, f64)>,
    /// A report read but not yet due.
    pending: Option<SourceEvent>,
}

impl<S: PenSource> Paced<S> {
    /// Paces `inner` at `speed` times its recorded pace (`speed` must be positive and finite).
    pub fn new(inner: S, speed: f64) -> Result<Self, SourceError> {
        if !(speed.is_finite() && speed > 0.0) {
            return Err(SourceError::Speed(speed));
        }
        Ok(Paced {
            inner,
            speed,
            origin: None,
            pending: None,
        })
    }

    /// When `event` is due on the wall clock.
    fn due(&mut self, event: &SourceEvent) -> Instant {
        let (wall, t0) = *self.origin.get_or_insert((Instant::now(), event.t));
        let offset = ((event.t - t0) / self.speed).max(0.0);
        wall + Duration::from_secs_f64(offset)
    }
}

impl<S: PenSource> PenSource for Paced<S> {
    fn next(&mut self) -> Result<Next, SourceError> {
        let event = match self.pending.take() {
            Some(event) => event,
            None => match self.inner.next()? {
                Next::Event(event) => event,
                other => return Ok(other),
            },
        };
        let due = self.due(&event);
        let now = Instant::now();
        if due > now + IDLE_INTERVAL {
            std::thread::sleep(IDLE_INTERVAL);
            self.pending = Some(event);
            return Ok(Next::Idle);
        }
        if due > now {
            std::thread::sleep(due - now);
        }
        Ok(Next::Event(event))
    }

    fn info(&self) -> &DeviceInfo {
        self.inner.info()
    }

    fn descriptor(&self) -> Option<&[u8]> {
        self.inner.descriptor()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::capture::source::{Decoded, Interface};
    use crate::stroke::Units;

    /// Events at the given recorded times.
    struct Times {
        times: Vec<f64>,
        info: DeviceInfo,
    }

    impl PenSource for Times {
        fn next(&mut self) -> Result<Next, SourceError> {
            if self.times.is_empty() {
                return Ok(Next::End);
            }
            let t = self.times.remove(0);
            Ok(Next::Event(SourceEvent {
                t,
                raw: None,
                decoded: Decoded::Other,
            }))
        }
        fn info(&self) -> &DeviceInfo {
            &self.info
        }
    }

    #[test]
    fn reports_arrive_at_their_recorded_pace() {
        // 0.3 s of recording at double speed takes at least 0.15 s of wall time, and a gap
        // longer than the idle interval is broken into idles without losing the report.
        let source = Times {
            times: vec![10.0, 10.1, 10.3],
            info: DeviceInfo::unknown(Interface::Hid, Units::Mm),
        };
        let mut paced = Paced::new(source, 2.0).expect("valid speed");
        let start = Instant::now();
        let mut times = Vec::new();
        loop {
            match paced.next().expect("no error") {
                Next::Event(e) => times.push(e.t),
                Next::Idle => {}
                Next::End => break,
            }
        }
        assert_eq!(times, vec![10.0, 10.1, 10.3]);
        assert!(start.elapsed() >= Duration::from_millis(150));
    }

    #[test]
    fn a_bad_speed_is_refused() {
        for speed in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let source = Times {
                times: vec![],
                info: DeviceInfo::unknown(Interface::Hid, Units::Mm),
            };
            assert!(Paced::new(source, speed).is_err(), "{speed}");
        }
    }
}
