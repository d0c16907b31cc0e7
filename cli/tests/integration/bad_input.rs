//! Reproducers, each from the outside: an input that panicked, hung, aborted or
//! failed late now exits 2 at once, naming the file or option, the field and the reason.

use crate::common;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use common::{magbench, plan_json, refused, write};

const BIN: &str = env!("CARGO_BIN_EXE_magbench");

/// env's small valid scenario, mutated one field at a time.
const SCENARIO: &str = include_str!("../../../env/tests/data/good.toml");

fn scenario(dir: &Path, text: &str) -> String {
    write(dir, "s.toml", text).display().to_string()
}

/// `planar = false` where nothing carries the out-of-plane force (bulk liquid: open-field names
/// no medium, and `plan`'s plant and the realistic preset are bulk) is refused for the planner
/// of `plan`, and for the tracker and the planner of `track`, naming the parameter, the value,
/// the scenario and the medium.
#[test]
fn planar_false_in_bulk_is_refused_naming_the_parameter() {
    let why = [
        "false needs a medium that carries the out-of-plane force",
        "open-field",
        "bulk",
    ];
    fn with<'a>(field: &'a str, why: &[&'a str]) -> Vec<&'a str> {
        [&[field][..], why].concat()
    }
    refused(
        &[
            "plan",
            "open-field",
            "--planner",
            "goal-zoom-rrt",
            "--param",
            "planar=false",
        ],
        &with("param.planar", &why),
    );
    let track = |extra: &[&str]| {
        let mut a = vec![
            "track",
            "open-field",
            "--tracker",
            "obc",
            "--max-iters",
            "10",
        ];
        a.extend_from_slice(extra);
        a.into_iter().map(String::from).collect::<Vec<_>>()
    };
    for (extra, field) in [
        (["--param", "planar=false"], "param.planar"),
        (["--planner-param", "planar=false"], "planner-param.planar"),
    ] {
        let args = track(&extra);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        refused(&args, &with(field, &why));
    }
    // at an interface (trio-row's [medium]) the same setting is accepted
    let (code, out, err) = magbench(&[
        "plan",
        "trio-row",
        "--planner",
        "goal-zoom-rrt",
        "--max-iters",
        "10",
        "--param",
        "planar=false",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains(r#""free":true"#), "{out}");
}

/// An experiment whose planner or tracker says `planar = false` on a scenario in bulk is refused
/// before any run, naming the file, the list and the variant; at an interface it is accepted.
#[test]
fn experiments_refuse_planar_false_in_bulk() {
    let d = tempfile::tempdir().unwrap();
    let exp = |scenario: &str, planner: &str, tracking: &str| {
        format!(
            "name = \"x\"\nscenarios = [\"{scenario}\"]\nplanners = [\"{planner}\"]\n{tracking}seeds = 2\n[limits]\niterations = 100\n"
        )
    };
    let cases = [
        (
            exp("open-field", "goal-zoom-rrt{planar=false}", ""),
            "planners",
        ),
        (
            exp(
                "open-field",
                "goal-zoom-rrt",
                "trackers = [\"obc{planar=false}\"]\n",
            ),
            "trackers",
        ),
    ];
    for (text, field) in cases {
        let f = write(d.path(), "e.toml", &text);
        let f = f.to_str().unwrap();
        refused(
            &["bench", f, "--dry-run"],
            &[
                f,
                field,
                "planar=false",
                "carries the out-of-plane force",
                "bulk",
            ],
        );
    }
    let f = write(
        d.path(),
        "ok.toml",
        &exp("trio-row", "goal-zoom-rrt{planar=false}", ""),
    );
    let (code, _, err) = magbench(&["bench", f.to_str().unwrap(), "--dry-run"]);
    assert_eq!(code, 0, "{err}");
}

/// `plan` says whether the elevation was free and why: three agents at an interface yes, the
/// same scenario without its `[medium]` (bulk, `plan`'s default plant) no.
#[test]
fn plan_says_whether_the_elevation_was_free() {
    let d = tempfile::tempdir().unwrap();
    let trio = include_str!("../../../scenarios/trio-row.toml");
    let bulk =
        trio.split("[medium]").next().unwrap().to_string() + &trio[trio.find("[start]").unwrap()..];
    let f = scenario(d.path(), &bulk);
    for (s, free, why) in [
        ("trio-row", true, "interface"),
        (f.as_str(), false, "bulk medium"),
        ("open-field", false, "two agents"),
    ] {
        let (code, out, err) = magbench(&[
            "plan",
            s,
            "--planner",
            "goal-zoom-rrt",
            "--max-iters",
            "10",
            "--json",
        ]);
        assert_eq!(code, 0, "{s}: {err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(v["elevation"]["free"], free, "{s}: {out}");
        assert!(
            v["elevation"]["reason"].as_str().unwrap().contains(why),
            "{s}: {out}"
        );
    }
}

/// The coil's elevation range: a preset's `coil.alpha_max_deg` and a rig file's are checked
/// ([0, 90]°), and `track` and `rig run` refuse an `alpha_max` above the coil's — the
/// planning setup's (`--alpha-max`) or the tracker's (`param.alpha_max`) — naming the coil's
/// file and field.
#[test]
fn alpha_max_beyond_the_coils_range_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let preset = std::fs::read_to_string(root.join("presets/realistic.toml")).unwrap();
    let coil = |a: &str| preset.replace("alpha_max_deg = 90.0", &format!("alpha_max_deg = {a}"));
    let bad = write(d.path(), "bad.toml", &coil("120"))
        .display()
        .to_string();
    refused(
        &["preset", "check", &bad],
        &[&bad, "coil.alpha_max_deg", "[0, 90]"],
    );
    refused(
        &["track", "open-field", "--tracker", "obc", "--preset", &bad],
        &[&bad, "coil.alpha_max_deg", "[0, 90]"],
    );
    let low = write(d.path(), "low.toml", &coil("20"))
        .display()
        .to_string();
    let track = |extra: &[&str]| {
        let mut a = vec![
            "track",
            "trio-row",
            "--tracker",
            "obc",
            "--max-iters",
            "10",
            "--preset",
        ];
        a.push(&low);
        a.extend_from_slice(extra);
        a.into_iter().map(String::from).collect::<Vec<_>>()
    };
    for (extra, field) in [
        (vec![], "--alpha-max"),
        (vec!["--alpha-max", "20"], "param.alpha_max"),
    ] {
        let args = track(&extra);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        refused(
            &args,
            &[
                field,
                "45° exceeds the coil's elevation range alpha_max_deg = 20°",
                &low,
            ],
        );
    }
    let rig = std::fs::read_to_string(root.join("rigs/emulator.toml")).unwrap();
    let rig_with = |a: &str| rig.replace("alpha_max_deg = 90.0", &format!("alpha_max_deg = {a}"));
    let bad_rig = write(d.path(), "bad-rig.toml", &rig_with("-5"))
        .display()
        .to_string();
    let planar_rig = write(d.path(), "planar-rig.toml", &rig_with("0"))
        .display()
        .to_string();
    let rig_run = |file: &str| {
        vec![
            "rig",
            "run",
            "--rig",
            file,
            "trio-row",
            "--planner",
            "sst",
            "--tracker",
            "obc",
        ]
        .into_iter()
        .map(String::from)
        .collect::<Vec<_>>()
    };
    let args = rig_run(&bad_rig);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    refused(&args, &[&bad_rig, "coil.alpha_max_deg", "[0, 90]"]);
    // a planar coil set: the elevation cannot be used (trio-row floats at an interface, so
    // `auto` would free it) until planar=true says so
    let args = rig_run(&planar_rig);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    refused(
        &args,
        &[
            "--alpha-max",
            "exceeds the coil's elevation range alpha_max_deg = 0°",
            &planar_rig,
        ],
    );
}

#[test]
fn scenario_values_that_crashed_later_are_refused_by_check_and_plan() {
    let d = tempfile::tempdir().unwrap();
    let cases = [
        (
            SCENARIO.replace("[[10.0, 0.0], [12.0", "[[1e308, 0.0], [12.0"),
            "world.obstacles[0].polygon[0]",
        ),
        (
            SCENARIO.replace("width = 30.0", "width = 1e20"),
            "world.width",
        ),
        (
            format!("{SCENARIO}[physics]\ndt_s = 1e-12\n"),
            "physics.dt_s",
        ),
    ];
    for (text, field) in cases {
        let f = scenario(d.path(), &text);
        refused(&["scenario", "check", &f], &[&f, field]);
        refused(
            &[
                "plan",
                &f,
                "--planner",
                "goal-zoom-rrt",
                "--max-iters",
                "10",
            ],
            &[&f, field],
        );
    }
}

/// Two lobes of an obstacle that touch where a vertex of one lies on an edge of the other are
/// refused alike in decimal and in binary-exact coordinates (the same shape, touching at
/// (0.1, 0.3) and at (0.125, 0.375)).
#[test]
fn lobes_touching_at_a_vertex_are_refused_in_either_coordinate_form() {
    let d = tempfile::tempdir().unwrap();
    for lobes in [
        "[[0.0, 0.2], [0.2, 0.4], [0.3, 0.3], [0.25, 0.25], [0.1, 0.3], [0.15, 0.15]]",
        "[[0.0, 0.25], [0.25, 0.5], [0.375, 0.375], [0.3125, 0.3125], [0.125, 0.375], [0.1875, 0.1875]]",
    ] {
        let text = SCENARIO.replace(
            "[[10.0, 0.0], [12.0, 0.0], [12.0, 8.0], [10.0, 8.0]]",
            lobes,
        );
        let f = scenario(d.path(), &text);
        refused(
            &["scenario", "check", &f],
            &[
                &f,
                "world.obstacles[0].polygon",
                "self-intersecting polygon",
            ],
        );
    }
}

#[test]
fn a_10000_vertex_polygon_is_refused_with_its_bound() {
    let d = tempfile::tempdir().unwrap();
    let ring: Vec<String> = (0..10_000)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 10_000.0;
            format!("[{}, {}]", 15.0 + 3.0 * a.cos(), 10.0 + 3.0 * a.sin())
        })
        .collect();
    let f = scenario(
        d.path(),
        &SCENARIO.replace(
            "[[10.0, 0.0], [12.0, 0.0], [12.0, 8.0], [10.0, 8.0]]",
            &format!("[{}]", ring.join(", ")),
        ),
    );
    refused(
        &["scenario", "check", &f],
        &["world.obstacles[0].polygon", "at most 2000 vertices"],
    );
}

#[test]
fn a_later_map_covering_an_earlier_goal_fails_check() {
    let f = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../env/tests/data/leg-blocks-earlier-goal.toml")
        .display()
        .to_string();
    refused(
        &["scenario", "check", &f],
        &["legs[1].obstacles", "leg 2 starts"],
    );
}

#[test]
fn huge_time_limits_and_zero_iterations_are_refused_everywhere() {
    let rig = Path::new(env!("CARGO_MANIFEST_DIR")).join("../rigs/emulator.toml");
    let rig = rig.to_str().unwrap();
    for limit in [["--time-limit", "1e20"], ["--max-iters", "0"]] {
        let opt = limit[0];
        refused(
            &["plan", "open-field", "--planner", "sst", limit[0], limit[1]],
            &["<command line>", opt],
        );
        refused(
            &[
                "track",
                "open-field",
                "--tracker",
                "obc",
                limit[0],
                limit[1],
            ],
            &["<command line>", opt],
        );
        refused(
            &[
                "rig",
                "run",
                "--rig",
                rig,
                "open-field",
                "--planner",
                "sst",
                "--tracker",
                "obc",
                limit[0],
                limit[1],
            ],
            &["<command line>", opt],
        );
    }
}

const EXPERIMENT: &str = r#"
name = "x"
scenarios = ["open-field"]
planners = ["goal-zoom-rrt"]
seeds = 2
[limits]
iterations = 100
"#;

#[test]
fn experiment_values_that_crashed_are_refused_even_in_a_dry_run() {
    let d = tempfile::tempdir().unwrap();
    let cases = [
        (
            EXPERIMENT.replace("seeds = 2", "seeds = 9223372036854775807"),
            "seeds",
        ),
        (
            EXPERIMENT.replace("seeds = 2", "seeds = 100000000000"),
            "seeds",
        ),
        (EXPERIMENT.replace("seeds = 2", "seeds = 1e11"), "seeds"),
        (
            EXPERIMENT.replace("iterations = 100", "time = 1e20"),
            "limits.time",
        ),
        (EXPERIMENT.replace("name = \"x\"", "name = \"..\""), "name"),
        (EXPERIMENT.replace("name = \"x\"", "name = \".\""), "name"),
        (
            EXPERIMENT.replace("name = \"x\"", &format!("name = \"{}\"", "a".repeat(300))),
            "name",
        ),
    ];
    for (text, field) in cases {
        let f = write(d.path(), "e.toml", &text);
        let f = f.to_str().unwrap();
        let out = d.path().join("out");
        let out = out.to_str().unwrap();
        refused(&["bench", f, "--dry-run"], &[f, field]);
        refused(&["bench", f, "--out", out, "--quiet"], &[f, field]);
    }
    assert!(
        !d.path().join("..").join("runs.csv").exists(),
        "results went into the parent folder"
    );
}

#[test]
fn plan_files_are_validated_before_tracking() {
    let d = tempfile::tempdir().unwrap();
    let (_, plan) = plan_json(d.path());
    let track = |p: &serde_json::Value, parts: &[&str]| {
        let f = write(d.path(), "bad.json", &p.to_string());
        let f = f.to_str().unwrap();
        let mut want = vec![f];
        want.extend_from_slice(parts);
        refused(
            &["track", "open-field", "--tracker", "obc", "--plan", f],
            &want,
        );
    };
    let mut long = plan.clone();
    long["durations"][3] = serde_json::json!(1e10);
    track(&long, &["durations", "3600"]);
    let mut far = plan.clone();
    far["states"][5][1][0] = serde_json::json!(1e20);
    track(&far, &["states[5][1]", "outside the world"]);
    let mut alpha = plan.clone();
    alpha["controls"][2]["alpha"] = serde_json::json!(1e19);
    track(&alpha, &["controls[2]"]);
    let mut grad = plan.clone();
    grad["controls"][4]["grad"][0] = serde_json::json!(5.0);
    track(&grad, &["controls[4]"]);
    let mut replay = plan.clone();
    replay["states"][7][0][1] =
        serde_json::json!(replay["states"][7][0][1].as_f64().unwrap() + 0.01);
    track(&replay, &["states[7]", "replay"]);
    // the unchanged plan tracks
    let f = write(d.path(), "good.json", &plan.to_string());
    let (code, _, stderr) = magbench(&[
        "track",
        "open-field",
        "--tracker",
        "open-loop",
        "--preset",
        "ideal",
        "--plan",
        f.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(code, 0, "{stderr}");
}

#[test]
fn stlc_refuses_unphysical_separations_and_survives_a_closed_pipe() {
    for r in ["1e308", "1", "0.5", "NaN", "1000"] {
        refused(&["stlc", "--r", r], &["--r", "separation"]);
    }
    for args in [
        vec!["stlc", "--step", "0.005"], // 2.5 MB: far more than a pipe holds
        vec!["scenario", "list"],
        vec!["plan", "--list"],
    ] {
        // `| head -1`: read one line and close the pipe
        let mut child = Command::new(BIN)
            .args(&args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut first = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut first)
            .unwrap();
        let out = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(out.status.success(), "{args:?}: {:?} {stderr}", out.status);
    }
}

#[test]
fn output_folders_that_cannot_be_written_are_named() {
    let d = tempfile::tempdir().unwrap();
    let file = write(d.path(), "a-file", "x");
    let under = file.join("sub");
    let exp = write(d.path(), "e.toml", EXPERIMENT);
    let exp = exp.to_str().unwrap();
    let mut cases = vec![(file.clone(), "is a file"), (under.clone(), "is a file")];
    if cfg!(target_os = "linux") {
        // read-only even for root
        cases.push((PathBuf::from("/proc/magbench-out"), "cannot create"));
    }
    for (out, why) in cases {
        let out_s = out.to_str().unwrap();
        for args in [
            vec![
                "plan",
                "open-field",
                "--planner",
                "sst",
                "--max-iters",
                "10",
                "--out",
                out_s,
            ],
            vec![
                "track",
                "open-field",
                "--tracker",
                "obc",
                "--max-iters",
                "10",
                "--out",
                out_s,
            ],
            vec!["bench", exp, "--out", out_s, "--quiet"],
        ] {
            refused(&args, &["--out", out_s, why]);
        }
    }
}

/// The planning options of the exact flow and the elevation: a bad value
/// names the option or parameter and the reason, before any planning.
#[test]
fn planning_options_name_their_bad_values() {
    let plan = |extra: &[&str]| {
        let mut a = vec!["plan", "open-field", "--planner", "goal-zoom-rrt"];
        a.extend_from_slice(extra);
        a.into_iter().map(String::from).collect::<Vec<_>>()
    };
    let cases: [(&[&str], &[&str]); 15] = [
        (&["--flow", "bogus"], &["--flow", "bogus", "pair-adaptive"]),
        // every squared distance would overflow to inf, and the tree never grow
        (
            &["--metric", "centroid-shape:1e308:1"],
            &[
                "--metric",
                "centroid weight 1e308",
                "must be in [1e-6, 1e6]",
            ],
        ),
        (
            &["--metric", "centroid-shape:1:1e-300"],
            &["--metric", "shape weight 1e-300", "must be in [1e-6, 1e6]"],
        ),
        (
            &["--param", "approach_radius=-1"],
            &["param.approach_radius", "must be in [0,", "got -1"],
        ),
        (&["--param", "timing=bogus"], &["param.timing", "closest"]),
        (
            &["--param", "max_duration=0.1", "--param", "min_duration=0.5"],
            &["min_duration", "exceeds max_duration"],
        ),
        (&["--param", "k=0"], &["param.k"]),
        (&["--param", "shortcut=-1"], &["param.shortcut"]),
        (&["--param", "guide=maybe"], &["param.guide"]),
        (&["--param", "straighten=maybe"], &["param.straighten"]),
        (&["--param", "aim=maybe"], &["param.aim"]),
        (
            &["--param", "aim=true", "--param", "timing=closest"],
            &["param.aim", "timing=random"],
        ),
        (&["--alpha-max", "120"], &["--alpha-max", "[0, 90]"]),
        (&["--param", "planar=maybe"], &["param.planar", "auto"]),
        (&["--fps", "0"], &["--fps", "got 0"]),
    ];
    for (extra, parts) in cases {
        let args = plan(extra);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        refused(&args, parts);
    }
    refused(&["stlc", "--agents", "7"], &["--agents", "got 7"]);
}

/// The tracking loop's stall rule: a bad `replan_stall` names the option or the
/// experiment field, the parameter and the allowed values, before any planning.
#[test]
fn the_stall_replan_rule_names_its_bad_values() {
    refused(
        &[
            "track",
            "trio-triangle",
            "--tracker",
            "obc",
            "--param",
            "replan_stall=maybe",
        ],
        &[
            "<command line>",
            "param.replan_stall",
            "\"maybe\"",
            "auto, true, false",
        ],
    );
    let dir = tempfile::tempdir().unwrap();
    let exp = write(
        dir.path(),
        "e.toml",
        "name = \"e\"\nscenarios = [\"trio-triangle\"]\nplanners = [\"goal-zoom-rrt\"]\n\
         trackers = [\"lookahead{replan_stall=\\\"sometimes\\\"}\"]\nseeds = 1\n\
         [limits]\niterations = 1000\n",
    );
    refused(
        &["bench", &exp.display().to_string(), "--dry-run"],
        &[
            "e.toml",
            "trackers[0]",
            "\"sometimes\"",
            "auto, true, false",
        ],
    );
}

/// A bad replay policy is refused before any run, naming `--replays` (of `bench` and `ablate`)
/// or the experiment file and its `replays` field, and the reason.
#[test]
fn bad_replay_policies_name_the_option_or_the_field() {
    let d = tempfile::tempdir().unwrap();
    let f = write(d.path(), "e.toml", EXPERIMENT);
    let f = f.to_str().unwrap();
    let out = d.path().join("out");
    let out = out.to_str().unwrap();
    let cases = [
        ("sample:x", "must be a whole number"),
        ("sample:0", "samples no run"),
        ("bogus", "unknown policy \"bogus\""),
        ("all+failed", "all cannot be combined"),
    ];
    for (policy, why) in cases {
        let parts = ["<command line>", "--replays", why];
        refused(&["bench", f, "--replays", policy, "--dry-run"], &parts);
        refused(
            &["bench", f, "--replays", policy, "--out", out, "--quiet"],
            &parts,
        );
        refused(
            &["ablate", "--replays", policy, "--out", out, "--quiet"],
            &parts,
        );
        let text = EXPERIMENT.replace("seeds = 2", &format!("seeds = 2\nreplays = {policy:?}"));
        let g = write(d.path(), "g.toml", &text);
        let g = g.to_str().unwrap();
        refused(&["bench", g, "--dry-run"], &[g, "replays", why]);
    }
    assert!(
        !Path::new(out).join("runs.csv").exists(),
        "a refused sweep ran"
    );
}
