//! `freefloat.plan`, `freefloat.compare` and `freefloat.Plan`: the library's planners driven as
//! the CLI drives them (`src/cli/plan.rs`), results as NumPy arrays, the CLI's JSON report as
//! the certificate.

use std::time::Instant;

use freefloat::{
    EcsaOptions, Method, NfaOptions, Plan, PlanningProblem, TorqueOptions, TorqueReport, Transform, Window,
};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::PyDict;
use serde_json::Value;

use crate::compat::{InputError, PlanReport, PlannerOptions, planner};
use crate::convert::{column, json_dict, rows};
use crate::errors::{BindingError, IntoPyResult, library_error};
use crate::robot::{PyRobot, triple};

/// The methods of `plan(method=...)`; `compare` plans with all of them by default.
pub const METHODS: &[&str] = &["nfa", "ecsa"];

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
}

impl Options {
    /// Parses the keywords; bad names and negative counts are `BadInput`.
    pub fn parse(
        transform: &str,
        samples: i64,
        torques: bool,
        tolerance: f64,
        harmonics: i64,
        window: &str,
    ) -> Result<Self, BindingError> {
        Ok(Self {
            transform: parse_transform(transform)?,
            samples: count("samples", samples)?,
            torques,
            tolerance,
            harmonics: count("harmonics", harmonics)?,
            window: match window {
                "none" => Window::None,
                "sin2" => Window::SinSquared,
                other => {
                    return Err(BindingError::UnknownChoice {
                        name: "window",
                        value: other.into(),
                        allowed: &["none", "sin2"],
                    });
                }
            },
        })
    }

    fn nfa(&self) -> NfaOptions {
        NfaOptions {
            transform: self.transform,
            samples: self.samples,
            accelerations: self.torques,
            tolerance: self.tolerance,
            ..Default::default()
        }
    }

    fn ecsa(&self) -> Result<EcsaOptions, freefloat::Error> {
        EcsaOptions { samples: self.samples, tolerance: self.tolerance, ..Default::default() }
            .with_window(self.window)
            .with_harmonics(self.harmonics)
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

/// A plan with its report (the CLI's JSON) and, with torques, the torque level.
pub struct Planned {
    plan: Plan,
    report: PlanReport,
    torques: Option<TorqueReport>,
}

/// Plans with `method`, then adds the torque level when asked (as `freefloat plan --torques`).
/// The one dispatch on the method: a new planner is one more arm here (and its name in
/// [`METHODS`]).
pub fn plan_core(method: &str, problem: &PlanningProblem, options: &Options) -> Result<Planned, BindingError> {
    let method = match method {
        "nfa" => Method::Nfa,
        "ecsa" => Method::Ecsa,
        other => return Err(BindingError::UnknownChoice { name: "method", value: other.into(), allowed: METHODS }),
    };
    let planner_options = PlannerOptions { nfa: options.nfa(), ecsa: options.ecsa()? };
    let mut planned = planner(method, &planner_options).plan(problem)?;
    if options.torques {
        planned.add_torques(&TorqueOptions::default())?;
    }
    let report = PlanReport::new(&planned, false);
    let (plan, torques) = (planned.plan, planned.torques);
    Ok(Planned { plan, report, torques })
}

/// The control effort `integral_0^T |u(t)|^2 dt` [rad^2/s] from the samples of `u = (dq1, dq2)`
/// by the composite Simpson rule (with Simpson's 3/8 rule on the last three intervals when
/// their number is odd, the trapezoid for a single interval): error O(h^4).
pub fn effort(t: &[f64], dq: &[[f64; 3]]) -> f64 {
    let f: Vec<f64> = dq.iter().map(|d| d[1] * d[1] + d[2] * d[2]).collect();
    let n = f.len().saturating_sub(1);
    if n == 0 {
        return 0.0;
    }
    let h = (t[n] - t[0]) / n as f64;
    if n == 1 {
        return h * (f[0] + f[1]) / 2.0;
    }
    let simpson = |f: &[f64]| -> f64 {
        let m = f.len() - 1;
        let inner: f64 = (1..m).map(|i| if i % 2 == 1 { 4.0 * f[i] } else { 2.0 * f[i] }).sum();
        h / 3.0 * (f[0] + inner + f[m])
    };
    if n.is_multiple_of(2) {
        simpson(&f)
    } else {
        let (head, tail) = (&f[..=n - 3], &f[n - 3..]);
        let head = if head.len() > 1 { simpson(head) } else { 0.0 };
        head + 3.0 * h / 8.0 * (tail[0] + 3.0 * tail[1] + 3.0 * tail[2] + tail[3])
    }
}

/// A certified plan: the sampled trajectory as NumPy arrays (SI units, radians) and its
/// certificate, the report of `freefloat plan --format json`.
#[pyclass(name = "Plan", module = "freefloat", frozen)]
pub struct PyPlan {
    /// Sample times [s], shape (N,).
    #[pyo3(get)]
    t: Py<PyArray1<f64>>,
    /// Configurations (phi, theta1, theta2) [rad], shape (N, 3).
    #[pyo3(get)]
    q: Py<PyArray2<f64>>,
    /// Velocities [rad/s], shape (N, 3); columns 1-2 are the controls u.
    #[pyo3(get)]
    dq: Py<PyArray2<f64>>,
    /// Accelerations [rad/s^2], shape (N, 3), or None when not computed.
    #[pyo3(get)]
    ddq: Option<Py<PyArray2<f64>>>,
    /// Chained-form state z, shape (N, 3) (NFA), else None.
    #[pyo3(get)]
    z: Option<Py<PyArray2<f64>>>,
    /// Joint torques (tau1, tau2) [N m], shape (N, 2), with torques=True, else None.
    #[pyo3(get)]
    tau: Option<Py<PyArray2<f64>>>,
    /// The method: "nfa" or "ecsa".
    #[pyo3(get)]
    method: String,
    /// The NFA's transformation ("eq11", "eq12", "eq14", "global"), None for ECSA.
    #[pyo3(get)]
    transform: Option<String>,
    /// integral of |u|^2 dt [rad^2/s], composite Simpson over the samples.
    #[pyo3(get)]
    effort: f64,
    /// Verified final error max_i |wrap(q_i(T) - qd_i)| [rad].
    #[pyo3(get)]
    final_error: f64,
    /// Its tolerance [rad].
    #[pyo3(get)]
    tolerance: f64,
    /// Every certificate holds (velocity level, and torque level with torques).
    #[pyo3(get)]
    certified: bool,
    report: Value,
    certificate: PyOnceLock<Py<PyDict>>,
}

#[pymethods]
impl PyPlan {
    /// The certificate: the CLI's JSON report as a dict (same keys), built on first access.
    #[getter]
    fn certificate(&self, py: Python<'_>) -> PyResult<Py<PyDict>> {
        let dict = self.certificate.get_or_try_init(py, || -> PyResult<Py<PyDict>> {
            let map = self.report.as_object().cloned().unwrap_or_default();
            Ok(json_dict(py, &map)?.unbind())
        })?;
        Ok(dict.clone_ref(py))
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let n = self.t.bind(py).len().unwrap_or(0);
        let transform = self.transform.as_deref().map(|t| format!(", transform='{t}'")).unwrap_or_default();
        format!(
            "Plan(method='{}'{transform}, samples={n}, final_error={:.3e}, certified={}, effort={:.6})",
            self.method,
            self.final_error,
            if self.certified { "True" } else { "False" },
            self.effort
        )
    }
}

/// The Python plan of `planned`; `NotCertified` (carrying the plan) when a certificate fails.
pub fn into_python(py: Python<'_>, planned: Planned) -> PyResult<Bound<'_, PyPlan>> {
    let Planned { plan, report, torques } = planned;
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
        method: method_name(&report_value),
        transform: report.transform.map(|t| t.name().to_string()),
        effort: effort(&tr.t, &tr.dq),
        final_error: v.final_error,
        tolerance: v.tolerance,
        certified: report.certified,
        report: report_value,
        certificate: PyOnceLock::new(),
    };
    let failure = plan.certified().err().or_else(|| torques.as_ref().and_then(|t| t.check().err()));
    let bound = Bound::new(py, py_plan)?;
    match failure {
        Some(e) => Err(library_error(py, &e, Some(bound.into_any()))),
        None => Ok(bound),
    }
}

fn method_name(report: &Value) -> String {
    report.get("method").and_then(Value::as_str).unwrap_or_default().to_string()
}

/// The problem of the arguments, validated.
pub fn problem(
    py: Python<'_>,
    robot: &PyRobot,
    start: &[f64],
    goal: &[f64],
    horizon: f64,
) -> PyResult<PlanningProblem> {
    let start = freefloat::Configuration::from_array(triple(py, "start", start)?);
    let goal = freefloat::Configuration::from_array(triple(py, "goal", goal)?);
    PlanningProblem::new(robot.inner, start, goal, horizon).py_result(py)
}

/// Plans a motion from `start` to `goal` in time `T` and certifies it; see the stub for the
/// keywords.
#[pyfunction]
#[pyo3(signature = (
    robot, start, goal, T, *, method = "nfa", transform = "auto", samples = 1001, torques = false,
    tolerance = 1e-9, harmonics = 1, window = "none"
))]
#[allow(non_snake_case, clippy::too_many_arguments)]
pub fn plan<'py>(
    py: Python<'py>,
    robot: PyRef<'py, PyRobot>,
    start: Vec<f64>,
    goal: Vec<f64>,
    T: f64,
    method: &str,
    transform: &str,
    samples: i64,
    torques: bool,
    tolerance: f64,
    harmonics: i64,
    window: &str,
) -> PyResult<Bound<'py, PyPlan>> {
    let problem = problem(py, &robot, &start, &goal, T)?;
    let options = Options::parse(transform, samples, torques, tolerance, harmonics, window).py_result(py)?;
    let planned = py.detach(|| plan_core(method, &problem, &options)).py_result(py)?;
    into_python(py, planned)
}

/// Plans the same problem with each of `methods` (default: all), returning a dict method ->
/// Plan; with `strict=False` a method without a certified plan maps to its exception instead.
#[pyfunction]
#[pyo3(signature = (
    robot, start, goal, T, *, methods = None, transform = "auto", samples = 1001, torques = false,
    tolerance = 1e-9, harmonics = 1, window = "none", strict = true
))]
#[allow(non_snake_case, clippy::too_many_arguments)]
pub fn compare<'py>(
    py: Python<'py>,
    robot: PyRef<'py, PyRobot>,
    start: Vec<f64>,
    goal: Vec<f64>,
    T: f64,
    methods: Option<Vec<String>>,
    transform: &str,
    samples: i64,
    torques: bool,
    tolerance: f64,
    harmonics: i64,
    window: &str,
    strict: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let problem = problem(py, &robot, &start, &goal, T)?;
    let options = Options::parse(transform, samples, torques, tolerance, harmonics, window).py_result(py)?;
    let methods = methods.unwrap_or_else(|| METHODS.iter().map(|m| m.to_string()).collect());
    let out = PyDict::new(py);
    for method in methods {
        let result = py.detach(|| plan_core(&method, &problem, &options));
        let value = match result {
            // Bad input is never a result: raise it even when not strict.
            Err(e @ BindingError::UnknownChoice { .. }) => return Err(e.into_pyerr(py)),
            Err(BindingError::Library(e)) if e.is_bad_input() => return Err(library_error(py, &e, None)),
            Err(e) => Err(e.into_pyerr(py)),
            Ok(planned) => into_python(py, planned).map(Bound::into_any),
        };
        match value {
            Ok(p) => out.set_item(&method, p)?,
            Err(e) if !strict => out.set_item(&method, e.value(py))?,
            Err(e) => return Err(e),
        }
    }
    Ok(out)
}

/// The wall time [s] of the Rust planner alone (the call `plan` makes with the GIL released,
/// without building the Python results), once per repeat: the benchmark's reference.
#[pyfunction]
#[pyo3(signature = (robot, start, goal, T, *, method = "nfa", transform = "auto", samples = 1001, torques = false, repeats = 1))]
#[allow(non_snake_case, clippy::too_many_arguments)]
pub fn _time_plan(
    py: Python<'_>,
    robot: PyRef<'_, PyRobot>,
    start: Vec<f64>,
    goal: Vec<f64>,
    T: f64,
    method: &str,
    transform: &str,
    samples: i64,
    torques: bool,
    repeats: i64,
) -> PyResult<Vec<f64>> {
    let problem = problem(py, &robot, &start, &goal, T)?;
    let options = Options::parse(transform, samples, torques, 1e-9, 1, "none").py_result(py)?;
    let repeats = count("repeats", repeats).py_result(py)?;
    py.detach(|| {
        (0..repeats)
            .map(|_| {
                let clock = Instant::now();
                let planned = plan_core(method, &problem, &options)?;
                let seconds = clock.elapsed().as_secs_f64();
                drop(planned);
                Ok(seconds)
            })
            .collect::<Result<Vec<f64>, BindingError>>()
    })
    .py_result(py)
}
