//! `freefloat.Robot`: the robot's parameters with the library's validation.

use std::path::PathBuf;

use freefloat::model::InputError;
use freefloat::{Configuration, Mount, RobotParams};
use pyo3::prelude::*;

use crate::convert::Reals;

use crate::errors::{BindingError, IntoPyResult};

/// A planar free-floating robot (SI units): base of mass `M` and inertia `I`, two links
/// (`l_i`, `d_i`, `m_i`) mounted at `(a, b)` in the base frame. Immutable.
#[pyclass(name = "Robot", module = "freefloat", frozen, eq)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PyRobot {
    /// The validated parameters.
    pub inner: RobotParams,
}

#[pymethods]
impl PyRobot {
    /// Every parameter by keyword; `a`, `b` default to 0 (centred mounting).
    #[new]
    #[pyo3(signature = (*, l1, l2, d1, d2, M, I, m1, m2, a = 0.0, b = 0.0, i1 = 0.0, i2 = 0.0))]
    #[allow(non_snake_case, clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        l1: f64,
        l2: f64,
        d1: f64,
        d2: f64,
        M: f64,
        I: f64,
        m1: f64,
        m2: f64,
        a: f64,
        b: f64,
        i1: f64,
        i2: f64,
    ) -> PyResult<Self> {
        let params =
            RobotParams { l1, l2, d1, d2, base_mass: M, base_inertia: I, m1, m2, i1, i2, mount: Mount { a, b } };
        RobotParams::new(params).map(|inner| Self { inner }).py_result(py)
    }

    /// The paper's SRC manipulator, mounted at the base's centre of mass.
    #[staticmethod]
    fn src() -> Self {
        Self { inner: RobotParams::src() }
    }

    /// Reads and validates a 2-link robot file: TOML (`[robot]` and optional `[mount]`, or
    /// two `[[link]]`s with their inertias) or, for a name ending in `.urdf`, a URDF.
    #[staticmethod]
    fn from_toml(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let arm = freefloat::Arm::load(&path).py_result(py)?;
        match arm.as_src() {
            Some(inner) => Ok(Self { inner }),
            None => Err(BindingError::Library(freefloat::Error::from(InputError::InvalidParameter {
                name: "link".into(),
                value: arm.joints() as f64,
                expected: "a robot of 2 links here; load other arms with freefloat.Arm.from_file",
            }))
            .into_pyerr(py)),
        }
    }

    /// The same robot with the arm mounted at `(a, b)` [m].
    fn with_mount(&self, py: Python<'_>, a: f64, b: f64) -> PyResult<Self> {
        Mount::new(a, b).and_then(|m| self.inner.with_mount(m)).map(|inner| Self { inner }).py_result(py)
    }

    /// The angular momentum `F phi' + G theta1' + H theta2'` (Eqs. 4-5) [kg m^2/s] at `q`
    /// [rad] with velocities `dq` [rad/s]; zero along every plan.
    fn momentum(&self, py: Python<'_>, q: Reals, dq: Reals) -> PyResult<f64> {
        let q = triple(py, "q", &q)?;
        let dq = triple(py, "dq", &dq)?;
        Ok(crate::compat::momentum(&self.inner.lumped(), &Configuration::from_array(q), dq))
    }

    /// Length of link 1 [m].
    #[getter]
    fn l1(&self) -> f64 {
        self.inner.l1
    }
    /// Length of link 2 [m].
    #[getter]
    fn l2(&self) -> f64 {
        self.inner.l2
    }
    /// Joint 1 to the centre of mass of link 1 [m].
    #[getter]
    fn d1(&self) -> f64 {
        self.inner.d1
    }
    /// Joint 2 to the centre of mass of link 2 [m].
    #[getter]
    fn d2(&self) -> f64 {
        self.inner.d2
    }
    /// Base mass [kg].
    #[getter(M)]
    fn base_mass(&self) -> f64 {
        self.inner.base_mass
    }
    /// Base moment of inertia [kg m^2].
    #[getter(I)]
    fn base_inertia(&self) -> f64 {
        self.inner.base_inertia
    }
    /// Mass of link 1 [kg].
    #[getter]
    fn m1(&self) -> f64 {
        self.inner.m1
    }
    /// Mass of link 2 [kg].
    #[getter]
    fn m2(&self) -> f64 {
        self.inner.m2
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

    /// Pickling (`pickle`, `copy`, Dask, multiprocessing): the robot is rebuilt from its
    /// keywords through the validating constructor, equal to this one.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let r = &self.inner;
        let kwargs = pyo3::types::PyDict::new(py);
        for (key, value) in [
            ("l1", r.l1),
            ("l2", r.l2),
            ("d1", r.d1),
            ("d2", r.d2),
            ("M", r.base_mass),
            ("I", r.base_inertia),
            ("m1", r.m1),
            ("m2", r.m2),
            ("a", r.mount.a),
            ("b", r.mount.b),
            ("i1", r.i1),
            ("i2", r.i2),
        ] {
            kwargs.set_item(key, value)?;
        }
        crate::convert::new_with_keywords(py, py.get_type::<Self>().into_any(), kwargs)
    }

    fn __repr__(&self) -> String {
        let r = &self.inner;
        format!(
            "Robot(l1={:?}, l2={:?}, d1={:?}, d2={:?}, M={:?}, I={:?}, m1={:?}, m2={:?}, a={:?}, b={:?})",
            r.l1, r.l2, r.d1, r.d2, r.base_mass, r.base_inertia, r.m1, r.m2, r.mount.a, r.mount.b
        )
    }
}

/// Three numbers from a sequence (`q`, `start`, ...), else `BadInput` naming the argument.
pub fn triple(py: Python<'_>, name: &str, values: &[f64]) -> PyResult<[f64; 3]> {
    <[f64; 3]>::try_from(values).map_err(|_| {
        BindingError::Library(freefloat::Error::from(crate::compat::InputError::InvalidParameter {
            name: name.to_string(),
            value: values.len() as f64,
            expected: "3 numbers (phi, theta1, theta2) [rad]",
        }))
        .into_pyerr(py)
    })
}
