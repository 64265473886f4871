//! The `render` module: golden images with a stated tolerance, and numeric checks beside them —
//! segment pixels lie on the exact LAC, the view round trip, `View::fit` holds every sample,
//! toggling an overlay changes pixels only where it draws, translating data and view together
//! changes nothing; errors are typed; `kansei fit --png` writes the file.
//!
//! Golden images live in `fixtures/render-golden/`. Regenerate them (after a deliberate change to
//! the drawing) with `KANSEI_BLESS=1 cargo test --test render`, then look at them before
//! committing. A failing comparison writes the render to `target/tmp/<name>.actual.png`.

mod common;
use common::run_ok;

use kansei::geom::{Point, Rect};
use kansei::lac::LacSegment;
use kansei::pipeline::{FitOutput, PipelineOptions, fit_file};
use kansei::render::{
    Overlays, Pixmap, RenderError, RenderOptions, Scene, View, render, scene_bounds,
};
use kansei::stroke::{Sample, Stroke, StrokeFile, Units};
use std::path::PathBuf;

/// A pixel differs from its golden when any channel (premultiplied RGBA8) is off by more than
/// this. tiny-skia rasterises deterministically in software; what can move between machines is
/// the fit itself (libm's last bits in sin/cos/exp), which shifts anti-aliased edges by a
/// fraction of a pixel: a few levels of coverage, well under this.
const PIXEL_TOLERANCE: u8 = 24;

/// At most this fraction of the pixels may differ (beyond [`PIXEL_TOLERANCE`]): 0.2 % of a
/// 480 × 300 image is 288 pixels, a few edges' worth; a moved marker or segment is more.
const MAX_DIFFERING_FRACTION: f64 = 0.002;

/// Size of the golden images: small enough to commit (tens of KB), large enough to show splits.
const GOLDEN_SIZE: (u32, u32) = (480, 300);

/// Margin of the views fitted in these tests, pixels.
const MARGIN: f64 = 30.0;

/// A channel counts as ink on a white background when it is this far below 255 (anti-aliasing
/// leaves coverage below 1/32 out).
const INK_LEVEL: u8 = 8;

fn fitted(file: &StrokeFile) -> FitOutput {
    fit_file(file, &PipelineOptions::default()).expect("the fixture fits")
}

/// The S-curve of `common::s_curve` in millimetres, with a pressure that swells mid-stroke.
fn s_curve_mm() -> StrokeFile {
    let stroke = common::sample_curve(common::s_curve, -48.0, 48.0, 240, 0.02, 7);
    let n = stroke.samples.len() as f64;
    let samples: Vec<Sample> = stroke
        .samples
        .iter()
        .enumerate()
        .map(|(i, s)| Sample {
            pressure: Some((std::f64::consts::PI * i as f64 / n).sin()),
            ..*s
        })
        .collect();
    StrokeFile::new(Units::Mm, vec![Stroke::new(samples)])
}

fn fit_view(scene: &Scene, (w, h): (u32, u32)) -> View {
    View::fit(
        scene_bounds(scene).expect("a non-empty scene"),
        w,
        h,
        MARGIN,
    )
}

fn draw(file: &StrokeFile, out: &FitOutput, size: (u32, u32), options: &RenderOptions) -> Pixmap {
    let scene = Scene::new(&file.strokes, &out.curves, file.units);
    render(&scene, &fit_view(&scene, size), options).expect("renders")
}

/// Pixels (index) where `a` and `b` differ by more than `tolerance` in some channel.
fn differing(a: &Pixmap, b: &Pixmap, tolerance: u8) -> Vec<usize> {
    assert_eq!((a.width(), a.height()), (b.width(), b.height()));
    a.data()
        .chunks_exact(4)
        .zip(b.data().chunks_exact(4))
        .enumerate()
        .filter(|(_, (p, q))| {
            p.iter()
                .zip(q.iter())
                .any(|(x, y)| x.abs_diff(*y) > tolerance)
        })
        .map(|(i, _)| i)
        .collect()
}

/// Pixels that are not (nearly) white.
fn inked(p: &Pixmap) -> Vec<bool> {
    touched(p, INK_LEVEL)
}

/// Pixels darker than white by more than `level` in some channel.
fn touched(p: &Pixmap, level: u8) -> Vec<bool> {
    p.data()
        .chunks_exact(4)
        .map(|c| c[..3].iter().any(|&v| v < 255 - level))
        .collect()
}

fn golden_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures/render-golden")
        .join(format!("{name}.png"))
}

/// Compares `pixmap` with its golden (or writes it under `KANSEI_BLESS=1`).
fn check_golden(name: &str, pixmap: &Pixmap) {
    let path = golden_path(name);
    if std::env::var_os("KANSEI_BLESS").is_some_and(|v| v == "1") {
        pixmap.save_png(&path).expect("writes the golden");
        return;
    }
    let bytes = std::fs::read(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e} (regenerate with KANSEI_BLESS=1 cargo test --test render)",
            path.display()
        )
    });
    let golden = Pixmap::decode_png(&bytes).expect("a PNG");
    let diff = differing(pixmap, &golden, PIXEL_TOLERANCE);
    let fraction = diff.len() as f64 / (pixmap.width() * pixmap.height()) as f64;
    if fraction > MAX_DIFFERING_FRACTION {
        let actual = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("{name}.actual.png"));
        let _ = pixmap.save_png(&actual);
        panic!(
            "{name}: {} pixels ({:.3} %) differ from {} by more than {PIXEL_TOLERANCE}; the \
             render is in {}",
            diff.len(),
            100.0 * fraction,
            path.display(),
            actual.display()
        );
    }
}

/// Every pixel index in `diff` (an image `width` wide) lies within one pixel of an inked pixel of
/// `mask`: what `what` changed, it changed only where it draws.
fn assert_changed_only_near(mask: &[bool], width: usize, diff: &[usize], what: &str) {
    for &k in diff {
        assert!(
            near(mask, width, k, 1),
            "{what}: pixel ({}, {}) changed, away from what it draws",
            k % width,
            k / width
        );
    }
}

#[test]
fn golden_spring_default_overlays_with_a_highlight() {
    let file = common::fixture("google-ink-spring");
    let out = fitted(&file);
    let options = RenderOptions {
        highlight: Some((0, 2)),
        ..RenderOptions::default()
    };
    check_golden(
        "google-ink-spring",
        &draw(&file, &out, GOLDEN_SIZE, &options),
    );
}

#[test]
fn golden_corners_every_overlay() {
    let file = common::fixture("perfect-freehand-corners");
    let out = fitted(&file);
    let options = RenderOptions::with_overlays(Overlays::ALL);
    check_golden(
        "perfect-freehand-corners",
        &draw(&file, &out, GOLDEN_SIZE, &options),
    );
}

#[test]
fn golden_s_curve_mm_with_pressure_and_comb() {
    let file = s_curve_mm();
    let out = fitted(&file);
    let options = RenderOptions::with_overlays(Overlays {
        comb: true,
        ..Overlays::default()
    });
    check_golden("s-curve-mm", &draw(&file, &out, GOLDEN_SIZE, &options));
}

/// Half the line width plus half a pixel's diagonal (the farthest a pixel centre can be from a
/// line that still covers part of the pixel), plus the drawn polyline's chord error and the
/// spacing of the dense evaluation it is compared with.
fn ink_bound(width: f64) -> f64 {
    0.5 * width
        + std::f64::consts::FRAC_1_SQRT_2
        + kansei::render::SEGMENT_CHORD_ERROR_PX
        + DENSE_STEP_PX
}

/// Spacing of the independent evaluation of the LAC in the pixel check, pixels.
const DENSE_STEP_PX: f64 = 0.1;

/// Checks that every inked pixel of `pixmap` lies within [`ink_bound`] of the `segments`
/// (evaluated independently of the renderer, with [`LacSegment::point`] every
/// [`DENSE_STEP_PX`]), and that ink touches the pixel under every evaluated point. Returns the
/// number of inked pixels and the largest distance of one from the evaluated points.
fn assert_ink_on_segments(
    pixmap: &Pixmap,
    view: &View,
    segments: &[LacSegment],
    width: f64,
) -> (usize, f64) {
    let bound = ink_bound(width);
    let (w, h) = (pixmap.width() as usize, pixmap.height() as usize);
    // Distance from each pixel centre to the nearest evaluated point, within 3 pixels.
    let mut dist = vec![f64::INFINITY; w * h];
    let mut curve_pixels = Vec::new();
    for seg in segments {
        let n = ((seg.length() * view.pixels_per_unit / DENSE_STEP_PX).ceil() as usize).max(1);
        for i in 0..=n {
            let q = view.to_pixel(seg.point(seg.length() * i as f64 / n as f64));
            curve_pixels.push(q);
            let (cx, cy) = (q.x.floor() as i64, q.y.floor() as i64);
            for y in cy - 3..=cy + 3 {
                for x in cx - 3..=cx + 3 {
                    if x < 0 || y < 0 || x >= w as i64 || y >= h as i64 {
                        continue;
                    }
                    let d = Point::new(x as f64 + 0.5, y as f64 + 0.5).distance(q);
                    let k = y as usize * w + x as usize;
                    dist[k] = dist[k].min(d);
                }
            }
        }
    }
    let ink = inked(pixmap);
    let mut count = 0;
    let mut farthest: f64 = 0.0;
    for (k, _) in ink.iter().enumerate().filter(|(_, i)| **i) {
        farthest = farthest.max(dist[k]);
        assert!(
            dist[k] <= bound,
            "pixel ({}, {}) is inked {:.3} px from the LAC (bound {bound:.3})",
            k % w,
            k / w,
            dist[k]
        );
        count += 1;
    }
    // And the curve is drawn: an inked pixel touches the one under every evaluated point (a
    // 1-px line through a pixel's corner can leave that pixel itself blank).
    for q in curve_pixels {
        let k = q.y.floor() as usize * w + q.x.floor() as usize;
        assert!(
            near(&ink, w, k, 1),
            "no ink at the LAC at ({:.2}, {:.2})",
            q.x,
            q.y
        );
    }
    (count, farthest)
}

#[test]
fn segment_pixels_lie_on_the_evaluated_lac() {
    let width = 1.0;
    let options = RenderOptions {
        segment_width: width,
        ..RenderOptions::with_overlays(Overlays {
            segments: true,
            ..Overlays::NONE
        })
    };
    let size = (640, 400);
    let mut files: Vec<StrokeFile> = ["google-ink-spring", "perfect-freehand-waves"]
        .into_iter()
        .map(common::fixture)
        .collect();
    files.push(s_curve_mm());
    let mut checked = 0;
    for file in &files {
        let out = fitted(file);
        let scene = Scene::new(&file.strokes, &out.curves, file.units);
        let view = fit_view(&scene, size);
        let pixmap = render(&scene, &view, &options).expect("renders");
        let segments: Vec<LacSegment> = out
            .curves
            .iter()
            .flat_map(|c| &c.chain.as_ref().expect("a chain").segments)
            .map(|s| s.segment)
            .collect();
        checked += assert_ink_on_segments(&pixmap, &view, &segments, width).0;
    }
    assert!(checked > 1000, "{checked} pixels checked");
}

#[test]
fn arcs_lines_and_spirals_are_drawn_on_the_exact_curve() {
    let o = Point::new(10.0, 20.0);
    let planted = [
        LacSegment::new(o, 0.3, 60.0, None, 0.05, 0.05),
        LacSegment::new(o, -2.0, 90.0, None, -0.08, -0.08),
        LacSegment::new(o, 1.0, 40.0, None, 0.0, 0.0),
        LacSegment::new(o, 0.0, 80.0, Some(1.0), 0.01, 0.1),
        LacSegment::new(o, 2.5, 70.0, Some(-1.0), 0.0, -0.08),
        LacSegment::new(o, -0.7, 50.0, Some(0.0), -0.2, -0.02),
    ];
    let width = 1.0;
    for seg in planted {
        let seg = seg.expect("a valid segment");
        let bounds = kansei::geom::bounding_box(seg.samples(0.5).map(|s| s.point)).expect("points");
        for (w, h) in [(300, 200), (97, 311)] {
            let view = View::fit(bounds, w, h, 10.0);
            let mut pixmap = Pixmap::new(w, h).expect("pixmap");
            pixmap.fill(tiny_skia::Color::WHITE);
            let path = kansei::render::segment_path(&seg, &view).expect("a path");
            let mut paint = tiny_skia::Paint::default();
            paint.set_color(tiny_skia::Color::BLACK);
            let stroke = tiny_skia::Stroke {
                width: width as f32,
                ..tiny_skia::Stroke::default()
            };
            pixmap.stroke_path(
                &path,
                &paint,
                &stroke,
                tiny_skia::Transform::identity(),
                None,
            );
            let (n, _) = assert_ink_on_segments(&pixmap, &view, &[seg], width);
            assert!(n > 50, "{seg:?}: {n} pixels");
        }
    }
}

#[test]
fn view_round_trip_is_exact_to_rounding() {
    let mut rng = common::Rng::new(3);
    for _ in 0..1000 {
        let mut r = |scale: f64| (rng.uniform() - 0.5) * scale;
        let view = View {
            width: 1 + (r(1.0).abs() * 4000.0) as u32,
            height: 1 + (r(1.0).abs() * 4000.0) as u32,
            center: Point::new(r(2e4), r(2e4)),
            pixels_per_unit: 10f64.powf(r(8.0)),
        };
        let p = Point::new(view.center.x + r(1e4), view.center.y + r(1e4));
        let back = view.to_model(view.to_pixel(p));
        // A few roundings of numbers of the size of |p| and |center|.
        let scale =
            p.x.abs()
                .max(p.y.abs())
                .max(view.center.x.abs())
                .max(view.center.y.abs());
        assert!(
            (back - p).hypot() <= 1e-12 * scale,
            "{view:?}: {p:?} → {back:?}"
        );
        let q = Point::new(r(8000.0), r(8000.0));
        let back = view.to_pixel(view.to_model(q));
        assert!(
            (back - q).hypot()
                <= 1e-9 * (1.0 + q.x.abs() + q.y.abs() + scale * view.pixels_per_unit)
        );
    }
}

#[test]
fn view_fit_holds_every_sample_within_the_margin() {
    let mut files: Vec<StrokeFile> = common::fixture_names()
        .iter()
        .map(|n| common::fixture(n))
        .collect();
    files.push(s_curve_mm());
    for file in &files {
        let out = fitted(file);
        let scene = Scene::new(&file.strokes, &out.curves, file.units);
        for (w, h) in [(1600, 1000), (300, 700), (101, 99)] {
            let view = fit_view(&scene, (w, h));
            for s in file.strokes.iter().flat_map(|s| &s.samples) {
                let q = view.to_pixel(s.point());
                let slack = 1e-9 * (w + h) as f64;
                assert!(
                    q.x >= MARGIN - slack
                        && q.x <= w as f64 - MARGIN + slack
                        && q.y >= MARGIN - slack
                        && q.y <= h as f64 - MARGIN + slack,
                    "{q:?} outside the {w}×{h} view"
                );
            }
        }
    }
}

/// Pixels of `set` that lie within `radius` pixels (Chebyshev) of some pixel of `mask`.
fn near(mask: &[bool], w: usize, k: usize, radius: usize) -> bool {
    let (x, y) = ((k % w) as i64, (k / w) as i64);
    let h = (mask.len() / w) as i64;
    let r = radius as i64;
    (y - r..=y + r).any(|yy| {
        (x - r..=x + r).any(|xx| {
            xx >= 0 && yy >= 0 && xx < w as i64 && yy < h && mask[yy as usize * w + xx as usize]
        })
    })
}

#[test]
fn toggling_an_overlay_changes_pixels_only_where_it_draws() {
    let file = common::fixture("perfect-freehand-corners");
    let out = fitted(&file);
    let size = (480, 300);
    let all = RenderOptions::with_overlays(Overlays::ALL);
    let full = draw(&file, &out, size, &all);
    type Toggle = fn(&mut Overlays);
    let toggles: [(&str, Toggle); 9] = [
        ("samples", |o| o.samples = false),
        ("bspline", |o| o.bspline = false),
        ("control_polygon", |o| o.control_polygon = false),
        ("splits", |o| o.splits = false),
        ("segments", |o| o.segments = false),
        ("joints", |o| o.joints = false),
        ("comb", |o| o.comb = false),
        ("legend", |o| o.legend = false),
        ("scale_bar", |o| o.scale_bar = false),
    ];
    for (name, off) in toggles {
        let mut without = Overlays::ALL;
        off(&mut without);
        let mut alone = Overlays::NONE;
        // The overlay alone: everything ALL has that `without` lacks.
        for (a, b, c) in [
            (&mut alone.samples, without.samples, true),
            (&mut alone.bspline, without.bspline, true),
            (&mut alone.control_polygon, without.control_polygon, true),
            (&mut alone.splits, without.splits, true),
            (&mut alone.segments, without.segments, true),
            (&mut alone.joints, without.joints, true),
            (&mut alone.comb, without.comb, true),
            (&mut alone.legend, without.legend, true),
            (&mut alone.scale_bar, without.scale_bar, true),
        ] {
            *a = c && !b;
        }
        // How the comb is drawn is a mode of the comb, not a layer of its own.
        alone.comb_log = Overlays::ALL.comb_log;
        let partial = draw(&file, &out, size, &RenderOptions::with_overlays(without));
        // The overlay alone, on black and on white: every pixel it covers shows on one of them,
        // whatever colour it paints there (white, like the legend's panel, or black).
        let on = |background: [u8; 4]| {
            let mut options = RenderOptions::with_overlays(alone);
            options.background = background;
            draw(&file, &out, size, &options)
        };
        let (on_black, on_white) = (on([0, 0, 0, 255]), on([255, 255, 255, 255]));
        let mask: Vec<bool> = on_black
            .data()
            .chunks_exact(4)
            .zip(on_white.data().chunks_exact(4))
            .map(|(b, w)| b[..3].iter().any(|&v| v != 0) || w[..3].iter().any(|&v| v != 255))
            .collect();
        let diff = differing(&full, &partial, 0);
        assert!(!diff.is_empty(), "{name}: toggling changed nothing");
        assert_changed_only_near(&mask, size.0 as usize, &diff, name);
    }
    // The highlight likewise.
    let lit = draw(
        &file,
        &out,
        size,
        &RenderOptions {
            highlight: Some((1, 0)),
            ..all
        },
    );
    let band = draw(
        &file,
        &out,
        size,
        &RenderOptions {
            highlight: Some((1, 0)),
            ..RenderOptions::with_overlays(Overlays::NONE)
        },
    );
    let mask = inked(&band);
    let diff = differing(&full, &lit, 0);
    assert!(!diff.is_empty());
    assert!(diff.iter().all(|&k| near(&mask, size.0 as usize, k, 1)));
    // A highlight naming no segment draws nothing.
    let none = draw(
        &file,
        &out,
        size,
        &RenderOptions {
            highlight: Some((999, 0)),
            ..all
        },
    );
    assert!(differing(&full, &none, 0).is_empty());
}

/// `out` moved by `v`: every position the renderer draws (B-spline, split points, span
/// pieces, fitted points, LAC segments). The fit itself is not redone, so the test below sees
/// the renderer alone (a refit of moved data rounds differently and may settle elsewhere).
fn translated_fit(out: &FitOutput, v: kansei::geom::Vec2) -> FitOutput {
    let mut out = out.clone();
    for c in &mut out.curves {
        let moved: Vec<_> = c
            .bspline
            .curve
            .control_points()
            .iter()
            .map(|&p| p + v)
            .collect();
        c.bspline.curve = kansei::bspline::BSpline::new(c.bspline.curve.knots().to_vec(), moved)
            .expect("same shape");
        for split in &mut c.spans.splits {
            split.point += v;
        }
        for span in &mut c.spans.spans {
            for piece in &mut span.pieces {
                let b = &mut piece.bez;
                (b.p0, b.p1, b.p2, b.p3) = (b.p0 + v, b.p1 + v, b.p2 + v, b.p3 + v);
            }
        }
        for p in &mut c.points {
            *p += v;
        }
        for seg in c
            .chain
            .iter_mut()
            .flat_map(|chain| chain.segments.iter_mut())
        {
            let s = seg.segment;
            let (alpha, k0, k1) = (s.alpha(), s.kappa0(), s.kappa1());
            seg.segment = LacSegment::new(s.start() + v, s.theta0(), s.length(), alpha, k0, k1)
                .expect("a valid segment moved is valid");
        }
    }
    out
}

#[test]
fn translating_data_and_view_together_leaves_the_image_unchanged() {
    let file = common::fixture("google-ink-spring");
    let shift = (1234.5, -678.25);
    let moved = StrokeFile::new(
        file.units,
        file.strokes
            .iter()
            .map(|s| common::transform(s, 0.0, 1.0, shift))
            .collect(),
    );
    let options = RenderOptions::with_overlays(Overlays::ALL);
    let size = (480, 300);
    let out = fitted(&file);
    let out_moved = translated_fit(&out, kansei::geom::Vec2::new(shift.0, shift.1));
    let scene = Scene::new(&file.strokes, &out.curves, file.units);
    let view = fit_view(&scene, size);
    let followed = View {
        center: view.center + kansei::geom::Vec2::new(shift.0, shift.1),
        ..view
    };
    let a = render(&scene, &view, &options).expect("renders");
    let scene_moved = Scene::new(&moved.strokes, &out_moved.curves, moved.units);
    let b = render(&scene_moved, &followed, &options).expect("renders");
    let diff = differing(&a, &b, PIXEL_TOLERANCE);
    let fraction = diff.len() as f64 / (size.0 * size.1) as f64;
    assert!(
        fraction <= MAX_DIFFERING_FRACTION,
        "{} pixels differ",
        diff.len()
    );
}

#[test]
fn scaled_options_multiply_every_pixel_size() {
    let o = RenderOptions::default();
    let s = o.scaled(2.0);
    assert_eq!(s.segment_width, 2.0 * o.segment_width);
    assert_eq!(s.bspline_width, 2.0 * o.bspline_width);
    assert_eq!(s.control_polygon_width, 2.0 * o.control_polygon_width);
    assert_eq!(s.sample_radius, 2.0 * o.sample_radius);
    assert_eq!(s.marker_size, 2.0 * o.marker_size);
    assert_eq!(s.comb_spacing, 2.0 * o.comb_spacing);
    assert_eq!(s.highlight_width, 2.0 * o.highlight_width);
    assert_eq!(s.text_size, 2.0 * o.text_size);
    assert_eq!(
        (s.overlays, s.comb_scale, s.background),
        (o.overlays, o.comb_scale, o.background)
    );
}

#[test]
fn bad_views_and_options_are_typed_errors() {
    let file = common::fixture("google-ink-straight-line");
    let out = fitted(&file);
    let scene = Scene::new(&file.strokes, &out.curves, file.units);
    let view = fit_view(&scene, (100, 80));
    let options = RenderOptions::default();
    assert!(matches!(
        render(&scene, &View { height: 0, ..view }, &options),
        Err(RenderError::EmptyImage { .. })
    ));
    assert!(matches!(
        render(
            &scene,
            &View {
                width: 20_000,
                ..view
            },
            &options
        ),
        Err(RenderError::TooLarge { .. })
    ));
    assert!(matches!(
        render(
            &scene,
            &View {
                pixels_per_unit: f64::NAN,
                ..view
            },
            &options
        ),
        Err(RenderError::BadView { .. })
    ));
    let bad = RenderOptions {
        segment_width: -1.0,
        ..options
    };
    assert_eq!(
        render(&scene, &view, &bad).err(),
        Some(RenderError::BadOption {
            name: "segment_width",
            value: -1.0
        })
    );
    // An empty scene has no bounds and renders as background.
    let empty = Scene::new(&[], &[], Units::Mm);
    assert_eq!(scene_bounds(&empty), None);
    let v = View::fit(Rect::default(), 10, 10, 0.0);
    let p = render(&empty, &v, &RenderOptions::with_overlays(Overlays::NONE)).expect("renders");
    assert!(p.data().iter().all(|&b| b == 255));
}

#[test]
fn cli_writes_the_png_at_the_requested_size_and_refuses_a_size_it_cannot_draw() {
    let dir = std::env::temp_dir().join(format!("kansei-render-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let png = dir.join("spring.png");
    let input = format!(
        "{}/fixtures/strokes/google-ink-spring.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let json = dir.join("spring.curve.json");
    let run = |size: &str, png: &PathBuf| {
        std::process::Command::new(env!("CARGO_BIN_EXE_kansei"))
            .args(["fit", &input, "--json"])
            .arg(&json)
            .arg("--png")
            .arg(png)
            .args(["--size", size])
            .output()
            .expect("runs")
    };
    let out = run("320x200", &png);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let image = Pixmap::load_png(&png).expect("a PNG");
    assert_eq!((image.width(), image.height()), (320, 200));
    assert!(inked(&image).iter().filter(|&&i| i).count() > 500);
    // A size the render cannot draw is a bad option value: exit 2, naming the option and the
    // size, and nothing written.
    let bad = dir.join("bad.png");
    let out = run("0x200", &bad);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--size") && stderr.contains("0×200"),
        "{stderr}"
    );
    assert!(!bad.exists());
    // Several inputs: a directory with one PNG per input stem.
    let pngs = dir.join("pngs");
    let jsons = dir.join("jsons");
    let second = input.replace("google-ink-spring", "perfect-freehand-waves");
    run_ok(
        std::process::Command::new(env!("CARGO_BIN_EXE_kansei"))
            .args(["fit", &input, &second, "--size", "200x120", "--json"])
            .arg(&jsons)
            .arg("--png")
            .arg(&pngs),
    );
    for stem in ["google-ink-spring", "perfect-freehand-waves"] {
        let image = Pixmap::load_png(pngs.join(format!("{stem}.png"))).expect("a PNG");
        assert_eq!((image.width(), image.height()), (200, 120));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_zoomed_view_matches_the_same_region_of_a_larger_image() {
    /// Pixels along the image edge left out of the comparison.
    const EDGE_BAND: u32 = 8;
    // Culling and every overlay depend on the view only through the pixel mapping: a W×H view
    // equals the centre of a 3W×3H view with the same centre and scale (whose pixels are the
    // small view's shifted by exactly (W, H)). The control polygon is left out: tiny-skia
    // rasterises a long straight edge that leaves the image up to a pixel differently depending
    // on where the image edge is (measured: 68 pixels differ at zoom 9 with it, 4 without it,
    // those from the comb's long teeth).
    let file = common::fixture("google-ink-spring");
    let out = fitted(&file);
    let scene = Scene::new(&file.strokes, &out.curves, file.units);
    let (w, h) = (240u32, 150u32);
    let options = RenderOptions {
        highlight: Some((0, 3)),
        ..RenderOptions::with_overlays(Overlays {
            legend: false,
            scale_bar: false,
            control_polygon: false,
            ..Overlays::ALL
        })
    };
    let base = fit_view(&scene, (w, h));
    // Zoom about samples, so there is something to see.
    let on_curve = |i: usize| base.to_pixel(file.strokes[0].samples[i].point());
    for (factor, anchor) in [
        (4.0, on_curve(40)),
        (9.0, on_curve(100)),
        (1.0, on_curve(0)),
    ] {
        let small = base.zoomed(factor, anchor);
        let big = View {
            width: 3 * w,
            height: 3 * h,
            ..small
        };
        let a = render(&scene, &small, &options).expect("renders");
        let b = render(&scene, &big, &options).expect("renders");
        let crop = b
            .clone_rect(tiny_skia::IntRect::from_xywh(w as i32, h as i32, w, h).expect("rect"))
            .expect("crop");
        let diff = differing(&a, &crop, PIXEL_TOLERANCE);
        // tiny-skia's anti-aliasing of a path that crosses the image edge depends on where the
        // edge is (it clips before scan conversion): compare away from the border.
        let interior = |k: &usize| {
            let (x, y) = ((k % w as usize) as u32, (k / w as usize) as u32);
            x >= EDGE_BAND && y >= EDGE_BAND && x + EDGE_BAND < w && y + EDGE_BAND < h
        };
        let diff: Vec<usize> = diff.into_iter().filter(interior).collect();
        assert!(
            diff.len() as f64 <= MAX_DIFFERING_FRACTION * (w * h) as f64,
            "zoom {factor}: {} pixels differ",
            diff.len()
        );
        assert!(inked(&a).iter().any(|&i| i), "zoom {factor}: nothing drawn");
    }
}

#[test]
fn culling_never_drops_a_visible_segment() {
    let mut rng = common::Rng::new(11);
    let view = View {
        width: 200,
        height: 120,
        center: Point::new(0.0, 0.0),
        pixels_per_unit: 2.0,
    };
    let (mut kept, mut culled) = (0, 0);
    for _ in 0..2000 {
        let mut r = |a: f64, b: f64| a + (b - a) * rng.uniform();
        let k0 = r(-0.2, 0.2);
        let k1 = k0 * r(0.1, 3.0);
        let alpha = (k0 != k1).then(|| r(-2.0, 2.0));
        let Ok(seg) = LacSegment::new(
            Point::new(r(-150.0, 150.0), r(-100.0, 100.0)),
            r(-3.0, 3.0),
            r(1.0, 80.0),
            alpha,
            k0,
            k1,
        ) else {
            continue;
        };
        let pad = 2.0;
        if kansei::render::segment_may_show(&seg, &view, pad) {
            kept += 1;
        } else {
            culled += 1;
            for s in seg.samples(0.05) {
                let q = view.to_pixel(s.point);
                assert!(
                    q.x < -pad || q.y < -pad || q.x > 200.0 + pad || q.y > 120.0 + pad,
                    "{seg:?} culled but reaches {q:?}"
                );
            }
        }
    }
    assert!(kept > 100 && culled > 100, "kept {kept}, culled {culled}");
}

/// A quarter circle of radius `r` mm, sampled every degree, and its fit.
fn quarter_circle(r: f64) -> (StrokeFile, FitOutput) {
    let arc = Stroke::from_points((0..=90).map(|d| {
        let a = (d as f64).to_radians();
        Point::new(r * a.cos(), r * a.sin())
    }));
    let file = StrokeFile::new(Units::Mm, vec![arc]);
    let out = fitted(&file);
    (file, out)
}

#[test]
fn legend_ramp_shows_the_svg_colour_of_each_alpha() {
    let options = RenderOptions::with_overlays(Overlays {
        legend: true,
        ..Overlays::NONE
    });
    let empty = Scene::new(&[], &[], Units::Mm);
    let view = View::fit(Rect::new(0.0, 0.0, 1.0, 1.0), 400, 200, 0.0);
    let pixmap = render(&empty, &view, &options).expect("renders");
    let layout =
        kansei::render::legend_layout(400, options.text_size).expect("a legend at size 13");
    let ramp = layout.ramp;
    assert!(layout.panel.contains(Point::new(ramp.x0, ramp.y0)));
    assert!(layout.panel.x1 <= 400.0 && layout.panel.y0 >= 0.0);
    let y = (0.5 * (ramp.y0 + ramp.y1)) as u32;
    let (a0, a1) = (
        kansei::render::ALPHA_BLUE_END,
        kansei::render::ALPHA_RED_END,
    );
    for x in ramp.x0 as u32..ramp.x1 as u32 {
        let alpha = a0 + (a1 - a0) * (f64::from(x) + 0.5 - ramp.x0) / ramp.width();
        let want = kansei::render::alpha_colour(Some(alpha));
        let got = pixmap.pixel(x, y).expect("inside").demultiply();
        let got = [got.red(), got.green(), got.blue()];
        // Whole-pixel columns: exact up to the rounding of the 8-bit colour.
        for c in 0..3 {
            assert!(
                got[c].abs_diff(want[c]) <= 1,
                "α {alpha}: {got:?} vs {want:?}"
            );
        }
    }
}

#[test]
fn automatic_comb_scale_of_a_circle_is_the_closed_form() {
    // κ = 1/r everywhere: the 95th percentile is 1/r, so the scale is 0.1 · diagonal · r.
    let r = 50.0;
    let (file, out) = quarter_circle(r);
    let scene = Scene::new(&file.strokes, &out.curves, file.units);
    let b = scene_bounds(&scene).expect("bounds");
    let want = kansei::render::COMB_HEIGHT_FRACTION * b.width().hypot(b.height()) * r;
    let got = kansei::render::auto_comb_scale(&scene).expect("a scale");
    // The fitted chain's curvature is 1/r within the fit's accuracy (a few percent at most).
    assert!((got / want - 1.0).abs() < 0.05, "{got} vs {want}");
    assert_eq!(
        kansei::render::auto_comb_scale(&Scene::new(&[], &[], Units::Mm)),
        None
    );
}

#[test]
fn comb_teeth_stand_outside_a_circle() {
    // Teeth point away from the centre of curvature: every comb pixel lies outside the circle
    // (less the line's half width and a pixel), and the envelope reaches r + κ·scale.
    let r = 50.0;
    let (file, out) = quarter_circle(r);
    let scene = Scene::new(&file.strokes, &out.curves, file.units);
    let scale = 20.0 * r; // teeth 20 mm long
    let options = RenderOptions {
        comb_scale: Some(scale),
        ..RenderOptions::with_overlays(Overlays {
            comb: true,
            ..Overlays::NONE
        })
    };
    let (w, h) = (400u32, 400u32);
    let view = View::fit(Rect::new(-5.0, -5.0, 75.0, 75.0), w, h, 0.0);
    let pixmap = render(&scene, &view, &options).expect("renders");
    let ink = inked(&pixmap);
    let mut farthest: f64 = 0.0;
    for (k, _) in ink.iter().enumerate().filter(|(_, i)| **i) {
        let q = Point::new((k % w as usize) as f64 + 0.5, (k / w as usize) as f64 + 0.5);
        let d = view.to_model(q).to_vec2().hypot();
        let slack = 1.5 / view.pixels_per_unit;
        assert!(d >= r - slack, "comb pixel at radius {d}");
        farthest = farthest.max(d);
    }
    let tooth = scale / r;
    assert!(
        (farthest - (r + tooth)).abs() < 0.05 * tooth,
        "envelope at {farthest}, want {}",
        r + tooth
    );
}

#[test]
fn cut_comb_teeth_carry_a_cross_beyond_the_envelope() {
    // A comb scale far beyond the drawing cuts every tooth of a circle to the longest length,
    // COMB_MAX_TOOTH_FRACTION of the diagonal: the envelope is the circle of radius r + that,
    // and only the crosses on the cut tips reach beyond it.
    let r = 50.0;
    let (file, out) = quarter_circle(r);
    let scene = Scene::new(&file.strokes, &out.curves, file.units);
    let b = scene_bounds(&scene).expect("bounds");
    let longest = kansei::render::COMB_MAX_TOOTH_FRACTION * b.width().hypot(b.height());
    let (w, h) = (400u32, 400u32);
    let view = View::fit(Rect::new(-5.0, -5.0, 95.0, 95.0), w, h, 0.0);
    let beyond = |scale: f64| {
        let options = RenderOptions {
            comb_scale: Some(scale),
            ..RenderOptions::with_overlays(Overlays {
                comb: true,
                ..Overlays::NONE
            })
        };
        let pixmap = render(&scene, &view, &options).expect("renders");
        let ink = inked(&pixmap);
        let edge = r + longest + 1.5 / view.pixels_per_unit;
        ink.iter()
            .enumerate()
            .filter(|(k, i)| {
                let q = Point::new((k % w as usize) as f64 + 0.5, (k / w as usize) as f64 + 0.5);
                **i && view.to_model(q).to_vec2().hypot() > edge
            })
            .count()
    };
    assert!(beyond(1000.0 * r) > 0, "no mark on the cut teeth");
    // Teeth a little shorter than the longest (none cut): nothing beyond the envelope.
    assert_eq!(beyond(0.95 * longest * r), 0);
}

#[test]
fn non_finite_samples_are_skipped() {
    let stroke = Stroke::new(vec![
        Sample::new(0.0, 0.0),
        Sample::new(f64::NAN, 1.0),
        Sample::new(10.0, f64::INFINITY),
        Sample::new(10.0, 10.0),
    ]);
    let strokes = [stroke];
    let scene = Scene::new(&strokes, &[], Units::Mm);
    let b = scene_bounds(&scene).expect("two finite samples");
    assert_eq!(b, Rect::new(0.0, 0.0, 10.0, 10.0));
    let view = View::fit(b, 50, 50, 5.0);
    let p = render(&scene, &view, &RenderOptions::default()).expect("renders");
    assert!(inked(&p).iter().any(|&i| i));
}

/// Size of the PNGs of [`every_fixture_png_through_the_cli_path_lies_on_its_chain`]: wide
/// enough that the fixtures' strokes are several pixels apart, small enough for eight renders.
const FIXTURE_PNG_SIZE: (u32, u32) = (800, 500);

/// The view `kansei fit --png` draws in (`kansei::render::quick_look_png`): the whole scene, with
/// the CLI's margin.
fn cli_view(file: &StrokeFile, out: &FitOutput, (w, h): (u32, u32)) -> View {
    let scene = Scene::new(&file.strokes, &out.curves, file.units);
    View::fit(
        scene_bounds(&scene).expect("a non-empty scene"),
        w,
        h,
        kansei::render::QUICK_LOOK_MARGIN_PX,
    )
}

#[test]
fn every_fixture_png_through_the_cli_path_lies_on_its_chain() {
    // The LAC segments alone (`--png-layers segments`), so every inked pixel is curve colour.
    let options = RenderOptions::with_overlays(Overlays {
        segments: true,
        ..Overlays::NONE
    });
    let width = options.segment_width;
    let mut figures = Vec::new();
    for name in common::fixture_names() {
        let file = common::fixture(&name);
        let out = fitted(&file);
        let bytes = kansei::render::quick_look_png(&file, &out, FIXTURE_PNG_SIZE, &options)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"), "{name}: not a PNG");
        let pixmap = Pixmap::decode_png(&bytes).expect("decodes");
        assert_eq!(
            (pixmap.width(), pixmap.height()),
            FIXTURE_PNG_SIZE,
            "{name}: the size asked"
        );
        let segments: Vec<LacSegment> = out
            .curves
            .iter()
            .filter_map(|c| c.chain.as_ref())
            .flat_map(|c| &c.segments)
            .map(|s| s.segment)
            .collect();
        assert!(!segments.is_empty(), "{name}: no chain");
        // Every inked pixel within ink_bound(width) of the exact chain, and ink beside every
        // point of the chain.
        let (inked, farthest) = assert_ink_on_segments(
            &pixmap,
            &cli_view(&file, &out, FIXTURE_PNG_SIZE),
            &segments,
            width,
        );
        assert!(inked > 100, "{name}: {inked} inked pixels");
        figures.push(format!("{name}: {inked} px, farthest {farthest:.3}"));
    }
    assert!(figures.len() >= 9, "every fixture: {figures:?}");
    println!(
        "{}×{} px, every inked pixel within {:.3} px of the chain, ink beside every chain point: {}",
        FIXTURE_PNG_SIZE.0,
        FIXTURE_PNG_SIZE.1,
        ink_bound(width),
        figures.join(", ")
    );
}

#[test]
fn cli_png_layers_draw_the_overlays_named_and_the_comb_only_where_it_draws() {
    let dir = std::env::temp_dir().join(format!("kansei-png-layers-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let name = "perfect-freehand-corners";
    let input = format!(
        "{}/fixtures/strokes/{name}.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let size = (480, 300);
    let run = |layers: &str| {
        let png = dir.join(format!("{}.png", layers.replace(',', "_")));
        run_ok(
            std::process::Command::new(env!("CARGO_BIN_EXE_kansei"))
                .args(["fit", &input, "--json"])
                .arg(dir.join("out.curve.json"))
                .arg("--png")
                .arg(&png)
                .args(["--size", "480x300", "--png-layers", layers]),
        );
        Pixmap::load_png(&png).expect("a PNG")
    };
    let base = run("segments,splits,legend");
    let with_comb = run("segments,splits,legend,comb");
    let comb = run("comb");
    // The flag names the overlays drawn: the CLI's image is the library's with those overlays.
    let file = common::fixture(name);
    let out = fitted(&file);
    let overlays = Overlays {
        segments: true,
        splits: true,
        legend: true,
        ..Overlays::NONE
    };
    let library =
        kansei::render::quick_look_png(&file, &out, size, &RenderOptions::with_overlays(overlays))
            .expect("renders");
    assert_eq!(
        base.data(),
        Pixmap::decode_png(&library).expect("decodes").data()
    );
    // Asking for the comb changes pixels, and only next to what the comb alone draws (any
    // pixel it touches at all: the difference is exact, and the faint end of a needle cut at
    // the image's edge is below the ink level).
    let mask = touched(&comb, 0);
    let diff = differing(&base, &with_comb, 0);
    assert!(!diff.is_empty(), "the comb changed nothing");
    assert!(mask.iter().filter(|&&m| m).count() > 100);
    assert_changed_only_near(&mask, size.0 as usize, &diff, "comb");
    // An unknown layer is a usage error naming the accepted ones.
    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_kansei"))
        .args(["fit", &input, "--png"])
        .arg(dir.join("bad.png"))
        .args(["--png-layers", "segments,wiggle"])
        .output()
        .expect("runs");
    assert!(!bad.status.success());
    let stderr = String::from_utf8_lossy(&bad.stderr);
    assert!(
        stderr.contains("wiggle") && stderr.contains("comb"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn lac_joints_are_bars_across_the_chain_ink_where_g2_and_red_where_the_curvature_jumps() {
    // The spring in G1 (its joints jump) and in G2 (where the smooth fit holds, they do not).
    let file = common::fixture("google-ink-spring");
    let options = RenderOptions::with_overlays(Overlays {
        joints: true,
        ..Overlays::NONE
    });
    let size = (800, 500);
    let mut seen = (0, 0);
    for continuity in [kansei::chain::Continuity::G1, kansei::chain::Continuity::G2] {
        let mut pipeline = PipelineOptions::default();
        pipeline.chain.continuity = continuity;
        let out = fit_file(&file, &pipeline).expect("fits");
        let scene = Scene::new(&file.strokes, &out.curves, file.units);
        let view = fit_view(&scene, size);
        let pixmap = render(&scene, &view, &options).expect("renders");
        let ink = inked(&pixmap);
        let w = size.0 as usize;
        let mut joints = Vec::new();
        for chain in out.curves.iter().filter_map(|c| c.chain.as_ref()) {
            for pair in chain.segments.windows(2) {
                let (a, b) = (&pair[0].segment, &pair[1].segment);
                let jump = kansei::export::relative_jump(a.kappa1(), b.kappa0()).expect("finite");
                joints.push((view.to_pixel(b.start()), jump <= 1e-9));
            }
        }
        assert!(!joints.is_empty());
        // Every inked pixel belongs to a bar: within the bar's half-length (0.7 markers) and
        // width of a joint.
        let reach = 0.7 * options.marker_size + 3.0;
        for (k, _) in ink.iter().enumerate().filter(|(_, i)| **i) {
            let q = kansei::geom::Point::new((k % w) as f64 + 0.5, (k / w) as f64 + 0.5);
            assert!(
                joints.iter().any(|(p, _)| p.distance(q) <= reach),
                "{continuity:?}: ink at {q:?} away from every joint"
            );
        }
        // The pixel under each joint that stands alone (no other joint within reach) is ink for
        // a curvature-continuous joint and red for a jump.
        for (p, continuous) in &joints {
            if joints
                .iter()
                .filter(|(o, _)| o.distance(*p) <= 2.0 * reach)
                .count()
                > 1
            {
                continue;
            }
            let (x, y) = (p.x.floor() as usize, p.y.floor() as usize);
            let c = &pixmap.data()[4 * (y * w + x)..4 * (y * w + x) + 3];
            let red = c[0] > 150 && c[1] < 100;
            let dark = c.iter().all(|&v| v < 100);
            if *continuous {
                assert!(dark, "{continuity:?}: G2 joint at {p:?} drawn {c:?}");
                seen.0 += 1;
            } else {
                assert!(red, "{continuity:?}: jump at {p:?} drawn {c:?}");
                seen.1 += 1;
            }
        }
    }
    assert!(seen.0 > 0 && seen.1 > 0, "both kinds drawn: {seen:?}");
}

#[test]
fn the_log_comb_is_the_linear_comb_for_small_curvature_and_keeps_needles_on_the_drawing() {
    use kansei::render::comb_tooth;
    let (scale, reference) = (50.0, 0.02);
    for k in [1e-6, 1e-5, 1e-4] {
        let (linear, log) = (
            comb_tooth(k, scale, None),
            comb_tooth(k, scale, Some(reference)),
        );
        assert!(
            (log - linear).abs() <= 0.01 * linear,
            "κ {k}: {log} against {linear}"
        );
        // Odd in κ: the tooth stands on the convex side either way.
        assert_eq!(comb_tooth(-k, scale, Some(reference)), -log);
    }
    // Monotone, and a needle a hundred times the reference is ln(101) references long, not 100.
    let teeth: Vec<f64> = (0..50)
        .map(|i| comb_tooth(reference * 1.2f64.powi(i), scale, Some(reference)))
        .collect();
    assert!(teeth.windows(2).all(|w| w[1] > w[0]));
    let needle = comb_tooth(100.0 * reference, scale, Some(reference));
    assert!((needle - scale * reference * 101f64.ln()).abs() < 1e-12);
    // A reference that is no positive number gives the linear tooth.
    assert_eq!(comb_tooth(0.3, scale, Some(0.0)), 0.3 * scale);
    assert_eq!(comb_tooth(0.3, scale, Some(f64::NAN)), 0.3 * scale);
}
