//! The QP subproblem of the S-l1-QP step (see the sibling `inequality` module): the convex
//! model at an iterate, its QP written with elastic variables and solved by Clarabel, and the
//! screening of the inequality rows far from their limit and of the trust region's box (an
//! active-set loop around the QP that keeps its minimiser exact).

use std::cell::{Cell, RefCell};

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus, SupportedConeT, ZeroConeT,
};
use nalgebra::{DMatrix, DVector};

use crate::planners::optimal::band::{BandCholesky, matvec};
use crate::planners::optimal::discrete::Evaluation;

/// The solution of one QP subproblem.
pub(super) struct Step {
    pub(super) d: DVector<f64>,
    /// Multiplier of the linearised equality.
    pub(super) lambda: f64,
    /// Multipliers of the inequality rows (zero for rows left out).
    pub(super) z: Vec<f64>,
}

/// The QP's data at an iterate: the convex model `W` (with the augmented weight `rho` on
/// `(grad c^T d)^2`), the cost's and the constraints' gradients.
pub(super) struct Model<'a> {
    pub(super) w: DMatrix<f64>,
    pub(super) rho: f64,
    /// Active rows outside the band with their weights `rho_i`: the model's terms
    /// `rho_i (b_i^T d)^2 / 2` (each an extra variable `v_i = b_i^T d`, as the equality's).
    pub(super) dense: Vec<(usize, f64)>,
    /// Whether the QP's `P` takes the model whole, every term in its `d` block (see
    /// [`Model::solve`]); at first the band `w` and the terms on their own variables.
    pub(super) full: Cell<bool>,
    pub(super) hb: usize,
    pub(super) e: &'a Evaluation,
    pub(super) rows: &'a [Vec<(usize, f64)>],
    /// The rows' local forms through a running sum, sent to the QP in place of their dense
    /// gradients ([`super::running`]).
    pub(super) running: Option<&'a super::Running>,
    /// The working set: rows sent to the QP however far from their limit (those found near or
    /// broken by an earlier step of this solve; see [`Model::solve`]).
    pub(super) working: &'a RefCell<Vec<bool>>,
    /// The trust region's working set: the steps' components `d_k` whose box `|d_k| <= radius`
    /// is sent to the QP (those found beyond it by an earlier QP of this solve; see
    /// [`Model::solve`]).
    pub(super) boxed: &'a RefCell<Vec<bool>>,
    /// The solve's last QP solver, the rows it was sent (`2 i + 1` for row `i` with an elastic
    /// variable, `2 i` without) and its box: a QP of the same rows and box (a steering
    /// penalty, a second-order correction, often the next iterate's) updates `P`, `A`, `q` and
    /// `b` in it instead of setting up a solver again (its ordering, symbolic factorisation and
    /// equilibration, a fifth of a QP's time), where the matrices' sparsity is the same (checked
    /// by Clarabel; otherwise a new solver). The equilibration kept from the first data changes
    /// a solution only within Clarabel's tolerance: on issue 20's benches 24 of 46 QPs (3-link
    /// velocity), 42 of 63 (2-link) and 76 of 106 (SPART-like) reuse a solver, to the same
    /// plans, Clarabel's iterations within 0.6 %.
    pub(super) solver: &'a RefCell<Option<Cached>>,
    /// The active-set step's factor and columns, shared by the iterate's QPs
    /// ([`super::active::step`]).
    pub(super) columns: RefCell<super::active::Columns>,
}

/// A QP solver with the rows it was sent and its box's components.
pub(super) type Cached = (Vec<usize>, Vec<bool>, DefaultSolver<f64>, Vec<usize>);

impl Model<'_> {
    /// Solves the S-l1-QP subproblem with the constraints' values `c` and `values` (those at the
    /// iterate, or at a trial point shifted back by its step for the second-order correction);
    /// `None` when Clarabel fails.
    ///
    /// Screening (an active-set outer loop): the QP gets only the rows within [`SCREEN`] of
    /// their limit and the working set's; a row left out whose linearisation the step breaks
    /// joins the working set and the QP is solved again, until the step keeps every row. The
    /// result is the full QP's minimiser: a row left out holds at the step, so with its elastic
    /// variable zero and its multiplier zero the reduced QP's optimality conditions are the full
    /// QP's, and the QP is convex (`inequality` module docs). Rows that cannot become active
    /// inside the trust region (`g_i + |grad g_i|_1 radius < 0`) are never sent.
    ///
    /// The trust region's box `|d_k| <= radius` is screened the same way: its rows are sent
    /// only for the components in [`Model::boxed`] (none at a solve's start), and a step with a
    /// component beyond the radius adds it there and is solved again; the step returned is
    /// inside the whole box, the minimiser of a relaxation that is feasible for the full QP, so
    /// the full QP's. Where the trust region does not bind (the solves' later iterations) the
    /// QP loses a third of its rows: on issue 20's benches Clarabel's iterations 631 -> 558
    /// (3-link velocity) and 617 -> 468 (2-link), the instructions 868 -> 772 M and 350 -> 273 M,
    /// to the same plans (efforts equal to 10 digits on the four plan benches). A QP that fails
    /// without the whole box (unbounded in a direction the model does not curve) is solved with
    /// it.
    ///
    /// Elastic variables only for the rows broken at the iterate (`g_i > 0`): a row that holds
    /// at `d = 0` is sent as a hard row `g_i + grad g_i^T d <= 0`, so the QP stays feasible
    /// (`d = 0` with the equality's slacks) and loses a variable and a cone row per such row.
    /// Where the penalty exceeds the row's multiplier (the exact-penalty condition, which the
    /// steering and the update to twice the multipliers keep) its elastic variable would be zero
    /// at the minimiser, so the step is the same; below it the step keeps the row's
    /// linearisation instead of trading it for the equality. On issue 20's benches (the
    /// plan's instructions per plan) 3-link velocity 399 -> 352 M, with torque 483 -> 414 M,
    /// 2-link 132 -> 113 M, SPART-like 378 -> 376 M, `--time auto` 4428 -> 4186 M, the QPs' and
    /// Clarabel's iterations within 1 %, the efforts equal to 10 digits (`--time auto`'s
    /// 18.0891287310 -> 18.0891287313, the same horizon).
    ///
    /// `P` must be positive semi-definite for Clarabel, and the band `w` with the equality's
    /// term and the dense rows' on their own variables is so only where `w` is: where it is not
    /// (convex only with those terms, `convexify`'s `rho`), the interior point's factorisation
    /// meets negative pivots and fails (Clarabel's `NumericalError` or `InsufficientProgress`).
    /// A QP with dense rows' terms (active base-range rows) that fails so is solved again with
    /// the model whole in `P`'s `d` block (dense, the same QP), for the rest of the iterate's
    /// QPs. Not without them: on issue 20's twenty problems, cases 5 and 6 (velocity limits, the
    /// equality's term only) then failed, where a quarter of the radius after the failure had
    /// led to their plans. Each failure had cost a quarter of the trust
    /// region: on the tests' 3-link arm inside a base range (issue 20) Clarabel failed 276 times
    /// in the plan, the refined solves crept at radii of 1e-3 .. 1e-5 and stalled, and the plan
    /// kept was the 8-span one, of effort 9.3217 against the oracle's 8.1154; with the model
    /// whole none fails and the plan is the 32-span one, of effort 8.1459.
    pub(super) fn solve(&self, c: f64, values: &[f64], mu: f64, radius: f64) -> Option<Step> {
        let reach = |i: usize| self.rows[i].iter().map(|(_, a)| a.abs()).sum::<f64>() * radius;
        let reachable: Vec<bool> = (0..values.len()).map(|i| values[i] + reach(i) >= 0.0).collect();
        let mut working = self.working.borrow_mut();
        working.resize(values.len(), false);
        let mut boxed = self.boxed.borrow_mut();
        loop {
            let sent: Vec<usize> =
                (0..values.len()).filter(|&i| reachable[i] && (working[i] || values[i] >= -SCREEN)).collect();
            let step = match self.solve_rows(c, values, mu, radius, &sent, &boxed) {
                Some(step) => step,
                // Unbounded or failed without the whole box: with it.
                None if boxed.iter().any(|b| !b) => {
                    boxed.iter_mut().for_each(|b| *b = true);
                    continue;
                }
                // Failed with dense rows' terms where the band alone is indefinite: with the
                // model whole.
                None if !self.full.get() && !self.dense.is_empty() && BandCholesky::new(&self.w, self.hb).is_none() => {
                    self.full.set(true);
                    continue;
                }
                None => return None,
            };
            let mut broken = false;
            for (b, d) in boxed.iter_mut().zip(step.d.iter()) {
                if !*b && d.abs() > radius {
                    *b = true;
                    broken = true;
                }
            }
            for i in 0..values.len() {
                if !reachable[i] || working[i] || values[i] >= -SCREEN {
                    continue;
                }
                let linear = values[i] + self.rows[i].iter().map(|&(k, a)| a * step.d[k]).sum::<f64>();
                if linear > -0.5 * SCREEN {
                    working[i] = true;
                    broken |= linear > 0.0;
                }
            }
            if !broken {
                return Some(step);
            }
        }
    }

    /// The S-l1-QP subproblem with the inequality rows `active` only (the others' multipliers
    /// zero); `None` when Clarabel fails.
    fn solve_rows(
        &self,
        c: f64,
        values: &[f64],
        mu: f64,
        radius: f64,
        active: &[usize],
        boxed: &[bool],
    ) -> Option<Step> {
        let e = self.e;
        let dim = e.grad_f.len();
        let m = active.len();
        // The elastic variable of each active row (its index among them), only where the row is
        // broken at `d = 0` ([`Model::solve`]).
        let mut ns = 0;
        let elastic: Vec<Option<usize>> = active
            .iter()
            .map(|&i| {
                (values[i] > 0.0).then(|| {
                    ns += 1;
                    ns - 1
                })
            })
            .collect();
        // The running sum's points of the active rows with a local form ([`super::running`]).
        let local = |i: usize| self.running.and_then(|r| r.row(i));
        let mut points: Vec<usize> = active.iter().filter_map(|&i| local(i).map(|r| r.point)).collect();
        points.sort_unstable();
        points.dedup();
        let links = self.running.map_or_else(Vec::new, |r| r.links(&points, dim));
        let np = points.len();
        // Variables: d (dim), s+ and s- of the equality, w = grad c^T d, t_k of each elastic
        // active row, v_i = b_i^T d of each dense term, e_k = grad y_k^T d at each point.
        let nd = self.dense.len();
        let ev = dim + 3 + ns + nd;
        let nv = ev + np;
        let (sp, sm, wv) = (dim, dim + 1, dim + 2);
        let vv = dim + 3 + ns;
        // P: W's upper band in the d block, rho on w (all divided by mu: the slacks' weight is 1,
        // the same minimiser, and Clarabel's relative tolerances stay meaningful); or the model
        // whole in the d block ([`Model::solve`]).
        let cols = if self.full.get() { self.whole_columns(mu, nv) } else { self.band_columns(mu, nv, wv, vv) };
        let p = csc(nv, nv, &cols);
        let mut q = vec![0.0; nv];
        for (qk, gk) in q.iter_mut().zip(e.grad_f.iter()) {
            *qk = gk / mu;
        }
        q[sp] = 1.0;
        q[sm] = 1.0;
        for qk in &mut q[dim + 3..vv] {
            *qk = 1.0;
        }
        // Rows of A x + s = b: the equality and w's definition (zero cone), then s+- >= 0,
        // t >= 0, the active rows, and the box |d_k| <= radius (nonnegative cone).
        let mut a: Vec<Vec<(usize, f64)>> = vec![Vec::new(); nv];
        let mut b = Vec::new();
        for (k, v) in e.grad_c.iter().enumerate() {
            if *v != 0.0 {
                a[k].push((0, *v));
                a[k].push((1, *v));
            }
        }
        a[sp].push((0, -1.0));
        a[sm].push((0, 1.0));
        a[wv].push((1, -1.0));
        b.extend([-c, 0.0]);
        // The dense terms' definitions `b_i^T d - v_i = 0`.
        for (r, &(i, _)) in self.dense.iter().enumerate() {
            for &(k, v) in &self.rows[i] {
                a[k].push((2 + r, v));
            }
            a[vv + r].push((2 + r, -1.0));
            b.push(0.0);
        }
        // The points' definitions `e_k - e_j - (grad y_k - grad y_j)^T d = 0`.
        for (r, link) in links.iter().enumerate() {
            for &(k, v) in link {
                a[k].push((2 + nd + r, -v));
            }
            a[ev + r].push((2 + nd + r, 1.0));
            if r > 0 {
                a[ev + r - 1].push((2 + nd + r, -1.0));
            }
            b.push(0.0);
        }
        let mut row = 2 + nd + np;
        for k in [sp, sm].into_iter().chain(dim + 3..vv) {
            a[k].push((row, -1.0));
            b.push(0.0);
            row += 1;
        }
        for (r, &i) in active.iter().enumerate() {
            match local(i) {
                Some(form) => {
                    form.local.iter().for_each(|&(k, v)| a[k].push((row, v)));
                    let e = points.binary_search(&form.point).expect("invariant: each active point has its e_k");
                    a[ev + e].push((row, form.slope));
                }
                None => self.rows[i].iter().for_each(|&(k, v)| a[k].push((row, v))),
            }
            if let Some(s) = elastic[r] {
                a[dim + 3 + s].push((row, -1.0));
            }
            b.push(-values[i]);
            row += 1;
        }
        for (col, _) in a.iter_mut().take(dim).zip(boxed).filter(|(_, b)| **b) {
            col.push((row, 1.0));
            col.push((row + 1, -1.0));
            b.extend([radius, radius]);
            row += 2;
        }
        let a = csc(row, nv, &a);
        let cones: [SupportedConeT<f64>; 2] = [ZeroConeT(2 + nd + np), NonnegativeConeT(row - 2 - nd - np)];
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .max_iter(100)
            .tol_gap_abs(QP_TOLERANCE)
            .tol_gap_rel(QP_TOLERANCE)
            .tol_feas(QP_TOLERANCE)
            // No iterative refinement of the KKT solves (each interior-point iteration's
            // residuals come from the data, so an inexact step is corrected by the next): on
            // issue 21's SPART case the refinement's solves and residual products were a third of
            // Clarabel's time, and without it the planner takes the same 640 SQP iterations to
            // the same plan (effort equal to 1e-9) in 4.9 s of CPU instead of 6.0 s.
            .iterative_refinement_enable(false)
            // Steps to 0.999 of the distance to the cone's boundary (default 0.99): each QP is
            // still solved to the tolerance above, and the longer steps save 7 % of Clarabel's
            // iterations on issue 20's 3-link benches and 15 % on the SPART-like one, to the
            // same plans (efforts equal to 1e-9 on the five benches).
            .max_step_fraction(0.999)
            // No equilibration: the data is scaled already (every inequality row to its limit,
            // the cost by the penalty, the box's rows of one entry), and Clarabel's ten Ruiz
            // passes over `P` and `A` at every new solver, with the scaled problem's residuals,
            // took more than they saved: on issue 20's 3-link velocity and torque bench
            // Clarabel's iterations 625 -> 575 and the plan's instructions 886 -> 848 M, to the
            // same plans (efforts equal to 10 digits on the four plan benches).
            .equilibrate_enable(false)
            .build()
            .ok()?;
        let mut cache = self.solver.borrow_mut();
        let reused = match cache.as_mut() {
            Some((sent, was, solver, terms))
                if sent.len() == m
                    && sent
                        .iter()
                        .zip(active.iter().zip(&elastic))
                        .all(|(k, (i, s))| *k == 2 * i + usize::from(s.is_some()))
                    && was.as_slice() == boxed
                    && terms.iter().eq(self.dense.iter().map(|(i, _)| i))
                    && solver.is_data_update_allowed() =>
            {
                solver.update_P(&p).is_ok()
                    && solver.update_A(&a).is_ok()
                    && solver.update_q(&q).is_ok()
                    && solver.update_b(&b).is_ok()
            }
            _ => false,
        };
        if !reused {
            let terms = self.dense.iter().map(|(i, _)| *i).collect();
            *cache = Some((
                active.iter().zip(&elastic).map(|(i, s)| 2 * i + usize::from(s.is_some())).collect(),
                boxed.to_vec(),
                DefaultSolver::new(&p, &q, &a, &b, &cones, settings).ok()?,
                terms,
            ));
        }
        let (_, _, solver, _) = cache.as_mut()?;
        solver.solve();
        let sol = &solver.solution;
        if !matches!(sol.status, SolverStatus::Solved | SolverStatus::AlmostSolved) {
            return None;
        }
        let d = DVector::from_column_slice(&sol.x[..dim]);
        if !d.iter().all(|v| v.is_finite()) {
            return None;
        }
        let mut z = vec![0.0; values.len()];
        for (r, &i) in active.iter().enumerate() {
            z[i] = mu * sol.z[4 + nd + np + ns + r].max(0.0);
        }
        // The equality's multiplier: its row's and w's (whose row carries rho grad c^T d).
        Some(Step { d, lambda: mu * (sol.z[0] + sol.z[1]), z })
    }

    /// `P`'s upper columns (see [`Model::solve_rows`]): `W`'s band in the `d` block, `rho` on
    /// `w` and each dense term's weight on its `v_i`, all divided by `mu`.
    fn band_columns(&self, mu: f64, nv: usize, wv: usize, vv: usize) -> Vec<Vec<(usize, f64)>> {
        let (dim, hb) = (self.w.nrows(), self.hb);
        let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); nv];
        for (j, col) in cols.iter_mut().enumerate().take(dim) {
            for i in j.saturating_sub(hb)..=j {
                let v = self.w[(i, j)] / mu;
                if v != 0.0 {
                    col.push((i, v));
                }
            }
        }
        if self.rho > 0.0 {
            cols[wv].push((wv, self.rho / mu));
        }
        for (r, &(_, weight)) in self.dense.iter().enumerate() {
            cols[vv + r].push((vv + r, weight / mu));
        }
        cols
    }

    /// `P`'s upper columns with the model whole ([`Model::whole`], divided by `mu`) in the `d`
    /// block and nothing on `w` and the `v_i`: positive semi-definite where the band alone is not
    /// (Clarabel's interior point needs it; with the band alone its factorisation met negative
    /// pivots and it failed, see [`Model::solve`]).
    #[cold]
    #[inline(never)]
    fn whole_columns(&self, mu: f64, nv: usize) -> Vec<Vec<(usize, f64)>> {
        let whole = self.whole();
        let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); nv];
        for (j, col) in cols.iter_mut().enumerate().take(whole.nrows()) {
            for i in 0..=j {
                let v = whole[(i, j)] / mu;
                if v != 0.0 {
                    col.push((i, v));
                }
            }
        }
        cols
    }

    /// The model's whole Hessian `W + rho grad c grad c^T + sum_i rho_i b_i b_i^T` (dense).
    fn whole(&self) -> DMatrix<f64> {
        let dim = self.w.nrows();
        let mut whole = DMatrix::zeros(dim, dim);
        for j in 0..dim {
            for i in j.saturating_sub(self.hb)..(j + self.hb + 1).min(dim) {
                whole[(i, j)] = self.w[(i, j)];
            }
        }
        let a = &self.e.grad_c;
        whole.ger(self.rho, a, a, 1.0);
        for &(i, weight) in &self.dense {
            let mut b = DVector::zeros(dim);
            for &(k, v) in &self.rows[i] {
                b[k] += v;
            }
            whole.ger(weight, &b, &b, 1.0);
        }
        whole
    }

    /// The linearised infeasibility `|c + grad c^T d| + sum max(0, g_i + grad g_i^T d)`.
    pub(super) fn infeasibility(&self, c: f64, values: &[f64], d: &DVector<f64>) -> f64 {
        (c + self.e.grad_c.dot(d)).abs()
            + values
                .iter()
                .zip(self.rows)
                .map(|(v, row)| (v + row.iter().map(|&(k, a)| a * d[k]).sum::<f64>()).max(0.0))
                .sum::<f64>()
    }

    /// An upper bound on the linearised infeasibility's reduction by any step in the trust region
    /// `|d|_inf <= radius`: each term `max(0, g_i)` (and `|c|`) falls by at most itself and by at
    /// most its gradient's l1 norm times the radius.
    pub(super) fn reducible(&self, c: f64, values: &[f64], radius: f64) -> f64 {
        let reach = |row: &[(usize, f64)]| row.iter().map(|(_, a)| a.abs()).sum::<f64>() * radius;
        c.abs().min(self.e.grad_c.lp_norm(1) * radius)
            + values.iter().zip(self.rows).map(|(v, row)| if *v > 0.0 { v.min(reach(row)) } else { 0.0 }).sum::<f64>()
    }

    /// `grad f^T d + 1/2 d^T (W + rho grad c grad c^T + sum_i rho_i b_i b_i^T) d`.
    pub(super) fn quadratic(&self, d: &DVector<f64>) -> f64 {
        let wd = matvec(&self.w, self.hb, d);
        let ad = self.e.grad_c.dot(d);
        let dense: f64 = self
            .dense
            .iter()
            .map(|&(i, weight)| weight * self.rows[i].iter().map(|&(k, v)| v * d[k]).sum::<f64>().powi(2))
            .sum();
        self.e.grad_f.dot(d) + 0.5 * (d.dot(&wd) + self.rho * ad * ad + dense)
    }
}

/// Rows within this (scaled) distance of their limit are sent to every QP (see
/// [`Model::solve`]); farther ones only once a step comes within half of it.
const SCREEN: f64 = 0.05;

/// Clarabel's gap and feasibility tolerances (its default 1e-8 is too loose for the multipliers
/// of a QP whose cost is divided by a large penalty; at 1e-10 the steps near a solution, of order
/// 1e-7, were determined to only a few digits, and a screened QP (fewer rows, the same minimiser)
/// and the full one gave steps that differed by a tenth, enough to stall the SQP at the
/// constraints' rounding floor on issue 20's 3-link bench, which plans again at 1e-12).
const QP_TOLERANCE: f64 = 1e-12;

/// A CSC matrix from its columns' `(row, value)` entries (rows increasing within a column).
fn csc(m: usize, n: usize, cols: &[Vec<(usize, f64)>]) -> CscMatrix<f64> {
    let mut colptr = Vec::with_capacity(n + 1);
    let (mut rowval, mut nzval) = (Vec::new(), Vec::new());
    colptr.push(0);
    for col in cols {
        let mut sorted = col.clone();
        sorted.sort_by_key(|(r, _)| *r);
        for (r, v) in sorted {
            rowval.push(r);
            nzval.push(v);
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(m, n, colptr, rowval, nzval)
}
