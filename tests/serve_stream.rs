//! `/v1/stream` against a real server on loopback: a fixture stroke streamed in small batches
//! gets previews as it grows and a final fit equal to `/v1/fit` of the same samples; a stroke
//! with a bad sample is refused with the command line's message while the connection goes on.

mod common;

use std::net::{SocketAddr, TcpStream};
use std::time::{Duration, Instant};

use common::http;
use kansei::export::CurveFile;
use kansei::serve::{ServeOptions, spawn};
use kansei::stroke::{Sample, Stroke, StrokeFile, Units};
use serde_json::{Value, json};
use tungstenite::stream::MaybeTlsStream;
use tungstenite::{Message, WebSocket};

type Socket = WebSocket<MaybeTlsStream<TcpStream>>;

fn connect(addr: SocketAddr, query: &str) -> Socket {
    let (ws, _) = tungstenite::connect(format!("ws://{addr}/v1/stream{query}").as_str())
        .expect("the stream opens");
    if let MaybeTlsStream::Plain(s) = ws.get_ref() {
        s.set_read_timeout(Some(Duration::from_secs(60)))
            .expect("timeout");
    }
    ws
}

fn send(ws: &mut Socket, v: Value) {
    ws.send(Message::text(v.to_string())).expect("send");
}

/// The next text message, as JSON.
fn next(ws: &mut Socket) -> Value {
    loop {
        match ws.read().expect("a message") {
            Message::Text(t) => return serde_json::from_str(t.as_str()).expect("JSON"),
            Message::Close(c) => panic!("closed: {c:?}"),
            _ => {}
        }
    }
}

/// Reads until the answer to `end` (`final` or `error` with `final: true`), returning it and
/// the previews seen on the way. A stroke refused as it arrives (a preview found a bad sample)
/// is reported before: that early error must say what the answer says.
fn until_final(ws: &mut Socket) -> (Value, Vec<Value>) {
    let mut previews = Vec::new();
    let mut early: Option<Value> = None;
    loop {
        let m = next(ws);
        match m["type"].as_str() {
            Some("preview") => previews.push(m),
            Some("final") => {
                assert!(early.is_none(), "{early:?} before {m}");
                return (m, previews);
            }
            Some("error") if m["final"] == true => {
                if let Some(e) = early {
                    assert_eq!(e["error"], m["error"]);
                }
                return (m, previews);
            }
            Some("error") if early.is_none() => early = Some(m),
            _ => panic!("unexpected {m}"),
        }
    }
}

fn samples_json(samples: &[Sample]) -> Value {
    serde_json::to_value(samples).expect("samples serialise")
}

fn api_fit(addr: SocketAddr, units: Units, samples: &[Sample], query: &str) -> CurveFile {
    let file = StrokeFile::new(units, vec![Stroke::new(samples.to_vec())]);
    let r =
        http::post(addr, &format!("/v1/fit{query}"), file.to_json().as_bytes()).expect("answers");
    assert_eq!(r.status, 200, "{}", r.text());
    CurveFile::from_json(&r.text()).expect("document")
}

#[test]
fn the_final_fit_of_a_streamed_stroke_equals_v1_fit() {
    let server =
        spawn(ServeOptions::at(SocketAddr::from(([127, 0, 0, 1], 0)))).expect("the server starts");
    let addr = server.addr();
    for (name, query) in [
        ("google-ink-spring", "?units=px"),
        (
            "wacom-intuos-pro-ccw-circle",
            "?units=mm&tolerance=0.2&alpha_range=-2:2",
        ),
    ] {
        let file = common::fixture(name);
        let samples = &file.strokes[0].samples;
        assert_eq!(
            file.units.name(),
            if query.contains("mm") { "mm" } else { "px" }
        );
        let mut ws = connect(addr, query);
        let started = Instant::now();
        for batch in samples.chunks(5) {
            send(
                &mut ws,
                json!({"type": "samples", "samples": samples_json(batch)}),
            );
            // 5 samples per 8 ms, faster than a pen (about 200 Hz): time for previews to come back.
            std::thread::sleep(Duration::from_millis(8));
        }
        send(&mut ws, json!({"type": "end"}));
        let (last, previews) = until_final(&mut ws);
        assert_eq!(last["type"], "final", "{name}: {last}");
        assert_eq!(last["stroke"], 0);
        assert_eq!(last["samples"], samples.len());
        let streamed: CurveFile =
            serde_json::from_value(last["curve"].clone()).expect("a kansei-curve document");
        let fit_query = query.replace("units=px", "").replace("units=mm&", "");
        let fit_query = if fit_query == "?" {
            String::new()
        } else {
            fit_query
        };
        assert_eq!(
            streamed,
            api_fit(addr, file.units, samples, &fit_query),
            "{name}"
        );
        // Previews came while the stroke grew, each of more samples than the one before.
        assert!(
            !previews.is_empty(),
            "{name}: no preview in {:?}",
            started.elapsed()
        );
        let counts: Vec<u64> = previews
            .iter()
            .map(|p| p["samples"].as_u64().expect("count"))
            .collect();
        assert!(counts.windows(2).all(|w| w[0] < w[1]), "{counts:?}");
        assert!(counts[0] >= 8 && counts[counts.len() - 1] <= samples.len() as u64);
        for p in &previews {
            let doc: CurveFile =
                serde_json::from_value(p["curve"].clone()).expect("preview document");
            assert_eq!(doc.format, "kansei-curve");
        }
        // The next stroke on the same connection is stroke 1.
        send(
            &mut ws,
            json!({"type": "samples", "samples": samples_json(&samples[..20])}),
        );
        send(&mut ws, json!({"type": "end"}));
        let (last, _) = until_final(&mut ws);
        assert_eq!(last["stroke"], 1, "{last}");
        assert_eq!(last["type"], "final");
    }
}

#[test]
fn a_bad_sample_refuses_its_stroke_and_the_connection_goes_on() {
    let server = spawn(ServeOptions {
        max_samples_per_stroke: 100,
        ..ServeOptions::at(SocketAddr::from(([127, 0, 0, 1], 0)))
    })
    .expect("the server starts");
    let mut ws = connect(server.addr(), "");
    let good: Vec<Sample> = (0..30)
        .map(|i| {
            let a = f64::from(i) * 0.05;
            Sample::new(100.0 * a.cos(), 100.0 * a.sin())
                .with_t(f64::from(i) * 0.01)
                .with_pressure(0.5)
        })
        .collect();
    let mut bad = good.clone();
    bad[12].pressure = Some(2.0);
    send(
        &mut ws,
        json!({"type": "samples", "samples": samples_json(&bad)}),
    );
    send(&mut ws, json!({"type": "end"}));
    let (answer, _) = until_final(&mut ws);
    assert_eq!(answer["type"], "error", "{answer}");
    assert_eq!(answer["status"], 400);
    assert_eq!(
        answer["error"],
        "stroke 0, sample 12: pressure 2 is outside 0..1"
    );
    // A malformed message is answered and ignored.
    ws.send(Message::text("{\"type\": \"draw\"}"))
        .expect("send");
    let m = next(&mut ws);
    assert_eq!(m["type"], "error");
    assert_eq!(m["final"], false);
    assert!(
        m["error"]
            .as_str()
            .is_some_and(|e| e.contains("not understood")),
        "{m}"
    );
    // Too many samples: 413.
    let many: Vec<Sample> = (0..101).map(|i| Sample::new(f64::from(i), 0.0)).collect();
    send(
        &mut ws,
        json!({"type": "samples", "samples": samples_json(&many)}),
    );
    let m = next(&mut ws);
    assert_eq!(m["status"], 413, "{m}");
    send(&mut ws, json!({"type": "end"}));
    let (answer, _) = until_final(&mut ws);
    assert_eq!(answer["status"], 413);
    // The next stroke is fitted.
    send(
        &mut ws,
        json!({"type": "samples", "samples": samples_json(&good)}),
    );
    send(&mut ws, json!({"type": "end"}));
    let (answer, _) = until_final(&mut ws);
    assert_eq!(answer["type"], "final", "{answer}");
    assert_eq!(answer["stroke"], 2);
    let streamed: CurveFile = serde_json::from_value(answer["curve"].clone()).expect("document");
    assert_eq!(streamed, api_fit(server.addr(), Units::Px, &good, ""));
    // Bad options are refused before the upgrade.
    let refused =
        tungstenite::connect(format!("ws://{}/v1/stream?continuity=g3", server.addr()).as_str());
    match refused {
        Err(tungstenite::Error::Http(r)) => assert_eq!(r.status(), 400),
        other => panic!("expected a 400, got {other:?}"),
    }
}
