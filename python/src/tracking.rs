//! `freefloat.track`: a plan executed in closed loop on a robot that may differ from the model
//! (the library's `track` module, one code path for every arm), results as a dict.

use freefloat::Arm;
use freefloat::model::InputError;
use freefloat::planners::chain::ChainProblem;
use freefloat::track::{Controller, Disturbances, Perturbation, ReplanOptions, TrackOptions, track as run_track};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arm::PyArm;
use crate::convert::{Reals, json_dict};
use crate::errors::{BindingError, IntoPyResult};
use crate::robot::PyRobot;

/// The arm of a `Robot` (the 2-link robot, [`Arm::from_params`]) or an `Arm`, else `TypeError`.
fn arm_of(name: &str, robot: &Bound<'_, PyAny>) -> PyResult<Arm> {
    if let Ok(r) = robot.extract::<PyRef<'_, PyRobot>>() {
        return Ok(Arm::from_params(&r.inner));
    }
    if let Ok(a) = robot.extract::<PyRef<'_, PyArm>>() {
        return Ok(a.inner.clone());
    }
    Err(PyTypeError::new_err(format!("{name}: expected a freefloat.Robot or a freefloat.Arm")))
}

/// The controller by its name.
fn controller(name: &str) -> Result<Controller, BindingError> {
    Ok(match name {
        "open" => Controller::Open,
        "ct" => Controller::Ct,
        "replan" => Controller::Replan,
        "adaptive" => Controller::Adaptive,
        other => {
            return Err(BindingError::UnknownChoice {
                name: "controller",
                value: other.into(),
                allowed: &["open", "ct", "replan", "adaptive"],
            });
        }
    })
}

/// Plans `start -> goal` (`n + 1` angles each) in `T` with the minimum-effort planner on `robot`
/// (a `Robot` or an `Arm`: the model), then executes
/// the plan in closed loop on the true robot (`true_robot`, or `robot` perturbed by `perturb`
/// relative and `perturb_mount` metres, seeded by `seed`) with `controller`; see the stub.
#[pyfunction]
#[pyo3(signature = (
    robot, start, goal, T, *, controller = "adaptive", true_robot = None, perturb = 0.0,
    perturb_mount = 0.0, torque_noise = 0.0, q_noise = 0.0, dq_noise = 0.0, rate = 1000.0,
    replan_rate = 5.0, margin = None, limit_margin = None, seed = 0
))]
#[allow(non_snake_case, clippy::too_many_arguments)]
pub fn track<'py>(
    py: Python<'py>,
    robot: Bound<'py, PyAny>,
    start: Reals,
    goal: Reals,
    T: f64,
    controller: &str,
    true_robot: Option<Bound<'py, PyAny>>,
    perturb: f64,
    perturb_mount: f64,
    torque_noise: f64,
    q_noise: f64,
    dq_noise: f64,
    rate: f64,
    replan_rate: f64,
    margin: Option<f64>,
    limit_margin: Option<f64>,
    seed: u64,
) -> PyResult<Bound<'py, PyDict>> {
    let model = arm_of("robot", &robot)?;
    let problem = ChainProblem::rest_to_rest(start.0, goal.0, T);
    problem.validate(&model).py_result(py)?;
    let controller = self::controller(controller).py_result(py)?;
    let mut options = TrackOptions { controller, rate, ..Default::default() };
    options.replan.rate = replan_rate;
    options.replan.margin = margin.unwrap_or(options.replan.margin);
    options.replan.limit_margin = limit_margin.unwrap_or(options.replan.limit_margin);
    ReplanOptions::check_margin(&model, margin).py_result(py)?;
    ReplanOptions::check_limit_margin(&model, limit_margin).map_err(limit_margin_keyword).py_result(py)?;
    options.disturbances = Disturbances { torque_noise, q_noise, dq_noise, ..Default::default() };
    // Every option and budget before planning (the library's checks, as the command line's).
    options.validate().map_err(limit_margin_keyword).py_result(py)?;
    options.check_budget(problem.horizon).py_result(py)?;
    let truth = true_robot.map(|r| arm_of("true_robot", &r)).transpose()?;
    let perturbation = Perturbation { relative: perturb, mount: perturb_mount };
    let limited = !model.limits.is_empty();
    let (tracked, limit_margin_used) = py
        .detach(|| -> Result<_, BindingError> {
            let truth = match truth {
                Some(t) => t,
                None => perturbation.apply(&model, seed)?,
            };
            // The plan keeps the margins beyond the clearance and inside the limits; the run is
            // judged at the clearance and the limits.
            let mut options = options;
            let planned = options.replan.first_plan(&model, &problem)?;
            planned.certified()?;
            // The margin the plans kept: `first_plan` lowers it where the horizon is too short
            // for the whole of it; none for a robot without limits.
            let used = if limited { options.replan.limit_margin } else { 0.0 };
            Ok((run_track(&model, &problem, &planned.plan, &truth, &options, seed)?, used))
        })
        .py_result(py)?;
    let value = serde_json::to_value(&tracked).map_err(|e| {
        pyo3::exceptions::PyRuntimeError::new_err(format!("invariant: the tracking result serialises: {e}"))
    })?;
    let result = json_dict(py, &value.as_object().cloned().unwrap_or_default())?;
    result.set_item("limit_margin_used", limit_margin_used)?;
    Ok(result)
}

/// `e` naming the keyword `limit_margin` where the library names the command line's
/// `limit-margin`.
fn limit_margin_keyword(e: freefloat::Error) -> freefloat::Error {
    match e {
        freefloat::Error::Input(InputError::InvalidParameter { name, value, expected }) if name == "limit-margin" => {
            InputError::InvalidParameter { name: "limit_margin".into(), value, expected }.into()
        }
        other => other,
    }
}
