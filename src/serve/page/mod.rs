//! The pen page, `GET /`: HTML, CSS and JavaScript embedded in the binary (no CDN, no build
//! step). It draws with pen, mouse or touch through Pointer Events (every coalesced sample,
//! with pressure and tilt), streams the samples to `/v1/stream` and draws the growing fit, and
//! the final one at pen-up, as the LAC chain coloured by α, with an optional curvature comb and
//! the split and joint markers. Its last fit document is `window.kansei.lastFit` (the browser
//! test reads it).

use axum::http::header;
use axum::response::{IntoResponse, Response};

/// The page.
pub const INDEX_HTML: &str = include_str!("index.html");
/// Its style sheet, `/style.css`.
pub const STYLE_CSS: &str = include_str!("style.css");
/// Its script, `/app.js`.
pub const APP_JS: &str = include_str!("app.js");

fn asset(content_type: &'static str, body: &'static str) -> Response {
    (
        [
            (header::CONTENT_TYPE, content_type),
            (header::CACHE_CONTROL, "no-cache"),
        ],
        body,
    )
        .into_response()
}

/// `GET /`.
pub async fn index() -> Response {
    asset("text/html; charset=utf-8", INDEX_HTML)
}

/// `GET /app.js`.
pub async fn script() -> Response {
    asset("text/javascript; charset=utf-8", APP_JS)
}

/// `GET /style.css`.
pub async fn style() -> Response {
    asset("text/css; charset=utf-8", STYLE_CSS)
}
