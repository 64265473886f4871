//! `kansei serve`: the fitting service. An HTTP API that fits `kansei-stroke` documents and
//! exports them (JSON, SVG, DXF, PNG), a WebSocket that fits a stroke while it is drawn, and the
//! pen page, which makes any tablet with a browser a kansei tablet (Pointer Events deliver
//! pressure and tilt on every OS). The API is documented in `docs/service.md`.
//!
//! - [`options`]: [`ServeOptions`], the address and limits, with their defaults.
//! - [`routes`]: the endpoints; [`stream`]: the WebSocket; [`page`]: the embedded page.
//! - [`fit`]: what the endpoints compute (strict reading, fit, documents, exports).
//! - [`limits`]: the bounded queue, the workers on the blocking pool, the deadline, panics
//!   contained; [`params`]: query parameters; [`error`]: `{"error": "..."}` answers.
//!
//! [`run`] serves until SIGINT or SIGTERM and then drains the requests in flight; [`spawn`]
//! serves on a thread of its own until [`Server::stop`] (tests, the load generator). No
//! endpoint reads or writes the server's file system.
//!
//! Built on axum and tokio (feature `serve`); nothing outside this module uses them.

pub mod error;
pub mod fit;
pub mod limits;
pub mod options;
pub mod page;
pub mod params;
pub mod routes;
pub mod stream;

use std::future::Future;
use std::net::SocketAddr;
use std::time::Duration;

use tokio::net::TcpListener;
use tokio::sync::watch;

pub use error::ApiError;
pub use options::{ServeArgs, ServeOptions};

/// Time allowed past the deadline for the requests in flight to be answered once the server
/// is told to stop; then it exits regardless.
pub const DRAIN_GRACE: Duration = Duration::from_secs(5);

/// Why the server could not run.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// The options are refused.
    #[error("{0}")]
    Options(String),
    /// The address could not be bound.
    #[error("cannot listen on {addr}: {source}")]
    Bind {
        /// The address.
        addr: SocketAddr,
        /// The cause.
        source: std::io::Error,
    },
    /// The runtime or the listener failed.
    #[error("the server failed: {0}")]
    Io(#[from] std::io::Error),
}

/// The warning printed when `addr` is not a loopback address, or `None`.
pub fn exposure_warning(addr: SocketAddr) -> Option<String> {
    (!addr.ip().is_loopback()).then(|| {
        format!(
            "warning: kansei serve listens on {addr}, beyond this machine: anyone who can reach \
             it can use the service (it has no authentication and no TLS)"
        )
    })
}

fn runtime(options: &ServeOptions) -> Result<tokio::runtime::Runtime, ServeError> {
    options.validate().map_err(ServeError::Options)?;
    Ok(tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .thread_name("kansei-serve")
        // The pool admits `workers` fits at once; the blocking threads are theirs.
        .max_blocking_threads(options.workers)
        .build()?)
}

async fn bind(addr: SocketAddr) -> Result<TcpListener, ServeError> {
    TcpListener::bind(addr)
        .await
        .map_err(|source| ServeError::Bind { addr, source })
}

/// Serves on `listener` until `stop` completes, then lets the requests in flight finish (at
/// most the deadline and [`DRAIN_GRACE`]) and closes the streams.
async fn serve_until(
    listener: TcpListener,
    options: ServeOptions,
    stop: impl Future<Output = ()> + Send + 'static,
) -> Result<(), ServeError> {
    let (tx, rx) = watch::channel(false);
    let app = routes::router(&options, rx.clone());
    let signal = async move {
        stop.await;
        let _ = tx.send(true);
    };
    let server = axum::serve(listener, app).with_graceful_shutdown(signal);
    let mut stopped = rx;
    let overdue = async move {
        let _ = stopped.wait_for(|s| *s).await;
        tokio::time::sleep(options.deadline + DRAIN_GRACE).await;
    };
    tokio::select! {
        r = server => r.map_err(ServeError::Io),
        () = overdue => {
            eprintln!("kansei serve: requests still open after the drain time; exiting");
            Ok(())
        }
    }
}

/// SIGINT (Ctrl-C) or SIGTERM.
async fn termination() {
    #[cfg(unix)]
    {
        use tokio::signal::unix::{SignalKind, signal};
        match signal(SignalKind::terminate()) {
            Ok(mut term) => {
                tokio::select! {
                    _ = tokio::signal::ctrl_c() => {}
                    _ = term.recv() => {}
                }
            }
            Err(_) => {
                let _ = tokio::signal::ctrl_c().await;
            }
        }
    }
    #[cfg(not(unix))]
    {
        let _ = tokio::signal::ctrl_c().await;
    }
}

/// `kansei serve`: listens on `options.addr` (printing where, and a warning beyond loopback),
/// serves until SIGINT or SIGTERM, drains the requests in flight and returns.
pub fn run(options: ServeOptions) -> Result<(), ServeError> {
    let rt = runtime(&options)?;
    let deadline = options.deadline;
    let result = rt.block_on(async move {
        let listener = bind(options.addr).await?;
        let addr = listener.local_addr()?;
        if let Some(w) = exposure_warning(addr) {
            eprintln!("{w}");
        }
        eprintln!(
            "kansei serve: http://{addr}/ ({} workers, queue of {}); Ctrl-C to stop",
            options.workers, options.queue_depth
        );
        serve_until(listener, options, async {
            termination().await;
            eprintln!("kansei serve: stopping; answering the requests in flight");
        })
        .await
    });
    // Fits past their deadline may still run on the blocking pool: give them a moment.
    rt.shutdown_timeout(deadline);
    result
}

/// A server running on a thread of its own ([`spawn`]); dropping it stops it.
#[derive(Debug)]
pub struct Server {
    addr: SocketAddr,
    stop: Option<tokio::sync::oneshot::Sender<()>>,
    thread: Option<std::thread::JoinHandle<Result<(), ServeError>>>,
}

impl Server {
    /// The address it listens on (the bound port when `options.addr` asked for port 0).
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// Stops it as SIGTERM stops [`run`] and waits for it to end.
    pub fn stop(mut self) -> Result<(), ServeError> {
        self.stop_and_join()
    }

    fn stop_and_join(&mut self) -> Result<(), ServeError> {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
        match self.thread.take().map(std::thread::JoinHandle::join) {
            Some(Ok(result)) => result,
            Some(Err(_)) => Err(ServeError::Io(std::io::Error::other(
                "the server thread panicked",
            ))),
            None => Ok(()),
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.stop_and_join();
    }
}

/// Starts a server on a thread of its own and returns once it listens (bind to port 0 for a
/// free port; [`Server::addr`] tells which). For tests and the load generator.
pub fn spawn(options: ServeOptions) -> Result<Server, ServeError> {
    let rt = runtime(&options)?;
    let (ready_tx, ready_rx) = std::sync::mpsc::channel();
    let (stop_tx, stop_rx) = tokio::sync::oneshot::channel::<()>();
    let thread = std::thread::Builder::new()
        .name("kansei-serve".into())
        .spawn(move || {
            let deadline = options.deadline;
            let result = rt.block_on(async move {
                let listener = match bind(options.addr).await {
                    Ok(l) => l,
                    Err(e) => {
                        let _ = ready_tx.send(Err(e));
                        return Ok(());
                    }
                };
                let _ = ready_tx.send(listener.local_addr().map_err(ServeError::Io));
                serve_until(listener, options, async {
                    let _ = stop_rx.await;
                })
                .await
            });
            rt.shutdown_timeout(deadline);
            result
        })?;
    let addr = ready_rx
        .recv()
        .map_err(|_| ServeError::Io(std::io::Error::other("the server thread ended early")))??;
    Ok(Server {
        addr,
        stop: Some(stop_tx),
        thread: Some(thread),
    })
}
