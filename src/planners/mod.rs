//! The planners behind one trait: [`nfa`], the paper's Normal Form Approach, [`ecsa`], its
//! reference method, and [`optimal`], the minimum-effort planner. A caller picks one by its
//! [`Method`] ([`planner`]) and uses it only through [`Planner`].
//!
//! The minimum-effort planner is one for every arm, [`chain`] (issue 19): an arm of another
//! number of links than the paper's two goes through [`arm::plan_arm`], the paper's robot through
//! [`optimal::OptimalPlanner`], its 2-link front-end.

pub mod arm;
pub mod chain;
pub mod ecsa;
pub mod nfa;
pub mod optimal;
pub mod to_pose;

pub use to_pose::plan_to_pose;

use crate::error::Error;
use crate::plan::{Method, Motion, Plan, PlanningProblem, TorqueOptions, TorqueReport, add_torques};

/// A motion planner (docs/spec.md, Sec. 2).
pub trait Planner {
    /// The method it implements.
    fn method(&self) -> Method;
    /// Plans and verifies. A plan is returned even when its certificate fails (see
    /// [`Plan::certified`]); errors mean there is no plan at all.
    fn plan(&self, problem: &PlanningProblem) -> Result<Planned, Error>;
}

/// A plan, the exact motion behind it (for the torque level, animations, re-planning) and the
/// method's own account of it.
pub struct Planned {
    /// The plan with its velocity-level certificate.
    pub plan: Plan,
    /// The planned motion, exact at any time.
    pub motion: Box<dyn Motion + Send + Sync>,
    /// What only this method knows (chained-form ends, iterations, ...).
    pub details: Details,
    /// The torque level, once [`Planned::add_torques`] has run.
    pub torques: Option<TorqueReport>,
}

impl Planned {
    /// A plan without its torque level yet.
    pub fn new(plan: Plan, motion: Box<dyn Motion + Send + Sync>, details: Details) -> Self {
        Self { plan, motion, details, torques: None }
    }

    /// Checks the clearance of the verified motion on the robot with `geometry` (issue 21;
    /// [`crate::plan::clearance::motion_clearance`]) and keeps it in the plan's verification, so
    /// that [`Planned::certified`] refuses a plan that collides. Nothing changes without shapes.
    pub fn check_clearance(&mut self, geometry: &crate::model::arm::collision::Geometry) -> Result<(), Error> {
        let ode = crate::numerics::ode::OdeOptions::default();
        let clearance =
            crate::plan::clearance::motion_clearance(self.motion.as_ref(), &self.plan.problem, geometry, &ode)?;
        self.plan.verification.clearance = clearance;
        Ok(())
    }

    /// Adds the torque level (Eq. 6; docs/spec.md, Sec. 2): the torques at the samples into the
    /// trajectory and the forward-dynamics certificate, kept in [`Planned::torques`].
    pub fn add_torques(&mut self, options: &TorqueOptions) -> Result<TorqueReport, Error> {
        let report = add_torques(&mut self.plan, self.motion.as_ref(), options)?;
        self.torques = Some(report);
        Ok(report)
    }

    /// `Ok` when every certificate computed holds: the velocity level, and the torque level
    /// when it was added; else [`Error::NotCertified`] naming the level.
    pub fn certified(&self) -> Result<(), Error> {
        self.plan.certified()?;
        self.torques.as_ref().map_or(Ok(()), TorqueReport::check)
    }
}

impl std::fmt::Debug for Planned {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Planned")
            .field("plan", &self.plan)
            .field("details", &self.details)
            .field("torques", &self.torques)
            .finish_non_exhaustive()
    }
}

/// A method's own account of a plan, beyond the common fields of [`Plan`].
#[derive(Debug, Clone, PartialEq)]
pub enum Details {
    /// The Normal Form Approach: the transformation, the chained-form ends and the steering.
    Nfa(nfa::NfaDetails),
    /// The ECSA: the control basis, its coefficients and the iteration.
    Ecsa(ecsa::EcsaSolution),
    /// The minimum-effort planner: its cost, residuals and SQP iterations.
    Optimal(optimal::OptimalStats),
}

/// The options of every planner, one field per method (each with its documented defaults).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PlannerOptions {
    /// Options of the Normal Form Approach.
    pub nfa: nfa::NfaOptions,
    /// Options of the ECSA.
    pub ecsa: ecsa::EcsaOptions,
    /// Options of the minimum-effort planner.
    pub optimal: optimal::OptimalOptions,
}

/// The planner of `method` with its options from `options`.
pub fn planner(method: Method, options: &PlannerOptions) -> Box<dyn Planner + Send + Sync> {
    match method {
        Method::Nfa => Box::new(nfa::NormalFormPlanner::new(options.nfa.clone())),
        Method::Ecsa => Box::new(ecsa::EcsaPlanner::new(options.ecsa)),
        Method::Optimal => Box::new(optimal::OptimalPlanner::new(options.optimal.clone())),
    }
}
