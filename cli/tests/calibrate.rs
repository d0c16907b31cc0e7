//! `magbench calibrate`'s validation: logs of `rig excite` on env's plant and camera under
//! presets drawn at random within physical ranges (seeded), then `magbench calibrate`; every
//! identified parameter comes back within its tolerance, and tracking with the fitted preset
//! predicts the true preset's tracking error. Also the command's bad input.
//!
//! The rig is [`SimRig`] stepped frame by frame: no sockets, no sleeps, no wall clock. The
//! validation prints every parameter's true and fitted value and the tracking errors as a
//! Markdown table, which `cargo xtask measure --only calibration-validation` keeps for
//! docs/calibration.md.

use std::path::Path;
use std::process::Command;

use magbench_drivers::excite::{ExciteSetup, excite, log_for};
use magbench_env::Scenario;
use magbench_env::plant::{DisturbancePreset, Fitted};
use magbench_trackers::SimRig;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

const BIN: &str = env!("CARGO_BIN_EXE_magbench");

/// Seconds of excitation per draw.
const EXCITE_S: f64 = 240.0;

/// Runs magbench; (exit code, stdout, stderr).
fn magbench(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(BIN).args(args).output().expect("run magbench");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A preset drawn within physical ranges: per-agent moments and drags ±25% (fabricated
/// microrobots spread 20–40%), gradient gains ±10%, a field bias within ±3°, a drift up to
/// 0.01 BL/s, 0–3 frames of latency, 0.005–0.03 BL of detection noise; hydrodynamic
/// interaction on.
fn truth(seed: u64, n: usize) -> DisturbancePreset {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut p = DisturbancePreset::ideal();
    p.name = format!("truth-{seed}");
    p.hydrodynamics.enabled = true;
    let mut u = |a: f64, b: f64| rng.random_range(a..=b);
    p.fitted = Fitted {
        enabled: true,
        moment: (0..n).map(|_| u(0.75, 1.25)).collect(),
        drag: (0..n).map(|_| u(0.75, 1.25)).collect(),
        gradient_gain: Some([u(0.9, 1.1), u(0.9, 1.1)]),
        field_bias_deg: Some(u(-3.0, 3.0)),
        drift_bl_s: Some([u(-0.01, 0.01), u(-0.01, 0.01)]),
    };
    let latency = u(0.0, 3.99).floor();
    p.camera.latency.enabled = latency > 0.0;
    p.camera.latency.frames = latency;
    p.camera.noise.enabled = true;
    p.camera.noise.sigma_bl = u(0.005, 0.03);
    p
}

/// The value of `name` in the `[fitted]` or `[camera]` tables of a preset file's text.
fn fitted_value(p: &DisturbancePreset, name: &str) -> Option<f64> {
    let f = &p.fitted;
    let idx = |s: &str| s[s.find('[')? + 1..s.find(']')?].parse::<usize>().ok();
    Some(match name {
        n if n.starts_with("moment[") => f.moment.get(idx(n)?).copied()?,
        n if n.starts_with("drag[") => f.drag.get(idx(n)?).copied()?,
        "gradient_gain.x" => f.gradient_gain?[0],
        "gradient_gain.y" => f.gradient_gain?[1],
        "field_bias_deg" => f.field_bias_deg?,
        "drift_bl_s.x" => f.drift_bl_s?[0],
        "drift_bl_s.y" => f.drift_bl_s?[1],
        "camera.latency.frames" => p.camera.nominal_latency_frames(),
        "camera.noise.sigma_bl" => p.camera.noise.sigma_bl,
        _ => return None,
    })
}

/// Mean true RMS tracking error (BL) of OBC following `plan` on short-open under `preset`,
/// over seeds 0–3.
fn tracking_error(preset: &Path, plan: &Path) -> f64 {
    let scenario = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenarios/short-open.toml");
    let mut sum = 0.0;
    for seed in 0..4 {
        let (code, out, err) = magbench(&[
            "track",
            scenario,
            "--tracker",
            "obc",
            "--preset",
            &preset.display().to_string(),
            "--plan",
            &plan.display().to_string(),
            "--seed",
            &seed.to_string(),
            "--json",
        ]);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        sum += v["rms_error_true_bl"].as_f64().unwrap();
    }
    sum / 4.0
}

#[test]
fn calibrate_recovers_presets_drawn_at_random_and_predicts_their_tracking_error() {
    let scenario = Scenario::load("open-field").unwrap();
    let n = scenario.agents();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut base = DisturbancePreset::ideal();
    base.name = "base".into();
    base.hydrodynamics.enabled = true;
    let base_file = d.join("base.toml");
    std::fs::write(&base_file, base.to_toml()).unwrap();
    let short = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenarios/short-open.toml");
    let (code, _, err) = magbench(&[
        "plan",
        short,
        "--planner",
        "goal-zoom-rrt",
        "--out",
        &d.join("plan").display().to_string(),
    ]);
    assert_eq!(code, 0, "{err}");
    let plan = d.join("plan").join("plan.json");
    println!("| draw | parameter | true | fitted | error |");
    println!("| --- | --- | --- | --- | --- |");
    for seed in [11u64, 15] {
        let t = truth(seed, n);
        let truth_file = d.join(format!("truth-{seed}.toml"));
        std::fs::write(&truth_file, t.to_toml()).unwrap();
        let logs = d.join(format!("exc-{seed}"));
        std::fs::create_dir_all(&logs).unwrap();
        let mut rig = SimRig::new(&scenario, &t, seed);
        let mut log = log_for(&logs.join("rig-log.csv"), n).unwrap();
        let setup = ExciteSetup {
            duration: EXCITE_S,
            seed,
            gradient_limit: scenario.physics.gradient_limit(),
            alpha_max: std::f64::consts::FRAC_PI_2,
            world: scenario.world.clone(),
        };
        let rep = excite(&mut rig, &setup, Some(&mut log)).unwrap();
        drop(log);
        assert!(rep.frames as f64 >= 0.99 * 60.0 * EXCITE_S, "{rep:?}");
        let fitted_file = d.join(format!("fitted-{seed}.toml"));
        let (code, out, err) = magbench(&[
            "calibrate",
            &logs.display().to_string(),
            "--scenario",
            "open-field",
            "--base",
            &base_file.display().to_string(),
            "--out",
            &fitted_file.display().to_string(),
        ]);
        assert_eq!(code, 0, "{err}");
        eprintln!("seed {seed}:\n{out}");
        // the report: predicted against observed motion per agent
        for ext in ["svg", "png"] {
            let f = fitted_file.with_extension(format!("motion.{ext}"));
            assert!(
                std::fs::metadata(&f).is_ok_and(|m| m.len() > 1000),
                "{}",
                f.display()
            );
        }
        let svg = std::fs::read_to_string(fitted_file.with_extension("motion.svg")).unwrap();
        for i in 0..n {
            assert!(
                svg.contains(&format!("agent {i}: x")),
                "agent {i} in the report"
            );
        }
        let text = std::fs::read_to_string(&fitted_file).unwrap();
        let fitted = DisturbancePreset::parse(&text, "fitted.toml").unwrap();
        // every line of the report: fitted, or reported as not identified
        let mut identified = 0;
        for line in out.lines() {
            let name = line.split_whitespace().next().unwrap_or("");
            let Some(truth_v) = fitted_value(&t, name) else {
                continue;
            };
            if line.contains("not identified") || line.contains("not seen") {
                println!("| {seed} | {name} | {truth_v:.4} | not identified | – |");
                continue;
            }
            let got = fitted_value(&fitted, name).unwrap();
            let relative = name.starts_with("moment[")
                || name.starts_with("drag[")
                || name.starts_with("gradient_gain")
                || name == "camera.noise.sigma_bl";
            let tol = match name {
                "camera.latency.frames" => 1.0,
                "camera.noise.sigma_bl" => 0.2,
                "field_bias_deg" => 0.5,
                _ if relative => 0.05,
                _ => 0.005,
            };
            let (err, shown) = match relative {
                true => (
                    got / truth_v - 1.0,
                    format!("{:+.1}%", 100.0 * (got / truth_v - 1.0)),
                ),
                false => (got - truth_v, format!("{:+.4}", got - truth_v)),
            };
            let ok = err.abs() <= tol;
            println!("| {seed} | {name} | {truth_v:.4} | {got:.4} | {shown} |");
            assert!(
                ok,
                "seed {seed}: {name} = {got} against {truth_v} (error {err:.4}, tolerance {tol})"
            );
            identified += 1;
        }
        assert!(
            identified >= 8,
            "seed {seed}: {identified} identified\n{out}"
        );
        let (e_true, e_fit) = (
            tracking_error(&truth_file, &plan),
            tracking_error(&fitted_file, &plan),
        );
        println!(
            "| {seed} | tracking error (BL; OBC on short-open, seeds 0–3) | {e_true:.4} | {e_fit:.4} | {:+.1}% |",
            100.0 * (e_fit / e_true - 1.0)
        );
        assert!(
            (e_fit / e_true - 1.0).abs() <= 0.2,
            "seed {seed}: the fitted preset predicts {e_fit}, the truth gives {e_true}"
        );
    }
}

/// Exit 2 naming the option, and no panic.
fn refused(args: &[&str], parts: &[&str]) {
    let (code, _, stderr) = magbench(args);
    assert_eq!(code, 2, "{args:?}: exit {code}, stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    for p in parts {
        assert!(stderr.contains(p), "{args:?}: {p:?} missing from: {stderr}");
    }
}

#[test]
fn calibrate_refuses_bad_options_and_logs_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let log = d.join("rig-log.csv");
    std::fs::write(&log, "kind,frame,t_s\nobservation,0,0\n").unwrap();
    let out = d.join("f.toml").display().to_string();
    let log_s = log.display().to_string();
    let base = [
        "calibrate",
        &log_s,
        "--scenario",
        "open-field",
        "--out",
        &out,
    ];
    let with = |extra: &[&'static str]| {
        let mut a: Vec<&str> = base.to_vec();
        a.extend_from_slice(extra);
        a
    };
    for (extra, parts) in [
        (
            &["--segment-frames", "0"][..],
            &["--segment-frames", "must be in [1, 600] frames", "got 0"][..],
        ),
        (
            &["--segment-frames", "100000"],
            &["--segment-frames", "got 100000"],
        ),
        (
            &["--max-latency", "31"],
            &["--max-latency", "must be in [0, 30] frames", "got 31"],
        ),
    ] {
        refused(&with(extra), parts);
    }
    // not a number: clap names the option
    refused(&with(&["--max-latency=-1"]), &["--max-latency"]);
    // a file that is not a rig log: its name, the header and why
    refused(&base, &[&log_s, "header", "no column `x0_bl`"]);
}

#[test]
fn calibrate_refuses_a_log_of_a_stuck_team_naming_the_file_and_the_stuck_seconds() {
    let scenario = Scenario::load("open-field").unwrap();
    let n = scenario.agents();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let t = truth(11, n);
    let mut rig = SimRig::new(&scenario, &t, 11);
    let path = d.join("rig-log.csv");
    let mut log = log_for(&path, n).unwrap();
    let setup = ExciteSetup {
        duration: 12.0,
        seed: 11,
        gradient_limit: scenario.physics.gradient_limit(),
        alpha_max: std::f64::consts::FRAC_PI_2,
        world: scenario.world.clone(),
    };
    excite(&mut rig, &setup, Some(&mut log)).unwrap();
    drop(log);
    // from 3 s on, agent 1 is seen touching agent 0 (1 BL along x): a stuck team
    let text = std::fs::read_to_string(&path).unwrap();
    let head: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let col = |c: &str| head.iter().position(|h| *h == c).unwrap();
    let (t_s, x0, y0, x1, y1) = (
        col("t_s"),
        col("x0_bl"),
        col("y0_bl"),
        col("x1_bl"),
        col("y1_bl"),
    );
    let lines: Vec<String> = text
        .lines()
        .map(|l| {
            let mut c: Vec<String> = l.split(',').map(String::from).collect();
            let late = c[t_s].parse::<f64>().is_ok_and(|t| t >= 3.0);
            if l.contains(",observation,") && late && !c[x0].is_empty() && !c[x1].is_empty() {
                let x: f64 = c[x0].parse().unwrap();
                c[x1] = format!("{}", x + 1.0);
                c[y1] = c[y0].clone();
            }
            c.join(",")
        })
        .collect();
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    let out = d.join("f.toml");
    let log_s = path.display().to_string();
    refused(
        &[
            "calibrate",
            &log_s,
            "--scenario",
            "open-field",
            "--out",
            &out.display().to_string(),
        ],
        &[
            &log_s,
            "frames",
            "too little usable data",
            "stuck in contact",
            "excluded",
        ],
    );
    assert!(!out.exists(), "a preset was written for a refused log");
}
