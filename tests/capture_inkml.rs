//! InkML: the real Windows Ink reference file against its independent decoding, the difference
//! encodings on planted values, exact write→read round trips, and bad input.

mod common;

use kansei::capture::inkml::{self, InkmlError, ValueProblem, decode_trace};
use kansei::stroke::{Sample, Stroke, StrokeFile, Units};

const REFERENCE: &str = include_str!("../fixtures/inkml/reference.inkml");
const REFERENCE_CSV: &str = include_str!("../fixtures/inkml/reference.decoded.csv");
const DIFFERENCES: &str = include_str!("../fixtures/inkml/differences.inkml");

/// The reference file's channel properties: counts per inch of X and Y, and F's max.
const X_PER_INCH: f64 = 3971.75757;
const Y_PER_INCH: f64 = 5295.24854;
const F_MAX: f64 = 32767.0;
const MM_PER_INCH: f64 = 25.4;
/// Relative tolerance of the mm comparison: the reader multiplies by 25.4/resolution, the test
/// divides; the two roundings differ by at most a few ulps (1e-15), far below this.
const RELATIVE_TOLERANCE: f64 = 1e-12;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= RELATIVE_TOLERANCE * a.abs().max(b.abs()).max(1.0)
}

#[test]
fn reference_file_matches_its_decoded_csv_at_every_point() {
    let file = inkml::read(REFERENCE).expect("reference reads");
    assert_eq!(file.units, Units::Mm);
    let counts: Vec<usize> = file.strokes.iter().map(|s| s.samples.len()).collect();
    assert_eq!(
        counts,
        [164, 9, 71, 11, 44, 124, 16, 15, 58, 35, 15, 26, 35]
    );
    let mut rows = 0;
    for line in REFERENCE_CSV.lines().skip(1) {
        let v: Vec<f64> = line
            .split(',')
            .map(|f| f.parse().expect("a number"))
            .collect();
        let (trace, point) = (v[0] as usize, v[1] as usize);
        let s = &file.strokes[trace].samples[point];
        let (x, y, f) = (v[2], v[3], v[4]);
        assert!(
            close(s.x, x * MM_PER_INCH / X_PER_INCH),
            "{line}: x {}",
            s.x
        );
        assert!(
            close(s.y, y * MM_PER_INCH / Y_PER_INCH),
            "{line}: y {}",
            s.y
        );
        // The raw integer counts come back exactly.
        assert_eq!((s.x * X_PER_INCH / MM_PER_INCH).round(), x, "{line}");
        assert_eq!((s.y * Y_PER_INCH / MM_PER_INCH).round(), y, "{line}");
        assert_eq!(s.pressure, Some(f / F_MAX), "{line}");
        assert_eq!((s.t, s.tilt_x, s.tilt_y), (None, None, None));
        rows += 1;
    }
    assert_eq!(rows, 623);
    assert_eq!(rows, counts.iter().sum::<usize>());
}

#[test]
fn reference_file_round_trips_through_write() {
    let file = inkml::read(REFERENCE).expect("reads");
    assert_eq!(inkml::read(&inkml::write(&file)).expect("reads"), file);
}

/// Encodes integer channel sequences as first (`'`) or second (`"`) differences, prefixing
/// only the first difference of each channel (the mode is sticky).
fn encode(points: &[[i64; 3]], order: u8) -> String {
    let mut out = String::new();
    for (i, p) in points.iter().enumerate() {
        if i > 0 {
            out.push(',');
        }
        for c in 0..3 {
            let prefix = match (order, i) {
                (_, 0) => "",
                (1, 1) => "'",
                (2, 1) => "'",
                (2, 2) => "\"",
                _ => "",
            };
            let value = match (order, i) {
                (_, 0) => p[c],
                (1, _) | (2, 1) => p[c] - points[i - 1][c],
                _ => (p[c] - points[i - 1][c]) - (points[i - 1][c] - points[i - 2][c]),
            };
            // Space-separate only non-negative values: a minus sign separates by itself.
            if c > 0 && (value >= 0 || !prefix.is_empty()) {
                out.push(' ');
            }
            out.push_str(prefix);
            out.push_str(&value.to_string());
        }
    }
    out
}

fn planted() -> Vec<[i64; 3]> {
    let mut rng = common::Rng::new(7);
    let mut p = [5000i64, -300, 100];
    (0..200)
        .map(|_| {
            for v in &mut p {
                *v += (rng.uniform() * 201.0) as i64 - 100;
            }
            p
        })
        .collect()
}

fn decoded_ints(text: &str) -> Vec<[i64; 3]> {
    decode_trace(text, &["X", "Y", "F"])
        .expect("present")
        .iter()
        .map(|p| [0, 1, 2].map(|c| p[c].expect("present") as i64))
        .collect()
}

#[test]
fn first_differences_decode_to_planted_values() {
    let points = planted();
    let text = encode(&points, 1);
    assert!(text.contains('\'') && !text.contains('"'));
    assert_eq!(decoded_ints(&text), points);
}

#[test]
fn second_differences_decode_to_planted_values() {
    let points = planted();
    let text = encode(&points, 2);
    assert!(text.contains('"'));
    assert_eq!(decoded_ints(&text), points);
}

#[test]
fn w3c_example_and_sign_separated_values() {
    // The example of the InkML specification: velocity then acceleration, sticky modes.
    let p = decode_trace("1125 18432,'23'43,\"7\"-8,3-5", &["X", "Y"]).expect("decodes");
    let xy: Vec<(f64, f64)> = p
        .iter()
        .map(|p| (p[0].expect("present"), p[1].expect("present")))
        .collect();
    assert_eq!(
        xy,
        [
            (1125.0, 18432.0),
            (1148.0, 18475.0),
            (1178.0, 18510.0),
            (1211.0, 18540.0)
        ]
    );
    // `!` returns to explicit values; decimals run together; hex; booleans; exponents; `?`
    // unknown; `*` repeats the previous value.
    let p = decode_trace("1 2, '1 !7, !1.5.25, #1F T, -2e1 F, ? *", &["A", "B"]).expect("decodes");
    let expected = [
        [Some(1.0), Some(2.0)],
        [Some(2.0), Some(7.0)],
        [Some(1.5), Some(0.25)],
        [Some(31.0), Some(1.0)],
        [Some(-20.0), Some(0.0)],
        [None, Some(0.0)],
    ];
    assert_eq!(p, expected);
}

#[test]
fn hand_written_fixture_decodes_to_planted_values() {
    let file = inkml::read(DIFFERENCES).expect("reads");
    assert_eq!(file.units, Units::Mm);
    assert_eq!(file.strokes.len(), 2);
    let deg = |rad: f64| rad * 180.0 / std::f64::consts::PI;
    // (X, Y) in himetric, T in ms, F of 1023, tilt in rad.
    type Row = (f64, f64, f64, Option<f64>, Option<f64>, Option<f64>);
    let expected: [Row; 5] = [
        (1000.0, 2000.0, 0.0, Some(512.0), Some(0.1), Some(-0.2)),
        (1010.0, 2000.0, 8.0, Some(524.0), None, None),
        (1022.0, 2005.0, 16.0, Some(534.0), Some(0.15), Some(-0.2)),
        (1036.0, 2015.0, 24.0, None, None, None),
        (1050.0, 2020.0, 32.0, Some(530.0), None, None),
    ];
    let samples = &file.strokes[0].samples;
    assert_eq!(samples.len(), expected.len());
    for (s, &(x, y, t, f, tx, ty)) in samples.iter().zip(&expected) {
        assert!(close(s.x, x * 0.01) && close(s.y, y * 0.01), "{s:?}");
        assert!(close(s.t.expect("present"), t * 1e-3), "{s:?}");
        assert_eq!(s.pressure.is_some(), f.is_some());
        if let (Some(p), Some(f)) = (s.pressure, f) {
            assert!(close(p, f / 1023.0), "{s:?}");
        }
        for (got, want) in [(s.tilt_x, tx), (s.tilt_y, ty)] {
            assert_eq!(got.is_some(), want.is_some(), "{s:?}");
            if let (Some(g), Some(w)) = (got, want) {
                assert!(close(g, deg(w)), "{s:?}");
            }
        }
    }
    let second = &file.strokes[1].samples;
    assert_eq!(second.len(), 2);
    assert_eq!((second[1].x, second[1].pressure), (1.0, Some(1.0)));
}

fn sample(x: f64, y: f64) -> Sample {
    Sample::new(x, y)
}

#[test]
fn every_stroke_fixture_round_trips_exactly() {
    for name in common::fixture_names() {
        let file = common::fixture(&name);
        let again = inkml::read(&inkml::write(&file)).expect("reads");
        assert_eq!(again, file, "{name}");
    }
}

#[test]
fn awkward_numbers_units_and_provenance_round_trip_bit_for_bit() {
    let xs = [
        0.1 + 0.2,
        1.0 / 3.0,
        1e-300,
        123456.78901234567,
        -0.0,
        -1e9,
        5e-324,
    ];
    let samples: Vec<Sample> = xs
        .iter()
        .enumerate()
        .map(|(i, &x)| {
            let mut s = sample(x, -x / 7.0 + i as f64).with_t(i as f64 * 0.1 + 1e-9);
            s.pressure = (i % 2 == 0).then_some(1.0 / (i as f64 + 3.0));
            s.tilt_x = Some(-45.0 + i as f64 / 3.0);
            s
        })
        .collect();
    for units in [Units::Mm, Units::Px, Units::Device] {
        let mut file = StrokeFile::new(
            units,
            vec![
                Stroke::new(samples.clone()),
                Stroke::new(vec![sample(0.0, 0.0), sample(1.0, 0.5)]),
            ],
        );
        file.source = Some("a <tricky> & \"quoted\" 'source'\r\nline two\tend".to_owned());
        file.device = Some(serde_json::json!({"name": "Wacom <Intuos>", "lpmm": 200}));
        let text = inkml::write(&file);
        let again = inkml::read(&text).expect("reads");
        assert_eq!(again, file, "{units:?}");
        for (a, b) in again.strokes[0].samples.iter().zip(&samples) {
            assert_eq!(a.x.to_bits(), b.x.to_bits());
        }
    }
}

#[test]
fn channel_and_resolution_units_convert_to_mm() {
    let doc = |x_units: &str, props: &str| {
        format!(
            r##"<ink><definitions><context xml:id="c"><inkSource xml:id="s">
            <traceFormat><channel name="X" units="{x_units}"/><channel name="Y" units="{x_units}"/></traceFormat>
            <channelProperties>{props}</channelProperties></inkSource></context></definitions>
            <trace contextRef="#c">0 0, 2 4</trace></ink>"##
        )
    };
    let end = |text: String| {
        let f = inkml::read(&text).expect("reads");
        let s = f.strokes[0].samples[1];
        (f.units, s.x, s.y)
    };
    assert_eq!(end(doc("cm", "")), (Units::Mm, 20.0, 40.0));
    assert_eq!(end(doc("in", "")), (Units::Mm, 2.0 * 25.4, 4.0 * 25.4));
    assert_eq!(end(doc("himetric", "")), (Units::Mm, 0.02, 0.04));
    assert_eq!(end(doc("dev", "")), (Units::Device, 2.0, 4.0));
    assert_eq!(end(doc("px", "")), (Units::Px, 2.0, 4.0));
    let res = r#"<channelProperty channel="X" name="resolution" value="2" units="1/mm"/>
                 <channelProperty channel="Y" name="resolution" value="0.5" units="1/cm"/>"#;
    assert_eq!(end(doc("dev", res)), (Units::Mm, 1.0, 80.0));
    // No trace format at all: the InkML default X Y, device units.
    let f = inkml::read("<ink><trace>1 2, 3 4</trace></ink>").expect("reads");
    assert_eq!(f.units, Units::Device);
    assert_eq!(f.strokes[0].samples[1], sample(3.0, 4.0));
}

#[test]
fn taps_are_kept_as_strokes_at_one_position() {
    let f =
        inkml::read("<ink><trace>1 2</trace><trace>5 5, 5 5</trace><trace>1 2, 3 4</trace></ink>")
            .expect("present");
    let counts: Vec<usize> = f.strokes.iter().map(|s| s.samples.len()).collect();
    assert_eq!(counts, [1, 2, 2]);
    assert_eq!(f.strokes[1].samples[0], sample(5.0, 5.0));
}

fn error(text: &str) -> InkmlError {
    match inkml::read(text) {
        Ok(f) => panic!("accepted {text:?}: {f:?}"),
        Err(e) => e,
    }
}

/// Trace index, point index, value position, and the problem.
type Located = (usize, usize, usize, ValueProblem);

fn value_error(trace_data: &str) -> Located {
    let text = format!(
        r##"<ink><traceFormat><channel name="X"/><channel name="Y"/><channel name="F" max="100"/></traceFormat>
        <trace>0 0 0, 1 1 1</trace><trace>{trace_data}</trace></ink>"##
    );
    match error(&text) {
        InkmlError::Value {
            trace,
            point,
            value,
            problem,
            ..
        } => (trace, point, value, problem),
        other => panic!("{other:?}"),
    }
}

#[test]
fn bad_values_name_trace_point_and_position() {
    use ValueProblem::*;
    let cases: Vec<(&str, Located)> = vec![
        ("0 0 0, 1 x 1", (1, 1, 1, UnexpectedChar('x'))),
        ("0 0 0, 1 NaN 1", (1, 1, 1, UnexpectedChar('N'))),
        ("0 0 0, 1 1 -", (1, 1, 2, NotANumber("-".to_owned()))),
        // A sign may be followed by white space: "- 1" is -1, so this is a pressure error.
        (
            "0 0 0, 1 1 - 1",
            (
                1,
                1,
                2,
                Pressure {
                    raw: -1.0,
                    normalised: -0.01,
                },
            ),
        ),
        ("0 0 0, 1 1e400 1", (1, 1, 1, OutOfRange(f64::INFINITY))),
        ("0 0 0, 1 2e15 1", (1, 1, 1, OutOfRange(2e15))),
        ("'0 0 0, 1 1 1", (1, 0, 0, NoPrevious)),
        ("0 0 0, \"1 1 1", (1, 1, 0, NoPreviousDifference)),
        ("0 0 0, 1 1 1 1", (1, 1, 3, TooManyValues(3))),
        (
            "0 0 0, 1 1",
            (
                1,
                1,
                2,
                TooFewValues {
                    found: 2,
                    expected: 3,
                },
            ),
        ),
        ("0 0 0, 1 1 '", (1, 1, 2, DanglingPrefix)),
        ("0 0 0, 1 1 '', 3", (1, 1, 2, DanglingPrefix)),
        ("0 0 0, 1 ? 1", (1, 1, 1, UnknownPosition)),
        (
            "0 0 0, 1 1 101",
            (
                1,
                1,
                2,
                Pressure {
                    raw: 101.0,
                    normalised: 1.01,
                },
            ),
        ),
        (
            "0 0 0, 1 1 *, 2 2 -1",
            (
                1,
                2,
                2,
                Pressure {
                    raw: -1.0,
                    normalised: -0.01,
                },
            ),
        ),
        (
            "0 0 0, 1 1 1, 2 2 #ZZ",
            (1, 2, 2, NotANumber("#".to_owned())),
        ),
    ];
    for (data, expected) in cases {
        let got = value_error(data);
        assert_eq!(got, expected, "{data}");
        // The message names the trace, the point and the position.
        let text = format!(
            r##"<ink><traceFormat><channel name="X"/><channel name="Y"/><channel name="F" max="100"/></traceFormat>
            <trace>0 0 0, 1 1 1</trace><trace>{data}</trace></ink>"##
        );
        let message = error(&text).to_string();
        assert!(
            message.starts_with(&format!(
                "trace 1, point {}, value {}",
                expected.1, expected.2
            )),
            "{message}"
        );
    }
}

#[test]
fn bad_documents_are_refused_with_clear_errors() {
    assert!(matches!(error(""), InkmlError::Xml(_)));
    assert!(matches!(error("<ink><trace>1 2</ink>"), InkmlError::Xml(_)));
    assert!(matches!(error("not xml at all"), InkmlError::Xml(_)));
    assert_eq!(error("<svg/>"), InkmlError::NotInk("svg".to_owned()));
    assert_eq!(
        error(r#"<ink><traceFormat><channel name="X"/></traceFormat><trace>1, 2</trace></ink>"#),
        InkmlError::MissingChannel {
            trace: 0,
            channel: "Y"
        }
    );
    assert!(matches!(
        error(r##"<ink><trace contextRef="#nowhere">1 2, 3 4</trace></ink>"##),
        InkmlError::BadReference { trace: 0, .. }
    ));
    // A context that refers to itself.
    assert!(matches!(
        error(
            r##"<ink><context xml:id="a" contextRef="#a"/><trace contextRef="#a">1 2, 3 4</trace></ink>"##
        ),
        InkmlError::BadReference { trace: 0, .. }
    ));
    assert!(matches!(
        error(
            r#"<ink><traceFormat><channel name="X" max="lots"/><channel name="Y"/></traceFormat><trace>1 2, 3 4</trace></ink>"#
        ),
        InkmlError::BadAttribute {
            attribute: "max",
            ..
        }
    ));
    assert!(matches!(
        error(
            r#"<ink><traceFormat><channel name="X"/><channel name="Y"/><channel name="F" min="5" max="5"/></traceFormat><trace>1 2 5, 3 4 5</trace></ink>"#
        ),
        InkmlError::BadChannel { .. }
    ));
    assert!(matches!(
        error(
            r#"<ink><traceFormat><channel name="X"/><channel name="Y"/><channel name="T" units="fortnight"/></traceFormat><trace>1 2 5, 3 4 5</trace></ink>"#
        ),
        InkmlError::BadChannel { .. }
    ));
    // Time running backwards within a trace, and coordinates past the accepted range.
    assert!(matches!(
        error(
            r#"<ink><traceFormat><channel name="X"/><channel name="Y"/><channel name="T"/></traceFormat><trace>1 2 5, 3 4 1</trace></ink>"#
        ),
        InkmlError::Invalid { trace: 0, .. }
    ));
    assert!(matches!(
        error("<ink><trace>0 0, 1 1</trace><trace>1 2, 3e10 4</trace></ink>"),
        InkmlError::Invalid { trace: 1, .. }
    ));
    // Traces in different units.
    assert!(matches!(
        error(
            r##"<ink><definitions>
        <context xml:id="a"><traceFormat><channel name="X" units="mm"/><channel name="Y" units="mm"/></traceFormat></context>
        <context xml:id="b"><traceFormat><channel name="X"/><channel name="Y"/></traceFormat></context></definitions>
        <trace contextRef="#a">1 2, 3 4</trace><trace contextRef="#b">1 2, 3 4</trace></ink>"##
        ),
        InkmlError::MixedUnits { trace: 1, .. }
    ));
}

#[test]
fn value_errors_carry_the_byte_offset() {
    let text = r#"<ink><traceFormat><channel name="X"/><channel name="Y"/><channel name="F" max="100"/></traceFormat><trace>0 0 0, 1 1 101</trace></ink>"#;
    match error(text) {
        InkmlError::Value {
            offset, channel, ..
        } => assert_eq!((offset, channel.as_str()), (11, "F")),
        other => panic!("{other:?}"),
    }
}

/// Characters that matter to the trace grammar and to XML.
const MUTATIONS: &[u8] = b"0123456789-+'\"!?*,. #eETFx<>&/";

#[test]
fn mutated_and_truncated_reference_never_panics_and_what_is_accepted_is_valid() {
    let mut rng = common::Rng::new(11);
    let bytes = REFERENCE.as_bytes();
    let mut accepted = 0;
    for round in 0..1500 {
        let mut text = bytes.to_vec();
        let at = (rng.uniform() * text.len() as f64) as usize;
        if round % 3 == 0 {
            text.truncate(at);
        } else if text[at].is_ascii() {
            text[at] = MUTATIONS[(rng.uniform() * MUTATIONS.len() as f64) as usize];
        }
        let Ok(text) = String::from_utf8(text) else {
            continue;
        };
        if let Ok(file) = inkml::read(&text) {
            assert!(file.validate().is_ok());
            accepted += 1;
        }
    }
    // Most single-character changes inside trace data still decode (to different ink).
    assert!(accepted > 100, "{accepted}");
}
