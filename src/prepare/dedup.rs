use crate::geom::{DUPLICATE_RELATIVE, Point, bounding_box};
use crate::stroke::Stroke;

/// A stroke's distinct consecutive positions.
#[derive(Clone, Debug, PartialEq)]
pub struct Distinct {
    /// The positions, consecutive duplicates merged.
    pub points: Vec<Point>,
    /// For each position, the first original sample index of its merged run.
    pub first: Vec<usize>,
    /// For each position, the last original sample index of its merged run.
    pub last: Vec<usize>,
}

/// Merges runs of consecutive samples closer than [`DUPLICATE_RELATIVE`] × the stroke's
/// bounding-box diagonal into their first sample.
pub fn merge_duplicates(stroke: &Stroke) -> Distinct {
    let pts = stroke.points();
    let diagonal = bounding_box(pts.iter().copied())
        .map_or(0.0, |b| b.origin().distance(Point::new(b.x1, b.y1)));
    let eps = DUPLICATE_RELATIVE * diagonal;
    let mut out = Distinct {
        points: Vec::new(),
        first: Vec::new(),
        last: Vec::new(),
    };
    for (i, p) in pts.into_iter().enumerate() {
        match out.points.last() {
            Some(q) if q.distance(p) <= eps => {
                if let Some(l) = out.last.last_mut() {
                    *l = i;
                }
            }
            _ => {
                out.points.push(p);
                out.first.push(i);
                out.last.push(i);
            }
        }
    }
    out
}
