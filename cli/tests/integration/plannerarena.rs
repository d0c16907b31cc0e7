//! Planner Arena (`pip install plannerarena`, 1.0.1) on magbench's OMPL logs: a small sweep
//! of a planner that stops at its first solution and one that improves its cost, through
//! OMPL's `ompl_benchmark_statistics` into a database, loaded by Planner Arena's own loader and
//! drawn with its "Overall performance" and "Progress" recipes (`plannerarena/check.py`).
//!
//! The Python interpreter is `MAGBENCH_PLANNERARENA_PYTHON` (default `python3`); without
//! `plannerarena` or `ompl_benchmark_statistics` the test is skipped with a message, unless
//! `MAGBENCH_REQUIRE_PLANNERARENA=1`.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{opts, write};
use magbench::experiment::Experiment;
use magbench::run::real::RealExecutor;
use magbench::sweep::run_sweep;

const EXP: &str = r#"
name = "arena"
scenarios = ["open-field", "cargo-delivery"]
planners = ["goal-zoom-rrt", "rrt-star"]
seeds = 4
[limits]
iterations = 1500
"#;

fn skip(why: &str) {
    eprintln!("skipped: {why}");
    if std::env::var("MAGBENCH_REQUIRE_PLANNERARENA").is_ok_and(|v| v == "1") {
        panic!("MAGBENCH_REQUIRE_PLANNERARENA=1 but {why}");
    }
}

fn python() -> String {
    std::env::var("MAGBENCH_PLANNERARENA_PYTHON").unwrap_or_else(|_| "python3".into())
}

fn results(dir: &Path) -> PathBuf {
    let e = Experiment::load(&write(dir, "exp.toml", EXP), &RealExecutor::default()).unwrap();
    let out = dir.join("r");
    let s = run_sweep(&e, &RealExecutor::default(), &opts(&out, 2)).unwrap();
    assert_eq!(s.failed, 0);
    out
}

#[test]
fn planner_arena_loads_the_logs_and_draws_every_tab() {
    let script = Path::new("/usr/bin/ompl_benchmark_statistics");
    if !script.exists() {
        return skip("ompl_benchmark_statistics is not installed (apt-get install ompl-demos)");
    }
    let has_arena = Command::new(python())
        .args(["-c", "import plannerarena.database, skmisc.loess"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !has_arena {
        return skip(&format!(
            "{} cannot import plannerarena (pip install plannerarena==1.0.1; set MAGBENCH_PLANNERARENA_PYTHON)",
            python()
        ));
    }
    let dir = tempfile::tempdir().unwrap();
    let out = results(dir.path());
    let log = std::fs::read_to_string(out.join("ompl").join("open-field.log")).unwrap();
    assert!(!log.contains("experiment properties"), "{log}");
    let db = dir.path().join("arena.db");
    let logs = ["open-field", "cargo-delivery"].map(|s| out.join("ompl").join(format!("{s}.log")));
    let o = Command::new("/usr/bin/python3")
        .arg(script)
        .args(&logs)
        .arg("-d")
        .arg(&db)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let check = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/plannerarena/check.py");
    let figs = dir.path().join("figs");
    let o = Command::new(python())
        .arg(&check)
        .arg(&db)
        .arg(&figs)
        .output()
        .unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(o.status.success(), "Planner Arena failed: {text}");
    assert!(text.contains("ok: 2 problems"), "{text}");
    for f in [
        "progress-arena-open-field-best cost.png",
        "progress-arena-cargo-delivery-iterations.png",
        "performance-arena-open-field-time.png",
    ] {
        assert!(figs.join(f).exists(), "{f} not drawn: {text}");
    }
}
