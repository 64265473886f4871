//! Where in a `kansei-stroke` document a byte lies: which stroke, which sample, which field.
//!
//! serde_json reports a bad value (a number out of range such as `1e999`, the JSON spelling of an
//! infinity; a string where a number belongs; a missing field) by line and column only. To name
//! the stroke and sample, [`place_at`] reads the document's structure up to that position: a
//! stack of the containers open there, with the key being read in each object and the element
//! count in each array. The place is then the path `strokes[i].samples[j].field`, or as much of
//! it as is open.

use std::fmt;

/// A place in a `kansei-stroke` document (0-based indices).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct JsonPlace {
    /// The stroke (element of `strokes`).
    pub stroke: usize,
    /// The sample (element of that stroke's `samples`), when inside one.
    pub sample: Option<usize>,
    /// The field being read inside the sample (`x`, `t`, …), when known.
    pub field: Option<String>,
}

impl fmt::Display for JsonPlace {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "stroke {}", self.stroke)?;
        if let Some(sample) = self.sample {
            write!(f, ", sample {sample}")?;
        }
        if let Some(field) = &self.field {
            write!(f, ", field {field:?}")?;
        }
        Ok(())
    }
}

/// An open container while scanning.
#[derive(Debug)]
enum Frame {
    /// An object, and the last key read in it (the value being read belongs to it).
    Object(Option<String>),
    /// An array, and the index of the element being read.
    Array(usize),
}

/// The byte offset of 1-based `line` and `column` (serde_json's position: the column counts
/// bytes from the line's start). Past the end, the end.
fn offset_of(text: &str, line: usize, column: usize) -> usize {
    let line_start = if line <= 1 {
        0
    } else {
        text.bytes()
            .enumerate()
            .filter(|&(_, b)| b == b'\n')
            .nth(line - 2)
            .map_or(text.len(), |(i, _)| i + 1)
    };
    (line_start + column).min(text.len())
}

/// The containers open at byte `end` of `text`, outermost first.
fn open_frames(text: &str, end: usize) -> Vec<Frame> {
    let bytes = &text.as_bytes()[..end];
    let mut stack: Vec<Frame> = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'{' => stack.push(Frame::Object(None)),
            b'[' => stack.push(Frame::Array(0)),
            b'}' | b']' => {
                stack.pop();
            }
            b',' => {
                if let Some(Frame::Array(n)) = stack.last_mut() {
                    *n += 1;
                }
            }
            b'"' => {
                // A string: skip it (escapes included); in an object, a string followed by `:`
                // is the key of the value that follows.
                let start = i + 1;
                i += 1;
                while i < bytes.len() && bytes[i] != b'"' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
                let string = text.get(start..i.min(bytes.len())).unwrap_or_default();
                let mut j = i + 1;
                while j < bytes.len() && bytes[j].is_ascii_whitespace() {
                    j += 1;
                }
                if j < bytes.len()
                    && bytes[j] == b':'
                    && let Some(Frame::Object(key)) = stack.last_mut()
                {
                    *key = Some(string.to_owned());
                }
            }
            _ => {}
        }
        i += 1;
    }
    stack
}

/// The stroke, sample and field at 1-based `line` and `column` of a `kansei-stroke` document,
/// or `None` outside `strokes` (or when the document's shape there is not the format's).
pub fn place_at(text: &str, line: usize, column: usize) -> Option<JsonPlace> {
    let frames = open_frames(text, offset_of(text, line, column));
    // The path must be: {strokes: [ i: {samples: [ j: {field …
    let key = |k: usize| match frames.get(k) {
        Some(Frame::Object(Some(key))) => Some(key.as_str()),
        _ => None,
    };
    let index = |k: usize| match frames.get(k) {
        Some(Frame::Array(n)) => Some(*n),
        _ => None,
    };
    if key(0) != Some("strokes") {
        return None;
    }
    let stroke = index(1)?;
    let (sample, field) = if key(2) == Some("samples") {
        let sample = index(3);
        let field = sample.and_then(|_| key(4)).map(str::to_owned);
        (sample, field)
    } else {
        (None, None)
    };
    Some(JsonPlace {
        stroke,
        sample,
        field,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn places_follow_the_documents_structure() {
        let text = "{\"format\": \"kansei-stroke\", \"strokes\": [\n\
                    {\"samples\": [{\"x\": 1, \"y\": 2}, {\"x\": 3, \"y\": 4}]},\n\
                    {\"samples\": [{\"x\": 5, \"y\": \"a,\\\"b\"}, {\"x\": 6, \"y\": 7e999}]}]}";
        // The `7e999` on line 3: stroke 1, sample 1, field y.
        let line3 = text.lines().nth(2).expect("three lines");
        let column = line3.find("7e999").expect("present") + 5;
        assert_eq!(
            place_at(text, 3, column),
            Some(JsonPlace {
                stroke: 1,
                sample: Some(1),
                field: Some("y".to_owned()),
            })
        );
        // The string with an escaped quote and a comma does not count as an element.
        let column = line3.find("a,").expect("present") + 1;
        assert_eq!(
            place_at(text, 3, column).map(|p| (p.stroke, p.sample)),
            Some((1, Some(0)))
        );
        // Line 2: stroke 0, its second sample.
        let line2 = text.lines().nth(1).expect("two lines");
        let column = line2.find("3").expect("present") + 1;
        assert_eq!(
            place_at(text, 2, column).map(|p| p.to_string()),
            Some("stroke 0, sample 1, field \"x\"".to_owned())
        );
        // The header is in no stroke.
        assert_eq!(place_at(text, 1, 5), None);
    }

    #[test]
    fn any_position_of_any_text_is_answered() {
        // Unbalanced brackets, a dangling escape, multi-byte characters, positions past the end.
        for text in [
            "",
            "]]}}",
            "{\"strokes\": [{\"samples\": [{\"x\\",
            "\"é\\",
            "{\"a\": \"ü\"}\n[,,,",
        ] {
            for line in 0..4 {
                for column in 0..(text.len() + 3) {
                    let place = place_at(text, line, column);
                    // Only a document with strokes has places.
                    assert!(place.is_none() || text.contains("strokes"), "{text:?}");
                }
            }
        }
    }
}
