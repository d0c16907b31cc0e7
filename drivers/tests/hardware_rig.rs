//! The hardware rig against an in-process emulator (TCP): the field goes to zero on a panic,
//! on a stalled loop (host hold timeout) and on a non-finite command.

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use magbench_drivers::emulator::faults::FaultPlan;
use magbench_drivers::emulator::render::RenderParams;
use magbench_drivers::emulator::{self, DeviceEndpoint, EmulatorConfig};
use magbench_drivers::rigfile::{CoilEndpoint, RigConfig};
use magbench_drivers::{HardwareError, HardwareRig};
use magbench_env::plant::DisturbancePreset;
use magbench_env::{Control, Scenario};

struct Emu {
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
    rig: RigConfig,
    log: std::path::PathBuf,
    _dir: tempfile::TempDir,
}

impl Drop for Emu {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn emulator() -> Emu {
    let text = include_str!("../../rigs/emulator.toml");
    let rig = RigConfig::parse(text, "emulator.toml").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("log.csv");
    let (tx, rx) = mpsc::channel();
    let stop = Arc::new(AtomicBool::new(false));
    let cfg = EmulatorConfig {
        rig: rig.clone(),
        scenario: Scenario::load("open-field").unwrap(),
        endpoint: DeviceEndpoint::Tcp("127.0.0.1:0".into()),
        camera_listen: "127.0.0.1:0".into(),
        faults: FaultPlan::default(),
        preset: DisturbancePreset::ideal(),
        render: RenderParams::default(),
        seed: 1,
        speed: 1.0,
        lockstep: false,
        duration: Some(60.0),
        log: log.clone(),
        record: None,
        on_ready: Box::new(move |coil: &str, cam: &str| {
            let _ = tx.send((coil.to_string(), cam.to_string()));
        }),
    };
    let s = stop.clone();
    let thread = std::thread::spawn(move || emulator::run(cfg, s).unwrap());
    let (coil, cam) = rx.recv_timeout(Duration::from_secs(30)).unwrap();
    let coil = coil.strip_prefix("tcp ").unwrap().to_string();
    let live = RigConfig::with_endpoints(text, &CoilEndpoint::Tcp(coil), Some(&cam)).unwrap();
    let rig = RigConfig::parse(&live, "live.toml").unwrap();
    Emu {
        stop,
        thread: Some(thread),
        rig,
        log,
        _dir: dir,
    }
}

/// (event, currents all zero) per line of the emulator log.
fn events(log: &Path) -> Vec<(String, bool)> {
    std::fs::read_to_string(log)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let zero = f[4]
                .split(';')
                .filter(|s| !s.is_empty())
                .all(|c| c.parse::<f64>().unwrap() == 0.0);
            (f[2].to_string(), zero)
        })
        .collect()
}

fn open(emu: &Emu) -> HardwareRig {
    let s = Scenario::load("open-field").unwrap();
    HardwareRig::open(
        &emu.rig,
        5.0,
        &s.start,
        Arc::new(AtomicBool::new(false)),
        None,
    )
    .unwrap()
}

fn drive(rig: &mut HardwareRig, frames: usize) {
    for _ in 0..frames {
        rig.observe().unwrap();
        rig.command(&Control::planar(1.0, 0.0, 0.0)).unwrap();
    }
}

#[test]
fn a_panic_in_the_loop_zeroes_the_field() {
    let emu = emulator();
    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let mut rig = open(&emu);
        drive(&mut rig, 10);
        panic!("a bug in the loop");
    }));
    assert!(r.is_err());
    std::thread::sleep(Duration::from_millis(100));
    let ev = events(&emu.log);
    let last_on = ev
        .iter()
        .rposition(|(e, z)| e == "currents" && !z)
        .expect("the field was on");
    assert!(
        ev[last_on..].iter().any(|(e, z)| e == "zero" && *z),
        "no ZERO after the panic: {:?}",
        &ev[last_on..]
    );
}

#[test]
fn a_stalled_loop_is_zeroed_by_the_hold_timeout() {
    let emu = emulator();
    let mut rig = open(&emu);
    drive(&mut rig, 10);
    std::thread::sleep(Duration::from_millis(400)); // > hold_timeout_ms = 250
    let ev = events(&emu.log);
    let last_on = ev.iter().rposition(|(e, z)| e == "currents" && !z).unwrap();
    assert!(
        ev[last_on..].iter().any(|(e, z)| e == "zero" && *z),
        "the keep-alive thread did not zero the field"
    );
    assert!(
        !ev.iter().any(|(e, _)| e == "watchdog"),
        "the heartbeat must keep the device watchdog quiet"
    );
    match rig.observe() {
        Err(HardwareError::Safety(m)) => assert!(m.contains("hold timeout"), "{m}"),
        other => panic!("expected a hold-timeout stop, got {other:?}"),
    }
}

#[test]
fn a_non_finite_command_is_never_sent() {
    let emu = emulator();
    let mut rig = open(&emu);
    drive(&mut rig, 5);
    rig.observe().unwrap();
    let bad = Control {
        theta: f64::NAN,
        ..Default::default()
    };
    assert!(rig.command(&bad).is_err());
    std::thread::sleep(Duration::from_millis(50));
    let ev = events(&emu.log);
    assert!(
        !ev.iter().any(|(e, _)| e == "refused"),
        "a NaN reached the device"
    );
    assert!(ev.last().is_some_and(|_| {
        ev.iter()
            .rev()
            .find(|(e, _)| e == "zero" || e == "currents")
            .is_some_and(|(_, z)| *z)
    }));
}
