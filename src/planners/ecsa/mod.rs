//! The Endogenous Configuration Space Approach (ECSA), the paper's reference method (Sec. 5,
//! Figs. 9-12), one engine for any planar serial arm of `n` joints, `n = 2` included: the
//! controls `u_i(t) = theta_i'` of each joint are a trigonometric series (constant terms and the
//! first harmonics, [`Basis`]) with coefficient vector `c` (the endogenous configuration), and
//! `c` solves the end-point equation `K(c) = q_d` by one of two [`ChainSolver`]s: the paper's
//! damped pseudo-inverse iteration
//! $$c \leftarrow c - \gamma J^{\#}(c)\, \mathrm{wrap}(K(c) - q_d), \quad
//! J^{\#} = J^\top (J J^\top + \lambda^2 I)^{-1},$$
//! from the straight line ([`ChainSolver::PseudoInverse`], the 2-link [`EcsaPlanner`]'s, the
//! paper's reproduction), or the least-norm solution (`min_norm.rs`,
//! [`ChainSolver::MinimumNorm`], the default for arms of more joints: the pseudo-inverse's first
//! step overshoots into large harmonics when the base must turn by loops). Every 2-link arm, the
//! paper's robot through any pipeline, takes the paper's iteration
//! ([`crate::planners::arm::plan_arm`]).
//!
//! **Initial guess**: all harmonics zero and the constant terms that move each joint from
//! `theta_i0` to `theta_id` ([`Basis::initial_guess`]): a linear joint motion (or its
//! `sin^2`-shaped counterpart with the window); only `phi` is then off.
//!
//! **Which controls the paper used**: the plain series ([`Window::None`], the default), whose
//! joint velocities do not vanish at `t = 0` and `t = T` (docs/spec.md §6, item 8): report it, the
//! plan's `trajectory.dq` shows the jump. [`Window::SinSquared`] gives plans that start and end
//! at rest, like the NFA's.
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
//!
//! The 2-link robot ([`EcsaPlanner`] on a [`crate::plan::PlanningProblem`], `paper.rs`) is this engine on
//! [`Arm::from_params`] with the pseudo-inverse iteration; its motion ([`EcsaMotion`]) is the
//! engine's plan seen as a 2-link [`crate::plan::Motion`].
//!
//! ## Reference
//! K. Tchoń, J. Jakubiak, *Endogenous configuration space approach to mobile manipulators: a
//! derivation and performance assessment of Jacobian inverse kinematics algorithms*,
//! Int. J. Control 76(14) (2003) 1387–1419, doi:10.1080/0020717031000099029.

pub mod basis;
mod min_norm;
mod motion;
mod paper;
mod plan;

pub use crate::numerics::iteration::{IterationStats, Termination};
pub use basis::{Basis, MAX_HARMONICS, Window};
pub use motion::EcsaMotion;
pub use paper::{EcsaPlanner, EcsaSolution, EndPoint};
pub use plan::ChainEcsaPlan;

use std::sync::Arc;
use std::time::Instant;

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::error::Error;
use crate::model::InputError;
use crate::model::arm::Arm;
use crate::model::wrap_angle;
use crate::numerics::ode::{OdeOptions, OdeStats};
use crate::numerics::quadrature::GaussLegendre;
use crate::plan::certificate::verify_chain;
use crate::planners::chain::connection::{Connection, Local};
use crate::planners::chain::{ChainProblem, MAX_JOINTS};

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
    /// from the straight line (`min_norm.rs`). Default.
    #[default]
    MinimumNorm,
    /// The 2-joint ECSA's damped pseudo-inverse iteration from its initial guess (the paper's; the 2-link
    /// [`EcsaPlanner`]'s).
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

    /// The arm's connection (shared with the plans).
    fn connection(&self) -> Arc<Connection> {
        self.connection.clone()
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

/// Options of the [`EcsaPlanner`]; every default is the one documented on its field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EcsaOptions {
    /// Number of harmonics `H` of the control basis, 1 to [`MAX_HARMONICS`]; default 1 (the
    /// paper's: 6 coefficients).
    pub harmonics: usize,
    /// Window of the series; default [`Window::None`] (the paper's).
    pub window: Window,
    /// Residual tolerance of the iteration \[rad\]; default 1e-10 (docs/spec.md §4).
    pub residual_tolerance: f64,
    /// Largest number of updates of `c`; default 50.
    pub max_iterations: usize,
    /// Step length `gamma` in (0, 1]; default 1 (Newton-like).
    pub gamma: f64,
    /// Damping `lambda >= 0` of the pseudo-inverse `J^T (J J^T + lambda^2 I)^-1`; default 1e-6
    /// (with `J J^T` of order `T^2` this perturbs the step by ~1e-14 relative, keeping
    /// quadratic convergence while guarding against a rank-deficient `J`).
    pub damping: f64,
    /// Number of samples of the trajectory, including both ends; default 1001.
    pub samples: usize,
    /// Integrator options of `K`, `J`, the samples and the verification (default
    /// rtol = atol = 1e-12).
    pub ode: OdeOptions,
    /// Tolerance of the verified final error \[rad\]; default 1e-9 (docs/spec.md §2).
    pub tolerance: f64,
}

impl Default for EcsaOptions {
    fn default() -> Self {
        Self {
            harmonics: 1,
            window: Window::None,
            residual_tolerance: 1e-10,
            max_iterations: 50,
            gamma: 1.0,
            damping: 1e-6,
            samples: 1001,
            ode: OdeOptions::default(),
            tolerance: 1e-9,
        }
    }
}

impl EcsaOptions {
    /// These options with `harmonics` harmonics (1 to [`MAX_HARMONICS`]).
    pub fn with_harmonics(self, harmonics: usize) -> Result<Self, Error> {
        let options = Self { harmonics, ..self };
        options.validate()?;
        Ok(options)
    }

    /// These options with the window `window`.
    pub fn with_window(self, window: Window) -> Self {
        Self { window, ..self }
    }

    /// These options with at most `max_iterations` updates.
    pub fn with_max_iterations(self, max_iterations: usize) -> Self {
        Self { max_iterations, ..self }
    }

    /// Checks every option's range.
    pub fn validate(&self) -> Result<(), Error> {
        let bad = |name: &str, value: f64, expected: &'static str| {
            Err(Error::from(InputError::InvalidParameter { name: name.into(), value, expected }))
        };
        if !(1..=MAX_HARMONICS).contains(&self.harmonics) {
            return bad("harmonics", self.harmonics as f64, "1 to 4 harmonics");
        }
        if !(self.residual_tolerance > 0.0) {
            return bad("residual_tolerance", self.residual_tolerance, "a positive number [rad]");
        }
        if !(self.gamma > 0.0 && self.gamma <= 1.0) {
            return bad("gamma", self.gamma, "a step length in (0, 1]");
        }
        if !(self.damping >= 0.0 && self.damping.is_finite()) {
            return bad("damping", self.damping, "a finite number >= 0");
        }
        crate::plan::limits::check_samples("samples", self.samples as u64)?;
        crate::plan::limits::check_tolerance("tolerance", self.tolerance)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_n;
