//! The Endogenous Configuration Space Approach (ECSA), the paper's reference method (Sec. 5,
//! Figs. 9-12): trigonometric controls with constant terms and the first harmonics, steered to
//! the goal by the Jacobian pseudo-inverse of the end-point map.
//!
//! The controls `u(t) = (theta1', theta2')` of system (7) are parametrised by a coefficient
//! vector `c` in the [`Basis`] (the endogenous configuration). The end-point map
//! `K(c) = q(T)` integrates (7) from `q0`; its Jacobian `J(c) = dK/dc` comes from the
//! variational equations
//! $$\dot{\xi} = \frac{\partial (g(q) u)}{\partial q} \xi + g(q) \frac{\partial u}{\partial c},
//! \quad \xi(0) = 0,$$
//! integrated alongside (7): the state is carried as vector dual numbers
//! ([`num_dual::DualSVec64`]), so `dg/dq` is exact (AD) and the dual parts are the exact
//! derivative of the discrete solution. The iteration is
//! $$c \leftarrow c - \gamma J^{\#}(c)\, \mathrm{wrap}(K(c) - q_d), \quad
//! J^{\#} = J^\top (J J^\top + \lambda^2 I)^{-1},$$
//! the damped Moore–Penrose pseudo-inverse, with the angle errors wrapped to (-pi, pi].
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
//! ## Reference
//! K. Tchoń, J. Jakubiak, *Endogenous configuration space approach to mobile manipulators: a
//! derivation and performance assessment of Jacobian inverse kinematics algorithms*,
//! Int. J. Control 76(14) (2003) 1387–1419, doi:10.1080/0020717031000099029.

pub mod basis;
pub mod chain;
mod motion;

use std::time::Instant;

use nalgebra::{Const, Matrix3, SMatrix, SVector, U1, Vector3};
use num_dual::{Derivative, DualSVec64};

pub use basis::{Basis, MAX_HARMONICS, Window};
pub use chain::{ChainEcsaPlan, ChainEcsaPlanner, ChainEcsaStats, ChainSolver};
pub use motion::EcsaMotion;

use crate::error::Error;
use crate::model::system::velocity;
use crate::model::{Configuration, InputError, Lumped, wrap_angle};
pub use crate::numerics::iteration::{IterationStats, Termination};
use crate::numerics::ode::{OdeOptions, OdeStats, integrate};
use crate::plan::{Method, Plan, PlanningProblem};
use crate::planners::{Details, Planned, Planner};

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

/// The result of the ECSA iteration: the controls' coefficients and the statistics.
#[derive(Debug, Clone, PartialEq)]
pub struct EcsaSolution {
    /// The control basis.
    pub basis: Basis,
    /// `c = (c_10, ..., c_1,2H, c_20, ..., c_2,2H)` \[rad/s\].
    pub coefficients: Vec<f64>,
    /// `K(c)`, the end point reached by the iteration's last integration \[rad\].
    pub reached: Configuration,
    /// Iterations, residuals, termination.
    pub stats: IterationStats,
}

/// The end-point map and its Jacobian at one `c`.
#[derive(Debug, Clone, PartialEq)]
pub struct EndPoint {
    /// `K(c) = q(T)` \[rad\].
    pub q: Configuration,
    /// `J = dK/dc`, 3 rows (`phi, theta1, theta2`) by `2 (2H + 1)` columns.
    pub jacobian: nalgebra::DMatrix<f64>,
    /// Integrator work.
    pub ode: OdeStats,
}

/// The Endogenous Configuration Space Approach (see the [module docs](self)).
///
/// ```
/// use freefloat::{EcsaOptions, EcsaPlanner, Planner, PlanningProblem, RobotParams};
/// let problem = PlanningProblem::paper(RobotParams::src());
/// let plan = EcsaPlanner::new(EcsaOptions::default()).plan(&problem).unwrap().plan;
/// assert!(plan.verification.final_error <= 1e-9);
/// assert!(plan.iterations.unwrap() < 20);
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EcsaPlanner {
    /// Options.
    pub options: EcsaOptions,
}

impl EcsaPlanner {
    /// A planner with these options.
    pub fn new(options: EcsaOptions) -> Self {
        Self { options }
    }

    fn basis(&self, problem: &PlanningProblem) -> Result<Basis, Error> {
        self.options.validate()?;
        Basis::new(self.options.harmonics, problem.horizon, self.options.window)
    }

    /// The end-point map `K(c)` and its Jacobian from the variational equations, for
    /// coefficients `c` of length `2 (2H + 1)`.
    pub fn end_point(&self, problem: &PlanningProblem, coefficients: &[f64]) -> Result<EndPoint, Error> {
        let basis = self.basis(problem)?;
        check_length(&basis, coefficients)?;
        let k = problem.robot.lumped();
        macro_rules! dispatch {
            ($($h:literal => $p:literal),*) => {
                match basis.harmonics() {
                    $($h => {
                        let (q, j, ode) =
                            end_point_dual::<$p>(&k, &basis, &problem.start, coefficients, &self.options.ode)?;
                        Ok(EndPoint {
                            q: Configuration::from_array(q),
                            jacobian: nalgebra::DMatrix::from_fn(3, $p, |r, c| j[(r, c)]),
                            ode,
                        })
                    })*
                    h => Err(harmonics_error(h)),
                }
            };
        }
        dispatch!(1 => 6, 2 => 10, 3 => 14, 4 => 18)
    }

    /// The end-point map `K(c)` alone, by integrating (7) in `f64`.
    pub fn end_point_map(&self, problem: &PlanningProblem, coefficients: &[f64]) -> Result<Configuration, Error> {
        let basis = self.basis(problem)?;
        check_length(&basis, coefficients)?;
        let flow = Flow { k: problem.robot.lumped(), basis, coefficients, ode: self.options.ode };
        Ok(Configuration::from_array(flow.advance(0.0, problem.start.to_array(), problem.horizon)?))
    }

    /// Runs the pseudo-inverse iteration from the initial guess to the residual tolerance.
    /// Non-convergence is [`Error::EcsaFailed`] with the statistics.
    pub fn solve(&self, problem: &PlanningProblem) -> Result<EcsaSolution, Error> {
        let basis = self.basis(problem)?;
        match basis.harmonics() {
            1 => self.iterate::<6>(problem, basis),
            2 => self.iterate::<10>(problem, basis),
            3 => self.iterate::<14>(problem, basis),
            4 => self.iterate::<18>(problem, basis),
            h => Err(harmonics_error(h)),
        }
    }

    fn iterate<const P: usize>(&self, problem: &PlanningProblem, basis: Basis) -> Result<EcsaSolution, Error> {
        let o = &self.options;
        let k = problem.robot.lumped();
        let (start, goal) = (problem.start, problem.goal);
        let displacement = [goal.theta1 - start.theta1, goal.theta2 - start.theta2];
        let mut c = SVector::<f64, P>::from_column_slice(&basis.initial_guess(displacement));
        let goal = Vector3::from(goal.to_array());
        let mut history = Vec::new();
        let mut ode = OdeStats::default();
        let mut iterations = 0;
        loop {
            let (q, jacobian, stats) = end_point_dual::<P>(&k, &basis, &start, c.as_slice(), &o.ode)?;
            ode.accepted += stats.accepted;
            ode.rejected += stats.rejected;
            ode.evaluations += stats.evaluations;
            let error = Vector3::from_fn(|i, _| wrap_angle(q[i] - goal[i]));
            let finite = error.iter().all(|e| e.is_finite());
            let residual = if finite { error.amax() } else { f64::NAN };
            history.push(residual);
            let mut stop = if !finite {
                Some(Termination::NonFinite)
            } else if residual <= o.residual_tolerance {
                Some(Termination::Converged)
            } else if iterations >= o.max_iterations {
                Some(Termination::MaxIterations)
            } else {
                None
            };
            let mut step = None;
            if stop.is_none() {
                let gram = jacobian * jacobian.transpose() + Matrix3::identity() * (o.damping * o.damping);
                match gram.cholesky() {
                    Some(cholesky) => step = Some(jacobian.transpose() * cholesky.solve(&error)),
                    None => stop = Some(Termination::SingularJacobian),
                }
            }
            if let Some(termination) = stop {
                let stats = IterationStats {
                    iterations,
                    residual,
                    tolerance: o.residual_tolerance,
                    residual_history: history,
                    termination,
                    ode,
                };
                if termination != Termination::Converged {
                    return Err(Error::EcsaFailed { stats });
                }
                return Ok(EcsaSolution {
                    basis,
                    coefficients: c.as_slice().to_vec(),
                    reached: Configuration::from_array(q),
                    stats,
                });
            }
            if let Some(step) = step {
                c -= step * o.gamma;
            }
            iterations += 1;
        }
    }

    /// The planned motion of a solution: its controls, and the configurations at `samples`
    /// equally spaced times from a dense integration of (7).
    pub fn motion(&self, problem: &PlanningProblem, solution: &EcsaSolution) -> Result<EcsaMotion, Error> {
        self.options.validate()?;
        check_length(&solution.basis, &solution.coefficients)?;
        let n = self.options.samples;
        let horizon = solution.basis.horizon();
        let flow = Flow {
            k: problem.robot.lumped(),
            basis: solution.basis,
            coefficients: &solution.coefficients,
            ode: self.options.ode,
        };
        let dt = horizon / (n - 1) as f64;
        let mut t = Vec::with_capacity(n);
        let mut q = Vec::with_capacity(n);
        t.push(0.0);
        q.push(problem.start.to_array());
        for i in 1..n {
            let ti = if i + 1 == n { horizon } else { i as f64 * dt };
            let qi = flow.advance(t[i - 1], q[i - 1], ti)?;
            t.push(ti);
            q.push(qi);
        }
        Ok(EcsaMotion {
            k: flow.k,
            basis: solution.basis,
            coefficients: solution.coefficients.clone(),
            ode: self.options.ode,
            t,
            q,
        })
    }

    /// Plans, samples and verifies, returning the solution's statistics beside the plan.
    pub fn plan_with_solution(&self, problem: &PlanningProblem) -> Result<(Plan, EcsaSolution, EcsaMotion), Error> {
        let clock = Instant::now();
        let solution = self.solve(problem)?;
        let motion = self.motion(problem, &solution)?;
        let trajectory = motion.trajectory()?;
        let plan_seconds = clock.elapsed().as_secs_f64();
        let (ode, tolerance) = (&self.options.ode, self.options.tolerance);
        let mut plan =
            Plan::verified(Method::Ecsa, problem, &motion, trajectory, motion.margins(), plan_seconds, ode, tolerance)?;
        plan.iterations = Some(solution.stats.iterations);
        Ok((plan, solution, motion))
    }
}

impl Planner for EcsaPlanner {
    fn method(&self) -> Method {
        Method::Ecsa
    }

    fn plan(&self, problem: &PlanningProblem) -> Result<Planned, Error> {
        problem.require_rest("ecsa")?;
        let (plan, solution, motion) = self.plan_with_solution(problem)?;
        Ok(Planned::new(plan, Box::new(motion), Details::Ecsa(solution)))
    }
}

fn harmonics_error(h: usize) -> Error {
    Error::from(InputError::InvalidParameter {
        name: "harmonics".into(),
        value: h as f64,
        expected: "1 to 4 harmonics",
    })
}

fn check_length(basis: &Basis, coefficients: &[f64]) -> Result<(), Error> {
    if coefficients.len() != 2 * basis.terms() {
        return Err(Error::from(InputError::InvalidParameter {
            name: "coefficients".into(),
            value: coefficients.len() as f64,
            expected: "2 (2H + 1) coefficients for H harmonics",
        }));
    }
    Ok(())
}

/// `K(c)` and `J(c)`: system (7) with its variational equations, as one integration of a
/// state of vector dual numbers whose `P` derivative parts are `dq/dc`.
fn end_point_dual<const P: usize>(
    k: &Lumped,
    basis: &Basis,
    start: &Configuration,
    c: &[f64],
    ode: &OdeOptions,
) -> Result<([f64; 3], SMatrix<f64, 3, P>, OdeStats), Error> {
    let m = basis.terms();
    let y0 = SVector::<DualSVec64<P>, 3>::from(start.to_array().map(DualSVec64::from_re));
    let rhs = |t: f64, y: &SVector<DualSVec64<P>, 3>| {
        let phi = basis.values(t);
        // u_i = sum_j c_ij phi_j(t), du_i/dc_ij = phi_j(t).
        let u: [DualSVec64<P>; 2] = std::array::from_fn(|i| {
            let mut re = 0.0;
            let mut eps = SVector::<f64, P>::zeros();
            for (j, p) in phi.iter().enumerate().take(m) {
                re += *p * c[i * m + j];
                eps[i * m + j] = *p;
            }
            DualSVec64::new(re, Derivative::some(eps))
        });
        Ok::<_, Error>(SVector::from(velocity(k, [y[0], y[1], y[2]], u)))
    };
    let (y, stats) = integrate(rhs, 0.0, y0, basis.horizon(), ode, |_, _| {})?;
    let mut jacobian = SMatrix::<f64, 3, P>::zeros();
    for i in 0..3 {
        jacobian.set_row(i, &y[i].eps.unwrap_generic(Const::<P>, U1).transpose());
    }
    Ok(([y[0].re, y[1].re, y[2].re], jacobian, stats))
}

/// System (7) under the controls of fixed coefficients, in `f64`.
struct Flow<'a> {
    k: Lumped,
    basis: Basis,
    coefficients: &'a [f64],
    ode: OdeOptions,
}

impl Flow<'_> {
    /// `q(t1)` from `q(t0) = q0`, `t1 >= t0`.
    fn advance(&self, t0: f64, q0: [f64; 3], t1: f64) -> Result<[f64; 3], Error> {
        if t1 <= t0 {
            return Ok(q0);
        }
        let rhs = |t: f64, y: &Vector3<f64>| {
            let u = self.basis.controls(self.coefficients, t);
            Ok::<_, Error>(Vector3::from(velocity(&self.k, [y[0], y[1], y[2]], u)))
        };
        let (y, _) = integrate(rhs, t0, Vector3::from(q0), t1, &self.ode, |_, _| {})?;
        Ok([y[0], y[1], y[2]])
    }
}

#[cfg(test)]
mod tests;
