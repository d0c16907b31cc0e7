//! `magbench regress` flags an injected regression (the tracker's gain halved), passes an
//! unchanged rerun of the same seeds (paired: zero-width intervals), calls a rerun with other
//! seeds inconclusive where 20 runs cannot tell (never "ok" by default), and warns about (or
//! with `--strict` refuses) folders whose manifests differ.

use crate::common;

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

fn regress_with(base: &Path, cur: &Path, flags: &[&str]) -> (i32, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_magbench"))
        .args(["regress", base.to_str().unwrap(), cur.to_str().unwrap()])
        .args(flags)
        .output()
        .unwrap();
    (
        o.status.code().unwrap(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn regress(base: &Path, cur: &Path) -> (i32, String) {
    let (code, out, _) = regress_with(base, cur, &[]);
    (code, out)
}

/// The block of the report whose heading contains `config` (blocks are separated by blank
/// lines).
fn section<'a>(table: &'a str, config: &str) -> &'a str {
    table
        .split("\n\n")
        .find(|b| b.lines().next().is_some_and(|h| h.contains(config)))
        .unwrap_or_else(|| panic!("no table for {config}:\n{table}"))
}

#[test]
fn flags_a_halved_gain_passes_a_same_seed_rerun_and_calls_other_seeds_inconclusive() {
    let dir = tempfile::tempdir().unwrap();
    let base_exp = write(dir.path(), "base.toml", &exp("20"));
    let other_seeds = write(
        dir.path(),
        "other.toml",
        &exp(&format!("{:?}", (100..120).collect::<Vec<u64>>())),
    );
    let [base, same, rerun, broken, broken_other] =
        ["base", "same", "rerun", "broken", "broken-other"].map(|d| dir.path().join(d));
    bench(&base_exp, &base, 1.0);
    bench(&base_exp, &same, 1.0);
    bench(&other_seeds, &rerun, 1.0);
    bench(&base_exp, &broken, 0.5);
    bench(&other_seeds, &broken_other, 0.5);

    // the same seeds, the same build: paired, every gated verdict ok with a zero-width interval
    let (code, table, warn) = regress_with(&base, &same, &[]);
    assert_eq!(code, 0, "an unchanged rerun was not passed:\n{table}{warn}");
    assert!(table.contains("result: pass (no regression)"), "{table}");
    assert!(table.contains("paired by seed (20 seeds)"), "{table}");
    assert!(warn.is_empty(), "{warn}");
    for l in table.lines().filter(|l| l.contains("_error")) {
        assert!(
            l.ends_with("ok") && l.contains("+0.0% [+0.0%, +0.0%]"),
            "{l}"
        );
    }

    // other seeds, the same build: unpaired; no regression, but 20 runs cannot show every
    // metric within 10%: inconclusive, which fails by default and passes when accepted
    let (code, table, warn) = regress_with(&base, &rerun, &[]);
    // wall-clock metrics are not gated: their verdicts depend on the machine's load
    assert!(!table.lines().any(|l| l.ends_with("REGRESSION")), "{table}");
    assert!(table.contains("unpaired: different seeds"), "{table}");
    assert!(table.contains("inconclusive (~"), "{table}");
    assert_eq!(code, 1, "{table}");
    assert!(
        table.contains("result: FAIL (no regression shown, but"),
        "{table}"
    );
    assert!(
        warn.contains("manifests differ")
            && warn.contains("seeds: baseline 0..19 (20 seeds), candidate 100..119 (20 seeds)"),
        "{warn}"
    );
    let (code, table, _) = regress_with(&base, &rerun, &["--inconclusive", "pass"]);
    assert_eq!(code, 0, "{table}");
    let (code, _, err) = regress_with(&base, &rerun, &["--strict"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("experiment file (sha256)") && err.contains("seeds"),
        "{err}"
    );

    // 13 error metrics (the team's five RMS errors, the observed and true worst agent, the
    // observed and true max, each of the two agents' observed and true RMS) × 2 scenarios × 2
    // presets, and possibly success (errors above the fake tracker's 0.3 BL limit miss the
    // goal); never a planner metric. Paired (same seeds) and unpaired (other seeds).
    for b in [&broken, &broken_other] {
        let (code, table) = regress(&base, b);
        assert_eq!(code, 1, "a halved gain was not flagged:\n{table}");
        let flagged: Vec<&str> = table
            .lines()
            .filter(|l| l.ends_with("REGRESSION"))
            .collect();
        assert_eq!(
            flagged.iter().filter(|l| l.contains("_error")).count(),
            52,
            "{table}"
        );
        assert!(
            flagged
                .iter()
                .all(|l| l.contains("_error") || l.contains("success_rate")),
            "{table}"
        );
        assert!(table.contains("result: FAIL ("), "{table}");
    }
    let (_, table) = regress(&base, &broken);
    for col in [
        "metric",
        "baseline",
        "candidate",
        "change [90% CI]",
        "verdict",
    ] {
        assert!(
            table.lines().nth(3).unwrap().contains(col),
            "{col} column missing:\n{table}"
        );
    }
    // The same folder against itself passes; a folder that is not one, or a bad flag, is exit 2.
    assert_eq!(regress(&base, &base).0, 0);
    assert_eq!(regress(&base, dir.path()).0, 2);
    assert_eq!(regress_with(&base, &same, &["--alpha", "0.7"]).0, 2);
    assert_eq!(
        regress_with(&base, &same, &["--inconclusive", "maybe"]).0,
        2
    );
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
    assert!(table.contains("result: pass"), "{table}");
    let new = table
        .lines()
        .find(|l| l.starts_with("new since the baseline"))
        .unwrap_or_else(|| panic!("no list of new columns:\n{table}"));
    for c in [
        "rms_error_true_worst_agent_bl",
        "max_error_true_bl",
        "rms_error_agent0_bl",
        "rms_error_true_agent2_bl",
        "rms_error_node_bl",
    ] {
        assert!(new.contains(c), "{c} not listed: {new}");
    }
    // the two-agent scenario has no agent 2, the three-agent one has
    assert!(
        section(&table, "trio-triangle")
            .lines()
            .any(|l| l.contains("rms_error_agent2_bl") && l.contains("new (not in baseline)")),
        "{table}"
    );
    assert!(!section(&table, "open-field").contains("agent2"), "{table}");
    // the columns the baseline has are compared
    assert!(
        table
            .lines()
            .any(|l| l.contains("rms_error_worst_agent_bl") && l.ends_with("ok")),
        "{table}"
    );
}
