//! A load generator for `kansei serve`: throughput and latency of `POST /v1/fit` at several
//! numbers of concurrent clients, over the fixture strokes, on loopback only.
//!
//! Each fixture stroke (`fixtures/strokes/*.json`, 38 strokes) becomes a one-stroke
//! `kansei-stroke` document; each client posts them in turn, one request per connection, for a
//! fixed time; every answer is checked against the library's own fit. Reported per level:
//! fits per second, latency percentiles, refusals, and the server's resident memory
//! (`VmRSS` and its peak `VmHWM` from `/proc/self/status`: the server runs in this process, on
//! the default options, unless `--addr` names one already running).
//!
//! `cargo run --release --example load -- [--seconds 5] [--clients 1,8,64] [--addr 127.0.0.1:7878]`

// Shared with the tests, which use all of it.
#[allow(dead_code)]
#[path = "../tests/common/http.rs"]
mod http;

use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use kansei::export::CurveFile;
use kansei::pipeline::{PipelineOptions, fit_file};
use kansei::serve::{ServeOptions, spawn};
use kansei::stroke::StrokeFile;

/// Longest run per level and most clients, whatever is asked: the load stays bounded.
const MAX_SECONDS: f64 = 60.0;
const MAX_CLIENTS: usize = 256;

struct Args {
    seconds: f64,
    clients: Vec<usize>,
    addr: Option<SocketAddr>,
}

fn args() -> Result<Args, String> {
    let mut a = Args {
        seconds: 5.0,
        clients: vec![1, 8, 64],
        addr: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let value = it.next().ok_or(format!("{flag} needs a value"))?;
        match flag.as_str() {
            "--seconds" => a.seconds = value.parse().map_err(|e| format!("--seconds: {e}"))?,
            "--clients" => {
                a.clients = value
                    .split(',')
                    .map(|c| c.trim().parse::<usize>())
                    .collect::<Result<_, _>>()
                    .map_err(|e| format!("--clients: {e}"))?
            }
            "--addr" => a.addr = Some(value.parse().map_err(|e| format!("--addr: {e}"))?),
            other => return Err(format!("unknown option {other}")),
        }
    }
    if !(a.seconds > 0.0 && a.seconds <= MAX_SECONDS) {
        return Err(format!("--seconds must be in (0, {MAX_SECONDS}]"));
    }
    if a.clients.iter().any(|&c| c == 0 || c > MAX_CLIENTS) {
        return Err(format!("--clients must be in 1..={MAX_CLIENTS}"));
    }
    if a.addr.is_some_and(|addr| !addr.ip().is_loopback()) {
        return Err("--addr must be a loopback address".into());
    }
    Ok(a)
}

/// One-stroke documents of every fixture stroke, with the expected answer of each.
fn bodies() -> Vec<(Vec<u8>, Vec<u8>)> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/strokes");
    let mut paths: Vec<_> = std::fs::read_dir(dir)
        .expect("fixtures/strokes")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    paths.sort();
    let mut out = Vec::new();
    for p in paths {
        let text = std::fs::read_to_string(&p).expect("fixture");
        let file = StrokeFile::from_json(&text).expect("a valid fixture");
        for stroke in &file.strokes {
            let one = StrokeFile::new(file.units, vec![stroke.clone()]);
            let fit = fit_file(&one, &PipelineOptions::default()).expect("fits");
            out.push((
                one.to_json().into_bytes(),
                CurveFile::from_output(&fit).to_json().into_bytes(),
            ));
        }
    }
    out
}

fn memory() -> String {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let field = |name: &str| {
        status
            .lines()
            .find(|l| l.starts_with(name))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|kb| kb.parse::<f64>().ok())
            .map_or("?".to_owned(), |kb| format!("{:.1} MiB", kb / 1024.0))
    };
    format!("RSS {} (peak {})", field("VmRSS:"), field("VmHWM:"))
}

fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let i = ((sorted.len() as f64 - 1.0) * q).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

fn main() {
    let args = match args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("load: {e}");
            std::process::exit(2);
        }
    };
    let bodies = Arc::new(bodies());
    let (server, addr) = match args.addr {
        Some(addr) => (None, addr),
        None => {
            let s = spawn(ServeOptions::at(SocketAddr::from(([127, 0, 0, 1], 0))))
                .expect("a server on loopback");
            let addr = s.addr();
            (Some(s), addr)
        }
    };
    println!(
        "kansei serve load: POST /v1/fit of {} one-stroke fixture documents, {} s per level, \
         {} cores, server {}",
        bodies.len(),
        args.seconds,
        std::thread::available_parallelism().map_or(1, |n| n.get()),
        if server.is_some() {
            "in this process (default options)"
        } else {
            "given by --addr"
        }
    );
    println!(
        "{:>7} {:>9} {:>9} {:>9} {:>9} {:>9} {:>6} {:>6}  memory",
        "clients", "requests", "fits/s", "p50 ms", "p99 ms", "max ms", "503", "errors"
    );
    for &clients in &args.clients {
        let stop = Arc::new(AtomicBool::new(false));
        let started = Instant::now();
        let threads: Vec<_> = (0..clients)
            .map(|c| {
                let (bodies, stop) = (bodies.clone(), stop.clone());
                std::thread::spawn(move || {
                    let (mut latencies, mut busy, mut errors) = (Vec::new(), 0usize, 0usize);
                    let mut i = c * 7;
                    while !stop.load(Ordering::Relaxed) {
                        let (body, expected) = &bodies[i % bodies.len()];
                        i += 1;
                        let t = Instant::now();
                        match http::post(addr, "/v1/fit", body) {
                            Ok(r) if r.status == 200 && r.body == *expected => {
                                latencies.push(t.elapsed().as_secs_f64() * 1e3)
                            }
                            Ok(r) if r.status == 503 => {
                                busy += 1;
                                std::thread::sleep(Duration::from_millis(50));
                            }
                            _ => errors += 1,
                        }
                    }
                    (latencies, busy, errors)
                })
            })
            .collect();
        std::thread::sleep(Duration::from_secs_f64(args.seconds));
        stop.store(true, Ordering::Relaxed);
        let (mut latencies, mut busy, mut errors) = (Vec::new(), 0, 0);
        for t in threads {
            let (l, b, e) = t.join().expect("client");
            latencies.extend(l);
            busy += b;
            errors += e;
        }
        let elapsed = started.elapsed().as_secs_f64();
        latencies.sort_by(f64::total_cmp);
        println!(
            "{:>7} {:>9} {:>9.1} {:>9.2} {:>9.2} {:>9.2} {:>6} {:>6}  {}",
            clients,
            latencies.len(),
            latencies.len() as f64 / elapsed,
            percentile(&latencies, 0.5),
            percentile(&latencies, 0.99),
            latencies.last().copied().unwrap_or(f64::NAN),
            busy,
            errors,
            memory()
        );
    }
    if let Some(s) = server {
        s.stop().expect("the server stops");
    }
}
