//! Output formats: `kansei-curve` v1 JSON ([`CurveFile`], documented by a JSON Schema in
//! [`CURVE_SCHEMA_V1`]), SVG ([`svg_document`]) and DXF ([`dxf_drawing`]), the latter two
//! through cubic Béziers within a stated error of the exact LAC chain ([`segment_beziers`]).
//!
//! [`Format`] is the one dispatch over them and the PNG ([`crate::render`]): a fit and its
//! [`FormatOptions`] in, the file's bytes out. The command line, the app and the service all
//! write through it.

mod bezier;
mod curve_json;
mod dxf;
mod format;
mod schema;
mod svg;

pub use bezier::{
    ACCURACY_FLOOR_ULPS, CHECK_POINTS_PER_CUBIC, COARSENING_FACTOR, DEFAULT_ACCURACY_FRACTION,
    FALLBACK_ACCURACY_FRACTION, LacCurve, MAX_COARSENINGS, MAX_FIT_STEPS_PER_SEGMENT,
    MAX_PARTS_PER_SEGMENT, MAX_SPLIT_DEPTH, MAX_TURNING_PER_PART, REFERENCE_CHORD_FRACTION,
    SegmentBeziers, bezier_error, segment_beziers,
};
pub use curve_json::{
    BSplineRecord, CURVE_FORMAT_NAME, CURVE_FORMAT_VERSION, ChainRecord, CurveEntry, CurveFile,
    CurveFormatError, DotRecord, ErrorRecord, ExportOptions, JointContinuity, JointRecord,
    LCG_POINTS, LcgRecord, SUPPORTED_CURVE_VERSIONS, SegmentRecord, SplitRecord, pieces_between,
    relative_jump,
};
pub use dxf::{
    C2_CHECKS_PER_SPAN, C2_CHORD_FRACTION, C2_FIT_FRACTION, C2_MAX_POINTS, DxfExport, DxfOptions,
    DxfSplineReport, DxfWriteError, SplineForm, bezier_chain_spline, c2_spline, dxf_drawing,
    dxf_units,
};
pub use format::{
    AccuracyReport, DEFAULT_PNG_SIZE, EmptyDrawing, Exported, Format, FormatError, FormatOptions,
    JsonLayout, PngOptions,
};
pub use schema::{CURVE_SCHEMA_V1, STROKE_SCHEMA_V1};
pub use svg::{
    ALPHA_BLUE_END, ALPHA_BLUE_RGB, ALPHA_RED_END, ALPHA_RED_RGB, ALPHA_ZERO_RGB,
    ARC_AS_LINE_FRACTION, LAC_CHORD_ERROR_FRACTION, MAX_ARC_TURNING, MAX_POINTS_PER_SEGMENT,
    MAX_TURNING_PER_STEP, NO_ALPHA_RGB, SVG_METADATA_NAMESPACE, SvgElement, SvgExport, SvgLayers,
    SvgOptions, SvgPathReport, SvgPieceReport, SvgSegmentReport, alpha_colour, chain_path_data,
    export_accuracy, lac_spacing, svg_document,
};
