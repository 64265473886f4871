//! The fitting service's HTTP API against a real server on loopback (port 0): health, `/v1/fit`
//! equal to `kansei fit` on every fixture, the exports equal to `kansei fit --svg/--dxf/--png`,
//! refusals with the command line's messages while the server keeps answering, 32 concurrent
//! clients, the full queue (`503`), the deadline (`504`), and SIGTERM draining a request in
//! flight.

mod common;

use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::http::{self, Response};
use kansei::export::CurveFile;
use kansei::serve::{ServeOptions, Server, spawn};
use kansei::stroke::StrokeFile;

fn loopback() -> SocketAddr {
    SocketAddr::from(([127, 0, 0, 1], 0))
}

fn server(options: ServeOptions) -> Server {
    spawn(options).expect("the server starts on loopback")
}

fn default_server() -> Server {
    server(ServeOptions::at(loopback()))
}

fn fixture_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("fixtures/strokes/{name}.json"))
}

fn fixture_text(name: &str) -> String {
    std::fs::read_to_string(fixture_path(name)).expect("fixture")
}

fn kansei() -> Command {
    Command::new(env!("CARGO_BIN_EXE_kansei"))
}

fn out_dir(test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("serve_api/{test}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch directory");
    dir
}

fn ok(r: std::io::Result<Response>) -> Response {
    let r = r.expect("the server answers");
    assert_eq!(r.status, 200, "{}", r.text());
    r
}

fn assert_healthy(addr: SocketAddr) {
    let r = ok(http::get(addr, "/v1/health"));
    assert_eq!(r.json()["status"], "ok");
}

#[test]
fn health_says_ok_and_the_version() {
    let s = default_server();
    let r = ok(http::get(s.addr(), "/v1/health"));
    assert_eq!(r.header("content-type"), Some("application/json"));
    let v = r.json();
    assert_eq!(v["status"], "ok");
    assert_eq!(v["version"], env!("CARGO_PKG_VERSION"));
    assert!(v["workers"].as_u64().is_some_and(|w| w >= 1));
    let page = ok(http::get(s.addr(), "/"));
    assert!(page.text().contains("<canvas"), "the pen page");
    let missing = http::get(s.addr(), "/v2/fit").expect("answers");
    assert_eq!(missing.status, 404);
    assert!(missing.error().contains("/v2/fit"));
    // A known endpoint asked with a method it does not take: a 405 with a JSON error body too.
    let wrong = http::get(s.addr(), "/v1/fit").expect("answers");
    assert_eq!(wrong.status, 405);
    assert!(wrong.error().contains("/v1/fit"), "{}", wrong.error());
}

#[test]
fn fit_equals_kansei_fit_on_every_fixture() {
    let s = default_server();
    let dir = out_dir("fit");
    let names = common::fixture_names();
    assert!(names.len() >= 9, "{names:?}");
    for (name, query, args) in names
        .iter()
        .map(|n| (n.as_str(), "", &[][..]))
        .chain([(
            "google-ink-spring",
            "?tolerance=1&alpha=-1&corner_angle=50&keep_hooks=true&lcg=true&continuity=g1",
            &[
                "--tolerance",
                "1",
                "--alpha",
                "-1",
                "--corner-angle",
                "50",
                "--keep-hooks",
                "--lcg",
                "--continuity",
                "g1",
            ][..],
        )])
        .chain([(
            "perfect-freehand-waves",
            "?alpha_range=-1:0.5",
            &["--alpha-range", "-1:0.5"][..],
        )])
        .chain([(
            "perfect-freehand-hey",
            "?continuity=g2",
            &["--continuity", "g2"][..],
        )])
    {
        let served = ok(http::post(
            s.addr(),
            &format!("/v1/fit{query}"),
            fixture_text(name).as_bytes(),
        ));
        assert_eq!(served.header("content-type"), Some("application/json"));
        let cli_out = dir.join(format!("{name}.curve.json"));
        common::run_ok(
            kansei()
                .arg("fit")
                .arg(fixture_path(name))
                .arg("--json")
                .arg(&cli_out)
                .args(args),
        );
        let cli = std::fs::read(&cli_out).expect("kansei fit wrote its JSON");
        let parse = |b: &[u8]| CurveFile::from_json(std::str::from_utf8(b).expect("UTF-8"));
        assert_eq!(
            parse(&served.body).expect("served document"),
            parse(&cli).expect("kansei fit's document"),
            "{name}{query}"
        );
        assert!(served.body == cli, "{name}{query}: the same bytes");
    }
}

#[test]
fn exports_equal_kansei_fit_exports() {
    let s = default_server();
    let dir = out_dir("exports");
    let name = "perfect-freehand-corners";
    let body = fixture_text(name);
    let (svg, dxf, png) = (dir.join("a.svg"), dir.join("a.dxf"), dir.join("a.png"));
    common::run_ok(
        kansei()
            .arg("fit")
            .arg(fixture_path(name))
            .arg("--json")
            .arg(dir.join("a.json"))
            .args([
                "--svg-layers",
                "alpha,splits",
                "--png-layers",
                "samples,segments,comb",
            ])
            .args(["--size", "800x600", "--svg"])
            .arg(&svg)
            .arg("--dxf")
            .arg(&dxf)
            .arg("--png")
            .arg(&png),
    );
    let r = ok(http::post(
        s.addr(),
        "/v1/export/svg?layers=alpha,splits",
        body.as_bytes(),
    ));
    assert_eq!(r.header("content-type"), Some("image/svg+xml"));
    assert!(r.body == std::fs::read(&svg).expect("svg"), "the SVG");
    let r = ok(http::post(
        s.addr(),
        "/v1/export/png?layers=samples,segments,comb&size=800x600",
        body.as_bytes(),
    ));
    assert_eq!(r.header("content-type"), Some("image/png"));
    assert!(r.body == std::fs::read(&png).expect("png"), "the PNG");
    let r = ok(http::post(s.addr(), "/v1/export/dxf", body.as_bytes()));
    assert_eq!(r.header("content-type"), Some("image/vnd.dxf"));
    // A DXF records when and by whom (a GUID) it was made: compare the entities.
    let entities = |bytes: &[u8]| {
        let d = dxf::Drawing::load(&mut std::io::Cursor::new(bytes)).expect("a DXF");
        d.entities()
            .map(|e| format!("{:?}", e.specific))
            .collect::<Vec<_>>()
    };
    let served = entities(&r.body);
    assert!(!served.is_empty());
    assert_eq!(served, entities(&std::fs::read(&dxf).expect("dxf")));
}

/// A one-stroke px document with these samples (JSON text).
fn doc(samples: &str) -> String {
    format!(
        "{{\"format\": \"kansei-stroke\", \"version\": 1, \"units\": \"px\",\n\"strokes\": [\
         {{\"samples\": [{{\"x\": 0, \"y\": 0}}, {{\"x\": 5, \"y\": 1}}]}},\n\
         {{\"samples\": [{samples}]}}]}}"
    )
}

#[test]
fn bad_input_is_refused_with_the_command_lines_message() {
    let s = default_server();
    let cases = [
        (
            "bad JSON",
            "{\"format\": \"kansei-stroke\", \"version\": 1,".to_owned(),
        ),
        (
            "an infinity",
            doc("{\"x\": 1, \"y\": 2}, {\"x\": 1e999, \"y\": 3}"),
        ),
        (
            "a pressure of 2",
            doc("{\"x\": 1, \"y\": 2, \"pressure\": 0.5}, {\"x\": 3, \"y\": 4, \"pressure\": 2}"),
        ),
        (
            "time running backwards",
            doc("{\"x\": 1, \"y\": 2, \"t\": 1}, {\"x\": 3, \"y\": 4, \"t\": 0.5}"),
        ),
        (
            "another format",
            "{\"format\": \"kansei-curve\", \"version\": 1}".to_owned(),
        ),
        ("nothing", String::new()),
    ];
    for (what, body) in &cases {
        let r = http::post(s.addr(), "/v1/fit", body.as_bytes()).expect("answers");
        assert_eq!(r.status, 400, "{what}: {}", r.text());
        let expected = StrokeFile::from_json(body).expect_err(what).to_string();
        assert_eq!(r.error(), expected, "{what}");
        assert_healthy(s.addr());
    }
    // The messages name the stroke, sample and field.
    let r = http::post(s.addr(), "/v1/fit", cases[2].1.as_bytes()).expect("answers");
    assert_eq!(r.error(), "stroke 1, sample 1: pressure 2 is outside 0..1");
    let r = http::post(s.addr(), "/v1/fit", cases[1].1.as_bytes()).expect("answers");
    assert!(
        r.error()
            .starts_with("stroke 1, sample 1, field \"x\": invalid JSON"),
        "{}",
        r.error()
    );
    // Options as `kansei fit` checks them.
    for (query, words) in [
        ("tolerance=-1", "tolerance must be a positive number"),
        ("continuity=g3", "continuity must be one of g1, g2, c3"),
        ("alpha=1&alpha_range=0:1", "cannot be used together"),
        ("bogus=1", "unknown query parameter \"bogus\""),
    ] {
        let body = fixture_text("google-ink-straight-line");
        let r =
            http::post(s.addr(), &format!("/v1/fit?{query}"), body.as_bytes()).expect("answers");
        assert_eq!(r.status, 400, "{query}");
        assert!(r.error().contains(words), "{query}: {}", r.error());
    }
    assert_healthy(s.addr());
}

#[test]
fn limits_are_answered_413_and_the_server_keeps_answering() {
    let s = server(ServeOptions {
        max_body_bytes: 100_000,
        max_strokes: 3,
        max_samples_per_stroke: 50,
        ..ServeOptions::at(loopback())
    });
    // Declared too large: refused before the body is read (only part of it is sent).
    let head = format!(
        "POST /v1/fit HTTP/1.1\r\nHost: x\r\nConnection: close\r\nContent-Length: {}\r\n\r\n",
        9 << 20
    );
    let r = http::send_raw(s.addr(), head.as_bytes(), &[b' '; 1000]).expect("answers");
    assert_eq!(r.status, 413, "{}", r.text());
    assert!(r.error().contains("100000 bytes"), "{}", r.error());
    // Chunked, with no length declared: refused once the limit is passed.
    let head = "POST /v1/fit HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\
                Transfer-Encoding: chunked\r\n\r\n";
    let mut chunks = Vec::new();
    for _ in 0..30 {
        chunks.extend_from_slice(format!("{:x}\r\n", 4000).as_bytes());
        chunks.extend_from_slice(&[b' '; 4000]);
        chunks.extend_from_slice(b"\r\n");
    }
    chunks.extend_from_slice(b"0\r\n\r\n");
    let r = http::send_raw(s.addr(), head.as_bytes(), &chunks).expect("answers");
    assert_eq!(r.status, 413, "{}", r.text());
    assert_healthy(s.addr());
    // Strokes and samples.
    let stroke = "{\"samples\": [{\"x\": 0, \"y\": 0}, {\"x\": 5, \"y\": 1}]}";
    let four = format!(
        "{{\"format\": \"kansei-stroke\", \"version\": 1, \"units\": \"px\", \"strokes\": [{}]}}",
        [stroke; 4].join(",")
    );
    let r = http::post(s.addr(), "/v1/fit", four.as_bytes()).expect("answers");
    assert_eq!(r.status, 413);
    assert_eq!(r.error(), "4 strokes, more than the 3 a request may hold");
    let long: Vec<String> = (0..51)
        .map(|i| format!("{{\"x\": {i}, \"y\": {}}}", (i * i) % 7))
        .collect();
    let r = http::post(s.addr(), "/v1/fit", doc(&long.join(",")).as_bytes()).expect("answers");
    assert_eq!(r.status, 413);
    assert_eq!(
        r.error(),
        "stroke 1: 51 samples, more than the 50 a stroke may hold"
    );
    assert_healthy(s.addr());
}

#[test]
fn thirty_two_concurrent_clients_all_get_correct_answers() {
    let s = default_server();
    let addr = s.addr();
    let names = common::fixture_names();
    let expected: Vec<(String, Vec<u8>)> = names
        .iter()
        .map(|n| {
            let file = common::fixture(n);
            let out = kansei::pipeline::fit_file(&file, &Default::default()).expect("fits");
            (
                fixture_text(n),
                CurveFile::from_output(&out).to_json().into_bytes(),
            )
        })
        .collect();
    let expected = std::sync::Arc::new(expected);
    let barrier = std::sync::Arc::new(std::sync::Barrier::new(32));
    let clients: Vec<_> = (0..32)
        .map(|i| {
            let (expected, barrier) = (expected.clone(), barrier.clone());
            std::thread::spawn(move || {
                let (body, answer) = &expected[i % expected.len()];
                barrier.wait();
                let r = ok(http::post(addr, "/v1/fit", body.as_bytes()));
                assert!(r.body == *answer, "client {i}: a different document");
            })
        })
        .collect();
    for c in clients {
        c.join().expect("every client got its answer");
    }
    assert_eq!(ok(http::get(addr, "/v1/health")).json()["busy"], 0);
}

#[test]
fn a_full_queue_is_answered_503_with_retry_after() {
    let s = server(ServeOptions {
        workers: 1,
        queue_depth: 0,
        ..ServeOptions::at(loopback())
    });
    let addr = s.addr();
    let body = std::sync::Arc::new(fixture_text("libmypaint-painting30sec"));
    let barrier = std::sync::Arc::new(std::sync::Barrier::new(8));
    let clients: Vec<_> = (0..8)
        .map(|_| {
            let (body, barrier) = (body.clone(), barrier.clone());
            std::thread::spawn(move || {
                barrier.wait();
                http::post(addr, "/v1/fit", body.as_bytes()).expect("answers")
            })
        })
        .collect();
    let answers: Vec<Response> = clients
        .into_iter()
        .map(|c| c.join().expect("client"))
        .collect();
    let busy: Vec<&Response> = answers.iter().filter(|r| r.status == 503).collect();
    assert!(
        answers.iter().all(|r| r.status == 200 || r.status == 503),
        "{:?}",
        answers.iter().map(|r| r.status).collect::<Vec<_>>()
    );
    assert!(answers.iter().any(|r| r.status == 200));
    assert!(
        !busy.is_empty(),
        "one worker and no queue: some are refused"
    );
    for r in busy {
        assert_eq!(r.header("retry-after"), Some("1"));
        assert!(r.error().contains("busy"), "{}", r.error());
    }
    assert_healthy(addr);
}

#[test]
fn past_the_deadline_is_answered_504() {
    let s = server(ServeOptions {
        deadline: Duration::from_millis(5),
        ..ServeOptions::at(loopback())
    });
    let body = fixture_text("libmypaint-painting30sec");
    let r = http::post(s.addr(), "/v1/fit", body.as_bytes()).expect("answers");
    assert_eq!(r.status, 504, "{}", r.text());
    assert!(r.error().contains("deadline"), "{}", r.error());
    assert_healthy(s.addr());
}

#[test]
fn sigterm_answers_the_request_in_flight_then_exits() {
    let mut child = kansei()
        .args(["serve", "--addr", "127.0.0.1:0"])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("kansei serve starts");
    let stderr = child.stderr.take().expect("stderr");
    let mut lines = std::io::BufRead::lines(std::io::BufReader::new(stderr));
    let first = lines.next().expect("a line").expect("text");
    let addr: SocketAddr = first
        .split("http://")
        .nth(1)
        .and_then(|rest| rest.split('/').next())
        .and_then(|a| a.parse().ok())
        .unwrap_or_else(|| panic!("no address in {first:?}"));
    assert_healthy(addr);
    let body = fixture_text("libmypaint-painting30sec");
    let expected = {
        let out = kansei::pipeline::fit_file(
            &common::fixture("libmypaint-painting30sec"),
            &Default::default(),
        )
        .expect("fits");
        CurveFile::from_output(&out).to_json().into_bytes()
    };
    let in_flight = std::thread::spawn(move || http::post(addr, "/v1/fit", body.as_bytes()));
    // Once the request is running, SIGTERM.
    let started = Instant::now();
    while http::get(addr, "/v1/health")
        .map(|r| r.json()["busy"] == 0)
        .unwrap_or(true)
        && started.elapsed() < Duration::from_secs(10)
    {
        std::thread::sleep(Duration::from_millis(2));
    }
    let pid = child.id().to_string();
    common::run_ok(Command::new("kill").args(["-TERM", &pid]));
    let answer = in_flight.join().expect("client").expect("answered");
    assert_eq!(answer.status, 200, "{}", answer.text());
    assert!(
        answer.body == expected,
        "the fit in flight is answered in full"
    );
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        assert!(
            started.elapsed() < Duration::from_secs(20),
            "kansei serve did not exit after SIGTERM"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    assert!(status.success(), "{status}");
    let rest: Vec<String> = lines.map_while(Result::ok).collect();
    assert!(rest.iter().any(|l| l.contains("stopping")), "{rest:?}");
    // Nothing listens any more.
    assert!(std::net::TcpStream::connect(addr).is_err());
}

#[test]
fn binding_beyond_loopback_is_warned_about() {
    assert!(kansei::serve::exposure_warning("127.0.0.1:7878".parse().expect("addr")).is_none());
    assert!(kansei::serve::exposure_warning("[::1]:7878".parse().expect("addr")).is_none());
    let w =
        kansei::serve::exposure_warning("0.0.0.0:7878".parse().expect("addr")).expect("a warning");
    assert!(w.contains("no authentication"), "{w}");
}

#[test]
fn a_tolerance_below_the_noise_floor_is_honoured_with_a_warning_header() {
    let s = default_server();
    let body = fixture_text("perfect-freehand-waves");
    let below = ok(http::post(
        s.addr(),
        "/v1/fit?tolerance=0.5",
        body.as_bytes(),
    ));
    let warning = below.header("warning").expect("a Warning header");
    assert!(
        warning.starts_with("299 kansei") && warning.contains("below the noise floor"),
        "{warning}"
    );
    // Honoured: the curves are held to 0.5.
    let doc = CurveFile::from_json(&below.text()).expect("a document");
    assert_eq!(doc.tolerance, 0.5);
    for c in &doc.curves {
        assert!(c.lac.as_ref().expect("chain").max_deviation <= 0.5);
    }
    // Without a tolerance, each stroke gets its floor and no warning.
    let default = ok(http::post(s.addr(), "/v1/fit", body.as_bytes()));
    assert_eq!(default.header("warning"), None);
}
