//! The Jacobians of the residuals and of the joint equations, by differences of the segments an
//! unknown moves.

use super::layout::{Form, Layout, Params, Var, get, perp, restore, set};
use super::solver::{Evaluation, Solver, c3_gap};
use crate::geom::{Point, Vec2};
use crate::lac::LacSegment;

/// Forward-difference step of the unknowns (angles in radians, logs of curvatures and lengths,
/// α): 1e-6 is √ε times the relative accuracy of the evaluation (~1e-12), the step that
/// balances truncation against rounding.
pub(super) const DIFFERENCE_STEP: f64 = 1e-6;

/// The constraints' Jacobian by columns: each unknown's nonzero rows (ascending) and entries.
/// A joint's equations involve the two segments that meet there, so a column of the shooting
/// form is nonzero only in the rows of the joints next to the segments it moves: held dense, a
/// part of 31 segments (92 equations, 186 unknowns) was allocated, zeroed, written and scanned
/// in full at every Jacobian, and its least-norm factor ([`super::lm::LeastNorm`]) scanned it
/// again.
#[derive(Clone, Debug)]
pub(super) struct ConstraintJacobian {
    /// The number of constraints.
    rows: usize,
    /// Per unknown: its nonzero rows, ascending, and their entries.
    columns: Vec<Vec<(usize, f64)>>,
}

impl ConstraintJacobian {
    /// `rows` constraints of `columns` unknowns, all zero.
    pub(super) fn zeros(rows: usize, columns: usize) -> Self {
        ConstraintJacobian {
            rows,
            columns: vec![Vec::new(); columns],
        }
    }

    /// The number of constraints.
    pub(super) fn nrows(&self) -> usize {
        self.rows
    }

    /// The number of unknowns.
    pub(super) fn ncols(&self) -> usize {
        self.columns.len()
    }

    /// Column j's nonzero rows and entries, rows ascending.
    pub(super) fn column(&self, j: usize) -> &[(usize, f64)] {
        &self.columns[j]
    }

    /// Column j set to zero.
    pub(super) fn clear_column(&mut self, j: usize) {
        self.columns[j].clear();
    }

    /// Entry (r, j).
    fn get(&self, r: usize, j: usize) -> f64 {
        self.columns[j]
            .iter()
            .find(|&&(row, _)| row == r)
            .map_or(0.0, |&(_, v)| v)
    }

    /// Entry (r, j) set to `value` (a zero is not stored).
    fn set(&mut self, r: usize, j: usize, value: f64) {
        let column = &mut self.columns[j];
        match column.binary_search_by(|&(row, _)| row.cmp(&r)) {
            Ok(at) if value != 0.0 => column[at].1 = value,
            Ok(at) => {
                column.remove(at);
            }
            Err(at) if value != 0.0 => column.insert(at, (r, value)),
            Err(_) => {}
        }
    }
}

/// The constraints' Jacobian in the forward form at its chain `segments`: a change of one
/// unknown reshapes at most two segments (differenced) and moves every later segment rigidly
/// with the end pose of the last reshaped one, so the chain's end moves by
/// δE + δθ·(Pₑ − E)^⊥ (E, θ that end pose); a C3 gap changes only where a reshaped segment meets
/// it. `None` where a differenced segment cannot be built.
pub(super) fn forward_constraint_jacobian(
    solver: &Solver,
    layout: &Layout,
    x: &Params,
    segments: &[LacSegment],
    vars: &[Var],
    c3_joints: &[usize],
) -> Option<ConstraintJacobian> {
    let n = layout.n();
    let c3_rows = if solver.c3 { c3_joints.len() } else { 0 };
    // At a closed chain's seam the end's angle is the last row: every unknown turns it by the
    // turn of the last segment it reshapes (the rest follow rigidly).
    // A whole closed chain's end angle is measured from its start's (the start angle moves both
    // alike), and its end joint's log-curvature tied to the start's by the row after it.
    let angle_row = (x.end_angle.is_some() || x.seam_turn.is_some()).then_some(2 + c3_rows);
    let tie_row = x.seam_turn.map(|_| 3 + c3_rows);
    let seam_c3_row = (x.seam_rows(solver.c3) == 3).then_some(4 + c3_rows);
    let nc = 2 + c3_rows + x.seam_rows(solver.c3);
    let mut jc = ConstraintJacobian::zeros(nc, vars.len());
    let end = segments[n - 1].end();
    for (col, &var) in vars.iter().enumerate() {
        if var == Var::Theta0 {
            let d = perp(end - x.pose[0].0) / solver.scale;
            jc.set(0, col, d.x);
            jc.set(1, col, d.y);
            if let Some(row) = angle_row.filter(|_| x.seam_turn.is_none()) {
                jc.set(row, col, 1.0);
            }
            continue;
        }
        if let (Some(row), Var::Joint(j)) = (tie_row, var) {
            if j == 0 {
                jc.set(row, col, -1.0);
            } else if j == n {
                jc.set(row, col, 1.0);
            }
        }
        if var == Var::EndShift {
            let d = x.anchors[1].1 / -solver.scale;
            jc.set(0, col, d.x);
            jc.set(1, col, d.y);
            continue;
        }
        let (k0, k1) = layout.reach(var);
        let mut xp = x.clone();
        set(layout, &mut xp, var, get(layout, x, var) + DIFFERENCE_STEP);
        let new = layout.rebuild(&xp, segments, k0, k1).ok()?;
        let last = &new[k1 - k0];
        let old_end = segments[k1].end();
        let d_end = (last.end() - old_end) / DIFFERENCE_STEP;
        let d_theta = (last.theta1() - segments[k1].theta1()) / DIFFERENCE_STEP;
        let d = (d_end + perp(end - old_end) * d_theta) / solver.scale;
        jc.set(0, col, d.x);
        jc.set(1, col, d.y);
        if let Some(row) = angle_row {
            jc.set(row, col, d_theta);
        }
        if solver.c3 {
            let pick = |k: usize| {
                if (k0..=k1).contains(&k) {
                    &new[k - k0]
                } else {
                    &segments[k]
                }
            };
            for (row, &j) in c3_joints.iter().enumerate() {
                if (k0..=k1).contains(&(j - 1)) || (k0..=k1).contains(&j) {
                    let before = c3_gap(&segments[j - 1], &segments[j]);
                    let after = c3_gap(pick(j - 1), pick(j));
                    jc.set(2 + row, col, (after - before) / DIFFERENCE_STEP);
                }
            }
            // Across a whole closed chain's seam: the last segment against the first.
            if let Some(row) = seam_c3_row
                && ((k0..=k1).contains(&0) || (k0..=k1).contains(&(n - 1)))
            {
                let before = c3_gap(&segments[n - 1], &segments[0]);
                let after = c3_gap(pick(n - 1), pick(0));
                jc.set(row, col, (after - before) / DIFFERENCE_STEP);
            }
        }
    }
    Some(jc)
}

/// The residuals' Jacobian, segment by segment: segment k's rows (its samples' residuals) are
/// nonzero only in the columns of the unknowns that reach it ([`Layout::shooting_reach`]), a
/// dozen or so whatever the chain's length, and hold only those. A dense matrix of every
/// sample against every unknown was allocated and zeroed at each Levenberg–Marquardt
/// iteration: on the he2 stroke's part of 31 segments (113 samples, 186 unknowns) about
/// fifteen times the entries used.
pub(super) struct ResidualJacobian<'r> {
    /// Per segment: the columns its rows hold, ascending.
    columns: &'r [Vec<usize>],
    /// Per segment: its rows × its columns, row by row.
    blocks: Vec<Vec<f64>>,
}

impl<'r> ResidualJacobian<'r> {
    /// Zeros for the residuals of `e`, segment k holding `columns[k]`.
    fn zeros(columns: &'r [Vec<usize>], e: &Evaluation) -> Self {
        ResidualJacobian {
            blocks: columns
                .iter()
                .zip(&e.residuals)
                .map(|(c, r)| vec![0.0; c.len() * r.len()])
                .collect(),
            columns,
        }
    }

    /// Where entry (row `m` of segment `k`, column `col`) sits in `blocks[k]`; `None` where the
    /// column does not reach the segment.
    fn at(&self, k: usize, m: usize, col: usize) -> Option<usize> {
        let c = &self.columns[k];
        c.binary_search(&col).ok().map(|i| m * c.len() + i)
    }

    /// Sets entry (row `m` of segment `k`, column `col`) where the column reaches the segment.
    fn set(&mut self, k: usize, m: usize, col: usize, value: f64) {
        if let Some(i) = self.at(k, m, col) {
            self.blocks[k][i] = value;
        }
    }

    /// Entry (row `m` of segment `k`, column `col`): zero where the column does not reach the
    /// segment.
    fn get(&self, k: usize, m: usize, col: usize) -> f64 {
        self.at(k, m, col).map_or(0.0, |i| self.blocks[k][i])
    }

    /// Segment k's columns and its rows, each over those columns.
    pub(super) fn segment(&self, k: usize) -> (&[usize], std::slice::Chunks<'_, f64>) {
        let c = &self.columns[k];
        (c, self.blocks[k].chunks(c.len().max(1)))
    }
}

/// The Jacobians of the residuals and of the constraints in the shooting form: a change of
/// one unknown rebuilds one segment (two for a joint's curvature) from its own start pose; the
/// residual columns are differenced at the samples' feet, the constraint columns by
/// differencing [`Solver::constraints`] with those segments replaced. `reaching[k]`: the
/// unknowns (indices into `vars`, ascending) that reach segment k.
pub(super) fn shooting_jacobian<'r>(
    solver: &Solver,
    layout: &Layout,
    x: &Params,
    e: &Evaluation,
    vars: &[Var],
    c3_joints: &[usize],
    reaching: &'r [Vec<usize>],
) -> Option<(ResidualJacobian<'r>, ConstraintJacobian)> {
    let c0 = solver.constraints(Form::Shooting, &e.segments, x, c3_joints);
    let mut jr = ResidualJacobian::zeros(reaching, e);
    let mut jc = ConstraintJacobian::zeros(c0.len(), vars.len());
    let mut segments = e.segments.clone();
    // Each foot evaluated as the differenced points will be: the stored foot points come from
    // the distance search's own integration, and a difference against them carries the two
    // integrations' disagreement divided by the step (seen: a length's column 2.3 where the
    // scaling identity ∂/∂v = (P − Pₖ) + Σ ∂/∂u, exact for a segment, gave 4.7 from the
    // joints' columns, each off by the same offset).
    let base: Vec<Vec<Point>> = e
        .segments
        .iter()
        .zip(&e.feet)
        .map(|(seg, feet)| {
            let mut out = Vec::new();
            super::solver::points_on(seg, feet, &mut out);
            out
        })
        .collect();
    // Without C3 rows, a length's column follows from the joints' (below): no construction.
    // A seam's held curvature has no column to add: the seam's segments are differenced.
    let n = layout.n();
    let scaled = |var: Var| match var {
        Var::Length(k) => {
            let held = (k == 0 && layout.held(0)) || (k + 1 == n && layout.held(1));
            !(solver.c3 || held)
        }
        _ => false,
    };
    // One moved copy of the unknowns, each column's change undone after it (see [`restore`]),
    // and the feet's and constraints' buffers shared by the columns: a column allocates only
    // its constraint column, at its size.
    let mut xp = x.clone();
    let (mut feet, mut moved, mut c1, mut nonzero) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (col, &var) in vars.iter().enumerate() {
        if scaled(var) {
            continue;
        }
        let (k0, k1) = layout.shooting_reach(var);
        // Outside a local solve's window the column is held at zero (see [`Solver::window`]).
        if solver.frozen(var, layout.n()) && !solver.reaches_window((k0, k1)) {
            continue;
        }
        set(layout, &mut xp, var, get(layout, x, var) + DIFFERENCE_STEP);
        for k in k0..=k1 {
            // A pose moves its segment rigidly, each point by shift + turn·(P − Pₖ)^⊥ per unit
            // of the unknown: no construction, no integration, and exact.
            let rigid = match var {
                Var::X(j) if j == k => Some((Vec2::new(1.0, 0.0), 0.0)),
                Var::Y(j) if j == k => Some((Vec2::new(0.0, 1.0), 0.0)),
                Var::Angle(j) if j == k => Some((Vec2::ZERO, 1.0)),
                Var::StartShift => Some((x.anchors[0].1, 0.0)),
                _ => None,
            };
            let rows = e.foot_points[k].iter().zip(&base[k]).enumerate();
            let seg = if let Some((shift, turn)) = rigid {
                let start = e.segments[k].start();
                for (m, ((_, nrm), f)) in rows {
                    jr.set(k, m, col, -nrm.dot(shift + perp(*f - start) * turn));
                }
                e.segments[k].placed(xp.pose[k].0, xp.pose[k].1)
            } else {
                let seg = layout.segment(&xp, k, xp.pose[k].0, xp.pose[k].1).ok()?;
                let ratio = seg.length() / e.segments[k].length();
                feet.clear();
                feet.extend(e.feet[k].iter().map(|s| s * ratio));
                super::solver::points_on(&seg, &feet, &mut moved);
                for ((m, ((_, nrm), f)), &p) in rows.zip(&moved) {
                    jr.set(k, m, col, -nrm.dot((p - *f) / DIFFERENCE_STEP));
                }
                seg
            };
            segments[k] = seg;
        }
        solver.constraints_into(Form::Shooting, &segments, &xp, c3_joints, &mut c1);
        // Gathered in the shared buffer, then stored at its size (grown by pushes, a column
        // reallocated three or four times).
        nonzero.clear();
        for (r, (after, before)) in c1.iter().zip(c0.as_slice()).enumerate() {
            let d = (after - before) / DIFFERENCE_STEP;
            if d != 0.0 {
                nonzero.push((r, d));
            }
        }
        jc.columns[col] = nonzero.clone();
        segments[k0..=k1].copy_from_slice(&e.segments[k0..=k1]);
        restore(&mut xp, x, var);
    }
    // Lengthening segment k by dv while both its end curvatures shrink by e^{−dv} scales it by
    // e^{dv} about its start (a similarity keeps α): a point at a fixed fraction of the length
    // moves by (P − Pₖ)·dv, the turning not at all. So ∂/∂v = (P − Pₖ) + Σ ∂/∂u over its
    // non-zero end joints, whose columns hold segment k's own rows (its samples, its end's
    // equations) apart from the other segment's.
    for (col, &var) in vars.iter().enumerate() {
        let Var::Length(k) = var else { continue };
        if !scaled(var) {
            continue;
        }
        let joints: Vec<usize> = [k, k + 1]
            .into_iter()
            .filter_map(|j| vars.iter().position(|&v| v == Var::Joint(j)))
            .collect();
        let start = e.segments[k].start();
        for (m, ((_, nrm), f)) in e.foot_points[k].iter().zip(&base[k]).enumerate() {
            let value = -nrm.dot(*f - start) + joints.iter().map(|&j| jr.get(k, m, j)).sum::<f64>();
            jr.set(k, m, col, value);
        }
        let (rx, ry, angle) = end_rows(n, k);
        let lever = (e.segments[k].end() - start) / solver.scale;
        for (row, own) in [(rx, lever.x), (ry, lever.y)] {
            let value = own + joints.iter().map(|&j| jc.get(row, j)).sum::<f64>();
            jc.set(row, col, value);
        }
        // The end's angle row at a closed chain's seam turns with the last segment as a joint's
        // tangent row does (the last row, or the one before a whole closed chain's tie).
        let seam_angle = (k + 1 == n && x.seam_rows(solver.c3) > 0)
            .then(|| 2 + 3 * (n - 1) + c3_joints.len() * usize::from(solver.c3));
        for row in angle.into_iter().chain(seam_angle) {
            let value = joints.iter().map(|&j| jc.get(row, j)).sum::<f64>();
            jc.set(row, col, value);
        }
    }
    Some((jr, jc))
}

/// The rows of segment k's end in the shooting form's constraints ([`Solver::constraints`]):
/// its position equations' two rows and, but for the last segment (whose end is the target
/// point), its tangent equation's row.
pub(super) fn end_rows(n: usize, k: usize) -> (usize, usize, Option<usize>) {
    if k + 1 == n {
        (0, 1, None)
    } else {
        (2 + 3 * k, 3 + 3 * k, Some(4 + 3 * k))
    }
}

/// The constraints' Jacobian alone at the chain `segments` of `x`.
pub(super) fn constraint_jacobian(
    form: Form,
    solver: &Solver,
    layout: &Layout,
    x: &Params,
    segments: &[LacSegment],
    vars: &[Var],
    c3_joints: &[usize],
) -> Option<ConstraintJacobian> {
    match form {
        Form::Shooting => {
            let n = segments.len();
            let e = Evaluation {
                segments: segments.to_vec(),
                residuals: vec![Vec::new(); n],
                feet: vec![Vec::new(); n],
                foot_points: vec![Vec::new(); n],
                cost: 0.0,
            };
            let reaching = vec![Vec::new(); n];
            shooting_jacobian(solver, layout, x, &e, vars, c3_joints, &reaching).map(|(_, jc)| jc)
        }
        Form::Forward => forward_constraint_jacobian(solver, layout, x, segments, vars, c3_joints),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A constraint column keeps its rows ascending, stores no zero, and reads back what was
    /// set.
    #[test]
    fn a_constraint_column_holds_its_nonzero_rows_in_order() {
        let mut jc = ConstraintJacobian::zeros(6, 2);
        jc.set(4, 1, 2.0);
        jc.set(1, 1, -1.0);
        jc.set(3, 1, 0.0);
        jc.set(2, 1, 5.0);
        assert_eq!(jc.column(1), &[(1, -1.0), (2, 5.0), (4, 2.0)]);
        jc.set(2, 1, 0.0);
        assert_eq!(jc.column(1), &[(1, -1.0), (4, 2.0)]);
        assert!(jc.column(0).is_empty());
        jc.clear_column(1);
        assert!(jc.column(1).is_empty());
        assert_eq!((jc.nrows(), jc.ncols()), (6, 2));
    }
}
