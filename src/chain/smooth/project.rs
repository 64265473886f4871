//! Projection onto the constraints: least-norm Newton steps that bring a trial chain back onto
//! its joint equations (and C3's dκ/ds equations), with the constraints ordered along the chain.

use super::END_TOLERANCE;
use super::jacobian::{ConstraintJacobian, constraint_jacobian};
use super::layout::{Form, Layout, Params, step_by};
use super::lm::{FRESH_REUSE_RATE, PROJECTION_STEPS, TRIAL_PROJECTION_STEPS};
use super::normal::positions;
use super::solver::Solver;
use crate::chain::solve::band::{Band, BandCholesky};
use crate::lac::LacSegment;
use nalgebra::DVector;

/// Projects `x` onto the constraints of `form` by least-norm Newton steps; returns the chain
/// there, or `None` when the steps do not meet the constraints.
///
/// With `chord`, the constraint Jacobian of the point a trial stepped from, factored once
/// ([`LeastNorm`]; `Some(None)` where it is singular, and the projection fails), is used
/// throughout (a chord method: a damped step away, it converges in two or three steps without
/// differencing the chain again; the trials of one iteration share the factor). Where it does
/// not converge, the fit projects the trial again without
/// `chord` (fresh Jacobians, a construction per unknown each) before refusing it: that gives
/// fewer segments in about the same time; measured in
/// `docs/performance-history.md` (chain constants).
pub(super) fn project(
    form: Form,
    solver: &Solver,
    layout: &Layout,
    x: &mut Params,
    c3_joints: &[usize],
    chord: Option<Option<&LeastNorm>>,
) -> Option<Vec<LacSegment>> {
    let vars = layout.vars_of(form);
    let n = layout.n();
    let rows = constraint_order(form, n, solver.c3, c3_joints, x.seam_rows(solver.c3));
    // A chain in the shooting form (the start, every trial) need meet the joints only well
    // within the tolerance; the fit's answer is laid out forward exactly at the end (see
    // [`TRIAL_GAP_TOLERANCES`]).
    let slack = match form {
        Form::Shooting => solver.trial_slack,
        Form::Forward => 1.0,
    };
    let newton = |x: &mut Params,
                  fixed: Option<Option<&LeastNorm>>,
                  steps: usize|
     -> Option<Vec<LacSegment>> {
        let chord = match fixed {
            Some(factor) => Some(factor?),
            None => None,
        };
        let mut previous: Option<f64> = None;
        // In the fresh mode, the last Jacobian's factor and whether it is still contracting.
        let mut kept: Option<LeastNorm> = None;
        for step in 0..=steps {
            layout.clamp(x, solver.log_kappa);
            let segments = layout.build_form(form, x).ok()?;
            if layout.winds(&segments) {
                return None;
            }
            let c = solver.constraints(form, &segments, x, c3_joints);
            if solver.constraints_met(form, n, &c, slack) {
                return Some(segments);
            }
            // The chord steps converge linearly: at the rate seen so far, would the steps
            // left reach the constraints? If not, refuse the trial now rather than after
            // every step.
            let size = c.amax();
            if fixed.is_some()
                && let Some(before) = previous
            {
                let rate = size / before;
                if !(rate < 1.0 && size * rate.powf((steps - step) as f64) <= slack * END_TOLERANCE)
                {
                    return None;
                }
            }
            // A fresh Jacobian is kept while its steps contract fast (Shamanskii's variant of
            // Newton): each new one costs a construction per unknown.
            if fixed.is_none()
                && let Some(before) = previous
                && !(size <= FRESH_REUSE_RATE * before)
            {
                kept = None;
            }
            previous = Some(size);
            let step = match (chord, &kept) {
                (Some(chord), _) => chord.step(&c)?,
                (None, Some(factor)) => factor.step(&c)?,
                (None, _) => {
                    let mut jc =
                        constraint_jacobian(form, solver, layout, x, &segments, &vars, c3_joints)?;
                    // Unknowns on a bound stay there: a step the clamp would cut short
                    // turns Newton's quadratic convergence into a crawl.
                    for (i, &var) in vars.iter().enumerate() {
                        if solver.frozen(var, n)
                            || layout.pushed_beyond(var, x, 1.0, solver.log_kappa)
                            || layout.pushed_beyond(var, x, -1.0, solver.log_kappa)
                        {
                            jc.clear_column(i);
                        }
                    }
                    let factor = LeastNorm::new(&jc, &rows)?;
                    let step = factor.step(&c)?;
                    kept = Some(factor);
                    step
                }
            };
            *x = step_by(layout, x, &vars, &step);
        }
        None
    };
    match chord {
        Some(_) => newton(x, chord, TRIAL_PROJECTION_STEPS),
        None => newton(x, None, PROJECTION_STEPS),
    }
}

/// Where each constraint row of `form` goes in an order along the chain (see [`band_order`]);
/// `seam_rows`: the closed chain's rows after the C3 rows ([`Params::seam_rows`]).
pub(super) fn constraint_order(
    form: Form,
    n: usize,
    c3: bool,
    c3_joints: &[usize],
    seam_rows: usize,
) -> Vec<usize> {
    let joint_rows = match form {
        Form::Shooting => 3 * n.saturating_sub(1),
        Form::Forward => 0,
    };
    let nc = 2 + joint_rows + if c3 { c3_joints.len() } else { 0 } + seam_rows;
    positions(
        (0..nc)
            .map(|r| (constraint_key(r, n, joint_rows, c3_joints), r))
            .collect(),
    )
}

/// A constraint row's place along the chain: the end point's (and the end angle's, the last
/// row) after every joint, a joint's equations (position, tangent, C3) at the joint.
pub(super) fn constraint_key(r: usize, n: usize, joint_rows: usize, c3_joints: &[usize]) -> f64 {
    if r < 2 {
        n as f64
    } else if r < 2 + joint_rows {
        (1 + (r - 2) / 3) as f64 - 0.1
    } else {
        c3_joints
            .get(r - 2 - joint_rows)
            .map_or(n as f64, |&j| j as f64 - 0.1)
    }
}

/// Least-norm steps −Jᵀ(JJᵀ)⁻¹c onto linearised constraints J·δ = −c, J factored once. Ordered
/// along the chain ([`constraint_order`]), the Gram matrix JJᵀ is a band (two joints' equations
/// share unknowns only where they are neighbours): it is assembled from each column's few
/// nonzero rows and factored by [`Band`]'s Cholesky, where a dense product and factor cost
/// O(rows²·unknowns).
pub(super) struct LeastNorm {
    /// Per unknown: its nonzero rows (in the band order) and entries.
    pub(super) columns: Vec<Vec<(usize, f64)>>,
    /// Each constraint row's place in the band order.
    pub(super) rows: Vec<usize>,
    pub(super) gram: BandCholesky,
}

impl LeastNorm {
    /// `None` where JJᵀ is singular or the sizes differ. A constraint no unknown moves (one among
    /// held segments, see [`Solver::window`], met already) gets a unit diagonal: its multiplier
    /// moves nothing.
    pub(super) fn new(jc: &ConstraintJacobian, rows: &[usize]) -> Option<Self> {
        let nc = jc.nrows();
        if rows.len() != nc {
            return None;
        }
        let columns: Vec<Vec<(usize, f64)>> = (0..jc.ncols())
            .map(|j| jc.column(j).iter().map(|&(r, v)| (rows[r], v)).collect())
            .collect();
        let width = columns
            .iter()
            .map(|col| {
                let lo = col.iter().map(|&(p, _)| p).min().unwrap_or(0);
                let hi = col.iter().map(|&(p, _)| p).max().unwrap_or(0);
                hi - lo
            })
            .max()
            .unwrap_or(0);
        let mut gram = Band::zeros(nc, width);
        for col in &columns {
            for (a, &(p, u)) in col.iter().enumerate() {
                for &(q, v) in &col[..=a] {
                    gram.add(p, q, u * v);
                }
            }
        }
        let mut moved_by = vec![false; nc];
        for &(p, _) in columns.iter().flatten() {
            moved_by[p] = true;
        }
        for p in (0..nc).filter(|&p| !moved_by[p]) {
            gram.add(p, p, 1.0);
        }
        Some(LeastNorm {
            columns,
            rows: rows.to_vec(),
            gram: gram.factor()?,
        })
    }

    /// The step for the constraint values `c`; `None` where its length differs.
    pub(super) fn step(&self, c: &DVector<f64>) -> Option<DVector<f64>> {
        if c.len() != self.rows.len() {
            return None;
        }
        let mut rhs = vec![0.0; c.len()];
        for (r, &p) in self.rows.iter().enumerate() {
            rhs[p] = c[r];
        }
        let y = self.gram.solve(&rhs);
        Some(DVector::from_iterator(
            self.columns.len(),
            self.columns
                .iter()
                .map(|col| -col.iter().map(|&(p, v)| v * y[p]).sum::<f64>()),
        ))
    }
}
