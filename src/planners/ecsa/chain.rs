//! The ECSA for any planar serial arm of `n` joints (issue 14): the controls `u_i(t)` of each
//! joint are the series of the 2-joint ECSA's [`Basis`], and `c` solves the end-point equation
//! `K(c) = q_d` by one of two [`ChainSolver`]s: the least-norm solution (the default,
//! `chain/min_norm.rs`) or the 2-joint ECSA's damped pseudo-inverse iteration
//! `c <- c - gamma J#(c) wrap(K(c) - qd)` from the straight line, whose first step overshoots
//! into large harmonics when the base must turn by loops (see `chain/min_norm.rs`).
//!
//! **The end-point map is a quadrature along an explicit path.** With `theta' = u` the joint
//! angles are explicit functions of the coefficients,
//! `theta_i(t) = theta_i0 + sum_j c_ij A_j(t)` with the closed-form antiderivatives
//! [`Basis::antiderivatives`], so `theta(T) = theta0 + sum_j c_ij A_j(T)` is linear in `c`, and
//! Eq. (7) at zero momentum integrates to
//! $$\varphi(T) = \varphi_0 - \int_0^T a(\theta(t)) \cdot u(t)\, dt, \quad a = G/F,$$
//! one scalar for any `n`. No ODE is solved: the integral is a composite Gauss–Legendre rule
//! ([`NODES`] nodes on each of `pieces` equal pieces), and its gradient in `c` is exact,
//! `d phi(T)/d c_ij = -int (dg/dtheta_i A_j + a_i phi_j) dt` with `g = a . u` and `dg/dtheta`
//! in closed form ([`Connection::local`], held to num-dual's derivatives of
//! [`Arm::momentum_coefficients`] by its tests and by `gradient_matches_num_dual_and_differences`
//! here).
//!
//! **Quadrature rule**: the iteration starts with `64 H` pieces of [`NODES`] nodes. When it has
//! converged the holonomy integral is recomputed with twice the pieces; if the two differ by more
//! than 1% of the residual tolerance the pieces are doubled and the iteration continues from
//! the current `c` (up to [`MAX_PIECES`]); the residual on the finer rule then replaces the last
//! entry of the residual history, which can therefore rise after a small residual. The plan is returned only when certified by
//! [`verify_chain`] (the system integrated with the planned controls by the adaptive
//! integrator), independent of the rule.

use std::sync::Arc;
use std::time::Instant;

use nalgebra::{DMatrix, DVector};
use num_dual::Dual64;
use serde::Serialize;

use super::{Basis, EcsaOptions, IterationStats, Termination, Window};
use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::Arm;
use crate::model::wrap_angle;
use crate::numerics::ode::OdeStats;
use crate::numerics::quadrature::GaussLegendre;
use crate::plan::chain_certificate::{ChainVerification, JointMotion, verify_chain};
use crate::planners::chain::connection::{Connection, Local};
use crate::planners::chain::{ChainPoint, ChainProblem, MAX_JOINTS};

/// Gauss–Legendre nodes per piece of the holonomy integral.
pub const NODES: usize = 16;
/// The largest number of pieces of the holonomy integral.
pub const MAX_PIECES: usize = 1024;

/// The [`NODES`]-node rule, computed once.
fn rule() -> &'static GaussLegendre {
    static RULE: std::sync::OnceLock<GaussLegendre> = std::sync::OnceLock::new();
    RULE.get_or_init(|| GaussLegendre::new(NODES))
}

/// The end-point map of an `n`-joint arm at one `c` and its exact Jacobian.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainEndPoint {
    /// `K(c) = (phi(T), theta(T))` \[rad\].
    pub q: Vec<f64>,
    /// `dK/dc`, `n + 1` rows by `n (2H + 1)` columns.
    pub jacobian: DMatrix<f64>,
}

/// How the `n`-joint ECSA solves `K(c) = q_d`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ChainSolver {
    /// `min |c|^2` s.t. `K(c) = q_d` by Lagrange–Newton with continuation in the base's target
    /// from the straight line (`chain/min_norm.rs`). Default.
    #[default]
    MinimumNorm,
    /// The 2-joint ECSA's damped pseudo-inverse iteration from its initial guess (at `n = 2` it
    /// reaches the 2-joint [`super::EcsaPlanner`]'s coefficients).
    PseudoInverse,
}

impl ChainSolver {
    /// `minimum-norm` or `pseudo-inverse`.
    pub fn name(self) -> &'static str {
        match self {
            ChainSolver::MinimumNorm => "minimum-norm",
            ChainSolver::PseudoInverse => "pseudo-inverse",
        }
    }
}

/// What a solver returns.
struct Solved {
    c: DVector<f64>,
    iteration: IterationStats,
    pieces: usize,
    change: f64,
    continuation_steps: usize,
}

/// The account of an `n`-joint ECSA plan.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainEcsaStats {
    /// Harmonics `H` of the basis.
    pub harmonics: usize,
    /// The window of the series.
    pub window: Window,
    /// The solver.
    pub solver: ChainSolver,
    /// `c = (c_10, .., c_1,2H, .., c_n0, .., c_n,2H)` \[rad/s\].
    pub coefficients: Vec<f64>,
    /// Iterations (Newton steps), residual history `|K(c) - q_s|_inf` (for the minimum-norm
    /// solver at the continuation's current target), termination (`ode` is zero: no ODE is
    /// solved).
    pub iteration: IterationStats,
    /// Steps of the continuation in the base's target (0 for the pseudo-inverse iteration).
    pub continuation_steps: usize,
    /// Pieces of the composite Gauss–Legendre rule of the holonomy integral.
    pub quadrature_pieces: usize,
    /// Nodes per piece.
    pub quadrature_nodes: usize,
    /// `|phi(T)|` with twice the pieces minus with the pieces, at the solution \[rad\].
    pub quadrature_change: f64,
    /// The effort `integral_0^T |u|^2 dt` \[rad^2/s\].
    pub effort: f64,
    /// Wall time of the iteration \[s\].
    pub plan_seconds: f64,
}

/// The ECSA for an `n`-joint arm (see the [module docs](self)).
#[derive(Debug, Clone)]
pub struct ChainEcsaPlanner {
    arm: Arm,
    connection: Arc<Connection>,
    /// Options (`samples` is not used: the caller samples the plan; `gamma` and `damping` are
    /// the pseudo-inverse iteration's).
    pub options: EcsaOptions,
    /// The solver; default [`ChainSolver::MinimumNorm`].
    pub solver: ChainSolver,
}

impl ChainEcsaPlanner {
    /// A planner for `arm`.
    pub fn new(arm: Arm, options: EcsaOptions) -> Self {
        let connection = Arc::new(Connection::new(&arm));
        Self { arm, connection, options, solver: ChainSolver::default() }
    }

    /// This planner with `solver`.
    pub fn with_solver(self, solver: ChainSolver) -> Self {
        Self { solver, ..self }
    }

    /// The arm.
    pub fn arm(&self) -> &Arm {
        &self.arm
    }

    fn basis(&self, horizon: f64) -> Result<Basis, Error> {
        self.options.validate()?;
        Basis::new(self.options.harmonics, horizon, self.options.window)
    }

    fn check(&self, start: &[f64], coefficients: Option<(&Basis, &[f64])>) -> Result<(), Error> {
        let n = self.arm.joints();
        let bad = |name: &str, value: usize, expected: &'static str| {
            Err(Error::from(InputError::InvalidParameter { name: name.into(), value: value as f64, expected }))
        };
        if !(1..=MAX_JOINTS).contains(&n) {
            return bad("joints", n, "an arm of 1 to 15 joints");
        }
        if start.len() != n + 1 {
            return bad("start.len", start.len(), "n + 1 values (phi, theta_1..theta_n)");
        }
        match coefficients {
            Some((basis, c)) if c.len() != n * basis.terms() => {
                bad("coefficients", c.len(), "n (2H + 1) coefficients for n joints and H harmonics")
            }
            _ => Ok(()),
        }
    }

    /// `K(c)` and its exact Jacobian from `start` (`n + 1` angles) over `horizon` \[s\], with
    /// `pieces` pieces of the quadrature.
    pub fn end_point(&self, start: &[f64], horizon: f64, c: &[f64], pieces: usize) -> Result<ChainEndPoint, Error> {
        let basis = self.basis(horizon)?;
        self.check(start, Some((&basis, c)))?;
        Ok(self.evaluate(&basis, start, c, pieces, true))
    }

    /// `K(c)` alone.
    pub fn end_point_map(&self, start: &[f64], horizon: f64, c: &[f64], pieces: usize) -> Result<Vec<f64>, Error> {
        let basis = self.basis(horizon)?;
        self.check(start, Some((&basis, c)))?;
        Ok(self.evaluate(&basis, start, c, pieces, false).q)
    }

    fn evaluate(&self, basis: &Basis, start: &[f64], c: &[f64], pieces: usize, with_jacobian: bool) -> ChainEndPoint {
        let n = self.arm.joints();
        let m = basis.terms();
        let pieces = pieces.clamp(1, MAX_PIECES);
        let h = basis.horizon() / pieces as f64;
        let (mut theta, mut u) = (vec![0.0; n], vec![0.0; n]);
        let mut local = Local::new(n);
        let mut integral = 0.0;
        let mut gradient = vec![0.0; if with_jacobian { n * m } else { 0 }];
        let r = rule();
        for piece in 0..pieces {
            let a = piece as f64 * h;
            for (x, w) in r.nodes.iter().zip(&r.weights) {
                let t = a + 0.5 * h * (1.0 + x);
                let weight = 0.5 * h * w;
                let (b, anti) = (basis.values(t), basis.antiderivatives(t));
                path(start, c, m, &b, &anti, &mut theta, &mut u);
                if with_jacobian {
                    self.connection.local(&theta, &u, &mut local);
                    integral += weight * local.value;
                    for i in 0..n {
                        let (gi, ai) = (weight * local.gradient[i], weight * local.a[i]);
                        for j in 0..m {
                            gradient[i * m + j] += gi * anti[j] + ai * b[j];
                        }
                    }
                } else {
                    integral += weight * self.connection.value(&theta, &u);
                }
            }
        }
        let ends = basis.integrals();
        let mut q = vec![start[0] - integral];
        let mut jacobian = DMatrix::zeros(if with_jacobian { n + 1 } else { 0 }, n * m);
        for i in 0..n {
            q.push(start[i + 1] + (0..m).map(|j| c[i * m + j] * ends[j]).sum::<f64>());
            if with_jacobian {
                for j in 0..m {
                    jacobian[(0, i * m + j)] = -gradient[i * m + j];
                    jacobian[(i + 1, i * m + j)] = ends[j];
                }
            }
        }
        ChainEndPoint { q, jacobian }
    }

    /// Solves `K(c) = q_d` with the planner's [`ChainSolver`] to the residual tolerance, with
    /// the quadrature rule of the [module docs](self). Non-convergence is
    /// [`Error::EcsaFailed`] with the statistics.
    pub fn solve(&self, problem: &ChainProblem) -> Result<ChainEcsaStats, Error> {
        let clock = Instant::now();
        problem.validate(&self.arm)?;
        if let Some(&value) = problem.initial_velocity.iter().find(|v| **v != 0.0) {
            return Err(Error::from(InputError::InvalidParameter {
                name: "start velocity".into(),
                value,
                expected: "zero: the ECSA plans from rest; the optimal planner takes a moving start",
            }));
        }
        let basis = self.basis(problem.horizon)?;
        let solved = match self.solver {
            ChainSolver::MinimumNorm => self.minimum_norm(&basis, problem)?,
            ChainSolver::PseudoInverse => self.pseudo_inverse(&basis, problem)?,
        };
        let coefficients = solved.c.as_slice().to_vec();
        let effort = effort(&basis, self.arm.joints(), &coefficients, solved.pieces);
        Ok(ChainEcsaStats {
            harmonics: basis.harmonics(),
            window: basis.window(),
            solver: self.solver,
            coefficients,
            iteration: solved.iteration,
            continuation_steps: solved.continuation_steps,
            quadrature_pieces: solved.pieces,
            quadrature_nodes: NODES,
            quadrature_change: solved.change,
            effort,
            plan_seconds: clock.elapsed().as_secs_f64(),
        })
    }

    /// [`ChainSolver::PseudoInverse`]: the 2-joint ECSA's iteration from its initial guess
    /// (constant terms moving each joint from `theta_i0` to `theta_id` literally).
    fn pseudo_inverse(&self, basis: &Basis, problem: &ChainProblem) -> Result<Solved, Error> {
        let o = &self.options;
        let (n, m) = (self.arm.joints(), basis.terms());
        let (start, goal) = (&problem.start, &problem.goal);
        let integral = basis.integrals()[0];
        let mut c = DVector::<f64>::zeros(n * m);
        for i in 0..n {
            c[i * m] = (goal[i + 1] - start[i + 1]) / integral;
        }
        let mut pieces = (64 * basis.harmonics()).min(MAX_PIECES);
        let mut history = Vec::new();
        let mut iterations = 0;
        let mut change = f64::NAN;
        loop {
            let k = self.evaluate(basis, start, c.as_slice(), pieces, true);
            // `wrap`: angles modulo 2 pi (as the 2-joint ECSA); else the goal literally.
            let error =
                DVector::from_fn(
                    n + 1,
                    |i, _| {
                        if problem.wrap { wrap_angle(k.q[i] - goal[i]) } else { k.q[i] - goal[i] }
                    },
                );
            let finite = error.iter().all(|e| e.is_finite());
            let residual = if finite { error.amax() } else { f64::NAN };
            history.push(residual);
            let mut stop = if !finite {
                Some(Termination::NonFinite)
            } else if residual <= o.residual_tolerance {
                // Converged on this rule: check it against twice the pieces.
                let fine = self.evaluate(basis, start, c.as_slice(), 2 * pieces, false);
                change = (fine.q[0] - k.q[0]).abs();
                if change <= 0.01 * o.residual_tolerance || 2 * pieces > MAX_PIECES {
                    Some(Termination::Converged)
                } else {
                    pieces *= 2;
                    history.pop();
                    continue;
                }
            } else if iterations >= o.max_iterations {
                Some(Termination::MaxIterations)
            } else {
                None
            };
            let mut step = None;
            if stop.is_none() {
                let j = &k.jacobian;
                let gram = j * j.transpose() + DMatrix::<f64>::identity(n + 1, n + 1) * (o.damping * o.damping);
                match gram.cholesky() {
                    Some(cholesky) => step = Some(j.transpose() * cholesky.solve(&error)),
                    None => stop = Some(Termination::SingularJacobian),
                }
            }
            if let Some(termination) = stop {
                let iteration = IterationStats {
                    iterations,
                    residual,
                    tolerance: o.residual_tolerance,
                    residual_history: history,
                    termination,
                    ode: OdeStats::default(),
                };
                if termination != Termination::Converged {
                    return Err(Error::EcsaFailed { stats: iteration });
                }
                return Ok(Solved { c, iteration, pieces, change, continuation_steps: 0 });
            }
            if let Some(step) = step {
                c -= step * o.gamma;
            }
            iterations += 1;
        }
    }

    /// Solves, and certifies the motion with [`verify_chain`] to `options.tolerance`; a motion
    /// that fails its certificate is [`Error::NotCertified`].
    pub fn plan(&self, problem: &ChainProblem) -> Result<ChainEcsaPlan, Error> {
        let stats = self.solve(problem)?;
        let basis = self.basis(problem.horizon)?;
        let mut plan = ChainEcsaPlan::new(self.connection.clone(), basis, &problem.start, stats);
        let o = &self.options;
        let verification = verify_chain(&self.arm, &plan, &problem.start, &problem.goal, &o.ode, o.tolerance)?;
        if !verification.certified {
            return Err(Error::NotCertified {
                final_error: verification.final_error,
                tolerance: verification.tolerance,
                level: "velocity",
            });
        }
        plan.verification = verification;
        Ok(plan)
    }
}

/// `theta = theta0 + C A`, `u = C b` for the basis values `b` and antiderivatives `anti`.
fn path(start: &[f64], c: &[f64], m: usize, b: &[f64], anti: &[f64], theta: &mut [f64], u: &mut [f64]) {
    for i in 0..theta.len() {
        let ci = &c[i * m..(i + 1) * m];
        theta[i] = start[i + 1] + ci.iter().zip(anti).map(|(c, a)| c * a).sum::<f64>();
        u[i] = ci.iter().zip(b).map(|(c, b)| c * b).sum();
    }
}

/// `integral_0^T |u|^2 dt` by the composite rule (exact for the trigonometric polynomials).
fn effort(basis: &Basis, n: usize, c: &[f64], pieces: usize) -> f64 {
    let m = basis.terms();
    rule().integrate_composite(0.0, basis.horizon(), pieces, |t| {
        let b = basis.values(t);
        (0..n).map(|i| (0..m).map(|j| c[i * m + j] * b[j]).sum::<f64>().powi(2)).sum()
    })
}

/// A certified `n`-joint ECSA plan: the joint motion in closed form, the base angle by the
/// holonomy integral from the nearest breakpoint.
#[derive(Debug, Clone)]
pub struct ChainEcsaPlan {
    connection: Arc<Connection>,
    basis: Basis,
    theta0: Vec<f64>,
    /// The breakpoints of the quadrature's pieces and `phi` there.
    breakpoints: Vec<f64>,
    phi_at_breakpoints: Vec<f64>,
    /// The iteration's account.
    pub stats: ChainEcsaStats,
    /// The velocity-level certificate.
    pub verification: ChainVerification,
}

impl ChainEcsaPlan {
    fn new(connection: Arc<Connection>, basis: Basis, start: &[f64], stats: ChainEcsaStats) -> Self {
        let pieces = stats.quadrature_pieces;
        let horizon = basis.horizon();
        let breakpoints: Vec<f64> =
            (0..=pieces).map(|i| if i == pieces { horizon } else { horizon * i as f64 / pieces as f64 }).collect();
        let mut me = Self {
            connection,
            basis,
            theta0: start[1..].to_vec(),
            breakpoints,
            phi_at_breakpoints: vec![start[0]],
            stats,
            verification: ChainVerification::pending(),
        };
        for i in 0..pieces {
            let next = me.phi_at_breakpoints[i] - me.holonomy(me.breakpoints[i], me.breakpoints[i + 1]);
            me.phi_at_breakpoints.push(next);
        }
        me
    }

    /// `integral_a^b a(theta) . u dt` by the [`NODES`]-node rule.
    fn holonomy(&self, a: f64, b: f64) -> f64 {
        let n = self.joints();
        let (mut theta, mut rate) = (vec![0.0; n], vec![0.0; n]);
        rule().integrate(a, b, |t| {
            self.state_into(t, &mut theta, &mut rate);
            self.connection.value(&theta, &rate)
        })
    }

    fn state_into(&self, t: f64, theta: &mut [f64], rate: &mut [f64]) {
        let t = t.clamp(0.0, self.horizon());
        let m = self.basis.terms();
        let (b, anti) = (self.basis.values(t), self.basis.antiderivatives(t));
        let c = &self.stats.coefficients;
        for i in 0..theta.len() {
            let ci = &c[i * m..(i + 1) * m];
            theta[i] = self.theta0[i] + ci.iter().zip(&anti).map(|(c, a)| c * a).sum::<f64>();
            rate[i] = ci.iter().zip(&b).map(|(c, b)| c * b).sum();
        }
    }

    /// The number of joints.
    pub fn joints(&self) -> usize {
        self.theta0.len()
    }

    /// The horizon `T` \[s\].
    pub fn horizon(&self) -> f64 {
        self.basis.horizon()
    }

    /// The control basis.
    pub fn basis(&self) -> &Basis {
        &self.basis
    }

    /// The base angle at `t` \[rad\].
    pub fn phi(&self, t: f64) -> f64 {
        let t = t.clamp(0.0, self.horizon());
        let pieces = self.breakpoints.len() - 1;
        let s = ((t / self.horizon() * pieces as f64) as usize).min(pieces - 1);
        let b = self.breakpoints[s];
        if t <= b {
            return self.phi_at_breakpoints[s];
        }
        self.phi_at_breakpoints[s] - self.holonomy(b, t)
    }

    /// `(phi, theta, theta', theta'')` at `t` \[s\] (clamped to `[0, T]`).
    pub fn at(&self, t: f64) -> ChainPoint {
        let t = t.clamp(0.0, self.horizon());
        let n = self.joints();
        let (mut theta, mut rate, mut acceleration) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        self.state_into(t, &mut theta, &mut rate);
        self.joint_acceleration(t, &mut acceleration);
        ChainPoint { t, phi: self.phi(t), theta, rate, acceleration }
    }

    /// `samples >= 2` equally spaced points from 0 to T, the last exactly at T.
    pub fn sample(&self, samples: usize) -> Vec<ChainPoint> {
        let samples = samples.max(2);
        let horizon = self.horizon();
        (0..samples)
            .map(|i| if i + 1 == samples { horizon } else { horizon * i as f64 / (samples - 1) as f64 })
            .map(|t| self.at(t))
            .collect()
    }
}

impl JointMotion for ChainEcsaPlan {
    fn joints(&self) -> usize {
        self.theta0.len()
    }

    fn breakpoints(&self) -> &[f64] {
        &self.breakpoints
    }

    fn joint_state(&self, t: f64, theta: &mut [f64], rate: &mut [f64]) {
        self.state_into(t, theta, rate);
    }

    fn phi_rate(&self, t: f64) -> f64 {
        let n = self.joints();
        let (mut theta, mut rate) = (vec![0.0; n], vec![0.0; n]);
        self.state_into(t, &mut theta, &mut rate);
        -self.connection.value(&theta, &rate)
    }

    fn joint_acceleration(&self, t: f64, out: &mut [f64]) {
        let m = self.basis.terms();
        let d = self.basis.values(Dual64::new(t.clamp(0.0, self.horizon()), 1.0));
        let c = &self.stats.coefficients;
        for (i, o) in out.iter_mut().enumerate() {
            *o = (0..m).map(|j| c[i * m + j] * d[j].eps).sum();
        }
    }
}

mod min_norm;

#[cfg(test)]
mod tests;
