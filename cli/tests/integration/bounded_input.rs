//! The accepted values that crashed or hung, and the garbage that was accepted, each from the
//! outside: every input exits 2 naming the file or option, the field and the reason (with the
//! bound and why, where the bound is a choice). Each command runs under a deadline; one that
//! outlives it is killed and fails the test as a hang.

use crate::common;

use std::path::Path;
use std::process::Command;

use common::{magbench_in_time, plan_json, refused};

fn write(dir: &Path, name: &str, text: &str) -> String {
    common::write(dir, name, text).display().to_string()
}

const RIG: &str = include_str!("../../../rigs/emulator.toml");
const SCENARIO: &str = include_str!("../../../env/tests/data/good.toml");

fn rig(dir: &Path, from: &str, to: &str) -> String {
    assert!(RIG.contains(from), "{from}");
    write(dir, "r.toml", &RIG.replace(from, to))
}

fn scenario(dir: &Path, from: &str, to: &str) -> String {
    assert!(SCENARIO.contains(from), "{from}");
    write(dir, "s.toml", &SCENARIO.replace(from, to))
}

#[test]
fn image_sizes_and_blur_are_bounded() {
    let d = tempfile::tempdir().unwrap();
    for v in ["1e308", "1e5"] {
        let r = rig(d.path(), "px_per_bl = 10.0", &format!("px_per_bl = {v}"));
        refused(
            &[
                "rig",
                "emulate",
                "--rig",
                &r,
                "open-field",
                "--duration",
                "0.1",
            ],
            &[
                &r,
                "pixels.px_per_bl",
                "must be in (0, 1000] px/BL",
                "fills a sensor side",
            ],
        );
    }
    for v in ["1e308", "1e5"] {
        let r = write(d.path(), "ok.toml", RIG);
        refused(
            &[
                "rig",
                "emulate",
                "--rig",
                &r,
                "open-field",
                "--duration",
                "0.1",
                "--blur",
                v,
            ],
            &[
                "<command line>",
                "--blur",
                "must be in [0, 50] px",
                "wipes out any agent",
            ],
        );
    }
    let r = rig(d.path(), "size_px = [520, 340]", "size_px = [16384, 16384]");
    refused(
        &["rig", "check", "--rig", &r, "open-field"],
        &[&r, "camera.size_px", "Mpx"],
    );
}

#[test]
fn camera_rates_and_fixed_arrays_of_rig_files_are_checked() {
    let d = tempfile::tempdir().unwrap();
    let r = rig(d.path(), "fps = 60.0", "fps = 5e-324");
    refused(
        &["rig", "check", "--rig", &r, "open-field"],
        &[
            &r,
            "camera.fps",
            "must be in [0.1, 10000] fps",
            "got 5e-324",
        ],
    );
    let r = rig(
        d.path(),
        "origin_px = [10.0, 330.0]",
        "origin_px = [10.0, 330.0, 1.0]",
    );
    refused(
        &["rig", "check", "--rig", &r, "open-field"],
        &[&r, "pixels.origin_px", "invalid length 3"],
    );
    let r = rig(d.path(), "[1.0, 1.0, 1.0]", "[1.0, 1.0, 1.0, 1.0]");
    refused(
        &["rig", "check", "--rig", &r, "open-field"],
        &[&r, "coil.calibration.field_mt_per_a", "invalid length 4"],
    );
    let r = rig(
        d.path(),
        "alpha_max_deg = 90.0",
        "alpha_max_deg = 90.0\nfield_mt = 1e9",
    );
    refused(
        &["rig", "check", "--rig", &r, "open-field"],
        &[&r, "coil.field_mt", "1 T"],
    );
}

/// The coil timers of a rig file are bounded by what they are for: a heartbeat whose double
/// wraps 32 bits, a hold timeout of days, a watchdog the device would clamp.
#[test]
fn rig_file_timers_are_bounded_by_their_meaning() {
    let d = tempfile::tempdir().unwrap();
    let cases = [
        (
            "heartbeat_ms = 50",
            "heartbeat_ms = 2147483698",
            "coil.heartbeat_ms",
            "must be at most half of watchdog_ms = 200",
        ),
        (
            "hold_timeout_ms = 250",
            "hold_timeout_ms = 1000000000",
            "coil.hold_timeout_ms",
            "must be at most 1000 ms: a stalled control loop",
        ),
        (
            "watchdog_ms = 200",
            "watchdog_ms = 65535",
            "coil.watchdog_ms",
            "must be in [20, 1000] ms: the device clamps",
        ),
        (
            "retries = 3",
            "retries = 4294967295",
            "coil.retries",
            "(retries + 1) × ack_timeout_ms = 85899345920 ms must be at most hold_timeout_ms = 250 ms",
        ),
        (
            "stuck_frames = 30",
            "stuck_frames = 4294967295",
            "camera.stuck_frames",
            "must be at most 60 at 60 fps",
        ),
    ];
    for (from, to, field, why) in cases {
        let r = rig(d.path(), from, to);
        refused(
            &["rig", "check", "--rig", &r, "open-field"],
            &[&format!("{r}: {field}: {why}")],
        );
    }
}

#[test]
fn nan_truth_in_a_recording_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let r = write(d.path(), "r.toml", RIG);
    let frames = d.path().join("frames");
    std::fs::create_dir(&frames).unwrap();
    write(
        &frames,
        "frames.csv",
        "index,t_s,file,x0_bl,y0_bl,x1_bl,y1_bl\n0,0.0,f0.pgm,NaN,4.0,6.0,4.0\n",
    );
    refused(
        &["rig", "redetect", "--rig", &r, frames.to_str().unwrap()],
        &["frames.csv", "line 2: x0_bl", "must be finite"],
    );
}

#[test]
fn strong_fields_under_the_hardware_preset_are_refused() {
    let d = tempfile::tempdir().unwrap();
    // (the scenario's physics, what the refusal names): beyond 1 T; within 1 T, but a moment
    // that turns faster than the plant can integrate
    for (physics, why) in [
        ("field_mt = 1e9\n", "at most 1000 mT"),
        (
            "field_mt = 900.0\nviscosity_mpa_s = 0.01\n",
            "sub-steps per step",
        ),
    ] {
        let s = write(
            d.path(),
            "s.toml",
            &format!("{SCENARIO}[physics]\n{physics}"),
        );
        refused(
            &[
                "track",
                &s,
                "--tracker",
                "obc",
                "--preset",
                "hardware",
                "--max-iters",
                "100",
            ],
            &[&s, "physics.field_mt", why],
        );
    }
}

#[test]
fn tracker_work_stlc_steps_and_threads_are_bounded() {
    refused(
        &[
            "track",
            "open-field",
            "--tracker",
            "obc",
            "--param",
            "grid=100000",
            "--param",
            "horizon=120",
            "--param",
            "refine=100",
            "--max-iters",
            "10",
        ],
        &[
            "<command line>",
            "param",
            "predictions per control tick",
            "at most 200000",
        ],
    );
    refused(
        &["stlc", "--step", "1e-300"],
        &["--step", "must be in [0.001, 90] degrees", "got 1e-300"],
    );
    let ci = concat!(env!("CARGO_MANIFEST_DIR"), "/../experiments/ci.toml");
    refused(
        &["bench", ci, "--dry-run", "--threads", "100000"],
        &["--threads", "per core of this machine", "got 100000"],
    );
}

#[test]
fn huge_maps_are_refused_by_their_bounds() {
    let d = tempfile::tempdir().unwrap();
    // 992 polygons of 2000 vertices: larger than a scenario file may be
    let ring = |cx: f64, cy: f64, n: usize| {
        (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                format!("[{:.3},{:.3}]", cx + 0.3 * a.cos(), cy + 0.3 * a.sin())
            })
            .collect::<Vec<_>>()
            .join(",")
    };
    let map = |polys: usize, n: usize| {
        let mut s = String::from("name = \"big\"\n[world]\nwidth = 60.0\nheight = 60.0\n");
        for k in 0..polys {
            let (cx, cy) = (10.0 + (k % 40) as f64, 10.0 + (k / 40) as f64);
            s += &format!("[[world.obstacles]]\npolygon = [{}]\n", ring(cx, cy, n));
        }
        s + "[start]\nagents = [[2.0, 2.0], [4.0, 2.0]]\n[goal]\nagents = [[55.0, 55.0], [57.0, 55.0]]\ntolerance = 0.5\n"
    };
    let s = write(d.path(), "big.toml", &map(992, 2000));
    refused(&["scenario", "check", &s], &[&s, "larger than 4096 KiB"]);
    // 30 polygons of 1000 vertices: a small file, but too many vertices for one map
    let s = write(d.path(), "many.toml", &map(30, 1000));
    refused(
        &["scenario", "check", &s],
        &[
            &s,
            "world.obstacles",
            "at most 20000 polygon vertices",
            "got 30000",
        ],
    );
}

#[test]
fn special_files_are_refused() {
    let d = tempfile::tempdir().unwrap();
    let fifo = d.path().join("fifo.toml");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        assert!(
            std::env::var_os("MAGBENCH_REQUIRE_TOOLS").is_none(),
            "MAGBENCH_REQUIRE_TOOLS is set but mkfifo failed"
        );
        eprintln!("skipped: no mkfifo");
        return;
    }
    let f = fifo.to_str().unwrap();
    refused(
        &["scenario", "check", f],
        &[f, "a FIFO", "not a regular file"],
    );
    refused(&["bench", f, "--dry-run"], &[f, "a FIFO"]);
    refused(&["rig", "check", "--rig", f, "open-field"], &[f, "a FIFO"]);
    refused(
        &["scenario", "check", "/dev/zero"],
        &["/dev/zero", "a device"],
    );
}

#[test]
fn garbage_scenarios_are_refused() {
    let d = tempfile::tempdir().unwrap();
    // (text replaced, its replacement, what the refusal names besides the file)
    let cases: [(&str, &str, &[&str]); 5] = [
        // an obstacle of leg 1's map covers the start
        (
            "[goal]\nagents = [[25.0, 15.0], [27.5, 15.0]]\ntolerance = 0.5\n",
            "[[legs]]\ngoal = { agents = [[25.0, 15.0], [27.5, 15.0]], tolerance = 0.5 }\nobstacles = [{ circle = { center = [4.0, 5.0], radius = 2.0 } }]\n",
            &[
                "legs[0].obstacles",
                "leg 1 starts at the start",
                "collision",
            ],
        ),
        (
            "[[3.0, 5.0], [5.0, 5.0]]",
            "[[4, 4, 999], [5.0, 5.0]]",
            &["start.agents[0]", "invalid length 3"],
        ),
        (
            "polygon = [[10.0, 0.0], [12.0, 0.0], [12.0, 8.0], [10.0, 8.0]]",
            "circle = { center = [11.0, 4.0, 1.0], radius = 1.0 }",
            &["world.obstacles[0].circle.center", "invalid length 3"],
        ),
        (
            "polygon = [[10.0, 0.0], [12.0, 0.0], [12.0, 8.0], [10.0, 8.0]]",
            "polygon = [[10.0, 0.5], [14.0, 0.5], [14.0, 8.0], [12.0, 0.5], [10.0, 8.0]]",
            &["world.obstacles[0].polygon"],
        ),
        (
            "[world]",
            "[wrold]",
            &["is `wrold` a misspelling of `world`?"],
        ),
    ];
    for (from, to, parts) in cases {
        let s = scenario(d.path(), from, to);
        let mut want = vec![s.as_str()];
        want.extend(parts);
        refused(&["scenario", "check", &s], &want);
    }
}

/// `time_slack` is simulated time granted beyond each plan's own: 1e6 s would track an
/// unsolved plan for minutes of wall time (and keep a log row per frame of it), in `track`
/// and in `bench`.
#[test]
fn a_time_slack_beyond_its_maximum_is_refused() {
    let why = ["param.time_slack", "must be in [0, 600]", "1e6"];
    refused(
        &[
            "track",
            "micro-factory",
            "--tracker",
            "obc",
            "--planner",
            "rrt-star",
            "--max-iters",
            "20",
            "--param",
            "time_slack=1e6",
        ],
        &why,
    );
    let d = tempfile::tempdir().unwrap();
    let e = write(
        d.path(),
        "e.toml",
        "name = \"e\"\nscenarios = [\"micro-factory\"]\nplanners = [\"rrt-star\"]\ntrackers = [\"obc{time_slack=1e6}\"]\nseeds = 1\n[limits]\niterations = 20\n",
    );
    refused(
        &["bench", &e, "--dry-run"],
        &[&e, "trackers[0].time_slack", "must be in [0, 600]"],
    );
}

#[test]
fn experiment_parameter_errors_name_the_key() {
    let d = tempfile::tempdir().unwrap();
    for (planner, limits, parts) in [
        (
            "goal-zoom-rrt{k=0}",
            "iterations",
            ["planners[0].k", "must be in"],
        ),
        (
            "goal-zoom-rrt{kk=3}",
            "iterations",
            ["planners[0].kk", "did you mean `k`?"],
        ),
        (
            "goal-zoom-rrt",
            "iteration",
            ["limits.iteration", "did you mean `iterations`?"],
        ),
    ] {
        let e = write(
            d.path(),
            "e.toml",
            &format!(
                "name = \"e\"\nscenarios = [\"open-field\"]\nplanners = [\"{planner}\"]\nseeds = 1\n[limits]\n{limits} = 10\n"
            ),
        );
        refused(&["bench", &e, "--dry-run"], &[&e, parts[0], parts[1]]);
    }
}

#[test]
fn plans_of_other_scenarios_teams_or_starts_are_refused() {
    let d = tempfile::tempdir().unwrap();
    let (good, plan) = plan_json(d.path());
    assert_eq!(plan["made_for"]["scenario"], "open-field");
    assert_eq!(plan["made_for"]["agents"], 2);
    let good = good.to_str().unwrap();
    let track = |scenario: &str, file: &str, extra: &[&str], parts: &[&str]| {
        let mut a = vec![
            "track",
            scenario,
            "--tracker",
            "obc",
            "--max-iters",
            "100",
            "--plan",
            file,
        ];
        a.extend_from_slice(extra);
        refused(&a, parts);
    };
    // another scenario's (same team): its record names it
    track(
        "narrow-passage",
        good,
        &[],
        &[good, "made_for.scenario", "\"open-field\""],
    );
    // another team
    track("trio-triangle", good, &[], &[good, "needs 3 agents"]);
    // agents swapped
    let mut swapped = plan.clone();
    for s in swapped["states"].as_array_mut().unwrap() {
        s.as_array_mut().unwrap().swap(0, 1);
    }
    let f = write(d.path(), "swapped.json", &swapped.to_string());
    track(
        "open-field",
        &f,
        &[],
        &[&f, "states[0][0]", "goal tolerance", "another order"],
    );
    // zero edges, far from the start, and no record (an older plan file)
    let mut far = plan.clone();
    let start = far["states"][0].clone();
    far["states"] = serde_json::json!([start]);
    far["states"][0][0][0] = serde_json::json!(20.0);
    far["states"][0][1][0] = serde_json::json!(22.0);
    far["controls"] = serde_json::json!([]);
    far["durations"] = serde_json::json!([]);
    far.as_object_mut().unwrap().remove("made_for");
    let f = write(d.path(), "far.json", &far.to_string());
    track(
        "open-field",
        &f,
        &[],
        &[&f, "states[0][0]", "from the scenario's start"],
    );
    // unknown keys
    let mut extra = plan.clone();
    extra["colour"] = serde_json::json!(1);
    let f = write(d.path(), "extra.json", &extra.to_string());
    track("open-field", &f, &[], &[&f, "colour", "unknown field"]);
    // --force tracks it with a warning
    let f = write(d.path(), "swapped.json", &swapped.to_string());
    let (code, stderr) = magbench_in_time(&[
        "track",
        "open-field",
        "--tracker",
        "obc",
        "--max-iters",
        "100",
        "--plan",
        &f,
        "--force",
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stderr.contains("warning:") && stderr.contains("--force"),
        "{stderr}"
    );
}

/// The rig commands' numbers go through the one bound type: `rig check --duration` is bounded
/// above, so no accepted duration runs unbounded.
#[test]
fn rig_command_numbers_are_bounded() {
    let d = tempfile::tempdir().unwrap();
    let r = write(d.path(), "ok.toml", RIG);
    for (args, field, reason) in [
        (
            vec![
                "rig",
                "check",
                "--rig",
                &r,
                "open-field",
                "--duration",
                "1e300",
            ],
            "--duration",
            "must be in (0, 86400] s",
        ),
        (
            vec![
                "rig",
                "excite",
                "--rig",
                &r,
                "open-field",
                "--out",
                "x",
                "--duration",
                "0",
            ],
            "--duration",
            "must be in (0, 86400] s",
        ),
        (
            vec![
                "rig",
                "emulate",
                "--rig",
                &r,
                "open-field",
                "--speed",
                "1e9",
            ],
            "--speed",
            "must be in (0, 100] × real time",
        ),
        (
            vec![
                "rig",
                "emulate",
                "--rig",
                &r,
                "open-field",
                "--duration",
                "NaN",
            ],
            "--duration",
            "must be in (0, 86400] s",
        ),
        (
            vec![
                "rig",
                "emulate",
                "--rig",
                &r,
                "open-field",
                "--noise",
                "NaN",
            ],
            "--noise",
            "must be in [0, 255] grey levels",
        ),
    ] {
        refused(&args, &["<command line>", field, reason]);
    }
}

/// Every number of the command line goes through the one bound type: a value outside its
/// bound exits 2 naming the option, the interval with its unit, and why, before any work.
#[test]
fn every_command_line_number_names_its_bound_and_why() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path().to_str().unwrap();
    let gen_out = d.path().join("gen");
    let gen_out = gen_out.to_str().unwrap();
    let ci = concat!(env!("CARGO_MANIFEST_DIR"), "/../experiments/ci.toml");
    let iterations = "must be in [1, 2097152] iterations";
    let memory = "within the 2 GiB memory budget";
    let plan = ["plan", "open-field", "--planner", "sst"];
    let regress = |more: &[&'static str]| [&["regress", dir, dir][..], more].concat();
    let stlc = |more: &[&'static str]| [&["stlc"][..], more].concat();
    let plan_with = |more: &[&'static str]| [&plan[..], more].concat();
    // (command lines, the option they name, its bound, why that bound)
    let cases: Vec<(Vec<Vec<&str>>, &str, &str, &str)> = vec![
        (
            vec![
                vec!["ablate", "--seeds", "0"],
                vec!["ablate", "--seeds", "18446744073709551615"],
            ],
            "--seeds",
            "must be in [1, 100000] seeds",
            "run matrix",
        ),
        (
            vec![
                vec!["ablate", "--max-iters", "0"],
                vec!["ablate", "--max-iters", "2097153"],
                plan_with(&["--max-iters", "18446744073709551615"]),
            ],
            "--max-iters",
            iterations,
            memory,
        ),
        (
            vec![vec![
                "figures",
                "--maze-iterations",
                "100000000",
                "--out",
                dir,
            ]],
            "--maze-iterations",
            iterations,
            memory,
        ),
        (
            vec![plan_with(&["--time-limit", "1e9"])],
            "--time-limit",
            "must be in (0, 604800] s",
            "a week",
        ),
        (
            vec![plan_with(&["--fps", "1e9"]), plan_with(&["--fps", "NaN"])],
            "--fps",
            "must be in [0.1, 10000] fps",
            "high-speed camera",
        ),
        (
            vec![regress(&["--alpha", "0.5"]), regress(&["--alpha", "0"])],
            "--alpha",
            "must be in (0, 0.25]",
            "cover less than half",
        ),
        (
            vec![regress(&["--success-tolerance", "1.5"])],
            "--success-tolerance",
            "must be in [0, 1] (fraction of the runs)",
            "drops by at most 1",
        ),
        (
            vec![regress(&["--tolerance", "inf"])],
            "--tolerance",
            "must be in [0, 1000000] (relative growth)",
            "lets every change pass",
        ),
        (
            vec![regress(&["--time-tolerance=-1"])],
            "--time-tolerance",
            "must be in [0, 1000000] (relative growth)",
            "lets every change pass",
        ),
        (
            vec![vec![
                "scenario", "generate", "corridor", "--count", "100001", "--out", gen_out,
            ]],
            "--count",
            "must be in [1, 100000] files",
            "as many as an experiment has seeds",
        ),
        (
            vec![stlc(&["--r", "1e308"])],
            "--r",
            "must be in (1, 30] BL",
            "too weak for the finite-difference rank test",
        ),
        (
            vec![stlc(&["--step", "0"])],
            "--step",
            "must be in [0.001, 90] degrees",
            "finer than the rank test resolves",
        ),
        (
            vec![
                stlc(&["--agents", "18446744073709551615"]),
                stlc(&["--agents", "1"]),
            ],
            "--agents",
            "must be in [2, 4] agents",
            "takes minutes",
        ),
        (
            vec![
                stlc(&["--agents", "3", "--alpha-max", "91"]),
                stlc(&["--alpha-max", "0"]),
            ],
            "--alpha-max",
            "must be in (0, 90] degrees",
            "straight up",
        ),
        (
            vec![
                vec!["bench", ci, "--dry-run", "--threads", "0"],
                vec!["ablate", "--threads", "100000"],
            ],
            "--threads",
            "threads",
            "per core of this machine",
        ),
        (
            vec![vec!["bench", ci, "--dry-run", "--shard", "1/2000000"]],
            "--shard",
            "must be in [1, 1000000] shards",
            "would be empty",
        ),
        (
            vec![vec!["results", "plot", dir, "--dpi", "5000"]],
            "--dpi",
            "must be in [50, 1200] dpi",
            "8592 px wide",
        ),
        (
            vec![vec!["results", "plot", dir, "--dpi", "10"]],
            "--dpi",
            "must be in [50, 1200] dpi",
            "unreadable",
        ),
    ];
    for (lines, option, bound, why) in &cases {
        for args in lines {
            refused(
                args,
                &["<command line>", &format!("{option}: "), bound, why],
            );
        }
    }
    assert!(
        !Path::new(gen_out).exists(),
        "a refused --count wrote files"
    );
}

/// A TOML file of more than 4 MiB (which parsing would take about 80 bytes of memory per byte
/// of) is refused before it is parsed, whatever its format.
#[test]
fn toml_files_beyond_4_mib_are_refused_before_parsing() {
    let d = tempfile::tempdir().unwrap();
    let mut text = String::from("name = \"big\"\nseeds = [");
    text.push_str(&"1,".repeat(5 << 19));
    text.push_str("1]\n");
    let f = write(d.path(), "big.toml", &text);
    for args in [
        vec!["bench", &f, "--dry-run"],
        vec!["preset", "check", &f],
        vec!["rig", "check", "--rig", &f, "open-field"],
    ] {
        refused(&args, &[&f, "larger than 4096 KiB", "memory budget"]);
    }
}

/// Names refused by the tracking loop's options: `replan_mode`, `repair_iterations` and
/// `replan_iterations` (exit 2 naming the parameter and the reason).
#[test]
fn unknown_replan_modes_are_refused_by_name() {
    let track = [
        "track",
        "open-field",
        "--planner",
        "goal-zoom-rrt",
        "--tracker",
        "obc",
    ];
    for (param, why) in [
        ("replan_mode=sometimes", "is not one of repair, restart"),
        ("repair_iterations=-3", "is not a whole number"),
        ("replan_iterations=0", "must be in [1, 1000000], got 0"),
        ("replan_iterations=2000000", "must be in [1, 1000000]"),
    ] {
        let mut args = track.to_vec();
        args.extend(["--param", param]);
        let key = param.split('=').next().unwrap();
        refused(&args, &["<command line>", &format!("param.{key}: "), why]);
    }
}
