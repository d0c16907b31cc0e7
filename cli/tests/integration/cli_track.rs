//! `magbench track` from the outside: the JSON object, the output folder, exit codes.

use crate::common;

use common::magbench;

#[test]
fn json_has_the_required_fields_and_out_writes_every_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let (code, stdout, stderr) = magbench(&[
        "track",
        "open-field",
        "--planner",
        "goal-zoom-rrt",
        "--tracker",
        "obc",
        "--seed",
        "1",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(stdout.lines().count(), 1, "one JSON object:\n{stdout}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    for key in [
        "scenario",
        "planner",
        "tracker",
        "seed",
        "solved",
        "reached_goal",
        "rms_error_bl",
        "max_error_bl",
        "agent_contact",
        "wall_contacts",
        "replans",
        "duration_s",
        "time_to_goal_s",
        "missed_frames",
        "planning_time_s",
        "final_goal_distance_bl",
        "status",
        "per_agent",
    ] {
        assert!(v.get(key).is_some(), "missing {key} in {v}");
    }
    assert_eq!(v["scenario"], "open-field");
    assert_eq!(v["tracker"], "obc");
    assert_eq!(v["reached_goal"], true, "{v}");
    for f in [
        "ticks.csv",
        "metrics.json",
        "plan.json",
        "plans.json",
        "world.svg",
        "world.png",
        "replay.html",
    ] {
        let m = std::fs::metadata(out.join(f)).unwrap_or_else(|_| panic!("{f} not written"));
        assert!(m.len() > 100, "{f} is empty");
    }
    let csv = std::fs::read_to_string(out.join("ticks.csv")).unwrap();
    assert!(
        csv.lines()
            .next()
            .unwrap()
            .starts_with("t_s,leg,plan,mode,")
    );
    assert!(csv.lines().count() > 100);

    // the written plan replays bit for bit: open-loop on the ideal plant has zero error
    let (code, stdout, stderr) = magbench(&[
        "track",
        "open-field",
        "--plan",
        out.join("plan.json").to_str().unwrap(),
        "--tracker",
        "open-loop",
        "--preset",
        "ideal",
        "--json",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["max_error_bl"], 0.0, "{v}");
    assert_eq!(v["reached_goal"], true, "{v}");
}

#[test]
fn bad_input_exits_2_with_a_clear_message() {
    let cases: [(&[&str], &str); 6] = [
        (
            &[
                "track",
                "open-field",
                "--planner",
                "goal-zoom-rrt",
                "--tracker",
                "pid",
            ],
            "tracker: unknown tracker \"pid\"",
        ),
        (
            &[
                "track",
                "open-field",
                "--planner",
                "goal-zoom-rrt",
                "--tracker",
                "obc",
                "--param",
                "gain=0.5",
            ],
            "param.gain: obc has no parameter \"gain\"",
        ),
        (
            &[
                "track",
                "open-field",
                "--planner",
                "goal-zoom-rrt",
                "--tracker",
                "lookahead",
                "--param",
                "gain=2",
            ],
            "param.gain: must be in [0, 1]",
        ),
        (
            &[
                "track",
                "open-field",
                "--planner",
                "goal-zoom-rrt",
                "--tracker",
                "obc",
                "--preset",
                "rough",
            ],
            "unknown preset",
        ),
        (
            &[
                "track",
                "open-field",
                "--planner",
                "nope",
                "--tracker",
                "obc",
            ],
            "unknown planner",
        ),
        (
            &["track", "open-field", "--tracker", "obc", "--flow", "euler"],
            "<command line>: --flow: unknown flow",
        ),
    ];
    for (args, want) in cases {
        let (code, _, stderr) = magbench(args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(stderr.contains(want), "{args:?}: {stderr}");
    }
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("plan.json");
    std::fs::write(&bad, "{\"states\": []}").unwrap();
    let (code, _, stderr) = magbench(&[
        "track",
        "open-field",
        "--plan",
        bad.to_str().unwrap(),
        "--tracker",
        "obc",
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("plan.json"), "{stderr}");
}

#[test]
fn a_three_agent_run_reports_each_agent_and_the_worst() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("trio");
    let (code, _, stderr) = magbench(&[
        "track",
        "trio-triangle",
        "--tracker",
        "open-loop",
        "--preset",
        "realistic",
        "--max-iters",
        "500",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).unwrap()).unwrap();
    let each = v["per_agent"].as_array().unwrap();
    assert_eq!(each.len(), 3, "{v}");
    let get = |a: &serde_json::Value, k: &str| a[k].as_f64().unwrap();
    let (mut worst, mut worst_true, mut max_true) = (0, 0.0f64, 0.0f64);
    for (i, a) in each.iter().enumerate() {
        assert_eq!(a["agent"], i, "{a}");
        assert!(
            get(a, "rms_bl") > 0.0 && a["samples"].as_u64().unwrap() > 0,
            "{a}"
        );
        if get(a, "rms_bl") > get(&each[worst], "rms_bl") {
            worst = i;
        }
        worst_true = worst_true.max(get(a, "rms_true_bl"));
        max_true = max_true.max(get(a, "max_true_bl"));
    }
    assert_eq!(v["worst_agent"], worst, "{v}");
    assert_eq!(
        get(&v, "rms_error_worst_agent_bl"),
        get(&each[worst], "rms_bl")
    );
    assert_eq!(get(&v, "rms_error_true_worst_agent_bl"), worst_true);
    assert_eq!(get(&v, "max_error_true_bl"), max_true);
    let max_obs = each.iter().map(|a| get(a, "max_bl")).fold(0.0, f64::max);
    assert_eq!(get(&v, "max_error_bl"), max_obs);

    // ticks.csv: the commanded elevation next to θ_B (a team of three plans with α free)
    let mut rd = csv::Reader::from_path(out.join("ticks.csv")).unwrap();
    let h = rd.headers().unwrap().clone();
    let col = |c: &str| h.iter().position(|x| x == c).unwrap();
    assert_eq!(col("alpha_rad"), col("theta_rad") + 1);
    assert!(h.iter().any(|x| x == "err2_bl"));
    let alphas: Vec<f64> = rd
        .records()
        .map(|r| r.unwrap()[col("alpha_rad")].parse().unwrap())
        .collect();
    assert!(alphas.iter().any(|a| *a != 0.0), "no elevation commanded");
    assert!(
        alphas
            .iter()
            .all(|a| a.abs() <= std::f64::consts::FRAC_PI_2)
    );
}
