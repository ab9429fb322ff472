//! # strider-py
//!
//! The native part of the `strider` Python package (`strider._strider`): numpy in and out over
//! the library functions the `strider` command calls. The Python side (`python/strider`) adds the
//! report object, the `gtsp` namespace and sweeps; this crate only converts and validates.
//!
//! Every entry point validates its arguments where they enter and turns every library error into
//! a `strider.StriderError` (a `ValueError`) carrying the command's one-line message, so that no
//! Rust panic or error crosses into Python.

use pyo3::prelude::*;

mod cost_model;
mod errors;
mod goal_planner;
mod gp;
mod gtsp;
mod layers;
mod map;
mod mission;
mod python_strategy;
mod rbcm;
mod sweep;

/// The `strider._strider` extension module.
#[pymodule]
fn _strider(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("StriderError", m.py().get_type::<errors::StriderError>())?;
    m.add_function(wrap_pyfunction!(mission::scenarios, m)?)?;
    m.add_function(wrap_pyfunction!(mission::scenario_layers, m)?)?;
    m.add_function(wrap_pyfunction!(mission::strategies, m)?)?;
    m.add_function(wrap_pyfunction!(mission::run, m)?)?;
    m.add_function(wrap_pyfunction!(mission::replay, m)?)?;
    m.add_function(wrap_pyfunction!(python_strategy::run_python, m)?)?;
    m.add_function(wrap_pyfunction!(gtsp::read, m)?)?;
    m.add_function(wrap_pyfunction!(gtsp::solve, m)?)?;
    m.add_function(wrap_pyfunction!(gtsp::solve_matrix, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::compare_plan, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::compare_trial, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::compare_assemble, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::table5_plan, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::table5_trial, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::table5_assemble, m)?)?;
    m.add_class::<gp::Gp>()?;
    m.add_class::<rbcm::Rbcm>()?;
    m.add_class::<cost_model::CostModel>()?;
    m.add_class::<gtsp::Instance>()?;
    m.add_class::<gtsp::Solution>()?;
    m.add_class::<map::ElevationMap>()?;
    Ok(())
}
