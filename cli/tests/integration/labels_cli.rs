//! Planners and trackers named on the command line as experiment files and reports label
//! them, `name{key=value,…}`, and `track --list`.

use crate::common;

use common::{magbench, refused};

fn json(args: &[&str]) -> serde_json::Value {
    let (code, stdout, stderr) = magbench(args);
    assert_eq!(code, 0, "{args:?}: {stderr}");
    serde_json::from_str(stdout.trim()).expect("one JSON object")
}

/// The fields of `plan --json` that the planner's parameters decide.
fn outcome(v: &serde_json::Value) -> (serde_json::Value, serde_json::Value, serde_json::Value) {
    (
        v["cost"].clone(),
        v["iterations"].clone(),
        v["nodes"].clone(),
    )
}

#[test]
fn plan_takes_a_label_as_its_parameters_and_merges_param_options() {
    let plan = |planner: &str, params: &[&str]| {
        let mut a = vec!["plan", "micro-factory", "--planner", planner, "--json"];
        for p in params {
            a.extend(["--param", p]);
        }
        json(&a)
    };
    let by_options = plan("goal-zoom-rrt", &["aim=true", "guide=true"]);
    let by_label = plan("goal-zoom-rrt{aim=true,guide=true}", &[]);
    let mixed = plan("goal-zoom-rrt{aim=true}", &["guide=true"]);
    let plain = plan("goal-zoom-rrt", &[]);
    assert_eq!(outcome(&by_label), outcome(&by_options));
    assert_eq!(outcome(&mixed), outcome(&by_options));
    assert_ne!(
        outcome(&plain),
        outcome(&by_options),
        "the parameters matter"
    );
    assert_eq!(by_label["planner"], "goal-zoom-rrt");
}

#[test]
fn label_errors_are_the_experiment_files_and_a_key_given_twice_is_refused() {
    let plan = |planner: &str, extra: &[&str]| {
        let mut a = vec!["plan", "open-field", "--planner", planner];
        a.extend_from_slice(extra);
        a.into_iter().map(String::from).collect::<Vec<_>>()
    };
    let cases: [(Vec<String>, &[&str]); 5] = [
        (
            plan("goal-zoom-rrt{k=5}", &["--param", "k=7"]),
            &[
                "--param",
                "k is given both in --planner",
                "goal-zoom-rrt{k=5}",
            ],
        ),
        (
            plan("goal-zoom-rrt{k}", &[]),
            &["--planner", "\"goal-zoom-rrt{k}\": \"k\" is not key=value"],
        ),
        (
            plan("goal-zoom-rrt{k=5", &[]),
            &["--planner", "parameters must be one {...} group at the end"],
        ),
        (plan("goal-zoom-rrt{k=0}", &[]), &["param.k", "must be in"]),
        (
            plan("goal-zoom-rrt{kk=3}", &[]),
            &["param.kk", "did you mean `k`?"],
        ),
    ];
    for (args, parts) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        refused(&args, parts);
    }
}

#[test]
fn track_and_rig_run_take_labels_for_the_tracker_and_the_planner() {
    let v = json(&[
        "track",
        "open-field",
        "--planner",
        "goal-zoom-rrt{k=5}",
        "--tracker",
        "obc{time_slack=5}",
        "--seed",
        "1",
        "--json",
    ]);
    assert_eq!(v["tracker"], "obc");
    assert_eq!(v["tracker_label"], "obc{time_slack=5}");
    assert_eq!(v["reached_goal"], true, "{v}");
    refused(
        &[
            "track",
            "open-field",
            "--tracker",
            "obc{time_slack=5}",
            "--param",
            "time_slack=6",
        ],
        &["--param", "time_slack is given both in --tracker"],
    );
    refused(
        &[
            "track",
            "open-field",
            "--tracker",
            "obc",
            "--planner",
            "goal-zoom-rrt{k=5}",
            "--planner-param",
            "k=6",
        ],
        &["--planner-param", "k is given both in --planner"],
    );
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let rig = format!("{root}/rigs/emulator.toml");
    refused(
        &[
            "rig",
            "run",
            "--rig",
            &rig,
            "open-field",
            "--planner",
            "goal-zoom-rrt{k=5}",
            "--tracker",
            "obc{bogus=1}",
        ],
        &["param.bogus"],
    );
    refused(
        &[
            "rig",
            "run",
            "--rig",
            &rig,
            "open-field",
            "--planner",
            "goal-zoom-rrt{k=0}",
            "--tracker",
            "obc{time_slack=5}",
        ],
        &["param.k", "must be in"],
    );
}

#[test]
fn track_lists_the_registrys_trackers_with_their_parameters_and_the_rig_types() {
    let (code, stdout, stderr) = magbench(&["track", "--list"]);
    assert_eq!(code, 0, "{stderr}");
    for part in [
        "obc\n",
        "lookahead\n",
        "open-loop\n",
        "time_slack",
        "replan_after",
        "rig types",
        "simulated\n",
        "coil\n",
    ] {
        assert!(stdout.contains(part), "{part:?} missing from:\n{stdout}");
    }
    let (_, help, _) = magbench(&["track", "--help"]);
    assert!(help.contains("--list"), "{help}");
}
