//! Split candidates: every point where `|κ|` can stop being monotonic or κ can change sign.

use super::curvature::PieceCurvature;
use super::poly::MAX_DEGREE;
use crate::geom::ParamBez;

/// A split candidate (and, after simplification, a split point).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Node {
    /// Global parameter.
    pub u: f64,
    /// Index of the piece the node is evaluated on.
    pub piece: usize,
    /// Local parameter on that piece (`0` only for the curve's start; a joint is `t = 1` of the
    /// earlier piece).
    pub t: f64,
    /// Signed curvature there.
    pub kappa: f64,
}

impl Node {
    /// `|κ|`.
    pub(crate) fn magnitude(&self) -> f64 {
        self.kappa.abs()
    }
}

/// The candidates of the whole chain, in increasing `u`: the start, every sign-changing root of
/// `γ` (inflections) and of `h` (curvature extrema) strictly inside each piece, every joint, and
/// the end.
///
/// Between two consecutive candidates κ has one sign and `|κ|` is monotonic (no root of `γ` or `h`
/// lies between them), so whether a candidate is an extremum of `|κ|` is decided by comparing its
/// `|κ|` with its neighbours'. In particular a joint is a curvature extremum exactly when
/// `d|κ|/du` changes sign across it, even though a C2 spline's `dκ/du` may jump there, and no
/// derivative at the joint is needed.
///
/// Roots within `u_tolerance` of a joint (or of the ends) are merged into it, and roots within
/// `u_tolerance` of the previous candidate into that one, so a root found at `t ≈ 1` of one piece
/// and `t ≈ 0` of the next yields one split. At a joint κ is the mean of the two one-sided values
/// (equal up to rounding for a C2 spline).
pub(crate) fn candidates(
    pieces: &[ParamBez],
    curvatures: &[PieceCurvature],
    u_tolerance: f64,
) -> Vec<Node> {
    let mut nodes = Vec::with_capacity(pieces.len() * (MAX_DEGREE + 2) + 1);
    for (i, (piece, curvature)) in pieces.iter().zip(curvatures).enumerate() {
        if i == 0 {
            nodes.push(Node {
                u: piece.u0,
                piece: 0,
                t: 0.0,
                kappa: curvature.kappa(0.0),
            });
        }
        let du = piece.u1 - piece.u0;
        let inflections = curvature.inflections();
        let extrema = curvature.extrema();
        let (mut a, mut b) = (
            inflections.crossings().peekable(),
            extrema.crossings().peekable(),
        );
        // Merge the two ascending lists.
        loop {
            let t = match (a.peek(), b.peek()) {
                (Some(&x), Some(&y)) if x <= y => a.next(),
                (Some(_), Some(_)) => b.next(),
                (Some(_), None) => a.next(),
                (None, Some(_)) => b.next(),
                (None, None) => None,
            };
            let Some(t) = t else { break };
            let near_start = t * du <= u_tolerance;
            let near_end = (1.0 - t) * du <= u_tolerance;
            let u = piece.global(t);
            let near_previous = nodes.last().is_some_and(|n: &Node| u - n.u <= u_tolerance);
            if !(near_start || near_end || near_previous) {
                nodes.push(Node {
                    u,
                    piece: i,
                    t,
                    kappa: curvature.kappa(t),
                });
            }
        }
        let kappa = match curvatures.get(i + 1) {
            Some(next) => 0.5 * (curvature.kappa(1.0) + next.kappa(0.0)),
            None => curvature.kappa(1.0),
        };
        nodes.push(Node {
            u: piece.u1,
            piece: i,
            t: 1.0,
            kappa,
        });
    }
    nodes
}
