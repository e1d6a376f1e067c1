//! A trust-region SQP method for `min f(x)` subject to one equality `c(x) = 0`, with exact
//! Hessians: Byrd–Omojokun composite steps (a normal step toward `c = 0`, a tangential step by
//! projected, preconditioned Steihaug CG), the l1 merit function and second-order corrections.
//!
//! The trust region is measured in the metric `S` of the effort's constant Hessian,
//! `|d|_S = sqrt(d^T S d)`, which also preconditions the CG: the effort is the cost (or close to
//! it), so the tangential subproblem is well conditioned in that metric whatever the knot grading.
//!
//! With inequalities `g(x) <= 0` ([`Discretised::inequalities`], linear bounds and nonlinear rows
//! with exact gradients) the step is the S-l1-QP step of `sqp/inequality.rs`; without them the
//! iteration is the equality-only one below.
//!
//! ## Reference
//! J. Nocedal, S. J. Wright, *Numerical Optimization*, 2nd ed., Springer (2006), Secs. 18.5
//! (Byrd–Omojokun) and 16.3 (projected CG), doi:10.1007/978-0-387-40065-5; N. I. M. Gould,
//! M. E. Hribar, J. Nocedal, *On the solution of equality constrained quadratic programming problems
//! arising in optimization*, SIAM J. Sci. Comput. 23 (2001) 1376–1395, doi:10.1137/S1064827598345667.

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use super::band::{BandCholesky, matvec, matvec_pair_into};
use super::discrete::{Discretisation, Evaluation};
use crate::error::Error;
use crate::model::InputError;
pub use inequality::Inequalities;
pub use running::{Running, RunningRow};

mod active;
mod inequality;
mod running;
mod subproblem;
#[cfg(test)]
mod tests_active;
#[cfg(test)]
mod tests_inequality;
#[cfg(test)]
mod tests_steihaug;

/// A discretised problem the SQP solves: cost and one equality constraint with exact first and
/// second derivatives, and the effort's constant Hessian as the trust-region metric (banded).
pub trait Discretised {
    /// Number of free variables.
    fn dim(&self) -> usize;
    /// Half-bandwidth of every Hessian in the free variables.
    fn half_bandwidth(&self) -> usize;
    /// The constant, positive definite metric `S` (the effort's Hessian).
    fn effort_hessian(&self) -> &DMatrix<f64>;
    /// Its band Cholesky factor (`None` when not positive definite).
    fn effort_cholesky(&self) -> Option<&BandCholesky>;
    /// Cost and constraint at `x`, with first derivatives for `order >= 1` and second
    /// derivatives for `order >= 2`.
    fn evaluate(&self, x: &DVector<f64>, order: usize) -> Evaluation;
    /// The inequalities `g(x) <= 0` at `x`, with their gradients for `order >= 1`; `None` (the
    /// default) when the problem has none: the equality-only iteration runs.
    fn inequalities(&self, _x: &DVector<f64>, _order: usize) -> Option<Inequalities> {
        None
    }
    /// Takes back the constraint's Hessian of an [`Evaluation`] the iteration is done with, for
    /// the next evaluation to fill instead of allocating another (the default drops it).
    fn recycle(&self, _hess_c: DMatrix<f64>) {}
    /// The inequalities' curvature `sum_i z_i hess g_i(x)` weighted by the multipliers `z` (one
    /// per row of [`Discretised::inequalities`]), in the band of half-bandwidth
    /// [`Discretised::half_bandwidth`], for the rows whose second derivatives the problem
    /// models; `None` (the default) where it models none: the QP's model leaves them linear.
    fn curvature(&self, _x: &DVector<f64>, _z: &[f64]) -> Option<DMatrix<f64>> {
        None
    }
    /// The rows whose curvature [`Discretised::curvature`] models (empty by default): where
    /// one of them is active outside the band, the QP's convex model takes its term
    /// `rho (b_i^T d)^2` too (see the `inequality` module's `convexify`).
    fn curved_rows(&self) -> std::ops::Range<usize> {
        0..0
    }
}

impl Discretised for Discretisation {
    fn dim(&self) -> usize {
        Discretisation::dim(self)
    }
    fn half_bandwidth(&self) -> usize {
        Discretisation::half_bandwidth(self)
    }
    fn effort_hessian(&self) -> &DMatrix<f64> {
        Discretisation::effort_hessian(self)
    }
    fn effort_cholesky(&self) -> Option<&BandCholesky> {
        Discretisation::effort_cholesky(self)
    }
    fn evaluate(&self, x: &DVector<f64>, order: usize) -> Evaluation {
        Discretisation::evaluate(self, x, order)
    }
}

/// Options of the SQP iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SqpOptions {
    /// Largest number of iterations per solve; default 200.
    pub max_iterations: usize,
    /// `|c| <= constraint_tolerance` \[rad\] at convergence; default 1e-12.
    pub constraint_tolerance: f64,
    /// Relative KKT residual `|grad f + lambda grad c|_{S^-1} / max(1, |grad f|_{S^-1})` at
    /// convergence; default 1e-7 (the projected CG keeps its residual on the tangent space, so
    /// refined solves reach about 1e-11).
    pub kkt_tolerance: f64,
    /// Stop as [`Termination::Stalled`] after this many iterations without halving the best KKT
    /// residual while feasible; default 8.
    pub stall_iterations: usize,
    /// With inequalities, an infeasible solve stops as [`Termination::Stalled`] after twice
    /// `stall_iterations` iterations that reduce its infeasibility by less than this fraction (a
    /// representative or a horizon the limits rule out: a crawl, not a convergence); default 0.01.
    pub feasibility_progress: f64,
    /// With inequalities, the l1 penalty's first value; `None` (the default) for
    /// `max(1, 2 |guess|)`, or 1 without a guess (see [`SqpOptions::balanced`]).
    pub initial_penalty: Option<f64>,
}

impl Default for SqpOptions {
    fn default() -> Self {
        Self {
            max_iterations: 200,
            constraint_tolerance: 1e-12,
            kkt_tolerance: 1e-7,
            stall_iterations: 8,
            feasibility_progress: 0.01,
            initial_penalty: None,
        }
    }
}

impl SqpOptions {
    /// The options of the coarse solves that rank the seeds and goal representatives (the
    /// 2-link planner's and the chain planner's alike): a looser KKT tolerance and fewer
    /// iterations than the refinement's [`Default`].
    pub const COARSE: Self = Self {
        max_iterations: 40,
        constraint_tolerance: 1e-10,
        kkt_tolerance: 1e-6,
        stall_iterations: 6,
        feasibility_progress: 0.01,
        initial_penalty: None,
    };

    /// These options with the penalty starting at `|f(x0)| / |c(x0)|` (in `[1, 1e4]`; the
    /// default where that is not finite, e.g. on the constraint): the weight at which the
    /// start's infeasibility counts as much as its cost. For a warm start
    /// off the constraint without a multiplier's estimate (the rate-limited line on the finest
    /// basis from the coarse line's infeasible solution, `chain::starts`), where a penalty of 1
    /// is steered up tenfold a QP at a time in the first iteration: on issue 20's benches the
    /// penalty starts at 84 (3-link, the coarse line 0.18 rad off the holonomy), and that solve's
    /// QPs 23 -> 20; Clarabel's iterations per plan 521 -> 486 (3-link velocity), 392 -> 361
    /// (2-link), 562 -> 523 (3-link velocity and torque), SPART-like unchanged.
    pub fn balanced<P: Discretised>(self, problem: &P, x0: &DVector<f64>) -> Self {
        let e = problem.evaluate(x0, 0);
        let ratio = e.f.abs() / e.c.abs();
        let initial_penalty = (e.c.abs() > 0.0 && ratio.is_finite()).then(|| ratio.clamp(1.0, 1e4));
        Self { initial_penalty, ..self }
    }
}

/// Why the iteration stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Termination {
    /// Both tolerances met.
    Converged,
    /// The iteration limit was hit.
    MaxIterations,
    /// The trust region shrank to nothing without meeting the tolerances.
    RadiusCollapsed,
    /// The constraint's gradient vanished away from feasibility.
    DegenerateConstraint,
    /// Feasible, but the KKT residual stopped decreasing above its tolerance (rounding floor).
    Stalled,
    /// The caller's watch gave the solve up ([`solve_watched`]).
    Abandoned,
}

impl Termination {
    /// The name in the reports (`converged`, `stalled`, ...).
    pub fn name(self) -> &'static str {
        match self {
            Termination::Converged => "converged",
            Termination::MaxIterations => "max_iterations",
            Termination::RadiusCollapsed => "radius_collapsed",
            Termination::DegenerateConstraint => "degenerate_constraint",
            Termination::Stalled => "stalled",
            Termination::Abandoned => "abandoned",
        }
    }
}

/// The result of one solve.
#[derive(Debug, Clone)]
pub struct SqpResult {
    /// The free variables.
    pub x: DVector<f64>,
    /// The Lagrange multiplier of `c = 0`.
    pub lambda: f64,
    /// Cost at `x`.
    pub f: f64,
    /// Constraint residual at `x` \[rad\].
    pub c: f64,
    /// Relative KKT residual at `x`.
    pub kkt: f64,
    /// Iterations made.
    pub iterations: usize,
    /// Why it stopped.
    pub termination: Termination,
    /// The KKT tolerance it was held to.
    pub kkt_tolerance: f64,
}

impl SqpResult {
    /// True when the iteration converged, or stalled feasible within 100 times the KKT
    /// tolerance (its rounding floor).
    pub fn converged(&self) -> bool {
        self.termination == Termination::Converged
            || (self.termination == Termination::Stalled && self.kkt <= 100.0 * self.kkt_tolerance)
    }
}

/// The metric `S` (Cholesky factor) with the helpers of the composite step.
struct Metric<'a> {
    s: &'a DMatrix<f64>,
    chol: &'a BandCholesky,
    hb: usize,
}

impl Metric<'_> {
    fn times(&self, v: &DVector<f64>) -> DVector<f64> {
        matvec(self.s, self.hb, v)
    }

    fn norm(&self, v: &DVector<f64>) -> f64 {
        v.dot(&self.times(v)).max(0.0).sqrt()
    }
}

/// Multiplier by least squares in the metric, and the relative KKT residual, with
/// `a_s = S^-1 grad c` (kept for the step at the same point).
fn multiplier(m: &Metric, e: &Evaluation) -> (f64, f64, DVector<f64>) {
    let a_s = m.chol.solve(&e.grad_c);
    let den = e.grad_c.dot(&a_s);
    let lambda = if den > 0.0 { -a_s.dot(&e.grad_f) / den } else { 0.0 };
    let r = &e.grad_f + &e.grad_c * lambda;
    let kkt = r.dot(&m.chol.solve(&r)).max(0.0); // |grad f|_S^2 = kkt + lambda^2 den (a_s^T r = 0)
    let scale = (kkt + lambda * lambda * den).max(0.0).sqrt().max(1.0);
    (lambda, kkt.sqrt() / scale, a_s)
}

/// Solves the discretised problem from `x0` (Byrd–Omojokun trust-region SQP; the S-l1-QP step
/// when the problem has inequalities, and then [`SqpResult::c`] is the larger of `|c|` and the
/// largest scaled violation `max_i g_i`, with the sign of `c`).
///
/// `guess`, an estimate of the multiplier at the solution (a coil's, or a warm start's), is a
/// safeguard where the multiplier is large: the l1 penalty starts at `2 |guess|`, so that the
/// first steps do not trade feasibility for cost, and the Lagrangian's Hessian keeps `guess`
/// until the least-squares multiplier is reliable (relative KKT residual below 0.1), instead
/// of swinging with it far from stationarity.
pub fn solve<P: Discretised>(
    problem: &P,
    x0: DVector<f64>,
    options: &SqpOptions,
    guess: Option<f64>,
) -> Result<SqpResult, Error> {
    solve_watched(problem, x0, options, guess, &mut |_, _, _| false)
}

/// [`solve`], with `abandon(iterations, f, c)` asked at every iterate (of the equality-only
/// iteration and of the S-l1-QP one with inequalities, `c` the equality's value): where it
/// answers `true` the solve stops there as [`Termination::Abandoned`]. Where it never does, the
/// iterates are exactly [`solve`]'s.
pub fn solve_watched<P: Discretised>(
    problem: &P,
    x0: DVector<f64>,
    options: &SqpOptions,
    guess: Option<f64>,
    abandon: &mut dyn FnMut(usize, f64, f64) -> bool,
) -> Result<SqpResult, Error> {
    let s = problem.effort_hessian();
    let hb = problem.half_bandwidth();
    let chol = problem.effort_cholesky().ok_or(Error::from(InputError::InvalidParameter {
        name: "spans".into(),
        value: s.nrows() as f64,
        expected: "a basis whose effort Hessian is positive definite",
    }))?;
    let m = Metric { s, chol, hb };
    if problem.inequalities(&x0, 0).is_some() {
        return inequality::solve(problem, x0, options, guess, &m, abandon);
    }
    let mut x = x0;
    let mut e = problem.evaluate(&x, 2);
    let (mut lambda, mut kkt, mut a_s) = multiplier(&m, &e);
    let mut radius = (m.norm(&x) * 0.5).max(1.0);
    let guess = guess.filter(|g| g.is_finite());
    let mut mu = guess.map_or(1.0, |g| (2.0 * g.abs()).max(1.0));
    let mut lambda_w = guess.unwrap_or(lambda);
    let (mut best_kkt, mut since_best, mut iterations) = (kkt, 0, 0);
    // The Lagrangian's Hessian, its band written at every iteration (zero outside it).
    let mut w = DMatrix::zeros(x.len(), x.len());
    // W's [`Factor`], kept after a rejected step (`e`, `lambda_w` and W stay as they were).
    let mut factor = None;
    let mut asked = false; // `abandon` asked at this iterate already (before its derivatives)
    let termination = loop {
        if !(e.f.is_finite() && e.c.is_finite() && kkt.is_finite()) {
            return Err(Error::from(InputError::InvalidParameter {
                name: "seed".into(),
                value: e.f,
                expected: "a finite cost",
            }));
        }
        if e.c.abs() <= options.constraint_tolerance && kkt <= options.kkt_tolerance {
            break Termination::Converged;
        }
        if e.c.abs() <= options.constraint_tolerance && since_best >= options.stall_iterations {
            break Termination::Stalled;
        }
        if iterations >= options.max_iterations {
            break Termination::MaxIterations;
        }
        if !std::mem::take(&mut asked) && abandon(iterations, e.f, e.c) {
            break Termination::Abandoned;
        }
        if radius < 1e-15 * (1.0 + m.norm(&x)) {
            break Termination::RadiusCollapsed;
        }
        iterations += 1;
        since_best += 1;
        if factor.is_none() {
            band_lagrangian(&e, m.s, lambda_w, hb, &mut w);
            factor = Some(BandCholesky::new(&w, hb).map(|c| (c.solve(&e.grad_c), c)));
        }
        let den = e.grad_c.dot(&a_s);
        if !(den > 0.0) && e.c.abs() > options.constraint_tolerance {
            break Termination::DegenerateConstraint;
        }
        // Normal step: the minimum-norm step to the linearised constraint, cut to 0.8 radius.
        let mut v = DVector::zeros(x.len());
        let mut v_norm = 0.0;
        if den > 0.0 {
            v = &a_s * (-e.c / den);
            v_norm = e.c.abs() / den.sqrt();
            if v_norm > 0.8 * radius {
                v *= 0.8 * radius / v_norm;
                v_norm = 0.8 * radius;
            }
        }
        let tangential_radius = (radius * radius - v_norm * v_norm).max(0.0).sqrt();
        let r0 = &e.grad_f + matvec(&w, hb, &v);
        // The Newton step on the constraint's tangent space when W is positive definite and the
        // step fits; else Steihaug's truncated CG.
        let newton = factor.as_ref().and_then(|f| newton_tangential(f.as_ref()?, &r0, &e.grad_c));
        let newton = newton.filter(|t| m.norm(t) <= tangential_radius);
        let t = match newton {
            Some(t) => t,
            None => steihaug(&m, &w, &r0, (&e.grad_c, &a_s, den), tangential_radius, x.len() + 5),
        };
        let d = &v + &t;
        let wd = matvec(&w, hb, &d);
        let q = e.grad_f.dot(&d) + 0.5 * d.dot(&wd);
        let linear_c = e.c + e.grad_c.dot(&d);
        let dc = e.c.abs() - linear_c.abs();
        if dc > 0.0 {
            mu = mu.max(q / (0.7 * dc) + 1e-8);
        }
        let pred = -q + mu * dc;
        let merit = e.f + mu * e.c.abs();
        let trial_x = &x + &d;
        let trial = problem.evaluate(&trial_x, 0);
        let noise = 1e-14 * (e.f.abs() + mu * e.c.abs() + 1e-300);
        let accept = |tr: &Evaluation| {
            let ared = merit - (tr.f + mu * tr.c.abs());
            let ok = tr.f.is_finite() && tr.c.is_finite();
            let ratio = if pred > noise {
                ared / pred
            } else if ared >= -noise {
                1.0
            } else {
                -1.0
            };
            (ok && ratio >= 1e-8, if ok { ratio } else { -1.0 })
        };
        let (mut accepted, mut ratio) = accept(&trial);
        let mut step = d.clone();
        if !accepted && den > 0.0 {
            // Second-order correction: back to the constraint along the metric's normal.
            let soc = &a_s * (-trial.c / den);
            let x2 = &trial_x + &soc;
            let trial2 = problem.evaluate(&x2, 0);
            let (ok2, ratio2) = accept(&trial2);
            if ok2 {
                accepted = true;
                ratio = ratio2;
                step = d + soc;
            }
        }
        let step_norm = m.norm(&step);
        if accepted {
            x += &step;
            if accept(&trial).0 && trial.c.abs() > options.constraint_tolerance && iterations < options.max_iterations {
                asked = true; // the watch before the derivatives (off the constraint, short of the limit)
                if abandon(iterations, trial.f, trial.c) {
                    (e.f, e.c) = (trial.f, trial.c);
                    break Termination::Abandoned;
                }
            }
            factor = None;
            problem.recycle(std::mem::replace(&mut e.hess_c, DMatrix::zeros(0, 0)));
            e = problem.evaluate(&x, 2);
            (lambda, kkt, a_s) = multiplier(&m, &e);
            if guess.is_none() || kkt < 0.1 {
                lambda_w = lambda;
            }
            if kkt < 0.5 * best_kkt {
                (best_kkt, since_best) = (kkt, 0);
            }
            if ratio > 0.75 && step_norm > 0.8 * radius {
                radius = (2.0 * radius).min(1e4);
            } else if ratio < 0.25 {
                radius *= 0.5;
            }
        } else {
            radius = 0.25 * step_norm.min(radius);
        }
    };
    Ok(SqpResult { x, lambda, f: e.f, c: e.c, kkt, iterations, termination, kkt_tolerance: options.kkt_tolerance })
}

/// The Lagrangian's Hessian `hess_f + lambda hess_c` ([`Evaluation::lagrangian_hessian`]) on
/// its band of half-bandwidth `hb` alone, zero outside: the iteration reads no other entry (by
/// [`matvec`] and [`BandCholesky::new`]), and the dense products cost `dim^2` per iteration.
/// Written into `w`, whose entries outside the band are zero (one matrix for every iteration of
/// a solve, not one allocated and zeroed per iteration).
fn band_lagrangian(e: &Evaluation, s: &DMatrix<f64>, lambda: f64, hb: usize, w: &mut DMatrix<f64>) {
    let h = e.hess_f_or(s);
    let n = h.nrows();
    let (hc, hf, out) = (e.hess_c.as_slice(), h.as_slice(), w.as_mut_slice());
    for col in 0..n {
        for k in col * n + col.saturating_sub(hb)..col * n + (col + hb + 1).min(n) {
            out[k] = hc[k] * lambda + hf[k];
        }
    }
}

/// Projected, `S`-preconditioned Steihaug CG for `min r0^T t + 1/2 t^T W t` subject to
/// `grad_c^T t = 0` and `|t|_S <= radius` (`normal = (grad_c, a_s, den)`, `a_s = S^-1 grad_c`,
/// `den = grad_c^T a_s`).
///
/// Where `r` is almost parallel to `grad_c` (near a KKT point), the residual is updated by its
/// component along it, `r <- r - grad_c (a_s^T r) / den`, before the projection (the residual
/// update of Gould, Hribar, Nocedal 2001; Nocedal, Wright Sec. 16.3), which leaves `z = P r`
/// unchanged in exact arithmetic: projecting `r` whole leaves a normal error of order
/// `eps cond(S) |S^-1 r|`, not small beside a projected residual `10^-6 |r|`, and the iterates
/// drift off the tangent space (steps that break the linearised constraint and are rejected over
/// and over). It is made when the update cancels three digits or more (`|r'| < 10^-3 |r|`),
/// where the plain projection is no longer accurate; elsewhere the iteration is the plain one.
fn steihaug(
    m: &Metric,
    w: &DMatrix<f64>,
    r0: &DVector<f64>,
    normal: (&DVector<f64>, &DVector<f64>, f64),
    radius: f64,
    max: usize,
) -> DVector<f64> {
    let (grad_c, a_s, den) = normal;
    let n = r0.len();
    let mut t = DVector::zeros(n);
    if radius <= 0.0 {
        return t;
    }
    let project = |r: &mut DVector<f64>| {
        if den > 0.0 {
            let updated = &*r - grad_c * (a_s.dot(r) / den);
            if updated.norm_squared() < 1e-6 * r.norm_squared() {
                *r = updated;
            }
        }
        let z = m.chol.solve(r);
        if den > 0.0 { &z - a_s * (a_s.dot(r) / den) } else { z }
    };
    let mut r = r0.clone();
    let mut z = project(&mut r);
    let mut rz = r.dot(&z);
    if !(rz > 0.0) {
        return t;
    }
    let tol = (rz.sqrt().sqrt()).min(0.1) * rz.sqrt();
    let tol = tol.max(1e-15 * rz.sqrt());
    let mut p = -&z;
    let mut st = DVector::zeros(n);
    // `W p` and `S p`, written at every iteration.
    let (mut wp, mut sp) = (DVector::zeros(n), DVector::zeros(n));
    for _ in 0..max {
        matvec_pair_into((w, m.s), m.hb, &p, (&mut wp, &mut sp));
        let kappa = p.dot(&wp);
        let pp = p.dot(&sp);
        if kappa <= 1e-14 * pp {
            return to_boundary(t, &st, &p, &sp, pp, radius);
        }
        let alpha = rz / kappa;
        let tt = t.dot(&st) + 2.0 * alpha * t.dot(&sp) + alpha * alpha * pp;
        if tt >= radius * radius {
            return to_boundary(t, &st, &p, &sp, pp, radius);
        }
        t.axpy(alpha, &p, 1.0);
        st.axpy(alpha, &sp, 1.0);
        r.axpy(alpha, &wp, 1.0);
        z = project(&mut r);
        let rz_new = r.dot(&z);
        if !(rz_new > 0.0) || rz_new.sqrt() <= tol {
            break;
        }
        let beta = rz_new / rz;
        p.axpy(-1.0, &z, beta);
        rz = rz_new;
    }
    t
}

/// `W^-1 a` with the band Cholesky factor of `W`.
type Factor = (DVector<f64>, BandCholesky);

/// The minimiser of `r0^T t + 1/2 t^T W t` subject to `a^T t = 0` when `W` is positive definite
/// (its [`Factor`]), by the range-space formula `t = -(W^-1 r0 - W^-1 a (a^T W^-1 r0) / (a^T W^-1 a))`.
fn newton_tangential((y1, chol): &Factor, r0: &DVector<f64>, a: &DVector<f64>) -> Option<DVector<f64>> {
    let y2 = chol.solve(r0);
    let den = a.dot(y1);
    let t = if den > 0.0 { -(&y2 - y1 * (a.dot(&y2) / den)) } else { -y2 };
    t.iter().all(|x| x.is_finite()).then_some(t)
}

/// `t + tau p` with `tau >= 0` on the boundary `|t + tau p|_S = radius`.
fn to_boundary(
    t: DVector<f64>,
    st: &DVector<f64>,
    p: &DVector<f64>,
    sp: &DVector<f64>,
    pp: f64,
    radius: f64,
) -> DVector<f64> {
    if !(pp > 0.0) {
        return t;
    }
    let tt = t.dot(st);
    let tp = t.dot(sp);
    let disc = (tp * tp + pp * (radius * radius - tt)).max(0.0);
    let tau = (-tp + disc.sqrt()) / pp;
    t + p * tau
}
