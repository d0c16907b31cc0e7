//! Python bindings of magbench (the module `magbench._magbench`; the package `magbench`
//! wraps it). A thin layer: every operation calls the Rust crates, and input errors become
//! Python exceptions with the command line's message.

mod arrays;
mod calls;
mod errors;
mod plan;
mod plugins;
mod reference;
mod registry;
mod scenario;
mod timing;

use pyo3::prelude::*;

/// The compiled part of the `magbench` package.
#[pymodule]
fn _magbench(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("InputError", py.get_type::<errors::InputError>())?;
    m.add("MagbenchError", py.get_type::<errors::MagbenchError>())?;
    m.add_class::<scenario::Scenario>()?;
    m.add_class::<plan::Plan>()?;
    m.add_class::<reference::Reference>()?;
    m.add_function(wrap_pyfunction!(calls::plan, m)?)?;
    m.add_function(wrap_pyfunction!(calls::track, m)?)?;
    m.add_function(wrap_pyfunction!(calls::main, m)?)?;
    m.add_function(wrap_pyfunction!(calls::experiment_name, m)?)?;
    m.add_function(wrap_pyfunction!(timing::rust_call_cost, m)?)?;
    m.add_function(wrap_pyfunction!(plugins::check_plugins, m)?)?;
    m.add_function(wrap_pyfunction!(plugins::list_registry, m)?)?;
    m.add_class::<plugins::PlanProblem>()?;
    Ok(())
}
