//! Google QuickDraw drawings (`.ndjson`): one JSON object per line, each a drawing whose
//! `"drawing"` holds its strokes as `[[x₀, x₁, …], [y₀, y₁, …], [t₀, t₁, …]]` (the raw dataset,
//! times in milliseconds from the drawing's first point) or `[[x…], [y…]]` (the simplified
//! dataset, coordinates on a 0–255 grid). Coordinates are screen pixels: `Units::Px`.
//!
//! All drawings' strokes go into one file, in order; `device.drawings` holds how many strokes
//! each drawing contributed, so they can be told apart.

use serde::Deserialize;

use crate::stroke::{Sample, Stroke, StrokeError, StrokeFile, Units};

/// Why a QuickDraw file was refused.
#[derive(Debug, thiserror::Error)]
pub enum QuickDrawError {
    /// A line is not a JSON object with a `drawing` field of the expected shape.
    #[error("line {line}: {message}")]
    Json {
        /// 1-based line number.
        line: usize,
        /// What serde_json reported.
        message: String,
    },
    /// A stroke's coordinate (or time) lists differ in length.
    #[error("line {line}, stroke {stroke}: x has {x} values, y {y}, t {t}")]
    Lengths {
        /// 1-based line number.
        line: usize,
        /// Stroke index within the drawing.
        stroke: usize,
        /// Number of x values.
        x: usize,
        /// Number of y values.
        y: usize,
        /// Number of t values (0 when absent).
        t: usize,
    },
    /// No drawing in the file.
    #[error("no drawing in the file")]
    Empty,
    /// The strokes broke the stroke rules (non-finite, time backwards, …).
    #[error(transparent)]
    Stroke(#[from] StrokeError),
}

#[derive(Deserialize)]
struct Drawing {
    drawing: Vec<Vec<Vec<f64>>>,
}

/// QuickDraw times are milliseconds.
const MS_PER_S: f64 = 1000.0;

/// Reads every drawing of a QuickDraw `.ndjson` file. Empty strokes are skipped; a stroke at one
/// position (a tap) is kept.
pub fn read(text: &str) -> Result<StrokeFile, QuickDrawError> {
    let mut strokes = Vec::new();
    let mut per_drawing = Vec::new();
    for (i, line) in text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
    {
        let n = i + 1;
        let d: Drawing = serde_json::from_str(line).map_err(|e| QuickDrawError::Json {
            line: n,
            message: e.to_string(),
        })?;
        let before = strokes.len();
        for (k, channels) in d.drawing.iter().enumerate() {
            let (x, y) = match (channels.first(), channels.get(1)) {
                (Some(x), Some(y)) => (x, y),
                _ => {
                    return Err(QuickDrawError::Json {
                        line: n,
                        message: format!("stroke {k} has fewer than two coordinate lists"),
                    });
                }
            };
            let t = channels.get(2);
            let t_len = t.map_or(0, Vec::len);
            if x.len() != y.len() || (t.is_some() && t_len != x.len()) {
                return Err(QuickDrawError::Lengths {
                    line: n,
                    stroke: k,
                    x: x.len(),
                    y: y.len(),
                    t: t_len,
                });
            }
            let samples: Vec<Sample> = (0..x.len())
                .map(|j| {
                    let s = Sample::new(x[j], y[j]);
                    match t {
                        Some(t) => s.with_t(t[j] / MS_PER_S),
                        None => s,
                    }
                })
                .collect();
            // A stroke at one position is a tap (the pipeline fits it as a dot); only empty
            // strokes carry nothing.
            if !samples.is_empty() {
                strokes.push(Stroke::new(samples));
            }
        }
        per_drawing.push(strokes.len() - before);
    }
    if per_drawing.is_empty() {
        return Err(QuickDrawError::Empty);
    }
    let mut file = StrokeFile::new(Units::Px, strokes);
    file.source = Some("Google QuickDraw ndjson".to_owned());
    file.device = Some(serde_json::json!({ "drawings": per_drawing }));
    file.validate()?;
    Ok(file)
}
