//! `magbench regress` flags an injected regression (the tracker's gain halved) and passes an
//! unchanged rerun with a different seed set.

mod common;

use std::path::Path;
use std::process::Command;

use common::write;

fn exp(seeds: &str) -> String {
    format!(
        "name = \"regress-test\"\nscenarios = [\"micro-factory\", \"open-field\"]\nplanners = [\"fake\"]\ntrackers = [\"fake\"]\npresets = [\"ideal\", \"realistic\"]\nseeds = {seeds}\n[limits]\niterations = 500\n"
    )
}

fn bench(file: &Path, out: &Path, gain_scale: f64) {
    let o = Command::new(env!("CARGO_BIN_EXE_magbench"))
        .args([
            "bench",
            file.to_str().unwrap(),
            "--executor",
            "fake",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ])
        .env("MAGBENCH_FAKE_TRACKER_GAIN_SCALE", gain_scale.to_string())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

fn regress(base: &Path, cur: &Path) -> (i32, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_magbench"))
        .args(["regress", base.to_str().unwrap(), cur.to_str().unwrap()])
        .output()
        .unwrap();
    (
        o.status.code().unwrap(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
    )
}

#[test]
fn flags_a_halved_gain_and_passes_a_rerun_with_other_seeds() {
    let dir = tempfile::tempdir().unwrap();
    let base_exp = write(dir.path(), "base.toml", &exp("20"));
    let other_seeds = write(
        dir.path(),
        "other.toml",
        &exp(&format!("{:?}", (100..120).collect::<Vec<u64>>())),
    );
    let (base, rerun, broken) = (
        dir.path().join("base"),
        dir.path().join("rerun"),
        dir.path().join("broken"),
    );
    bench(&base_exp, &base, 1.0);
    bench(&other_seeds, &rerun, 1.0);
    bench(&other_seeds, &broken, 0.5);

    let (code, table) = regress(&base, &rerun);
    assert_eq!(code, 0, "an unchanged rerun was flagged:\n{table}");
    assert!(table.contains("no regression"));

    let (code, table) = regress(&base, &broken);
    assert_eq!(code, 1, "a halved gain was not flagged:\n{table}");
    // the four RMS errors and the max error × 2 scenarios × 2 presets, and possibly success (errors above the fake
    // tracker's 0.3 BL limit miss the goal); never a planner metric.
    let flagged: Vec<&str> = table
        .lines()
        .filter(|l| l.ends_with("REGRESSION"))
        .collect();
    assert_eq!(
        flagged.iter().filter(|l| l.contains("_error")).count(),
        20,
        "{table}"
    );
    assert!(
        flagged
            .iter()
            .all(|l| l.contains("_error") || l.contains("success_rate")),
        "{table}"
    );
    for col in ["metric", "baseline", "current", "change", "verdict"] {
        assert!(
            table.lines().next().unwrap().contains(col),
            "{col} column missing"
        );
    }
    // The same folder against itself is no regression; a folder that is not one is exit 2.
    assert_eq!(regress(&base, &base).0, 0);
    assert_eq!(regress(&base, dir.path()).0, 2);
}
