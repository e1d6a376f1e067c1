//! The ECSA for the paper's 2-link robot (Sec. 5, Figs. 9-12): the one engine
//! ([`ChainEcsaPlanner`]) on [`Arm::from_params`] of the problem's robot with the paper's
//! damped pseudo-inverse iteration ([`ChainSolver::PseudoInverse`]), its results in the 2-link
//! types ([`Configuration`], [`Plan`], [`EcsaMotion`]).
//!
//! The end-point map `K(c) = q(T)` is the engine's: `theta(T)` linear in `c`, `phi(T)` the
//! holonomy integral by the composite Gauss–Legendre rule with its exact gradient (see the
//! [module docs](super)); the paper's reproduction (iterations 4, 2, 5, 4 at a = b = 0, 0.1,
//! 0.2, 0.3) is its `n = 2` case.

use std::time::Instant;

use nalgebra::DMatrix;

use super::{Basis, ChainEcsaPlan, ChainEcsaPlanner, ChainEcsaStats, ChainSolver, EcsaMotion, EcsaOptions, MAX_PIECES};
use crate::error::Error;
use crate::model::Configuration;
use crate::model::arm::Arm;
use crate::numerics::iteration::IterationStats;
use crate::numerics::ode::OdeStats;
use crate::plan::{Method, Plan, PlanningProblem};
use crate::planners::chain::ChainProblem;
use crate::planners::{Details, Planned, Planner};

/// The result of the ECSA iteration: the controls' coefficients and the statistics.
#[derive(Debug, Clone, PartialEq)]
pub struct EcsaSolution {
    /// The control basis.
    pub basis: Basis,
    /// `c = (c_10, ..., c_1,2H, c_20, ..., c_2,2H)` \[rad/s\].
    pub coefficients: Vec<f64>,
    /// `K(c)`, the end point of the iteration's map at the solution \[rad\].
    pub reached: Configuration,
    /// Iterations, residuals, termination (`ode` is zero: the map is a quadrature).
    pub stats: IterationStats,
    /// The engine's account (quadrature pieces, effort, wall time).
    pub account: ChainEcsaStats,
}

/// The end-point map and its Jacobian at one `c`.
#[derive(Debug, Clone, PartialEq)]
pub struct EndPoint {
    /// `K(c) = q(T)` \[rad\].
    pub q: Configuration,
    /// `J = dK/dc`, 3 rows (`phi, theta1, theta2`) by `2 (2H + 1)` columns.
    pub jacobian: DMatrix<f64>,
    /// Integrator work (zero: the map is a quadrature).
    pub ode: OdeStats,
}

/// The Endogenous Configuration Space Approach for the 2-link robot (see the
/// [module docs](super)).
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

/// The 2-link problem as the engine's (angles modulo 2 pi, from rest).
fn chain_problem(problem: &PlanningProblem) -> ChainProblem {
    ChainProblem::rest_to_rest(problem.start.to_array().to_vec(), problem.goal.to_array().to_vec(), problem.horizon)
}

/// The first quadrature rule of the engine's iteration, `64 H` pieces.
fn first_pieces(options: &EcsaOptions) -> usize {
    (64 * options.harmonics).clamp(1, MAX_PIECES)
}

impl EcsaPlanner {
    /// A planner with these options.
    pub fn new(options: EcsaOptions) -> Self {
        Self { options }
    }

    /// The engine on the problem's robot, with the paper's pseudo-inverse iteration.
    fn engine(&self, problem: &PlanningProblem) -> ChainEcsaPlanner {
        ChainEcsaPlanner::new(Arm::from_params(&problem.robot), self.options).with_solver(ChainSolver::PseudoInverse)
    }

    /// The end-point map `K(c)` and its exact Jacobian, for coefficients `c` of length
    /// `2 (2H + 1)`, on the iteration's first quadrature rule (`64 H` pieces).
    pub fn end_point(&self, problem: &PlanningProblem, coefficients: &[f64]) -> Result<EndPoint, Error> {
        let start = problem.start.to_array();
        let k = self.engine(problem).end_point(&start, problem.horizon, coefficients, first_pieces(&self.options))?;
        Ok(EndPoint { q: Configuration::new(k.q[0], k.q[1], k.q[2]), jacobian: k.jacobian, ode: OdeStats::default() })
    }

    /// The end-point map `K(c)` alone, on the same rule.
    pub fn end_point_map(&self, problem: &PlanningProblem, coefficients: &[f64]) -> Result<Configuration, Error> {
        let start = problem.start.to_array();
        let q =
            self.engine(problem).end_point_map(&start, problem.horizon, coefficients, first_pieces(&self.options))?;
        Ok(Configuration::new(q[0], q[1], q[2]))
    }

    /// Runs the pseudo-inverse iteration from the initial guess to the residual tolerance.
    /// Non-convergence is [`Error::EcsaFailed`] with the statistics.
    pub fn solve(&self, problem: &PlanningProblem) -> Result<EcsaSolution, Error> {
        let engine = self.engine(problem);
        let account = engine.solve(&chain_problem(problem))?;
        let basis = Basis::new(account.harmonics, problem.horizon, account.window)?;
        let start = problem.start.to_array();
        let q = engine.end_point_map(&start, problem.horizon, &account.coefficients, account.quadrature_pieces)?;
        Ok(EcsaSolution {
            basis,
            coefficients: account.coefficients.clone(),
            reached: Configuration::new(q[0], q[1], q[2]),
            stats: account.iteration.clone(),
            account,
        })
    }

    /// The planned motion of a solution: the engine's plan and the configurations at `samples`
    /// equally spaced times.
    pub fn motion(&self, problem: &PlanningProblem, solution: &EcsaSolution) -> Result<EcsaMotion, Error> {
        self.options.validate()?;
        let engine = self.engine(problem);
        let start = problem.start.to_array();
        // Checks the coefficients' length against the basis.
        engine.end_point_map(&start, problem.horizon, &solution.coefficients, 1)?;
        let account = ChainEcsaStats { coefficients: solution.coefficients.clone(), ..solution.account.clone() };
        let plan = ChainEcsaPlan::new(engine.connection(), solution.basis, &start, account);
        Ok(EcsaMotion::new(plan, problem.robot.lumped(), self.options.samples))
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
