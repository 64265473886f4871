//! [`ServeOptions`]: where the service listens and the limits it keeps, with their defaults, and
//! [`ServeArgs`], the same as `kansei serve` options.

use std::net::SocketAddr;
use std::time::Duration;

/// The default address: loopback only, port 7878.
pub const DEFAULT_ADDR: &str = "127.0.0.1:7878";
/// Default [`ServeOptions::max_body_bytes`]: 8 MiB, about 80 000 samples of JSON with pressure,
/// tilt and time.
pub const DEFAULT_MAX_BODY_BYTES: usize = 8 << 20;
/// Default [`ServeOptions::max_strokes`].
pub const DEFAULT_MAX_STROKES: usize = 1000;
/// Default [`ServeOptions::max_samples_per_stroke`]: a minute of a 300 Hz pen without lifting
/// it. The fit's time grows faster than linearly with a stroke's length; the longest fixture
/// stroke (675 samples) fits in about 35 ms.
pub const DEFAULT_MAX_SAMPLES_PER_STROKE: usize = 20_000;
/// Default [`ServeOptions::deadline`].
pub const DEFAULT_DEADLINE: Duration = Duration::from_secs(10);
/// Default [`ServeOptions::queue_depth`].
pub const DEFAULT_QUEUE_DEPTH: usize = 64;

/// How the service runs. `Default` gives the documented defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct ServeOptions {
    /// Where to listen. Default [`DEFAULT_ADDR`] (loopback); binding any other address prints a
    /// warning: the service has no authentication and no TLS.
    pub addr: SocketAddr,
    /// Largest request body, bytes; a larger one is answered `413`. Default
    /// [`DEFAULT_MAX_BODY_BYTES`]. Also the largest streaming message.
    pub max_body_bytes: usize,
    /// Most strokes in one request (`413` beyond). Default [`DEFAULT_MAX_STROKES`].
    pub max_strokes: usize,
    /// Most samples in one stroke (`413` beyond; on the stream, an error message). Default
    /// [`DEFAULT_MAX_SAMPLES_PER_STROKE`].
    pub max_samples_per_stroke: usize,
    /// Longest time from a request's admission to its answer: queueing, reading, fitting and
    /// writing the result (`504` beyond). A fit that has started cannot be interrupted: it runs
    /// to its end on its worker, which stays busy until then. Default [`DEFAULT_DEADLINE`].
    pub deadline: Duration,
    /// Requests that may wait for a worker; one more is answered `503` with `Retry-After`.
    /// Default [`DEFAULT_QUEUE_DEPTH`].
    pub queue_depth: usize,
    /// Fits that run at once, each on its own thread of the blocking pool. Default: the number
    /// of cores ([`std::thread::available_parallelism`]).
    pub workers: usize,
}

impl Default for ServeOptions {
    fn default() -> Self {
        ServeOptions {
            addr: SocketAddr::from(([127, 0, 0, 1], 7878)),
            max_body_bytes: DEFAULT_MAX_BODY_BYTES,
            max_strokes: DEFAULT_MAX_STROKES,
            max_samples_per_stroke: DEFAULT_MAX_SAMPLES_PER_STROKE,
            deadline: DEFAULT_DEADLINE,
            queue_depth: DEFAULT_QUEUE_DEPTH,
            workers: default_workers(),
        }
    }
}

/// The number of cores, or 1 when it cannot be told.
pub fn default_workers() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

impl ServeOptions {
    /// The options with `addr`, others default; port 0 picks a free port (tests).
    pub fn at(addr: SocketAddr) -> Self {
        ServeOptions {
            addr,
            ..ServeOptions::default()
        }
    }

    /// Refuses limits that would make the service useless: zero workers, bodies, strokes or
    /// samples, a zero deadline.
    pub fn validate(&self) -> Result<(), String> {
        for (name, value) in [
            ("the number of workers", self.workers),
            ("the body limit (bytes)", self.max_body_bytes),
            ("the strokes limit", self.max_strokes),
            ("the samples-per-stroke limit", self.max_samples_per_stroke),
        ] {
            if value == 0 {
                return Err(format!("{name} must be at least 1"));
            }
        }
        if self.deadline.is_zero() {
            return Err("the deadline must be longer than zero".to_owned());
        }
        Ok(())
    }
}

/// `kansei serve` options: [`ServeOptions`] on the command line.
#[derive(Clone, Debug, clap::Args)]
pub struct ServeArgs {
    /// Address to listen on. Anything but a loopback address prints a warning: the service has
    /// no authentication and no TLS.
    #[arg(long, default_value = DEFAULT_ADDR)]
    pub addr: SocketAddr,
    /// Fits that run at once [default: the number of cores].
    #[arg(long)]
    pub workers: Option<usize>,
    /// Requests that may wait for a worker; more are answered 503 with Retry-After.
    #[arg(long, default_value_t = DEFAULT_QUEUE_DEPTH)]
    pub queue_depth: usize,
    /// Seconds from a request's admission to its answer; later is answered 504.
    #[arg(long, default_value_t = DEFAULT_DEADLINE.as_secs_f64())]
    pub deadline: f64,
    /// Largest request body in bytes; larger is answered 413.
    #[arg(long, default_value_t = DEFAULT_MAX_BODY_BYTES)]
    pub max_body: usize,
    /// Most strokes per request.
    #[arg(long, default_value_t = DEFAULT_MAX_STROKES)]
    pub max_strokes: usize,
    /// Most samples per stroke.
    #[arg(long, default_value_t = DEFAULT_MAX_SAMPLES_PER_STROKE)]
    pub max_samples: usize,
}

impl ServeArgs {
    /// The options these arguments give, or why they are refused.
    pub fn options(&self) -> Result<ServeOptions, String> {
        if !(self.deadline.is_finite() && self.deadline > 0.0 && self.deadline < 1e9) {
            return Err(format!(
                "--deadline must be a positive number of seconds, got {}",
                self.deadline
            ));
        }
        let options = ServeOptions {
            addr: self.addr,
            max_body_bytes: self.max_body,
            max_strokes: self.max_strokes,
            max_samples_per_stroke: self.max_samples,
            deadline: Duration::from_secs_f64(self.deadline),
            queue_depth: self.queue_depth,
            workers: self.workers.unwrap_or_else(default_workers),
        };
        options.validate()?;
        Ok(options)
    }
}
