//! `GET /v1/stream`: a WebSocket on which a client sends a stroke's samples as the pen moves and
//! gets the growing fit back (previews), then the final fit at pen-up.
//!
//! Client to server, JSON text messages:
//! - `{"type": "samples", "samples": [{"x": .., "y": .., "t": .., "pressure": .., ...}]}`:
//!   samples appended to the stroke being drawn (the first starts it); the fields of a
//!   `kansei-stroke` sample.
//! - `{"type": "end"}`: pen-up. The stroke is fitted and answered with `final` or `error`.
//! - `{"type": "cancel"}`: the stroke is dropped without an answer.
//!
//! Server to client:
//! - `{"type": "preview", "stroke": n, "samples": k, "curve": {kansei-curve}}`: the fit of the
//!   stroke's first `k` samples. One preview is computed at a time per connection; when it
//!   lands and at least [`PREVIEW_NEW_SAMPLES`] samples have arrived since, the next starts, so
//!   previews come as fast as the server fits them. A preview that would wait for a busy
//!   server is skipped.
//! - `{"type": "final", "stroke": n, "samples": k, "curve": {kansei-curve}}`: the answer to
//!   `end`: the document `/v1/fit` gives for a file of this one stroke (its `stroke` fields 0).
//! - `{"type": "error", "stroke": n, "status": 400, "error": "..", "final": b}`: `final` true
//!   answers an `end`; false reports a malformed message (ignored) or a stroke refused as it
//!   arrives (invalid samples, `400`, or too many, `413`), whose later samples are ignored and
//!   whose `end` is answered with the same error.
//!
//! `n` counts the connection's strokes from 0 (each `end` or `cancel` closes one). The fit
//! options are the query parameters of `/v1/fit`, plus `units` (`px`, the default; `mm`,
//! `device`).

use axum::extract::ws::{Message, WebSocket, WebSocketUpgrade};
use axum::extract::{RawQuery, State};
use axum::response::Response;
use serde::Deserialize;
use tokio::task::JoinHandle;

use super::error::ApiError;
use super::fit::{RequestLimits, stroke_document};
use super::params::{FIT_PARAMS, Params};
use super::routes::AppState;
use crate::pipeline::PipelineOptions;
use crate::stroke::{Sample, Units};

/// New samples needed before the next preview.
pub const PREVIEW_NEW_SAMPLES: usize = 4;
/// Samples a stroke needs before its first preview.
pub const PREVIEW_MIN_SAMPLES: usize = 8;

/// A client's message.
#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
enum ClientMessage {
    Samples { samples: Vec<Sample> },
    End,
    Cancel,
}

/// The connection's settings, from the query.
#[derive(Clone, Debug)]
struct Settings {
    options: PipelineOptions,
    units: Units,
    lcg: bool,
    limits: RequestLimits,
}

impl Settings {
    /// The compact document of a stroke of `samples` under these settings (a preview's or the
    /// final fit's; see [`stroke_document`]).
    fn document(&self, samples: Vec<crate::stroke::Sample>) -> Result<String, ApiError> {
        stroke_document(samples, self.units, &self.options, self.lcg, &self.limits)
    }
}

/// `GET /v1/stream`: the WebSocket upgrade, after the query is checked.
pub async fn upgrade(
    State(state): State<AppState>,
    RawQuery(query): RawQuery,
    ws: Result<WebSocketUpgrade, axum::extract::ws::rejection::WebSocketUpgradeRejection>,
) -> Result<Response, ApiError> {
    let mut allowed = FIT_PARAMS.to_vec();
    allowed.push("units");
    let params = Params::parse(query.as_deref(), &allowed)?;
    let settings = Settings {
        options: params.pipeline_options()?,
        units: params.units()?,
        lcg: params.lcg()?,
        limits: state.limits,
    };
    let ws = ws.map_err(|e| ApiError::new(e.status(), e.body_text()))?;
    Ok(ws
        .max_message_size(state.max_body_bytes)
        .on_upgrade(move |socket| Session::new(state, settings).run(socket)))
}

/// A preview being computed: the samples it fits and its task.
struct Preview {
    samples: usize,
    task: JoinHandle<Result<String, ApiError>>,
}

/// One connection's state.
struct Session {
    state: AppState,
    settings: Settings,
    /// Strokes closed so far: the current stroke's number.
    stroke: usize,
    samples: Vec<Sample>,
    /// Why the current stroke was refused, if it was.
    refused: Option<ApiError>,
    preview: Option<Preview>,
    /// Samples the newest preview sent covered.
    previewed: usize,
}

/// Waits for the preview, if any (never returns without one).
async fn preview_done(preview: &mut Option<Preview>) -> (usize, Result<String, ApiError>) {
    match preview {
        Some(p) => {
            let result = (&mut p.task)
                .await
                .unwrap_or_else(|e| Err(ApiError::internal(e.to_string())));
            (p.samples, result)
        }
        None => std::future::pending().await,
    }
}

impl Session {
    fn new(state: AppState, settings: Settings) -> Self {
        Session {
            state,
            settings,
            stroke: 0,
            samples: Vec::new(),
            refused: None,
            preview: None,
            previewed: 0,
        }
    }

    async fn run(mut self, mut socket: WebSocket) {
        let mut shutdown = self.state.shutdown.clone();
        loop {
            let sent = tokio::select! {
                message = socket.recv() => match message {
                    Some(Ok(Message::Text(text))) => self.on_text(text.as_str()).await,
                    Some(Ok(Message::Binary(_))) => vec![self.error_message(
                        &ApiError::bad_request("binary messages are not understood; send JSON text"),
                        false,
                    )],
                    Some(Ok(Message::Close(_))) | None | Some(Err(_)) => break,
                    Some(Ok(_)) => Vec::new(),
                },
                (samples, result) = preview_done(&mut self.preview) => {
                    self.preview = None;
                    let mut out = Vec::new();
                    match result {
                        Ok(doc) => {
                            self.previewed = samples;
                            out.push(self.fit_message("preview", samples, &doc));
                        }
                        // A preview that found the stroke invalid refuses it; a busy server
                        // or a late deadline only skips the preview.
                        Err(e) if e.status.is_client_error() => {
                            out.push(self.error_message(&e, false));
                            self.refused = Some(e);
                        }
                        Err(_) => {}
                    }
                    self.start_preview();
                    out
                }
                _ = shutdown.changed() => {
                    let _ = socket.send(Message::Close(Some(axum::extract::ws::CloseFrame {
                        code: axum::extract::ws::close_code::AWAY,
                        reason: "the server is shutting down".into(),
                    }))).await;
                    break;
                }
            };
            for text in sent {
                if socket.send(Message::text(text)).await.is_err() {
                    return;
                }
            }
        }
        if let Some(p) = self.preview.take() {
            p.task.abort();
        }
    }

    async fn on_text(&mut self, text: &str) -> Vec<String> {
        let message = match serde_json::from_str::<ClientMessage>(text) {
            Ok(m) => m,
            Err(e) => {
                let e = ApiError::bad_request(format!("the message is not understood: {e}"));
                return vec![self.error_message(&e, false)];
            }
        };
        match message {
            ClientMessage::Samples { samples } => {
                if self.refused.is_some() {
                    return Vec::new();
                }
                self.samples.extend(samples);
                let limit = self.settings.limits.max_samples_per_stroke;
                if self.samples.len() > limit {
                    let e = ApiError::too_large(format!(
                        "stroke 0: {} samples, more than the {limit} a stroke may hold",
                        self.samples.len()
                    ));
                    let out = vec![self.error_message(&e, false)];
                    self.refused = Some(e);
                    self.samples = Vec::new();
                    return out;
                }
                self.start_preview();
                Vec::new()
            }
            ClientMessage::Cancel => {
                self.close_stroke();
                Vec::new()
            }
            ClientMessage::End => {
                let answer = match self.refused.take() {
                    Some(e) => self.error_message(&e, true),
                    None => {
                        if let Some(p) = self.preview.take() {
                            p.task.abort();
                        }
                        let samples = std::mem::take(&mut self.samples);
                        let n = samples.len();
                        let settings = self.settings.clone();
                        let result = self
                            .state
                            .pool
                            .run("fitting", move || settings.document(samples))
                            .await;
                        match result {
                            Ok(doc) => self.fit_message("final", n, &doc),
                            Err(e) => self.error_message(&e, true),
                        }
                    }
                };
                self.close_stroke();
                vec![answer]
            }
        }
    }

    /// Starts a preview when none runs and enough new samples have come.
    fn start_preview(&mut self) {
        let n = self.samples.len();
        if self.preview.is_some()
            || self.refused.is_some()
            || n < PREVIEW_MIN_SAMPLES
            || n < self.previewed + PREVIEW_NEW_SAMPLES
        {
            return;
        }
        let samples = self.samples.clone();
        let settings = self.settings.clone();
        let pool = self.state.pool.clone();
        let task = tokio::spawn(async move {
            pool.run("fitting a preview", move || settings.document(samples))
                .await
        });
        self.preview = Some(Preview { samples: n, task });
    }

    fn close_stroke(&mut self) {
        if let Some(p) = self.preview.take() {
            p.task.abort();
        }
        self.samples = Vec::new();
        self.refused = None;
        self.previewed = 0;
        self.stroke += 1;
    }

    fn fit_message(&self, kind: &str, samples: usize, doc: &str) -> String {
        format!(
            "{{\"type\":\"{kind}\",\"stroke\":{},\"samples\":{samples},\"curve\":{doc}}}",
            self.stroke
        )
    }

    fn error_message(&self, e: &ApiError, last: bool) -> String {
        serde_json::json!({
            "type": "error",
            "stroke": self.stroke,
            "status": e.status.as_u16(),
            "error": e.message,
            "final": last,
        })
        .to_string()
    }
}
