//! The binding `plan_arm` (behind `freefloat.plan` for an `Arm`): an arm's plan, to a goal
//! configuration or a tool pose (`goal_ee`), with its certificate, as a `freefloat.Plan` (module
//! `plan_class`, the one plan class of every robot).

use freefloat::planners::arm::{ArmRequest, plan_arm as library_plan_arm};
use freefloat::planners::chain::ChainProblem;
use freefloat::planners::optimal::Cost;
use freefloat::planners::to_pose::plan_arm_to_pose;
use freefloat::report::arm::trajectory;
use freefloat::report::io::PlanReport;
use freefloat::{Arm, EcsaOptions, Method, Window};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyList};

use crate::arm::{PyArm, exactly};
use crate::arm_nfa::{NfaRequest, plan_nfa_of_arm};
use crate::compat::InputError;
use crate::convert::{Reals, column};
use crate::errors::{BindingError, IntoPyResult};
use crate::plan_class::{PyPlan, certified_or_raise};
use crate::planning::{count, parse_method, parse_window};
use crate::robot::PyRobot;

/// Rows of `width` numbers as a `(rows, width)` float64 array.
fn matrix<'py>(py: Python<'py>, rows: &[Vec<f64>], width: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    let array = Array2::from_shape_vec((rows.len(), width), flat).map_err(|e| {
        pyo3::exceptions::PyRuntimeError::new_err(format!("invariant: every row has {width} numbers: {e}"))
    })?;
    Ok(array.into_pyarray(py))
}

/// Fixed-size rows as rows of a matrix.
fn rows<const N: usize>(v: &[[f64; N]]) -> Vec<Vec<f64>> {
    v.iter().map(|r| r.to_vec()).collect()
}

/// The arm of `plan_arm(arm, ...)`: an `Arm`, or a 2-link `Robot` converted.
fn any_arm(arm: &Bound<'_, PyAny>) -> PyResult<Arm> {
    if let Ok(arm) = arm.cast::<PyArm>() {
        return Ok(arm.get().inner.clone());
    }
    if let Ok(robot) = arm.cast::<PyRobot>() {
        return Ok(Arm::from_params(&robot.get().inner));
    }
    let type_name = arm.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "?".into());
    Err(PyTypeError::new_err(format!("plan_arm: arm must be a freefloat.Arm or a freefloat.Robot, not {type_name}")))
}

/// The library's refusal of a method or of the shortest horizon names the command line's flag
/// (`--method`, `--time auto`); here it is the keyword (`method`, `T="auto"`).
fn python_names(e: freefloat::Error) -> freefloat::Error {
    match e {
        freefloat::Error::Input(InputError::InvalidText { name, text, expected }) if name == "--method" => {
            freefloat::Error::Input(InputError::InvalidText { name: "method".into(), text, expected })
        }
        freefloat::Error::Input(InputError::InvalidText { name, text, expected })
            if name == "horizon" && text == "--time auto" =>
        {
            freefloat::Error::Input(InputError::InvalidText { name, text: "T=\"auto\"".into(), expected })
        }
        e => e,
    }
}

/// The first probe of `T="auto"`'s search [s], the command line's for `--time auto`
/// (src/cli/plan_arm.rs, `problem`).
const AUTO_FIRST_PROBE: f64 = 10.0;

/// The horizon keyword `T` of `plan` for an arm: a number of seconds, or `"auto"` for the
/// shortest horizon ([`ArmRequest::shortest_horizon`], issue 20 item 4), whose search starts at
/// [`AUTO_FIRST_PROBE`]. Returns the horizon and whether it is to be searched; any other string
/// is `BadInput`, any other type `TypeError`.
fn horizon_keyword(py: Python<'_>, value: &Bound<'_, PyAny>) -> PyResult<(f64, bool)> {
    if let Ok(text) = value.extract::<String>() {
        if text == "auto" {
            return Ok((AUTO_FIRST_PROBE, true));
        }
        let message = format!("unknown horizon T={text:?}");
        let expected = "a horizon in seconds, or \"auto\" (the shortest horizon inside the arm's limits)";
        return Err(BindingError::Key { kind: "invalid_parameter", name: "T".into(), message, expected }.into_pyerr(py));
    }
    let horizon = value.extract::<f64>().map_err(|_| {
        let type_name = value.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "?".into());
        PyTypeError::new_err(format!("T: expected a number of seconds or \"auto\", got {type_name}"))
    })?;
    Ok((horizon, false))
}

/// Plans a motion of `arm` from `start` to `goal` in `T` and certifies it; see the stub.
#[pyfunction]
#[pyo3(signature = (
    arm, start, goal, T, *, goal_ee = None, branch = None, samples = 1001, torques = false, wrap = true, initial_velocity = None,
    tolerance = 1e-9, method = "optimal", harmonics = 1, window = "none", smooth_ends = false, cost = "effort",
    limits = None, obstacles = None, clearance = None, no_collide = None
))]
#[allow(non_snake_case, clippy::too_many_arguments)]
pub fn plan_arm<'py>(
    py: Python<'py>,
    arm: &Bound<'py, PyAny>,
    start: Reals,
    goal: Option<Reals>,
    T: &Bound<'py, PyAny>,
    goal_ee: Option<Reals>,
    branch: Option<String>,
    samples: i64,
    torques: bool,
    wrap: bool,
    initial_velocity: Option<Reals>,
    tolerance: f64,
    method: &str,
    harmonics: i64,
    window: &str,
    smooth_ends: bool,
    cost: &str,
    limits: Option<Bound<'py, PyDict>>,
    obstacles: Option<Bound<'py, PyList>>,
    clearance: Option<f64>,
    no_collide: Option<Vec<(String, String)>>,
) -> PyResult<Bound<'py, PyPlan>> {
    let arm = any_arm(arm)?;
    let (horizon, shortest_horizon) = horizon_keyword(py, T)?;
    // Issue 20: `limits=` over the arm's own (module `limits`).
    let arm = match &limits {
        Some(l) => {
            let own = crate::limits::apply(&arm.limits, arm.joints(), l).py_result(py)?;
            arm.with_limits(own).py_result(py)?
        }
        None => arm,
    };
    // Issue 21: obstacles, the clearance and the excluded pairs over the arm's own shapes.
    let arm = if obstacles.is_some() || clearance.is_some() || no_collide.is_some() {
        let own = crate::geometry::apply(&arm.geometry, arm.joints(), obstacles.as_ref(), clearance, no_collide)
            .py_result(py)?;
        arm.with_geometry(own).py_result(py)?
    } else {
        arm
    };
    let n = arm.joints();
    let method: Method = parse_method(method).py_result(py)?;
    let window = parse_window(window).py_result(py)?;
    let harmonics = count("harmonics", harmonics).py_result(py)?;
    if (harmonics != 1 || window != Window::None) && method != Method::Ecsa {
        let misplaced = BindingError::Misplaced { keywords: "harmonics/window", owner: "ecsa", method: method.name() };
        return Err(misplaced.into_pyerr(py));
    }
    let ecsa = EcsaOptions::default()
        .with_window(window)
        .with_harmonics(harmonics)
        .map_err(BindingError::from)
        .py_result(py)?;
    // The NFA plans the paper's 2-link model (module `arm_nfa`); another 2-link arm, a pose
    // goal or the shortest horizon is refused naming why (the library's reason, "another number
    // of links", is not this arm's).
    let nfa_robot = (n == 2 && method == Method::Nfa).then(|| arm.as_src());
    if let Some(robot) = &nfa_robot
        && (robot.is_none() || goal_ee.is_some() || shortest_horizon)
    {
        let message = "method=\"nfa\" plans a 2-link arm of the paper's model to a goal configuration in a given \
             horizon (not a goal_ee, not T=\"auto\")"
            .to_string();
        let expected = "method=\"optimal\" or \"ecsa\", or the NFA to a goal configuration with a horizon in s";
        return Err(
            BindingError::Key { kind: "invalid_parameter", name: "method".into(), message, expected }.into_pyerr(py)
        );
    }
    let samples = count("samples", samples).py_result(py)?;
    let angles = "n + 1 numbers (phi, theta_1..theta_n) [rad]";
    let start = exactly(py, "start", start, n + 1, angles)?;
    let pose = match (goal_ee, &goal) {
        (Some(pose), None) => {
            let [x, y, psi]: [f64; 3] = exactly(py, "goal_ee", pose, 3, "(x, y, psi) [m, m, rad]")?
                .try_into()
                .map_err(|_| PyTypeError::new_err("goal_ee: three numbers"))?;
            Some((x, y, psi))
        }
        (None, Some(_)) => None,
        _ => {
            let message = "plan_arm: give either goal (joint space) or goal_ee (task space)";
            return Err(BindingError::Conflict { message }.into_pyerr(py));
        }
    };
    if branch.is_some() && pose.is_none() {
        let message = "plan_arm: branch applies to a goal_ee, not to a goal configuration";
        return Err(BindingError::Conflict { message }.into_pyerr(py));
    }
    let goal = match goal {
        Some(goal) => exactly(py, "goal", goal, n + 1, angles)?,
        // A placeholder checked by `validate`; the pose's branches replace it.
        None => start.clone(),
    };
    let initial_velocity = match initial_velocity {
        None => vec![0.0; n],
        Some(v) => exactly(py, "initial_velocity", v, n, "n numbers (dtheta_1..dtheta_n) [rad/s]")?,
    };
    let problem = ChainProblem { start, goal, horizon, initial_velocity, wrap };
    problem.validate(&arm).py_result(py)?;
    if let Some(Some(robot)) = nfa_robot {
        if smooth_ends || cost != "effort" || problem.initial_velocity.iter().any(|w| *w != 0.0) {
            let keywords = "smooth_ends/cost/initial_velocity";
            return Err(BindingError::Misplaced { keywords, owner: "optimal", method: "nfa" }.into_pyerr(py));
        }
        let (start, goal) = (&problem.start, &problem.goal);
        let request = NfaRequest { start, goal, horizon, samples, tolerance, torques };
        return plan_nfa_of_arm(py, &arm, robot, &request);
    }
    let cost = match cost {
        "effort" => Cost::Effort,
        "energy" => Cost::Energy,
        other => {
            let message = format!("unknown cost {other:?}");
            let expected = "\"effort\" or \"energy\"";
            return Err(
                BindingError::Key { kind: "invalid_parameter", name: "cost".into(), message, expected }.into_pyerr(py)
            );
        }
    };
    let request = ArmRequest {
        samples,
        tolerance,
        torques,
        ecsa,
        cost,
        smooth_ends,
        shortest_horizon,
        ..ArmRequest::new(problem)
    };
    let (planned, to_ee) = py
        .detach(|| match pose {
            None => library_plan_arm(&arm, method, &request).map(|planned| (planned, None)),
            Some(pose) => plan_arm_to_pose(&arm, method, &request, pose, branch.as_deref())
                .map(|(goal, planned)| (planned, Some(goal))),
        })
        .map_err(python_names)
        .py_result(py)?;
    let goal = to_ee.as_ref().and_then(|g| g.kept()).map_or(&request.problem.goal, |b| &b.solution.q);
    let mut report = PlanReport::from_arm(&planned, &request.problem.start, goal, false);
    if let Some(g) = &to_ee {
        report.notes.push(g.note());
    }
    report.to_ee = to_ee;
    let report_value = serde_json::to_value(&report).map_err(|e| {
        pyo3::exceptions::PyRuntimeError::new_err(format!("invariant: the arm's report serialises: {e}"))
    })?;
    let tr = trajectory(&planned);
    let v = planned.verification();
    let py_plan = PyPlan {
        t: column(py, &tr.t).unbind(),
        q: matrix(py, &tr.q, n + 1)?.unbind(),
        dq: matrix(py, &tr.dq, n + 1)?.unbind(),
        ddq: Some(matrix(py, &tr.ddq, n + 1)?.unbind()),
        z: None,
        base: matrix(py, &rows(&tr.base), 2)?.unbind(),
        end_effector: matrix(py, &rows(&tr.end_effector), 3)?.unbind(),
        end_effector_velocity: matrix(py, &rows(&tr.end_effector_velocity), 3)?.unbind(),
        tau: tr.tau.as_deref().map(|tau| matrix(py, tau, n).map(Bound::unbind)).transpose()?,
        method: planned.method.name().to_string(),
        transform: None,
        elbow: None,
        joints: n,
        horizon: planned.plan.horizon(),
        effort: planned.effort(),
        final_error: v.final_error,
        tolerance: v.tolerance,
        certified: report.certified,
        report: report_value,
        certificate: PyOnceLock::new(),
    };
    certified_or_raise(py, py_plan, planned.certified().err())
}
