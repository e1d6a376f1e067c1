//! Conversions to Python: JSON values to Python objects, sampled columns to NumPy arrays.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::IntoPyObjectExt;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyList};
use serde_json::Value;

/// A JSON value as the Python object `json.loads` would give (dicts keep the key order).
pub fn json_to_py<'py>(py: Python<'py>, value: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => b.into_bound_py_any(py)?,
        Value::Number(n) => match (n.as_i64(), n.as_u64()) {
            (Some(i), _) => i.into_bound_py_any(py)?,
            (None, Some(u)) => u.into_bound_py_any(py)?,
            // serde_json writes non-finite floats as null; finite ones are always f64 here.
            _ => n.as_f64().unwrap_or(f64::NAN).into_bound_py_any(py)?,
        },
        Value::String(s) => s.into_bound_py_any(py)?,
        Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(json_to_py(py, item)?)?;
            }
            list.into_any()
        }
        Value::Object(map) => json_dict(py, map)?.into_any(),
    })
}

/// A JSON object as a Python dict.
pub fn json_dict<'py>(py: Python<'py>, map: &serde_json::Map<String, Value>) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (key, item) in map {
        dict.set_item(key, json_to_py(py, item)?)?;
    }
    Ok(dict)
}

/// Rows of `N` numbers as an `(rows, N)` float64 array (the vector is moved, not copied twice).
pub fn rows<'py, const N: usize>(py: Python<'py>, rows: &[[f64; N]]) -> Bound<'py, PyArray2<f64>> {
    let flat = rows.as_flattened().to_vec();
    let array = Array2::from_shape_vec((rows.len(), N), flat).expect("invariant: rows * N numbers");
    array.into_pyarray(py)
}

/// A column as a float64 array.
pub fn column<'py>(py: Python<'py>, values: &[f64]) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, values)
}

/// The JSON report `report` as a Python dict, built once into `cell` and shared after (the
/// `certificate` of `Plan` and `ArmPlan`).
pub fn report_dict(py: Python<'_>, cell: &PyOnceLock<Py<PyDict>>, report: &Value) -> PyResult<Py<PyDict>> {
    let dict = cell.get_or_try_init(py, || -> PyResult<Py<PyDict>> {
        let map = report.as_object().cloned().unwrap_or_default();
        Ok(json_dict(py, &map)?.unbind())
    })?;
    Ok(dict.clone_ref(py))
}

/// The `__reduce__` value that rebuilds an instance of `class` by `class(**kwargs)` (through
/// `copyreg.__newobj_ex__`, which pickle resolves by name at any protocol).
pub fn new_with_keywords<'py>(
    py: Python<'py>,
    class: Bound<'py, PyAny>,
    kwargs: Bound<'py, PyDict>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let newobj = py.import("copyreg")?.getattr("__newobj_ex__")?;
    let args = (class, pyo3::types::PyTuple::empty(py), kwargs).into_bound_py_any(py)?;
    Ok((newobj, args))
}

/// Real numbers from a Python sequence (a list, a tuple, a NumPy array): a complex number is a
/// `TypeError` naming the argument, never a warning with the imaginary part dropped.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Reals(pub Vec<f64>);

impl std::ops::Deref for Reals {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.0
    }
}

/// A Python complex number, a NumPy complex scalar or a complex array (`dtype.kind == "c"`).
fn is_complex(obj: &Bound<'_, PyAny>) -> bool {
    obj.is_instance_of::<pyo3::types::PyComplex>()
        || obj
            .getattr("dtype")
            .and_then(|d| d.getattr("kind"))
            .and_then(|k| k.extract::<String>())
            .is_ok_and(|k| k == "c")
}

impl<'py> FromPyObject<'_, 'py> for Reals {
    type Error = PyErr;

    fn extract(obj: Borrowed<'_, 'py, PyAny>) -> PyResult<Self> {
        let complex = || {
            pyo3::exceptions::PyTypeError::new_err(
                "complex numbers are not accepted (angles and velocities are real; the imaginary part would be dropped)",
            )
        };
        let obj: &Bound<'py, PyAny> = &obj;
        if is_complex(obj) {
            return Err(complex());
        }
        let items: Vec<Bound<'py, PyAny>> = obj.extract()?;
        items
            .iter()
            .map(|x| if is_complex(x) { Err(complex()) } else { x.extract::<f64>() })
            .collect::<PyResult<_>>()
            .map(Reals)
    }
}
