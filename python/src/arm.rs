//! `freefloat.Arm`, `freefloat.plan_arm` and `freefloat.ArmPlan`: any planar serial arm (n
//! links, link inertias), as the command line reads it (a TOML robot file with `[[link]]`, or a
//! URDF), planned by the library's one entry point for arms ([`plan_arm`]) with its
//! certificates; results as NumPy arrays, the CLI's JSON report as the certificate.

use std::path::PathBuf;

use freefloat::planners::arm::{ArmRequest, plan_arm as library_plan_arm};
use freefloat::planners::chain::ChainProblem;
use freefloat::planners::optimal::Cost;
use freefloat::report::arm::{ArmReport, trajectory};
use freefloat::{Arm, Base, EcsaOptions, Link, Method, Mount, Window};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyList};
use serde_json::Value;

use crate::compat::InputError;
use crate::convert::{Reals, column, report_dict};
use crate::errors::{BindingError, IntoPyResult, library_error};
use crate::planning::{count, parse_method, parse_window};
use crate::robot::PyRobot;

/// The keys of a link given as a dict, in the order of a link given as a tuple.
const LINK_KEYS: [&str; 4] = ["length", "com", "mass", "inertia"];

/// A planar free-floating robot with a serial arm of `n` revolute links (SI units): a base of
/// mass `M` and inertia `I`, links `(length, com, mass, inertia)` from the base outwards, joint
/// 1 mounted at `(a, b)` in the base frame. Immutable.
#[pyclass(name = "Arm", module = "freefloat", frozen, eq)]
#[derive(Debug, Clone, PartialEq)]
pub struct PyArm {
    /// The validated arm.
    pub inner: Arm,
}

/// `BadInput` for a parameter named `name`.
fn bad(name: String, value: f64, expected: &'static str) -> BindingError {
    BindingError::Library(freefloat::Error::from(InputError::InvalidParameter { name, value, expected }))
}

/// One number of a link, else `TypeError` naming its key.
fn number(item: &Bound<'_, PyAny>, key: &str) -> PyResult<f64> {
    item.extract::<f64>().map_err(|_| {
        let type_name = item.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "?".into());
        PyTypeError::new_err(format!("{key}: expected a number, got {type_name}"))
    })
}

/// The links of `Arm(links=...)`: dicts `{"length", "com", "mass", "inertia"}` (inertia
/// optional, 0) or sequences `(length, com, mass[, inertia])`. Keys are named as the robot file
/// names them, `link[k].mass` with `k` from 1.
fn parse_links(py: Python<'_>, links: &Bound<'_, PyAny>) -> PyResult<Vec<Link>> {
    if links.is_instance_of::<PyDict>() || links.extract::<String>().is_ok() {
        return Err(PyTypeError::new_err("links: expected a sequence of links (dicts or tuples), one per joint"));
    }
    let mut out = Vec::new();
    for (i, item) in links.try_iter()?.enumerate() {
        let item = item?;
        let key = |field: &str| format!("link[{}].{field}", i + 1);
        let mut values = [f64::NAN, f64::NAN, f64::NAN, 0.0];
        if let Ok(dict) = item.cast::<PyDict>() {
            for (k, v) in dict.iter() {
                let name: String =
                    k.extract().map_err(|_| PyTypeError::new_err(format!("{}: keys are strings", key(""))))?;
                let Some(j) = LINK_KEYS.iter().position(|x| *x == name) else {
                    let name = key(&name);
                    let message = format!("unknown key `{name}`");
                    let expected = "the keys length, com, mass and inertia";
                    return Err(BindingError::Key { kind: "unknown_key", name, message, expected }.into_pyerr(py));
                };
                values[j] = number(&v, &key(LINK_KEYS[j]))?;
            }
            for field in &LINK_KEYS[..3] {
                if !dict.contains(field)? {
                    let name = key(field);
                    let message = format!("missing key `{name}`");
                    let expected = "length, com and mass in every link (inertia defaults to 0)";
                    return Err(BindingError::Key { kind: "missing_key", name, message, expected }.into_pyerr(py));
                }
            }
        } else {
            let fields: Vec<Bound<'_, PyAny>> = item
                .try_iter()
                .and_then(|it| it.collect::<PyResult<Vec<_>>>())
                .map_err(|_| PyTypeError::new_err(format!("link[{}]: expected a dict or a tuple", i + 1)))?;
            if !(3..=4).contains(&fields.len()) {
                let expected = "a link (length, com, mass[, inertia]) of 3 or 4 numbers";
                return Err(bad(format!("link[{}]", i + 1), fields.len() as f64, expected).into_pyerr(py));
            }
            for (j, v) in fields.iter().enumerate() {
                values[j] = number(v, &key(LINK_KEYS[j]))?;
            }
        }
        let [length, com, mass, inertia] = values;
        out.push(Link { length, com, mass, inertia });
    }
    Ok(out)
}

/// A link as the dict `{"length", "com", "mass", "inertia"}`.
fn link_dict<'py>(py: Python<'py>, link: &Link) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("length", link.length)?;
    d.set_item("com", link.com)?;
    d.set_item("mass", link.mass)?;
    d.set_item("inertia", link.inertia)?;
    Ok(d)
}

/// `n` numbers from a sequence, else `BadInput` naming it.
fn exactly(py: Python<'_>, name: &str, values: Reals, n: usize, expected: &'static str) -> PyResult<Vec<f64>> {
    if values.len() == n {
        Ok(values.0)
    } else {
        Err(bad(format!("{name}.len"), values.len() as f64, expected).into_pyerr(py))
    }
}

#[pymethods]
impl PyArm {
    /// The arm of the keywords; validated by the library (`BadInput` naming the key).
    #[new]
    #[pyo3(signature = (*, M, I, links, a = 0.0, b = 0.0))]
    #[allow(non_snake_case)]
    fn new(py: Python<'_>, M: f64, I: f64, links: &Bound<'_, PyAny>, a: f64, b: f64) -> PyResult<Self> {
        let links = parse_links(py, links)?;
        Arm::new(Base { mass: M, inertia: I }, Mount { a, b }, links).map(|inner| Self { inner }).py_result(py)
    }

    /// Reads and validates a robot file: a URDF when the name ends in `.urdf`, else TOML.
    #[staticmethod]
    fn from_file(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        Arm::load(&path).map(|inner| Self { inner }).py_result(py)
    }

    /// The 2-link `Robot` as an arm.
    #[staticmethod]
    fn from_robot(robot: PyRef<'_, PyRobot>) -> Self {
        Self { inner: Arm::from_params(&robot.inner) }
    }

    /// The 2-link arm as a `Robot` (for `plan`'s every method), else `BadInput`.
    fn to_robot(&self, py: Python<'_>) -> PyResult<PyRobot> {
        match self.inner.as_src() {
            Some(inner) => Ok(PyRobot { inner }),
            None => {
                let expected = "an arm of 2 links with com > 0 on both (the 2-link robot of freefloat.plan)";
                Err(bad("link".into(), self.inner.joints() as f64, expected).into_pyerr(py))
            }
        }
    }

    /// The arm as a TOML robot file (`[robot]`, `[mount]`, `[[link]]`).
    fn to_toml(&self) -> String {
        self.inner.to_toml()
    }

    /// The arm as a URDF that `from_file` reads back to the same arm.
    fn to_urdf(&self) -> String {
        self.inner.to_urdf()
    }

    /// The same arm mounted at `(a, b)` [m].
    fn with_mount(&self, py: Python<'_>, a: f64, b: f64) -> PyResult<Self> {
        Arm::new(self.inner.base, Mount { a, b }, self.inner.links.clone()).map(|inner| Self { inner }).py_result(py)
    }

    /// The angular momentum `F phi' + G . theta'` [kg m^2/s] at `q` [rad] with velocities `dq`
    /// [rad/s] (n + 1 values each); zero along every plan.
    fn momentum(&self, py: Python<'_>, q: Reals, dq: Reals) -> PyResult<f64> {
        let n = self.inner.joints();
        let expected = "n + 1 numbers (phi, theta_1..theta_n)";
        let q = exactly(py, "q", q, n + 1, expected)?;
        let dq = exactly(py, "dq", dq, n + 1, expected)?;
        let (f, g) = self.inner.momentum_coefficients(&q[1..]);
        Ok(f * dq[0] + g.iter().zip(&dq[1..]).map(|(g, w)| g * w).sum::<f64>())
    }

    /// The free-floating inverse kinematics of the tool pose `pose = (x, y, psi)` [m, m, rad]
    /// (inertial frame, the system's centre of mass at the origin) from `start` (n + 1 angles
    /// [rad]; each angle of a solution the representative nearest the start's): every branch
    /// tried, as dicts `{"branch", "q", "residual" [m], "reached"}` (the command line's
    /// `--to-ee` branches). A pose out of reach is `BadInput` with the reach.
    fn inverse_kinematics<'py>(&self, py: Python<'py>, pose: Reals, start: Reals) -> PyResult<Bound<'py, PyList>> {
        let n = self.inner.joints();
        let pose = exactly(py, "pose", pose, 3, "three numbers (x [m], y [m], psi [rad])")?;
        let start = exactly(py, "start", start, n + 1, "n + 1 numbers (phi, theta_1..theta_n) [rad]")?;
        for (name, values) in [("pose", &pose), ("start", &start)] {
            if let Some((i, x)) = values.iter().enumerate().find(|(_, x)| !x.is_finite()) {
                return Err(bad(format!("{name}[{i}]"), *x, "finite numbers").into_pyerr(py));
            }
        }
        let branches = self
            .inner
            .inverse_kinematics((pose[0], pose[1], pose[2]), &start)
            .map_err(InputError::from)
            .py_result(py)?;
        let out = PyList::empty(py);
        for b in branches {
            let d = PyDict::new(py);
            d.set_item("branch", b.branch)?;
            d.set_item("q", b.q)?;
            d.set_item("residual", b.residual)?;
            d.set_item("reached", b.reached)?;
            out.append(d)?;
        }
        Ok(out)
    }

    /// The number of joints `n`.
    #[getter]
    fn joints(&self) -> usize {
        self.inner.joints()
    }
    /// Base mass [kg].
    #[getter(M)]
    fn base_mass(&self) -> f64 {
        self.inner.base.mass
    }
    /// Base moment of inertia [kg m^2].
    #[getter(I)]
    fn base_inertia(&self) -> f64 {
        self.inner.base.inertia
    }
    /// Mounting point along the base's X axis [m].
    #[getter]
    fn a(&self) -> f64 {
        self.inner.mount.a
    }
    /// Mounting point along the base's Y axis [m].
    #[getter]
    fn b(&self) -> f64 {
        self.inner.mount.b
    }
    /// The links as dicts `{"length", "com", "mass", "inertia"}` (a new list on each access).
    #[getter]
    fn links<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for link in &self.inner.links {
            list.append(link_dict(py, link)?)?;
        }
        Ok(list)
    }

    /// Pickling (`pickle`, `copy`, Dask, multiprocessing): the arm is rebuilt from its keywords
    /// through the validating constructor, equal to this one.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let kwargs = PyDict::new(py);
        kwargs.set_item("M", self.inner.base.mass)?;
        kwargs.set_item("I", self.inner.base.inertia)?;
        kwargs.set_item("links", self.links(py)?)?;
        kwargs.set_item("a", self.inner.mount.a)?;
        kwargs.set_item("b", self.inner.mount.b)?;
        crate::convert::new_with_keywords(py, py.get_type::<Self>().into_any(), kwargs)
    }

    fn __repr__(&self) -> String {
        let r = &self.inner;
        let links = r
            .links
            .iter()
            .map(|l| {
                format!(
                    "{{'length': {:?}, 'com': {:?}, 'mass': {:?}, 'inertia': {:?}}}",
                    l.length, l.com, l.mass, l.inertia
                )
            })
            .collect::<Vec<_>>()
            .join(", ");
        format!(
            "Arm(M={:?}, I={:?}, links=[{links}], a={:?}, b={:?})",
            r.base.mass, r.base.inertia, r.mount.a, r.mount.b
        )
    }
}

/// A certified plan of an arm: the sampled trajectory as NumPy arrays (SI units, radians) and
/// its certificate, the report of `freefloat plan --format json` for the arm.
#[pyclass(name = "ArmPlan", module = "freefloat", frozen)]
pub struct PyArmPlan {
    /// Sample times [s], shape (S,).
    #[pyo3(get)]
    t: Py<PyArray1<f64>>,
    /// Configurations (phi, theta_1..theta_n) [rad], shape (S, n + 1).
    #[pyo3(get)]
    q: Py<PyArray2<f64>>,
    /// Velocities [rad/s], shape (S, n + 1); columns 1.. are the controls u.
    #[pyo3(get)]
    dq: Py<PyArray2<f64>>,
    /// Joint accelerations [rad/s^2], shape (S, n).
    #[pyo3(get)]
    ddtheta: Py<PyArray2<f64>>,
    /// Accelerations (phi'', theta_1''..theta_n'') [rad/s^2], shape (S, n + 1).
    #[pyo3(get)]
    ddq: Py<PyArray2<f64>>,
    /// The base's centre of mass (xb, yb) [m], shape (S, 2), the system's centre of mass at 0.
    #[pyo3(get)]
    base: Py<PyArray2<f64>>,
    /// The tool's pose (xe, ye, psie) [m, m, rad], shape (S, 3).
    #[pyo3(get)]
    end_effector: Py<PyArray2<f64>>,
    /// Its velocity [m/s, m/s, rad/s], shape (S, 3).
    #[pyo3(get)]
    end_effector_velocity: Py<PyArray2<f64>>,
    /// Joint torques [N m], shape (S, n), with torques=True, else None.
    #[pyo3(get)]
    tau: Option<Py<PyArray2<f64>>>,
    /// "optimal".
    #[pyo3(get)]
    method: String,
    /// The number of joints n.
    #[pyo3(get)]
    joints: usize,
    /// The horizon T [s]: the one given, or with `T="auto"` the shortest one found.
    #[pyo3(get)]
    horizon: f64,
    /// integral of |theta'|^2 dt [rad^2/s] (exact).
    #[pyo3(get)]
    effort: f64,
    /// Verified final error [rad].
    #[pyo3(get)]
    final_error: f64,
    /// Its tolerance [rad].
    #[pyo3(get)]
    tolerance: f64,
    /// Every certificate computed holds.
    #[pyo3(get)]
    certified: bool,
    report: Value,
    certificate: PyOnceLock<Py<PyDict>>,
}

#[pymethods]
impl PyArmPlan {
    /// The certificate: the CLI's JSON report as a dict (same keys), built on first access.
    #[getter]
    fn certificate(&self, py: Python<'_>) -> PyResult<Py<PyDict>> {
        report_dict(py, &self.certificate, &self.report)
    }

    /// Pickling: every array and number, and the report as its JSON text; rebuilt by
    /// `freefloat._freefloat._arm_plan_from_state`, equal field by field.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyDict>,))> {
        let state = PyDict::new(py);
        state.set_item("t", self.t.clone_ref(py))?;
        state.set_item("q", self.q.clone_ref(py))?;
        state.set_item("dq", self.dq.clone_ref(py))?;
        state.set_item("ddtheta", self.ddtheta.clone_ref(py))?;
        state.set_item("ddq", self.ddq.clone_ref(py))?;
        state.set_item("base", self.base.clone_ref(py))?;
        state.set_item("end_effector", self.end_effector.clone_ref(py))?;
        state.set_item("end_effector_velocity", self.end_effector_velocity.clone_ref(py))?;
        state.set_item("tau", self.tau.as_ref().map(|a| a.clone_ref(py)))?;
        state.set_item("method", &self.method)?;
        state.set_item("joints", self.joints)?;
        state.set_item("horizon", self.horizon)?;
        state.set_item("effort", self.effort)?;
        state.set_item("final_error", self.final_error)?;
        state.set_item("tolerance", self.tolerance)?;
        state.set_item("certified", self.certified)?;
        state.set_item("report", self.report.to_string())?;
        Ok((py.import("freefloat._freefloat")?.getattr("_arm_plan_from_state")?, (state,)))
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let n = self.t.bind(py).len().unwrap_or(0);
        format!(
            "ArmPlan(method='{}', joints={}, samples={n}, final_error={:.3e}, certified={}, effort={:.6})",
            self.method,
            self.joints,
            self.final_error,
            if self.certified { "True" } else { "False" },
            self.effort
        )
    }
}

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
        freefloat::Error::Input(InputError::InvalidParameter { name, value, expected })
            if name == "--method" || name == "--time auto" =>
        {
            let name = if name == "--method" { "method" } else { "T=\"auto\"" };
            freefloat::Error::Input(InputError::InvalidParameter { name: name.into(), value, expected })
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
    arm, start, goal, T, *, samples = 1001, torques = false, wrap = true, initial_velocity = None,
    tolerance = 1e-9, method = "optimal", harmonics = 1, window = "none", smooth_ends = false, cost = "effort",
    limits = None, obstacles = None, clearance = None, no_collide = None
))]
#[allow(non_snake_case, clippy::too_many_arguments)]
pub fn plan_arm<'py>(
    py: Python<'py>,
    arm: &Bound<'py, PyAny>,
    start: Reals,
    goal: Reals,
    T: &Bound<'py, PyAny>,
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
) -> PyResult<Bound<'py, PyArmPlan>> {
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
    if n == 2 && method != Method::Optimal {
        // The library's reason ("another number of links") is not this arm's: point to `plan`.
        let message = format!("plan_arm has no method={:?} for a 2-link arm", method.name());
        let expected =
            "method=\"optimal\"; the NFA and ECSA plan a 2-link arm with freefloat.plan(arm.to_robot(), ...)";
        return Err(
            BindingError::Key { kind: "invalid_parameter", name: "method".into(), message, expected }.into_pyerr(py)
        );
    }
    let samples = count("samples", samples).py_result(py)?;
    let angles = "n + 1 numbers (phi, theta_1..theta_n) [rad]";
    let start = exactly(py, "start", start, n + 1, angles)?;
    let goal = exactly(py, "goal", goal, n + 1, angles)?;
    let initial_velocity = match initial_velocity {
        None => vec![0.0; n],
        Some(v) => exactly(py, "initial_velocity", v, n, "n numbers (dtheta_1..dtheta_n) [rad/s]")?,
    };
    let problem = ChainProblem { start, goal, horizon, initial_velocity, wrap };
    problem.validate(&arm).py_result(py)?;
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
    let planned = py.detach(|| library_plan_arm(&arm, method, &request)).map_err(python_names).py_result(py)?;

    let report = ArmReport::new(&planned, &request.problem.start, &request.problem.goal, false);
    let report_value = serde_json::to_value(&report).map_err(|e| {
        pyo3::exceptions::PyRuntimeError::new_err(format!("invariant: the arm's report serialises: {e}"))
    })?;
    let tr = trajectory(&planned);
    let v = planned.verification();
    let py_plan = PyArmPlan {
        t: column(py, &tr.t).unbind(),
        q: matrix(py, &tr.q, n + 1)?.unbind(),
        dq: matrix(py, &tr.dq, n + 1)?.unbind(),
        ddtheta: matrix(py, &tr.ddtheta, n)?.unbind(),
        ddq: matrix(py, &tr.ddq, n + 1)?.unbind(),
        base: matrix(py, &rows(&tr.base), 2)?.unbind(),
        end_effector: matrix(py, &rows(&tr.end_effector), 3)?.unbind(),
        end_effector_velocity: matrix(py, &rows(&tr.end_effector_velocity), 3)?.unbind(),
        tau: tr.tau.as_deref().map(|tau| matrix(py, tau, n).map(Bound::unbind)).transpose()?,
        method: planned.method.name().to_string(),
        joints: n,
        horizon: planned.plan.horizon(),
        effort: planned.effort(),
        final_error: v.final_error,
        tolerance: v.tolerance,
        certified: report.certified,
        report: report_value,
        certificate: PyOnceLock::new(),
    };
    let failure = planned.certified().err();
    let bound = Bound::new(py, py_plan)?;
    match failure {
        Some(e) => Err(library_error(py, &e, Some(bound.into_any()))),
        None => Ok(bound),
    }
}

/// The `freefloat.ArmPlan` of a pickled state (see `ArmPlan.__reduce__`).
#[pyfunction]
pub fn _arm_plan_from_state(state: &Bound<'_, PyDict>) -> PyResult<PyArmPlan> {
    let get = |key: &str| -> PyResult<Bound<'_, PyAny>> {
        state.get_item(key)?.ok_or_else(|| PyTypeError::new_err(format!("ArmPlan state: missing `{key}`")))
    };
    let report: String = get("report")?.extract()?;
    let report = serde_json::from_str(&report).map_err(|e| PyTypeError::new_err(format!("ArmPlan state: {e}")))?;
    Ok(PyArmPlan {
        t: get("t")?.extract()?,
        q: get("q")?.extract()?,
        dq: get("dq")?.extract()?,
        ddtheta: get("ddtheta")?.extract()?,
        ddq: get("ddq")?.extract()?,
        base: get("base")?.extract()?,
        end_effector: get("end_effector")?.extract()?,
        end_effector_velocity: get("end_effector_velocity")?.extract()?,
        tau: get("tau")?.extract()?,
        method: get("method")?.extract()?,
        joints: get("joints")?.extract()?,
        horizon: get("horizon")?.extract()?,
        effort: get("effort")?.extract()?,
        final_error: get("final_error")?.extract()?,
        tolerance: get("tolerance")?.extract()?,
        certified: get("certified")?.extract()?,
        report,
        certificate: PyOnceLock::new(),
    })
}
