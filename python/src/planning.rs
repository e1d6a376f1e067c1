//! `freefloat.plan` and `freefloat.compare` of a `Robot`: the library's 2-link planners driven
//! as the CLI drives them (`src/cli/plan.rs`), results as `freefloat.Plan` (module
//! `plan_class`), the CLI's JSON report as the certificate.

use std::time::Instant;

use freefloat::{
    Configuration, EcsaOptions, Method, NfaOptions, Plan, PlanningProblem, TorqueOptions, TorqueReport, Transform,
    Window,
};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::PyDict;

use crate::compat::{Cost, Elbow, InputError, OptimalOptions, PlanReport, PlannerOptions, plan_to_pose, planner};
use crate::convert::{Reals, column, rows};
use crate::errors::{BindingError, IntoPyResult, library_error};
use crate::plan_class::{PyPlan, certified_or_raise};
use crate::robot::{PyRobot, triple};

/// The methods of `plan(method=...)`, the default first; `compare` plans with all of them by
/// default, in this order (as `freefloat compare`).
pub const METHODS: &[&str] = &["optimal", "nfa", "ecsa"];

/// A method by its name.
pub fn parse_method(name: &str) -> Result<Method, BindingError> {
    Ok(match name {
        "optimal" => Method::Optimal,
        "nfa" => Method::Nfa,
        "ecsa" => Method::Ecsa,
        other => return Err(BindingError::UnknownChoice { name: "method", value: other.into(), allowed: METHODS }),
    })
}

/// The method keywords of `plan`, `compare` and `_time_plan` as given, before validation. The
/// defaults are those of the Python signatures.
#[derive(Debug, Clone)]
pub struct Keywords<'a> {
    /// `transform` (NFA): "auto", "eq11", "eq12", "eq14" or "global".
    pub transform: &'a str,
    /// `samples`.
    pub samples: i64,
    /// `torques`.
    pub torques: bool,
    /// `tolerance` [rad].
    pub tolerance: f64,
    /// `harmonics` (ECSA).
    pub harmonics: i64,
    /// `window` (ECSA): "none" or "sin2".
    pub window: &'a str,
    /// `smooth_ends` (optimal).
    pub smooth_ends: bool,
    /// `initial_velocity` (optimal): (dtheta1, dtheta2) [rad/s], None for rest.
    pub initial_velocity: Option<Reals>,
    /// `wrap` (optimal).
    pub wrap: bool,
    /// `cost` (optimal): "effort" or "energy".
    pub cost: &'a str,
}

impl Default for Keywords<'_> {
    fn default() -> Self {
        Self {
            transform: "auto",
            samples: 1001,
            torques: false,
            tolerance: 1e-9,
            harmonics: 1,
            window: "none",
            smooth_ends: false,
            initial_velocity: None,
            wrap: true,
            cost: "effort",
        }
    }
}

/// Options of one call, parsed from the keywords before the GIL is released.
#[derive(Debug, Clone, Copy)]
pub struct Options {
    /// NFA transformation; `None` is `auto`.
    pub transform: Option<Transform>,
    /// Samples of the trajectory, both ends included.
    pub samples: usize,
    /// Add the torque level (and the accelerations).
    pub torques: bool,
    /// Tolerance of the verified final error [rad].
    pub tolerance: f64,
    /// ECSA harmonics.
    pub harmonics: usize,
    /// ECSA window.
    pub window: Window,
    /// Optimal: quintic splines, zero accelerations at both ends.
    pub smooth_ends: bool,
    /// Optimal: `theta'(0)` [rad/s].
    pub initial_velocity: [f64; 2],
    /// Optimal: count the goal's angles modulo 2 pi.
    pub wrap: bool,
    /// Optimal: the cost minimised.
    pub cost: Cost,
}

impl Options {
    /// Parses the keywords; bad names, negative counts and a velocity that is not two numbers
    /// are `BadInput`.
    pub fn parse(k: &Keywords<'_>) -> Result<Self, BindingError> {
        let initial_velocity = match k.initial_velocity.as_deref() {
            None => [0.0; 2],
            Some(&[v1, v2]) => [v1, v2],
            Some(other) => {
                return Err(BindingError::Library(freefloat::Error::from(InputError::InvalidParameter {
                    name: "initial_velocity".into(),
                    value: other.len() as f64,
                    expected: "2 numbers (dtheta1, dtheta2) [rad/s]",
                })));
            }
        };
        Ok(Self {
            transform: parse_transform(k.transform)?,
            samples: count("samples", k.samples)?,
            torques: k.torques,
            tolerance: k.tolerance,
            harmonics: count("harmonics", k.harmonics)?,
            window: parse_window(k.window)?,
            smooth_ends: k.smooth_ends,
            initial_velocity,
            wrap: k.wrap,
            cost: match k.cost {
                "effort" => Cost::Effort,
                "energy" => Cost::Energy,
                other => {
                    return Err(BindingError::UnknownChoice {
                        name: "cost",
                        value: other.into(),
                        allowed: &["effort", "energy"],
                    });
                }
            },
        })
    }

    /// `BadInput` when a method's keywords have values other than their defaults and `method`
    /// is another one (as `freefloat plan` rejects misplaced flags).
    pub fn check_method(&self, method: Method) -> Result<(), BindingError> {
        let ecsa = self.harmonics != 1 || self.window != Window::None;
        let optimal = self.smooth_ends
            || !self.wrap
            || self.cost != Cost::Effort
            || self.initial_velocity.iter().any(|v| v.abs() > 0.0);
        let misplaced = [
            (self.transform.is_some(), Method::Nfa, "transform"),
            (ecsa, Method::Ecsa, "harmonics/window"),
            (optimal, Method::Optimal, "smooth_ends/initial_velocity/wrap/cost"),
        ];
        for (given, owner, keywords) in misplaced {
            if given && method != owner {
                return Err(BindingError::Misplaced { keywords, owner: owner.name(), method: method.name() });
            }
        }
        Ok(())
    }

    fn planner_options(&self) -> Result<PlannerOptions, freefloat::Error> {
        Ok(PlannerOptions {
            nfa: NfaOptions {
                transform: self.transform,
                samples: self.samples,
                accelerations: self.torques,
                tolerance: self.tolerance,
                ..Default::default()
            },
            ecsa: EcsaOptions { samples: self.samples, tolerance: self.tolerance, ..Default::default() }
                .with_window(self.window)
                .with_harmonics(self.harmonics)?,
            optimal: OptimalOptions {
                cost: self.cost,
                smooth_ends: self.smooth_ends,
                wrap: self.wrap,
                samples: self.samples,
                tolerance: self.tolerance,
                ..Default::default()
            },
        })
    }
}

/// The ECSA's window by its name: `none` or `sin2`.
pub fn parse_window(name: &str) -> Result<Window, BindingError> {
    match name {
        "none" => Ok(Window::None),
        "sin2" => Ok(Window::SinSquared),
        other => Err(BindingError::UnknownChoice { name: "window", value: other.into(), allowed: &["none", "sin2"] }),
    }
}

/// A transformation by its name; `auto` is `None`.
pub fn parse_transform(name: &str) -> Result<Option<Transform>, BindingError> {
    Ok(match name {
        "auto" => None,
        "eq11" => Some(Transform::Eq11),
        "eq12" => Some(Transform::Eq12),
        "eq14" => Some(Transform::Eq14),
        "global" => Some(Transform::Global),
        other => {
            return Err(BindingError::UnknownChoice {
                name: "transform",
                value: other.into(),
                allowed: &["auto", "eq11", "eq12", "eq14", "global"],
            });
        }
    })
}

/// A non-negative count, else `BadInput` naming it.
pub fn count(name: &str, value: i64) -> Result<usize, BindingError> {
    usize::try_from(value).map_err(|_| {
        BindingError::Library(freefloat::Error::from(InputError::InvalidParameter {
            name: name.into(),
            value: value as f64,
            expected: "a non-negative integer",
        }))
    })
}

/// Where a plan goes: the problem's goal configuration, or an end-effector pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    /// `problem.goal` (joint space).
    Joints,
    /// The end-effector pose `(x, y, psi)` [m, m, rad] (the problem's goal is unused), by the
    /// library's free-floating inverse kinematics ([`plan_to_pose`]); `elbow` None plans both
    /// solutions and keeps the certified plan of least effort.
    Pose {
        /// `(x, y, psi)`.
        pose: (f64, f64, f64),
        /// The elbow asked for.
        elbow: Option<Elbow>,
    },
}

/// A plan with its report (the CLI's JSON), the torque level with torques, the elbow of a plan
/// to a pose.
pub struct Planned {
    pub(crate) plan: Plan,
    pub(crate) report: PlanReport,
    pub(crate) torques: Option<TorqueReport>,
    pub(crate) elbow: Option<Elbow>,
}

/// Plans with `method` to `target`, then adds the torque level when asked (as `freefloat plan
/// --torques`). The one dispatch on the method is the library's [`planner`]; a new planner is
/// one more name in [`parse_method`] and [`METHODS`].
pub fn plan_core(
    method: Method,
    problem: &PlanningProblem,
    target: Target,
    options: &Options,
) -> Result<Planned, BindingError> {
    let planner = planner(method, &options.planner_options()?);
    // `initial_velocity` is the problem's start velocity: the torque certificate starts there.
    let problem = &problem.with_start_velocity(options.initial_velocity)?;
    let (elbow, mut planned) = match target {
        Target::Joints => (None, planner.plan(problem)?),
        Target::Pose { pose, elbow } => {
            let (elbow, planned) = plan_to_pose(planner.as_ref(), problem, pose, elbow)?;
            (Some(elbow), planned)
        }
    };
    if options.torques {
        planned.add_torques(&TorqueOptions::default())?;
    }
    let report = PlanReport::new(&planned, false);
    let (plan, torques) = (planned.plan, planned.torques);
    Ok(Planned { plan, report, torques, elbow })
}

/// The Python plan of `planned`; `NotCertified` (carrying the plan) when a certificate fails or,
/// where they hold, with `failure` (a check beyond the plan's own certificates, e.g. an arm's
/// limits).
pub fn into_python(py: Python<'_>, planned: Planned, failure: Option<freefloat::Error>) -> PyResult<Bound<'_, PyPlan>> {
    let Planned { plan, report, torques, elbow } = planned;
    let tr = &plan.trajectory;
    let report_value = serde_json::to_value(&report).map_err(|e| {
        pyo3::exceptions::PyRuntimeError::new_err(format!("invariant: the plan report serialises: {e}"))
    })?;
    let v = &plan.verification;
    let py_plan = PyPlan {
        t: column(py, &tr.t).unbind(),
        q: rows(py, &tr.q).unbind(),
        dq: rows(py, &tr.dq).unbind(),
        ddq: tr.ddq.as_deref().map(|a| rows(py, a).unbind()),
        z: tr.z.as_deref().map(|a| rows(py, a).unbind()),
        tau: tr.tau.as_deref().map(|a| rows(py, a).unbind()),
        base: rows(py, &tr.base).unbind(),
        end_effector: rows(py, &tr.end_effector).unbind(),
        end_effector_velocity: rows(py, &tr.end_effector_velocity).unbind(),
        method: plan.method.name().to_string(),
        transform: report.transform.map(|t| t.name().to_string()),
        elbow: elbow.map(|e| elbow_name(e).to_string()),
        joints: 2,
        horizon: report_value["time"].as_f64().unwrap_or(f64::NAN),
        effort: plan.effort,
        final_error: v.final_error,
        tolerance: v.tolerance,
        certified: report.certified,
        report: report_value,
        certificate: PyOnceLock::new(),
    };
    let failure = plan.certified().err().or_else(|| torques.as_ref().and_then(|t| t.check().err())).or(failure);
    certified_or_raise(py, py_plan, failure)
}

fn elbow_name(elbow: Elbow) -> &'static str {
    match elbow {
        Elbow::Up => "up",
        Elbow::Down => "down",
    }
}

/// The problem of the arguments, validated, and where it goes: exactly one of `goal`
/// (joint space) and `goal_ee` (task space, with an optional `elbow`); `T` is required
/// (`TypeError` when missing, as for any required argument of `function`).
#[allow(non_snake_case, clippy::too_many_arguments)]
pub fn problem(
    py: Python<'_>,
    function: &str,
    robot: &PyRobot,
    start: &[f64],
    goal: Option<&[f64]>,
    T: Option<f64>,
    goal_ee: Option<&[f64]>,
    elbow: Option<&str>,
) -> PyResult<(PlanningProblem, Target)> {
    let horizon =
        T.ok_or_else(|| PyTypeError::new_err(format!("{function}() missing required argument 'T' (the horizon [s])")))?;
    let start = Configuration::from_array(triple(py, "start", start)?);
    let elbow = match elbow {
        None => None,
        Some("up") => Some(Elbow::Up),
        Some("down") => Some(Elbow::Down),
        Some(other) => {
            let e = BindingError::UnknownChoice { name: "elbow", value: other.into(), allowed: &["up", "down"] };
            return Err(e.into_pyerr(py));
        }
    };
    let conflict = |message| BindingError::Conflict { message }.into_pyerr(py);
    let (goal, target) = match (goal, goal_ee) {
        (Some(goal), None) => {
            if elbow.is_some() {
                return Err(conflict("elbow applies to a goal_ee, not to a goal configuration"));
            }
            (Configuration::from_array(triple(py, "goal", goal)?), Target::Joints)
        }
        (None, Some(pose)) => {
            let [x, y, psi] = pose_triple(py, pose)?;
            // The problem's goal is unused: plan_to_pose replaces it by the inverse kinematics'.
            (start, Target::Pose { pose: (x, y, psi), elbow })
        }
        (Some(_), Some(_)) => return Err(conflict("give either goal (joint space) or goal_ee (task space), not both")),
        (None, None) => return Err(conflict("give a goal (phi, theta1, theta2) or a goal_ee (x, y, psi)")),
    };
    let problem = PlanningProblem::new(robot.inner, start, goal, horizon).py_result(py)?;
    Ok((problem, target))
}

/// The three finite numbers (x, y, psi) of `goal_ee`, else `BadInput`.
fn pose_triple(py: Python<'_>, pose: &[f64]) -> PyResult<[f64; 3]> {
    let bad = |value: f64| {
        BindingError::Library(freefloat::Error::from(InputError::InvalidParameter {
            name: "goal_ee".into(),
            value,
            expected: "3 finite numbers (x, y, psi) [m, m, rad]",
        }))
        .into_pyerr(py)
    };
    let pose = <[f64; 3]>::try_from(pose).map_err(|_| bad(pose.len() as f64))?;
    match pose.iter().find(|x| !x.is_finite()) {
        Some(&x) => Err(bad(x)),
        None => Ok(pose),
    }
}

/// Plans a motion from `start` to `goal` (or to the end-effector pose `goal_ee`) in time `T`
/// and certifies it; see the stub for the keywords.
#[pyfunction]
#[pyo3(signature = (
    robot, start, goal = None, T = None, *, goal_ee = None, elbow = None, method = "optimal",
    transform = "auto", samples = 1001, torques = false, tolerance = 1e-9, harmonics = 1, window = "none",
    smooth_ends = false, initial_velocity = None, wrap = true, cost = "effort"
))]
#[allow(non_snake_case, clippy::too_many_arguments)]
pub fn plan<'py>(
    py: Python<'py>,
    robot: PyRef<'py, PyRobot>,
    start: Reals,
    goal: Option<Reals>,
    T: Option<f64>,
    goal_ee: Option<Reals>,
    elbow: Option<&str>,
    method: &str,
    transform: &str,
    samples: i64,
    torques: bool,
    tolerance: f64,
    harmonics: i64,
    window: &str,
    smooth_ends: bool,
    initial_velocity: Option<Reals>,
    wrap: bool,
    cost: &str,
) -> PyResult<Bound<'py, PyPlan>> {
    let (problem, target) = problem(py, "plan", &robot, &start, goal.as_deref(), T, goal_ee.as_deref(), elbow)?;
    let keywords = Keywords {
        transform,
        samples,
        torques,
        tolerance,
        harmonics,
        window,
        smooth_ends,
        initial_velocity,
        wrap,
        cost,
    };
    let options = Options::parse(&keywords).py_result(py)?;
    let method = parse_method(method).py_result(py)?;
    options.check_method(method).py_result(py)?;
    let planned = py.detach(|| plan_core(method, &problem, target, &options)).py_result(py)?;
    into_python(py, planned, None)
}

/// Plans the same problem with each of `methods` (default: all), returning a dict method ->
/// Plan; with `strict=False` a method without a certified plan maps to its exception instead.
/// Each method takes its own keywords and ignores the others' (as `freefloat compare`).
#[pyfunction]
#[pyo3(signature = (
    robot, start, goal = None, T = None, *, goal_ee = None, elbow = None, methods = None,
    transform = "auto", samples = 1001, torques = false, tolerance = 1e-9, harmonics = 1, window = "none",
    smooth_ends = false, initial_velocity = None, wrap = true, cost = "effort", strict = true
))]
#[allow(non_snake_case, clippy::too_many_arguments)]
pub fn compare<'py>(
    py: Python<'py>,
    robot: PyRef<'py, PyRobot>,
    start: Reals,
    goal: Option<Reals>,
    T: Option<f64>,
    goal_ee: Option<Reals>,
    elbow: Option<&str>,
    methods: Option<Vec<String>>,
    transform: &str,
    samples: i64,
    torques: bool,
    tolerance: f64,
    harmonics: i64,
    window: &str,
    smooth_ends: bool,
    initial_velocity: Option<Reals>,
    wrap: bool,
    cost: &str,
    strict: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let (problem, target) = problem(py, "compare", &robot, &start, goal.as_deref(), T, goal_ee.as_deref(), elbow)?;
    let keywords = Keywords {
        transform,
        samples,
        torques,
        tolerance,
        harmonics,
        window,
        smooth_ends,
        initial_velocity,
        wrap,
        cost,
    };
    let options = Options::parse(&keywords).py_result(py)?;
    let names = methods.unwrap_or_else(|| METHODS.iter().map(|m| m.to_string()).collect());
    // Every name is checked before the first (possibly long) plan.
    let methods = names.iter().map(|m| parse_method(m)).collect::<Result<Vec<_>, _>>().py_result(py)?;
    let out = PyDict::new(py);
    for (name, method) in names.iter().zip(methods) {
        let result = py.detach(|| plan_core(method, &problem, target, &options));
        let value = match result {
            // Bad input is never a result: raise it even when not strict.
            Err(BindingError::Library(e)) if e.is_bad_input() => return Err(library_error(py, &e, None)),
            Err(e @ BindingError::Library(_)) => Err(e.into_pyerr(py)),
            Err(e) => return Err(e.into_pyerr(py)),
            Ok(planned) => into_python(py, planned, None).map(Bound::into_any),
        };
        match value {
            Ok(p) => out.set_item(name, p)?,
            Err(e) if !strict => out.set_item(name, e.value(py))?,
            Err(e) => return Err(e),
        }
    }
    Ok(out)
}

/// The wall time [s] of the Rust planner alone (the call `plan` makes with the GIL released,
/// without building the Python results), once per repeat: the benchmark's reference.
#[pyfunction]
#[pyo3(signature = (
    robot, start, goal = None, T = None, *, goal_ee = None, elbow = None, method = "optimal",
    transform = "auto", samples = 1001, torques = false, smooth_ends = false, initial_velocity = None,
    wrap = true, cost = "effort", repeats = 1
))]
#[allow(non_snake_case, clippy::too_many_arguments)]
pub fn _time_plan(
    py: Python<'_>,
    robot: PyRef<'_, PyRobot>,
    start: Reals,
    goal: Option<Reals>,
    T: Option<f64>,
    goal_ee: Option<Reals>,
    elbow: Option<&str>,
    method: &str,
    transform: &str,
    samples: i64,
    torques: bool,
    smooth_ends: bool,
    initial_velocity: Option<Reals>,
    wrap: bool,
    cost: &str,
    repeats: i64,
) -> PyResult<Vec<f64>> {
    let (problem, target) = problem(py, "_time_plan", &robot, &start, goal.as_deref(), T, goal_ee.as_deref(), elbow)?;
    let keywords =
        Keywords { transform, samples, torques, smooth_ends, initial_velocity, wrap, cost, ..Keywords::default() };
    let options = Options::parse(&keywords).py_result(py)?;
    let method = parse_method(method).py_result(py)?;
    options.check_method(method).py_result(py)?;
    let repeats = count("repeats", repeats).py_result(py)?;
    py.detach(|| {
        (0..repeats)
            .map(|_| {
                let clock = Instant::now();
                let planned = plan_core(method, &problem, target, &options)?;
                let seconds = clock.elapsed().as_secs_f64();
                drop(planned);
                Ok(seconds)
            })
            .collect::<Result<Vec<f64>, BindingError>>()
    })
    .py_result(py)
}
