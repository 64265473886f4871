//! Output formats. So far: `kansei-curve` v1 JSON ([`CurveFile`]).

mod curve_json;

pub use curve_json::{
    BSplineRecord, CURVE_FORMAT_NAME, CURVE_FORMAT_VERSION, CurveEntry, CurveFile, SplitRecord,
};
