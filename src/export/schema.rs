//! The JSON Schemas (draft 2020-12) of kansei's file formats, checked in beside this file and
//! compiled in, so a program can hand them to a validator or a user.
//!
//! Every fixture stroke file and every fit output is validated against them in
//! `tests/export_fixtures.rs` (`stroke_files_and_fit_outputs_validate_against_the_schemas`,
//! which also checks that the schemas reject broken documents).

/// The JSON Schema of `kansei-stroke` v1 (`src/export/schema/kansei-stroke.v1.schema.json`).
pub const STROKE_SCHEMA_V1: &str = include_str!("schema/kansei-stroke.v1.schema.json");

/// The JSON Schema of `kansei-curve` v1 (`src/export/schema/kansei-curve.v1.schema.json`).
pub const CURVE_SCHEMA_V1: &str = include_str!("schema/kansei-curve.v1.schema.json");
