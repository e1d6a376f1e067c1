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

use crate::error::Error;
use crate::model::kinematics::{Elbow, inverse_kinematics};
use crate::model::{Configuration, InputError};
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

/// Plans from `problem.start` to the end-effector pose `(x, y, psi)` (inertial frame, the
/// system's centre of mass at the origin; m, m, rad) instead of `problem.goal`: the goal
/// configurations are the free-floating inverse kinematics' solutions
/// ([`inverse_kinematics`], `phi` of the start where the pose leaves it free), each angle the
/// representative nearest the start's; with `elbow` only that solution, else each is planned and
/// the certified plan of least effort kept. Unreachable poses are [`InputError::Unreachable`].
pub fn plan_to_pose(
    planner: &dyn Planner,
    problem: &PlanningProblem,
    pose: (f64, f64, f64),
    elbow: Option<Elbow>,
) -> Result<(Elbow, Planned), Error> {
    let solutions = inverse_kinematics(&problem.robot, pose, problem.start.phi).map_err(InputError::from)?;
    let near = |x: f64, reference: f64| x + std::f64::consts::TAU * ((reference - x) / std::f64::consts::TAU).round();
    let mut best: Option<(Elbow, Planned)> = None;
    let mut first_error = None;
    for (e, q) in solutions.into_iter().filter(|(e, _)| elbow.is_none_or(|want| want == *e)) {
        let s = problem.start;
        let goal = Configuration::new(near(q.phi, s.phi), near(q.theta1, s.theta1), near(q.theta2, s.theta2));
        match planner.plan(&PlanningProblem { goal, ..*problem }) {
            Ok(planned) if planned.plan.verification.certified => {
                if best.as_ref().is_none_or(|(_, b)| planned.plan.effort < b.plan.effort) {
                    best = Some((e, planned));
                }
            }
            Ok(planned) => first_error = first_error.or(planned.plan.certified().err()),
            Err(err) => first_error = first_error.or(Some(err)),
        }
    }
    match (best, first_error) {
        (Some(best), _) => Ok(best),
        (None, Some(err)) => Err(err),
        (None, None) => Err(InputError::InvalidParameter {
            name: "elbow".into(),
            value: f64::NAN,
            expected: "an elbow that reaches the pose (at a = b = 0 the two coincide: leave it unset)",
        }
        .into()),
    }
}
