//! Planners and trackers by name, and the command line, for the module's functions: each
//! call resolves names in a registry of the built-ins plus the registered Python plugins.

use std::path::Path;

use magbench_planners::Planner;
use magbench_trackers::{LoopOptions, Tracker};
use pyo3::prelude::*;

use crate::calls::detached;
use crate::errors::input_error;
use crate::plugins;

/// The planner `name` with `params` set; errors name `<python>`.
pub fn planner(
    py: Python<'_>,
    name: &str,
    params: &[(String, String)],
) -> PyResult<Box<dyn Planner>> {
    plugins::registry(py)?
        .planners()
        .create_in("<python>", name, params)
        .map_err(|e| input_error(py, &e))
}

/// The tracker `name` and the loop's options with `params` set; errors name `<python>`.
pub fn tracker(
    py: Python<'_>,
    name: &str,
    params: &[(String, String)],
) -> PyResult<(Box<dyn Tracker>, LoopOptions)> {
    plugins::registry(py)?
        .trackers()
        .build(name, params, "<python>")
        .map_err(|e| input_error(py, &e))
}

/// Runs the command line `magbench ARGS…` with the GIL released (Python plugins take it for
/// each call).
pub fn run_cli(py: Python<'_>, args: Vec<String>) -> PyResult<()> {
    let cli = magbench::Cli::with_registry(plugins::registry(py)?);
    let argv: Vec<String> = std::iter::once("magbench".to_string())
        .chain(args)
        .collect();
    detached(py, "magbench", move || cli.run_args(argv))
}

/// The name of the experiment in `path`.
pub fn experiment_name(py: Python<'_>, path: &Path) -> PyResult<String> {
    let ex = magbench::run::real::RealExecutor::new(plugins::registry(py)?);
    magbench::experiment::Experiment::load(path, &ex)
        .map(|e| e.name)
        .map_err(|e| input_error(py, &e))
}
