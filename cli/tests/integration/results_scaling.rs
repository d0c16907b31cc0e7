//! `magbench results scaling` on the command line: the exponents of time and of iterations to a
//! first solution against a size, each printed and plotted.

use std::process::Command;

use magbench::metrics::Metric;
use magbench::results::store::write_runs_atomic;
use magbench::run::RunRecord;

/// Planning runs of `planner` on serpentine problems of k walls: time 0.01·k³ s, iterations
/// 100·k² (runs of k = 16 unsolved).
fn runs(planner: &str) -> Vec<RunRecord> {
    let mut out = vec![];
    for k in [1u32, 2, 4, 8, 16] {
        for instance in 0..2 {
            let mut r = RunRecord::example();
            r.run = out.len();
            r.scenario = format!("serpentine-gap=4-walls={k}-s{instance}");
            r.planner = planner.into();
            r.solved = k < 16;
            let k = k as f64;
            if r.solved {
                r.set(Metric::FirstSolutionTime, Some(0.01 * k.powi(3)));
                r.set(Metric::FirstSolutionIteration, Some(100.0 * k.powi(2)));
            }
            out.push(r);
        }
    }
    out
}

#[test]
fn prints_and_plots_the_exponents_of_time_and_iterations() {
    let dir = tempfile::tempdir().unwrap();
    write_runs_atomic(&dir.path().join("runs.csv"), 0, &runs("a")).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_magbench"))
        .args(["results", "scaling"])
        .arg(dir.path())
        .args(["--family", "serpentine", "--by", "walls"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        text.contains("a: time to 1st solution ≈ walls^3.00 [3.00, 3.00] over 4 sizes"),
        "{text}"
    );
    assert!(
        text.contains("a: iterations to 1st solution ≈ walls^2.00 [2.00, 2.00] over 4 sizes"),
        "{text}"
    );
    assert!(
        text.contains("walls = 8: median 6400, 2/2 solved"),
        "{text}"
    );
    assert!(text.contains("walls = 16: median inf"), "{text}");
    let plots = dir.path().join("plots");
    for f in [
        "scaling-serpentine-walls.svg",
        "scaling-serpentine-walls-iterations.svg",
    ] {
        assert!(plots.join(f).is_file(), "{f}");
    }
}
