//! `magbench regress`: compare a candidate results folder against a baseline; exit 1 on a
//! regression (and, by default, on an inconclusive comparison), 2 on bad input.

use std::path::PathBuf;

use clap::Args;

use magbench_env::input::Bound;

use super::number::checked;
use crate::Error;
use crate::output::out;
use crate::regress::manifests::check;
use crate::regress::report::regressions;
use crate::regress::{OnInconclusive, Runs, Tolerances, compare_runs, failures, footer, table};

/// Arguments of `magbench regress`.
#[derive(Debug, Args)]
pub struct RegressArgs {
    /// The baseline results folder (e.g. results/baseline).
    pub baseline: PathBuf,
    /// The candidate results folder.
    pub current: PathBuf,
    /// Level of the tests: family-wise error rate of the regression decisions (Holm) and the
    /// one-sided level of each end of the intervals (which are 1 − 2·alpha two-sided).
    #[arg(long, default_value_t = Tolerances::default().alpha)]
    pub alpha: f64,
    /// Largest acceptable drop of a success rate (absolute fraction: 0.1 = 10 points).
    #[arg(long, default_value_t = Tolerances::default().success)]
    pub success_tolerance: f64,
    /// Largest acceptable relative growth of tracking errors, cost and iterations (0.1 = 10%).
    #[arg(long, default_value_t = Tolerances::default().relative)]
    pub tolerance: f64,
    /// Largest acceptable relative growth of wall-clock times (1 = 100%).
    #[arg(long, default_value_t = Tolerances::default().time)]
    pub time_tolerance: f64,
    /// Leave out the wall-clock metrics.
    #[arg(long, conflicts_with = "gate_time")]
    pub no_time: bool,
    /// Let wall-clock verdicts fail the check too (only for results from the same, otherwise
    /// idle, machine: times depend on the machine and its load).
    #[arg(long)]
    pub gate_time: bool,
    /// Whether an inconclusive verdict (too few runs to tell) fails the check.
    #[arg(long, value_enum, default_value = "fail")]
    pub inconclusive: OnInconclusive,
    /// Make differing manifests (experiment file, scenarios, limits, presets, seeds, executor,
    /// magbench version) an error (exit 2) instead of a warning.
    #[arg(long)]
    pub strict: bool,
}

/// `--alpha`: a level of the tests, in (0, 0.25].
const ALPHA: Bound = Bound::above(
    0.0,
    0.25,
    "",
    "each end of the 1 − 2·alpha intervals; above 0.25 they cover less than half and say nothing",
);

/// `--success-tolerance`: a drop of a success rate, a fraction of the runs.
const SUCCESS_TOLERANCE: Bound = Bound::closed(
    0.0,
    1.0,
    " (fraction of the runs)",
    "a success rate drops by at most 1",
);

/// `--tolerance` and `--time-tolerance`: a relative growth (1 = 100%).
const TOLERANCE: Bound = Bound::closed(
    0.0,
    1e6,
    " (relative growth)",
    "a millionfold growth; a tolerance beyond it lets every change pass",
);

/// Runs `magbench regress`.
pub fn run(a: RegressArgs) -> Result<(), Error> {
    checked("--alpha", &ALPHA, a.alpha)?;
    checked(
        "--success-tolerance",
        &SUCCESS_TOLERANCE,
        a.success_tolerance,
    )?;
    checked("--tolerance", &TOLERANCE, a.tolerance)?;
    checked("--time-tolerance", &TOLERANCE, a.time_tolerance)?;
    for d in [&a.baseline, &a.current] {
        if !d.join("runs.csv").is_file() {
            return Err(Error::Input(magbench_env::InputError::new(
                d.display().to_string(),
                "runs.csv",
                "no such file: not a results folder",
            )));
        }
    }
    let m = check(&a.baseline, &a.current)?;
    if !m.differences.is_empty() {
        let list: String = m.differences.iter().map(|d| format!("\n  - {d}")).collect();
        if a.strict {
            return Err(Error::Input(magbench_env::InputError::new(
                a.current.display().to_string(),
                "manifest.json",
                format!(
                    "--strict: the manifests of {} and {} differ:{list}",
                    a.baseline.display(),
                    a.current.display()
                ),
            )));
        }
        eprintln!(
            "warning: the two folders' manifests differ (--strict makes this an error):{list}"
        );
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
    let rows = compare_runs(&Runs::read(&a.baseline)?, &Runs::read(&a.current)?, &tol);
    if let Some(b) = &m.builds {
        out!("{b}\n\n");
    }
    out!(
        "{}\n{}",
        table(&rows, &tol),
        footer(&rows, &tol, a.inconclusive)
    );
    let bad = failures(&rows, a.inconclusive);
    if bad > 0 {
        let reg = regressions(&rows);
        return Err(Error::Failed(if reg > 0 {
            format!("{reg} regression(s) against {}", a.baseline.display())
        } else {
            format!(
                "{bad} inconclusive comparison(s) against {} (more seeds, or --inconclusive pass)",
                a.baseline.display()
            )
        }));
    }
    Ok(())
}
