//! `freefloat.Plan`: the one plan class of every robot (issue 19 item 5). A `Robot`'s plan (the
//! 2-link pipeline: optimal, NFA, ECSA) and an `Arm`'s plan (any number of links) are the same
//! class with the same attributes; what does not apply is None (`z` and `transform` outside the
//! NFA, `elbow` outside a 2-link plan to a pose). `freefloat.ArmPlan` is another name of it.

use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::PyDict;
use serde_json::Value;

use crate::convert::report_dict;
use crate::errors::library_error;

/// A certified plan: the sampled trajectory as NumPy arrays (SI units, radians) and its
/// certificate, the report of `freefloat plan --format json`; the same class for a `Robot` and
/// for an `Arm` of any number of links `n` (2 for a `Robot`).
#[pyclass(name = "Plan", module = "freefloat", frozen)]
pub struct PyPlan {
    /// Sample times [s], shape (S,).
    #[pyo3(get)]
    pub t: Py<PyArray1<f64>>,
    /// Configurations (phi, theta_1..theta_n) [rad], shape (S, n + 1).
    #[pyo3(get)]
    pub q: Py<PyArray2<f64>>,
    /// Velocities [rad/s], shape (S, n + 1); columns 1.. are the controls u.
    #[pyo3(get)]
    pub dq: Py<PyArray2<f64>>,
    /// Accelerations [rad/s^2], shape (S, n + 1), or None when not computed (the NFA without
    /// torques).
    #[pyo3(get)]
    pub ddq: Option<Py<PyArray2<f64>>>,
    /// Chained-form state z, shape (S, 3) (NFA), else None.
    #[pyo3(get)]
    pub z: Option<Py<PyArray2<f64>>>,
    /// Joint torques [N m], shape (S, n), with torques=True, else None.
    #[pyo3(get)]
    pub tau: Option<Py<PyArray2<f64>>>,
    /// Base centre of mass (xb, yb) [m], shape (S, 2), inertial frame, the system's centre of
    /// mass at the origin.
    #[pyo3(get)]
    pub base: Py<PyArray2<f64>>,
    /// The tool's pose (xe, ye, psie) [m, m, rad], shape (S, 3); psie = phi + sum theta_i.
    #[pyo3(get)]
    pub end_effector: Py<PyArray2<f64>>,
    /// Its velocity [m/s, m/s, rad/s], shape (S, 3).
    #[pyo3(get)]
    pub end_effector_velocity: Py<PyArray2<f64>>,
    /// The method: "optimal", "nfa" or "ecsa".
    #[pyo3(get)]
    pub method: String,
    /// The NFA's transformation ("eq11", "eq12", "eq14", "global"), None for the other methods.
    #[pyo3(get)]
    pub transform: Option<String>,
    /// The elbow ("up", "down") of a `Robot`'s plan to an end-effector pose (`goal_ee`), else
    /// None (an arm's plan to a pose names its branch in `certificate["to_ee"]`).
    #[pyo3(get)]
    pub elbow: Option<String>,
    /// The number of joints n.
    #[pyo3(get)]
    pub joints: usize,
    /// The horizon T [s]: the one given, or with `T="auto"` the shortest one found.
    #[pyo3(get)]
    pub horizon: f64,
    /// integral of |u|^2 dt [rad^2/s]: the library's (exact for the optimal planner).
    #[pyo3(get)]
    pub effort: f64,
    /// Verified final error [rad].
    #[pyo3(get)]
    pub final_error: f64,
    /// Its tolerance [rad].
    #[pyo3(get)]
    pub tolerance: f64,
    /// Every certificate computed holds.
    #[pyo3(get)]
    pub certified: bool,
    /// The report (the CLI's JSON).
    pub report: Value,
    /// The report as a dict, built on first access.
    pub certificate: PyOnceLock<Py<PyDict>>,
}

#[pymethods]
impl PyPlan {
    /// The certificate: the CLI's JSON report as a dict (same keys), built on first access.
    #[getter]
    fn certificate(&self, py: Python<'_>) -> PyResult<Py<PyDict>> {
        report_dict(py, &self.certificate, &self.report)
    }

    /// Joint accelerations [rad/s^2], shape (S, n): `ddq[:, 1:]`, None where `ddq` is.
    #[getter]
    fn ddtheta<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray2<f64>>> {
        let ddq = self.ddq.as_ref()?.bind(py).readonly();
        Some(ddq.as_array().slice(numpy::ndarray::s![.., 1..]).to_owned().into_pyarray(py))
    }

    /// Pickling: every array and number, and the report as its JSON text; rebuilt by
    /// `freefloat._freefloat._plan_from_state`, equal field by field.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyDict>,))> {
        let state = PyDict::new(py);
        let optional = |a: &Option<Py<PyArray2<f64>>>| a.as_ref().map(|a| a.clone_ref(py));
        state.set_item("t", self.t.clone_ref(py))?;
        state.set_item("q", self.q.clone_ref(py))?;
        state.set_item("dq", self.dq.clone_ref(py))?;
        state.set_item("ddq", optional(&self.ddq))?;
        state.set_item("z", optional(&self.z))?;
        state.set_item("tau", optional(&self.tau))?;
        state.set_item("base", self.base.clone_ref(py))?;
        state.set_item("end_effector", self.end_effector.clone_ref(py))?;
        state.set_item("end_effector_velocity", self.end_effector_velocity.clone_ref(py))?;
        state.set_item("method", &self.method)?;
        state.set_item("transform", &self.transform)?;
        state.set_item("elbow", &self.elbow)?;
        state.set_item("joints", self.joints)?;
        state.set_item("horizon", self.horizon)?;
        state.set_item("effort", self.effort)?;
        state.set_item("final_error", self.final_error)?;
        state.set_item("tolerance", self.tolerance)?;
        state.set_item("certified", self.certified)?;
        state.set_item("report", self.report.to_string())?;
        Ok((py.import("freefloat._freefloat")?.getattr("_plan_from_state")?, (state,)))
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let n = self.t.bind(py).len();
        let transform = self.transform.as_deref().map(|t| format!(", transform='{t}'")).unwrap_or_default();
        let elbow = self.elbow.as_deref().map(|e| format!(", elbow='{e}'")).unwrap_or_default();
        format!(
            "Plan(method='{}'{transform}{elbow}, samples={n}, joints={}, final_error={:.3e}, certified={}, effort={:.6})",
            self.method,
            self.joints,
            self.final_error,
            if self.certified { "True" } else { "False" },
            self.effort
        )
    }
}

/// The Python plan `plan`, or `NotCertified` carrying it when `failure` (a certificate that
/// does not hold) is given.
pub fn certified_or_raise(
    py: Python<'_>,
    plan: PyPlan,
    failure: Option<freefloat::Error>,
) -> PyResult<Bound<'_, PyPlan>> {
    let bound = Bound::new(py, plan)?;
    match failure {
        Some(e) => Err(library_error(py, &e, Some(bound.into_any()))),
        None => Ok(bound),
    }
}

/// The `freefloat.Plan` of a pickled state (see `Plan.__reduce__`). A state pickled before the
/// one class (a `Plan` without `joints` and `horizon`, an `ArmPlan` without `z`, `transform`
/// and `elbow`; `_arm_plan_from_state` is this function) loads with those derived or None.
#[pyfunction]
pub fn _plan_from_state(state: &Bound<'_, PyDict>) -> PyResult<PyPlan> {
    let get = |key: &str| -> PyResult<Bound<'_, PyAny>> {
        state.get_item(key)?.ok_or_else(|| PyTypeError::new_err(format!("Plan state: missing `{key}`")))
    };
    // Absent (an older pickle) or None.
    let optional = |key: &str| -> PyResult<Option<Py<PyArray2<f64>>>> {
        Ok(match state.get_item(key)? {
            Some(v) => v.extract()?,
            None => None,
        })
    };
    let label = |key: &str| -> PyResult<Option<String>> {
        Ok(match state.get_item(key)? {
            Some(v) => v.extract()?,
            None => None,
        })
    };
    let report: String = get("report")?.extract()?;
    let report: Value = serde_json::from_str(&report).map_err(|e| PyTypeError::new_err(format!("Plan state: {e}")))?;
    let q: Py<PyArray2<f64>> = get("q")?.extract()?;
    let joints = match state.get_item("joints")? {
        Some(v) => v.extract()?,
        None => q.bind(state.py()).shape()[1].saturating_sub(1),
    };
    let horizon = match state.get_item("horizon")? {
        Some(v) => v.extract()?,
        None => report["time"].as_f64().unwrap_or(f64::NAN),
    };
    Ok(PyPlan {
        t: get("t")?.extract()?,
        q,
        dq: get("dq")?.extract()?,
        ddq: optional("ddq")?,
        z: optional("z")?,
        tau: optional("tau")?,
        base: get("base")?.extract()?,
        end_effector: get("end_effector")?.extract()?,
        end_effector_velocity: get("end_effector_velocity")?.extract()?,
        method: get("method")?.extract()?,
        transform: label("transform")?,
        elbow: label("elbow")?,
        joints,
        horizon,
        effort: get("effort")?.extract()?,
        final_error: get("final_error")?.extract()?,
        tolerance: get("tolerance")?.extract()?,
        certified: get("certified")?.extract()?,
        report,
        certificate: PyOnceLock::new(),
    })
}
