//! The kansei-stroke format: round trips and every kind of bad input.

mod common;

use kansei::pipeline::{PipelineOptions, fit_file};
use kansei::stroke::{Sample, Stroke, StrokeError, StrokeFile, Units};

fn doc(samples: &str) -> String {
    format!(
        r#"{{"format": "kansei-stroke", "version": 1, "units": "mm", "strokes": [{{"samples": [{samples}]}}]}}"#
    )
}

#[test]
fn every_fixture_round_trips_exactly() {
    for name in common::fixture_names() {
        let file = common::fixture(&name);
        let again = StrokeFile::from_json(&file.to_json()).expect("own output reads back");
        assert_eq!(file, again, "{name}");
    }
}

#[test]
fn awkward_numbers_round_trip_bit_for_bit() {
    let xs = [
        0.1 + 0.2,
        1.0 / 3.0,
        1e-300,
        123456.78901234567,
        -0.0,
        5e-324,
    ];
    let stroke = Stroke::new(
        xs.iter()
            .enumerate()
            .map(|(i, &x)| Sample::new(x, i as f64).with_t(i as f64 * 1e-3))
            .collect(),
    );
    let file = StrokeFile::new(Units::Px, vec![stroke]);
    let again = StrokeFile::from_json(&file.to_json()).expect("reads back");
    for (a, b) in file.strokes[0]
        .samples
        .iter()
        .zip(&again.strokes[0].samples)
    {
        assert_eq!(a.x.to_bits(), b.x.to_bits());
    }
}

#[test]
fn bad_inputs_give_errors_naming_the_place() {
    let cases: Vec<(String, StrokeError)> = vec![
        (String::new(), StrokeError::Empty),
        ("   \n".into(), StrokeError::Empty),
        (doc(""), StrokeError::NoSamples { stroke: 0 }),
        (
            doc(r#"{"x": 0, "y": 0, "t": 1.0}, {"x": 1, "y": 0, "t": 0.5}"#),
            StrokeError::TimeBackwards {
                stroke: 0,
                sample: 1,
                t: 0.5,
                previous: 1.0,
            },
        ),
        (
            doc(r#"{"x": 0, "y": 0}, {"x": 1e10, "y": 0}"#),
            StrokeError::OutOfRange {
                stroke: 0,
                sample: 1,
                field: "x",
                value: 1e10,
                limit: 1e9,
            },
        ),
        (
            doc(r#"{"x": 0, "y": 0, "pressure": 1.5}, {"x": 1, "y": 0}"#),
            StrokeError::Pressure {
                stroke: 0,
                sample: 0,
                value: 1.5,
            },
        ),
        (
            doc(r#"{"x": 0, "y": 0, "t": 0}, {"x": 1, "y": 0}"#),
            StrokeError::MixedTime {
                stroke: 0,
                sample: 1,
            },
        ),
        (
            r#"{"format": "kansei-curve", "version": 1, "units": "mm", "strokes": []}"#.into(),
            StrokeError::WrongFormat {
                found: "kansei-curve".into(),
            },
        ),
        (
            r#"{"format": "kansei-stroke", "version": 2, "units": "mm", "strokes": []}"#.into(),
            StrokeError::WrongVersion { found: 2 },
        ),
    ];
    for (text, expected) in cases {
        assert_eq!(
            StrokeFile::from_json(&text),
            Err(expected.clone()),
            "input {text:?}"
        );
        assert!(!expected.to_string().is_empty());
    }
}

#[test]
fn malformed_json_and_non_numbers_report_line_and_column() {
    for text in [
        "{\"format\": \"kansei-stroke\",",
        &doc(r#"{"x": NaN, "y": 0}, {"x": 1, "y": 0}"#),
        &doc(r#"{"x": 1e999, "y": 0}, {"x": 1, "y": 0}"#),
        &doc(r#"{"x": "one", "y": 0}, {"x": 1, "y": 0}"#),
        &doc(r#"{"y": 0}, {"x": 1, "y": 0}"#),
        r#"{"format": "kansei-stroke", "version": 1, "units": "furlongs", "strokes": []}"#,
    ] {
        match StrokeFile::from_json(text) {
            Err(StrokeError::Json { line, column, .. }) => assert!(line >= 1 && column >= 1),
            other => panic!("{text:?}: expected a JSON error, got {other:?}"),
        }
    }
}

#[test]
fn bad_values_in_a_file_name_their_stroke_sample_and_field() {
    let two = |second: &str| {
        format!(
            r#"{{"format": "kansei-stroke", "version": 1, "units": "mm", "strokes": [
{{"samples": [{{"x": 0, "y": 0}}, {{"x": 1, "y": 0}}]}},
{{"samples": [{{"x": 0, "y": 0, "t": 0.0}}, {second}]}}]}}"#
        )
    };
    for (second, field) in [
        // 1e999 is JSON's infinity (out of f64's range); NaN and Infinity are not JSON at all.
        (r#"{"x": 1e999, "y": 0}"#, Some("x")),
        (r#"{"x": 1, "y": -1e999}"#, Some("y")),
        (r#"{"x": 1, "y": 0, "t": NaN}"#, Some("t")),
        (
            r#"{"x": 1, "y": 0, "pressure": Infinity}"#,
            Some("pressure"),
        ),
        (r#"{"x": "one", "y": 0}"#, Some("x")),
        // A missing field is named by serde_json's message, not by the place.
        (r#"{"y": 0}"#, None),
    ] {
        let text = two(second);
        match StrokeFile::from_json(&text) {
            Err(e @ StrokeError::Json { place: Some(_), .. }) => {
                let StrokeError::Json {
                    place: Some(place), ..
                } = &e
                else {
                    unreachable!()
                };
                assert_eq!((place.stroke, place.sample), (1, Some(1)), "{second}");
                assert_eq!(place.field.as_deref(), field, "{second}");
                let message = e.to_string();
                assert!(message.starts_with("stroke 1, sample 1"), "{message}");
            }
            other => panic!("{second}: expected a placed JSON error, got {other:?}"),
        }
    }
    // Outside the strokes there is no place to name.
    let header = r#"{"format": "kansei-stroke", "version": 1e999, "strokes": []}"#;
    assert!(matches!(
        StrokeFile::from_json(header),
        Err(StrokeError::Json { place: None, .. })
    ));
}

#[test]
fn a_stroke_too_small_for_its_coordinates_is_a_dot_or_refused_with_its_size() {
    // 50 samples a tenth of a micrometre apart at 10⁹ mm: a few dozen rounding steps wide.
    let far = |offset: f64, spacing: f64| {
        Stroke::from_points(
            (0..50).map(|i| kansei::geom::Point::new(offset + spacing * f64::from(i), offset)),
        )
    };
    let stroke = far(9.99e8, 1e-7);
    assert!(stroke.validate(0).is_ok(), "valid data");
    match stroke.check_resolvable(0) {
        Err(
            e @ StrokeError::Unresolvable {
                stroke: 0,
                extent,
                magnitude,
            },
        ) => {
            assert!((extent - 4.9e-6).abs() < 1e-6 && (magnitude - 9.99e8).abs() < 1.0);
            assert!(e.to_string().contains("nearer the origin"), "{e}");
        }
        other => panic!("expected an unresolvable stroke, got {other:?}"),
    }
    // At the default 0.1 mm its 4.9 µm are a dot, within the tolerance of one point.
    let file = StrokeFile::new(Units::Mm, vec![stroke.clone()]);
    let out = fit_file(&file, &PipelineOptions::default()).expect("fits");
    assert_eq!((out.curves.len(), out.dots.len()), (0, 1));
    assert!(out.dots[0].max_deviation < 1e-5);
    // At a tolerance finer than its extent it would be a curve f64 cannot resolve: an input
    // error naming its size, in the output, not a failed file.
    let out = fit_file(&file, &PipelineOptions::default().with_tolerance(1e-7)).expect("fits");
    assert_eq!(out.failures.len(), 1);
    assert!(out.failures[0].message.contains("nearer the origin"));
    // The same drawing at the origin, or spanning 0.1 mm there, is fine.
    assert!(far(0.0, 1e-7).check_resolvable(0).is_ok());
    assert!(far(9.99e8, 2e-3).check_resolvable(0).is_ok());
}

#[test]
fn a_tap_is_a_dot_and_costs_no_other_stroke() {
    // The dot of an "i" between two letters, a tap with its tremor, and a stroke that breaks a
    // rule: every stroke is accounted for, in order.
    let line =
        |y: f64| Stroke::from_points((0..20).map(|i| kansei::geom::Point::new(f64::from(i), y)));
    let tap = Stroke::from_points([kansei::geom::Point::new(5.0, 9.0); 3]);
    let tremor = Stroke::from_points(
        [(5.0, 5.0), (5.02, 5.0), (5.0, 4.97), (5.01, 5.01)]
            .map(|(x, y)| kansei::geom::Point::new(x, y)),
    );
    let bad = Stroke::new(vec![
        Sample::new(0.0, 0.0).with_pressure(2.0),
        Sample::new(1.0, 0.0),
    ]);
    let file = StrokeFile::new(Units::Mm, vec![line(0.0), tap, bad, tremor, line(3.0)]);
    let out = fit_file(&file, &PipelineOptions::default()).expect("fits");
    let strokes = |v: Vec<usize>| v;
    assert_eq!(strokes(out.dots.iter().map(|d| d.stroke).collect()), [1, 3]);
    assert_eq!(out.dots[0].point, kansei::geom::Point::new(5.0, 9.0));
    assert_eq!(out.dots[0].samples, (0, 2));
    assert!((out.dots[1].point - kansei::geom::Point::new(5.01, 4.99)).hypot() < 1e-12);
    assert!(out.dots[1].max_deviation <= 0.1);
    assert_eq!(out.failures.len(), 1);
    assert_eq!(out.failures[0].stroke, 2);
    assert_eq!(out.failures[0].kind, kansei::pipeline::FailureKind::Input);
    assert!(
        out.failures[0].message.contains("sample 0: pressure 2"),
        "{}",
        out.failures[0].message
    );
    let mut fitted: Vec<usize> = out.curves.iter().map(|c| c.stroke).collect();
    fitted.dedup();
    assert_eq!(fitted, [0, 4]);
}

#[test]
fn non_finite_values_built_in_code_are_refused() {
    let stroke = Stroke::new(vec![Sample::new(0.0, 0.0), Sample::new(f64::NAN, 1.0)]);
    let file = StrokeFile::new(Units::Mm, vec![stroke]);
    assert_eq!(
        file.validate().map_err(|e| matches!(
            e,
            StrokeError::NonFinite {
                stroke: 0,
                sample: 1,
                field: "x",
                ..
            }
        )),
        Err(true)
    );
}

#[test]
fn a_hundred_thousand_samples_fit_correctly() {
    // A slowly winding spiral drawn with 100 000 samples: a correct fit, in bounded time.
    let samples: Vec<Sample> = (0..100_000)
        .map(|i| {
            let a = i as f64 * 2e-4;
            let r = 50.0 + 4.0 * a;
            Sample::new(r * a.cos(), r * a.sin()).with_t(i as f64 * 0.005)
        })
        .collect();
    let file = StrokeFile::new(Units::Mm, vec![Stroke::new(samples)]);
    file.validate().expect("valid");
    let out = fit_file(&file, &PipelineOptions::splits_only()).expect("fit");
    assert!(!out.curves.is_empty());
    for c in &out.curves {
        assert!(c.bspline.within_tolerance && c.bspline.max_deviation <= 0.1);
    }
    let covered: usize = out.curves.iter().map(|c| c.samples.1 - c.samples.0).sum();
    assert!(covered >= 99_000, "samples covered {covered}");
}
