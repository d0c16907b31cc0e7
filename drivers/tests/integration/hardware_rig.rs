//! The hardware rig against an in-process emulator (TCP): the field goes to zero on a panic,
//! on a stalled loop (host hold timeout), on an interrupt (the abort flag the Ctrl-C handler
//! raises) and on a non-finite command.
//!
//! Host and emulator share one [`ManualClock`] and the emulator runs in lockstep, so no timer
//! (hold timeout, heartbeat, device watchdog) moves unless the test moves it: "the loop stalls
//! for 300 ms" is `clock.advance(300 ms)`, whatever the machine's load.

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use magbench_drivers::clock::{Clock, ManualClock};
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
    /// A message after each event the emulator logs.
    logged: mpsc::Receiver<()>,
    clock: Arc<ManualClock>,
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
    let text = include_str!("../../../rigs/emulator.toml");
    let rig = RigConfig::parse(text, "emulator.toml").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("log.csv");
    let (tx, rx) = mpsc::channel();
    let stop = Arc::new(AtomicBool::new(false));
    let clock = Arc::new(ManualClock::new());
    let (logged_tx, logged) = mpsc::channel();
    let cfg = EmulatorConfig {
        rig: rig.clone(),
        scenario: Scenario::load("open-field").unwrap(),
        endpoint: DeviceEndpoint::Tcp("127.0.0.1:0".into()),
        camera_listen: "127.0.0.1:0".into(),
        faults: FaultPlan::default(),
        preset: DisturbancePreset::ideal(),
        render: RenderParams::default(),
        preset_camera: false,
        seed: 1,
        clock: clock.clone(),
        speed: 1.0,
        lockstep: true,
        duration: None,
        log: log.clone(),
        record: None,
        on_ready: Box::new(move |coil: &str, cam: &str| {
            let _ = tx.send((coil.to_string(), cam.to_string()));
        }),
        on_event: Some(Arc::new(move |_: &str| {
            let _ = logged_tx.send(());
        })),
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
        logged,
        clock,
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

/// Reads the emulator's log again after each event it writes until `done` holds; a minute
/// without an event fails the test instead of hanging it.
fn wait_for(emu: &Emu, what: &str, done: impl Fn(&[(String, bool)]) -> bool) {
    while !done(&events(&emu.log)) {
        if emu.logged.recv_timeout(Duration::from_secs(60)).is_err() {
            panic!("the emulator never logged {what}: {:?}", events(&emu.log));
        }
    }
}

fn count(ev: &[(String, bool)], name: &str) -> usize {
    ev.iter().filter(|(e, _)| e == name).count()
}

fn open(emu: &Emu) -> HardwareRig {
    open_with_abort(emu, Arc::new(AtomicBool::new(false)))
}

/// The rig with `abort` as its interrupt flag (what `interrupt::interrupt_flag` hands a real run).
fn open_with_abort(emu: &Emu, abort: Arc<AtomicBool>) -> HardwareRig {
    let s = Scenario::load("open-field").unwrap();
    HardwareRig::open_with_clock(&emu.rig, 5.0, &s.start, abort, None, emu.clock.clone()).unwrap()
}

fn drive(rig: &mut HardwareRig, frames: usize) {
    for _ in 0..frames {
        rig.observe().unwrap();
        rig.command(&Control::planar(1.0, 0.0, 0.0)).unwrap();
    }
}

/// The field was on, and a ZERO came after the last non-zero currents.
fn zeroed_after_on(ev: &[(String, bool)]) -> bool {
    ev.iter()
        .rposition(|(e, z)| e == "currents" && !z)
        .is_some_and(|on| ev[on..].iter().any(|(e, z)| e == "zero" && *z))
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
    // the rig's Drop waited for the device's acknowledgement of ZERO, which the device logs
    // before it answers: the log has it now
    let ev = events(&emu.log);
    assert!(zeroed_after_on(&ev), "no ZERO after the panic: {ev:?}");
}

#[test]
fn a_stalled_loop_is_zeroed_by_the_hold_timeout() {
    let emu = emulator();
    let cfg = &emu.rig.coil;
    let (heartbeat, hold) = (cfg.heartbeat_ms as u64, cfg.hold_timeout_ms as u64);
    assert!(heartbeat < cfg.watchdog_ms as u64 && hold % heartbeat == 0);
    let mut rig = open(&emu);
    drive(&mut rig, 10);
    // the loop stalls: every heartbeat period the keep-alive thread renews the device's
    // watchdog, until the hold timeout zeroes the field
    let beats = count(&events(&emu.log), "heartbeat");
    for k in 1..=hold / heartbeat {
        emu.clock.advance(Duration::from_millis(heartbeat));
        wait_for(&emu, "a heartbeat", |ev| {
            count(ev, "heartbeat") >= beats + k as usize
        });
    }
    let ev = events(&emu.log);
    assert!(!zeroed_after_on(&ev), "zeroed before the hold timeout");
    emu.clock.advance(Duration::from_millis(1));
    wait_for(&emu, "the hold-timeout ZERO", zeroed_after_on);
    assert!(
        emu.clock.now() > Duration::from_millis(cfg.watchdog_ms as u64),
        "the stall outlasted the device watchdog"
    );
    assert_eq!(
        count(&events(&emu.log), "watchdog"),
        0,
        "the heartbeat must keep the device watchdog quiet"
    );
    match rig.observe() {
        Err(HardwareError::Safety(m)) => assert!(m.contains("hold timeout"), "{m}"),
        other => panic!("expected a hold-timeout stop, got {other:?}"),
    }
}

#[test]
fn an_interrupt_zeroes_the_field_from_the_keep_alive_thread() {
    let emu = emulator();
    let abort = Arc::new(AtomicBool::new(false));
    let mut rig = open_with_abort(&emu, abort.clone());
    drive(&mut rig, 10);
    let ev = events(&emu.log);
    assert!(
        ev.iter().any(|(e, z)| e == "currents" && !z),
        "the field was never on: {ev:?}"
    );
    assert!(!zeroed_after_on(&ev), "zeroed before the interrupt: {ev:?}");
    // Ctrl-C while the loop sits between frames: the keep-alive thread alone must zero the
    // field. The shared clock stands still, so neither the hold timeout nor the device
    // watchdog can be what zeroes it.
    let before = emu.clock.now();
    abort.store(true, Ordering::SeqCst);
    wait_for(&emu, "the interrupt's ZERO", zeroed_after_on);
    assert_eq!(emu.clock.now(), before);
    let ev = events(&emu.log);
    assert_eq!(count(&ev, "watchdog"), 0, "{ev:?}");
    assert!(
        ev.iter()
            .rev()
            .find(|(e, _)| e == "currents" || e == "zero")
            .is_some_and(|(_, z)| *z),
        "the currents in force are not zero: {ev:?}"
    );
    // the loop ends as interrupted, and sends nothing more
    match rig.observe() {
        Err(HardwareError::Safety(m)) => {
            assert!(
                m.contains("interrupted: field zeroed (acknowledged)"),
                "{m}"
            )
        }
        other => panic!("expected an interrupted stop, got {other:?}"),
    }
    assert!(rig.command(&Control::planar(1.0, 0.0, 0.0)).is_err());
    drop(rig);
    let ev = events(&emu.log);
    let on_after = ev
        .iter()
        .rposition(|(e, z)| e == "zero" && *z)
        .is_some_and(|z| ev[z..].iter().any(|(e, z)| e == "currents" && !z));
    assert!(!on_after, "currents after the interrupt: {ev:?}");
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
    // the rig zeroed the field before returning the error (acknowledged, so logged)
    let ev = events(&emu.log);
    assert_eq!(count(&ev, "refused"), 0, "a NaN reached the device");
    assert!(
        ev.iter()
            .rev()
            .find(|(e, _)| e == "zero" || e == "currents")
            .is_some_and(|(_, z)| *z),
        "{ev:?}"
    );
}

/// In lockstep, frames pause while no host has a session: a host that comes a second after
/// the last one left sees the frames it would have seen at once (the plant does not run on
/// between them), so runs made one after another repeat whatever the machine's load.
#[test]
fn a_second_host_sees_the_frames_the_first_left_whatever_the_time_between() {
    let emu = emulator();
    let mut rig = open(&emu);
    drive(&mut rig, 10);
    drop(rig);
    wait_for(&emu, "the first host's disconnect", |ev| {
        count(ev, "coil_disconnect") == 1
    });
    // a second of the emulator's clock passes with no host: twenty of its 50 ms waits
    for _ in 0..20 {
        emu.clock.advance(Duration::from_millis(50));
    }
    let mut rig = open(&emu);
    drive(&mut rig, 10);
    drop(rig);
    wait_for(&emu, "the second host's disconnect", |ev| {
        count(ev, "coil_disconnect") == 2
    });
    // each frame's index and session, in the log's order: the first host's last command
    // answers its tenth frame and so releases an eleventh, made for that host's session even
    // when the host has left before it is made (so it may be logged after the second host's
    // hello); then none until the second host, whose first frame is the twelfth
    let frames = frames(&emu.log);
    let indices: Vec<u64> = frames.iter().map(|f| f.0).collect();
    let first = frames.iter().take_while(|f| f.1 == 1).count();
    assert_eq!(first, 11, "frames went out with no host: {frames:?}");
    assert!(frames[11..].iter().all(|f| f.1 == 2), "{frames:?}");
    assert!(frames.len() - 11 >= 10, "{frames:?}");
    assert!(
        indices
            .iter()
            .zip(indices.iter().skip(1))
            .all(|(a, b)| b == &(a + 1)),
        "{indices:?}"
    );
}

/// The index and session of each `frame` event (detail `index k session s`), in the log's order.
fn frames(log: &Path) -> Vec<(u64, u64)> {
    std::fs::read_to_string(log)
        .unwrap()
        .lines()
        .skip(1)
        .filter(|l| l.split(',').nth(2) == Some("frame"))
        .map(|l| {
            let w: Vec<&str> = l.rsplit(',').next().unwrap().split(' ').collect();
            match w[..] {
                ["index", k, "session", s] => (k.parse().unwrap(), s.parse().unwrap()),
                _ => panic!("a frame without its index and session: {l}"),
            }
        })
        .collect()
}
