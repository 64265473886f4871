//! Output formats. So far: `kansei-curve` v1 JSON ([`CurveFile`]) and a quick-look SVG
//! ([`quick_look_svg`]).

mod curve_json;
mod svg;

pub use curve_json::{
    BSplineRecord, CURVE_FORMAT_NAME, CURVE_FORMAT_VERSION, ChainRecord, CurveEntry, CurveFile,
    ExportOptions, LCG_POINTS, LcgRecord, SegmentRecord, SplitRecord, pieces_between,
};
pub use svg::{
    ALPHA_BLUE_END, ALPHA_BLUE_RGB, ALPHA_RED_END, ALPHA_RED_RGB, ALPHA_ZERO_RGB,
    LAC_CHORD_ERROR_FRACTION, MAX_POINTS_PER_SEGMENT, MAX_TURNING_PER_STEP, NO_ALPHA_RGB,
    SvgLayers, SvgOptions, alpha_colour, lac_spacing, quick_look_svg,
};
