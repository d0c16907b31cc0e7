//! `magbench regress`: compare current results against a baseline; exit 1 on a significant
//! regression.

use std::path::PathBuf;

use clap::Args;

use super::output::out;
use crate::CliError;
use crate::regress::report::regressions;
use crate::regress::{Tolerances, compare, footer, table};
use crate::results::store::read_runs;

/// Arguments of `magbench regress`.
#[derive(Debug, Args)]
pub struct RegressArgs {
    /// The baseline results folder (e.g. results/baseline).
    pub baseline: PathBuf,
    /// The current results folder.
    pub current: PathBuf,
    /// Significance level of each one-sided test.
    #[arg(long, default_value_t = Tolerances::default().alpha)]
    pub alpha: f64,
    /// Largest acceptable drop of a success rate (absolute fraction).
    #[arg(long, default_value_t = Tolerances::default().success)]
    pub success_tolerance: f64,
    /// Largest acceptable relative growth of the median tracking error, cost or iterations.
    #[arg(long, default_value_t = Tolerances::default().relative)]
    pub tolerance: f64,
    /// Largest acceptable relative growth of the median wall-clock times.
    #[arg(long, default_value_t = Tolerances::default().time)]
    pub time_tolerance: f64,
    /// Leave out the wall-clock metrics.
    #[arg(long, conflicts_with = "gate_time")]
    pub no_time: bool,
    /// Fail on a significant slowdown too (only for results from the same, otherwise idle,
    /// machine: times depend on the machine and its load).
    #[arg(long)]
    pub gate_time: bool,
}

/// Runs `magbench regress`.
pub fn run(a: RegressArgs) -> Result<(), CliError> {
    for (name, v, max) in [
        ("--alpha", a.alpha, 1.0),
        ("--success-tolerance", a.success_tolerance, 1.0),
        ("--tolerance", a.tolerance, f64::INFINITY),
        ("--time-tolerance", a.time_tolerance, f64::INFINITY),
    ] {
        if !(v.is_finite() && v >= 0.0 && v <= max) {
            return Err(CliError::arg(
                name,
                format!("must be in [0, {max}], got {v}"),
            ));
        }
    }
    for d in [&a.baseline, &a.current] {
        if !d.join("runs.csv").is_file() {
            return Err(CliError::Input(magbench_env::InputError::new(
                d.display().to_string(),
                "runs.csv",
                "no such file: not a results folder",
            )));
        }
    }
    let tol = Tolerances {
        alpha: a.alpha,
        success: a.success_tolerance,
        relative: a.tolerance,
        time: a.time_tolerance,
        wall_clock: !a.no_time,
        gate_time: a.gate_time,
    };
    // analysis, then report
    let rows = compare(&read_runs(&a.baseline)?, &read_runs(&a.current)?, &tol);
    out!("{}\n{}", table(&rows), footer(&rows, &tol));
    let bad = regressions(&rows);
    if bad > 0 {
        return Err(CliError::Failed(format!(
            "{bad} significant regression(s) against {}",
            a.baseline.display()
        )));
    }
    Ok(())
}
