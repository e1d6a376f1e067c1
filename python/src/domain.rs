//! `freefloat.domain` and `freefloat.Domain`: where a transformation exists on the joint torus
//! (the paper's Figs. 13-14), as a label grid and the summary of `freefloat domain`.

use std::time::Instant;

use freefloat::{Configuration, Transform, paper_problem};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::compat::{DomainMap, DomainSummary};
use crate::convert::{Reals, column, json_dict};
use crate::errors::{BindingError, IntoPyResult};
use crate::planning::{count, parse_transform};
use crate::robot::{PyRobot, triple};

/// The domain map of one transformation on a grid x grid map of the (theta1, theta2) torus.
#[pyclass(name = "Domain", module = "freefloat", frozen)]
pub struct PyDomain {
    /// Component of each cell, -1 outside the domain; shape (grid, grid), int64, indexed
    /// `labels[i2, i1]` (rows theta2, columns theta1), components numbered by decreasing area.
    #[pyo3(get)]
    labels: Py<PyArray2<i64>>,
    /// Cell centres (i + 1/2) 2 pi / grid [rad], shape (grid,): the theta1 of the columns and
    /// the theta2 of the rows.
    #[pyo3(get)]
    centres: Py<PyArray1<f64>>,
    /// The transformation mapped ("eq11", "eq12", "eq14", "global").
    #[pyo3(get)]
    transform: String,
    /// Grid size N.
    #[pyo3(get)]
    grid: usize,
    /// Number of resolved connected components.
    #[pyo3(get)]
    components: usize,
    /// Area share of each resolved component, decreasing.
    #[pyo3(get)]
    component_fractions: Vec<f64>,
    /// Number of unresolved components (slivers).
    #[pyo3(get)]
    slivers: usize,
    /// Their total area share.
    #[pyo3(get)]
    sliver_fraction: f64,
    /// Area share of the whole domain.
    #[pyo3(get)]
    defined_fraction: f64,
    /// Component of the start, None outside the domain.
    #[pyo3(get)]
    start_component: Option<usize>,
    /// Component of the goal, None outside the domain.
    #[pyo3(get)]
    goal_component: Option<usize>,
    /// Area share of the start's component (0 outside the domain).
    #[pyo3(get)]
    start_component_fraction: f64,
    /// Start and goal lie in the same component.
    #[pyo3(get)]
    start_goal_connected: bool,
    /// Wall time of the map [s].
    #[pyo3(get)]
    seconds: f64,
    summary: serde_json::Value,
}

#[pymethods]
impl PyDomain {
    /// The summary of `freefloat domain --format json` (without its plan check) as a dict.
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        json_dict(py, &self.summary.as_object().cloned().unwrap_or_default())
    }

    fn __repr__(&self) -> String {
        format!(
            "Domain(transform='{}', grid={}, components={}, start_component_fraction={:.4}, start_goal_connected={})",
            self.transform,
            self.grid,
            self.components,
            self.start_component_fraction,
            if self.start_goal_connected { "True" } else { "False" }
        )
    }
}

/// Maps the domain of `transform` ("auto": the one `plan` tries first) for `robot` on a
/// grid x grid map; start and goal (default: the paper's) are located on it.
#[pyfunction]
#[pyo3(signature = (robot, transform = "auto", grid = 720, *, start = None, goal = None))]
pub fn domain<'py>(
    py: Python<'py>,
    robot: PyRef<'py, PyRobot>,
    transform: &str,
    grid: i64,
    start: Option<Reals>,
    goal: Option<Reals>,
) -> PyResult<Bound<'py, PyDomain>> {
    let robot = robot.inner;
    let transform: Transform = match parse_transform(transform).py_result(py)? {
        Some(t) => t,
        None => Transform::auto(&robot),
    };
    let grid = count("grid", grid).py_result(py)?;
    let (paper_start, paper_goal, _) = paper_problem();
    let start = match start {
        Some(q) => Configuration::from_array(triple(py, "start", &q)?),
        None => paper_start,
    };
    let goal = match goal {
        Some(q) => Configuration::from_array(triple(py, "goal", &q)?),
        None => paper_goal,
    };
    let (labels, summary, seconds) = py
        .detach(|| -> Result<(Vec<i64>, DomainSummary, f64), BindingError> {
            let clock = Instant::now();
            let map = DomainMap::new(&robot, transform, grid)?;
            let seconds = clock.elapsed().as_secs_f64();
            let mut labels = Vec::with_capacity(grid * grid);
            for i2 in 0..grid {
                for i1 in 0..grid {
                    labels.push(map.component(i1, i2).map_or(-1, |c| c as i64));
                }
            }
            Ok((labels, map.summary(&start, &goal), seconds))
        })
        .py_result(py)?;
    let labels = Array2::from_shape_vec((grid, grid), labels).expect("invariant: grid * grid labels");
    let h = std::f64::consts::TAU / grid as f64;
    let centres: Vec<f64> = (0..grid).map(|i| (i as f64 + 0.5) * h).collect();
    let summary_value = serde_json::to_value(&summary)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("invariant: the summary serialises: {e}")))?;
    Bound::new(
        py,
        PyDomain {
            labels: labels.into_pyarray(py).unbind(),
            centres: column(py, &centres).unbind(),
            transform: transform.name().to_string(),
            grid,
            components: summary.components,
            component_fractions: summary.component_fractions.clone(),
            slivers: summary.slivers,
            sliver_fraction: summary.sliver_fraction,
            defined_fraction: summary.defined_fraction,
            start_component: summary.start_component,
            goal_component: summary.goal_component,
            start_component_fraction: summary.start_component_fraction,
            start_goal_connected: summary.start_goal_connected,
            seconds,
            summary: summary_value,
        },
    )
}
