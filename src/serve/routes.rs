//! The endpoints: [`router`] maps paths to handlers; each handler reads its query parameters
//! ([`Params`]) and body, and runs the work on the [`FitPool`].

use axum::Router;
use axum::body::Bytes;
use axum::extract::rejection::{BytesRejection, FailedToBufferBody};
use axum::extract::{DefaultBodyLimit, RawQuery, State};
use axum::http::{HeaderValue, Method, StatusCode, Uri, header};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};

use super::error::ApiError;
use super::fit::{RequestLimits, export, fit, read_request};
use super::limits::FitPool;
use super::options::ServeOptions;
use super::page;
use super::params::{FIT_PARAMS, PNG_LAYERS, Params, SVG_LAYERS};
use super::stream;
use crate::export::{ExportOptions, Format, FormatOptions, PngOptions, SvgLayers};
use crate::pipeline::PipelineOptions;
use crate::render::{Overlays, RenderOptions};

/// What every handler shares: the pool and the limits.
#[derive(Clone, Debug)]
pub struct AppState {
    /// The workers and their queue.
    pub pool: FitPool,
    /// Strokes and samples per request.
    pub limits: RequestLimits,
    /// Largest body or streaming message, bytes.
    pub max_body_bytes: usize,
    /// The options the server runs with (reported by `/v1/health`).
    pub options: ServeOptions,
    /// Turns true when the server stops: streams close.
    pub shutdown: tokio::sync::watch::Receiver<bool>,
}

/// The service's routes (see `docs/service.md`); `shutdown` turning true closes the streams.
pub fn router(options: &ServeOptions, shutdown: tokio::sync::watch::Receiver<bool>) -> Router {
    let state = AppState {
        pool: FitPool::new(options),
        limits: RequestLimits::of(options),
        max_body_bytes: options.max_body_bytes,
        options: options.clone(),
        shutdown,
    };
    Router::new()
        .route("/", get(page::index))
        .route("/app.js", get(page::script))
        .route("/style.css", get(page::style))
        .route("/v1/health", get(health))
        .route("/v1/fit", post(fit_endpoint))
        .route("/v1/export/svg", post(export_svg))
        .route("/v1/export/dxf", post(export_dxf))
        .route("/v1/export/png", post(export_png))
        .route("/v1/stream", get(stream::upgrade))
        .fallback(not_found)
        .method_not_allowed_fallback(method_not_allowed)
        .layer(axum::middleware::from_fn_with_state(
            options.max_body_bytes,
            declared_length,
        ))
        .layer(DefaultBodyLimit::max(options.max_body_bytes))
        .with_state(state)
}

/// `413` at once for a body whose declared `Content-Length` exceeds the limit, before any of it
/// is read (a body without one is cut off at the limit as it arrives).
async fn declared_length(
    State(limit): State<usize>,
    request: axum::extract::Request,
    next: axum::middleware::Next,
) -> Response {
    let declared = request
        .headers()
        .get(header::CONTENT_LENGTH)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.trim().parse::<u64>().ok());
    match declared {
        Some(n) if n > limit as u64 => too_large(limit).into_response(),
        _ => next.run(request).await,
    }
}

fn too_large(limit: usize) -> ApiError {
    ApiError::too_large(format!(
        "the body is larger than the {limit} bytes a request may hold"
    ))
}

/// `GET /v1/health`.
async fn health(State(state): State<AppState>) -> Response {
    let o = &state.options;
    let body = serde_json::json!({
        "status": "ok",
        "service": "kansei",
        "version": env!("CARGO_PKG_VERSION"),
        "workers": o.workers,
        "queue_depth": o.queue_depth,
        "busy": state.pool.busy(),
        "limits": {
            "max_body_bytes": o.max_body_bytes,
            "max_strokes": o.max_strokes,
            "max_samples_per_stroke": o.max_samples_per_stroke,
            "deadline_s": o.deadline.as_secs_f64(),
        },
    });
    json_response(body.to_string())
}

/// Anything else: `404` with the JSON error body.
async fn not_found(method: Method, uri: Uri) -> ApiError {
    ApiError::new(
        StatusCode::NOT_FOUND,
        format!("no endpoint {method} {}; see docs/service.md", uri.path()),
    )
}

/// `405` with a JSON error body, as every other error (an endpoint asked with a method it does
/// not take: `GET /v1/fit`).
async fn method_not_allowed(method: Method, uri: Uri) -> ApiError {
    ApiError::new(
        StatusCode::METHOD_NOT_ALLOWED,
        format!("{} does not take {method}; see docs/service.md", uri.path()),
    )
}

fn json_response(body: impl IntoResponse) -> Response {
    ([(header::CONTENT_TYPE, "application/json")], body).into_response()
}

/// A file to download: its type and a file name.
fn file_response(content_type: &'static str, name: &str, body: impl IntoResponse) -> Response {
    let mut r = ([(header::CONTENT_TYPE, content_type)], body).into_response();
    if let Ok(v) = HeaderValue::from_str(&format!("attachment; filename=\"{name}\"")) {
        r.headers_mut().insert(header::CONTENT_DISPOSITION, v);
    }
    r
}

/// The body, or `413` past the limit, `400` when it could not be read.
fn body(body: Result<Bytes, BytesRejection>, limit: usize) -> Result<Bytes, ApiError> {
    body.map_err(|e| match e {
        BytesRejection::FailedToBufferBody(FailedToBufferBody::LengthLimitError(_)) => {
            too_large(limit)
        }
        other => {
            ApiError::bad_request(format!("the body could not be read: {}", other.body_text()))
        }
    })
}

/// The fit options and these extra names.
fn allowed(extra: &[&'static str]) -> Vec<&'static str> {
    FIT_PARAMS
        .iter()
        .filter(|&&n| n != "lcg")
        .chain(extra)
        .copied()
        .collect()
}

/// `POST /v1/fit`: the `kansei-curve` document `kansei fit` writes.
async fn fit_endpoint(
    State(state): State<AppState>,
    RawQuery(query): RawQuery,
    bytes: Result<Bytes, BytesRejection>,
) -> Result<Response, ApiError> {
    let params = Params::parse(query.as_deref(), &FIT_PARAMS)?;
    let options = params.pipeline_options()?;
    let lcg = params.lcg()?;
    let bytes = body(bytes, state.max_body_bytes)?;
    let limits = state.limits;
    let (json, below) = state
        .pool
        .run("fitting", move || {
            let file = read_request(&bytes, &limits)?;
            let output = fit(&file, &options)?;
            let formats = FormatOptions {
                json: ExportOptions { lcg },
                ..FormatOptions::default()
            };
            let json = export(Format::Json, &file, &output, &formats)?;
            Ok((json, output.below_floor()))
        })
        .await?;
    let mut response = json_response(json);
    // A tolerance below some strokes' noise floor is honoured, with a warning (RFC 9111's
    // Warning header is obsolete for caches, but code 299 still says "persistent warning").
    if let Some(below) = below
        && let Ok(v) = HeaderValue::from_str(&format!("299 kansei \"{below}\""))
    {
        response.headers_mut().insert(header::WARNING, v);
    }
    Ok(response)
}

/// `POST /v1/export/svg`.
async fn export_svg(
    State(state): State<AppState>,
    RawQuery(query): RawQuery,
    bytes: Result<Bytes, BytesRejection>,
) -> Result<Response, ApiError> {
    let params = Params::parse(query.as_deref(), &allowed(&["layers", "accuracy"]))?;
    let options = params.pipeline_options()?;
    let formats = FormatOptions {
        accuracy: params.accuracy()?,
        svg_layers: SvgLayers::named(&params.layers(&SVG_LAYERS)?.unwrap_or_default()),
        ..FormatOptions::default()
    };
    let what = "fitting and writing the SVG";
    export_file(&state, Format::Svg, options, formats, bytes, what).await
}

/// `POST /v1/export/dxf`.
async fn export_dxf(
    State(state): State<AppState>,
    RawQuery(query): RawQuery,
    bytes: Result<Bytes, BytesRejection>,
) -> Result<Response, ApiError> {
    let params = Params::parse(query.as_deref(), &allowed(&["accuracy"]))?;
    let options = params.pipeline_options()?;
    let formats = FormatOptions {
        accuracy: params.accuracy()?,
        ..FormatOptions::default()
    };
    let what = "fitting and writing the DXF";
    export_file(&state, Format::Dxf, options, formats, bytes, what).await
}

/// `POST /v1/export/png`.
async fn export_png(
    State(state): State<AppState>,
    RawQuery(query): RawQuery,
    bytes: Result<Bytes, BytesRejection>,
) -> Result<Response, ApiError> {
    let params = Params::parse(query.as_deref(), &allowed(&["layers", "size"]))?;
    let options = params.pipeline_options()?;
    let size = params.size()?;
    let render = RenderOptions::with_overlays(
        params
            .layers(&PNG_LAYERS)?
            .as_deref()
            .map_or_else(Overlays::default, Overlays::named),
    );
    let formats = FormatOptions {
        png: PngOptions::default().with_size(size).with_render(render),
        ..FormatOptions::default()
    };
    let what = "fitting and drawing the PNG";
    export_file(&state, Format::Png, options, formats, bytes, what).await
}

/// An export endpoint's work once its query is read: the body read, fitted with `options` and
/// written in `format` with `formats` on the pool (`what` names the work in its errors), sent
/// as a download `kansei.EXTENSION` of the format's media type.
async fn export_file(
    state: &AppState,
    format: Format,
    options: PipelineOptions,
    formats: FormatOptions,
    bytes: Result<Bytes, BytesRejection>,
    what: &str,
) -> Result<Response, ApiError> {
    let bytes = body(bytes, state.max_body_bytes)?;
    let limits = state.limits;
    let data = state
        .pool
        .run(what, move || {
            let file = read_request(&bytes, &limits)?;
            let output = fit(&file, &options)?;
            export(format, &file, &output, &formats)
        })
        .await?;
    let name = format!("kansei.{}", format.extension());
    Ok(file_response(format.mime_type(), &name, data))
}
