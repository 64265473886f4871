//! W3C InkML (<https://www.w3.org/TR/InkML/>): read traces into a [`StrokeFile`], write one back.
//!
//! # Reading
//!
//! Every `<trace>` outside `<definitions>` becomes one stroke, in document order. A trace's
//! channels come from its context: the trace's `contextRef`, else the nearest enclosing
//! `<traceGroup contextRef>`, else the last `<context>` child of `<ink>` before it (the "current
//! context"), else the document's only `<traceFormat>`, else the InkML default (`X Y`). A
//! context's `<traceFormat>` and `<inkSource>` may be children or references
//! (`traceFormatRef`, `inkSourceRef`, `contextRef`).
//!
//! Trace data use the full compact grammar: values separated by white space or by their sign
//! (`0-1347` is two values); `!` explicit, `'` first difference, `"` second difference, each prefix
//! setting the channel's mode until another prefix changes it (every channel starts explicit at
//! the trace's start); `?` an unknown value; `*` the channel's previous value, unchanged; `T`/`F`
//! booleans (1/0); `#` hexadecimal integers; decimals with an optional exponent. Values of
//! `<intermittentChannels>` may be left off at the end of a point (they read as unknown).
//!
//! Channels used: `X`, `Y` (required), `T` time, `F` force, `OTx`/`OTy` tilt. Others are
//! decoded (so the encoding is checked) and dropped.
//!
//! - **Position units.** `mm` when both `X` and `Y` convert to millimetres: a
//!   `<channelProperty name="resolution" units="1/U">` of the `<inkSource>` (counts per `U`), or
//!   else the channel's own `units`, with `U` one of `mm`, `cm`, `m`, `in`, `pt`, `pc`,
//!   `himetric` (0.01 mm). `px` when both channels say `px`. Otherwise [`Units::Device`], raw.
//! - **Time.** `T` in seconds: its `units` `s`, `ms` or `us`; no units means milliseconds (the
//!   unit of InkML's `timeOffset` and of Microsoft's exports). Without a `T` channel samples
//!   have no time: a trace's `timeOffset` dates only its first point.
//! - **Pressure.** `F` normalised to 0..1 as `(F - min) / (max - min)` (`min` defaults to 0);
//!   without a `max` the values must already lie in 0..1.
//! - **Tilt.** `OTx`/`OTy` in degrees: a resolution in `1/deg` or `1/rad`, else the channel's
//!   `units` `deg` (also the default) or `rad`.
//! - Empty traces are skipped; a trace at one position (a tap, the dot of an "i") is kept (the
//!   pipeline fits it as a dot); every trace must pass
//!   [`crate::stroke::Stroke::validate`]. Errors name the trace by its 0-based index among
//!   all traces of the file, and a value by its point and its position within the point.
//!
//! # Writing
//!
//! [`write()`] emits one context whose trace format holds `X`, `Y` and, when any sample has
//! them, `T` (seconds), `F` (`min="0" max="1"`), `OTx`, `OTy` (degrees); a sample lacking an
//! optional field writes `?`. Numbers use Rust's shortest round-trip formatting, so reading
//! the output gives back the input exactly. The file's `source` and `device` travel in
//! `<annotation type="kansei:source">` and `<annotation type="kansei:device">` (JSON).

use std::collections::HashMap;
use std::fmt::Write as _;

use roxmltree::{Document, Node};
use thiserror::Error;

use crate::stroke::{Sample, Stroke, StrokeError, StrokeFile, Units};

/// The InkML namespace, written on the root of [`write()`]'s output. Reading accepts any namespace.
pub const INKML_NAMESPACE: &str = "http://www.w3.org/2003/InkML";

/// The namespace of the `xml:` prefix, for `xml:id`.
const XML_NAMESPACE: &str = "http://www.w3.org/XML/1998/namespace";

/// Raw channel values beyond this magnitude are refused. Device counts fit 32 bits (4.3e9) and
/// physical values are far smaller; staying below 2^53 (9.0e15) keeps integer difference
/// decoding exact.
pub const MAX_RAW_VALUE: f64 = 1e15;

/// How deep `contextRef` chains are followed before the file is refused as cyclic. Real files
/// use one level; ten leaves room for layered definitions.
const MAX_CONTEXT_DEPTH: usize = 10;

/// Annotation type carrying [`StrokeFile::source`].
const SOURCE_ANNOTATION: &str = "kansei:source";
/// Annotation type carrying [`StrokeFile::device`] as JSON.
const DEVICE_ANNOTATION: &str = "kansei:device";

/// Millimetres per unit for the length units InkML files use.
fn mm_per_unit(units: &str) -> Option<f64> {
    match units {
        "mm" => Some(1.0),
        "cm" => Some(10.0),
        "m" => Some(1000.0),
        "in" => Some(25.4),
        // PostScript point and pica: 1/72 and 1/6 inch.
        "pt" => Some(25.4 / 72.0),
        "pc" => Some(25.4 / 6.0),
        // Windows ink's HIMETRIC unit: 0.01 mm.
        "himetric" => Some(0.01),
        _ => None,
    }
}

/// Seconds per unit for the time channel.
fn seconds_per_unit(units: &str) -> Option<f64> {
    match units {
        "s" => Some(1.0),
        "ms" => Some(1e-3),
        "us" | "µs" => Some(1e-6),
        _ => None,
    }
}

/// Degrees per unit for the tilt channels.
fn degrees_per_unit(units: &str) -> Option<f64> {
    match units {
        "deg" => Some(1.0),
        "rad" => Some(180.0 / std::f64::consts::PI),
        _ => None,
    }
}

/// What is wrong with one value of a trace.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ValueProblem {
    /// The text is not a number, `?`, `*`, `T` or `F`.
    #[error("{0:?} is not a number")]
    NotANumber(String),
    /// The value (after difference decoding) is not finite or exceeds [`MAX_RAW_VALUE`].
    #[error("{0} is not finite or beyond ±{MAX_RAW_VALUE}")]
    OutOfRange(f64),
    /// A difference, or `*`, with no known previous value to apply it to.
    #[error("a difference or '*' has no previous value to apply to")]
    NoPrevious,
    /// A second difference with no known previous first difference.
    #[error("a second difference has no previous first difference to apply to")]
    NoPreviousDifference,
    /// A character that cannot start a value.
    #[error("unexpected character {0:?}")]
    UnexpectedChar(char),
    /// A difference prefix (`!`, `'`, `"`) not followed by a value.
    #[error("a difference prefix is not followed by a value")]
    DanglingPrefix,
    /// More values than the trace format has channels.
    #[error("more values than the {0} channels of the trace format")]
    TooManyValues(usize),
    /// Fewer values than the trace format's regular channels.
    #[error("{found} values where the trace format has {expected} regular channels")]
    TooFewValues {
        /// Values found in the point.
        found: usize,
        /// Regular channels of the format.
        expected: usize,
    },
    /// `X` or `Y` is `?`: a sample needs a position.
    #[error("the position is unknown ('?')")]
    UnknownPosition,
    /// `F` normalises to a value outside 0..1.
    #[error("force {raw} normalises to {normalised}, outside 0..1")]
    Pressure {
        /// The raw channel value.
        raw: f64,
        /// The value after normalisation.
        normalised: f64,
    },
}

/// Why an InkML file could not be read.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum InkmlError {
    /// The text is not well-formed XML.
    #[error("not well-formed XML: {0}")]
    Xml(String),
    /// The root element is not `<ink>`.
    #[error("the root element is <{0}>, expected <ink>")]
    NotInk(String),
    /// A `contextRef`, `traceFormatRef` or `inkSourceRef` names no element, or the chain is
    /// cyclic or too deep.
    #[error("trace {trace}: reference {reference:?} cannot be resolved")]
    BadReference {
        /// Trace index.
        trace: usize,
        /// The reference as written.
        reference: String,
    },
    /// The trace format lacks `X` or `Y`.
    #[error("trace {trace}: the trace format has no {channel} channel")]
    MissingChannel {
        /// Trace index.
        trace: usize,
        /// The missing channel.
        channel: &'static str,
    },
    /// A numeric attribute of a channel or channel property is not a finite number.
    #[error("channel {channel}: {attribute}={value:?} is not a finite number")]
    BadAttribute {
        /// Channel name.
        channel: String,
        /// Attribute name.
        attribute: &'static str,
        /// The attribute's text.
        value: String,
    },
    /// A channel's units cannot be converted (time or tilt), or its range is empty.
    #[error("channel {channel}: {problem}")]
    BadChannel {
        /// Channel name.
        channel: String,
        /// What is wrong.
        problem: String,
    },
    /// Traces disagree on position units (for instance one in mm, one in device counts).
    #[error("trace {trace}: positions in {found}, earlier traces in {expected}")]
    MixedUnits {
        /// Trace index.
        trace: usize,
        /// This trace's units.
        found: &'static str,
        /// The earlier traces' units.
        expected: &'static str,
    },
    /// A value of a trace is malformed or out of range.
    #[error(
        "trace {trace}, point {point}, value {value} ({channel}, byte {offset} of the trace): {problem}"
    )]
    Value {
        /// Trace index (0-based, all traces of the file in document order).
        trace: usize,
        /// Point index within the trace (0-based).
        point: usize,
        /// Value position within the point (0-based).
        value: usize,
        /// The channel's name.
        channel: String,
        /// Byte offset of the value in the trace's text.
        offset: usize,
        /// What is wrong.
        problem: ValueProblem,
    },
    /// A decoded trace fails the stroke rules (time backwards, coordinates beyond range...).
    #[error("trace {trace}: {source}")]
    Invalid {
        /// Trace index.
        trace: usize,
        /// The rule broken (its `stroke` field is the trace index).
        source: StrokeError,
    },
}

/// Difference mode of one channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    Explicit,
    First,
    Second,
}

/// Decoding state of one channel within a trace.
#[derive(Clone, Copy, Debug)]
struct ChannelState {
    mode: Mode,
    previous: Option<f64>,
    velocity: Option<f64>,
}

impl Default for ChannelState {
    fn default() -> Self {
        ChannelState {
            mode: Mode::Explicit,
            previous: None,
            velocity: None,
        }
    }
}

/// One lexical value of trace data.
#[derive(Clone, Copy, Debug)]
enum Token {
    Number(f64),
    Unknown,
    Repeat,
}

/// Decodes the text of one trace into points of channel values (`None` for `?` and for
/// intermittent channels left off), with `channels` naming the trace format's channels in
/// order. All channels are regular here; errors report trace 0.
///
/// ```
/// use kansei::capture::inkml::decode_trace;
/// let points = decode_trace("10 5,'2'-1,\"1\"0, !4 !4", &["X", "Y"]).unwrap();
/// let xs: Vec<f64> = points.iter().map(|p| p[0].unwrap()).collect();
/// assert_eq!(xs, [10.0, 12.0, 15.0, 4.0]);
/// ```
pub fn decode_trace(data: &str, channels: &[&str]) -> Result<Vec<Vec<Option<f64>>>, InkmlError> {
    let names: Vec<String> = channels.iter().map(|s| (*s).to_owned()).collect();
    let points = decode(0, data, &names, names.len())?;
    Ok(points
        .into_iter()
        .map(|p| p.into_iter().map(|(v, _)| v).collect())
        .collect())
}

/// A decoded value and its byte offset in the trace's text.
type Located = (Option<f64>, usize);

/// Decodes trace data; `names` lists all channels, the first `regular` of them regular.
fn decode(
    trace: usize,
    data: &str,
    names: &[String],
    regular: usize,
) -> Result<Vec<Vec<Located>>, InkmlError> {
    let total = names.len();
    let bytes = data.as_bytes();
    let mut points: Vec<Vec<Located>> = Vec::new();
    let mut current: Vec<Located> = Vec::with_capacity(total);
    let mut states = vec![ChannelState::default(); total];
    let mut pending: Option<(Mode, usize)> = None;
    let error = |point: usize, value: usize, offset: usize, problem: ValueProblem| {
        let channel = names.get(value).cloned().unwrap_or_else(|| "-".to_owned());
        InkmlError::Value {
            trace,
            point,
            value,
            channel,
            offset,
            problem,
        }
    };
    let finish = |points: &mut Vec<Vec<Located>>,
                  current: &mut Vec<Located>,
                  offset: usize|
     -> Result<(), InkmlError> {
        if current.len() < regular {
            return Err(error(
                points.len(),
                current.len(),
                offset,
                ValueProblem::TooFewValues {
                    found: current.len(),
                    expected: regular,
                },
            ));
        }
        current.resize(total, (None, offset));
        points.push(std::mem::take(current));
        Ok(())
    };
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        match b {
            b' ' | b'\t' | b'\n' | b'\r' => i += 1,
            b',' => {
                if let Some((_, at)) = pending {
                    return Err(error(
                        points.len(),
                        current.len(),
                        at,
                        ValueProblem::DanglingPrefix,
                    ));
                }
                finish(&mut points, &mut current, i)?;
                i += 1;
            }
            b'!' | b'\'' | b'"' => {
                if let Some((_, at)) = pending {
                    return Err(error(
                        points.len(),
                        current.len(),
                        at,
                        ValueProblem::DanglingPrefix,
                    ));
                }
                let mode = match b {
                    b'!' => Mode::Explicit,
                    b'\'' => Mode::First,
                    _ => Mode::Second,
                };
                pending = Some((mode, i));
                i += 1;
            }
            _ => {
                let start = pending.map_or(i, |(_, at)| at);
                let point = points.len();
                let value = current.len();
                let (token, next) =
                    lex_value(data, i).map_err(|problem| error(point, value, start, problem))?;
                let Some(state) = states.get_mut(value) else {
                    return Err(error(
                        point,
                        value,
                        start,
                        ValueProblem::TooManyValues(total),
                    ));
                };
                if let Some((mode, _)) = pending.take() {
                    state.mode = mode;
                }
                let decoded =
                    apply(state, token).map_err(|problem| error(point, value, start, problem))?;
                current.push((decoded, start));
                i = next;
            }
        }
    }
    if let Some((_, at)) = pending {
        return Err(error(
            points.len(),
            current.len(),
            at,
            ValueProblem::DanglingPrefix,
        ));
    }
    // A trailing comma leaves an empty last point: tolerated. An empty trace has no points.
    if !current.is_empty() {
        finish(&mut points, &mut current, bytes.len())?;
    }
    Ok(points)
}

/// Reads one value starting at byte `i` (after any difference prefix); returns it and the
/// index after it.
fn lex_value(data: &str, mut i: usize) -> Result<(Token, usize), ValueProblem> {
    let bytes = data.as_bytes();
    let skip_space = |mut j: usize| {
        while j < bytes.len() && matches!(bytes[j], b' ' | b'\t' | b'\n' | b'\r') {
            j += 1;
        }
        j
    };
    i = skip_space(i);
    let Some(&first) = bytes.get(i) else {
        return Err(ValueProblem::DanglingPrefix);
    };
    match first {
        b'?' => return Ok((Token::Unknown, i + 1)),
        b'*' => return Ok((Token::Repeat, i + 1)),
        b'T' => return Ok((Token::Number(1.0), i + 1)),
        b'F' => return Ok((Token::Number(0.0), i + 1)),
        _ => {}
    }
    let start = i;
    let mut negative = false;
    if first == b'-' || first == b'+' {
        negative = first == b'-';
        i = skip_space(i + 1);
    }
    let digits_from = |mut j: usize, hex: bool| {
        while j < bytes.len()
            && (bytes[j].is_ascii_digit() || (hex && bytes[j].is_ascii_hexdigit()))
        {
            j += 1;
        }
        j
    };
    let sign = if negative { -1.0 } else { 1.0 };
    if bytes.get(i) == Some(&b'#') {
        let end = digits_from(i + 1, true);
        let text = data.get(i + 1..end).unwrap_or("");
        return match u64::from_str_radix(text, 16) {
            // Integers up to 2^64 convert to the nearest f64; the range check follows.
            Ok(v) => Ok((Token::Number(sign * v as f64), end)),
            Err(_) => Err(ValueProblem::NotANumber(
                data.get(start..end).unwrap_or("").to_owned(),
            )),
        };
    }
    let mantissa_start = i;
    let mut end = digits_from(i, false);
    let mut digits = end - mantissa_start;
    if bytes.get(end) == Some(&b'.') {
        let after = digits_from(end + 1, false);
        digits += after - (end + 1);
        end = after;
    }
    if digits == 0 {
        let shown = data
            .get(start..)
            .and_then(|s| s.chars().next())
            .unwrap_or(' ');
        if start == mantissa_start {
            return Err(ValueProblem::UnexpectedChar(shown));
        }
        let upto = (end.max(start + 1)).min(data.len());
        return Err(ValueProblem::NotANumber(
            data.get(start..upto).unwrap_or("").to_owned(),
        ));
    }
    if matches!(bytes.get(end), Some(b'e' | b'E')) {
        let mut j = end + 1;
        if matches!(bytes.get(j), Some(b'+' | b'-')) {
            j += 1;
        }
        if bytes.get(j).is_some_and(u8::is_ascii_digit) {
            end = digits_from(j, false);
        }
    }
    let text = data.get(mantissa_start..end).unwrap_or("");
    match text.parse::<f64>() {
        Ok(v) => Ok((Token::Number(sign * v), end)),
        Err(_) => Err(ValueProblem::NotANumber(
            data.get(start..end).unwrap_or("").to_owned(),
        )),
    }
}

/// Applies one token to a channel's state, returning the decoded value.
fn apply(state: &mut ChannelState, token: Token) -> Result<Option<f64>, ValueProblem> {
    let (value, velocity) = match token {
        Token::Unknown => {
            state.previous = None;
            state.velocity = None;
            return Ok(None);
        }
        Token::Repeat => {
            let p = state.previous.ok_or(ValueProblem::NoPrevious)?;
            (p, Some(0.0))
        }
        Token::Number(n) => match state.mode {
            Mode::Explicit => (n, state.previous.map(|p| n - p)),
            Mode::First => {
                let p = state.previous.ok_or(ValueProblem::NoPrevious)?;
                (p + n, Some(n))
            }
            Mode::Second => {
                let p = state.previous.ok_or(ValueProblem::NoPrevious)?;
                let v = state.velocity.ok_or(ValueProblem::NoPreviousDifference)?;
                (p + v + n, Some(v + n))
            }
        },
    };
    if !value.is_finite() || value.abs() > MAX_RAW_VALUE {
        return Err(ValueProblem::OutOfRange(value));
    }
    state.previous = Some(value);
    state.velocity = velocity;
    Ok(Some(value))
}

/// A channel of a trace format, with its `<inkSource>` resolution when there is one.
#[derive(Clone, Debug)]
struct Channel {
    name: String,
    min: Option<f64>,
    max: Option<f64>,
    units: Option<String>,
    /// Counts per unit, and the unit (from `units="1/U"`).
    resolution: Option<(f64, String)>,
}

/// A resolved trace format: channels in value order, the first `regular` regular.
#[derive(Clone, Debug)]
struct Format {
    channels: Vec<Channel>,
    regular: usize,
}

impl Format {
    fn default_xy() -> Self {
        let plain = |name: &str| Channel {
            name: name.to_owned(),
            min: None,
            max: None,
            units: None,
            resolution: None,
        };
        Format {
            channels: vec![plain("X"), plain("Y")],
            regular: 2,
        }
    }

    fn index(&self, name: &str) -> Option<usize> {
        self.channels.iter().position(|c| c.name == name)
    }
}

fn is(node: &Node, name: &str) -> bool {
    node.is_element() && node.tag_name().name() == name
}

fn id_of<'a>(node: &Node<'a, '_>) -> Option<&'a str> {
    node.attribute((XML_NAMESPACE, "id"))
        .or_else(|| node.attribute("id"))
}

fn child<'a, 'i>(node: &Node<'a, 'i>, name: &str) -> Option<Node<'a, 'i>> {
    node.children().find(|c| is(c, name))
}

fn number_attribute(
    node: &Node,
    attribute: &'static str,
    channel: &str,
) -> Result<Option<f64>, InkmlError> {
    match node.attribute(attribute) {
        None => Ok(None),
        Some(text) => match text.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(Some(v)),
            _ => Err(InkmlError::BadAttribute {
                channel: channel.to_owned(),
                attribute,
                value: text.to_owned(),
            }),
        },
    }
}

/// Reads a `<traceFormat>` and the resolutions of an `<inkSource>`.
fn parse_format(trace_format: &Node, ink_source: Option<&Node>) -> Result<Format, InkmlError> {
    let mut channels = Vec::new();
    let mut regular = 0;
    let read_channel = |c: &Node| -> Result<Channel, InkmlError> {
        let name = c.attribute("name").unwrap_or("").to_owned();
        Ok(Channel {
            min: number_attribute(c, "min", &name)?,
            max: number_attribute(c, "max", &name)?,
            units: c.attribute("units").map(str::to_owned),
            resolution: None,
            name,
        })
    };
    for c in trace_format.children() {
        if is(&c, "channel") {
            channels.push(read_channel(&c)?);
            regular += 1;
        } else if is(&c, "intermittentChannels") {
            for ic in c.children().filter(|n| is(n, "channel")) {
                channels.push(read_channel(&ic)?);
            }
        }
    }
    if let Some(properties) = ink_source.and_then(|s| child(s, "channelProperties")) {
        for p in properties.children().filter(|n| is(n, "channelProperty")) {
            if p.attribute("name") != Some("resolution") {
                continue;
            }
            let name = p.attribute("channel").unwrap_or("");
            let Some(value) = number_attribute(&p, "value", name)? else {
                continue;
            };
            let unit = p
                .attribute("units")
                .and_then(|u| u.trim().strip_prefix("1/"))
                .map(str::to_owned);
            if let (Some(unit), Some(channel)) =
                (unit, channels.iter_mut().find(|c| c.name == name))
                && value > 0.0
            {
                channel.resolution = Some((value, unit));
            }
        }
    }
    Ok(Format { channels, regular })
}

/// A context's `<traceFormat>` and `<inkSource>`, when it has them.
type ContextParts<'a, 'i> = (Option<Node<'a, 'i>>, Option<Node<'a, 'i>>);

/// The document's elements by id, and the lookups that follow references.
struct Definitions<'a, 'i> {
    by_id: HashMap<&'a str, Node<'a, 'i>>,
}

impl<'a, 'i> Definitions<'a, 'i> {
    fn lookup(&self, trace: usize, reference: &str) -> Result<Node<'a, 'i>, InkmlError> {
        let key = reference.trim().trim_start_matches('#');
        self.by_id
            .get(key)
            .copied()
            .ok_or_else(|| InkmlError::BadReference {
                trace,
                reference: reference.to_owned(),
            })
    }

    /// The `<traceFormat>` and `<inkSource>` a context provides, following its references.
    fn context_parts(
        &self,
        trace: usize,
        context: Node<'a, 'i>,
        depth: usize,
    ) -> Result<ContextParts<'a, 'i>, InkmlError> {
        if depth > MAX_CONTEXT_DEPTH {
            return Err(InkmlError::BadReference {
                trace,
                reference: context.attribute("contextRef").unwrap_or("").to_owned(),
            });
        }
        let mut source = match child(&context, "inkSource") {
            Some(s) => Some(s),
            None => match context.attribute("inkSourceRef") {
                Some(r) => Some(self.lookup(trace, r)?),
                None => None,
            },
        };
        let mut format = match child(&context, "traceFormat") {
            Some(f) => Some(f),
            None => match context.attribute("traceFormatRef") {
                Some(r) => Some(self.lookup(trace, r)?),
                None => None,
            },
        };
        if format.is_none() {
            format = source.and_then(|s| child(&s, "traceFormat"));
        }
        if (format.is_none() || source.is_none())
            && let Some(r) = context.attribute("contextRef")
        {
            let parent = self.lookup(trace, r)?;
            let (f, s) = self.context_parts(trace, parent, depth + 1)?;
            format = format.or(f);
            source = source.or(s);
        }
        Ok((format, source))
    }
}

/// How a trace's positions convert.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Positions {
    /// Millimetres per raw value, for X and Y.
    Mm(f64, f64),
    Px,
    Device,
}

impl Positions {
    fn units(self) -> Units {
        match self {
            Positions::Mm(..) => Units::Mm,
            Positions::Px => Units::Px,
            Positions::Device => Units::Device,
        }
    }
}

fn length_scale(c: &Channel) -> Option<f64> {
    if let Some((counts, unit)) = &c.resolution {
        return mm_per_unit(unit).map(|mm| mm / counts);
    }
    c.units.as_deref().and_then(mm_per_unit)
}

/// The conversions of one trace format.
struct Plan {
    x: usize,
    y: usize,
    positions: Positions,
    /// Channel index and seconds per raw value.
    t: Option<(usize, f64)>,
    /// Channel index, min and max (None: already 0..1).
    f: Option<(usize, Option<(f64, f64)>)>,
    /// Channel index and degrees per raw value.
    tilt_x: Option<(usize, f64)>,
    tilt_y: Option<(usize, f64)>,
}

fn plan(trace: usize, format: &Format) -> Result<Plan, InkmlError> {
    let x = format.index("X").ok_or(InkmlError::MissingChannel {
        trace,
        channel: "X",
    })?;
    let y = format.index("Y").ok_or(InkmlError::MissingChannel {
        trace,
        channel: "Y",
    })?;
    let (cx, cy) = (&format.channels[x], &format.channels[y]);
    let positions = match (length_scale(cx), length_scale(cy)) {
        (Some(sx), Some(sy)) => Positions::Mm(sx, sy),
        _ if cx.units.as_deref() == Some("px") && cy.units.as_deref() == Some("px") => {
            Positions::Px
        }
        _ => Positions::Device,
    };
    let bad = |c: &Channel, problem: String| InkmlError::BadChannel {
        channel: c.name.clone(),
        problem,
    };
    let t = match format.index("T") {
        None => None,
        Some(i) => {
            let c = &format.channels[i];
            let units = c.units.as_deref().unwrap_or("ms");
            let scale = seconds_per_unit(units)
                .ok_or_else(|| bad(c, format!("time units {units:?} are not s, ms or us")))?;
            Some((i, scale))
        }
    };
    let f = match format.index("F") {
        None => None,
        Some(i) => {
            let c = &format.channels[i];
            let range = match c.max {
                None => None,
                Some(max) => {
                    let min = c.min.unwrap_or(0.0);
                    if !(max > min) {
                        return Err(bad(c, format!("max {max} is not above min {min}")));
                    }
                    Some((min, max))
                }
            };
            Some((i, range))
        }
    };
    let angle = |name: &str| -> Result<Option<(usize, f64)>, InkmlError> {
        let Some(i) = format.index(name) else {
            return Ok(None);
        };
        let c = &format.channels[i];
        let scale = match &c.resolution {
            Some((counts, unit)) => degrees_per_unit(unit).map(|d| d / counts),
            None => degrees_per_unit(c.units.as_deref().unwrap_or("deg")),
        };
        let scale = scale.ok_or_else(|| bad(c, "tilt units are not deg or rad".to_owned()))?;
        Ok(Some((i, scale)))
    };
    Ok(Plan {
        x,
        y,
        positions,
        t,
        f,
        tilt_x: angle("OTx")?,
        tilt_y: angle("OTy")?,
    })
}

/// Reads an InkML document. See the [module documentation](self) for what is read and how.
pub fn read(text: &str) -> Result<StrokeFile, InkmlError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let doc = Document::parse(text).map_err(|e| InkmlError::Xml(e.to_string()))?;
    let root = doc.root_element();
    if root.tag_name().name() != "ink" {
        return Err(InkmlError::NotInk(root.tag_name().name().to_owned()));
    }
    let defs = Definitions {
        by_id: root
            .descendants()
            .filter(|n| n.is_element())
            .filter_map(|n| id_of(&n).map(|id| (id, n)))
            .collect(),
    };
    let only_format = {
        let mut formats = root.descendants().filter(|n| is(n, "traceFormat"));
        match (formats.next(), formats.next()) {
            (Some(f), None) => Some(f),
            _ => None,
        }
    };

    let mut source = None;
    let mut device = None;
    for a in root.children().filter(|n| is(n, "annotation")) {
        let body = a.text().unwrap_or("");
        match a.attribute("type") {
            Some(SOURCE_ANNOTATION) => source = Some(body.to_owned()),
            Some(DEVICE_ANNOTATION) => device = serde_json::from_str(body).ok(),
            _ => {}
        }
    }

    let mut strokes = Vec::new();
    let mut units: Option<Units> = None;
    let mut current_context: Option<Node> = None;
    let mut trace_index = 0;
    for node in root.descendants() {
        if is(&node, "context") && node.parent().is_some_and(|p| p == root) {
            current_context = Some(node);
            continue;
        }
        if !is(&node, "trace") || node.ancestors().any(|a| is(&a, "definitions")) {
            continue;
        }
        let trace = trace_index;
        trace_index += 1;

        let reference = node.attribute("contextRef").or_else(|| {
            node.ancestors()
                .filter(|a| is(a, "traceGroup"))
                .find_map(|a| a.attribute("contextRef"))
        });
        let context = match reference {
            Some(r) => Some(defs.lookup(trace, r)?),
            None => current_context,
        };
        let (format_node, source_node) = match context {
            Some(c) => defs.context_parts(trace, c, 0)?,
            None => (None, None),
        };
        let (format_node, source_node) = match format_node {
            Some(f) => (Some(f), source_node),
            None => (
                only_format,
                only_format.and_then(|f| f.parent().filter(|p| is(p, "inkSource"))),
            ),
        };
        let format = match format_node {
            Some(f) => parse_format(&f, source_node.as_ref())?,
            None => Format::default_xy(),
        };
        let plan = plan(trace, &format)?;
        let found = plan.positions.units();
        match units {
            None => units = Some(found),
            Some(expected) if expected != found => {
                return Err(InkmlError::MixedUnits {
                    trace,
                    found: found.name(),
                    expected: expected.name(),
                });
            }
            Some(_) => {}
        }

        let names: Vec<String> = format.channels.iter().map(|c| c.name.clone()).collect();
        let data = node.text().unwrap_or("");
        let points = decode(trace, data, &names, format.regular)?;
        let stroke = Stroke::new(
            points
                .iter()
                .enumerate()
                .map(|(i, p)| to_sample(trace, i, p, &plan, &names))
                .collect::<Result<_, _>>()?,
        );
        match stroke.validate(trace) {
            Ok(()) => strokes.push(stroke),
            Err(StrokeError::NoSamples { .. }) => {}
            Err(e) => return Err(InkmlError::Invalid { trace, source: e }),
        }
    }
    let mut file = StrokeFile::new(units.unwrap_or(Units::Device), strokes);
    file.source = source;
    file.device = device;
    Ok(file)
}

/// Converts one decoded point.
fn to_sample(
    trace: usize,
    point: usize,
    values: &[Located],
    plan: &Plan,
    names: &[String],
) -> Result<Sample, InkmlError> {
    let error = |value: usize, problem: ValueProblem| InkmlError::Value {
        trace,
        point,
        value,
        channel: names.get(value).cloned().unwrap_or_default(),
        offset: values.get(value).map_or(0, |&(_, at)| at),
        problem,
    };
    let get = |i: usize| values.get(i).and_then(|&(v, _)| v);
    let (Some(x), Some(y)) = (get(plan.x), get(plan.y)) else {
        let which = if get(plan.x).is_none() {
            plan.x
        } else {
            plan.y
        };
        return Err(error(which, ValueProblem::UnknownPosition));
    };
    let (x, y) = match plan.positions {
        Positions::Mm(sx, sy) => (x * sx, y * sy),
        Positions::Px | Positions::Device => (x, y),
    };
    let mut sample = Sample::new(x, y);
    sample.t = plan.t.and_then(|(i, scale)| get(i).map(|v| v * scale));
    if let Some((i, range)) = plan.f
        && let Some(raw) = get(i)
    {
        let normalised = match range {
            Some((min, max)) => (raw - min) / (max - min),
            None => raw,
        };
        if !(0.0..=1.0).contains(&normalised) {
            return Err(error(i, ValueProblem::Pressure { raw, normalised }));
        }
        sample.pressure = Some(normalised);
    }
    sample.tilt_x = plan.tilt_x.and_then(|(i, scale)| get(i).map(|v| v * scale));
    sample.tilt_y = plan.tilt_y.and_then(|(i, scale)| get(i).map(|v| v * scale));
    Ok(sample)
}

/// Escapes text for XML content and attribute values. Carriage returns become character
/// references so the parser's line-end normalisation keeps them; characters XML 1.0 forbids
/// (other control characters) become U+FFFD.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\r' => out.push_str("&#13;"),
            '\t' | '\n' => out.push(c),
            c if (c as u32) < 0x20 => out.push('\u{fffd}'),
            c => out.push(c),
        }
    }
    out
}

/// Writes a [`StrokeFile`] as InkML. See the [module documentation](self) for the layout.
///
/// ```
/// use kansei::capture::inkml;
/// use kansei::stroke::{Sample, Stroke, StrokeFile, Units};
/// let file = StrokeFile::new(Units::Mm, vec![Stroke::new(vec![
///     Sample::new(0.1, 2.0).with_t(0.0),
///     Sample::new(1.0 / 3.0, 2.5).with_t(0.008),
/// ])]);
/// assert_eq!(inkml::read(&inkml::write(&file)).unwrap(), file);
/// ```
pub fn write(file: &StrokeFile) -> String {
    let samples = || file.strokes.iter().flat_map(|s| s.samples.iter());
    let has_t = samples().any(|s| s.t.is_some());
    let has_f = samples().any(|s| s.pressure.is_some());
    let has_tx = samples().any(|s| s.tilt_x.is_some());
    let has_ty = samples().any(|s| s.tilt_y.is_some());
    let xy_units = match file.units {
        Units::Mm => "mm",
        Units::Px => "px",
        Units::Device => "dev",
    };

    let mut out = String::new();
    out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    // Writing to a String cannot fail; the results of write! are ignored on that ground.
    let _ = writeln!(out, "<ink xmlns=\"{INKML_NAMESPACE}\">");
    if let Some(source) = &file.source {
        let _ = writeln!(
            out,
            "  <annotation type=\"{SOURCE_ANNOTATION}\">{}</annotation>",
            escape(source)
        );
    }
    if let Some(device) = &file.device {
        let _ = writeln!(
            out,
            "  <annotation type=\"{DEVICE_ANNOTATION}\">{}</annotation>",
            escape(&device.to_string())
        );
    }
    out.push_str("  <definitions>\n    <context xml:id=\"ctx0\">\n      <traceFormat>\n");
    let _ = writeln!(
        out,
        "        <channel name=\"X\" type=\"decimal\" units=\"{xy_units}\"/>"
    );
    let _ = writeln!(
        out,
        "        <channel name=\"Y\" type=\"decimal\" units=\"{xy_units}\"/>"
    );
    if has_t {
        out.push_str("        <channel name=\"T\" type=\"decimal\" units=\"s\"/>\n");
    }
    if has_f {
        out.push_str("        <channel name=\"F\" type=\"decimal\" min=\"0\" max=\"1\"/>\n");
    }
    if has_tx {
        out.push_str("        <channel name=\"OTx\" type=\"decimal\" units=\"deg\"/>\n");
    }
    if has_ty {
        out.push_str("        <channel name=\"OTy\" type=\"decimal\" units=\"deg\"/>\n");
    }
    out.push_str("      </traceFormat>\n    </context>\n  </definitions>\n");
    for stroke in &file.strokes {
        out.push_str("  <trace contextRef=\"#ctx0\">");
        for (i, s) in stroke.samples.iter().enumerate() {
            if i > 0 {
                out.push_str(", ");
            }
            let _ = write!(out, "{} {}", s.x, s.y);
            let optional = [
                (has_t, s.t),
                (has_f, s.pressure),
                (has_tx, s.tilt_x),
                (has_ty, s.tilt_y),
            ];
            for (present, value) in optional {
                match (present, value) {
                    (false, _) => {}
                    (true, Some(v)) => {
                        let _ = write!(out, " {v}");
                    }
                    (true, None) => out.push_str(" ?"),
                }
            }
        }
        out.push_str("</trace>\n");
    }
    out.push_str("</ink>\n");
    out
}
