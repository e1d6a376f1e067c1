//! The SQP step with inequalities: `min f(x)` subject to `c(x) = 0` and `g(x) <= 0` by the
//! S-l1-QP method (Fletcher): at each iterate the convex quadratic program
//!
//! `min_d grad f^T d + 1/2 d^T W d + mu (|c + grad c^T d| + sum_i max(0, g_i + grad g_i^T d))`,
//! `|d|_inf <= radius`,
//!
//! written with elastic variables as a QP and solved by the interior-point solver Clarabel; the
//! step is accepted on the l1 merit `f + mu (|c| + sum max(0, g))` with the trust-region ratio
//! test, as the equality-only path in the parent module. `W` is the Lagrangian's Hessian of the
//! cost and the equality, `hess f + lambda hess c` (the inequalities' curvature left out: a
//! Gauss–Newton model for them), shifted by multiples of the metric `S` until it is positive
//! definite. Rows that cannot become active inside the trust region
//! (`g_i + |grad g_i|_1 radius < 0`) are left out of the QP.
//!
//! ## Reference
//! R. Fletcher, *Practical Methods of Optimization*, 2nd ed., Wiley (1987), Sec. 14.4 (the
//! S-l1-QP method), doi:10.1002/9781118723203; P. J. Goulart, Y. Chen, *Clarabel: An
//! interior-point solver for conic programs with quadratic objectives*, arXiv:2405.12762 (2024).

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus, SupportedConeT, ZeroConeT,
};
use nalgebra::{DMatrix, DVector};

use super::{Discretised, Inequalities, Metric, SqpOptions, SqpResult, Termination};
use crate::error::Error;
use crate::model::InputError;
use crate::planners::optimal::band::{BandCholesky, matvec};
use crate::planners::optimal::discrete::Evaluation;

/// The largest violation `max(0, g_i)` of the inequalities.
fn violation(g: &Inequalities) -> f64 {
    g.values.iter().fold(0.0_f64, |m, v| m.max(*v))
}

/// The l1 penalty `sum_i max(0, g_i)`.
fn penalty(g: &Inequalities) -> f64 {
    g.values.iter().map(|v| v.max(0.0)).sum()
}

/// The solution of one QP subproblem.
struct Step {
    d: DVector<f64>,
    /// Multiplier of the linearised equality.
    lambda: f64,
    /// Multipliers of the inequality rows (zero for rows left out).
    z: Vec<f64>,
}

/// Solves the S-l1-QP subproblem at `(e, g)` with the convex `w`; `None` when Clarabel fails.
fn subproblem(w: &DMatrix<f64>, hb: usize, e: &Evaluation, g: &Inequalities, mu: f64, radius: f64) -> Option<Step> {
    let dim = e.grad_f.len();
    let reach = |i: usize| g.rows[i].iter().map(|(_, a)| a.abs()).sum::<f64>() * radius;
    let active: Vec<usize> = (0..g.values.len()).filter(|&i| g.values[i] + reach(i) >= 0.0).collect();
    let m = active.len();
    // Variables: d (dim), s+ and s- of the equality, t_k of each active row.
    let nv = dim + 2 + m;
    let (sp, sm) = (dim, dim + 1);
    // P: W's upper band in the d block.
    let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); nv];
    for (j, col) in cols.iter_mut().enumerate().take(dim) {
        for i in j.saturating_sub(hb)..=j {
            let v = w[(i, j)] / mu;
            if v != 0.0 {
                col.push((i, v));
            }
        }
    }
    let p = csc(nv, nv, &cols);
    let mut q = vec![0.0; nv];
    // The objective divided by mu (the slacks' weight 1): the same minimiser, and Clarabel's
    // relative tolerances stay meaningful when the penalty is large.
    for (qk, gk) in q.iter_mut().zip(e.grad_f.iter()) {
        *qk = gk / mu;
    }
    for qk in &mut q[dim..] {
        *qk = 1.0;
    }
    // Rows of A x + s = b: the equality (zero cone), then s+- >= 0, t >= 0, the active rows,
    // and the box |d_k| <= radius (nonnegative cone).
    let mut a: Vec<Vec<(usize, f64)>> = vec![Vec::new(); nv];
    let mut b = Vec::new();
    let mut row = 0;
    for (k, v) in e.grad_c.iter().enumerate() {
        if *v != 0.0 {
            a[k].push((row, *v));
        }
    }
    a[sp].push((row, -1.0));
    a[sm].push((row, 1.0));
    b.push(-e.c);
    row += 1;
    for col in a.iter_mut().skip(dim) {
        col.push((row, -1.0));
        b.push(0.0);
        row += 1;
    }
    for (r, &i) in active.iter().enumerate() {
        for &(k, v) in &g.rows[i] {
            a[k].push((row, v));
        }
        a[dim + 2 + r].push((row, -1.0));
        b.push(-g.values[i]);
        row += 1;
    }
    for col in a.iter_mut().take(dim) {
        col.push((row, 1.0));
        col.push((row + 1, -1.0));
        b.extend([radius, radius]);
        row += 2;
    }
    let a = csc(row, nv, &a);
    let cones: [SupportedConeT<f64>; 2] = [ZeroConeT(1), NonnegativeConeT(row - 1)];
    let settings = DefaultSettingsBuilder::default().verbose(false).max_iter(100).build().ok()?;
    let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings).ok()?;
    solver.solve();
    let sol = &solver.solution;
    if !matches!(sol.status, SolverStatus::Solved | SolverStatus::AlmostSolved) {
        return None;
    }
    let d = DVector::from_column_slice(&sol.x[..dim]);
    if !d.iter().all(|v| v.is_finite()) {
        return None;
    }
    let mut z = vec![0.0; g.values.len()];
    for (r, &i) in active.iter().enumerate() {
        z[i] = mu * sol.z[3 + m + r].max(0.0);
    }
    Some(Step { d, lambda: mu * sol.z[0], z })
}

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

/// `W + tau S` with the least `tau` in `0, 1e-4, 1e-3, ..` that is positive definite.
fn convexify(w: DMatrix<f64>, s: &DMatrix<f64>, hb: usize) -> DMatrix<f64> {
    if BandCholesky::new(&w, hb).is_some() {
        return w;
    }
    let mut tau = 1e-4;
    for _ in 0..12 {
        let shifted = &w + s * tau;
        if BandCholesky::new(&shifted, hb).is_some() {
            return shifted;
        }
        tau *= 10.0;
    }
    s.clone()
}

/// The relative KKT residual `|grad f + lambda grad c + sum z_i grad g_i|_{S^-1} / max(1,
/// |grad f|_{S^-1})` and the complementarity `max_i z_i |g_i|` relative to the same scale.
fn kkt(m: &Metric, e: &Evaluation, g: &Inequalities, lambda: f64, z: &[f64]) -> f64 {
    let mut r = &e.grad_f + &e.grad_c * lambda;
    let mut complementarity: f64 = 0.0;
    for (i, zi) in z.iter().enumerate() {
        if *zi > 0.0 {
            for &(k, v) in &g.rows[i] {
                r[k] += zi * v;
            }
            complementarity = complementarity.max(zi * g.values[i].abs());
        }
    }
    let norm = r.dot(&m.chol.solve(&r)).max(0.0).sqrt();
    let scale = e.grad_f.dot(&m.chol.solve(&e.grad_f)).max(0.0).sqrt().max(1.0);
    (norm + complementarity) / scale
}

/// Solves `min f` subject to `c = 0`, `g <= 0` from `x0` (see the module docs). Converged means
/// `|c| <= constraint_tolerance`, `max g <= constraint_tolerance` (the rows are scaled to the
/// limits, so this is relative) and the KKT residual below `kkt_tolerance`.
pub(super) fn solve<P: Discretised>(
    problem: &P,
    x0: DVector<f64>,
    options: &SqpOptions,
    guess: Option<f64>,
    m: &Metric,
) -> Result<SqpResult, Error> {
    let hb = m.hb;
    let mut x = x0;
    let mut e = problem.evaluate(&x, 2);
    let no_rows = || {
        Error::from(InputError::InvalidParameter {
            name: "inequalities".into(),
            value: f64::NAN,
            expected: "inequalities at every point where they were declared",
        })
    };
    let mut g = problem.inequalities(&x, 1).ok_or_else(no_rows)?;
    let guess = guess.filter(|v| v.is_finite());
    let mut lambda = guess.unwrap_or(0.0);
    let mut z = vec![0.0; g.values.len()];
    let mut mu = guess.map_or(1.0, |v| (2.0 * v.abs()).max(1.0));
    let mut radius = (m.norm(&x) * 0.5).max(1.0);
    let mut iterations = 0;
    let mut kkt_value = f64::INFINITY;
    let (mut best_kkt, mut since_best) = (f64::INFINITY, 0);
    let tol = options.constraint_tolerance;
    let termination = loop {
        if !(e.f.is_finite() && e.c.is_finite() && g.values.iter().all(|v| v.is_finite())) {
            return Err(Error::from(InputError::InvalidParameter {
                name: "seed".into(),
                value: e.f,
                expected: "a finite cost",
            }));
        }
        let feasible = e.c.abs() <= tol && violation(&g) <= tol;
        if feasible && kkt_value <= options.kkt_tolerance {
            break Termination::Converged;
        }
        if feasible && since_best >= options.stall_iterations {
            break Termination::Stalled;
        }
        if iterations >= options.max_iterations {
            break Termination::MaxIterations;
        }
        if radius < 1e-15 * (1.0 + m.norm(&x)) {
            break Termination::RadiusCollapsed;
        }
        iterations += 1;
        since_best += 1;
        let w = convexify(&e.hess_f + &e.hess_c * lambda, m.s, hb);
        let infeasibility = e.c.abs() + penalty(&g);
        let model_penalty = |d: &DVector<f64>| {
            (e.c + e.grad_c.dot(d)).abs()
                + g.values
                    .iter()
                    .zip(&g.rows)
                    .map(|(v, row)| (v + row.iter().map(|&(k, a)| a * d[k]).sum::<f64>()).max(0.0))
                    .sum::<f64>()
        };
        // Steering: while the elastic variables take part of the linearised infeasibility, a ten
        // times larger penalty is tried, and kept when it reduces that infeasibility by a tenth
        // more (a trust region too small to reach feasibility keeps the smaller one).
        let Some(mut step) = subproblem(&w, hb, &e, &g, mu, radius) else {
            radius *= 0.25;
            continue;
        };
        for _ in 0..4 {
            let left = model_penalty(&step.d);
            if infeasibility <= tol || left <= 1e-12 * (1.0 + infeasibility) || mu >= 1e8 {
                break;
            }
            let Some(more) = subproblem(&w, hb, &e, &g, 10.0 * mu, radius) else { break };
            if infeasibility - model_penalty(&more.d) > 1.1 * (infeasibility - left) {
                (step, mu) = (more, 10.0 * mu);
            } else {
                break;
            }
        }
        // The QP at x: its multipliers are those of x when its step vanishes.
        kkt_value = kkt(m, &e, &g, step.lambda, &step.z);
        if kkt_value < 0.5 * best_kkt {
            (best_kkt, since_best) = (kkt_value, 0);
        }
        if feasible && kkt_value <= options.kkt_tolerance {
            (lambda, z) = (step.lambda, step.z);
            break Termination::Converged;
        }
        let d = &step.d;
        if model_penalty(d) <= 1e-12 * (1.0 + infeasibility) {
            let largest = step.z.iter().fold(step.lambda.abs(), |a, b| a.max(*b));
            mu = mu.max(1.2 * largest);
        }
        let wd = matvec(&w, hb, d);
        let quad = e.grad_f.dot(d) + 0.5 * d.dot(&wd);
        // The penalty that makes the predicted reduction at least 0.3 mu dc (as the equality-only
        // path; Nocedal, Wright Eq. 18.36).
        let dc = infeasibility - model_penalty(d);
        if dc > 0.0 {
            mu = mu.max(quad / (0.7 * dc) + 1e-8);
        }
        let merit = e.f + mu * (e.c.abs() + penalty(&g));
        let pred = merit - (e.f + quad + mu * model_penalty(d));
        let trial_merit = |x: &DVector<f64>| {
            let tr = problem.evaluate(x, 0);
            let tg = problem.inequalities(x, 0);
            match tg {
                Some(tg) if tr.f.is_finite() && tr.c.is_finite() => tr.f + mu * (tr.c.abs() + penalty(&tg)),
                _ => f64::INFINITY,
            }
        };
        let noise = 1e-14 * (e.f.abs() + mu * e.c.abs() + 1e-300);
        let ratio_of = |value: f64| {
            let ared = merit - value;
            if !value.is_finite() {
                -1.0
            } else if pred > noise {
                ared / pred
            } else if ared >= -noise {
                1.0
            } else {
                -1.0
            }
        };
        let trial_x = &x + d;
        let mut ratio = ratio_of(trial_merit(&trial_x));
        let mut accepted_step = d.clone();
        if ratio < 1e-8 {
            // Second-order correction of the equality: back along the metric's normal.
            let a_s = m.chol.solve(&e.grad_c);
            let den = e.grad_c.dot(&a_s);
            let tr = problem.evaluate(&trial_x, 0);
            if den > 0.0 && tr.c.is_finite() {
                let soc = &a_s * (-tr.c / den);
                let ratio2 = ratio_of(trial_merit(&(&trial_x + &soc)));
                if ratio2 >= 1e-8 {
                    ratio = ratio2;
                    accepted_step = d + soc;
                }
            }
        }
        let step_norm = accepted_step.amax();
        if ratio >= 1e-8 {
            x += &accepted_step;
            e = problem.evaluate(&x, 2);
            g = problem.inequalities(&x, 1).ok_or_else(no_rows)?;
            (lambda, z) = (step.lambda, step.z);
            if ratio > 0.75 && step_norm > 0.8 * radius {
                radius = (2.0 * radius).min(1e4);
            } else if ratio < 0.25 {
                radius *= 0.5;
            }
        } else {
            radius = 0.25 * step_norm.min(radius);
        }
    };
    let kkt_final = if kkt_value.is_finite() { kkt_value } else { kkt(m, &e, &g, lambda, &z) };
    Ok(SqpResult {
        x,
        lambda,
        f: e.f,
        c: e.c.abs().max(violation(&g)).copysign(e.c),
        kkt: kkt_final,
        iterations,
        termination,
        kkt_tolerance: options.kkt_tolerance,
    })
}
