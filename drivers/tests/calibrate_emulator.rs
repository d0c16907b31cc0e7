//! `rig excite` against the rig emulator, then `calibrate`: the excitation goes through the
//! real coil link and the emulator's rendered camera frames (its pixel detector, frame timing
//! and the preset's camera latency and detection noise), and the fit recovers the emulated
//! preset: moments, drags and gradient gains within 5%, latency within one frame, detection
//! noise within 20%.
//!
//! Host and emulator share one [`ManualClock`] that the test never moves, and the emulator runs
//! in lockstep (a frame goes out once the host has answered the last one): no timer fires, no
//! sleep, and device time is frame count × period whatever the machine's load.

mod common;

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use magbench_drivers::HardwareRig;
use magbench_drivers::clock::ManualClock;
use magbench_drivers::emulator::faults::FaultPlan;
use magbench_drivers::emulator::render::RenderParams;
use magbench_drivers::emulator::{self, DeviceEndpoint, EmulatorConfig};
use magbench_drivers::excite::{ExciteSetup, excite};
use magbench_drivers::fit::{FitOptions, FitReport, Kind, Status, calibrate, read_log};
use magbench_drivers::rigfile::{CoilEndpoint, RigConfig};
use magbench_env::Scenario;
use magbench_env::plant::{DisturbancePreset, Fitted};

/// Seconds of excitation.
const DURATION_S: f64 = 60.0;

/// The emulated rig's preset: per-agent moments and drags off by up to 14%, gradient gains off
/// by 6%, two frames of camera latency and 0.01 BL of detection noise.
fn truth() -> DisturbancePreset {
    let fitted = Fitted {
        enabled: true,
        moment: vec![1.12, 0.88],
        drag: vec![0.90, 1.14],
        gradient_gain: Some([1.06, 0.95]),
        field_bias_deg: Some(0.0),
        drift_bl_s: Some([0.0, 0.0]),
    };
    common::emulated("emulated", fitted, 2.0, 0.01)
}

/// An excitation run of [`DURATION_S`] through the lockstep emulator of [`truth`]: the folder
/// that holds its log, and the log's path.
fn excite_on_the_emulator(scenario: &Scenario) -> (tempfile::TempDir, PathBuf) {
    let text = include_str!("../../rigs/emulator.toml");
    let rig = RigConfig::parse(text, "emulator.toml").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let (tx, rx) = mpsc::channel();
    let stop = Arc::new(AtomicBool::new(false));
    let clock = Arc::new(ManualClock::new());
    let cfg = EmulatorConfig {
        rig: rig.clone(),
        scenario: scenario.clone(),
        endpoint: DeviceEndpoint::Tcp("127.0.0.1:0".into()),
        camera_listen: "127.0.0.1:0".into(),
        faults: FaultPlan::default(),
        preset: truth(),
        render: RenderParams::default(),
        preset_camera: true,
        seed: 5,
        clock: clock.clone(),
        speed: 1.0,
        lockstep: true,
        duration: None,
        log: dir.path().join("emulator-log.csv"),
        record: None,
        on_ready: Box::new(move |coil: &str, cam: &str| {
            let _ = tx.send((coil.to_string(), cam.to_string()));
        }),
        on_event: None,
    };
    let s = stop.clone();
    let emu = std::thread::spawn(move || emulator::run(cfg, s));
    let (coil, cam) = rx.recv_timeout(Duration::from_secs(30)).unwrap();
    let coil = coil.strip_prefix("tcp ").unwrap().to_string();
    let live = RigConfig::with_endpoints(text, &CoilEndpoint::Tcp(coil), Some(&cam)).unwrap();
    let live = RigConfig::parse(&live, "live.toml").unwrap();

    let log = dir.path().join("rig-log.csv");
    let mut hw = HardwareRig::open_with_clock(
        &live,
        live.coil.field_mt.unwrap_or(scenario.physics.field_mt),
        &scenario.start,
        Arc::new(AtomicBool::new(false)),
        Some(&log),
        clock,
    )
    .unwrap();
    let setup = ExciteSetup {
        duration: DURATION_S,
        seed: 2,
        gradient_limit: scenario.physics.gradient_limit(),
        alpha_max: live.coil.alpha_max_deg.to_radians(),
        world: scenario.world.clone(),
    };
    let rep = excite(&mut hw, &setup, None).unwrap();
    drop(hw);
    stop.store(true, Ordering::Relaxed);
    emu.join().unwrap().unwrap();
    eprintln!("{rep:?}");
    assert!(rep.frames as f64 >= 0.99 * DURATION_S * 60.0, "{rep:?}");
    (dir, log)
}

/// Fits the hydrodynamic-only base to the log at `log`, with the start states free or from
/// the observed starts.
fn fit(scenario: &Scenario, log: &Path, free_starts: bool) -> FitReport {
    let mut base = DisturbancePreset::ideal();
    base.hydrodynamics.enabled = true;
    let run = read_log(log, scenario.agents()).unwrap();
    let opts = FitOptions {
        free_starts,
        ..FitOptions::default()
    };
    calibrate(scenario, &base, vec![run], &opts).unwrap()
}

/// The true value of a fitted parameter, and whether its error is relative (a factor) rather
/// than absolute; `None` for the coils' τ, which the emulated preset does not have.
fn true_value(kind: Kind, f: &Fitted) -> Option<(f64, bool)> {
    Some(match kind {
        Kind::Moment(i) => (f.moment[i], true),
        Kind::Drag(i) => (f.drag[i], true),
        Kind::GradientGain(a) => (f.gradient_gain?[a], true),
        Kind::FieldBias => (f.field_bias_deg?, false),
        Kind::Drift(a) => (f.drift_bl_s?[a], false),
        Kind::FieldTau | Kind::GradientTau | Kind::Latency => return None,
    })
}

/// A fitted value and its error against `truth`: relative (%) or absolute.
fn shown(value: Option<f64>, truth: f64, relative: bool) -> String {
    match value {
        None => "not fitted | –".into(),
        Some(v) if relative => format!("{v:.4} | {:+.1}%", 100.0 * (v / truth - 1.0)),
        Some(v) => format!("{v:.4} | {:+.4}", v - truth),
    }
}

/// Checks `fit` against the truth within the tolerances of the module doc; the largest
/// relative error of the moments, drags and gradient gains.
fn check(fit: &FitReport) -> f64 {
    let t = truth();
    let mut checked = 0;
    let mut worst: f64 = 0.0;
    for p in &fit.params {
        let Status::Fitted = p.status else { continue };
        let Some((truth, true)) = true_value(p.kind, &t.fitted) else {
            continue;
        };
        let err = (p.value / truth - 1.0).abs();
        assert!(err <= 0.05, "{} = {} against {truth}", p.name, p.value);
        worst = worst.max(err);
        checked += 1;
    }
    assert!(
        checked >= 4,
        "only {checked} of moments, drags and gains identified"
    );
    assert!((fit.latency - 2.0).abs() <= 0.5, "latency {}", fit.latency);
    let s = fit.noise.expect("noise seen");
    let sigma = t.camera.noise.sigma_bl;
    assert!((s / sigma - 1.0).abs() <= 0.2, "noise {s} against {sigma}");
    assert!(
        !fit.traces.is_empty(),
        "the report has predicted against observed motion"
    );
    worst
}

#[test]
fn excite_on_the_emulator_then_calibrate_recovers_its_preset() {
    let scenario = Scenario::load("open-field").unwrap();
    let (_dir, log) = excite_on_the_emulator(&scenario);
    let fit = fit(&scenario, &log, true);
    for l in fit.lines() {
        eprintln!("  {l}");
    }
    check(&fit);
}

/// The same run fitted from the observed starts and with the start states free, both fits'
/// values and errors printed as a Markdown table, which `cargo xtask measure --only
/// calibration-emulator` keeps for docs/calibration.md; the free-start fit is held to the
/// tolerances of the module doc. A second fit on top of the default test's run.
#[test]
#[ignore = "the default test plus a fit from the observed starts; run with --ignored"]
fn free_start_states_against_the_observed_starts_on_the_emulator() {
    let scenario = Scenario::load("open-field").unwrap();
    let (_dir, log) = excite_on_the_emulator(&scenario);
    let observed = fit(&scenario, &log, false);
    let free = fit(&scenario, &log, true);
    let t = truth();
    println!(
        "| parameter | true | fitted from the observed starts | error | fitted with the start states free | error |"
    );
    println!("| --- | --- | --- | --- | --- | --- |");
    let value = |f: &FitReport, name: &str| {
        f.params
            .iter()
            .find(|p| p.name == name && p.status == Status::Fitted)
            .map(|p| p.value)
    };
    let mut worst_observed: f64 = 0.0;
    for p in &free.params {
        let Some((truth, relative)) = true_value(p.kind, &t.fitted) else {
            continue;
        };
        let o = value(&observed, &p.name);
        if let (Some(o), true) = (o, relative) {
            worst_observed = worst_observed.max((o / truth - 1.0).abs());
        }
        println!(
            "| {} | {truth:.4} | {} | {} |",
            p.name,
            shown(o, truth, relative),
            shown(value(&free, &p.name), truth, relative)
        );
    }
    let latency = t.camera.nominal_latency_frames();
    println!(
        "| camera.latency.frames | {latency} | {} | {:+} | {} | {:+} |",
        observed.latency,
        observed.latency - latency,
        free.latency,
        free.latency - latency
    );
    let sigma = t.camera.noise.sigma_bl;
    println!(
        "| camera.noise.sigma_bl | {sigma:.4} | {} | {} |",
        shown(observed.noise, sigma, true),
        shown(free.noise, sigma, true)
    );
    let worst_free = check(&free);
    println!(
        "| worst of moments, drags and gains | | | {:.1}% | | {:.1}% |",
        100.0 * worst_observed,
        100.0 * worst_free
    );
}
