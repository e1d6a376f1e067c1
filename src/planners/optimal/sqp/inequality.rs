//! The SQP step with inequalities: `min f(x)` subject to `c(x) = 0` and `g(x) <= 0` by the
//! S-l1-QP method (Fletcher): at each iterate the convex quadratic program
//!
//! `min_d grad f^T d + 1/2 d^T W d + mu (|c + grad c^T d| + sum_i max(0, g_i + grad g_i^T d))`,
//! `|d|_inf <= radius`,
//!
//! written with elastic variables as a QP and solved by the interior-point solver Clarabel; the
//! step is accepted on the l1 merit `f + mu (|c| + sum max(0, g))` with the trust-region ratio
//! test, as the equality-only path in the parent module. `W` is the Lagrangian's Hessian of the
//! cost and the equality, `hess f + lambda hess c`, with the multiplier-weighted curvature of the
//! rows the problem models ([`Discretised::curvature`]: the base-range rows, whose `phi(t)` is
//! curved as the equality's `phi(T)` is); the other rows' curvature is left out (a Gauss–Newton
//! model for them). The QP needs a convex `W`; at a minimum `W` is positive
//! definite on the equality's tangent space only, so the augmented term `rho (grad c^T d)^2 / 2`
//! is added first (an extra variable `w = grad c^T d` keeps the QP banded): it does not change
//! the step where the linearised equality holds, and makes `W` positive definite for a large
//! enough `rho` (Debreu's lemma), so Newton's convergence is kept. Where limits bind, `W` is
//! positive definite only on the null space of the equality's and the active rows' gradients, so
//! the same term is added for each active row (in the band, or as the equality's with an extra
//! variable for a modelled row outside it; see `convexify`). Only when no `rho`
//! does is `W` shifted by multiples of the metric `S` (a gradient-like step). Rows that cannot become active
//! inside the trust region (`g_i + |grad g_i|_1 radius < 0`) are left out of the QP, and so are
//! rows far from their limit until a step comes near them (screening, an active-set loop around
//! the QP that keeps its minimiser exact; see `Model::solve`).
//!
//! The penalty `mu` follows Byrd, Nocedal and Waltz's steering rules: it is raised only until
//! the step achieves a tenth of the linearised infeasibility reduction that the trust region
//! allows, and it is lowered back to twice the largest multiplier once the linearised
//! constraints hold (a needlessly large `mu` makes the ratio test reject good steps, the Maratos effect, and
//! drowns the QP's cost in its tolerances). A rejected step gets Fletcher's second-order
//! correction: the same QP with the constraints' values at the trial point.
//!
//! Each QP is first solved from a guess of its active set, the rows active at the last accepted
//! step (sibling `active` module: a few direct solves, the step kept only where it satisfies
//! every optimality condition of the QP, so it is the QP's minimiser); Clarabel solves the QPs
//! whose guess fails, in the iterations where the active set still moves.
//!
//! ## Reference
//! R. Fletcher, *Practical Methods of Optimization*, 2nd ed., Wiley (1987), Sec. 14.4 (the
//! S-l1-QP method, its second-order correction), doi:10.1002/9781118723203; R. H. Byrd,
//! J. Nocedal, R. A. Waltz, *Steering exact penalty methods for nonlinear programming*, Optim.
//! Methods Softw. 23 (2008) 197–213, doi:10.1080/10556780701394169; P. J. Goulart, Y. Chen, *Clarabel: An
//! interior-point solver for conic programs with quadratic objectives*, arXiv:2405.12762 (2024).

use std::cell::{Cell, RefCell};

use nalgebra::{DMatrix, DVector};

use super::active;
use super::subproblem::Model;
use super::{Discretised, Metric, Running, SqpOptions, SqpResult, Termination};
use crate::error::Error;
use crate::model::InputError;
use crate::planners::optimal::band::BandCholesky;
use crate::planners::optimal::discrete::Evaluation;

/// Inequalities `g(x) <= 0` at a point: values and sparse gradient rows.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Inequalities {
    /// `g_i(x)`, each scaled to its limit (dimensionless: 0 on the limit, -1 at zero use).
    pub values: Vec<f64>,
    /// `dg_i/dx` as `(free index, derivative)` pairs, one row per value (empty for order 0).
    pub rows: Vec<Vec<(usize, f64)>>,
    /// The rows' local forms through a running sum (the QP's banded form; module `running`).
    pub running: Option<Running>,
}

/// The largest violation `max(0, g_i)` of the inequalities.
fn violation(g: &Inequalities) -> f64 {
    g.values.iter().fold(0.0_f64, |m, v| m.max(*v))
}

/// The l1 penalty `sum_i max(0, g_i)`.
fn penalty(g: &Inequalities) -> f64 {
    g.values.iter().map(|v| v.max(0.0)).sum()
}

/// The convex model of `w`, with the equality's gradient `a` and the active rows' normals `b_i`
/// (rows `active` of `rows`, whose multiplier is positive: those with their support inside the
/// band, and those outside it in `curved`, the rows whose curvature `w` carries): `(w, 0, [])`
/// when it is positive definite; else the least `rho` in `r, 10 r, .., 1e8 r` (`r = max_i w_ii`)
/// that makes `w + rho (a a^T / |a|^2 + sum_i b_i b_i^T / |b_i|^2)` positive definite (dense
/// Cholesky), the banded rows' terms added to `w`, `rho / |a|^2` returned for the equality's and
/// `(i, rho / |b_i|^2)` for each row outside the band (the QP takes those terms with extra
/// variables, [`Model::dense`]); else `(w + tau S, 0, [])` with the least `tau` in `1e-4, 1e-3,
/// ..` that is positive definite.
///
/// A base-range row `phi(t_k) - hi` depends on every coefficient before `t_k`: without its
/// term, `w` with the rows' curvature stayed indefinite where the range binds and every step was
/// the shift's `w + 10 S` (the QP's step the exact Newton step of that model, the iteration
/// linear at a rate of 0.97: issue 20's base-range oracle case on the tests' arm, 200 iterations
/// to a KKT residual of 1e-4).
///
/// At a strict constrained minimum `w` is positive definite on the null space of the equality's
/// and the active rows' gradients only (the limits block the directions of negative curvature),
/// so the equality's term alone may not convexify it; with the active rows' terms it does for a
/// large enough `rho` (Debreu's lemma). Every term is constant where its linearised row holds
/// with equality, so the QP's minimiser is unchanged while the active set is; and a positive
/// semi-definite term adds nothing to the QP's optimality conditions at `d = 0`, so a fixed point
/// is one of the problem in any case. The shift `tau S` makes the step a gradient-like one
/// (linear convergence): without the rows' terms it was taken at every iteration near a
/// velocity-limited minimum, which then stalled after hundreds of iterations at a KKT residual
/// of 3e-5 (issue 20's 20 problems, case 9; with them, 24 iterations to 1e-7).
fn convexify(
    w: DMatrix<f64>,
    a: &DVector<f64>,
    active: &[usize],
    rows: &[Vec<(usize, f64)>],
    curved: std::ops::Range<usize>,
    s: &DMatrix<f64>,
    hb: usize,
) -> (DMatrix<f64>, f64, Vec<(usize, f64)>) {
    if BandCholesky::new(&w, hb).is_some() {
        return (w, 0.0, Vec::new());
    }
    let aa = a.norm_squared();
    let dim = w.nrows();
    // The rows' normalised outer products: banded for rows inside the band, dense for the
    // others (a base angle's or an obstacle's row, through `phi(t)`), whose terms the QP takes
    // as `(b_i^T d)^2` of an extra variable as the equality's.
    let mut rows_outer = DMatrix::zeros(dim, dim);
    let mut dense_outer = DMatrix::zeros(dim, dim);
    let mut dense = Vec::new();
    for &i in active {
        let row = &rows[i];
        let bb: f64 = row.iter().map(|(_, v)| v * v).sum();
        let (lo, hi) = row.iter().fold((usize::MAX, 0), |(l, h), (k, _)| (l.min(*k), h.max(*k)));
        if !(bb > 0.0) || (hi - lo > hb && !curved.contains(&i)) {
            continue;
        }
        let outer = if hi - lo > hb {
            dense.push((i, 1.0 / bb));
            &mut dense_outer
        } else {
            &mut rows_outer
        };
        for &(i, u) in row {
            for &(j, v) in row {
                outer[(i, j)] += u * v / bb;
            }
        }
    }
    let r = w.diagonal().amax().max(1e-300);
    let outer = if aa > 0.0 { a * a.transpose() / aa } else { DMatrix::zeros(dim, dim) };
    // Each trial `(w + rho R) + rho A + rho D` formed in one buffer, element by element in the
    // order of the matrices' sums (the same values, without a temporary per term and trial; the
    // Cholesky factor is computed in place).
    let positive_definite = |k: i32| {
        let rho = r * 10f64.powi(k);
        let mut trial = DMatrix::zeros(dim, dim);
        let (t, wv, ro, o, d) =
            (trial.as_mut_slice(), w.as_slice(), rows_outer.as_slice(), outer.as_slice(), dense_outer.as_slice());
        for i in 0..t.len() {
            t[i] = (wv[i] + ro[i] * rho) + o[i] * rho + d[i] * rho;
        }
        trial.cholesky().is_some()
    };
    // Every term added is positive semi-definite, so a `rho` that fails fails for every smaller
    // one: after the least, the largest is tried, and where it fails (the obstacles' rows
    // outside the band and not curved take no term, and the equality's alone seldom
    // convexifies: 103 of the 109 iterations of the 3-link obstacle bench, 223 of 418 on the
    // SPART-like one) the shift follows after two dense Cholesky factorisations instead of
    // nine. Else the least that succeeds, in increasing order as before.
    let least = if positive_definite(0) {
        Some(0)
    } else if positive_definite(8) {
        (1..=8).find(|&k| k == 8 || positive_definite(k))
    } else {
        None
    };
    if let Some(k) = least {
        let rho = r * 10f64.powi(k);
        let banded = &w + &rows_outer * rho;
        let dense = dense.into_iter().map(|(i, inv)| (i, rho * inv)).collect();
        return (banded, if aa > 0.0 { rho / aa } else { 0.0 }, dense);
    }
    let mut tau = 1e-4;
    for _ in 0..12 {
        let shifted = &w + s * tau;
        if BandCholesky::new(&shifted, hb).is_some() {
            return (shifted, 0.0, Vec::new());
        }
        tau *= 10.0;
    }
    (s.clone(), 0.0, Vec::new())
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

/// Most times the penalty is lowered in one solve (a guard against cycling).
const PENALTY_DECREASES: usize = 8;

/// Consecutive iterations with a vanishing step (`|d|_inf <= 1e-10 (1 + |x|_inf)`) after which
/// an infeasible solve stops as stalled: the QP, with the penalty steered up, finds no step that
/// reduces the linearised infeasibility inside a trust region many times larger, so the iterate
/// is a stationary point of the infeasibility's model, and later iterations solve the same QP
/// again. On issue 20's 2-link bench a loop's coarse solve reached such a point (the capped
/// line's, 3.6e-3 rad off the constraint) at its 7th iteration and took 11 more, 28 of the
/// plan's 67 QPs, to stop there at twice `stall_iterations` (46 QPs with two such steps, the
/// same plan). One is enough: the second iteration at the same point solved the same QP with
/// the multipliers of the first and a penalty ten times larger, and its step vanished as well
/// (both coarse solves of that bench, 3 QPs each); with one, the 2-link bench's QPs 46 -> 40,
/// Clarabel's iterations 474 -> 417, the same plan (effort 0.4470714501).
const STATIONARY_STEPS: usize = 1;

/// Solves `min f` subject to `c = 0`, `g <= 0` from `x0` (see the module docs). Converged means
/// `|c| <= constraint_tolerance`, `max g <= constraint_tolerance` (the rows are scaled to the
/// limits, so this is relative) and the KKT residual, the least of the QPs' at the iterate,
/// below `kkt_tolerance`. Where `abandon(iterations, f, c)` answers `true` at an iterate the
/// solve stops there as [`Termination::Abandoned`] (see [`super::solve_watched`]).
pub(super) fn solve<P: Discretised>(
    problem: &P,
    x0: DVector<f64>,
    options: &SqpOptions,
    guess: Option<f64>,
    m: &Metric,
    abandon: &mut dyn FnMut(usize, f64, f64) -> bool,
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
    let working = RefCell::new(vec![false; g.values.len()]);
    let boxed = RefCell::new(vec![false; x.len()]);
    let solver = RefCell::new(None);
    let mut mu = options.initial_penalty.unwrap_or_else(|| guess.map_or(1.0, |v| (2.0 * v.abs()).max(1.0)));
    let mut radius = (m.norm(&x) * 0.5).max(1.0);
    let mut iterations = 0;
    // The least KKT residual of the QPs solved at the current iterate.
    let mut kkt_here = f64::INFINITY;
    let (mut best_kkt, mut since_best, mut decreases) = (f64::INFINITY, 0, 0);
    let (mut least_infeasibility, mut since_infeasibility) = (f64::INFINITY, 0);
    // Consecutive iterations whose step vanished (below the iterate's rounding).
    let mut vanished = 0;
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
        if feasible && kkt_here <= options.kkt_tolerance {
            break Termination::Converged;
        }
        if feasible && since_best >= options.stall_iterations {
            break Termination::Stalled;
        }
        if iterations >= options.max_iterations {
            break Termination::MaxIterations;
        }
        if abandon(iterations, e.f, e.c) {
            break Termination::Abandoned;
        }
        if radius < 1e-15 * (1.0 + m.norm(&x)) {
            break Termination::RadiusCollapsed;
        }
        // Infeasible and no longer reducing the infeasibility by `feasibility_progress` (1 % by
        // default) in twice `stall_iterations` (a representative or a horizon the limits rule
        // out, or a local minimum of the infeasibility): stop rather than crawl.
        let infeasibility = e.c.abs() + penalty(&g);
        if infeasibility < (1.0 - options.feasibility_progress) * least_infeasibility {
            (least_infeasibility, since_infeasibility) = (infeasibility, 0);
        }
        // Infeasible where the steps have vanished: a stationary point of the infeasibility's
        // model ([`STATIONARY_STEPS`]).
        if !feasible && (since_infeasibility >= 2 * options.stall_iterations || vanished >= STATIONARY_STEPS) {
            break Termination::Stalled;
        }
        iterations += 1;
        since_best += 1;
        since_infeasibility += 1;
        // The rows active at the last accepted QP's solution (a multiplier above the interior
        // point's rounding, a millionth of the largest).
        let largest_z = z.iter().fold(0.0_f64, |m, v| m.max(*v));
        let active: Vec<usize> = (0..z.len()).filter(|&i| z[i] > 1e-6 * largest_z.max(1.0)).collect();
        let mut hessian = e.lagrangian_hessian(m.s, lambda);
        if let Some(curvature) = problem.curvature(&x, &z) {
            hessian += curvature;
        }
        let (w, rho, dense) = convexify(hessian, &e.grad_c, &active, &g.rows, problem.curved_rows(), m.s, hb);
        let model = Model {
            w,
            rho,
            dense,
            full: Cell::new(false),
            hb,
            e: &e,
            rows: &g.rows,
            running: g.running.as_ref(),
            working: &working,
            boxed: &boxed,
            solver: &solver,
            columns: Default::default(),
        };
        let left = |d: &DVector<f64>| model.infeasibility(e.c, &g.values, d);
        // Each QP from the active set of the last accepted one first ([`active::step`], exact
        // where it is taken), by Clarabel where that guess is not the QP's: on issue 20's
        // benches Clarabel's iterations per plan 486 -> 211 (3-link velocity), 351 -> 127
        // (2-link), 523 -> 254 (with torque), 443 -> 94 (SPART-like); the same efforts.
        let qp = |c: f64, values: &[f64], mu: f64| {
            active::step(&model, c, values, mu, radius, &active).or_else(|| model.solve(c, values, mu, radius))
        };
        let Some(mut step) = qp(e.c, &g.values, mu) else {
            radius *= 0.25;
            continue;
        };
        // Steering: when the step leaves linearised infeasibility, the reduction the trust region
        // allows (the step of a 1e4 times larger penalty) is the reference; the penalty is raised
        // tenfold (up to three times) until the step achieves a tenth of it (as any step that removes
        // a tenth of the infeasibility does: the reference is then not solved, 12 of 118 QPs on issue
        // 20's SPART-like bench). Nor is it where the step achieves a tenth of an upper bound on
        // it, the reduction each term allows inside the trust region (`Model::reducible`): the
        // loop would stop at once (one reference a plan on issue 20's 3-link velocity bench, whose
        // QPs fell from 51 to 46 as the working set then grew differently; the same plan).
        let reduction = infeasibility - left(&step.d);
        let enough = reduction >= 0.1 * infeasibility;
        let bounded = || reduction >= 0.1 * (1.0 + 1e-9) * model.reducible(e.c, &g.values, radius);
        if !enough && infeasibility > tol && left(&step.d) > 1e-12 * (1.0 + infeasibility) && mu < 1e8 && !bounded() {
            let best = qp(e.c, &g.values, 1e4 * mu).map(|s| infeasibility - left(&s.d));
            if let Some(best) = best.filter(|b| *b > 0.0) {
                for _ in 0..3 {
                    if infeasibility - left(&step.d) >= 0.1 * best {
                        break;
                    }
                    let Some(more) = qp(e.c, &g.values, 10.0 * mu) else { break };
                    (step, mu) = (more, 10.0 * mu);
                }
            }
        }
        // The QP at x: its multipliers are those of x when its step vanishes.
        let kkt_value = kkt(m, &e, &g, step.lambda, &step.z);
        kkt_here = kkt_here.min(kkt_value);
        if kkt_here < 0.5 * best_kkt {
            (best_kkt, since_best) = (kkt_here, 0);
        }
        if feasible && kkt_here <= options.kkt_tolerance {
            (lambda, z) = (step.lambda, step.z);
            break Termination::Converged;
        }
        let d = &step.d;
        let largest = step.z.iter().fold(step.lambda.abs(), |a, b| a.max(*b));
        if left(d) <= 1e-12 * (1.0 + infeasibility) {
            // A linearisation that holds with a needlessly large penalty: back to twice the multipliers.
            if mu > 20.0 * largest.max(0.5) && decreases < PENALTY_DECREASES {
                mu = 2.0 * largest.max(0.5);
                decreases += 1;
            }
            mu = mu.max(1.2 * largest);
        }
        let quad = model.quadratic(d);
        // The penalty that makes the predicted reduction at least 0.3 mu dc (as the equality-only
        // path; Nocedal, Wright Eq. 18.36), while the infeasibility is above the constraints'
        // rounding (below it the ratio explodes, and the multipliers' bound keeps the penalty
        // exact).
        let dc = infeasibility - left(d);
        if dc > 1e-8 {
            mu = mu.max(quad / (0.7 * dc) + 1e-8);
        }
        let merit = e.f + mu * infeasibility;
        let pred = merit - (e.f + quad + mu * left(d));
        let trial_merit = |x: &DVector<f64>| {
            let tr = problem.evaluate(x, 0);
            match problem.inequalities(x, 0) {
                Some(tg) if tr.f.is_finite() && tr.c.is_finite() => {
                    (tr.f + mu * (tr.c.abs() + penalty(&tg)), Some((tr.c, tg.values)))
                }
                _ => (f64::INFINITY, None),
            }
        };
        // The merit's rounding floor: the cost's relative 1e-14 and the penalty times the
        // constraints' absolute rounding (quadrature sums of order 1e-13 rad).
        let noise = 1e-14 * e.f.abs() + 1e-13 * mu;
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
        let (trial, at_trial) = trial_merit(&(&x + d));
        let mut ratio = ratio_of(trial);
        let mut accepted_step = d.clone();
        if ratio < 1e-8
            && let Some((c_t, g_t)) = at_trial
        {
            // Fletcher's second-order correction: the QP at x with the constraints' values at
            // the trial point, shifted back by the step.
            let shifted: Vec<f64> =
                g_t.iter().zip(&g.rows).map(|(v, row)| v - row.iter().map(|&(k, a)| a * d[k]).sum::<f64>()).collect();
            if let Some(soc) = qp(c_t - e.grad_c.dot(d), &shifted, mu) {
                let ratio2 = ratio_of(trial_merit(&(&x + &soc.d)).0);
                if ratio2 >= 1e-8 {
                    ratio = ratio2;
                    accepted_step = soc.d;
                }
            }
        }
        let step_norm = accepted_step.amax();
        vanished = if step_norm <= 1e-10 * (1.0 + x.amax()) { vanished + 1 } else { 0 };
        if ratio >= 1e-8 {
            x += &accepted_step;
            e = problem.evaluate(&x, 2);
            g = problem.inequalities(&x, 1).ok_or_else(no_rows)?;
            (lambda, z) = (step.lambda, step.z);
            kkt_here = f64::INFINITY;
            if ratio > 0.75 && step_norm > 0.8 * radius {
                radius = (2.0 * radius).min(1e4);
            } else if ratio < 0.25 {
                radius *= 0.5;
            }
        } else {
            radius = 0.25 * step_norm.min(radius);
        }
    };
    let kkt_final = if kkt_here.is_finite() { kkt_here } else { kkt(m, &e, &g, lambda, &z) };
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
