//! The quick-look SVG: well-formed XML (checked by a small tag-balance parser), the layer
//! structure, one coloured path per LAC segment with its data attributes, a viewBox that holds
//! every sample, LAC polylines on the exact segments within the stated chord error, layer flags,
//! the colour map, and a run on the pipeline's output.

use kansei::export::{
    ALPHA_BLUE_RGB, ALPHA_RED_RGB, ALPHA_ZERO_RGB, NO_ALPHA_RGB, SvgLayers, SvgOptions,
    alpha_colour, lac_spacing, quick_look_svg,
};
use kansei::geom::{CubicBez, ParamBez, Point, Vec2};
use kansei::lac::LacSegment;
use kansei::pipeline::{PipelineOptions, fit_file};
use kansei::stroke::{Stroke, StrokeFile, Units};

// ---------------------------------------------------------------------------------------------
// A minimal XML reader: enough of XML 1.0 to check what `quick_look_svg` may produce.

/// One element: its name and attributes (values unescaped: the writer never escapes).
#[derive(Debug, Clone)]
struct Element {
    name: String,
    attrs: Vec<(String, String)>,
    /// Index of the parent element, `None` for the root.
    parent: Option<usize>,
}

impl Element {
    fn attr(&self, key: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
}

fn is_name_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | ':' | '.')
}

/// Parses `text` as an XML document (declaration, comments, one root element, whitespace-only
/// text); returns the elements in document order or the first violation.
fn parse_xml(text: &str) -> Result<Vec<Element>, String> {
    let mut elements: Vec<Element> = Vec::new();
    let mut open: Vec<usize> = Vec::new();
    let mut roots = 0;
    let mut rest = text;
    if let Some(r) = rest.strip_prefix("<?xml") {
        let end = r.find("?>").ok_or("unterminated declaration")?;
        rest = &r[end + 2..];
    }
    loop {
        let lt = match rest.find('<') {
            Some(i) => i,
            None => {
                if !rest.trim().is_empty() {
                    return Err(format!("text outside tags: {rest:?}"));
                }
                break;
            }
        };
        let between = &rest[..lt];
        if !between.trim().is_empty() {
            return Err(format!("unexpected text {between:?}"));
        }
        rest = &rest[lt..];
        if let Some(r) = rest.strip_prefix("<!--") {
            let end = r.find("-->").ok_or("unterminated comment")?;
            if r[..end].contains("--") {
                return Err("'--' inside a comment".into());
            }
            rest = &r[end + 3..];
            continue;
        }
        if let Some(r) = rest.strip_prefix("</") {
            let end = r.find('>').ok_or("unterminated end tag")?;
            let name = r[..end].trim_end();
            let top = open.pop().ok_or(format!("</{name}> closes nothing"))?;
            if elements[top].name != name {
                return Err(format!("</{name}> closes <{}>", elements[top].name));
            }
            rest = &r[end + 1..];
            continue;
        }
        // A start or empty-element tag.
        let r = &rest[1..];
        let name_len = r.find(|c: char| !is_name_char(c)).unwrap_or(r.len());
        if name_len == 0 {
            return Err(format!("bad tag at {:?}", &rest[..rest.len().min(20)]));
        }
        let name = r[..name_len].to_string();
        let mut r = &r[name_len..];
        let mut attrs = Vec::new();
        let empty = loop {
            let trimmed = r.trim_start();
            let had_space = trimmed.len() < r.len();
            r = trimmed;
            if let Some(after) = r.strip_prefix("/>") {
                r = after;
                break true;
            }
            if let Some(after) = r.strip_prefix('>') {
                r = after;
                break false;
            }
            if !had_space {
                return Err(format!("<{name}>: attributes must be separated by space"));
            }
            let key_len = r.find(|c: char| !is_name_char(c)).unwrap_or(r.len());
            if key_len == 0 {
                return Err(format!(
                    "<{name}>: bad attribute at {:?}",
                    &r[..r.len().min(20)]
                ));
            }
            let key = r[..key_len].to_string();
            r = r[key_len..]
                .strip_prefix("=\"")
                .ok_or(format!("<{name}> {key}: expected =\""))?;
            let end = r.find('"').ok_or("unterminated attribute value")?;
            let value = &r[..end];
            if value.contains(['<', '&']) {
                return Err(format!("<{name}> {key}: unescaped markup in {value:?}"));
            }
            if attrs.iter().any(|(k, _): &(String, String)| *k == key) {
                return Err(format!("<{name}>: duplicate attribute {key}"));
            }
            attrs.push((key, value.to_string()));
            r = &r[end + 1..];
        };
        if open.is_empty() {
            roots += 1;
        }
        elements.push(Element {
            name,
            attrs,
            parent: open.last().copied(),
        });
        if !empty {
            open.push(elements.len() - 1);
        }
        rest = r;
    }
    if let Some(&top) = open.last() {
        return Err(format!("<{}> never closed", elements[top].name));
    }
    if roots != 1 {
        return Err(format!("{roots} root elements"));
    }
    Ok(elements)
}

#[test]
fn the_checker_rejects_broken_xml() {
    assert!(parse_xml("<a><b/></a>").is_ok());
    for bad in [
        "<a><b></a>",
        "<a>",
        "<a></a><b/>",
        "<a x=\"1\"y=\"2\"/>",
        "<a x=1/>",
        "<a x=\"<\"/>",
        "<a>text</a>",
        "<!-- a -- b --><a/>",
        "<a x=\"1\" x=\"2\"/>",
    ] {
        assert!(parse_xml(bad).is_err(), "{bad} accepted");
    }
}

// ---------------------------------------------------------------------------------------------
// Fixtures.

fn seg(start: Point, theta0: f64, length: f64, alpha: Option<f64>, k0: f64, k1: f64) -> LacSegment {
    LacSegment::new(start, theta0, length, alpha, k0, k1)
        .unwrap_or_else(|e| panic!("{alpha:?} {k0} {k1}: {e}"))
}

/// A G1 chain of LAC segments of several kinds (spirals of both senses, an arc, a line, a κ = 0
/// end) in millimetres, starting at (10, 20).
fn chain() -> Vec<LacSegment> {
    let specs = [
        (30.0, Some(-1.0), 0.0, 0.05),
        (25.0, Some(0.5), 0.05, 0.12),
        (20.0, None, 0.12, 0.12),
        (30.0, Some(2.0), 0.12, 0.01),
        (15.0, None, 0.0, 0.0),
        (40.0, Some(3.0), -0.01, -0.2),
        (10.0, Some(0.0), -0.2, -0.05),
    ];
    let mut v: Vec<LacSegment> = Vec::new();
    let (mut start, mut theta) = (Point::new(10.0, 20.0), 0.3);
    for (length, alpha, k0, k1) in specs {
        let s = seg(start, theta, length, alpha, k0, k1);
        (start, theta) = (s.end(), s.theta1());
        v.push(s);
    }
    v
}

/// Samples every 0.5 mm along the chain, as a stroke would give.
fn samples_of(chain: &[LacSegment]) -> Vec<Point> {
    chain
        .iter()
        .flat_map(|s| s.samples(0.5).map(|x| x.point))
        .collect()
}

/// A C1 Hermite Bézier per 5 mm of the chain (stands in for the B-spline).
fn beziers_of(chain: &[LacSegment]) -> Vec<ParamBez> {
    let mut v = Vec::new();
    for s in chain {
        let n = (s.length() / 5.0).ceil() as usize;
        let h = s.length() / n as f64;
        for i in 0..n {
            let (a, b) = (s.sample(i as f64 * h), s.sample((i + 1) as f64 * h));
            let (ta, tb) = (
                Vec2::from_angle(a.theta) * (h / 3.0),
                Vec2::from_angle(b.theta) * (h / 3.0),
            );
            v.push(ParamBez {
                bez: CubicBez::new(a.point, a.point + ta, b.point - tb, b.point),
                u0: v.len() as f64,
                u1: v.len() as f64 + 1.0,
            });
        }
    }
    v
}

struct Fixture {
    segments: Vec<LacSegment>,
    samples: Vec<Vec<Point>>,
    bsplines: Vec<Vec<ParamBez>>,
    splits: Vec<Point>,
}

impl Fixture {
    fn new() -> Self {
        let segments = chain();
        let splits = std::iter::once(segments[0].start())
            .chain(segments.iter().map(|s| s.end()))
            .collect();
        Fixture {
            samples: vec![samples_of(&segments)],
            bsplines: vec![beziers_of(&segments)],
            splits,
            segments,
        }
    }

    fn layers(&self) -> SvgLayers<'_> {
        SvgLayers {
            samples: &self.samples,
            bsplines: &self.bsplines,
            segments: &self.segments,
            splits: &self.splits,
        }
    }
}

/// The element with `id`, and its children.
fn group<'a>(elements: &'a [Element], id: &str) -> (usize, Vec<&'a Element>) {
    let matches: Vec<usize> = (0..elements.len())
        .filter(|&i| elements[i].attr("id") == Some(id))
        .collect();
    assert_eq!(matches.len(), 1, "id {id}");
    let g = matches[0];
    assert_eq!(elements[g].name, "g");
    let children = elements.iter().filter(|e| e.parent == Some(g)).collect();
    (g, children)
}

fn numbers(text: &str) -> Vec<f64> {
    text.split(|c: char| c.is_whitespace() || c == ',' || c.is_ascii_alphabetic() && c != 'e')
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().unwrap_or_else(|e| panic!("{t:?}: {e}")))
        .collect()
}

fn parse_attr(e: &Element, key: &str) -> f64 {
    let v = e.attr(key).unwrap_or_else(|| panic!("no {key} on {e:?}"));
    v.parse().unwrap_or_else(|err| panic!("{key}={v:?}: {err}"))
}

fn view_box(elements: &[Element]) -> [f64; 4] {
    let v = numbers(elements[0].attr("viewBox").expect("viewBox"));
    assert_eq!(v.len(), 4);
    assert!(v[2] > 0.0 && v[3] > 0.0);
    [v[0], v[1], v[2], v[3]]
}

// ---------------------------------------------------------------------------------------------
// Tests.

#[test]
fn structure_and_well_formedness() {
    let f = Fixture::new();
    let svg = quick_look_svg(&f.layers(), &SvgOptions::default());
    assert_eq!(svg.matches("<svg").count(), 1);
    assert_eq!(svg.matches("</svg>").count(), 1);
    assert!(svg.trim_end().ends_with("</svg>"));
    assert!(svg.contains("y axis is not flipped"));
    for bad in ["NaN", "inf"] {
        assert!(!svg.contains(bad), "{bad} in output");
    }
    let elements = parse_xml(&svg).unwrap_or_else(|e| panic!("{e}\n{svg}"));
    let root = &elements[0];
    assert_eq!(root.name, "svg");
    assert_eq!(root.attr("xmlns"), Some("http://www.w3.org/2000/svg"));
    let [_, _, w, h] = view_box(&elements);
    // Millimetre data: a physical size equal to the viewBox.
    assert_eq!(root.attr("width"), Some(format!("{w}mm").as_str()));
    assert_eq!(root.attr("height"), Some(format!("{h}mm").as_str()));

    let (_, samples) = group(&elements, "samples");
    assert_eq!(samples.len(), f.samples[0].len());
    assert!(samples.iter().all(|e| e.name == "circle"));
    let (_, bspline) = group(&elements, "bspline");
    assert_eq!(bspline.len(), 1);
    let d = bspline[0].attr("d").expect("d");
    assert_eq!(d.matches('C').count(), f.bsplines[0].len());
    // The pieces join, so a single move-to.
    assert_eq!(d.matches('M').count(), 1);
    let (_, splits) = group(&elements, "splits");
    assert_eq!(splits.len(), f.splits.len());
    assert!(splits.iter().all(|e| e.name == "rect"));

    let (_, lac) = group(&elements, "lac");
    assert_eq!(lac.len(), f.segments.len());
    for (e, s) in lac.iter().zip(&f.segments) {
        assert_eq!(e.name, "path");
        let alpha = e.attr("data-alpha").expect("data-alpha");
        match s.alpha() {
            Some(a) => assert_eq!(alpha.parse::<f64>().expect("a number"), a),
            None => assert_eq!(alpha, "null"),
        }
        assert_eq!(parse_attr(e, "data-length"), s.length());
        assert_eq!(parse_attr(e, "data-kappa0"), s.kappa0());
        assert_eq!(parse_attr(e, "data-kappa1"), s.kappa1());
        let [r, g, b] = alpha_colour(s.alpha());
        assert_eq!(
            e.attr("stroke"),
            Some(format!("#{r:02x}{g:02x}{b:02x}").as_str())
        );
    }
}

#[test]
fn view_box_holds_everything_with_the_margin() {
    let f = Fixture::new();
    let options = SvgOptions::default();
    let svg = quick_look_svg(&f.layers(), &options);
    let elements = parse_xml(&svg).expect("well-formed");
    let [x, y, w, h] = view_box(&elements);
    // x + w rounds: allow a few ulps of the extent where an element touches the edge.
    let slack = 1e-12 * w.max(h);
    let inside = |p: Point, pad: f64| {
        p.x - pad >= x - slack
            && p.x + pad <= x + w + slack
            && p.y - pad >= y - slack
            && p.y + pad <= y + h + slack
    };
    for p in &f.samples[0] {
        // The dot and the margin.
        assert!(inside(*p, options.sample_radius + options.margin), "{p:?}");
    }
    for p in &f.splits {
        assert!(
            inside(*p, 0.5 * options.split_size + options.margin),
            "{p:?}"
        );
    }
    // Tight: the margin is exactly what surrounds the drawing on each side (the samples'
    // extreme dots or the splits' squares or the lines decide the box).
    let xs = f.samples[0].iter().map(|p| p.x);
    let min_x = xs.clone().fold(f64::INFINITY, f64::min);
    assert!(x <= min_x - options.margin && x >= min_x - options.margin - 2.0 * options.split_size);
    // Coordinates are the data's own: the first sample's dot is written verbatim (no y flip).
    let (_, dots) = group(&elements, "samples");
    assert_eq!(parse_attr(dots[0], "cx"), f.samples[0][0].x);
    assert_eq!(parse_attr(dots[0], "cy"), f.samples[0][0].y);
}

/// Distance from `p` to the line segment a–b.
fn distance_to_chord(p: Point, a: Point, b: Point) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.hypot2()).clamp(0.0, 1.0);
    (p - (a + ab * t)).hypot()
}

#[test]
fn lac_polylines_lie_on_the_segments_within_the_chord_error() {
    let f = Fixture::new();
    for options in [
        SvgOptions::default(),
        SvgOptions::default().with_line_width(0.05),
        SvgOptions::default().with_line_width(2.0),
    ] {
        let svg = quick_look_svg(&f.layers(), &options);
        let elements = parse_xml(&svg).expect("well-formed");
        let (_, lac) = group(&elements, "lac");
        let error = options.chord_error();
        for (e, s) in lac.iter().zip(&f.segments) {
            let d = e.attr("d").expect("d");
            assert!(d.starts_with('M'));
            let v = numbers(d);
            let vertices: Vec<Point> = v.chunks(2).map(|c| Point::new(c[0], c[1])).collect();
            let steps = vertices.len() - 1;
            assert!(steps >= 1);
            let spacing = lac_spacing(s, error);
            assert_eq!(steps, (s.length() / spacing).ceil() as usize);
            let step = s.length() / steps as f64;
            for (i, p) in vertices.iter().enumerate() {
                // Each vertex is on the exact segment (the fast path's accumulated integral).
                let exact = s.point(i as f64 * step);
                assert!(
                    (*p - exact).hypot() <= 1e-9 * s.length(),
                    "{i}: {p:?} {exact:?}"
                );
            }
            for (i, w) in vertices.windows(2).enumerate() {
                // The exact curve between two vertices stays within the chord error.
                for k in 1..8 {
                    let q = s.point((i as f64 + k as f64 / 8.0) * step);
                    let dist = distance_to_chord(q, w[0], w[1]);
                    assert!(dist <= error, "segment {s:?}, step {i}: {dist} > {error}");
                }
            }
        }
    }
}

#[test]
fn layer_flags_hide_groups() {
    let f = Fixture::new();
    let names = ["samples", "bspline", "lac", "splits"];
    for hidden in 0..4 {
        let mut shown = [true; 4];
        shown[hidden] = false;
        let options = SvgOptions::default().with_layers(shown[0], shown[1], shown[2], shown[3]);
        let svg = quick_look_svg(&f.layers(), &options);
        let elements = parse_xml(&svg).expect("well-formed");
        for (name, show) in names.iter().zip(shown) {
            let present = elements.iter().any(|e| e.attr("id") == Some(name));
            assert_eq!(present, show, "{name}");
        }
    }
    // Nothing at all: still a valid document with a positive viewBox.
    let empty = quick_look_svg(&SvgLayers::default(), &SvgOptions::default());
    let elements = parse_xml(&empty).expect("well-formed");
    view_box(&elements);
    let none = SvgOptions::default().with_margin(0.0);
    let one_point = [Point::new(3.0, 4.0)];
    let layers = SvgLayers {
        splits: &one_point,
        ..SvgLayers::default()
    };
    let mut options = none;
    options.split_size = 0.0;
    view_box(&parse_xml(&quick_look_svg(&layers, &options)).expect("well-formed"));
}

#[test]
fn colour_map() {
    assert_eq!(alpha_colour(None), NO_ALPHA_RGB);
    assert_eq!(alpha_colour(Some(f64::NAN)), NO_ALPHA_RGB);
    assert_eq!(alpha_colour(Some(0.0)), ALPHA_ZERO_RGB);
    assert_eq!(alpha_colour(Some(-2.0)), ALPHA_BLUE_RGB);
    assert_eq!(alpha_colour(Some(-7.0)), ALPHA_BLUE_RGB);
    assert_eq!(alpha_colour(Some(2.0)), ALPHA_RED_RGB);
    assert_eq!(alpha_colour(Some(5.0)), ALPHA_RED_RGB);
    // Monotonic between the ends: more blue below 0, more red above.
    let blue = |a: f64| alpha_colour(Some(a))[2];
    let red = |a: f64| alpha_colour(Some(a))[0];
    assert!(blue(-1.5) > blue(-0.5) && blue(-0.5) > blue(0.0));
    assert!(red(1.5) > red(0.5) && red(0.5) > red(0.0));
    // Halfway is the rounded midpoint.
    let mid = alpha_colour(Some(1.0));
    for i in 0..3 {
        let m = (f64::from(ALPHA_ZERO_RGB[i]) + f64::from(ALPHA_RED_RGB[i])) / 2.0;
        assert!((f64::from(mid[i]) - m).abs() <= 0.5);
    }
}

#[test]
fn non_finite_input_is_left_out() {
    let nan = Point::new(f64::NAN, 1.0);
    let samples = vec![vec![Point::new(0.0, 0.0), nan, Point::new(1.0, 1.0)]];
    let bad = ParamBez {
        bez: CubicBez::new((0.0, 0.0), (f64::INFINITY, 0.0), (1.0, 1.0), (2.0, 0.0)),
        u0: 0.0,
        u1: 1.0,
    };
    let bsplines = vec![vec![bad]];
    let splits = [nan];
    let layers = SvgLayers {
        samples: &samples,
        bsplines: &bsplines,
        splits: &splits,
        ..SvgLayers::default()
    };
    let mut options = SvgOptions::for_units(Units::Px);
    options.line_width = f64::NAN;
    let svg = quick_look_svg(&layers, &options);
    assert!(!svg.contains("NaN") && !svg.contains("inf"), "{svg}");
    let elements = parse_xml(&svg).expect("well-formed");
    assert_eq!(group(&elements, "samples").1.len(), 2);
    assert_eq!(group(&elements, "bspline").1.len(), 0);
    assert_eq!(group(&elements, "splits").1.len(), 0);
    // Pixel data: unitless width/height.
    let w = elements[0].attr("width").expect("width");
    assert!(w.parse::<f64>().is_ok());
}

#[test]
fn pipeline_output_draws() {
    // A quarter circle of radius 50 mm, sampled every degree (the crate's doc example).
    let points: Vec<Point> = (0..=90)
        .map(|d| {
            let a = f64::from(d).to_radians();
            Point::new(50.0 * a.cos(), 50.0 * a.sin())
        })
        .collect();
    let file = StrokeFile::new(Units::Mm, vec![Stroke::from_points(points.iter().copied())]);
    let out = fit_file(&file, &PipelineOptions::default()).expect("fit");
    let bsplines: Vec<Vec<ParamBez>> = out
        .curves
        .iter()
        .map(|c| {
            c.spans
                .spans
                .iter()
                .flat_map(|s| s.pieces.clone())
                .collect()
        })
        .collect();
    let splits: Vec<Point> = out
        .curves
        .iter()
        .flat_map(|c| c.spans.splits.iter().map(|s| s.point))
        .collect();
    let arc = seg(
        Point::new(50.0, 0.0),
        std::f64::consts::FRAC_PI_2,
        25.0 * std::f64::consts::PI,
        None,
        0.02,
        0.02,
    );
    let samples = vec![points];
    let segments = [arc];
    let layers = SvgLayers {
        samples: &samples,
        bsplines: &bsplines,
        segments: &segments,
        splits: &splits,
    };
    let svg = quick_look_svg(&layers, &SvgOptions::for_units(out.units));
    let elements = parse_xml(&svg).expect("well-formed");
    let (_, paths) = group(&elements, "bspline");
    assert_eq!(paths.len(), out.curves.len());
    let (_, lac) = group(&elements, "lac");
    assert_eq!(lac[0].attr("data-alpha"), Some("null"));
    assert_eq!(lac[0].attr("stroke"), Some("#000000"));
    assert_eq!(group(&elements, "splits").1.len(), splits.len());
    let [x, y, w, h] = view_box(&elements);
    assert!(x <= -5.0 && y <= -5.0 && x + w >= 55.0 && y + h >= 55.0);
}

#[test]
fn tight_curls_are_capped() {
    use kansei::export::MAX_POINTS_PER_SEGMENT;
    // κ up to 1e4 per mm over 100 mm would need ~2e6 points for a 0.025 mm chord error.
    let curl = seg(Point::ORIGIN, 0.0, 100.0, Some(1.0), 1e4, 1.0);
    let spacing = lac_spacing(&curl, SvgOptions::default().chord_error());
    assert!(curl.samples(spacing).len() <= MAX_POINTS_PER_SEGMENT);
    // An ordinary segment is not affected: the sagitta rule decides.
    let gentle = seg(Point::ORIGIN, 0.0, 100.0, Some(1.0), 0.1, 0.01);
    let spacing = lac_spacing(&gentle, 0.025);
    assert!((spacing - (8.0 * 0.025 / 0.1_f64).sqrt()).abs() <= 1e-12);
    // A line: its two ends.
    let line = seg(Point::ORIGIN, 0.0, 100.0, None, 0.0, 0.0);
    assert_eq!(line.samples(lac_spacing(&line, 0.025)).len(), 2);
}
