//! QuickDraw `.ndjson` drawings.

use kansei::capture::quickdraw::{QuickDrawError, read};
use kansei::stroke::Units;

fn fixture() -> String {
    let path = format!(
        "{}/fixtures/quickdraw/two-drawings.ndjson",
        env!("CARGO_MANIFEST_DIR")
    );
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

#[test]
fn both_forms_are_read_in_order() {
    let file = read(&fixture()).expect("valid");
    assert_eq!(file.units, Units::Px);
    assert_eq!(file.strokes.len(), 3);
    let lens: Vec<usize> = file.strokes.iter().map(|s| s.samples.len()).collect();
    assert_eq!(lens, [8, 5, 6]);
    // Raw form: times in seconds; simplified form: none.
    assert_eq!(file.strokes[0].samples[1].t, Some(0.016));
    assert_eq!(file.strokes[1].samples[0].t, Some(0.4));
    assert!(file.strokes[2].samples.iter().all(|s| s.t.is_none()));
    assert_eq!(
        (file.strokes[2].samples[3].x, file.strokes[2].samples[3].y),
        (120.0, 3.0)
    );
    assert_eq!(file.device, Some(serde_json::json!({ "drawings": [2, 1] })));
}

#[test]
fn bad_lines_name_the_line() {
    let cases = [
        ("", "no drawing"),
        ("{\"drawing\": [[[1, 2], [3]]]}", "line 1, stroke 0"),
        ("{\"drawing\": [[[1, 2]]]}", "line 1"),
        ("{\"word\": \"cat\"}\n", "line 1"),
        (
            "{\"drawing\": [[[0, 1], [0, 1], [5, 4]]]}",
            "time goes backwards",
        ),
        ("not json", "line 1"),
    ];
    for (text, expected) in cases {
        let e = read(text).expect_err(text).to_string();
        assert!(e.contains(expected), "{text:?}: {e}");
    }
    assert!(matches!(read("\n\n"), Err(QuickDrawError::Empty)));
}
