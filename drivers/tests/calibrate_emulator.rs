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
use magbench_drivers::fit::{FitOptions, Kind, Status, calibrate, read_log};
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

#[test]
fn excite_on_the_emulator_then_calibrate_recovers_its_preset() {
    let text = include_str!("../../rigs/emulator.toml");
    let rig = RigConfig::parse(text, "emulator.toml").unwrap();
    let scenario = Scenario::load("open-field").unwrap();
    let n = scenario.agents();
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

    let mut base = DisturbancePreset::ideal();
    base.hydrodynamics.enabled = true;
    let run = read_log(&log, n).unwrap();
    let fit = calibrate(&scenario, &base, vec![run], &FitOptions::default()).unwrap();
    for l in fit.lines() {
        eprintln!("  {l}");
    }
    let t = truth();
    let f = &t.fitted;
    let mut checked = 0;
    for p in &fit.params {
        let Status::Fitted = p.status else { continue };
        let (truth, tol) = match p.kind {
            Kind::Moment(i) => (f.moment[i], 0.05),
            Kind::Drag(i) => (f.drag[i], 0.05),
            Kind::GradientGain(a) => (f.gradient_gain.unwrap()[a], 0.05),
            _ => continue,
        };
        let err = (p.value / truth - 1.0).abs();
        eprintln!(
            "  {:<18} true {truth:.4} fitted {:.4} error {:.1}%",
            p.name,
            p.value,
            100.0 * err
        );
        assert!(err <= tol, "{} = {} against {truth}", p.name, p.value);
        checked += 1;
    }
    assert!(
        checked >= 4,
        "only {checked} of moments, drags and gains identified"
    );
    assert!(fit.latency.abs_diff(2) <= 1, "latency {}", fit.latency);
    let s = fit.noise.expect("noise seen");
    let sigma = t.camera.noise.sigma_bl;
    assert!((s / sigma - 1.0).abs() <= 0.2, "noise {s} against {sigma}");
    assert!(
        !fit.traces.is_empty(),
        "the report has predicted against observed motion"
    );
}
