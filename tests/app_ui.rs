//! Headless UI tests of `kansei app` with egui_kittest: pointer events in, widget queries and
//! the canvas's rendered image out. No window and no GPU: the canvas is drawn by tiny-skia.
#![cfg(feature = "app")]

use std::path::PathBuf;
use std::time::{Duration, Instant};

use eframe::egui::{self, Event, Modifiers, PointerButton, Vec2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use kansei::app::{AppOptions, KanseiApp};

/// Window size of the harness, points.
const WINDOW: [f32; 2] = [1280.0, 800.0];

/// Simulated frame time, seconds: a 60 Hz display (kittest's default is 0.25 s, which would end
/// a replay in a few frames).
const FRAME_S: f32 = 1.0 / 60.0;

/// Longest wait for the fitting thread; a guard against a hang, not a timing claim.
const FIT_DEADLINE: Duration = Duration::from_secs(120);

/// A fresh directory under the system's temp dir for one test.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("kansei-app-ui-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::create_dir_all(&dir);
    dir
}

fn harness(options: AppOptions) -> Harness<'static, KanseiApp> {
    let app = KanseiApp::new(&egui::Context::default(), options);
    Harness::builder()
        .with_size(WINDOW)
        .with_step_dt(FRAME_S)
        .build_ui_state(|ui, app: &mut KanseiApp| app.ui(ui), app)
}

/// Steps until every fit is back (the worker thread runs meanwhile).
fn wait_for_fits(harness: &mut Harness<'static, KanseiApp>) {
    let start = Instant::now();
    loop {
        harness.step();
        if harness.state().fits_settled() {
            // One more frame so the panels show what arrived.
            harness.step();
            harness.step();
            return;
        }
        assert!(start.elapsed() < FIT_DEADLINE, "the fit never arrived");
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// Draws through `points` with the primary button: pressed at the first, one frame per move,
/// released at the last.
fn pointer_stroke(harness: &mut Harness<'static, KanseiApp>, points: &[egui::Pos2]) {
    let (Some(&start), Some(&last)) = (points.first(), points.last()) else {
        return;
    };
    harness.event(Event::PointerMoved(start));
    harness.step();
    harness.event(Event::PointerButton {
        pos: start,
        button: PointerButton::Primary,
        pressed: true,
        modifiers: Modifiers::NONE,
    });
    harness.step();
    for &p in &points[1..] {
        harness.event(Event::PointerMoved(p));
        harness.step();
    }
    harness.event(Event::PointerButton {
        pos: last,
        button: PointerButton::Primary,
        pressed: false,
        modifiers: Modifiers::NONE,
    });
    harness.step();
}

/// Draws a 100° arc of radius 80 points with the primary button, one frame per move.
fn draw_arc(harness: &mut Harness<'static, KanseiApp>) {
    harness.step();
    let rect = harness.state().canvas().screen_rect();
    let Some(rect) = rect else {
        panic!("the canvas was not shown");
    };
    let centre = rect.center() + Vec2::new(-40.0, 40.0);
    let point = |deg: f32| {
        let a = deg.to_radians();
        centre + 80.0 * Vec2::new(a.cos(), -a.sin())
    };
    let points: Vec<egui::Pos2> = std::iter::once(point(0.0))
        .chain((2..=100).step_by(2).map(|deg| point(deg as f32)))
        .collect();
    pointer_stroke(harness, &points);
}

/// Samples the canvas shows (a replay shows them as their time comes).
fn shown_samples(harness: &Harness<'static, KanseiApp>) -> usize {
    harness
        .state()
        .scene()
        .strokes
        .iter()
        .map(|s| s.samples.len())
        .sum()
}

fn segment_count(harness: &Harness<'static, KanseiApp>) -> usize {
    harness.state().scene().segments().count()
}

#[test]
fn a_drawn_stroke_is_fitted_and_its_segments_are_listed() {
    let mut harness = harness(AppOptions::default());
    draw_arc(&mut harness);
    assert_eq!(harness.state().document().strokes().len(), 1);
    let stroke = &harness.state().document().strokes()[0].stroke;
    assert!(
        stroke.samples.len() >= 40,
        "{} samples",
        stroke.samples.len()
    );
    assert!(stroke.samples.iter().all(|s| s.t.is_some()));
    wait_for_fits(&mut harness);
    let n = segment_count(&harness);
    assert!(n >= 1);
    harness.get_by_label(&format!("Segments ({n})"));
    // The first row, stroke 1, piece 1, segment 1, selects the segment and shows its plots.
    harness.get_by_label("1.1.1").click();
    harness.step();
    harness.step();
    let selection = harness.state().view.selection;
    assert!(selection.is_some());
    assert_eq!(harness.state().render_options().highlight, Some((0, 0)));
    harness.get_by_label_contains("LCG");
    // The fitted arc is near a circle of radius 80 points = 20 mm at 4 px/mm (and 1 point per
    // pixel here): the segments' curvature is within 10 % of 1/20 mm⁻¹.
    for (_, _, seg) in harness.state().scene().segments() {
        for k in [seg.segment.kappa0(), seg.segment.kappa1()] {
            assert!((k.abs() - 0.05).abs() < 0.005, "κ = {k}");
        }
    }
}

#[test]
fn overlay_toggles_change_the_rendered_image() {
    let mut harness = harness(AppOptions::default());
    draw_arc(&mut harness);
    wait_for_fits(&mut harness);
    let before = harness
        .state()
        .canvas()
        .rendered()
        .map(|r| r.pixmap.clone());
    let Some(before) = before else {
        panic!("nothing rendered");
    };
    for label in ["samples", "B-spline", "split points", "LAC segments"] {
        harness.get_by_label(label).click();
    }
    harness.step();
    harness.step();
    let rendered = harness.state().canvas().rendered();
    let Some(after) = rendered else {
        panic!("nothing rendered");
    };
    let o = after.options.overlays;
    assert!(!o.samples && !o.bspline && !o.splits && !o.segments);
    assert_ne!(after.pixmap.data(), before.data());
    // With the drawing's layers off, only the legend and scale bar remain: fewer ink pixels.
    let ink = |p: &kansei::render::Pixmap| p.pixels().iter().filter(|c| c.red() < 200).count();
    assert!(
        ink(&after.pixmap) < ink(&before),
        "{} vs {}",
        ink(&after.pixmap),
        ink(&before)
    );
}

#[test]
fn undo_removes_the_stroke_and_redo_brings_it_back() {
    let mut harness = harness(AppOptions::default());
    draw_arc(&mut harness);
    wait_for_fits(&mut harness);
    let drawn = harness.state().document().strokes()[0].stroke.clone();
    let n = segment_count(&harness);
    harness.get_by_label("Undo").click();
    harness.step();
    harness.step();
    assert!(harness.state().document().strokes().is_empty());
    assert_eq!(segment_count(&harness), 0);
    harness.get_by_label("Segments (0)");
    harness.get_by_label("Redo").click();
    harness.step();
    wait_for_fits(&mut harness);
    assert_eq!(harness.state().document().strokes()[0].stroke, drawn);
    assert_eq!(segment_count(&harness), n);
}

#[test]
fn a_bad_file_leaves_the_drawing_and_says_why() {
    let dir = temp_dir("bad-file");
    let bad = dir.join("broken.json");
    let _ = std::fs::write(&bad, "{\"format\": \"kansei-stroke\", \"version\": 7}");
    let mut harness = harness(AppOptions::default());
    draw_arc(&mut harness);
    wait_for_fits(&mut harness);
    let strokes = harness.state().document().strokes().to_vec();
    harness.state_mut().view.path = bad.display().to_string();
    harness.step();
    harness.get_by_label("Open").click();
    harness.step();
    harness.step();
    assert_eq!(harness.state().document().strokes(), &strokes[..]);
    harness.get_by_label_contains("cannot open");
    harness.get_by_label_contains("broken.json");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_finished_stroke_survives_in_the_recovery_file() {
    let dir = temp_dir("recovery");
    let recovery = dir.join("recovery.json");
    let options = AppOptions {
        recovery: Some(recovery.clone()),
        ..AppOptions::default()
    };
    let mut first = harness(options.clone());
    draw_arc(&mut first);
    let drawn = first.state().document().to_file();
    assert!(recovery.exists(), "no recovery file after a stroke");
    // The app is "killed": no on_exit. The next start offers the drawing back.
    drop(first);
    let mut second = harness(options);
    second.step();
    assert!(second.state().recovery_offered());
    second.get_by_label("Recover").click();
    second.step();
    second.step();
    assert_eq!(second.state().document().to_file(), drawn);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_opened_fixture_is_fitted_and_replayed() {
    let fixture = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/strokes");
    let Some(path) = std::fs::read_dir(&fixture).ok().and_then(|d| {
        let mut paths: Vec<PathBuf> = d.filter_map(Result::ok).map(|e| e.path()).collect();
        paths.sort();
        paths
            .into_iter()
            .find(|p| p.extension().is_some_and(|e| e == "json"))
    }) else {
        panic!("no fixture in {}", fixture.display());
    };
    let mut harness = harness(AppOptions {
        open: Some(path.clone()),
        replay: true,
        ..AppOptions::default()
    });
    harness.step();
    let strokes = harness.state().document().strokes().len();
    assert!(strokes >= 1);
    // While replaying, the canvas shows fewer samples than the file has.
    let total: usize = harness
        .state()
        .document()
        .strokes()
        .iter()
        .map(|s| s.stroke.samples.len())
        .sum();
    let shown = shown_samples(&harness);
    assert!(
        shown < total,
        "{shown} of {total} samples shown at the replay's start"
    );
    harness.get_by_label("Stop").click();
    wait_for_fits(&mut harness);
    let shown = shown_samples(&harness);
    assert_eq!(shown, total);
    assert!(segment_count(&harness) >= 1);
}

#[test]
fn fixing_alpha_refits_the_selected_stroke_at_once() {
    let mut harness = harness(AppOptions::default());
    draw_arc(&mut harness);
    wait_for_fits(&mut harness);
    let revision = harness.state().document().strokes()[0].revision;
    let drawn = harness.state().document().strokes()[0].settings;
    harness.get_by_label("1.1.1").click();
    harness.step();
    harness.get_by_label("fixed").click();
    harness.step();
    let stroke = &harness.state().document().strokes()[0];
    assert_ne!(
        stroke.revision, revision,
        "the settings change is a new revision"
    );
    // The range [−3, 3] becomes its middle, α = 0, for this stroke only.
    assert_eq!(stroke.settings.alpha, kansei::lac::AlphaChoice::Fixed(0.0));
    assert_eq!(
        harness.state().view.new_stroke_settings,
        kansei::app::document::FitSettings::default()
    );
    wait_for_fits(&mut harness);
    for (_, _, seg) in harness.state().scene().segments() {
        assert!(
            seg.segment.alpha().is_none_or(|a| a == 0.0),
            "{:?}",
            seg.segment.alpha()
        );
    }
    // Undo restores the range and refits again.
    harness.get_by_label("Undo").click();
    harness.step();
    assert_eq!(harness.state().document().strokes()[0].settings, drawn);
}

#[test]
fn choosing_g2_refits_the_selected_stroke_curvature_continuous() {
    let mut harness = harness(AppOptions::default());
    draw_arc(&mut harness);
    wait_for_fits(&mut harness);
    harness.get_by_label("1.1.1").click();
    harness.step();
    harness.get_by_label("G2").click();
    harness.step();
    let stroke = &harness.state().document().strokes()[0];
    assert_eq!(stroke.settings.continuity, kansei::chain::Continuity::G2);
    wait_for_fits(&mut harness);
    // The drawn arc's chain is G2: every joint between consecutive segments of one piece is
    // curvature-continuous to rounding.
    let rows: Vec<_> = harness.state().scene().segments().collect();
    assert!(!rows.is_empty());
    for w in rows.windows(2) {
        let ((a, _, first), (b, _, second)) = (w[0], w[1]);
        if a.stroke == b.stroke && a.piece == b.piece {
            let jump =
                kansei::export::relative_jump(first.segment.kappa1(), second.segment.kappa0());
            assert!(jump.is_some_and(|j| j <= 1e-9), "{jump:?}");
        }
    }
}

/// Steps until the tablet feed has ended or failed.
fn wait_for_tablet(harness: &mut Harness<'static, KanseiApp>) {
    use kansei::app::tablet::FeedState;
    let start = Instant::now();
    loop {
        harness.step();
        let state = harness.state().tablet().map(|t| t.state().clone());
        if matches!(state, Some(FeedState::Ended | FeedState::Failed(_))) {
            harness.step();
            return;
        }
        assert!(
            start.elapsed() < FIT_DEADLINE,
            "the tablet feed never ended"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[test]
fn a_tablet_recording_draws_the_strokes_kansei_replay_gives() {
    // The recording plays through the tablet feed (its own thread, paced, the capture layer's
    // decoder and stroke builder) into the drawing: the strokes must be exactly those that
    // `kansei replay` makes of the same file, pressure and tilt included, and get fitted.
    use kansei::app::tablet::TabletChoice;
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures/hid/pen-three-vertical-strokes.hid");
    let text = std::fs::read_to_string(&path).expect("fixture");
    let (expected, _) = kansei::capture::replay::replay_text(&text).expect("replays");
    let mut harness = harness(AppOptions {
        tablet: Some(TabletChoice::Recording { path, speed: 40.0 }),
        ..AppOptions::default()
    });
    wait_for_tablet(&mut harness);
    wait_for_fits(&mut harness);
    let app = harness.state();
    assert_eq!(
        app.tablet().map(|t| t.state().clone()),
        Some(kansei::app::tablet::FeedState::Ended)
    );
    let drawn: Vec<_> = app
        .document()
        .strokes()
        .iter()
        .map(|s| s.stroke.clone())
        .collect();
    assert_eq!(drawn.len(), 3, "the recording holds three strokes");
    assert_eq!(drawn, expected.strokes);
    assert!(
        drawn
            .iter()
            .flat_map(|s| &s.samples)
            .all(|s| s.pressure.is_some() && s.tilt_x.is_some())
    );
    assert!(segment_count(&harness) >= 3, "every stroke is fitted");
}

#[test]
fn a_tablet_that_cannot_be_opened_says_why_and_the_app_goes_on() {
    use kansei::app::tablet::{FeedState, TabletChoice};
    let mut harness = harness(AppOptions {
        tablet: Some(TabletChoice::Recording {
            path: PathBuf::from("/nonexistent/tablet.hid"),
            speed: 1.0,
        }),
        ..AppOptions::default()
    });
    wait_for_tablet(&mut harness);
    let state = harness.state().tablet().map(|t| t.state().clone());
    let Some(FeedState::Failed(reason)) = state else {
        panic!("expected a failure, got {state:?}");
    };
    assert!(reason.contains("/nonexistent/tablet.hid"), "{reason}");
    harness.get_by_label_contains("tablet.hid");
    // Drawing with the pointer still works.
    draw_arc(&mut harness);
    wait_for_fits(&mut harness);
    assert_eq!(harness.state().document().strokes().len(), 1);
}

/// Clicks the primary button at `pos` (press and release, no movement).
fn click_at(harness: &mut Harness<'static, KanseiApp>, pos: egui::Pos2) {
    harness.event(Event::PointerMoved(pos));
    harness.step();
    for pressed in [true, false] {
        harness.event(Event::PointerButton {
            pos,
            button: PointerButton::Primary,
            pressed,
            modifiers: Modifiers::NONE,
        });
        harness.step();
    }
    harness.step();
}

/// The screen position (points) of a model point in the canvas's current view.
fn on_screen(harness: &Harness<'static, KanseiApp>, p: kansei::geom::Point) -> egui::Pos2 {
    let canvas = harness.state().canvas();
    let (Some(view), Some(rect)) = (canvas.view(), canvas.screen_rect()) else {
        panic!("the canvas was not shown");
    };
    let px = view.to_pixel(p);
    // The harness draws at one pixel per point.
    rect.min + Vec2::new(px.x as f32, px.y as f32)
}

#[test]
fn clicking_a_segment_selects_it_and_delete_removes_its_stroke() {
    let mut harness = harness(AppOptions::default());
    draw_arc(&mut harness);
    wait_for_fits(&mut harness);
    let strokes = harness.state().document().strokes().len();
    assert_eq!(strokes, 1);
    // Click the middle of the last segment: it becomes the selection.
    let (want, middle) = {
        let (selection, _, seg) = harness
            .state()
            .scene()
            .segments()
            .last()
            .expect("a fitted segment");
        (selection, seg.segment.point(0.5 * seg.segment.length()))
    };
    let pos = on_screen(&harness, middle);
    click_at(&mut harness, pos);
    assert_eq!(harness.state().view.selection, Some(want));
    assert_eq!(
        harness.state().document().strokes().len(),
        strokes,
        "a click draws nothing"
    );
    // A click far from every segment clears the selection: of a few points 150 px around the
    // segment's middle, the one farthest from the drawn chain (each segment sampled on screen).
    let drawn: Vec<egui::Pos2> = harness
        .state()
        .scene()
        .segments()
        .flat_map(|(_, _, seg)| {
            (0..=32).map(|i| seg.segment.point(seg.segment.length() * i as f64 / 32.0))
        })
        .collect::<Vec<_>>()
        .into_iter()
        .map(|p| on_screen(&harness, p))
        .collect();
    let clearance = |q: egui::Pos2| {
        drawn
            .iter()
            .map(|p| p.distance(q))
            .fold(f32::INFINITY, f32::min)
    };
    let away = [(0.0, 150.0), (0.0, -150.0), (150.0, 0.0), (-150.0, 0.0)]
        .into_iter()
        .map(|(x, y)| pos + Vec2::new(x, y))
        .max_by(|a, b| clearance(*a).total_cmp(&clearance(*b)))
        .expect("four candidates");
    assert!(clearance(away) > 60.0, "{}", clearance(away));
    click_at(&mut harness, away);
    assert_eq!(harness.state().view.selection, None);
    // Select again, then delete the stroke with the button; undo brings it back.
    click_at(&mut harness, pos);
    assert_eq!(harness.state().view.selection, Some(want));
    harness.get_by_label("Delete stroke").click();
    harness.step();
    harness.step();
    assert!(harness.state().document().strokes().is_empty());
    assert_eq!(harness.state().view.selection, None);
    harness.get_by_label("Undo").click();
    harness.step();
    wait_for_fits(&mut harness);
    assert_eq!(harness.state().document().strokes().len(), 1);
}

#[test]
fn the_fit_grows_while_the_pen_moves_and_gives_way_to_the_final_fit() {
    let mut harness = harness(AppOptions::default());
    harness.step();
    let Some(rect) = harness.state().canvas().screen_rect() else {
        panic!("the canvas was not shown");
    };
    let centre = rect.center() + Vec2::new(-40.0, 40.0);
    let point = |deg: f32| {
        let a = deg.to_radians();
        centre + 80.0 * Vec2::new(a.cos(), -a.sin())
    };
    harness.event(Event::PointerMoved(point(0.0)));
    harness.step();
    harness.event(Event::PointerButton {
        pos: point(0.0),
        button: PointerButton::Primary,
        pressed: true,
        modifiers: Modifiers::NONE,
    });
    harness.step();
    for deg in (2..=90).step_by(2) {
        harness.event(Event::PointerMoved(point(deg as f32)));
        harness.step();
    }
    // The button is still down: the stroke so far gets fitted and drawn over the live line.
    let start = Instant::now();
    while harness.state().canvas().preview.is_empty() {
        assert!(start.elapsed() < FIT_DEADLINE, "no growing fit appeared");
        std::thread::sleep(Duration::from_millis(10));
        harness.step();
    }
    assert!(harness.state().document().strokes().is_empty());
    // The preview follows the arc drawn so far: every point about 80 points (20 mm) from the
    // centre in model units, within the pointer's quantisation.
    let view = harness.state().canvas().view().expect("a view");
    let c = view.to_model(kansei::geom::Point::new(
        f64::from(centre.x - rect.min.x),
        f64::from(centre.y - rect.min.y),
    ));
    for (points, _) in &harness.state().canvas().preview {
        for p in points {
            let r = p.distance(c) * view.pixels_per_unit;
            assert!(
                (r - 80.0).abs() < 2.0,
                "preview point {r} points from the centre"
            );
        }
    }
    harness.event(Event::PointerButton {
        pos: point(90.0),
        button: PointerButton::Primary,
        pressed: false,
        modifiers: Modifiers::NONE,
    });
    harness.step();
    harness.step();
    assert!(harness.state().canvas().preview.is_empty());
    wait_for_fits(&mut harness);
    assert_eq!(harness.state().document().strokes().len(), 1);
    assert!(segment_count(&harness) >= 1);
}

#[test]
fn the_file_chooser_fills_the_path_and_save_writes_there() {
    let dir = temp_dir("chooser");
    let target = dir.join("chosen.json");
    let mut harness = harness(AppOptions::default());
    draw_arc(&mut harness);
    wait_for_fits(&mut harness);
    // The chooser starts in the path field's folder with its file name; choosing keeps both.
    harness.state_mut().view.path = target.display().to_string();
    harness.step();
    harness.get_by_label("Browse…").click();
    harness.step();
    harness.step();
    assert!(harness.state().chooser_open(), "Browse… opens the chooser");
    // A new window sizes itself on its first frame and shows on the next.
    harness.step();
    harness.get_by_label("Up");
    harness.state_mut().view.path.clear();
    harness.get_by_label("Choose").click();
    harness.step();
    harness.step();
    assert_eq!(PathBuf::from(&harness.state().view.path), target);
    assert!(harness.query_by_label("Up").is_none(), "the chooser closed");
    harness.get_by_label("Save").click();
    harness.step();
    let text = std::fs::read_to_string(&target).expect("the drawing was saved where chosen");
    let saved = kansei::stroke::StrokeFile::from_json(&text).expect("a stroke file");
    assert_eq!(saved.strokes.len(), 1);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_apps_svg_export_writes_one_path_per_stroke_with_the_samples_layer() {
    use kansei::pipeline::{PipelineOptions, fit_file};
    use kansei::stroke::StrokeFile;
    let dir = temp_dir("svg-export");
    for name in ["perfect-freehand-corners", "perfect-freehand-hey"] {
        let path = format!(
            "{}/fixtures/strokes/{name}.json",
            env!("CARGO_MANIFEST_DIR")
        );
        let text = std::fs::read_to_string(&path).expect("fixture");
        let file = StrokeFile::from_json(&text).expect("parses");
        let output = fit_file(&file, &PipelineOptions::default()).expect("fits");
        let svg = dir.join(format!("{name}.svg"));
        use kansei::app::files::{Overwrite, export};
        use kansei::export::Format;
        let png = kansei::render::RenderOptions::default();
        export(&svg, Format::Svg, &file, &output, &png, Overwrite::Never).expect("writes");
        let text = std::fs::read_to_string(&svg).expect("reads");
        let doc = roxmltree::Document::parse(&text).expect("well-formed");
        let layer = |id: &str| {
            doc.descendants()
                .find(|n| n.attribute("id") == Some(id))
                .map(|g| g.children().filter(|c| c.is_element()).count())
        };
        // One path per stroke (a stroke cut at corners is still one path), and every sample.
        let mut strokes: Vec<usize> = output.curves.iter().map(|c| c.stroke).collect();
        strokes.dedup();
        assert!(
            output.curves.len() > strokes.len(),
            "{name}: pieces to join"
        );
        assert_eq!(layer("curves"), Some(strokes.len()), "{name}");
        let samples: usize = file.strokes.iter().map(|s| s.samples.len()).sum();
        assert_eq!(layer("samples"), Some(samples), "{name}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Steps a few frames (a new window sizes itself on its first frame and shows on the next).
fn settle(harness: &mut Harness<'static, KanseiApp>) {
    for _ in 0..3 {
        harness.step();
    }
}

/// The opened drawing is never an export's target: each export goes to its own file next to
/// it, with its own extension, and an existing file is replaced only once the user says so.
#[test]
fn exports_get_their_own_paths_and_ask_before_replacing_a_file() {
    let dir = temp_dir("exports");
    let opened = dir.join("waves.json");
    std::fs::copy(
        format!(
            "{}/fixtures/strokes/perfect-freehand-waves.json",
            env!("CARGO_MANIFEST_DIR")
        ),
        &opened,
    )
    .expect("copy the fixture");
    let original = std::fs::read(&opened).expect("read");
    let mut harness = harness(AppOptions {
        open: Some(opened.clone()),
        ..AppOptions::default()
    });
    wait_for_fits(&mut harness);
    assert_eq!(PathBuf::from(&harness.state().view.path), opened);
    let exports = [
        ("Export JSON", "waves.curve.json"),
        ("Export SVG", "waves.svg"),
        ("Export DXF", "waves.dxf"),
        ("Export PNG", "waves.png"),
    ];
    for (button, name) in exports {
        harness.get_by_label(button).click();
        settle(&mut harness);
        assert!(
            harness.state().pending_replace().is_none(),
            "{button} asked"
        );
        assert!(dir.join(name).is_file(), "{button} did not write {name}");
        assert_eq!(std::fs::read(&opened).expect("read"), original, "{button}");
    }
    let curves = std::fs::read_to_string(dir.join("waves.curve.json")).expect("read");
    kansei::export::CurveFile::from_json(&curves).expect("a curve file");
    assert!(
        std::fs::read_to_string(dir.join("waves.svg"))
            .expect("read")
            .contains("<svg")
    );
    assert!(
        std::fs::read(dir.join("waves.png"))
            .expect("read")
            .starts_with(b"\x89PNG")
    );
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .expect("dir")
        .filter_map(Result::ok)
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "waves.curve.json",
            "waves.dxf",
            "waves.json",
            "waves.png",
            "waves.svg"
        ]
    );

    // An existing target: the export asks and writes nothing until confirmed.
    let svg = dir.join("waves.svg");
    std::fs::write(&svg, "the user's own SVG").expect("write");
    harness.get_by_label("Export SVG").click();
    settle(&mut harness);
    let pending = harness.state().pending_replace().cloned();
    assert_eq!(pending.map(|p| p.path), Some(svg.clone()));
    harness.get_by_label("Replace waves.svg?");
    assert_eq!(
        std::fs::read_to_string(&svg).expect("read"),
        "the user's own SVG"
    );
    harness.get_by_label("Cancel").click();
    settle(&mut harness);
    assert!(harness.state().pending_replace().is_none());
    assert!(harness.query_by_label("Replace waves.svg?").is_none());
    assert_eq!(
        std::fs::read_to_string(&svg).expect("read"),
        "the user's own SVG"
    );
    harness.get_by_label("Export SVG").click();
    settle(&mut harness);
    harness.get_by_label("Replace").click();
    settle(&mut harness);
    assert!(
        std::fs::read_to_string(&svg)
            .expect("read")
            .contains("<svg"),
        "replaced once confirmed"
    );
    assert_eq!(std::fs::read(&opened).expect("read"), original);

    // Save over the drawing's own file is the normal Save; over another file it asks.
    harness.get_by_label("Save").click();
    settle(&mut harness);
    assert!(harness.state().pending_replace().is_none());
    let saved =
        kansei::stroke::StrokeFile::from_json(&std::fs::read_to_string(&opened).expect("read"))
            .expect("a stroke file");
    assert_eq!(
        saved.strokes.len(),
        harness.state().document().strokes().len()
    );
    harness.state_mut().view.path = svg.display().to_string();
    settle(&mut harness);
    let before = std::fs::read(&svg).expect("read");
    harness.get_by_label("Save").click();
    settle(&mut harness);
    assert!(
        harness.state().pending_replace().is_some(),
        "Save over another file asks"
    );
    harness.get_by_label("Cancel").click();
    settle(&mut harness);
    assert_eq!(std::fs::read(&svg).expect("read"), before);

    // An export never targets a stroke file, even when asked to replace it.
    let stroke_copy = dir.join("copy.curve.json");
    std::fs::copy(&opened, &stroke_copy).expect("copy");
    harness.state_mut().view.path = stroke_copy.display().to_string();
    settle(&mut harness);
    harness.get_by_label("Export JSON").click();
    settle(&mut harness);
    if harness.state().pending_replace().is_some() {
        harness.get_by_label("Replace").click();
        settle(&mut harness);
    }
    assert_eq!(
        std::fs::read(&stroke_copy).expect("read"),
        std::fs::read(&opened).expect("read")
    );
    assert!(
        harness
            .state()
            .status()
            .is_some_and(|s| s.error && s.text.contains("stroke file")),
        "{:?}",
        harness.state().status()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The tolerance the selected (only) stroke was fitted to, its noise floor, and its segments.
fn fitted_tolerance(harness: &Harness<'static, KanseiApp>) -> (f64, f64, usize) {
    let curves = &harness.state().scene().curves;
    let first = curves.first().expect("a fitted curve");
    let floor = first.noise.expect("the stroke's noise").floor;
    (first.tolerance, floor, segment_count(harness))
}

#[test]
fn a_drawn_stroke_gets_its_tolerance_from_the_screen_and_the_presets_refit_it() {
    let mut harness = harness(AppOptions::default());
    draw_arc(&mut harness);
    wait_for_fits(&mut harness);
    let settings = harness.state().document().strokes()[0].settings;
    let k = settings.pixels_per_unit.expect("drawn at a zoom");
    assert_eq!(settings.tolerance, None);
    // The normal preset: 1.5 screen pixels at the zoom it was drawn at, unless the noise asks
    // for more.
    let (normal, floor, normal_count) = fitted_tolerance(&harness);
    assert_eq!(normal, (1.5 / k).max(floor), "{normal} at {k} px per unit");
    harness.get_by_label("1.1.1").click();
    harness.step();
    harness.step();
    harness.get_by_label_contains("fitted to");
    harness.get_by_label("loose").click();
    harness.step();
    wait_for_fits(&mut harness);
    let (loose, _, loose_count) = fitted_tolerance(&harness);
    assert_eq!(loose, (4.0 / k).max(floor));
    assert!(
        loose_count <= normal_count,
        "{loose_count} > {normal_count}"
    );
    harness.get_by_label("tight").click();
    harness.step();
    wait_for_fits(&mut harness);
    let (tight, _, tight_count) = fitted_tolerance(&harness);
    assert_eq!(tight, (0.5 / k).max(floor));
    assert!(tight_count >= loose_count, "{tight_count} < {loose_count}");
}

#[test]
fn a_mouse_s_in_a_fresh_app_comes_back_as_a_handful_of_segments() {
    // The first stroke of a new user: an S drawn with the mouse (whole pixels, one sample per
    // frame) in a fresh app. At 0.1 mm regardless of zoom this one came back as 44 segments;
    // drawn at the normal screen tolerance (1.5 px where drawn, raised to the noise floor) it is
    // 3.
    let mut harness = harness(AppOptions::default());
    harness.step();
    let rect = harness.state().canvas().screen_rect().expect("the canvas");
    let centre = rect.center();
    // Two arcs of radius 90 points, three quarters of a turn each, turning opposite ways and
    // meeting tangentially at the S's middle (screen y down): 360 points tall, drawn at 0.7.
    let point = |t: f32| {
        let (r, turn) = (90.0f32, 1.5 * std::f32::consts::PI);
        let p = if t <= 1.0 {
            let a = -turn * t;
            Vec2::new(r * a.cos(), -r + r * a.sin())
        } else {
            let b = -0.5 * std::f32::consts::PI + turn * (t - 1.0);
            Vec2::new(r * b.cos(), r + r * b.sin())
        };
        let q = centre + p * 0.7;
        egui::pos2(q.x.round(), q.y.round())
    };
    let steps = 160;
    let points: Vec<egui::Pos2> = (0..=steps)
        .map(|i| point(2.0 * i as f32 / steps as f32))
        .collect();
    pointer_stroke(&mut harness, &points);
    wait_for_fits(&mut harness);
    let n = segment_count(&harness);
    assert!((1..=6).contains(&n), "{n} segments for a mouse S");
}
