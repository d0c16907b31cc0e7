//! `magbench plan`: JSON on stdout, exit codes, and the files `--out` writes.

use crate::common;

use common::magbench;

#[test]
fn json_is_one_object_with_the_documented_keys() {
    let (code, stdout, _) = magbench(&[
        "plan",
        "open-field",
        "--planner",
        "goal-zoom-rrt",
        "--seed",
        "4",
        "--json",
    ]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).expect("one JSON object");
    for key in [
        "scenario",
        "planner",
        "seed",
        "solved",
        "approximate",
        "iterations",
        "nodes",
        "time_s",
        "cost",
        "goal_distance",
    ] {
        assert!(v.get(key).is_some(), "missing {key} in {v}");
    }
    assert_eq!(v["solved"], true);
    assert_eq!(v["seed"], 4);
    assert!(v["cost"].as_f64().unwrap() > 0.0);
    // the same seed gives the same plan
    let (_, again, _) = magbench(&[
        "plan",
        "open-field",
        "--planner",
        "goal-zoom-rrt",
        "--seed",
        "4",
        "--json",
    ]);
    let w: serde_json::Value = serde_json::from_str(again.trim()).unwrap();
    assert_eq!(
        (&v["cost"], &v["iterations"]),
        (&w["cost"], &w["iterations"])
    );
}

#[test]
fn help_states_the_default_time_limit() {
    for cmd in ["plan", "track", "rig"] {
        let args: &[&str] = if cmd == "rig" {
            &["rig", "run", "--help"]
        } else {
            &[cmd, "--help"]
        };
        let (code, stdout, _) = magbench(args);
        assert_eq!(code, 0);
        let flat = stdout.split_whitespace().collect::<Vec<_>>().join(" ");
        assert!(
            flat.contains("--time-limit <TIME_LIMIT> Planner wall-time limit of every planning call (s; default 60"),
            "{cmd}: {stdout}"
        );
    }
}

#[test]
fn unsolved_exits_zero_with_null_cost() {
    let (code, stdout, _) = magbench(&[
        "plan",
        "micro-factory",
        "--planner",
        "rrt-star",
        "--max-iters",
        "20",
        "--json",
    ]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    assert_eq!(
        (
            v["solved"].clone(),
            v["approximate"].clone(),
            v["cost"].clone()
        ),
        (false.into(), true.into(), serde_json::Value::Null)
    );
}

#[test]
fn bad_input_exits_two_with_a_message() {
    for args in [
        vec!["plan", "open-field", "--planner", "rrt"],
        vec![
            "plan",
            "open-field",
            "--planner",
            "sst",
            "--param",
            "radius=1",
        ],
        vec!["plan", "open-field", "--planner", "sst", "--param", "k=0"],
        vec!["plan", "open-field", "--planner", "sst", "--param", "k"],
        vec!["plan", "no-such-scenario", "--planner", "sst"],
        vec![
            "plan",
            "open-field",
            "--planner",
            "sst",
            "--time-limit",
            "-1",
        ],
        vec![
            "plan",
            "open-field",
            "--planner",
            "sst",
            "--objective",
            "fun",
        ],
    ] {
        let (code, stdout, stderr) = magbench(&args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(
            stdout.is_empty() && stderr.starts_with("error: "),
            "{args:?}: {stderr}"
        );
    }
}

#[test]
fn out_writes_plan_csv_result_and_plot() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap();
    let (code, _, stderr) = magbench(&[
        "plan",
        "open-field",
        "--planner",
        "goal-zoom-rrt",
        "--out",
        d,
    ]);
    assert_eq!(code, 0, "{stderr}");
    for f in [
        "plan.json",
        "plan.csv",
        "result.json",
        "world.svg",
        "world.png",
    ] {
        assert!(
            dir.path()
                .join(f)
                .metadata()
                .map(|m| m.len() > 0)
                .unwrap_or(false),
            "{f} missing"
        );
    }
    let plan: magbench_planners::Plan =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("plan.json")).unwrap())
            .unwrap();
    let s = magbench_env::Scenario::load("open-field").unwrap();
    let p = magbench_planners::Problem::from_scenario(&s, 0, None, 0);
    magbench_planners::validate_plan(&p, &plan).unwrap();
    let csv = std::fs::read_to_string(dir.path().join("plan.csv")).unwrap();
    assert_eq!(csv.lines().count(), plan.states.len() + 1);
}

#[test]
fn multi_leg_scenarios_are_planned_leg_by_leg() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap();
    let (code, stdout, stderr) = magbench(&[
        "plan",
        "cargo-delivery",
        "--planner",
        "goal-zoom-rrt",
        "--json",
        "--out",
        d,
    ]);
    assert_eq!(code, 0, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    assert_eq!(v["legs"].as_array().unwrap().len(), 2);
    assert!(
        dir.path().join("plan-leg2.json").exists() && dir.path().join("world-leg2.png").exists()
    );
}
