use serde::{Deserialize, Serialize};

use super::locate::place_at;
use super::{Stroke, StrokeError, Units};

/// The `format` value of a `kansei-stroke` file.
pub const FORMAT_NAME: &str = "kansei-stroke";
/// The newest `kansei-stroke` version this library reads and writes.
pub const FORMAT_VERSION: u64 = 1;

/// A `kansei-stroke` v1 file: units, provenance and strokes.
///
/// ```json
/// {"format": "kansei-stroke", "version": 1, "units": "mm",
///  "source": "optional free text", "device": {"optional": "object"},
///  "strokes": [{"samples": [{"x": 1.0, "y": 2.0, "t": 0.004, "pressure": 0.5,
///                             "tilt_x": 10.0, "tilt_y": -3.0}]}]}
/// ```
/// Unknown fields are ignored, so later minor additions stay readable.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StrokeFile {
    /// Always [`FORMAT_NAME`].
    pub format: String,
    /// Always [`FORMAT_VERSION`] for files this library writes.
    pub version: u64,
    /// Units of every coordinate.
    pub units: Units,
    /// Free-text provenance.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    /// Free-form description of the capturing device.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub device: Option<serde_json::Value>,
    /// The strokes, in drawing order.
    pub strokes: Vec<Stroke>,
}

/// Just enough of a file to tell its format and version before reading the rest.
#[derive(Deserialize)]
struct Header {
    format: Option<String>,
    version: Option<u64>,
}

impl StrokeFile {
    /// A new file holding `strokes` in `units`.
    pub fn new(units: Units, strokes: Vec<Stroke>) -> Self {
        StrokeFile {
            format: FORMAT_NAME.to_owned(),
            version: FORMAT_VERSION,
            units,
            source: None,
            device: None,
            strokes,
        }
    }

    /// Parses and validates `kansei-stroke` JSON: the document and every stroke
    /// ([`StrokeFile::validate`]); the first bad stroke refuses the file.
    pub fn from_json(text: &str) -> Result<Self, StrokeError> {
        let file = Self::read_json(text)?;
        file.validate()?;
        Ok(file)
    }

    /// Parses `kansei-stroke` JSON, checking the document (syntax, `format`, `version`, field
    /// types) but not the strokes' values: for a caller that validates each stroke on its own,
    /// as [`crate::pipeline::fit_one`] does, so that one bad stroke costs only itself.
    pub fn read_json(text: &str) -> Result<Self, StrokeError> {
        if text.trim().is_empty() {
            return Err(StrokeError::Empty);
        }
        let header: Header = serde_json::from_str(text).map_err(|e| json_error(text, e))?;
        match header.format {
            Some(f) if f == FORMAT_NAME => {}
            Some(f) => return Err(StrokeError::WrongFormat { found: f }),
            None => {
                return Err(StrokeError::WrongFormat {
                    found: String::new(),
                });
            }
        }
        match header.version {
            Some(FORMAT_VERSION) => {}
            Some(v) => return Err(StrokeError::WrongVersion { found: v }),
            None => return Err(StrokeError::WrongVersion { found: 0 }),
        }
        serde_json::from_str(text).map_err(|e| json_error(text, e))
    }

    /// Writes the file as JSON, one sample per line. Numbers round-trip exactly.
    pub fn to_json(&self) -> String {
        // Built by hand around serde_json's number formatting: pretty-printing every sample field
        // on its own line makes real recordings ten times longer than they need to be.
        let mut out = String::new();
        out.push_str("{\n");
        push_field(&mut out, "format", &self.format);
        push_field(&mut out, "version", &self.version);
        push_field(&mut out, "units", &self.units);
        if let Some(source) = &self.source {
            push_field(&mut out, "source", source);
        }
        if let Some(device) = &self.device {
            push_field(&mut out, "device", device);
        }
        out.push_str("  \"strokes\": [");
        for (i, stroke) in self.strokes.iter().enumerate() {
            out.push_str(if i == 0 { "\n" } else { ",\n" });
            out.push_str("    {\"samples\": [");
            for (j, s) in stroke.samples.iter().enumerate() {
                out.push_str(if j == 0 { "\n      " } else { ",\n      " });
                out.push_str(&to_compact(s));
            }
            out.push_str("\n    ]}");
        }
        out.push_str("\n  ]\n}\n");
        out
    }

    /// Checks every stroke (see [`Stroke::validate`]).
    pub fn validate(&self) -> Result<(), StrokeError> {
        if self.format != FORMAT_NAME {
            return Err(StrokeError::WrongFormat {
                found: self.format.clone(),
            });
        }
        if self.version != FORMAT_VERSION {
            return Err(StrokeError::WrongVersion {
                found: self.version,
            });
        }
        self.strokes
            .iter()
            .enumerate()
            .try_for_each(|(i, s)| s.validate(i))
    }
}

fn push_field<T: Serialize + ?Sized>(out: &mut String, name: &str, value: &T) {
    out.push_str("  \"");
    out.push_str(name);
    out.push_str("\": ");
    out.push_str(&to_compact(value));
    out.push_str(",\n");
}

fn to_compact<T: Serialize + ?Sized>(value: &T) -> String {
    // Serialising plain data (numbers, strings, JSON values) into a String cannot fail: the only
    // error sources are I/O and maps with non-string keys, neither of which occur here.
    serde_json::to_string(value).unwrap_or_else(|_| "null".to_owned())
}

/// serde_json's error, placed in the document's strokes and samples ([`place_at`]).
fn json_error(text: &str, e: serde_json::Error) -> StrokeError {
    // serde_json's message ends with the position, which the error states itself.
    let full = e.to_string();
    let suffix = format!(" at line {} column {}", e.line(), e.column());
    let message = full.strip_suffix(&suffix).unwrap_or(&full).to_owned();
    let place = place_at(text, e.line(), e.column()).map(|mut place| {
        // A missing field is reported at the sample's closing brace, after the last key read:
        // that key is not the one missing.
        if message.starts_with("missing field") {
            place.field = None;
        }
        place
    });
    StrokeError::Json {
        line: e.line(),
        column: e.column(),
        message,
        place,
    }
}
