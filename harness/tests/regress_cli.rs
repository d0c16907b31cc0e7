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
    // 12 error metrics (the team's four RMS errors, the observed and true worst agent, the
    // observed and true max, each of the two agents' observed and true RMS) × 2 scenarios × 2
    // presets, and possibly success (errors above the fake tracker's 0.3 BL limit miss the
    // goal); never a planner metric.
    let flagged: Vec<&str> = table
        .lines()
        .filter(|l| l.ends_with("REGRESSION"))
        .collect();
    assert_eq!(
        flagged.iter().filter(|l| l.contains("_error")).count(),
        48,
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

/// The columns of `runs.csv` before the per-agent and worst-agent columns were added.
const OLD_COLUMNS: &str = "run,run_id,experiment,scenario,agents,planner,planner_name,planner_params,tracker,preset,seed,max_iterations,time_limit_s,status,solved,approximate,iterations,nodes,plan_time_s,cost,goal_distance,first_solution_iteration,first_solution_time_s,plan_edges,plan_duration_s,track_status,reached_goal,time_to_goal_s,rms_error_bl,max_error_bl,rms_error_worst_agent_bl,rms_error_true_bl,rms_error_sync_bl,rms_error_time_bl,legs_completed,final_distance_bl,agent_contact,wall_contacts,missed_frames,replans,track_duration_s,track_time_s,error";

#[test]
fn a_baseline_from_before_the_per_agent_columns_compares_cleanly_and_lists_them() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(
        dir.path(),
        "trio.toml",
        "name = \"trio-regress\"\nscenarios = [\"trio-triangle\", \"open-field\"]\nplanners = [\"fake\"]\ntrackers = [\"fake\"]\npresets = [\"realistic\"]\nseeds = 10\n[limits]\niterations = 500\n",
    );
    let (old, cur) = (dir.path().join("old"), dir.path().join("cur"));
    bench(&file, &old, 1.0);
    bench(&file, &cur, 1.0);
    // the baseline as an older magbench wrote it: only the old columns
    let runs = old.join("runs.csv");
    let mut rd = csv::Reader::from_path(&runs).unwrap();
    let header = rd.headers().unwrap().clone();
    assert!(
        header.iter().any(|h| h == "rms_error_agent2_bl"),
        "{header:?}"
    );
    let keep: Vec<usize> = OLD_COLUMNS
        .split(',')
        .map(|c| header.iter().position(|h| h == c).unwrap())
        .collect();
    let mut w = csv::Writer::from_writer(vec![]);
    w.write_record(OLD_COLUMNS.split(',')).unwrap();
    for r in rd.records() {
        let r = r.unwrap();
        w.write_record(keep.iter().map(|&i| &r[i])).unwrap();
    }
    std::fs::write(&runs, w.into_inner().unwrap()).unwrap();

    let (code, table) = regress(&old, &cur);
    assert_eq!(code, 0, "{table}");
    assert!(table.contains("no regression"), "{table}");
    let new = table
        .lines()
        .find(|l| l.starts_with("new since the baseline"))
        .unwrap_or_else(|| panic!("no list of new columns:\n{table}"));
    for c in [
        "rms_error_true_worst_agent_bl",
        "max_error_true_bl",
        "rms_error_agent0_bl",
        "rms_error_true_agent2_bl",
    ] {
        assert!(new.contains(c), "{c} not listed: {new}");
    }
    // the two-agent scenario has no agent 2, the three-agent one has
    assert!(
        table.lines().any(|l| l.contains("trio-triangle")
            && l.contains("rms_error_agent2_bl")
            && l.contains("new (not in baseline)")),
        "{table}"
    );
    assert!(
        !table
            .lines()
            .any(|l| l.contains("open-field") && l.contains("agent2")),
        "{table}"
    );
    // the columns the baseline has are compared as before
    assert!(
        table
            .lines()
            .any(|l| l.contains("rms_error_worst_agent_bl") && l.ends_with("ok")),
        "{table}"
    );
}
