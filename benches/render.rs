//! Benchmark of the `render` module: one [`render`] of a fitted fixture at 1600 × 1000 with the
//! whole scene in view (what `kansei fit --png` draws, and the app's canvas at that size).
//!
//! ```sh
//! cargo bench --bench render
//! ```
//!
//! `render/<fixture>/default` uses [`RenderOptions::default`]; `…/all` every overlay
//! ([`Overlays::ALL`]); `…/all_zoom20` every overlay zoomed 20× about the first stroke's tenth
//! sample (culling at work). The fit runs once, before timing.

use criterion::{Criterion, criterion_group, criterion_main};
use kansei::pipeline::{PipelineOptions, fit_file};
use kansei::render::{Overlays, RenderOptions, Scene, View, render, scene_bounds};
use kansei::stroke::StrokeFile;
use std::hint::black_box;

fn fixture(name: &str) -> StrokeFile {
    let path = format!(
        "{}/fixtures/strokes/{name}.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    StrokeFile::from_json(&text).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn bench_render(c: &mut Criterion) {
    let mut group = c.benchmark_group("render");
    group.sample_size(10);
    for name in ["google-ink-spring", "libmypaint-painting30sec"] {
        let file = fixture(name);
        let out = fit_file(&file, &PipelineOptions::default()).expect("the fixture fits");
        let scene = Scene::new(&file.strokes, &out.curves, file.units);
        let view = View::fit(scene_bounds(&scene).expect("a scene"), 1600, 1000, 48.0);
        let zoomed = view.zoomed(20.0, view.to_pixel(file.strokes[0].samples[10].point()));
        let all = RenderOptions::with_overlays(Overlays::ALL);
        for (label, view, options) in [
            ("default", view, RenderOptions::default()),
            ("all", view, all),
            ("all_zoom20", zoomed, all),
        ] {
            group.bench_function(format!("{name}/{label}"), |b| {
                b.iter(|| render(black_box(&scene), &view, &options).expect("renders"))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench_render);
criterion_main!(benches);
