//! `freefloat.plan(arm, method="nfa")` of a 2-link arm of the paper's model that carries limits
//! or shapes (the arm pipeline's): the Normal Form Approach plans the paper's robot, which has
//! neither, and its motion is then checked against the arm's limits and shapes along the
//! integrated motion, as the command line's `plan --method nfa --limit` does (issue 20 item 5,
//! issue 21 item 5). A motion outside a limit or under the clearance is `NotCertified` with its
//! numbers, never a plan.

use freefloat::numerics::ode::OdeOptions;
use freefloat::plan::certificate::verify_on_arm;
use freefloat::plan::limit_use::LimitReport;
use freefloat::{Arm, Configuration, Method, NfaOptions, PlanningProblem, RobotParams, TorqueOptions};
use pyo3::prelude::*;

use crate::compat::{PlanReport, PlannerOptions, planner};
use crate::errors::IntoPyResult;
use crate::plan_class::PyPlan;
use crate::planning::{Planned, into_python};

/// What the NFA of an arm needs from `plan_arm`'s keywords.
pub struct NfaRequest<'a> {
    /// `(phi, theta1, theta2)` at the start \[rad\].
    pub start: &'a [f64],
    /// `(phi, theta1, theta2)` at the goal \[rad\].
    pub goal: &'a [f64],
    /// `T` \[s\].
    pub horizon: f64,
    /// Samples of the trajectory.
    pub samples: usize,
    /// The certificate's tolerance \[rad\].
    pub tolerance: f64,
    /// With the torque level.
    pub torques: bool,
}

/// The NFA's plan of `robot` (the paper's model of `arm`), checked against `arm`'s limits and
/// shapes.
pub fn plan_nfa_of_arm<'py>(
    py: Python<'py>,
    arm: &Arm,
    robot: RobotParams,
    r: &NfaRequest<'_>,
) -> PyResult<Bound<'py, PyPlan>> {
    let triple = |q: &[f64]| Configuration { phi: q[0], theta1: q[1], theta2: q[2] };
    let problem = PlanningProblem::new(robot, triple(r.start), triple(r.goal), r.horizon).py_result(py)?;
    let options = PlannerOptions {
        nfa: NfaOptions { samples: r.samples, accelerations: r.torques, tolerance: r.tolerance, ..Default::default() },
        ..Default::default()
    };
    let (planned, limits) = py
        .detach(|| {
            let mut planned = planner(Method::Nfa, &options).plan(&problem)?;
            if r.torques {
                planned.add_torques(&TorqueOptions::default())?;
            }
            let tolerance = planned.plan.verification.tolerance;
            let v =
                verify_on_arm(planned.motion.as_ref(), &planned.plan.problem, arm, &OdeOptions::default(), tolerance)?;
            planned.plan.verification.clearance = v.clearance;
            let limits = (!arm.limits.is_empty()).then(|| v.limits.unwrap_or_else(LimitReport::empty));
            Ok::<_, freefloat::Error>((planned, limits))
        })
        .py_result(py)?;
    let mut report = PlanReport::new(&planned, false);
    report.robot = arm.clone();
    report.set_limits(limits.clone());
    let outside = limits.and_then(|l| l.check().err());
    let planned = Planned { plan: planned.plan, report, torques: planned.torques, elbow: None };
    into_python(py, planned, outside)
}
