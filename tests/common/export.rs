//! Shared checks of the exporters: a minimal XML reader, an SVG path-data reader that keeps
//! arcs exact, and distances between exported curves and exact LAC segments measured
//! independently of the library's own measure (golden-section projection onto the segment).
#![allow(dead_code)]

use kansei::geom::Point;
use kansei::lac::LacSegment;
use kurbo::{Arc, BezPath, CubicBez, Line, ParamCurve, ParamCurveNearest, SvgArc, Vec2};

// ---------------------------------------------------------------------------------------------
// A minimal XML reader: enough of XML 1.0 to check what the SVG writer may produce.

/// One element: its name and attributes (values unescaped: the writer never escapes).
#[derive(Debug, Clone)]
pub struct Element {
    pub name: String,
    pub attrs: Vec<(String, String)>,
    /// Index of the parent element, `None` for the root.
    pub parent: Option<usize>,
}

impl Element {
    pub fn attr(&self, key: &str) -> Option<&str> {
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
pub fn parse_xml(text: &str) -> Result<Vec<Element>, String> {
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

/// The element with `id`, and its children.
pub fn group<'a>(elements: &'a [Element], id: &str) -> (usize, Vec<&'a Element>) {
    let matches: Vec<usize> = (0..elements.len())
        .filter(|&i| elements[i].attr("id") == Some(id))
        .collect();
    assert_eq!(matches.len(), 1, "id {id}");
    let g = matches[0];
    let children = elements.iter().filter(|e| e.parent == Some(g)).collect();
    (g, children)
}

/// The children of element `i`.
pub fn children(elements: &[Element], i: usize) -> Vec<(usize, &Element)> {
    elements
        .iter()
        .enumerate()
        .filter(|(_, e)| e.parent == Some(i))
        .collect()
}

pub fn index_of(elements: &[Element], e: &Element) -> usize {
    elements
        .iter()
        .position(|x| std::ptr::eq(x, e))
        .expect("element of the list")
}

pub fn numbers(text: &str) -> Vec<f64> {
    text.split(|c: char| c.is_whitespace() || c == ',')
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().unwrap_or_else(|e| panic!("{t:?}: {e}")))
        .collect()
}

pub fn parse_attr(e: &Element, key: &str) -> f64 {
    let v = e.attr(key).unwrap_or_else(|| panic!("no {key} on {e:?}"));
    v.parse().unwrap_or_else(|err| panic!("{key}={v:?}: {err}"))
}

pub fn view_box(elements: &[Element]) -> [f64; 4] {
    let v = numbers(elements[0].attr("viewBox").expect("viewBox"));
    assert_eq!(v.len(), 4);
    assert!(v[2] > 0.0 && v[3] > 0.0);
    [v[0], v[1], v[2], v[3]]
}

// ---------------------------------------------------------------------------------------------
// Path data.

/// One drawing command of a path, exact.
#[derive(Clone, Copy, Debug)]
pub enum Piece {
    Line(Line),
    Arc(Arc),
    Cubic(CubicBez),
}

impl Piece {
    pub fn letter(&self) -> char {
        match self {
            Piece::Line(_) => 'L',
            Piece::Arc(_) => 'A',
            Piece::Cubic(_) => 'C',
        }
    }

    pub fn eval(&self, t: f64) -> Point {
        match self {
            Piece::Line(l) => l.eval(t),
            Piece::Arc(a) => a.eval(t),
            Piece::Cubic(c) => c.eval(t),
        }
    }

    pub fn start(&self) -> Point {
        self.eval(0.0)
    }

    pub fn end(&self) -> Point {
        self.eval(1.0)
    }

    /// Distance from `p` to the piece (exact for lines and arcs; kurbo's nearest point for
    /// cubics).
    pub fn distance(&self, p: Point) -> f64 {
        match self {
            Piece::Line(l) => l.nearest(p, 0.0).distance_sq.sqrt(),
            Piece::Cubic(c) => c.nearest(p, 1e-12).distance_sq.sqrt(),
            Piece::Arc(a) => {
                assert!((a.radii.x - a.radii.y).abs() <= 1e-12 * a.radii.x);
                let v = p - a.center;
                let angle = v.atan2() - a.x_rotation;
                let from_start = if a.sweep_angle >= 0.0 {
                    (angle - a.start_angle).rem_euclid(std::f64::consts::TAU)
                } else {
                    (a.start_angle - angle).rem_euclid(std::f64::consts::TAU)
                };
                if from_start <= a.sweep_angle.abs() {
                    (v.hypot() - a.radii.x).abs()
                } else {
                    p.distance(self.start()).min(p.distance(self.end()))
                }
            }
        }
    }
}

/// One subpath of a path's data: where its move-to put the pen, and its commands.
#[derive(Clone, Debug)]
pub struct Subpath {
    pub start: Point,
    pub pieces: Vec<Piece>,
}

/// Parses the path data the SVG writer produces (subpaths, each an `M` then `L`, `A`, `C` with
/// absolute coordinates) into exact pieces, split at every `M`; `A` through kurbo's own SVG-arc
/// conversion (endpoint to centre parametrisation). Also checks that kurbo's
/// `BezPath::from_svg` reads the same data: as many subpaths, each ending at the same point.
pub fn parse_subpaths(d: &str) -> Vec<Subpath> {
    let kurbo_path = BezPath::from_svg(d).unwrap_or_else(|e| panic!("kurbo rejects {d:?}: {e}"));
    let mut out: Vec<Subpath> = Vec::new();
    let mut pen: Option<Point> = None;
    let toks: Vec<&str> = d.split_whitespace().collect();
    let mut i = 0;
    let num = |i: &mut usize| -> f64 {
        let t = toks[*i];
        *i += 1;
        t.parse().unwrap_or_else(|e| panic!("{t:?}: {e}"))
    };
    while i < toks.len() {
        let cmd = toks[i];
        i += 1;
        let piece = match cmd {
            "M" => {
                let p = Point::new(num(&mut i), num(&mut i));
                out.push(Subpath {
                    start: p,
                    pieces: Vec::new(),
                });
                pen = Some(p);
                continue;
            }
            "L" => {
                let p0 = pen.expect("move-to first");
                let p1 = Point::new(num(&mut i), num(&mut i));
                Piece::Line(Line::new(p0, p1))
            }
            "C" => {
                let p0 = pen.expect("move-to first");
                let p1 = Point::new(num(&mut i), num(&mut i));
                let p2 = Point::new(num(&mut i), num(&mut i));
                let p3 = Point::new(num(&mut i), num(&mut i));
                Piece::Cubic(CubicBez::new(p0, p1, p2, p3))
            }
            "A" => {
                let from = pen.expect("move-to first");
                let (rx, ry, rot) = (num(&mut i), num(&mut i), num(&mut i));
                let (large, sweep) = (num(&mut i), num(&mut i));
                let to = Point::new(num(&mut i), num(&mut i));
                let arc = SvgArc {
                    from,
                    to,
                    radii: Vec2::new(rx, ry),
                    x_rotation: rot.to_radians(),
                    large_arc: large == 1.0,
                    sweep: sweep == 1.0,
                };
                Piece::Arc(Arc::from_svg_arc(&arc).expect("a proper arc"))
            }
            other => panic!("unexpected command {other:?} in {d:?}"),
        };
        pen = Some(piece.end());
        out.last_mut().expect("move-to first").pieces.push(piece);
    }
    // kurbo sees the same subpaths, ending at the same points.
    let mut kurbo_subpaths: Vec<Option<Point>> = Vec::new();
    for el in kurbo_path.elements() {
        match el {
            kurbo::PathEl::MoveTo(_) => kurbo_subpaths.push(None),
            kurbo::PathEl::LineTo(p)
            | kurbo::PathEl::QuadTo(_, p)
            | kurbo::PathEl::CurveTo(_, _, p) => {
                *kurbo_subpaths.last_mut().expect("move-to first") = Some(*p);
            }
            kurbo::PathEl::ClosePath => panic!("the writer never closes a path"),
        }
    }
    assert_eq!(kurbo_subpaths.len(), out.len(), "subpaths in {d:?}");
    for (end, sub) in kurbo_subpaths.iter().zip(&out) {
        if let (Some(end), Some(last)) = (end, sub.pieces.last()) {
            assert!(end.distance(last.end()) <= 1e-9 * (1.0 + end.to_vec2().hypot()));
        }
    }
    out
}

/// Parses path data of one subpath (see [`parse_subpaths`]) into its pieces.
pub fn parse_path(d: &str) -> Vec<Piece> {
    let mut subpaths = parse_subpaths(d);
    assert_eq!(subpaths.len(), 1, "one subpath expected in {d:?}");
    subpaths.remove(0).pieces
}

/// One fitted piece as written in its stroke's `<path>`: its index in the fit's curves, whether
/// it opened a subpath with its own `M` (else it continues the previous piece's), and its
/// segments' `<kansei:segment>` elements, each with the commands written for it.
#[derive(Clone, Debug)]
pub struct WrittenPiece<'a> {
    pub piece: usize,
    pub move_to: bool,
    pub segments: Vec<(&'a Element, Vec<Piece>)>,
}

/// Reads a stroke's `<path>` (element `path` of `elements`) back into its pieces: the path data
/// is split into subpaths at every `M` ([`parse_subpaths`]), the segments' metadata grouped by
/// their `piece` attribute, and each segment given the number of commands its `commands`
/// attribute announces, in order. Asserts that every subpath begins with a piece (a move-to
/// never falls inside a piece), that no subpath is empty and that no command is left over.
pub fn written_pieces<'a>(elements: &'a [Element], path: &Element) -> Vec<WrittenPiece<'a>> {
    let subpaths = parse_subpaths(path.attr("d").expect("d"));
    // Every command in order, with whether it opens a subpath.
    let mut commands: Vec<(bool, Piece)> = Vec::new();
    for sub in &subpaths {
        assert!(!sub.pieces.is_empty(), "an empty subpath");
        for (i, p) in sub.pieces.iter().enumerate() {
            commands.push((i == 0, *p));
        }
    }
    let meta = children(elements, index_of(elements, path));
    assert_eq!(meta.len(), 1, "one <metadata> per path");
    assert_eq!(meta[0].1.name, "metadata");
    let mut out: Vec<WrittenPiece<'a>> = Vec::new();
    let mut at = 0;
    for (_, e) in children(elements, meta[0].0) {
        assert_eq!(e.name, "kansei:segment");
        let piece = parse_attr(e, "piece") as usize;
        let n = parse_attr(e, "commands") as usize;
        assert!(
            at + n <= commands.len(),
            "more commands announced than written"
        );
        let mine: Vec<Piece> = commands[at..at + n].iter().map(|c| c.1).collect();
        let opens = (at..at + n).filter(|&k| commands[k].0).collect::<Vec<_>>();
        match out.last_mut().filter(|w| w.piece == piece) {
            Some(w) => {
                assert!(opens.is_empty(), "a move-to inside piece {piece}");
                w.segments.push((e, mine));
            }
            None => {
                assert!(
                    out.last().is_none_or(|w| w.piece < piece),
                    "pieces out of order"
                );
                assert!(
                    opens.iter().all(|&k| k == at),
                    "a move-to inside piece {piece}"
                );
                out.push(WrittenPiece {
                    piece,
                    move_to: opens == [at],
                    segments: vec![(e, mine)],
                });
            }
        }
        at += n;
    }
    assert_eq!(at, commands.len(), "commands left over");
    if let Some(first) = out.first() {
        assert!(first.move_to, "a path begins with a move-to");
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Distances to the exact segment.

/// Arc length of the point of `segment` nearest to `q`: the best of a grid fine enough that the
/// distance is unimodal between neighbours (steps of at most a fifth of the smallest radius of
/// curvature), refined by golden-section search.
pub fn project(segment: &LacSegment, grid: &[(f64, Point)], q: Point) -> (f64, f64) {
    let (mut k, mut best) = (0, f64::INFINITY);
    for (i, (_, p)) in grid.iter().enumerate() {
        let d = p.distance(q);
        if d < best {
            (k, best) = (i, d);
        }
    }
    let lo = grid[k.saturating_sub(1)].0;
    let hi = grid[(k + 1).min(grid.len() - 1)].0;
    let f = |s: f64| segment.point(s).distance(q);
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (lo, hi);
    // 0.618^50 ≈ 4e-11 of a bracket of two grid steps: far below any accuracy.
    for _ in 0..50 {
        let (c, e) = (b - g * (b - a), a + g * (b - a));
        if f(c) < f(e) {
            b = e;
        } else {
            a = c;
        }
    }
    let s = 0.5 * (a + b);
    (s, f(s).min(best))
}

/// The projection grid of `segment` (arc length and point): steps of at most 1/400 of the
/// length and a fifth of the radius of curvature anywhere within the step (|κ| is monotonic
/// along an LAC, so its largest value on a step is at one of the step's ends); the last step may
/// be a quarter longer rather than leave a sliver.
pub fn grid_of(segment: &LacSegment) -> Vec<(f64, Point)> {
    const TURN: f64 = 0.2;
    let length = segment.length();
    let limit = |s: f64| TURN / segment.kappa(s).abs();
    let mut grid = Vec::new();
    let mut s = 0.0;
    while s < length {
        grid.push((s, segment.point(s)));
        let mut h = (length / 400.0).min(limit(s));
        // Shrink until the far end's curvature allows the step too.
        while limit(s + h) < h {
            h *= 0.5;
        }
        // Land on the end rather than leave a sliver: the bracket `project` searches around the
        // end point would be the sliver, and miss a foot just before it.
        if length - (s + h) < 0.25 * h {
            break;
        }
        s += h;
    }
    grid.push((length, segment.end()));
    grid
}

/// The two-sided distance between `pieces` and `segment`: 24 points inside each piece
/// projected onto the segment, and the segment's grid points to the nearest piece.
pub fn two_sided_distance(segment: &LacSegment, pieces: &[Piece]) -> f64 {
    let grid = grid_of(segment);
    let mut worst: f64 = 0.0;
    const INSIDE: usize = 24;
    for piece in pieces {
        for i in 0..=INSIDE + 1 {
            let q = piece.eval(i as f64 / (INSIDE + 1) as f64);
            worst = worst.max(project(segment, &grid, q).1);
        }
    }
    for (_, p) in &grid {
        let d = pieces
            .iter()
            .map(|x| x.distance(*p))
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(d);
    }
    worst
}

/// The SPLINE entities of a DXF drawing, in order.
pub fn dxf_splines(drawing: &dxf::Drawing) -> Vec<&dxf::entities::Spline> {
    drawing
        .entities()
        .filter_map(|e| match &e.specific {
            dxf::entities::EntityType::Spline(s) => Some(s),
            _ => None,
        })
        .collect()
}
