//! The sweep with the real planners: a run's row depends only on its spec, so a small sweep
//! gives the same rows at 1 and 2 threads (wall-clock columns aside).

use crate::common;

use std::path::{Path, PathBuf};

use common::{deterministic_progress, deterministic_runs, opts, write};
use magbench::experiment::Experiment;
use magbench::metrics::Metric;
use magbench::run::real::RealExecutor;
use magbench::sweep::run_sweep;

const EXP: &str = r#"
name = "real-small"
scenarios = ["open-field", "cargo-delivery"]
planners = ["goal-zoom-rrt", "goal-zoom-rrt{k=5, goal_bias=0.2}"]
seeds = 2
[limits]
iterations = 600
"#;

/// The experiment `text` written to `dir/name` and loaded for the real executor.
fn load(dir: &Path, name: &str, text: &str) -> Result<Experiment, magbench_env::InputError> {
    Experiment::load(&write(dir, name, text), &RealExecutor::default())
}

/// Sweeps `e` with the real executor into `dir/t1` at 1 thread and `dir/t2` at 2, each
/// executing `runs` runs without a failure; the two folders.
fn sweep_at_one_and_two_threads(dir: &Path, e: &Experiment, runs: usize) -> Vec<PathBuf> {
    [1, 2]
        .into_iter()
        .map(|threads| {
            let out = dir.join(format!("t{threads}"));
            let s = run_sweep(e, &RealExecutor::default(), &opts(&out, threads)).unwrap();
            assert_eq!((s.executed, s.failed), (runs, 0));
            out
        })
        .collect()
}

#[test]
fn real_planner_runs_are_identical_at_one_and_two_threads() {
    let dir = tempfile::tempdir().unwrap();
    let e = load(dir.path(), "exp.toml", EXP).unwrap();
    let outs = sweep_at_one_and_two_threads(dir.path(), &e, 8);
    let runs = deterministic_runs(&outs[0]);
    assert_eq!(runs, deterministic_runs(&outs[1]));
    assert_eq!(
        deterministic_progress(&outs[0]),
        deterministic_progress(&outs[1])
    );
    assert!(runs.iter().all(|r| !r[0].is_empty()));
}

#[test]
fn unknown_planners_and_parameters_are_input_errors() {
    let dir = tempfile::tempdir().unwrap();
    for (bad, field) in [
        ("\"no-such-planner\"", "planners[0]"),
        ("\"goal-zoom-rrt{kk=5}\"", "planners[0].kk"),
        ("\"goal-zoom-rrt{objective=\\\"speed\\\"}\"", "planners[0]"),
        ("\"goal-zoom-rrt{flow=\\\"euler\\\"}\"", "planners[0]"),
    ] {
        let text = EXP.replace(
            "\"goal-zoom-rrt\", \"goal-zoom-rrt{k=5, goal_bias=0.2}\"",
            bad,
        );
        let err = load(dir.path(), "bad.toml", &text).unwrap_err();
        assert_eq!(err.field, field, "{err}");
    }
}

#[test]
fn tracked_runs_fill_the_tracking_columns_deterministically() {
    let dir = tempfile::tempdir().unwrap();
    let text = "name = \"real-track\"\nscenarios = [\"open-field\"]\nplanners = [\"goal-zoom-rrt\"]\ntrackers = [\"open-loop\"]\npresets = [\"ideal\", \"realistic\"]\nseeds = 2\n[limits]\niterations = 400\n";
    let e = load(dir.path(), "exp.toml", text).unwrap();
    let outs = sweep_at_one_and_two_threads(dir.path(), &e, 4);
    assert_eq!(deterministic_runs(&outs[0]), deterministic_runs(&outs[1]));
    let runs = magbench::results::store::read_runs(&outs[0]).unwrap();
    assert!(runs.iter().all(|r| r.get(Metric::RmsError).is_some()
        && !r.track_status.is_empty()
        && r.get(Metric::TrackDuration).is_some()));
    // the path-quality metrics of the plan followed: positive lengths and clearances
    assert!(
        runs.iter()
            .all(|r| r.get(Metric::PathLength).is_some_and(|l| l > 0.0)
                && r.get(Metric::ClearanceMin).is_some_and(|c| c > 0.0)
                && r.get(Metric::ClearanceMin) <= r.get(Metric::ClearanceMean)
                && r.get(Metric::FieldVariation).is_some())
    );
    // Under the ideal preset the plant is the planning model: open-loop follows its plan.
    assert!(
        runs.iter()
            .filter(|r| r.preset == "ideal")
            .all(|r| r.get(Metric::RmsError).unwrap() < 1e-6),
        "{runs:?}"
    );
    // Bad tracker names and parameters are input errors naming the field.
    for (bad, field) in [
        ("\"nope\"", "trackers[0]"),
        ("\"obc{zz=1}\"", "trackers[0].zz"),
    ] {
        let err = load(dir.path(), "bad.toml", &text.replace("\"open-loop\"", bad)).unwrap_err();
        assert_eq!(err.field, field, "{err}");
    }
}

/// `[tracking]` with the real executor: every planner's planning runs, and tracked runs for the
/// listed plans only; the `flow` key sets the planning model of every plan of the run.
#[test]
fn a_tracking_table_plans_every_planner_and_tracks_the_listed_plans() {
    let dir = tempfile::tempdir().unwrap();
    let text = r#"
name = "real-mixed"
scenarios = ["open-field"]
planners = ["goal-zoom-rrt", "goal-zoom-rrt{flow=\"rk4\"}", "sst{stop_on_solution=true}"]
seeds = 2
[limits]
iterations = 3000
[tracking]
plans = ["goal-zoom-rrt"]
trackers = ["open-loop"]
presets = ["ideal"]
"#;
    let e = load(dir.path(), "exp.toml", text).unwrap();
    let out = dir.path().join("r");
    let s = run_sweep(&e, &RealExecutor::default(), &opts(&out, 2)).unwrap();
    assert_eq!((s.executed, s.failed), (3 * 2 + 2, 0));
    let runs = magbench::results::store::read_runs(&out).unwrap();
    let tracked: Vec<_> = runs.iter().filter(|r| !r.tracker.is_empty()).collect();
    assert_eq!(tracked.len(), 2);
    assert!(
        tracked
            .iter()
            .all(|r| r.planner == "goal-zoom-rrt" && r.get(Metric::RmsError).is_some())
    );
    assert!(
        runs.iter()
            .filter(|r| r.tracker.is_empty())
            .all(|r| r.get(Metric::RmsError).is_none() && r.status != magbench::run::Status::Crash)
    );
    // the tracked run's first plan is its planning run's (open-field has one leg), and
    // open-loop follows it exactly under the ideal preset (whose plant moves by the exact flow)
    for t in &tracked {
        let p = runs
            .iter()
            .find(|r| r.tracker.is_empty() && r.planner == t.planner && r.seed == t.seed)
            .unwrap();
        assert_eq!(
            (
                p.get(Metric::Iterations),
                p.get(Metric::Cost),
                p.get(Metric::PlanEdges)
            ),
            (
                t.get(Metric::Iterations),
                t.get(Metric::Cost),
                t.get(Metric::PlanEdges)
            )
        );
        assert!(t.get(Metric::RmsError).unwrap() < 1e-6, "{t:?}");
    }
    // rk4 and the exact flow give different plans from the same seed
    let plain = runs
        .iter()
        .find(|r| r.tracker.is_empty() && r.planner == "goal-zoom-rrt" && r.seed == 0)
        .unwrap();
    let rk4 = runs
        .iter()
        .find(|r| r.tracker.is_empty() && r.planner == "goal-zoom-rrt{flow=rk4}" && r.seed == 0)
        .unwrap();
    assert_ne!(plain.get(Metric::Cost), rk4.get(Metric::Cost));
}
