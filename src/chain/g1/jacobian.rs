//! The G1 refinement's Jacobian: each unknown's column from the segments it touches, analytic
//! where the segment's sensitivities allow (tested against forward differences).

#[cfg(test)]
use super::refine::{add, step_of, touched};

use crate::chain::g1::refine::RefineOptions;
use crate::chain::g1::refine::{ALPHA_STEP, ANGLE_STEP, Unknown};
use crate::chain::g1::state::{Evaluated, model_at_feet, model_at_own_feet};
use crate::chain::g1::state::{Joint, State};
use crate::geom::Vec2;
use crate::lac::sensitivity::{Sensitivity, sensitivities};

/// The Jacobian of the residuals, one dense block per segment (rows: its sample residuals then
/// its end anchors; columns: its range of unknowns), at the first-order model of the current
/// state (see [`State::residuals_near`]).
///
/// Only three columns per segment need a construction: its two tangent angles and its α, by
/// forward differences. The four position columns follow from the similarity covariance of the
/// Yoshida–Saito segment. Moving the start A by δ with B and both tangents held splits δ into
/// u along ê = (A − B)/|A − B| and v along n̂ = ê rotated by 90°: the u part scales the segment
/// about B by σ = u/|A − B| (the tangents are unchanged, so the scaled segment is the new one);
/// the v part rotates it about B by ω = v/|A − B|, which also turns both tangents by ω, undone
/// by turning them back by −ω. At a sample row with curve point P and measuring direction d
/// (the first-order model moves the foot along the curve, which leaves the residual unchanged to
/// first order), the column is therefore
///
/// ∂r/∂δ = −(σ·(P − B) + ω·J(P − B))·d − ω·(∂r/∂θ_A + ∂r/∂θ_B),
///
/// J the quarter turn, and likewise for the end B about A. The end anchors (q − A)·T_A are
/// differentiated exactly: −T_A for the position, (q − A)·N_A for the angle. Seven
/// constructions per segment and iteration become three.
pub(super) fn jacobian(
    state: &State<'_>,
    current: &[Evaluated],
    unknowns: &[Unknown],
    ranges: &[std::ops::Range<usize>],
    options: &RefineOptions,
) -> Vec<Vec<f64>> {
    let quarter = |v: Vec2| Vec2::new(-v.y, v.x);
    current
        .iter()
        .enumerate()
        .map(|(k, e)| {
            let range = ranges[k].clone();
            let cols = range.len();
            if cols == 0 {
                // A segment held as it is: no column, nothing to build.
                return Vec::new();
            }
            let column = |u: Unknown| {
                range
                    .clone()
                    .find(|&c| unknowns[c] == u)
                    .map(|c| c - range.start)
            };
            let points = state.points_of(k);
            // The sensitivities, where the log-radius form applies; the model about the feet from
            // the measurement itself then (the difference probes need it recomputed the way
            // their own residuals are, see `State::sample_residuals_with`).
            let sensitivity = sensitivities(&e.segment, &e.feet);
            let model = sensitivity
                .as_ref()
                .and_then(|_| model_at_own_feet(&points, e))
                .unwrap_or_else(|| model_at_feet(&e.segment, &points, e));
            let anchors = state.anchors(k);
            let rows = model.len() + anchors.len();
            let mut block = vec![0.0; rows * cols];
            let (a, b, alpha) = (state.joints[k], state.joints[k + 1], state.alphas[k]);
            // Forward differences of the sample rows (zero where the probe cannot be built).
            let difference = |pa: Joint, pb: Joint, palpha: f64, h: f64| -> Vec<f64> {
                match state.sample_residuals_with(k, &pa, &pb, palpha, e) {
                    Ok(r) => r
                        .iter()
                        .zip(&model)
                        .map(|(r1, m)| (r1 - m.residual) / h)
                        .collect(),
                    Err(_) => vec![0.0; model.len()],
                }
            };
            let alpha_column = column(Unknown::Alpha(k));
            // The two angle columns and the α column: in one pass along the segment where its
            // log-radius form applies, else by differences of probe constructions.
            let (d_theta_a, d_theta_b, d_alpha) = match sensitivity {
                Some(d) => {
                    let rows = |of: fn(&Sensitivity) -> Vec2| -> Vec<f64> {
                        model
                            .iter()
                            .zip(&d)
                            .map(|(m, d)| -of(d).dot(m.direction))
                            .collect()
                    };
                    (
                        rows(|d| d.start_angle),
                        rows(|d| d.end_angle),
                        rows(|d| d.alpha),
                    )
                }
                None => {
                    let turned = |j: Joint| Joint {
                        angle: j.angle + ANGLE_STEP,
                        ..j
                    };
                    let d_alpha = if alpha_column.is_some() {
                        // A step that the range would clip is taken backwards instead.
                        let (lo, hi) = options
                            .alpha_range
                            .unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
                        let h = if alpha + ALPHA_STEP <= hi || alpha - ALPHA_STEP < lo {
                            ALPHA_STEP
                        } else {
                            -ALPHA_STEP
                        };
                        difference(a, b, alpha + h, h)
                    } else {
                        Vec::new()
                    };
                    (
                        difference(turned(a), b, alpha, ANGLE_STEP),
                        difference(a, turned(b), alpha, ANGLE_STEP),
                        d_alpha,
                    )
                }
            };
            let mut put = |col: Option<usize>, values: &[f64]| {
                if let Some(c) = col {
                    for (i, v) in values.iter().enumerate() {
                        block[i * cols + c] = *v;
                    }
                }
            };
            put(column(Unknown::Angle(k)), &d_theta_a);
            put(column(Unknown::Angle(k + 1)), &d_theta_b);
            put(alpha_column, &d_alpha);
            // Positions, from the similarity covariance (see the function doc).
            let length = a.p.distance(b.p);
            if length > 0.0 {
                for (j, moving, pivot) in [(k, a.p, b.p), (k + 1, b.p, a.p)] {
                    let e_hat = (moving - pivot) * (1.0 / length);
                    let n_hat = quarter(e_hat);
                    for (u, delta) in [
                        (Unknown::X(j), Vec2::new(1.0, 0.0)),
                        (Unknown::Y(j), Vec2::new(0.0, 1.0)),
                    ] {
                        let Some(c) = column(u) else {
                            continue;
                        };
                        let sigma = e_hat.dot(delta) / length;
                        let omega = n_hat.dot(delta) / length;
                        for (i, m) in model.iter().enumerate() {
                            let arm = m.point - pivot;
                            let moved = arm * sigma + quarter(arm) * omega;
                            block[i * cols + c] =
                                -moved.dot(m.direction) - omega * (d_theta_a[i] + d_theta_b[i]);
                        }
                    }
                }
            }
            // End anchors: (q − P_j)·T_j.
            for (n, (j, q)) in anchors.iter().enumerate() {
                let row = model.len() + n;
                let joint = state.joints[*j];
                let tangent = joint.tangent();
                let normal = quarter(tangent);
                for (u, value) in [
                    (Unknown::X(*j), -tangent.x),
                    (Unknown::Y(*j), -tangent.y),
                    (Unknown::Angle(*j), (*q - joint.p).dot(normal)),
                ] {
                    if let Some(c) = column(u) {
                        block[row * cols + c] = value;
                    }
                }
            }
            block
        })
        .collect()
}

/// The Jacobian of [`jacobian`] by forward differences in every unknown (each probe builds the
/// segments the unknown moves): the reference the fast form is tested against.
#[cfg(test)]
pub(super) fn jacobian_by_differences(
    state: &State<'_>,
    current: &[Evaluated],
    unknowns: &[Unknown],
    ranges: &[std::ops::Range<usize>],
    options: &RefineOptions,
) -> Vec<Vec<f64>> {
    let mut blocks: Vec<Vec<f64>> = current
        .iter()
        .zip(ranges)
        .map(|(e, r)| vec![0.0; e.residuals.len() * r.len()])
        .collect();
    let base: Vec<Vec<f64>> = current
        .iter()
        .enumerate()
        .map(|(k, e)| state.model_residuals(k, &e.segment, e))
        .collect();
    for (c, &u) in unknowns.iter().enumerate() {
        let h = step_of(u, options);
        let mut probe = state.clone();
        add(&mut probe, u, h, options);
        for k in touched(u, state.len()) {
            let Ok(r) = probe.residuals_near(k, &current[k]) else {
                continue;
            };
            let (cols, col) = (ranges[k].len(), c - ranges[k].start);
            for (i, (r1, r0)) in r.iter().zip(&base[k]).enumerate() {
                blocks[k][i * cols + col] = (r1 - r0) / h;
            }
        }
    }
    blocks
}
