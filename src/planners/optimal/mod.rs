//! Minimum-effort motion planning (issue 11) for the paper's two-link robot: the joint path that
//! minimises `J = integral_0^T |theta'|^2 dt` (or the kinetic energy) among those that reach the
//! goal's joint angles at rest and turn the base to its goal angle.
//!
//! `phi` is cyclic: with zero angular momentum (Eq. 5) it follows the joint path,
//! `phi(t) = phi0 - integral_0^t (G theta1' + H theta2') / F ds` (Eqs. 7-8), and `F > 0` on the
//! whole torus, so a plan is a joint path alone, subject to one scalar holonomy constraint
//! `phi(T) = phi_d`, across the posture singularity `sigma = 0` (Eq. 9) as freely as anywhere.
//!
//! [`OptimalPlanner`] is the two-link front-end of the one minimum-effort planner of every arm
//! ([`crate::planners::chain`], issue 19), as [`crate::planners::ecsa::EcsaPlanner`] is of the
//! one ECSA: the robot is the 2-link [`Arm`] of its [`crate::model::RobotParams`], the plan that
//! planner's certified plan, and its joint splines become an exact [`OptimalMotion`] (the base
//! angle by the paper's closed-form connection, [`holonomy`]), certified again as a 2-link plan
//! like every plan of the crate. This module keeps the pieces the planner is built from: the
//! clamped B-splines ([`spline`]), the banded factorisation ([`band`]), the trust-region SQP
//! ([`sqp`]), and the two-joint discretisation ([`discrete`], [`seeds`]) that the tests' oracle
//! (a slow exhaustive search) is made of.

pub mod band;
pub mod discrete;
#[cfg(test)]
pub(crate) mod engine;
pub mod holonomy;
pub mod motion;
#[cfg(test)]
pub(crate) mod reference;
pub mod seeds;
pub mod spline;
pub mod sqp;

use std::sync::{Arc, Mutex, PoisonError};
use std::time::Instant;

use serde::Serialize;

use crate::error::Error;
use crate::model::arm::Arm;
use crate::numerics::ode::OdeOptions;
use crate::plan::{Method, Motion, Plan, PlanningProblem};
use crate::planners::chain::{ChainOptions, ChainPlan, ChainPlanner, ChainProblem};
use crate::planners::{Details, Planned, Planner};

pub use motion::{OptimalMotion, OptimalStats};
pub use seeds::Sampled;
pub use sqp::{SqpOptions, Termination};

/// The cost minimised.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Cost {
    /// `integral_0^T |theta'|^2 dt` \[rad^2/s\] (default).
    #[default]
    Effort,
    /// `integral_0^T 1/2 q'^T M q' dt` \[J s\]: the kinetic energy of Eq. (3) with the base's `phi'`
    /// from the momentum constraint (5).
    Energy,
}

/// Options of the [`OptimalPlanner`].
#[derive(Debug, Clone, PartialEq)]
pub struct OptimalOptions {
    /// The cost; default [`Cost::Effort`].
    pub cost: Cost,
    /// Also `theta''(0) = theta''(T) = 0` (quintic splines), so that the torques start and end at
    /// zero; default false (cubic splines).
    pub smooth_ends: bool,
    /// Count the goal's `phi` and joint angles modulo 2 pi: try nearby representatives and keep
    /// the best certified plan; default true. False: the goal's angles literally.
    pub wrap: bool,
    /// Number of samples of the trajectory, including both ends; default 1001.
    pub samples: usize,
    /// Tolerance of the verified final error \[rad\]; default 1e-9.
    pub tolerance: f64,
    /// Integrator options of the verification (default rtol = atol = 1e-12).
    pub ode: OdeOptions,
    /// Uniform knot spans of the coarse basis on which every seed is solved; default 8.
    pub coarse_spans: usize,
    /// Largest number of uniform knot spans of the refinement (doubling from `coarse_spans`);
    /// default 32.
    pub max_spans: usize,
    /// Graded knots at `h / 4^j`, `j = 1..=grading`, in the first and last spans; default 1.
    ///
    /// With `theta'(0) = theta'(T) = 0` the infimum of the effort is that of free end velocities
    /// and is not attained: the optimum steepens the velocity ramps at the ends into layers as
    /// thin as the basis allows, and the accelerations (so the torques) grow as the layers thin.
    /// On the paper's problem at `a = b = 0.1` grading 5 gives effort 0.21954 with a peak torque
    /// of 221 N m inside a 0.3 ms layer; grading 1 gives 0.22013 (+0.3 %) with 0.89 N m. The
    /// default keeps within 1 % of the infimum at a physical torque.
    pub grading: usize,
    /// The refinement stops when the cost changes by less than this, relative; default 1e-6.
    pub refinement_tolerance: f64,
    /// Gauss–Legendre nodes per knot span of the optimiser; default 8 (raised automatically
    /// until the motion's finer quadrature agrees).
    pub quadrature_nodes: usize,
    /// How many of the best coarse solutions are refined; default 2. The best line solved beside
    /// a coil is refined as one more where its coarse cost is below all of theirs.
    pub finalists: usize,
    /// How many goal representatives (best first by the constant-speed effort of their loop
    /// seeds) are solved; default 2.
    pub targets_solved: usize,
    /// Largest radius of a loop seed \[rad\]; larger areas take several turns; default 2.
    pub max_loop_radius: f64,
    /// SQP options of the refined solves.
    pub sqp: SqpOptions,
}

impl Default for OptimalOptions {
    fn default() -> Self {
        Self {
            cost: Cost::Effort,
            smooth_ends: false,
            wrap: true,
            samples: 1001,
            tolerance: DEFAULT_TOLERANCE,
            ode: OdeOptions::default(),
            coarse_spans: 8,
            max_spans: 32,
            grading: 1,
            refinement_tolerance: 1e-6,
            quadrature_nodes: 8,
            finalists: 2,
            targets_solved: 2,
            max_loop_radius: 2.0,
            sqp: SqpOptions::default(),
        }
    }
}

impl OptimalOptions {
    /// Checks the options: the samples and, through [`ChainOptions::validate`], the rest.
    pub fn validate(&self) -> Result<(), Error> {
        crate::plan::limits::check_samples("samples", self.samples as u64)?;
        self.chain_options().validate()
    }

    /// The one minimum-effort planner's options of these (issue 19).
    pub fn chain_options(&self) -> ChainOptions {
        ChainOptions {
            cost: self.cost,
            smooth_ends: self.smooth_ends,
            tolerance: self.tolerance,
            ode: self.ode,
            coarse_spans: self.coarse_spans,
            max_spans: self.max_spans,
            grading: self.grading,
            refinement_tolerance: self.refinement_tolerance,
            quadrature_nodes: self.quadrature_nodes,
            targets_solved: self.targets_solved,
            finalists: self.finalists,
            max_loop_radius: self.max_loop_radius,
            sqp: self.sqp,
            ..ChainOptions::default()
        }
    }
}

/// The minimum-effort planner (see the [module docs](self)).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct OptimalPlanner {
    /// Options.
    pub options: OptimalOptions,
    /// The chain planner of the last call, with the coil sites and tables it found: the next
    /// call on the same robot with the same options plans with it (a fresh one per call found
    /// them again; on the paper's problem at a = b = 0.1 they were 12 % of a plan's
    /// instructions). Shared by clones.
    last: LastPlanner,
}

/// [`OptimalPlanner`]'s last chain planner; every one compares equal (a cache).
#[derive(Debug, Clone, Default)]
struct LastPlanner(Arc<Mutex<Option<ChainPlanner>>>);

impl PartialEq for LastPlanner {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl LastPlanner {
    /// The last planner where it equals `fresh` (the same arm and options), else `fresh`, kept
    /// as the last.
    fn same_as(&self, fresh: ChainPlanner) -> ChainPlanner {
        let mut last = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        match last.as_ref() {
            Some(p) if *p == fresh => p.clone(),
            _ => {
                *last = Some(fresh.clone());
                fresh
            }
        }
    }
}

/// The default tolerance of the certificate \[rad\].
pub(crate) const DEFAULT_TOLERANCE: f64 = 1e-9;

/// The largest constraint residual \[rad\] of a coarse line beside a coil that is refined as an
/// extra finalist (in the [chain](crate::planners::chain) planner).
pub(crate) const EXTRA_RESIDUAL: f64 = 1e-3;

impl OptimalPlanner {
    /// A planner with these options.
    pub fn new(options: OptimalOptions) -> Self {
        Self { options, last: LastPlanner::default() }
    }

    /// The one planner's certified plan of `problem` (module docs) as an exact 2-link motion,
    /// without its 2-link certificate. Errors are the planner's: bad input, no plan
    /// ([`Error::OptimalFailed`]), or no certified one at the default tolerance
    /// ([`Error::NotCertified`]). Below the default tolerance a plan that misses it is returned
    /// for its certificate to report.
    pub fn motion(&self, problem: &PlanningProblem) -> Result<OptimalMotion, Error> {
        self.options.validate()?;
        let planner =
            self.last.same_as(ChainPlanner::new(Arm::from_params(&problem.robot), self.options.chain_options()));
        let chain = ChainProblem {
            start: problem.start.to_array().to_vec(),
            goal: problem.goal.to_array().to_vec(),
            horizon: problem.horizon,
            initial_velocity: problem.start_velocity.to_vec(),
            wrap: self.options.wrap,
        };
        let plan = match planner.plan(&chain) {
            Err(Error::NotCertified { .. }) if self.options.tolerance < DEFAULT_TOLERANCE => {
                // No plan holds the tolerance asked for: the plan at the default one, for the
                // 2-link certificate to report by how much it misses (exit 3 with the numbers).
                let options = ChainOptions { tolerance: DEFAULT_TOLERANCE, ..planner.options.clone() };
                ChainPlanner::new(Arm::from_params(&problem.robot), options).plan(&chain)?
            }
            result => result?,
        };
        Ok(self.motion_of_plan(problem, &plan))
    }

    /// The exact 2-link motion of the one planner's plan, with its statistics: the joint goal
    /// and the base's goal representative it reached, and `|phi(T) - phi_end|` by the motion's
    /// own quadrature of the paper's connection.
    fn motion_of_plan(&self, problem: &PlanningProblem, plan: &ChainPlan) -> OptimalMotion {
        let c = plan.coefficients();
        let coefficients = [c[0].clone(), c[1].clone()];
        let end = plan.at(problem.horizon);
        let goal = problem.goal.phi;
        let tau = std::f64::consts::TAU;
        let phi_end = if self.options.wrap { goal + tau * ((end.phi - goal) / tau).round() } else { goal };
        let s = plan.stats;
        let stats = OptimalStats {
            iterations: s.iterations,
            final_iterations: s.final_iterations,
            cost: s.cost,
            effort: s.effort,
            constraint_residual: s.constraint_residual,
            holonomy_residual: f64::NAN,
            kkt_residual: s.kkt_residual,
            multiplier: s.multiplier,
            termination: s.termination,
            spans: s.spans,
            degree: plan.basis().degree(),
            quadrature_nodes: s.quadrature_nodes,
            seeds: s.seeds,
            theta_end: [end.theta[0], end.theta[1]],
            phi_end,
        };
        let k = problem.robot.lumped();
        let mut motion = OptimalMotion::new(k, plan.basis().clone(), coefficients, problem.start.phi, stats);
        let phi_t = motion.at(problem.horizon).map(|p| p.q.phi).unwrap_or(f64::NAN);
        motion.stats.holonomy_residual = (phi_t - phi_end).abs();
        motion
    }

    /// Plans and verifies, returning the exact motion beside the plan (its 2-link certificate:
    /// system (7) integrated with the planned controls, [`Plan::verified`]).
    pub fn plan_with_motion(&self, problem: &PlanningProblem) -> Result<(Plan, OptimalMotion), Error> {
        let clock = Instant::now();
        let motion = self.motion(problem)?;
        let plan_seconds = clock.elapsed().as_secs_f64();
        let trajectory = motion.trajectory(problem, self.options.samples)?;
        let margins = motion.margins(&trajectory);
        let (ode, tolerance) = (&self.options.ode, self.options.tolerance);
        let mut plan =
            Plan::verified(Method::Optimal, problem, &motion, trajectory, margins, plan_seconds, ode, tolerance)?;
        plan.iterations = Some(motion.stats.iterations);
        plan.effort = motion.stats.effort;
        Ok((plan, motion))
    }
}

impl Planner for OptimalPlanner {
    fn method(&self) -> Method {
        Method::Optimal
    }

    fn plan(&self, problem: &PlanningProblem) -> Result<Planned, Error> {
        let (plan, motion) = self.plan_with_motion(problem)?;
        let details = Details::Optimal(motion.stats);
        Ok(Planned::new(plan, Box::new(motion), details))
    }
}

#[cfg(test)]
mod tests;

#[cfg(test)]
pub(crate) mod comparison;
