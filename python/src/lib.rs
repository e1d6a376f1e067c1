//! Python bindings of freefloat (PyO3): `freefloat.Robot`, `plan`, `compare`, `domain`, `track`,
//! and `freefloat.Arm`, `plan_arm` for any planar serial arm; both plan to the one
//! `freefloat.Plan` (`ArmPlan` is another name of it).
//!
//! The Python package is `python/freefloat/` (its exceptions in `_errors.py`, the stubs in
//! `_freefloat.pyi`); this crate is its native module `freefloat._freefloat`. Planning and
//! domain maps run with the GIL released.

mod arm;
mod arm_nfa;
mod arm_plan;
mod cli;
mod compat;
mod convert;
mod domain;
mod errors;
mod geometry;
mod limits;
mod plan_class;
mod planning;
mod robot;
mod tracking;

use pyo3::prelude::*;

/// The native module `freefloat._freefloat`.
#[pymodule]
fn _freefloat(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<robot::PyRobot>()?;
    m.add_class::<plan_class::PyPlan>()?;
    // Issue 19 item 5: one plan class for every robot; `ArmPlan` stays as its other name.
    m.add("ArmPlan", m.getattr("Plan")?)?;
    m.add_class::<domain::PyDomain>()?;
    m.add_class::<arm::PyArm>()?;
    m.add_function(wrap_pyfunction!(planning::plan, m)?)?;
    m.add_function(wrap_pyfunction!(planning::compare, m)?)?;
    m.add_function(wrap_pyfunction!(planning::_time_plan, m)?)?;
    m.add_function(wrap_pyfunction!(domain::domain, m)?)?;
    m.add_function(wrap_pyfunction!(tracking::track, m)?)?;
    m.add_function(wrap_pyfunction!(arm_plan::plan_arm, m)?)?;
    m.add_function(wrap_pyfunction!(cli::_cli_main, m)?)?;
    m.add_function(wrap_pyfunction!(plan_class::_plan_from_state, m)?)?;
    // Pickles of an `ArmPlan` made before the one class load with the same function.
    m.add("_arm_plan_from_state", m.getattr("_plan_from_state")?)?;
    m.add("METHODS", planning::METHODS.to_vec())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
