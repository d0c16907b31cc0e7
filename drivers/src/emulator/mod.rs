//! The rig emulator: the device side of a coil-and-camera rig, run as its own process by
//! `magbench rig emulate`.
//!
//! - [`device`]: the coil driver — protocol, acknowledgements, device limits, watchdog;
//! - [`io`]: its end of the link (TCP, or a pseudo-terminal the host opens as a serial port);
//! - the plant: env's [`Plant`] under the field the currents produce (never other physics);
//! - [`render`]: grey-level frames of the agents at the camera rate, streamed over TCP;
//! - [`faults`]: dropped, delayed, stuck frames, corrupted bytes, a disconnect;
//! - [`log`]: every event, flushed as it happens.

pub mod device;
pub mod faults;
pub mod io;
pub mod log;
pub mod render;

use std::net::{TcpListener, TcpStream};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use magbench_env::collision::CollisionWorld;
use magbench_env::plant::{DisturbancePreset, Plant};
use magbench_env::{Coil, Scenario, TriaxialMaxwell, Vec2};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use self::device::{DeviceEvent, DeviceState};
use self::faults::{Cut, FaultPlan, maybe_corrupt};
use self::io::DeviceIo;
use self::log::EventLog;
use self::render::{RenderParams, Renderer};
use crate::calibration::Calibration;
use crate::camera::FrameRecorder;
use crate::coil_driver::control_of_field;
use crate::frame::{Frame, encode_frame};
use crate::protocol::{Decoder, encode};
use crate::rigfile::RigConfig;

/// Where the emulated coil driver listens.
#[derive(Debug, Clone, PartialEq)]
pub enum DeviceEndpoint {
    /// A pseudo-terminal whose slave is linked at this path (the host opens it as a serial port).
    Pty(PathBuf),
    /// A TCP listen address (`127.0.0.1:0` picks a free port).
    Tcp(String),
}

/// Called once with the live endpoints (coil description, camera address).
pub type OnReady = Box<dyn FnOnce(&str, &str) + Send>;

/// Everything an emulator run needs.
pub struct EmulatorConfig {
    /// The rig being emulated (calibration, limits, camera size, pixel map).
    pub rig: RigConfig,
    /// World and start positions.
    pub scenario: Scenario,
    /// The coil link's endpoint.
    pub endpoint: DeviceEndpoint,
    /// The frame stream's TCP listen address.
    pub camera_listen: String,
    /// Faults to inject.
    pub faults: FaultPlan,
    /// Disturbances of the plant.
    pub preset: DisturbancePreset,
    /// How frames look.
    pub render: RenderParams,
    /// Seed of the plant, the renderer and the faults.
    pub seed: u64,
    /// Device time runs this many times faster than wall time (frames come faster; the
    /// watchdog stays in wall time).
    pub speed: f64,
    /// Lockstep: frames start once a host has said HELLO and connected its camera; after each
    /// frame, wait (up to 50 ms of wall time) for the host's command before advancing the plant
    /// one frame; device time is then frame count × period. Runs as fast as the host's loop, is
    /// immune to machine load and repeats exactly (frame noise depends on the frame index);
    /// `speed` is ignored.
    pub lockstep: bool,
    /// Stop after this much device time (s).
    pub duration: Option<f64>,
    /// The event log.
    pub log: PathBuf,
    /// Also write every frame (and the truth) here.
    pub record: Option<PathBuf>,
    /// Called once with the live endpoints (coil description, camera address) when ready.
    pub on_ready: OnReady,
}

/// The device clock: wall time since start, times `speed`; in lockstep, the time of the last
/// frame sent.
#[derive(Debug, Clone, Copy)]
struct Clock {
    start: Instant,
    speed: f64,
    virtual_t: Option<&'static AtomicU64>,
}

impl Clock {
    fn t(&self) -> f64 {
        match self.virtual_t {
            Some(v) => f64::from_bits(v.load(Ordering::Acquire)),
            None => self.start.elapsed().as_secs_f64() * self.speed,
        }
    }
    fn wall_of(&self, t: f64) -> Instant {
        self.start + Duration::from_secs_f64(t / self.speed)
    }
}

struct Shared {
    device: DeviceState,
    /// (device time, currents) at each change, consumed by the plant.
    changes: Vec<(f64, Vec<f64>)>,
    /// Device time of the first HELLO: fault times count from here.
    hello_t: Option<f64>,
    /// Current-setting messages (SET_CURRENTS, ZERO) handled so far.
    commands: u64,
}

/// Runs the emulator until `duration` passes or `stop` is set.
pub fn run(cfg: EmulatorConfig, stop: Arc<AtomicBool>) -> Result<(), String> {
    if !(cfg.speed.is_finite() && cfg.speed > 0.0) {
        return Err(format!("speed must be > 0, got {}", cfg.speed));
    }
    let start = Instant::now();
    // one emulator per process: the lockstep clock lives as long as the process
    let virtual_t: Option<&'static AtomicU64> = cfg
        .lockstep
        .then(|| &*Box::leak(Box::new(AtomicU64::new(0))));
    let clock = Clock {
        start,
        speed: if cfg.lockstep { 1.0 } else { cfg.speed },
        virtual_t,
    };
    let log = Arc::new(
        EventLog::create(&cfg.log, start).map_err(|e| format!("{}: {e}", cfg.log.display()))?,
    );
    let device_limits: Vec<f64> = cfg
        .rig
        .coil
        .current_limit_a
        .iter()
        .map(|l| l * 1.05)
        .collect();
    let shared = Arc::new(Mutex::new(Shared {
        device: DeviceState::new(
            device_limits,
            Duration::from_millis(cfg.rig.coil.watchdog_ms as u64),
            start,
        ),
        changes: Vec::new(),
        hello_t: None,
        commands: 0,
    }));

    // the camera's frame stream
    let cam_listener = TcpListener::bind(&cfg.camera_listen)
        .map_err(|e| format!("camera listen {}: {e}", cfg.camera_listen))?;
    let cam_addr = cam_listener
        .local_addr()
        .map_err(|e| e.to_string())?
        .to_string();
    let cam_client: Arc<Mutex<Option<TcpStream>>> = Arc::new(Mutex::new(None));
    {
        let (client, stop, log) = (cam_client.clone(), stop.clone(), log.clone());
        cam_listener
            .set_nonblocking(true)
            .map_err(|e| e.to_string())?;
        std::thread::spawn(move || {
            while !stop.load(Ordering::Relaxed) {
                match cam_listener.accept() {
                    Ok((s, peer)) => {
                        let _ = s.set_nonblocking(false);
                        let _ = s.set_nodelay(true);
                        let _ = s.set_write_timeout(Some(Duration::from_millis(500)));
                        log.event(
                            clock.t(),
                            "camera_connect",
                            None,
                            &[],
                            &[],
                            &peer.to_string(),
                        );
                        *client.lock().unwrap() = Some(s);
                    }
                    Err(_) => std::thread::sleep(Duration::from_millis(5)),
                }
            }
        });
    }

    // the coil driver
    let coil_desc = match &cfg.endpoint {
        DeviceEndpoint::Tcp(addr) => {
            let l = TcpListener::bind(addr).map_err(|e| format!("coil listen {addr}: {e}"))?;
            let desc = l.local_addr().map_err(|e| e.to_string())?.to_string();
            l.set_nonblocking(true).map_err(|e| e.to_string())?;
            let (shared, stop, log, faults, seed) = (
                shared.clone(),
                stop.clone(),
                log.clone(),
                cfg.faults.clone(),
                cfg.seed,
            );
            std::thread::spawn(move || {
                let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0xFA_0175);
                let mut cut = false;
                while !stop.load(Ordering::Relaxed) {
                    watchdog(&shared, &log, clock);
                    match l.accept() {
                        Ok((s, peer)) => {
                            if cut {
                                continue; // the cable stays cut
                            }
                            let _ = s.set_nonblocking(false);
                            let _ = s.set_nodelay(true);
                            log.event(clock.t(), "coil_connect", None, &[], &[], &peer.to_string());
                            let mut s = s;
                            cut = serve(&mut s, &shared, &log, clock, &faults, &mut rng, &stop);
                        }
                        Err(_) => std::thread::sleep(Duration::from_millis(2)),
                    }
                }
            });
            format!("tcp {desc}")
        }
        #[cfg(unix)]
        DeviceEndpoint::Pty(link) => {
            let mut pty =
                io::pty::Pty::open(link).map_err(|e| format!("pty {}: {e}", link.display()))?;
            let (shared, stop, log, faults, seed) = (
                shared.clone(),
                stop.clone(),
                log.clone(),
                cfg.faults.clone(),
                cfg.seed,
            );
            std::thread::spawn(move || {
                let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0xFA_0175);
                log.event(clock.t(), "coil_open", None, &[], &[], "pty");
                serve(&mut pty, &shared, &log, clock, &faults, &mut rng, &stop);
                // a cut pty: dropping it closes the master; keep the watchdog honest meanwhile
                drop(pty);
                while !stop.load(Ordering::Relaxed) {
                    std::thread::sleep(Duration::from_millis(5));
                }
            });
            format!("serial {}", link.display())
        }
        #[cfg(not(unix))]
        DeviceEndpoint::Pty(_) => return Err("pseudo-terminals need a Unix system".into()),
    };

    // the plant and the camera
    let scenario = &cfg.scenario;
    let p = &scenario.physics;
    let coil: Arc<dyn Coil> = Arc::new(TriaxialMaxwell::new(p.gradient_limit()));
    let collision = Arc::new(CollisionWorld::new(&scenario.world, 0.5));
    let mut plant = Plant::new(p, coil, collision, &cfg.preset, cfg.seed, &scenario.start);
    let field_on = 0.5 * cfg.rig.coil.field_mt.unwrap_or(p.field_mt) * 1e-3;
    let calibration: Calibration = cfg.rig.coil.calibration.clone();
    let renderer = Renderer::new(
        cfg.rig.pixels.clone(),
        cfg.rig.camera.size_px,
        Some(&scenario.world),
        cfg.render.clone(),
        cfg.seed,
    );
    let mut recorder = match &cfg.record {
        Some(dir) => Some(
            FrameRecorder::create(dir, scenario.agents())
                .map_err(|e| format!("{}: {e}", dir.display()))?,
        ),
        None => None,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(cfg.seed ^ 0xF4A3E5);
    log.event(
        0.0,
        "start",
        None,
        &vec![0.0; calibration.channels()],
        &scenario.start,
        &format!(
            "scenario {} preset {} speed {}",
            scenario.name, cfg.preset.name, cfg.speed
        ),
    );
    (cfg.on_ready)(&coil_desc, &cam_addr);

    let period = 1.0 / cfg.rig.camera.fps;
    let mut in_force = vec![0.0; calibration.channels()];
    let mut t_prev = 0.0;
    let mut stuck_frame: Option<image::GrayImage> = None;
    let mut was_stuck = false;
    let mut camera_cut = false;
    let mut commands_at_frame = 0;
    if clock.virtual_t.is_some() {
        // lockstep: frame 1 goes to a host with an open session and a connected camera, so
        // that a run sees the same frames whatever the timing
        while !stop.load(Ordering::Relaxed)
            && (shared.lock().unwrap().hello_t.is_none() || cam_client.lock().unwrap().is_none())
        {
            std::thread::sleep(Duration::from_millis(2));
        }
    }
    for k in 1u64.. {
        if stop.load(Ordering::Relaxed) {
            break;
        }
        let t = k as f64 * period;
        if cfg.duration.is_some_and(|d| t > d) {
            break;
        }
        if let Some(v) = clock.virtual_t {
            // lockstep: the host's answer to the last frame, or 50 ms
            let deadline = Instant::now() + Duration::from_millis(50);
            while shared.lock().unwrap().commands == commands_at_frame && Instant::now() < deadline
            {
                std::thread::sleep(Duration::from_micros(100));
            }
            let _ = v;
        } else {
            let wake = clock.wall_of(t);
            let now = Instant::now();
            if wake > now {
                std::thread::sleep(wake - now);
            }
        }
        // integrate the plant piecewise under the currents in force
        let changes = std::mem::take(&mut shared.lock().unwrap().changes);
        let mut seg_start = t_prev;
        let advance = |plant: &mut Plant, cur: &[f64], a: f64, b: f64| {
            if b > a {
                let (u, field) = control_of_field(&calibration.field(cur));
                if field >= field_on {
                    plant.run(&u, b - a);
                }
            }
        };
        for (tc, cur) in changes {
            let tc = tc.clamp(seg_start, t);
            advance(&mut plant, &in_force, seg_start, tc);
            seg_start = tc;
            in_force = cur;
        }
        advance(&mut plant, &in_force, seg_start, t);
        t_prev = t;
        if let Some(v) = clock.virtual_t {
            v.store(t.to_bits(), Ordering::Release);
        }
        let truth: Vec<Vec2> = plant.positions().to_vec();
        if plant.stuck() {
            log.event(
                t,
                "agents_stuck",
                None,
                &in_force,
                &truth,
                "the agents touched and stuck",
            );
        }
        // the frame, and its faults (fault times count from the host's HELLO)
        let since_hello = shared.lock().unwrap().hello_t.map(|h| t - h);
        let stuck = since_hello.is_some_and(|s| cfg.faults.stuck_at(s));
        let image = match (&stuck_frame, stuck) {
            (Some(img), true) => img.clone(),
            _ => renderer.render_frame(&truth, k),
        };
        if stuck && !was_stuck {
            stuck_frame = Some(image.clone());
            log.event(
                t,
                "fault_stuck_start",
                None,
                &in_force,
                &truth,
                "the camera repeats this frame",
            );
        }
        if !stuck && was_stuck {
            stuck_frame = None;
            log.event(t, "fault_stuck_end", None, &in_force, &truth, "");
        }
        was_stuck = stuck;
        let frame = Frame {
            index: k,
            t,
            image,
            received: Instant::now(),
        };
        log.event(t, "frame", None, &in_force, &truth, &format!("index {k}"));
        if let Some(r) = recorder.as_mut() {
            r.write(&frame, &truth)
                .map_err(|e| format!("recording: {e}"))?;
        }
        if let Some((tc, Cut::Camera)) = cfg.faults.disconnect
            && since_hello.is_some_and(|s| s >= tc)
            && !camera_cut
        {
            camera_cut = true;
            *cam_client.lock().unwrap() = None;
            log.event(
                t,
                "fault_disconnect",
                None,
                &in_force,
                &[],
                "camera stream cut",
            );
        }
        if camera_cut {
            continue;
        }
        if cfg.faults.drop > 0.0 && rng.random::<f64>() < cfg.faults.drop {
            log.event(
                t,
                "fault_drop",
                None,
                &in_force,
                &[],
                &format!("frame {k} dropped"),
            );
            continue;
        }
        if let Some((p, ms)) = cfg.faults.delay
            && rng.random::<f64>() < p
        {
            log.event(
                t,
                "fault_delay",
                None,
                &in_force,
                &[],
                &format!("frame {k} delayed {ms} ms"),
            );
            std::thread::sleep(Duration::from_secs_f64(ms * 1e-3));
        }
        let bytes = encode_frame(&frame);
        commands_at_frame = shared.lock().unwrap().commands;
        let mut client = cam_client.lock().unwrap();
        if let Some(s) = client.as_mut() {
            use std::io::Write;
            if let Err(e) = s.write_all(&bytes) {
                log.event(t, "camera_disconnect", None, &in_force, &[], &e.to_string());
                *client = None;
            }
        }
    }
    // leave the device safe
    stop.store(true, Ordering::Relaxed);
    let mut sh = shared.lock().unwrap();
    sh.device.zero();
    log.event(
        clock.t(),
        "end",
        None,
        sh.device.currents(),
        plant.positions(),
        "emulator stopped; currents zero",
    );
    Ok(())
}

/// Trips the watchdog if the host has been silent too long.
fn watchdog(shared: &Mutex<Shared>, log: &EventLog, clock: Clock) {
    let mut sh = shared.lock().unwrap();
    if sh.device.check_watchdog(Instant::now()) {
        let t = clock.t();
        let silent = sh
            .device
            .last_rx()
            .map(|r| r.elapsed().as_secs_f64() * 1e3)
            .unwrap_or(0.0);
        let cur = sh.device.currents().to_vec();
        sh.changes.push((t, cur.clone()));
        log.event(
            t,
            "watchdog",
            None,
            &cur,
            &[],
            &format!(
                "no message for {silent:.0} ms (timeout {} ms): currents zeroed",
                sh.device.watchdog().as_millis()
            ),
        );
    }
}

/// Serves one host connection until it closes or the link is cut; returns true when cut.
fn serve(
    io: &mut dyn DeviceIo,
    shared: &Mutex<Shared>,
    log: &EventLog,
    clock: Clock,
    faults: &FaultPlan,
    rng: &mut ChaCha8Rng,
    stop: &AtomicBool,
) -> bool {
    let mut dec = Decoder::new();
    let mut buf = [0u8; 512];
    let mut idle = Duration::ZERO;
    let zero_on = |why: &str| {
        let mut sh = shared.lock().unwrap();
        sh.device.zero();
        let cur = sh.device.currents().to_vec();
        sh.changes.push((clock.t(), cur.clone()));
        log.event(clock.t(), why, None, &cur, &[], "currents zeroed");
    };
    while !stop.load(Ordering::Relaxed) {
        watchdog(shared, log, clock);
        let since_hello = shared.lock().unwrap().hello_t.map(|h| clock.t() - h);
        if let Some((tc, Cut::Coil)) = faults.disconnect
            && since_hello.is_some_and(|s| s >= tc)
        {
            zero_on("fault_disconnect");
            return true;
        }
        let n = match io.read_timeout(&mut buf, Duration::from_millis(2)) {
            Ok(None) => {
                idle += Duration::from_millis(2);
                if idle >= Duration::from_millis(4) && dec.pending() > 0 {
                    dec.drop_stalled();
                }
                continue;
            }
            Ok(Some(0)) => {
                zero_on("coil_disconnect");
                return false;
            }
            Ok(Some(n)) => n,
            Err(e) => {
                zero_on(&format!("coil_error {e}"));
                return false;
            }
        };
        idle = Duration::ZERO;
        let chunk = &mut buf[..n];
        if maybe_corrupt(chunk, faults.corrupt, rng) {
            log.event(
                clock.t(),
                "fault_corrupt_rx",
                None,
                &[],
                &[],
                "one received byte flipped",
            );
        }
        dec.feed(chunk);
        while let Some(d) = dec.next_frame() {
            let now = Instant::now();
            let t = clock.t();
            let (reply, seq, cur, event) = {
                let mut sh = shared.lock().unwrap();
                let seq = match &d {
                    crate::protocol::Decoded::Message { seq, .. }
                    | crate::protocol::Decoded::Invalid { seq, .. } => Some(*seq),
                    _ => None,
                };
                let before = sh.device.currents().to_vec();
                let (reply, event) = sh.device.handle(d, now);
                let cur = sh.device.currents().to_vec();
                if cur != before {
                    sh.changes.push((t, cur.clone()));
                }
                if matches!(
                    event,
                    DeviceEvent::Currents | DeviceEvent::Duplicate | DeviceEvent::Zero
                ) {
                    sh.commands += 1;
                }
                if matches!(event, DeviceEvent::Hello { .. }) && sh.hello_t.is_none() {
                    sh.hello_t = Some(t);
                }
                (reply, seq, cur, event)
            };
            let (name, detail) = match &event {
                DeviceEvent::Hello { watchdog_ms } => {
                    ("hello", format!("watchdog {watchdog_ms} ms"))
                }
                DeviceEvent::Currents => ("currents", String::new()),
                DeviceEvent::Duplicate => ("currents_repeat", String::new()),
                DeviceEvent::Heartbeat => ("heartbeat", String::new()),
                DeviceEvent::Zero => ("zero", String::new()),
                DeviceEvent::Refused(s) => ("refused", format!("{s:?}")),
                DeviceEvent::BadFrame => ("bad_frame", "checksum failed: NAK".into()),
            };
            log.event(t, name, seq, &cur, &[], &detail);
            let mut bytes = encode(seq.unwrap_or(0), &reply);
            if maybe_corrupt(&mut bytes, faults.corrupt, rng) {
                log.event(
                    t,
                    "fault_corrupt_tx",
                    seq,
                    &cur,
                    &[],
                    "one reply byte flipped",
                );
            }
            if let Err(e) = io.send(&bytes) {
                zero_on(&format!("coil_error {e}"));
                return false;
            }
        }
    }
    false
}
