//! Why a split can fail.

use thiserror::Error;

/// Errors of [`split_spans`](super::split_spans). Every variant names the offending piece by its
/// index in the input slice.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum SplitError {
    /// No Bézier pieces were given.
    #[error("no Bézier pieces to split")]
    Empty,
    /// A control point or a parameter bound is NaN or infinite.
    #[error("piece {piece}: non-finite control point or parameter")]
    NonFinite {
        /// Index of the piece.
        piece: usize,
    },
    /// A piece's parameter range is empty or reversed (`u1 ≤ u0`).
    #[error("piece {piece}: parameter range [{u0}, {u1}] is empty or reversed")]
    EmptyParameterRange {
        /// Index of the piece.
        piece: usize,
        /// Its `u0`.
        u0: f64,
        /// Its `u1`.
        u1: f64,
    },
    /// Piece `piece` does not start where piece `piece − 1` ends: their parameters differ by more
    /// than the joint tolerance ([`SplitOptions::joint_tolerance`](super::SplitOptions::joint_tolerance)
    /// times the total parameter range).
    #[error("piece {piece}: starts at u = {u0} but the previous piece ends at u = {previous_u1}")]
    ParameterGap {
        /// Index of the later piece.
        piece: usize,
        /// `u1` of the previous piece.
        previous_u1: f64,
        /// `u0` of this piece.
        u0: f64,
    },
    /// Piece `piece` does not start at the point where piece `piece − 1` ends (distance larger
    /// than `POSITION_GAP_RELATIVE` times the control points' bounding-box diagonal).
    #[error("piece {piece}: starts {distance} away from the end of the previous piece")]
    PositionGap {
        /// Index of the later piece.
        piece: usize,
        /// Distance between the previous end point and this start point.
        distance: f64,
    },
    /// A piece is not a regular curve: its speed vanishes (a cusp, coincident control points)
    /// somewhere, so its curvature is undefined. Split such strokes at corners first.
    #[error(
        "piece {piece}: speed vanishes (cusp or coincident control points); curvature undefined"
    )]
    Singular {
        /// Index of the piece.
        piece: usize,
    },
    /// An option is out of its documented range.
    #[error("option {name} = {value} is out of range ({expected})")]
    InvalidOption {
        /// The option's field name.
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// The accepted range, in words.
        expected: &'static str,
    },
}
