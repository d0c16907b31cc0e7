//! Planners and trackers by name, and the command line, for the module's functions.

use std::path::Path;

use clap::Parser;
use magbench_planners::Planner;
use magbench_trackers::{LoopOptions, Tracker, TrackerSpec};
use pyo3::prelude::*;

use crate::calls::detached;
use crate::errors::input_error;

/// The planner `name` with `params` set; errors name `<python>`.
pub fn planner(
    py: Python<'_>,
    name: &str,
    params: &[(String, String)],
) -> PyResult<Box<dyn Planner>> {
    magbench_planners::registry::create_in("<python>", name, params)
        .map_err(|e| input_error(py, &e))
}

/// The tracker `name` and the loop's options with `params` set; errors name `<python>`.
pub fn tracker(
    py: Python<'_>,
    name: &str,
    params: &[(String, String)],
) -> PyResult<(Box<dyn Tracker>, LoopOptions)> {
    let spec = TrackerSpec::parse(name, params, "<python>").map_err(|e| input_error(py, &e))?;
    Ok((spec.build(), spec.loop_options()))
}

/// Runs the command line `magbench ARGS…`.
pub fn run_cli(py: Python<'_>, args: Vec<String>) -> PyResult<()> {
    let argv = std::iter::once("magbench".to_string()).chain(args);
    let cli = match magbench::cli::Cli::try_parse_from(argv) {
        Ok(c) => c,
        Err(e) if !e.use_stderr() => {
            print!("{e}");
            return Ok(());
        }
        Err(e) => {
            return Err(input_error(
                py,
                &magbench_env::InputError::new("<command line>", "", e.to_string().trim_end()),
            ));
        }
    };
    detached(py, "magbench", move || magbench::cli::run(cli))
}

/// The name of the experiment in `path`.
pub fn experiment_name(py: Python<'_>, path: &Path) -> PyResult<String> {
    magbench::experiment::Experiment::load(path, &magbench::run::real::RealExecutor)
        .map(|e| e.name)
        .map_err(|e| input_error(py, &e))
}
