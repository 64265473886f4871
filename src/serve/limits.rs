//! The fit pool: a bounded queue in front of a fixed number of workers on tokio's blocking
//! pool, a deadline per request, and panics contained to the request that caused them.
//!
//! A request is admitted while fewer than `workers + queue_depth` are queued or running,
//! else answered `503` with `Retry-After` at once. An admitted request waits for a worker, then
//! runs on a thread of the blocking pool (the async threads never fit, so the server keeps
//! answering while every worker is busy). The deadline runs from admission: a request still
//! waiting when it passes is dropped without running; one running is answered `504` while its
//! fit runs to its end (a fit cannot be interrupted) and keeps its worker until then, so the
//! pool never runs more than `workers` fits.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;
use std::time::Duration;

use axum::http::StatusCode;
use tokio::sync::Semaphore;

use super::error::ApiError;
use super::options::ServeOptions;

/// Seconds a client is asked to wait after a `503` (`Retry-After`).
pub const RETRY_AFTER_S: u32 = 1;

/// The bounded queue and the workers (see the module documentation).
#[derive(Clone, Debug)]
pub struct FitPool {
    admission: Arc<Semaphore>,
    workers: Arc<Semaphore>,
    capacity: usize,
    deadline: Duration,
}

impl FitPool {
    /// A pool with the workers, queue depth and deadline of `options`.
    pub fn new(options: &ServeOptions) -> Self {
        let capacity = options.workers.saturating_add(options.queue_depth);
        FitPool {
            admission: Arc::new(Semaphore::new(capacity)),
            workers: Arc::new(Semaphore::new(options.workers)),
            capacity,
            deadline: options.deadline,
        }
    }

    /// Requests queued or running now.
    pub fn busy(&self) -> usize {
        self.capacity - self.admission.available_permits()
    }

    /// Runs `job` on a worker: `503` when the queue is full, `504` past the deadline, `500` if
    /// the job panics (the panic is printed on stderr by the panic hook, and logged here with
    /// the message answered).
    pub async fn run<T, F>(&self, what: &str, job: F) -> Result<T, ApiError>
    where
        T: Send + 'static,
        F: FnOnce() -> Result<T, ApiError> + Send + 'static,
    {
        let Ok(admitted) = Arc::clone(&self.admission).try_acquire_owned() else {
            let mut e = ApiError::new(
                StatusCode::SERVICE_UNAVAILABLE,
                format!(
                    "the server is busy: {} requests are queued or running; try again later",
                    self.capacity
                ),
            );
            e.retry_after = Some(RETRY_AFTER_S);
            return Err(e);
        };
        let workers = Arc::clone(&self.workers);
        let what_owned = what.to_owned();
        let work = async move {
            let running = workers
                .acquire_owned()
                .await
                .map_err(|_| ApiError::internal("the fit pool is closed"))?;
            let handle = tokio::task::spawn_blocking(move || {
                // Both permits are released when the job ends, not when its request gives up.
                let _permits = (admitted, running);
                catch_unwind(AssertUnwindSafe(job))
            });
            match handle.await {
                Ok(Ok(result)) => result,
                Ok(Err(panic)) => {
                    let message = format!(
                        "internal error while {what_owned}: {}; this is a defect of kansei, \
                         please report it with the request",
                        panic_message(panic.as_ref())
                    );
                    eprintln!("kansei serve: 500: {message}");
                    Err(ApiError::internal(message))
                }
                Err(e) => Err(ApiError::internal(format!(
                    "internal error while {what_owned}: {e}"
                ))),
            }
        };
        match tokio::time::timeout(self.deadline, work).await {
            Ok(result) => result,
            Err(_) => Err(ApiError::new(
                StatusCode::GATEWAY_TIMEOUT,
                format!(
                    "{what} took longer than the deadline of {} s",
                    self.deadline.as_secs_f64()
                ),
            )),
        }
    }
}

/// The text a panic was raised with.
pub fn panic_message(panic: &(dyn std::any::Any + Send)) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pool(workers: usize, queue_depth: usize, deadline_ms: u64) -> FitPool {
        FitPool::new(&ServeOptions {
            workers,
            queue_depth,
            deadline: Duration::from_millis(deadline_ms),
            ..ServeOptions::default()
        })
    }

    fn runtime() -> tokio::runtime::Runtime {
        tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .enable_all()
            .build()
            .expect("a tokio runtime for the test")
    }

    #[test]
    fn a_panic_is_answered_500_and_the_pool_keeps_working() {
        runtime().block_on(async {
            let p = pool(1, 0, 5000);
            let e = p
                .run("fitting", || -> Result<(), ApiError> { panic!("planted") })
                .await
                .expect_err("a panic is an error");
            assert_eq!(e.status, StatusCode::INTERNAL_SERVER_ERROR);
            assert!(e.message.contains("planted"), "{}", e.message);
            assert_eq!(p.run("fitting", || Ok(7)).await, Ok(7));
            assert_eq!(p.busy(), 0);
        });
    }

    #[test]
    fn a_full_queue_is_answered_503_with_retry_after() {
        runtime().block_on(async {
            let p = pool(1, 1, 5000);
            let (tx, rx) = std::sync::mpsc::channel::<()>();
            let rx = Arc::new(std::sync::Mutex::new(rx));
            let hold = |rx: Arc<std::sync::Mutex<std::sync::mpsc::Receiver<()>>>| {
                move || {
                    let _ = rx.lock().map(|r| r.recv());
                    Ok(())
                }
            };
            let (a, b) = (p.clone(), p.clone());
            let first = tokio::spawn({
                let job = hold(Arc::clone(&rx));
                async move { a.run("fitting", job).await }
            });
            let second = tokio::spawn({
                let job = hold(Arc::clone(&rx));
                async move { b.run("fitting", job).await }
            });
            while p.busy() < 2 {
                tokio::time::sleep(Duration::from_millis(5)).await;
            }
            let e = p
                .run("fitting", || Ok(()))
                .await
                .expect_err("the third is refused");
            assert_eq!(e.status, StatusCode::SERVICE_UNAVAILABLE);
            assert_eq!(e.retry_after, Some(RETRY_AFTER_S));
            tx.send(()).expect("first job waits");
            tx.send(()).expect("second job waits");
            assert_eq!(first.await.ok(), Some(Ok(())));
            assert_eq!(second.await.ok(), Some(Ok(())));
        });
    }

    #[test]
    fn past_the_deadline_is_answered_504() {
        runtime().block_on(async {
            let p = pool(1, 4, 50);
            let e = p
                .run("fitting", || {
                    std::thread::sleep(Duration::from_millis(300));
                    Ok(())
                })
                .await
                .expect_err("too slow");
            assert_eq!(e.status, StatusCode::GATEWAY_TIMEOUT);
            // The slow job keeps its worker until it ends.
            assert_eq!(p.busy(), 1);
            tokio::time::sleep(Duration::from_millis(400)).await;
            assert_eq!(p.busy(), 0);
        });
    }
}
