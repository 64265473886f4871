//! The pen page in a real browser: headless Chromium opens `GET /`, pen pointer events
//! (pointerType `pen`, pressure, tilt) are dispatched through the DevTools protocol along a
//! planted curve, and the page shows the fitted chain: its last fit document
//! (`window.kansei.lastFit`) equals `/v1/fit` of the samples the page recorded, previews came
//! while the pen moved, and a screenshot has ink along the chain and none far from it.
//!
//! The DevTools protocol is spoken over a plain WebSocket (tungstenite, already in the tree for
//! axum), so no browser-automation crate is needed. Skipped with a message when no `chromium`
//! runs here; `.ci/run` installs Debian's `chromium` and sets `KANSEI_REQUIRE_CHROMIUM=1`, and
//! then a missing or failing browser is a failure.

mod common;

use std::io::{BufRead, BufReader};
use std::net::{SocketAddr, TcpStream};
use std::process::Child;
use std::time::{Duration, Instant};

use common::http;
use kansei::export::CurveFile;
use kansei::serve::{ServeOptions, spawn};
use serde_json::{Value, json};
use tiny_skia::Pixmap;
use tungstenite::stream::MaybeTlsStream;
use tungstenite::{Message, WebSocket};

/// Longest wait for the browser to start, the page to load or the fit to come back.
const TIMEOUT: Duration = Duration::from_secs(60);
/// The browser's window, CSS pixels.
const WINDOW: (u32, u32) = (1200, 900);
/// The page's viewport (set through the protocol, device scale 1): room below the toolbar for
/// the planted stroke.
const VIEWPORT: (u32, u32) = (1200, 900);

/// The browser process, killed when dropped.
struct Browser {
    child: Child,
    _profile: std::path::PathBuf,
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Starts headless `name` on `url` and returns it with the DevTools port.
fn launch(name: &str, url: &str) -> (Browser, u16) {
    let profile = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("serve_browser_profile");
    let mut child = common::browser::headless(name, &profile, WINDOW)
        .unwrap_or_else(|e| panic!("{e}"))
        .args([
            "--force-device-scale-factor=1",
            "--remote-debugging-address=127.0.0.1",
            "--remote-debugging-port=0",
        ])
        .arg(url)
        .spawn()
        .unwrap_or_else(|e| panic!("{name} does not start: {e}"));
    let stderr = child.stderr.take().expect("stderr");
    let (tx, rx) = std::sync::mpsc::channel();
    // Reads stderr to its end on its own thread (a full pipe would block the browser).
    std::thread::spawn(move || {
        let mut sent = false;
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            if !sent
                && let Some(rest) = line.split("ws://127.0.0.1:").nth(1)
                && let Some(port) = rest.split('/').next().and_then(|p| p.parse::<u16>().ok())
            {
                let _ = tx.send(port);
                sent = true;
            }
        }
    });
    let browser = Browser {
        child,
        _profile: profile,
    };
    let port = rx
        .recv_timeout(TIMEOUT)
        .unwrap_or_else(|_| panic!("{name} printed no DevTools address"));
    (browser, port)
}

/// A DevTools protocol connection to one page.
struct Page {
    ws: WebSocket<MaybeTlsStream<TcpStream>>,
    next_id: u64,
}

impl Page {
    /// Connects to the page target showing `url`.
    fn connect(port: u16, url: &str) -> Page {
        let devtools = SocketAddr::from(([127, 0, 0, 1], port));
        let started = Instant::now();
        let target = loop {
            let list = http::get(devtools, "/json/list").expect("the target list");
            let targets: Value = list.json();
            let page = targets.as_array().and_then(|t| {
                t.iter()
                    .find(|t| t["type"] == "page" && t["url"].as_str() == Some(url))
                    .and_then(|t| t["webSocketDebuggerUrl"].as_str().map(str::to_owned))
            });
            if let Some(ws) = page {
                break ws;
            }
            assert!(started.elapsed() < TIMEOUT, "no page at {url}: {targets}");
            std::thread::sleep(Duration::from_millis(50));
        };
        let (ws, _) = tungstenite::connect(target.as_str()).expect("the page's DevTools socket");
        Page { ws, next_id: 0 }
    }

    /// Sends a command and returns its result (events on the way are skipped).
    fn call(&mut self, method: &str, params: Value) -> Value {
        self.next_id += 1;
        let id = self.next_id;
        let message = json!({"id": id, "method": method, "params": params}).to_string();
        self.ws.send(Message::text(message)).expect("send");
        loop {
            let m = self.ws.read().expect("a DevTools message");
            let Message::Text(text) = m else { continue };
            let v: Value = serde_json::from_str(text.as_str()).expect("JSON");
            if v["id"] == id {
                assert!(v.get("error").is_none(), "{method}: {v}");
                return v["result"].clone();
            }
        }
    }

    /// Evaluates `expression` in the page and returns its value (JSON-serialisable values).
    fn eval(&mut self, expression: &str) -> Value {
        let r = self.call(
            "Runtime.evaluate",
            json!({"expression": expression, "returnByValue": true, "awaitPromise": true}),
        );
        assert!(r.get("exceptionDetails").is_none(), "{expression}: {r}");
        r["result"]["value"].clone()
    }

    /// Waits until `expression` is true.
    fn wait_for(&mut self, expression: &str) {
        let started = Instant::now();
        while self.eval(expression) != Value::Bool(true) {
            assert!(started.elapsed() < TIMEOUT, "never true: {expression}");
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    fn pen(&mut self, kind: &str, (x, y): (f64, f64), pressure: f64, tilt: (f64, f64)) {
        let buttons = if kind == "mouseReleased" { 0 } else { 1 };
        self.call(
            "Input.dispatchMouseEvent",
            json!({
                "type": kind, "x": x, "y": y, "button": "left", "buttons": buttons,
                "clickCount": 1, "pointerType": "pen", "force": pressure,
                "tiltX": tilt.0, "tiltY": tilt.1, "twist": 30,
            }),
        );
    }
}

/// The planted stroke, in the canvas's CSS pixels: an arc of a spiral (curvature growing along
/// it), with the pen's pressure rising and its tilt turning.
fn planted(i: usize, n: usize) -> ((f64, f64), f64, (f64, f64)) {
    let u = i as f64 / (n - 1) as f64;
    let phi = 3.6 * u;
    let r = 260.0 * (-0.35 * phi).exp();
    let point = (470.0 + r * phi.cos(), 300.0 - r * phi.sin());
    (point, 0.25 + 0.6 * u, (20.0 - 30.0 * u, 10.0 + 15.0 * u))
}

#[test]
fn the_pen_page_fits_a_pen_stroke_like_the_api() {
    let name = match common::browser::browser() {
        Ok(name) => name,
        Err(why) if std::env::var_os("KANSEI_REQUIRE_CHROMIUM").is_some() => {
            panic!("KANSEI_REQUIRE_CHROMIUM is set but {why}")
        }
        Err(why) => {
            eprintln!("skip: {why}; the pen page is not tested in a browser");
            return;
        }
    };
    let server =
        spawn(ServeOptions::at(SocketAddr::from(([127, 0, 0, 1], 0)))).expect("the server starts");
    let url = format!("http://{}/", server.addr());
    let (_browser, port) = launch(name, &url);
    let mut page = Page::connect(port, &url);
    page.wait_for("window.kansei !== undefined && window.kansei.ready === true");
    // A stroke kept by an earlier run (local storage) would be fitted too: start empty.
    page.eval("localStorage.clear(); true");
    page.call("Page.reload", json!({}));
    page.wait_for("window.kansei !== undefined && window.kansei.ready === true");
    page.call(
        "Emulation.setDeviceMetricsOverride",
        json!({"width": VIEWPORT.0, "height": VIEWPORT.1, "deviceScaleFactor": 1, "mobile": false}),
    );
    page.eval("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))");
    let canvas = page.eval(
        "(() => { const r = document.getElementById('ink').getBoundingClientRect(); \
         return [r.left, r.top, r.width, r.height]; })()",
    );
    let origin = (
        canvas[0].as_f64().expect("left"),
        canvas[1].as_f64().expect("top"),
    );
    assert!(canvas[3].as_f64().expect("height") > 600.0, "{canvas}");

    let n = 120;
    let at = |p: (f64, f64)| (p.0 + origin.0, p.1 + origin.1);
    let (p0, f0, t0) = planted(0, n);
    page.pen("mousePressed", at(p0), f0, t0);
    for i in 1..n {
        let (p, f, t) = planted(i, n);
        page.pen("mouseMoved", at(p), f, t);
        std::thread::sleep(Duration::from_millis(4));
    }
    let (p1, f1, t1) = planted(n - 1, n);
    page.pen("mouseReleased", at(p1), f1, t1);
    page.wait_for("window.kansei.finals >= 1");

    let errors = page.eval("window.kansei.errors");
    assert_eq!(errors, json!([]), "the page reported errors");
    let previews = page.eval("window.kansei.previews").as_u64().expect("count");
    assert!(previews >= 1, "the fit grew while the pen moved");
    let stroke_text = page
        .eval("JSON.stringify(window.kansei.lastStroke)")
        .as_str()
        .expect("the page's stroke")
        .to_owned();
    let fit_text = page
        .eval("JSON.stringify(window.kansei.lastFit)")
        .as_str()
        .expect("the page's fit")
        .to_owned();

    // The samples are the pen's: every move, with its pressure and tilt.
    let stroke: Value = serde_json::from_str(&stroke_text).expect("JSON");
    let samples = stroke["strokes"][0]["samples"].as_array().expect("samples");
    assert!(
        samples.len() >= n,
        "{} samples for {n} events",
        samples.len()
    );
    let first = &samples[0];
    assert!(
        (first["x"].as_f64().expect("x") - p0.0).abs() < 1.0,
        "{first}"
    );
    assert!(
        (first["y"].as_f64().expect("y") - p0.1).abs() < 1.0,
        "{first}"
    );
    let pressures: Vec<f64> = samples
        .iter()
        .map(|s| s["pressure"].as_f64().expect("pressure recorded"))
        .collect();
    assert!(
        pressures.iter().all(|p| (0.2..=0.9).contains(p)),
        "{pressures:?}"
    );
    assert!(
        pressures[pressures.len() - 1] > pressures[0] + 0.4,
        "{pressures:?}"
    );
    assert!(
        samples
            .iter()
            .all(|s| s["tilt_x"].is_number() && s["tilt_y"].is_number())
    );
    assert_eq!(first["tilt_x"].as_f64(), Some(t0.0));

    // The page's fit is the API's fit of the same samples.
    let answer = http::post(server.addr(), "/v1/fit", stroke_text.as_bytes()).expect("answers");
    assert_eq!(answer.status, 200, "{}", answer.text());
    let api = CurveFile::from_json(&answer.text()).expect("the API's document");
    let shown = CurveFile::from_json(&fit_text).expect("the page's document");
    assert_eq!(shown, api, "the page shows the API's fit");
    assert_eq!(api.curves.len(), 1);
    assert!(!api.curves[0].segments.is_empty());

    // The screenshot has ink along the chain, and none far from the stroke.
    page.eval("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))");
    let shot = page.call("Page.captureScreenshot", json!({"format": "png"}));
    let png = base64(shot["data"].as_str().expect("screenshot data"));
    let pixmap = Pixmap::decode_png(&png).expect("a PNG screenshot");
    let ink = |x: f64, y: f64| {
        let (x, y) = (x.round() as i64, y.round() as i64);
        if x < 0 || y < 0 || x >= pixmap.width() as i64 || y >= pixmap.height() as i64 {
            return false;
        }
        let p = pixmap.pixel(x as u32, y as u32).expect("inside");
        p.red().min(p.green()).min(p.blue()) < 200
    };
    let near_ink = |x: f64, y: f64| {
        (-2..=2).any(|dx| (-2..=2).any(|dy| ink(x + f64::from(dx), y + f64::from(dy))))
    };
    let mut checked = 0;
    let mut missing = Vec::new();
    for record in &api.curves[0].segments {
        let seg = record.segment().expect("a valid segment");
        let steps = (seg.length() / 3.0).ceil() as usize;
        for k in 0..=steps {
            let p = seg.point(seg.length() * k as f64 / steps as f64);
            let (x, y) = at((p.x, p.y));
            checked += 1;
            if !near_ink(x, y) {
                missing.push((x, y));
            }
        }
    }
    assert!(checked > 100, "{checked} points checked");
    assert!(
        missing.is_empty(),
        "no ink at {} of {checked}: {missing:?}",
        missing.len()
    );
    for far in [
        (60.0, 620.0),
        (900.0, 600.0),
        (930.0, 100.0),
        (470.0, 300.0),
    ] {
        assert!(
            !near_ink(at(far).0, at(far).1),
            "ink far from the stroke at {far:?}"
        );
    }
    let _ = std::fs::write(
        std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("serve_browser.png"),
        &png,
    );

    // A second stroke, an S with an inflection, drawn with the curvature comb on: fitted too,
    // without a script error, and both strokes are in the drawing.
    page.eval("document.getElementById('show-comb').click(); true");
    let s_curve = |i: usize| {
        let u = i as f64 / 99.0;
        (
            200.0 + 600.0 * u,
            650.0 + 60.0 * (std::f64::consts::TAU * u).sin(),
        )
    };
    page.pen("mousePressed", at(s_curve(0)), 0.5, (0.0, 0.0));
    for i in 1..100 {
        page.pen("mouseMoved", at(s_curve(i)), 0.5, (0.0, 0.0));
    }
    page.pen("mouseReleased", at(s_curve(99)), 0.5, (0.0, 0.0));
    page.wait_for("window.kansei.finals >= 2");
    page.eval("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))");
    assert_eq!(page.eval("window.kansei.errors"), json!([]));
    assert_eq!(page.eval("window.kansei.state.strokes.length"), json!(2));
    let second: CurveFile = serde_json::from_value(page.eval("window.kansei.lastFit"))
        .expect("the second stroke's document");
    assert!(
        second.curves[0]
            .splits
            .iter()
            .any(|s| format!("{:?}", s.kind)
                .to_lowercase()
                .contains("inflection")),
        "the S has an inflection"
    );
    let shot = page.call("Page.captureScreenshot", json!({"format": "png"}));
    let _ = std::fs::write(
        std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("serve_browser_comb.png"),
        base64(shot["data"].as_str().expect("screenshot data")),
    );

    // The tolerance starts empty (auto: each stroke's own, as the API's default the first
    // stroke was compared with), and every setting changed is restored on reload.
    assert_eq!(
        page.eval("document.getElementById('tolerance').value"),
        json!("")
    );
    page.eval(
        "for (const [id, v] of [['continuity', 'c3'], ['close', 'never'], ['tolerance', '1.5']]) { \
         const el = document.getElementById(id); el.value = v; \
         el.dispatchEvent(new Event('change')); } true",
    );
    page.call("Page.reload", json!({}));
    page.wait_for("window.kansei !== undefined && window.kansei.ready === true");
    for (id, value) in [
        ("continuity", "c3"),
        ("close", "never"),
        ("tolerance", "1.5"),
    ] {
        let shown = page.eval(&format!("document.getElementById('{id}').value"));
        assert_eq!(shown, json!(value), "{id} restored on reload");
    }
}

/// Decodes standard base64 (what the DevTools protocol sends screenshots in).
fn base64(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    };
    let bytes: Vec<u8> = text.bytes().filter(|&c| c != b'=' && c != b'\n').collect();
    let mut out = Vec::with_capacity(bytes.len() * 3 / 4);
    for chunk in bytes.chunks(4) {
        let v: Vec<u32> = chunk.iter().map(|&c| u32::from(value(c))).collect();
        let n = v.iter().fold(0u32, |acc, d| (acc << 6) | d) << (6 * (4 - v.len()));
        let b = n.to_be_bytes();
        out.extend_from_slice(&b[1..v.len()]);
    }
    out
}
