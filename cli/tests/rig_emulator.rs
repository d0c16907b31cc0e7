//! The physical code path against the emulator, each in its own process over real I/O
//! (loopback TCP or a pseudo-terminal): bring-up runs, every injected fault, a killed host, an
//! interrupted host.
//!
//! The emulator runs in lockstep: a frame goes out when the host has answered the last one,
//! and fault times count frames, so machine load cannot reorder what a test checks. Nothing
//! here sleeps to wait for something: the emulator writes its event log into a FIFO that a
//! thread of the test reads, and a test waits on each event it delivers (or on a host's exit)
//! until its condition holds, with a generous overall deadline. Tests run one at a time (a
//! lock) so that two emulators never compete for the 2 cores, in a binary of their own (not
//! the command line's `integration`): a host late by more than the emulator's 50 ms wait for
//! its command changes the run, and the micro-factory run missed its goal once with four busy
//! loops on the 2 cores.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::{Arc, Condvar, Mutex, mpsc};
use std::time::{Duration, Instant};

static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

const BIN: &str = env!("CARGO_BIN_EXE_magbench");

fn rig_file() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../rigs/emulator.toml")
}

/// An emulator process, killed when dropped.
struct Emulator {
    child: Child,
    dir: tempfile::TempDir,
    events: Arc<Events>,
}

/// The emulator's events in the order its log delivered them, and whether the log has ended;
/// `arrived` is notified after each.
#[derive(Default)]
struct Events {
    log: Mutex<(Vec<Event>, bool)>,
    arrived: Condvar,
}

impl Events {
    /// Reads the event log at `fifo` (blocking until the emulator opens it) to its end.
    fn read(&self, fifo: &Path) {
        let file = std::fs::File::open(fifo).unwrap();
        for line in BufReader::new(file).lines().map_while(Result::ok).skip(1) {
            self.log.lock().unwrap().0.push(Event::parse(&line));
            self.arrived.notify_all();
        }
        self.log.lock().unwrap().1 = true;
        self.arrived.notify_all();
    }
}

impl Emulator {
    fn start(scenario: &str, args: &[&str]) -> Emulator {
        let dir = tempfile::tempdir().unwrap();
        let log = dir.path().join("emulator-log.csv");
        let made = Command::new("mkfifo").arg(&log).status().unwrap();
        assert!(made.success(), "mkfifo {}: {made}", log.display());
        let events = Arc::new(Events::default());
        let reader = Arc::clone(&events);
        let fifo = log.clone();
        std::thread::spawn(move || reader.read(&fifo));
        let mut cmd = Command::new(BIN);
        cmd.args(["rig", "emulate", "--lockstep", "--rig"])
            .arg(rig_file())
            .arg(scenario);
        cmd.arg("--write-rig").arg(dir.path().join("live.toml"));
        cmd.arg("--log").arg(&log);
        if !args.contains(&"--duration") {
            cmd.args(["--duration", "120"]);
        }
        cmd.args(args);
        let mut child = cmd
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let out = child.stdout.take().unwrap();
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(out).lines().map_while(Result::ok) {
                if line == "ready" {
                    let _ = tx.send(());
                }
            }
        });
        let emu = Emulator { child, dir, events };
        rx.recv_timeout(Duration::from_secs(30))
            .expect("the emulator did not get ready in 30 s");
        emu
    }

    fn rig(&self) -> PathBuf {
        self.dir.path().join("live.toml")
    }

    fn out(&self) -> PathBuf {
        self.dir.path().join("out")
    }

    fn host_log(&self) -> String {
        std::fs::read_to_string(self.out().join("rig-log.csv")).unwrap_or_default()
    }
}

impl Drop for Emulator {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// One line of the emulator's event log.
#[derive(Debug, Clone)]
struct Event {
    /// The emulator clock's time of the event (the clock its watchdog counts).
    clock: f64,
    t: f64,
    name: String,
    currents: Vec<f64>,
    detail: String,
}

impl Event {
    fn parse(line: &str) -> Event {
        let f: Vec<&str> = line.split(',').collect();
        Event {
            clock: f[0].parse().unwrap(),
            t: f[1].parse().unwrap(),
            name: f[2].to_string(),
            currents: f[4]
                .split(';')
                .filter(|s| !s.is_empty())
                .map(|s| s.parse().unwrap())
                .collect(),
            detail: f.get(6).unwrap_or(&"").to_string(),
        }
    }
}

/// Runs `magbench rig check` against the emulator, killing it (and failing) if it hangs.
fn host(emu: &Emulator, scenario: &str, duration: f64) -> Output {
    let child = Command::new(BIN)
        .args(["rig", "check", "--rig"])
        .arg(emu.rig())
        .arg(scenario)
        .args(["--duration", &duration.to_string(), "--out"])
        .arg(emu.out())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_or_kill(child, Duration::from_secs_f64(duration + 20.0))
}

/// Waits for `child` to exit and returns its output; kills it (and fails) after `limit`.
fn wait_or_kill(child: Child, limit: Duration) -> Output {
    let pid = child.id().to_string();
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || tx.send(child.wait_with_output()));
    match rx.recv_timeout(limit) {
        Ok(out) => out.unwrap(),
        Err(_) => {
            let _ = Command::new("kill").args(["-KILL", &pid]).status();
            let out = rx.recv().unwrap().unwrap();
            panic!(
                "the host hung for {limit:?}; stderr: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
    }
}

/// The currents the device holds at the end of the emulator log (after the host is gone): those
/// of the coil link's last event (a command, a zero, the watchdog or the link's end). A `frame`
/// or a camera event carries the currents the plant felt up to that frame, which may predate a
/// disconnect logged just before it.
fn final_currents(log: &[Event]) -> Option<Vec<f64>> {
    let device = |name: &str| {
        matches!(
            name,
            "currents" | "currents_repeat" | "zero" | "watchdog" | "fault_disconnect"
        ) || name.starts_with("coil_")
    };
    log.iter()
        .rev()
        .find(|e| device(&e.name))
        .map(|e| e.currents.clone())
}

fn any_nonzero(log: &[Event]) -> bool {
    log.iter()
        .any(|e| e.name == "currents" && e.currents.iter().any(|c| *c != 0.0))
}

/// Waits, event by event, until the emulator's log so far satisfies `done`, and returns it;
/// fails (does not hang) when the log ends first or after a generous deadline.
fn wait_for_log(emu: &Emulator, what: &str, done: impl Fn(&[Event]) -> bool) -> Vec<Event> {
    let deadline = Instant::now() + Duration::from_secs(60);
    let mut seen = emu.events.log.lock().unwrap();
    loop {
        let (log, ended) = &*seen;
        if done(log) {
            return log.clone();
        }
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(
            !ended && !left.is_zero(),
            "the emulator never logged {what}; log tail: {:?}",
            &log[log.len().saturating_sub(5)..]
        );
        seen = emu.events.arrived.wait_timeout(seen, left).unwrap().0;
    }
}

/// Waits until the host has sent the emulator 30 commands with a current on.
fn wait_for_host_driving(emu: &Emulator) {
    wait_for_log(emu, "the host driving the coil", |log| {
        log.iter()
            .filter(|e| e.name == "currents" && e.currents.iter().any(|c| *c != 0.0))
            .count()
            >= 30
    });
}

/// The emulator's log once the currents it has in force are zero (the host gone or stopped).
fn log_after_zero(emu: &Emulator) -> Vec<Event> {
    wait_for_log(emu, "zero currents at the end", |log| {
        final_currents(log).is_some_and(|c| c.iter().all(|c| *c == 0.0))
    })
}

/// The host either went on to the end (exit 0) or stopped with zero field and a clear message
/// (exit 1, "field zeroed"), never panicked, and the stop followed the fault it detected within
/// one control period: in the host log the fatal `fault` row, then the `stop` row, with no
/// `command` between them.
fn recovered_or_stopped_cleanly(out: &Output, host_log: &str) -> bool {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "the host panicked: {stderr}");
    match out.status.code() {
        Some(0) => true,
        Some(1) => {
            assert!(
                stderr.contains("field zeroed"),
                "unclear stop message: {stderr}"
            );
            let rows: Vec<&str> = host_log.lines().collect();
            let stop = rows
                .iter()
                .position(|r| r.split(',').nth(2) == Some("stop"))
                .expect("a stop row in the host log");
            let fault = rows[..stop]
                .iter()
                .rposition(|r| r.split(',').nth(2) == Some("fault"))
                .expect("the fault before the stop");
            let commands = rows[fault..stop]
                .iter()
                .filter(|r| r.split(',').nth(2) == Some("command"))
                .count();
            assert_eq!(
                commands, 0,
                "the host sent commands between the fault and the stop"
            );
            false
        }
        other => panic!("host exit {other:?}: {stderr}"),
    }
}

#[test]
fn check_over_tcp_turns_the_pair_and_leaves_zero_currents() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let emu = Emulator::start("open-field", &[]);
    let out = host(&emu, "open-field", 3.0);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    println!("{stdout}");
    let log = log_after_zero(&emu);
    assert!(any_nonzero(&log), "no current was ever commanded");
    assert!(stdout.contains("0 missed"), "{stdout}");
    // the pair turned in place: it moved, and the separation held
    let turned: f64 = stdout
        .split("turned ")
        .nth(1)
        .unwrap()
        .split('°')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(turned.abs() > 30.0, "{stdout}");
}

#[cfg(unix)]
#[test]
fn check_over_a_pseudo_terminal() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let port = dir.path().join("coil-tty");
    let emu = Emulator::start("open-field", &["--port", port.to_str().unwrap()]);
    let out = host(&emu, "open-field", 2.0);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("coil serial"));
    let log = log_after_zero(&emu);
    assert!(any_nonzero(&log));
}

/// Runs one fault; returns (recovered, emulator log, host log).
fn fault_run(faults: &str, duration: f64) -> (bool, Vec<Event>, String) {
    let emu = Emulator::start("open-field", &["--faults", faults, "--seed", "3"]);
    let out = host(&emu, "open-field", duration);
    let recovered = recovered_or_stopped_cleanly(&out, &emu.host_log());
    let log = log_after_zero(&emu);
    (recovered, log, emu.host_log())
}

#[test]
fn dropped_frames_are_counted_and_the_run_goes_on() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let (recovered, log, host_log) = fault_run("drop=0.1", 2.0);
    assert!(recovered);
    assert!(log.iter().any(|e| e.name == "fault_drop"));
    assert!(
        host_log.contains("dropped before frame"),
        "the host did not notice the dropped frames"
    );
}

#[test]
fn slightly_delayed_frames_are_tolerated() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let (recovered, log, _) = fault_run("delay=0.1:30", 2.0);
    assert!(recovered);
    assert!(log.iter().any(|e| e.name == "fault_delay"));
}

#[test]
fn a_frame_later_than_the_timeout_stops_the_run() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let (recovered, _, host_log) = fault_run("delay=0.2:250", 4.0);
    assert!(
        !recovered,
        "a 250 ms gap must stop the run (frame timeout 100 ms)"
    );
    assert!(
        host_log.contains("no camera frame for 100 ms"),
        "{host_log}"
    );
}

#[test]
fn corrupted_bytes_are_resent_or_stop_cleanly() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let (_, log, host_log) = fault_run("corrupt=0.05", 2.0);
    assert!(log.iter().any(|e| e.name.starts_with("fault_corrupt")));
    assert!(
        log.iter()
            .any(|e| e.name == "bad_frame" || e.name == "currents_repeat"),
        "no corruption reached the protocol"
    );
    assert!(host_log.contains("tries"), "the host never resent");
}

#[test]
fn a_coil_disconnect_stops_the_run() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let (recovered, log, host_log) = fault_run("disconnect=1.0", 4.0);
    assert!(!recovered);
    assert!(log.iter().any(|e| e.name == "fault_disconnect"));
    assert!(host_log.contains("coil link lost"), "{host_log}");
}

#[test]
fn a_camera_disconnect_stops_the_run_and_zeroes_the_field() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let (recovered, log, host_log) = fault_run("disconnect=1.0:camera", 4.0);
    assert!(!recovered);
    let cut = log
        .iter()
        .position(|e| e.name == "fault_disconnect")
        .expect("cut logged");
    // after the cut the host received no frame: it answered at most the last one it had,
    // then zeroed the field over the coil link
    let after: Vec<&Event> = log[cut..]
        .iter()
        .filter(|e| matches!(e.name.as_str(), "currents" | "currents_repeat" | "zero"))
        .collect();
    let zero = after
        .iter()
        .position(|e| e.name == "zero")
        .unwrap_or_else(|| panic!("no ZERO from the host after the cut\n{host_log}"));
    assert!(
        zero <= 1,
        "the host kept commanding after the camera was cut: {after:?}"
    );
    assert!(host_log.contains("camera"), "{host_log}");
}

#[test]
fn a_short_stuck_camera_is_ridden_out() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let (recovered, _, host_log) = fault_run("stuck=0.5:0.2", 2.0);
    assert!(recovered);
    assert!(
        host_log.contains("stuck camera"),
        "the host did not notice the repeated frames"
    );
}

#[test]
fn a_long_stuck_camera_stops_the_run() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let (recovered, log, host_log) = fault_run("stuck=0.5:3", 4.0);
    assert!(!recovered);
    let start = log.iter().find(|e| e.name == "fault_stuck_start").unwrap();
    let zero = log
        .iter()
        .find(|e| e.t > start.t && e.name == "zero")
        .expect("a ZERO from the host");
    // 30 identical frames at 60 fps, plus a frame of slack
    assert!(
        zero.t - start.t < 31.0 / 60.0 + 0.05,
        "zeroed {} s after the camera stuck",
        zero.t - start.t
    );
    assert!(host_log.contains("camera stuck"), "{host_log}");
}

/// Kills (or freezes) the host mid-run; the emulator must zero its currents after the
/// watchdog timeout (200 ms) and log it.
fn silent_host(port: Option<&Path>, freeze: bool) {
    let mut args = vec![];
    if let Some(p) = port {
        args = vec!["--port", p.to_str().unwrap()];
    }
    let emu = Emulator::start("open-field", &args);
    let mut host = Command::new(BIN)
        .args(["rig", "check", "--rig"])
        .arg(emu.rig())
        .args(["open-field", "--duration", "60"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // let the host drive for a while (a few dozen commands), then silence it
    wait_for_host_driving(&emu);
    let pid = host.id().to_string();
    let signal = if freeze { "-STOP" } else { "-KILL" };
    assert!(
        Command::new("kill")
            .args([signal, &pid])
            .status()
            .unwrap()
            .success()
    );
    let log = wait_for_log(&emu, "a watchdog trip", |log| {
        log.iter().any(|e| e.name == "watchdog")
    });
    let _ = host.kill();
    let _ = host.wait();
    let wd = log.iter().find(|e| e.name == "watchdog").unwrap();
    assert!(wd.currents.iter().all(|c| *c == 0.0));
    // the last message from the host, and the silence before the trip. Both are stamped with
    // the emulator clock's reading the device judged them by (not when their lines were
    // written), so a loaded machine can lengthen the silence but never shorten it.
    let last_rx = log
        .iter()
        .rfind(|e| {
            e.clock < wd.clock
                && matches!(
                    e.name.as_str(),
                    "currents" | "heartbeat" | "zero" | "currents_repeat" | "hello" | "refused"
                )
        })
        .unwrap();
    // never before the watchdog time (200 ms) of silence
    let silence = wd.clock - last_rx.clock;
    assert!(
        silence >= 0.2,
        "watchdog tripped after only {silence} s of silence: {}",
        wd.detail
    );
    // the device sends nothing non-zero after the trip, and the plant comes to zero currents
    // (a frame stepped just before the trip may be logged after it with the currents then in
    // force, so wait for the plant rather than read the snapshot)
    assert!(
        log.iter()
            .filter(|e| e.clock > wd.clock && e.name == "currents")
            .all(|e| e.currents.iter().all(|c| *c == 0.0))
    );
    log_after_zero(&emu);
}

#[cfg(unix)]
#[test]
fn a_killed_host_leaves_the_device_zeroing_after_the_watchdog() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    silent_host(Some(&dir.path().join("coil-tty")), false);
}

#[cfg(unix)]
#[test]
fn a_frozen_host_on_tcp_trips_the_watchdog() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    silent_host(None, true);
}

/// Ctrl-C (a real SIGINT) mid-run: the host's handler raises the abort flag, the field is
/// zeroed by the host (its keep-alive thread, or the loop if it sees the flag first) and the run
/// ends as interrupted. Without the handler SIGINT would kill the host, and only the closed
/// connection would zero the currents, with no ZERO message and no stop in the host log.
#[cfg(unix)]
#[test]
fn ctrl_c_makes_the_host_zero_the_field() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let emu = Emulator::start("open-field", &[]);
    let host = Command::new(BIN)
        .args(["rig", "check", "--rig"])
        .arg(emu.rig())
        .args(["open-field", "--duration", "60", "--out"])
        .arg(emu.out())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_for_host_driving(&emu);
    let pid = host.id().to_string();
    assert!(
        Command::new("kill")
            .args(["-INT", &pid])
            .status()
            .unwrap()
            .success()
    );
    let out = wait_or_kill(host, Duration::from_secs(30));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("interrupted: zeroing the field and stopping"),
        "the handler did not run: {stderr}"
    );
    let last = stderr.lines().last().unwrap_or("");
    assert!(
        last.contains("interrupted") && last.ends_with("field zeroed"),
        "{stderr}"
    );
    // the host log: the interrupt as a fault, then the acknowledged stop
    let rows: Vec<String> = emu.host_log().lines().map(str::to_string).collect();
    let kind = |r: &str| r.split(',').nth(2).unwrap_or("").to_string();
    let fault = rows
        .iter()
        .position(|r| kind(r) == "fault" && r.contains("interrupted"))
        .unwrap_or_else(|| panic!("no interrupt in the host log: {rows:?}"));
    assert!(
        rows[fault..]
            .iter()
            .any(|r| kind(r) == "stop" && r.contains("field zeroed (acknowledged)")),
        "{rows:?}"
    );
    // the device saw ZERO after the last non-zero currents, and its currents are zero: the host
    // zeroed them, not the watchdog
    let log = log_after_zero(&emu);
    let last_on = log
        .iter()
        .rposition(|e| e.name == "currents" && e.currents.iter().any(|c| *c != 0.0))
        .unwrap();
    assert!(
        log[last_on..].iter().any(|e| e.name == "zero"),
        "no ZERO after the last currents: {:?}",
        &log[last_on..]
    );
    assert!(log.iter().all(|e| e.name != "watchdog"), "{log:?}");
}

/// The end-to-end run: `magbench rig run` on micro-factory against the emulator in its own
/// process, over loopback TCP. Lockstep, so machine load cannot starve the 60 fps loop and the
/// frames — so the observed start, and with it the plan — are the same every run (a start
/// 1e-4 BL away gives another plan).
#[test]
fn rig_run_on_micro_factory_reaches_the_goal_and_leaves_zero_currents() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let emu = Emulator::start("micro-factory", &["--seed", "1", "--duration", "3000"]);
    let child = Command::new(BIN)
        .args(["rig", "run", "--rig"])
        .arg(emu.rig())
        .args([
            "micro-factory",
            "--planner",
            "goal-zoom-rrt",
            "--tracker",
            "obc",
            "--json",
            "--out",
        ])
        .arg(emu.out())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let out = wait_or_kill(child, Duration::from_secs(900));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "rig run failed: {stderr}\n{stdout}");
    let v: serde_json::Value = serde_json::from_str(stdout.trim()).expect("one JSON object");
    println!("{v}");
    assert_eq!(v["reached_goal"], true, "{v}");
    assert_eq!(v["agent_contact"], false, "{v}");
    // a physical rig scores observed positions only: no true-position figure
    assert!(v["rms_error_true_bl"].is_null(), "{v}");
    assert!(v["rms_error_sync_bl"].as_f64().unwrap() >= 0.0, "{v}");
    // the same metrics.json as `magbench track` writes: the parameters too
    let metrics: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(emu.out().join("metrics.json")).unwrap())
            .unwrap();
    assert_eq!(metrics["params"]["hold"], 0.5, "{metrics}");
    for f in [
        "ticks.csv",
        "plans.json",
        "plan.json",
        "world.svg",
        "replay.html",
    ] {
        assert!(emu.out().join(f).is_file(), "{f} missing");
    }
    let log = log_after_zero(&emu);
    assert!(any_nonzero(&log));
    // the host logged every frame's observation and every command
    let host_log = emu.host_log();
    let frames = host_log
        .lines()
        .filter(|l| l.split(',').nth(2) == Some("observation"))
        .count();
    let commands = host_log
        .lines()
        .filter(|l| l.split(',').nth(2) == Some("command"))
        .count();
    assert!(
        frames > 100 && commands > 100,
        "{frames} observations, {commands} commands logged"
    );
}
