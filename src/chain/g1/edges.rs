//! The drawable region's edges as linear constraints on a refinement step: a segment that left
//! the region is held inside it by the nearest step (in the normal matrix's metric) that keeps
//! every margin.

use crate::chain::g1::refine::{
    ALPHA_STEP, ANGLE_STEP, EDGE_MARGIN, MARGIN_POSITION_STEP, Unknown,
};
use crate::chain::g1::state::{Joint, State};
use crate::chain::solve::band::BandCholesky;
use crate::lac::yoshida_saito::{edge_margins, mirror};

/// One edge of a segment's drawable region, held: the linearised constraint m + ∇m·δ ≥ target
/// on the step δ, with m the edge's margin at the iterate (see [`edge_margins`]).
///
/// Without it, a segment at the edge of its region (where the α search or an earlier step often
/// leaves it: the data want an α beyond the edge) blocks the whole chain: the Gauss–Newton step
/// points outside, and so does every damped step, which only shrinks it. Held, the step slides
/// along the edge instead. Both edges of the region are held, in the mirror frame of the
/// iterate: a near-straight segment's region is a wedge narrower than a step, and one edge alone
/// let the step leave through the other or through the apex.
#[derive(Clone, Debug)]
pub(super) struct EdgeConstraint {
    /// Margin at the iterate.
    pub(super) margin: f64,
    /// The margin the step must keep: min(m, max(m/2, [`EDGE_MARGIN`])).
    pub(super) target: f64,
    /// ∂m/∂x over the segment's unknowns: (unknown index, value).
    pub(super) gradient: Vec<(usize, f64)>,
}

impl EdgeConstraint {
    /// The two edge constraints of segment `k` at `state` (forward differences of the margins
    /// over the unknowns in `range`); `None` where the margins are undefined.
    pub(super) fn at(
        state: &State<'_>,
        k: usize,
        unknowns: &[Unknown],
        range: &std::ops::Range<usize>,
    ) -> Option<[Self; 2]> {
        let (a, b, alpha) = (
            *state.joints.get(k)?,
            *state.joints.get(k + 1)?,
            *state.alphas.get(k)?,
        );
        let sigma = mirror(a.p, a.tangent(), b.p, b.tangent())?;
        let margins = |a: Joint, b: Joint, alpha: f64| {
            edge_margins(a.p, a.tangent(), b.p, b.tangent(), alpha, sigma)
        };
        let at = margins(a, b, alpha)?;
        let h_position = MARGIN_POSITION_STEP * a.p.distance(b.p);
        let mut gradients = [
            Vec::with_capacity(range.len()),
            Vec::with_capacity(range.len()),
        ];
        for c in range.clone() {
            let (mut pa, mut pb, mut palpha) = (a, b, alpha);
            let h = match unknowns[c] {
                Unknown::X(j) | Unknown::Y(j) => {
                    let joint = if j == k { &mut pa } else { &mut pb };
                    match unknowns[c] {
                        Unknown::X(_) => joint.p.x += h_position,
                        _ => joint.p.y += h_position,
                    }
                    h_position
                }
                Unknown::Angle(j) => {
                    let joint = if j == k { &mut pa } else { &mut pb };
                    joint.angle += ANGLE_STEP;
                    ANGLE_STEP
                }
                Unknown::Alpha(_) => {
                    palpha += ALPHA_STEP;
                    ALPHA_STEP
                }
            };
            let moved = margins(pa, pb, palpha)?;
            for (g, (m1, m0)) in gradients.iter_mut().zip(moved.iter().zip(&at)) {
                g.push((c, (m1 - m0) / h));
            }
        }
        let [g0, g1] = gradients;
        let edge = |margin: f64, gradient| EdgeConstraint {
            margin,
            target: margin.min((0.5 * margin).max(EDGE_MARGIN)),
            gradient,
        };
        Some([edge(at[0], g0), edge(at[1], g1)])
    }

    /// The linearised margin after the step x ← x − `delta`, less the target.
    pub(super) fn slack(&self, delta: &[f64]) -> f64 {
        let change: f64 = self.gradient.iter().map(|&(c, g)| -g * delta[c]).sum();
        self.margin + change - self.target
    }
}

/// The damped step `delta` (applied as x ← x − δ) of the system `a`, moved to the nearest step in
/// `a`'s metric that keeps every constraint's slack ≥ 0: δ' = δ − Σ μᵢ·a⁻¹∇mᵢ with μ ≥ 0 from the
/// active constraints' normal equations (an active set grown by the violated constraints, and
/// shrunk by those whose multiplier turns negative). `None` if a solve fails.
pub(super) fn keep_inside(
    a: &BandCholesky,
    delta: Vec<f64>,
    edges: &[EdgeConstraint],
) -> Option<Vec<f64>> {
    if edges.iter().all(|e| e.slack(&delta) >= 0.0) {
        return Some(delta);
    }
    let n = delta.len();
    let dense = |e: &EdgeConstraint| {
        let mut g = vec![0.0; n];
        for &(c, v) in &e.gradient {
            g[c] = v;
        }
        g
    };
    // a⁻¹∇mᵢ for every constraint (few: the segments held at an edge).
    let inverse: Vec<Vec<f64>> = edges.iter().map(|e| a.solve(&dense(e))).collect();
    let mut active: Vec<usize> = Vec::new();
    let mut result = delta.clone();
    for _ in 0..=2 * edges.len() {
        let violated: Vec<usize> = (0..edges.len())
            .filter(|&i| !active.contains(&i) && edges[i].slack(&result) < 0.0)
            .collect();
        if violated.is_empty() {
            break;
        }
        active.extend(violated);
        loop {
            // Slack after δ − Σ μⱼ·vⱼ is slackᵢ(δ) + Σ μⱼ·∇mᵢ·vⱼ: solve for zero slack.
            let m = active.len();
            let matrix = nalgebra::DMatrix::from_fn(m, m, |i, j| {
                edges[active[i]]
                    .gradient
                    .iter()
                    .map(|&(c, g)| g * inverse[active[j]][c])
                    .sum::<f64>()
            });
            let rhs = nalgebra::DVector::from_fn(m, |i, _| -edges[active[i]].slack(&delta));
            let mu = matrix.lu().solve(&rhs)?;
            if let Some(negative) = (0..m).find(|&i| mu[i] < 0.0) {
                active.remove(negative);
                if active.is_empty() {
                    result = delta.clone();
                    break;
                }
                continue;
            }
            result = delta.clone();
            for (i, &e) in active.iter().enumerate() {
                for (r, v) in result.iter_mut().zip(&inverse[e]) {
                    *r -= mu[i] * v;
                }
            }
            break;
        }
    }
    Some(result)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chain::solve::band::Band;

    /// A symmetric positive definite band matrix (diagonally dominant), pseudo-random.
    fn random_band(n: usize, p: usize, seed: &mut u64) -> Band {
        let mut next = || {
            *seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (*seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut a = Band::zeros(n, p);
        for i in 0..n {
            a.add(i, i, 2.0 * p as f64 + 1.0 + next());
            for j in i.saturating_sub(p)..i {
                a.add(i, j, next());
            }
        }
        a
    }

    /// (x − y)ᵀA(x − y).
    fn metric(a: &Band, x: &[f64], y: &[f64]) -> f64 {
        let d: Vec<f64> = x.iter().zip(y).map(|(x, y)| x - y).collect();
        (0..d.len())
            .map(|i| (0..d.len()).map(|j| d[i] * a.get(i, j) * d[j]).sum::<f64>())
            .sum()
    }

    #[test]
    fn a_held_step_keeps_every_margin_and_is_the_nearest_such_step() {
        let mut seed = 7u64;
        for case in 0..20 {
            let (n, p) = (11, 3);
            let a = random_band(n, p, &mut seed);
            let delta: Vec<f64> = (0..n).map(|i| ((i * 7 + case) % 5) as f64 - 2.0).collect();
            // Two constraints over overlapping blocks; the second is violated only in some cases.
            let edges = vec![
                EdgeConstraint {
                    margin: 0.01,
                    target: 0.005,
                    gradient: vec![(2, 1.0), (3, -0.5), (4, 0.25)],
                },
                EdgeConstraint {
                    margin: 0.3,
                    target: 0.15,
                    gradient: vec![(4, -0.2), (5, 1.0 - 0.1 * case as f64), (6, 0.4)],
                },
            ];
            let factor = a.factor().expect("positive definite");
            let out = keep_inside(&factor, delta.clone(), &edges).expect("solvable");
            for e in &edges {
                assert!(
                    e.slack(&out) >= -1e-12,
                    "case {case}: slack {}",
                    e.slack(&out)
                );
            }
            if edges.iter().all(|e| e.slack(&delta) >= 0.0) {
                assert_eq!(out, delta);
                continue;
            }
            // No feasible step nearby is closer to the free one in the system's metric.
            let best = metric(&a, &out, &delta);
            for t in 0..200 {
                let y: Vec<f64> = out
                    .iter()
                    .enumerate()
                    .map(|(i, v)| v + 1e-3 * (((i * 31 + t * 17) % 13) as f64 - 6.0))
                    .collect();
                if edges.iter().all(|e| e.slack(&y) >= 0.0) {
                    assert!(metric(&a, &y, &delta) >= best - 1e-12, "case {case}");
                }
            }
        }
    }
}
