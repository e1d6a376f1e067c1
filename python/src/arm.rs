//! `freefloat.Arm`: any planar serial arm (n links, link inertias), as the command line reads it
//! (a TOML robot file with `[[link]]`, or a URDF). Its plans are `crate::arm_plan`'s.

use std::path::PathBuf;

use freefloat::{Arm, Base, Link, Mount};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::compat::InputError;
use crate::convert::Reals;
use crate::errors::{BindingError, IntoPyResult};
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
pub(crate) fn exactly(
    py: Python<'_>,
    name: &str,
    values: Reals,
    n: usize,
    expected: &'static str,
) -> PyResult<Vec<f64>> {
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
    /// The arm carries limits or shapes of its own (its robot file's `[limits]`, `[[link.shape]]`
    /// ...): `freefloat.plan` then plans it by the arm pipeline, which checks them, even with
    /// 2 links.
    #[getter]
    fn constrained(&self) -> bool {
        !self.inner.limits.is_empty() || !self.inner.geometry.is_empty()
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
