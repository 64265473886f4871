//! Exported SVG files render in a real browser: headless Chromium screenshots three exports (two
//! fixtures in px, one fixture rescaled to mm; one `<path>` per stroke, its pieces as subpaths)
//! and the ink in the screenshot lies where the exact LAC chain is — along every part of the
//! chain, and nowhere else.
//!
//! Skipped with a message when no `chromium` runs here; `.ci/run` installs Debian's `chromium`
//! and sets `KANSEI_REQUIRE_CHROMIUM=1`, and then a missing or failing browser is a failure.

mod common;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use kansei::export::{SvgOptions, svg_document};
use kansei::pipeline::{FitOutput, PipelineOptions, fit_file};
use kansei::stroke::{StrokeFile, Units};
use kurbo::Point;

/// A screenshot that takes longer than this has hung (a cold start here takes a few seconds).
const BROWSER_TIMEOUT: Duration = Duration::from_secs(60);

/// CSS pixels per millimetre: 96 px per inch, 25.4 mm per inch.
const CSS_PX_PER_MM: f64 = 96.0 / 25.4;

/// Empty space right of and below the drawing in the browser window, in pixels: the page's own
/// background, with room so that no scroll bar appears.
const WINDOW_PADDING: u32 = 48;

/// A pixel whose darkest channel is at most this is ink: the curves are black strokes about one
/// pixel wide, so the pixel at a curve's centre is at least half covered (≤ 127), while a
/// pixel merely touched by anti-aliasing may be fainter.
const INK: u8 = 160;

/// A pixel whose darkest channel is below this is not the white background (anti-aliasing's
/// faintest edge included).
const NOT_BACKGROUND: u8 = 250;

/// Ink must lie within this many pixels of every point of the chain: half the line width,
/// plus the export's accuracy (a tenth of the tolerance, under a pixel here) and a pixel of
/// rounding.
const INK_REACH: f64 = 2.0;

/// Every non-background pixel lies within this many pixels of the chain: half the line width,
/// the anti-aliasing fringe, the round caps and joins.
const FRINGE: f64 = 3.0;

/// Spacing of the chain's sample points, in pixels: well under [`INK_REACH`].
const CHAIN_SPACING_PX: f64 = 0.5;

/// Runs `browser` headless on `svg`, writing a `size` screenshot to `png`, with a fresh profile
/// in `profile`. Kills the browser after [`BROWSER_TIMEOUT`].
fn screenshot(
    browser: &str,
    svg: &Path,
    png: &Path,
    profile: &Path,
    size: (u32, u32),
) -> Result<(), String> {
    let _ = std::fs::remove_file(png);
    let mut child = common::browser::headless(browser, profile, size)?
        .arg(format!("--screenshot={}", png.display()))
        .arg(format!("file://{}", svg.display()))
        .spawn()
        .map_err(|e| format!("{browser} does not start: {e}"))?;
    // stderr is read on its own thread so that a chatty browser never blocks on a full pipe.
    let mut stderr = child.stderr.take();
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        if let Some(s) = stderr.as_mut() {
            let _ = std::io::Read::read_to_string(s, &mut text);
        }
        text
    });
    let started = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break status,
            Ok(None) if started.elapsed() > BROWSER_TIMEOUT => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(format!(
                    "{browser} did not finish in {BROWSER_TIMEOUT:?}; killed"
                ));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(50)),
            Err(e) => return Err(format!("{browser}: {e}")),
        }
    };
    let log = reader.join().unwrap_or_default();
    if !status.success() || !png.exists() {
        return Err(format!(
            "{browser} exited with {status}, no screenshot:\n{log}"
        ));
    }
    Ok(())
}

/// The root `<svg>`'s viewBox and its size in CSS pixels (`None` without width and height:
/// then the drawing fills the window).
fn geometry(svg: &str) -> ([f64; 4], Option<(f64, f64)>) {
    let doc = roxmltree::Document::parse(svg).expect("the SVG is well-formed XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    let v: Vec<f64> = root
        .attribute("viewBox")
        .expect("viewBox")
        .split_whitespace()
        .map(|n| n.parse().expect("viewBox number"))
        .collect();
    let css = |a: &str| {
        let a = root.attribute(a)?;
        Some(match a.strip_suffix("mm") {
            Some(mm) => mm.parse::<f64>().expect("length") * CSS_PX_PER_MM,
            None => a.parse::<f64>().expect("length"),
        })
    };
    let size = css("width").zip(css("height"));
    ([v[0], v[1], v[2], v[3]], size)
}

/// Where a point of the data lands in the screenshot: the viewBox fitted into the drawing's
/// box at the window's top left (`preserveAspectRatio` xMidYMid meet, the default).
struct ViewTransform {
    scale: f64,
    offset: (f64, f64),
    origin: (f64, f64),
}

impl ViewTransform {
    fn new(view: [f64; 4], size: (f64, f64)) -> Self {
        let scale = (size.0 / view[2]).min(size.1 / view[3]);
        ViewTransform {
            scale,
            offset: (
                0.5 * (size.0 - scale * view[2]),
                0.5 * (size.1 - scale * view[3]),
            ),
            origin: (view[0], view[1]),
        }
    }

    fn pixel(&self, p: Point) -> Point {
        Point::new(
            self.offset.0 + self.scale * (p.x - self.origin.0),
            self.offset.1 + self.scale * (p.y - self.origin.1),
        )
    }
}

/// Points along every chain of the fit, in pixels, [`CHAIN_SPACING_PX`] apart or closer.
fn chain_pixels(out: &FitOutput, t: &ViewTransform) -> Vec<Point> {
    let mut points = Vec::new();
    for chain in out.curves.iter().filter_map(|c| c.chain.as_ref()) {
        for cs in &chain.segments {
            let seg = &cs.segment;
            let n = (seg.length() * t.scale / CHAIN_SPACING_PX).ceil().max(1.0) as usize;
            points.extend((0..=n).map(|i| t.pixel(seg.point(seg.length() * i as f64 / n as f64))));
        }
    }
    points
}

/// The darkest channel of each pixel (row-major), and the image's size.
fn darkness(png: &Path) -> (Vec<u8>, u32, u32) {
    let pixmap = tiny_skia::Pixmap::load_png(png).expect("the screenshot decodes as PNG");
    let values = pixmap
        .pixels()
        .iter()
        .map(|p| {
            // Unpremultiplied over white: a transparent pixel is background.
            let c = p.demultiply();
            let over_white = |v: u8| {
                let a = u32::from(c.alpha());
                ((u32::from(v) * a + 255 * (255 - a)) / 255) as u8
            };
            over_white(c.red())
                .min(over_white(c.green()))
                .min(over_white(c.blue()))
        })
        .collect();
    (values, pixmap.width(), pixmap.height())
}

/// The pixels (x, y) whose centres lie within `radius` of `p`, inside a `w` × `h` image.
fn pixels_near(p: Point, radius: f64, w: u32, h: u32) -> impl Iterator<Item = (u32, u32)> {
    let r = radius.ceil() as i64;
    let (cx, cy) = (p.x.floor() as i64, p.y.floor() as i64);
    let ys = (cy - r).max(0)..=(cy + r).min(i64::from(h) - 1);
    ys.flat_map(move |y| {
        let xs = (cx - r).max(0)..=(cx + r).min(i64::from(w) - 1);
        xs.map(move |x| (x, y))
    })
    .filter(move |&(x, y)| Point::new(x as f64 + 0.5, y as f64 + 0.5).distance(p) <= radius)
    .map(|(x, y)| (x as u32, y as u32))
}

/// The three exports: name, stroke file, fit.
fn cases() -> Vec<(String, StrokeFile, FitOutput)> {
    let mut files: Vec<(String, StrokeFile)> =
        ["perfect-freehand-corners", "libmypaint-painting30sec"]
            .into_iter()
            .map(|n| (n.to_string(), common::fixture(n)))
            .collect();
    // A fixture in mm (a quarter of its px size): the drawing's size is then given in mm.
    let spring = common::fixture("google-ink-spring");
    let strokes = spring
        .strokes
        .iter()
        .map(|s| common::transform(s, 0.0, 0.25, (0.0, 0.0)))
        .collect();
    files.push((
        "google-ink-spring-mm".to_string(),
        StrokeFile::new(Units::Mm, strokes),
    ));
    files
        .into_iter()
        .map(|(name, file)| {
            let out = fit_file(&file, &PipelineOptions::default()).expect("fit");
            (name, file, out)
        })
        .collect()
}

#[test]
fn exported_svgs_render_in_headless_chromium_where_the_chain_is() {
    let required = std::env::var_os("KANSEI_REQUIRE_CHROMIUM").is_some();
    let browser = match common::browser::browser() {
        Ok(b) => b,
        Err(why) if required => panic!("KANSEI_REQUIRE_CHROMIUM is set but {why}"),
        Err(why) => {
            eprintln!("skipped: {why} (install Debian's chromium; .ci/run does)");
            return;
        }
    };
    let dir: PathBuf = Path::new(env!("CARGO_TARGET_TMPDIR")).join("svg-browser");
    std::fs::create_dir_all(&dir).expect("temp dir");
    for (name, file, out) in cases() {
        let export = svg_document(&out, Some(&file), &SvgOptions::for_units(file.units));
        // One <path> per stroke in the curves layer (pieces are its subpaths), each stroke
        // once: the screenshot below shows every piece of every stroke.
        let doc = roxmltree::Document::parse(&export.svg).expect("well-formed");
        let strokes: Vec<usize> = doc
            .descendants()
            .filter(|n| n.attribute("id") == Some("curves"))
            .flat_map(|g| g.children().filter(|c| c.has_tag_name("path")))
            .map(|p| {
                let stroke = p.attribute("data-stroke").expect("data-stroke");
                stroke.parse().expect("a stroke index")
            })
            .collect();
        let mut expected: Vec<usize> = out
            .curves
            .iter()
            .filter(|c| c.chain.is_some())
            .map(|c| c.stroke)
            .collect();
        expected.dedup();
        assert_eq!(strokes, expected, "{name}: one path per stroke");
        let (view, size) = geometry(&export.svg);
        let size = size.expect("px and mm exports state their size");
        if file.units == Units::Mm {
            assert!((size.0 - view[2] * CSS_PX_PER_MM).abs() < 1e-9 * size.0);
        }
        let window = (
            size.0.ceil() as u32 + WINDOW_PADDING,
            size.1.ceil() as u32 + WINDOW_PADDING,
        );
        let svg = dir.join(format!("{name}.svg"));
        let png = dir.join(format!("{name}.png"));
        std::fs::write(&svg, &export.svg).expect("write the SVG");
        if let Err(why) = screenshot(browser, &svg, &png, &dir.join("profile"), window) {
            if required {
                panic!("{name}: {why}");
            }
            eprintln!("skipped: {name}: {why}");
            return;
        }

        let (dark, w, h) = darkness(&png);
        assert_eq!((w, h), window, "{name}: the screenshot is the window");
        let t = ViewTransform::new(view, size);
        let chain = chain_pixels(&out, &t);
        assert!(chain.len() > 100, "{name}: {} chain points", chain.len());
        // Every point of the chain has ink close by.
        let at = |(x, y): (u32, u32)| (y * w + x) as usize;
        let missing: Vec<Point> = chain
            .iter()
            .copied()
            .filter(|&p| !pixels_near(p, INK_REACH, w, h).any(|q| dark[at(q)] <= INK))
            .collect();
        assert!(
            missing.is_empty(),
            "{name}: {} of {} chain points have no ink within {INK_REACH} px, e.g. {:?}",
            missing.len(),
            chain.len(),
            &missing[..missing.len().min(5)]
        );
        // Nothing is drawn away from the chain, and most of the image is background.
        let mut fringe = vec![false; dark.len()];
        for &p in &chain {
            pixels_near(p, FRINGE, w, h).for_each(|q| fringe[at(q)] = true);
        }
        let stray: Vec<(u32, u32)> = (0..w * h)
            .filter(|&i| dark[i as usize] < NOT_BACKGROUND && !fringe[i as usize])
            .map(|i| (i % w, i / w))
            .collect();
        assert!(
            stray.is_empty(),
            "{name}: {} drawn pixels farther than {FRINGE} px from the chain, e.g. {:?}",
            stray.len(),
            &stray[..stray.len().min(5)]
        );
        let drawn = dark.iter().filter(|&&d| d < NOT_BACKGROUND).count();
        let fraction = drawn as f64 / dark.len() as f64;
        assert!(fraction < 0.1, "{name}: {fraction} of the image is drawn");
        println!(
            "{name}: {w}×{h} px, {} chain points all inked, {drawn} drawn pixels ({:.2} %)",
            chain.len(),
            100.0 * fraction
        );
    }
}
