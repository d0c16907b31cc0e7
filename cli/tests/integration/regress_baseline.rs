//! CI's regression check: the small experiment `experiments/ci.toml` is run again and compared
//! with the committed baseline `results/baseline/` by `magbench regress`'s statistics, paired by
//! seed. A change that worsens tracking error, success, cost or iterations to a solution
//! beyond the tolerances fails this test, and so does a change the 32 seeds cannot show to be
//! within them (inconclusive: the default of `magbench regress`). Wall-clock times are left
//! out (CI machines differ). To update the baseline after an intended change, see docs/benchmarks.md
//! ("Regression checks").

use crate::common;

use std::path::Path;

use common::opts;
use magbench::experiment::Experiment;
use magbench::regress::{Design, OnInconclusive, Tolerances, compare, failures, footer, table};
use magbench::results::Manifest;
use magbench::results::store::read_runs;
use magbench::run::real::RealExecutor;
use magbench::sweep::run_sweep;

#[test]
fn the_ci_experiment_shows_no_regression_against_the_baseline() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let baseline = root.join("results/baseline");
    let e = Experiment::load(&root.join("experiments/ci.toml"), &RealExecutor::default()).unwrap();
    let m = Manifest::read(&baseline).unwrap();
    assert_eq!(
        m.experiment.sha256,
        e.hash(),
        "experiments/ci.toml changed since results/baseline was made: regenerate the baseline (docs/benchmarks.md, section Regression checks)"
    );
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("ci");
    let s = run_sweep(&e, &RealExecutor::default(), &opts(&out, 2)).unwrap();
    assert_eq!(s.failed, 0);
    let tol = Tolerances {
        wall_clock: false,
        gate_time: false,
        ..Tolerances::default()
    };
    let rows = compare(
        &read_runs(&baseline).unwrap(),
        &read_runs(&out).unwrap(),
        &tol,
    );
    assert_eq!(
        failures(&rows, OnInconclusive::Fail),
        0,
        "regression or inconclusive against results/baseline:\n{}\n{}",
        table(&rows, &tol),
        footer(&rows, &tol, OnInconclusive::Fail)
    );
    assert!(
        rows.iter()
            .all(|r| r.design == Design::Paired(e.seeds.len())),
        "the baseline and the rerun hold the same seeds: compared seed by seed"
    );
    assert!(
        rows.iter().any(|r| r.metric == "rms_error_bl"),
        "the check must cover tracking error"
    );
}
