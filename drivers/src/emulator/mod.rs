//! The rig emulator: the device side of a coil-and-camera rig, run as its own process by
//! `magbench rig emulate`.
//!
//! It is built from parts, which [`run`] wires together and then drives frame by frame:
//!
//! - [`clock`]: the device clock (real time × speed, or lockstep with the host);
//! - [`coil`]: the coil server — [`device`] (protocol, acknowledgements, limits, watchdog) on
//!   any transport of [`io`] (TCP, or a pseudo-terminal the host opens as a serial port);
//! - [`plant`]: the plant stepper — env's [`Plant`] under the field the currents produce
//!   (never other physics);
//! - [`render`] and [`camera`]: grey-level frames of the agents at the camera rate, and the
//!   server that streams them over TCP;
//! - [`faults`]: the fault injector — dropped, delayed, stuck frames, corrupted bytes, a
//!   disconnect;
//! - [`log`]: every event, flushed as it happens.

pub mod camera;
pub mod clock;
pub mod coil;
pub mod device;
pub mod error;
pub mod faults;
pub mod io;
pub mod log;
pub mod plant;
pub mod render;

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use magbench_env::plant::{Camera, CameraParams, DisturbancePreset, Plant};
use magbench_env::{Coil, Scenario, TriaxialMaxwell};

use self::camera::CameraServer;
use self::clock::DeviceClock;
use self::coil::{CoilServer, DeviceShared, Shared, TcpTransport, lock};
use self::device::DeviceState;
pub use self::error::EmulatorError;
use self::faults::{Delivery, FaultInjector, FaultPlan};
use self::log::EventLog;
pub use self::log::OnEvent;
use self::plant::PlantStepper;
use self::render::{RenderParams, Renderer};
use crate::camera::FrameRecorder;
use crate::clock::Clock;
use crate::frame::{Frame, encode_frame};
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
    /// Frames show the agents as the preset's camera model sees them ([`seen_by`]): late by
    /// its latency, displaced by its detection noise and bias; the detector's own pixel error
    /// comes on top. Off: frames show the true positions.
    pub preset_camera: bool,
    /// Seed of the plant, the renderer and the faults.
    pub seed: u64,
    /// The clock of the device (its watchdog and its frame pacing): the wall clock on a
    /// bench, a [`crate::clock::ManualClock`] in a test.
    pub clock: Arc<dyn Clock>,
    /// Device time runs this many times faster than wall time (frames come faster; the
    /// watchdog stays in wall time).
    pub speed: f64,
    /// Lockstep: frames start once a host has said HELLO and connected its camera; after each
    /// frame, wait (up to 50 ms of wall time) for the host's command before advancing the plant
    /// one frame; device time is then frame count × period. When the host closes its link,
    /// frames (and the plant) pause until the next host has said HELLO and connected its
    /// camera, so that hosts run one after another see the same frames whatever the time
    /// between them. Runs as fast as the host's loop, is immune to machine load and repeats
    /// exactly (frame noise depends on the frame index); `speed` is ignored.
    pub lockstep: bool,
    /// Stop after this much device time (s).
    pub duration: Option<f64>,
    /// The event log.
    pub log: PathBuf,
    /// Also write every frame (and the truth) here.
    pub record: Option<PathBuf>,
    /// Called once with the live endpoints (coil description, camera address) when ready.
    pub on_ready: OnReady,
    /// Called after each event is written to the log, with its name: a test or a tool waits
    /// for the device's events on it instead of polling the log file.
    pub on_event: Option<OnEvent>,
}

/// Runs the emulator until `duration` passes or `stop` is set.
pub fn run(cfg: EmulatorConfig, stop: Arc<AtomicBool>) -> Result<(), EmulatorError> {
    let mut emu = Emulator::start(cfg, &stop)?;
    emu.wait_for_host(&stop);
    let mut result = Ok(());
    for k in 1u64.. {
        if stop.load(Ordering::Relaxed) || !emu.within_duration(k) {
            break;
        }
        if let Err(e) = emu.frame(k, &stop) {
            result = Err(e);
            break;
        }
    }
    // leave the device safe, whatever ended the run
    stop.store(true, Ordering::Relaxed);
    emu.finish();
    result
}

/// The parts of a running emulator, wired together.
struct Emulator {
    clock: Arc<DeviceClock>,
    log: Arc<EventLog>,
    shared: Shared,
    camera: CameraServer,
    plant: PlantStepper,
    renderer: Renderer,
    /// The preset's camera model, when frames show what it sees.
    seen: Option<Camera>,
    recorder: Option<FrameRecorder>,
    faults: FaultInjector,
    period: f64,
    duration: Option<f64>,
    /// Commands handled when the last frame went out (lockstep waits for the next); `None`
    /// before the first frame of a host's session, which goes out at once.
    commands_at_frame: Option<u64>,
    /// Lockstep: the host session frames go to (0 before the first), and the camera
    /// connection of that session (the number the camera server gave it).
    session: (u64, u64),
}

impl Emulator {
    /// Starts every part: the clock, the log, the camera server, the coil server on its
    /// transport (a thread each), the plant stepper, the renderer and the fault injector; then
    /// reports the live endpoints.
    fn start(cfg: EmulatorConfig, stop: &Arc<AtomicBool>) -> Result<Self, EmulatorError> {
        if !(cfg.speed.is_finite() && cfg.speed > 0.0) {
            return Err(EmulatorError::Speed(cfg.speed));
        }
        let clock = Arc::new(if cfg.lockstep {
            DeviceClock::lockstep(cfg.clock.clone())
        } else {
            DeviceClock::real_time(cfg.clock.clone(), cfg.speed)
        });
        let log = Arc::new(
            EventLog::create(&cfg.log, cfg.clock.clone())
                .map_err(|e| EmulatorError::io(cfg.log.display().to_string(), e))?
                .observed(cfg.on_event.clone()),
        );
        let shared: Shared = Arc::new(Mutex::new(DeviceShared {
            device: DeviceState::new(
                cfg.rig
                    .coil
                    .current_limit_a
                    .iter()
                    .map(|l| l * 1.05)
                    .collect(),
                Duration::from_millis(cfg.rig.coil.watchdog_ms as u64),
            ),
            changes: Vec::new(),
            hello_t: None,
            commands: 0,
            session_open: false,
            sessions: 0,
        }));
        let camera =
            CameraServer::start(&cfg.camera_listen, stop.clone(), log.clone(), clock.clone())?;
        let coil = CoilServer {
            shared: shared.clone(),
            log: log.clone(),
            clock: clock.clone(),
            faults: cfg.faults.clone(),
            seed: cfg.seed,
            stop: stop.clone(),
        };
        let coil_desc = match &cfg.endpoint {
            DeviceEndpoint::Tcp(addr) => {
                let (transport, bound) = TcpTransport::bind(addr)?;
                coil.spawn(transport);
                format!("tcp {bound}")
            }
            #[cfg(unix)]
            DeviceEndpoint::Pty(link) => {
                coil.spawn(coil::PtyTransport::open(link)?);
                format!("serial {}", link.display())
            }
            #[cfg(not(unix))]
            DeviceEndpoint::Pty(_) => return Err(EmulatorError::NoPty),
        };
        let scenario = &cfg.scenario;
        let p = &scenario.physics;
        // the emulated coil tilts the field no further than its rig file says
        let coil_model: Arc<dyn Coil> = Arc::new(
            TriaxialMaxwell::new(p.gradient_limit()).with_alpha_max_deg(cfg.rig.coil.alpha_max_deg),
        );
        let plant = PlantStepper::new(
            Plant::in_world(
                p,
                coil_model,
                &scenario.world,
                &emulated_preset(scenario, &cfg.preset),
                cfg.seed,
                &scenario.start,
            ),
            cfg.rig.coil.calibration.clone(),
            0.5 * cfg.rig.coil.field_mt.unwrap_or(p.field_mt) * 1e-3,
        );
        let renderer = Renderer::new(
            cfg.rig.pixels.clone(),
            cfg.rig.camera.size_px,
            Some(&scenario.world),
            cfg.render.clone(),
            cfg.seed,
        );
        let recorder = match &cfg.record {
            Some(dir) => Some(
                FrameRecorder::create(dir, scenario.agents())
                    .map_err(|e| EmulatorError::io(dir.display().to_string(), e))?,
            ),
            None => None,
        };
        log.event(
            0.0,
            "start",
            None,
            plant.in_force(),
            &scenario.start,
            &format!(
                "scenario {} preset {} speed {}",
                scenario.name, cfg.preset.name, cfg.speed
            ),
        );
        (cfg.on_ready)(&coil_desc, camera.addr());
        Ok(Self {
            clock,
            log,
            shared,
            camera,
            plant,
            renderer,
            seen: cfg
                .preset_camera
                .then(|| seen_by(&cfg.preset.camera, cfg.seed)),
            recorder,
            faults: FaultInjector::new(cfg.faults.clone(), cfg.seed),
            period: 1.0 / cfg.rig.camera.fps,
            duration: cfg.duration,
            commands_at_frame: None,
            session: (0, 0),
        })
    }

    /// Lockstep: the next frame goes to a host with an open session and a connected camera,
    /// so that a run sees the same frames whatever the timing: before frame 1, and whenever the
    /// host of the last frames has closed its link. The camera stream of a session that ended
    /// is cut, unless a newer host has connected its camera already; the frames wait for the
    /// new session's camera.
    fn wait_for_host(&mut self, stop: &AtomicBool) {
        if !self.clock.is_lockstep() {
            return;
        }
        let (session, camera) = self.session;
        if lock(&self.shared).in_session(session) {
            return;
        }
        self.camera.cut_unless_newer(camera);
        loop {
            if stop.load(Ordering::Relaxed) {
                return;
            }
            let sessions = {
                let sh = lock(&self.shared);
                sh.session_open.then_some(sh.sessions)
            };
            let accepted = self.camera.accepted();
            if let Some(s) = sessions
                && accepted > camera
                && self.camera.connected()
            {
                self.session = (s, accepted);
                self.commands_at_frame = None;
                return;
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    /// Frame `k` is within the run's duration.
    fn within_duration(&self, k: u64) -> bool {
        self.duration.is_none_or(|d| k as f64 * self.period <= d)
    }

    /// Frame `k`: wait for its time, step the plant to it, render it, inject its faults and
    /// send it.
    fn frame(&mut self, k: u64, stop: &AtomicBool) -> Result<(), EmulatorError> {
        let t = k as f64 * self.period;
        // lockstep: the host commands handled when the frame before went out; this frame is
        // stepped with the changes up to the host's answer to it (`None`: every change)
        let mut before = None;
        if self.clock.is_lockstep() {
            // the host's answer to the last frame, its link closed, or 50 ms
            if let Some(at_frame) = self.commands_at_frame {
                let session = self.session.0;
                self.clock.wait_for_host(
                    || {
                        let sh = lock(&self.shared);
                        sh.commands != at_frame || !sh.in_session(session)
                    },
                    stop,
                );
                before = Some(at_frame);
            }
            // a frame the host answered belongs to its session, even if the host has left
            if before.is_none_or(|a| lock(&self.shared).commands == a) {
                self.wait_for_host(stop);
                if self.commands_at_frame.is_none() {
                    // a new session's first frame: every change so far
                    before = None;
                }
            }
        } else {
            self.clock.wait_until(t, stop);
        }
        let changes = {
            let mut sh = lock(&self.shared);
            match before {
                Some(a) => {
                    let (now, later) = std::mem::take(&mut sh.changes)
                        .into_iter()
                        .partition(|c| c.commands_before <= a);
                    sh.changes = later;
                    now
                }
                None => std::mem::take(&mut sh.changes),
            }
        };
        self.plant.advance_to(t, changes);
        self.clock.frame_sent(t);
        let truth = self.plant.positions().to_vec();
        let in_force = self.plant.in_force().to_vec();
        let log = &*self.log;
        if self.plant.stuck() {
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
        let since_hello = lock(&self.shared).hello_t.map(|h| t - h);
        let drawn = match self.seen.as_mut() {
            Some(cam) => cam
                .capture(t, &truth)
                .map(|o| {
                    o.agents
                        .iter()
                        .zip(&truth)
                        .map(|(s, p)| s.unwrap_or(*p))
                        .collect()
                })
                .unwrap_or_else(|| truth.clone()),
            None => truth.clone(),
        };
        let renderer = &self.renderer;
        let image = self.faults.image(
            t,
            since_hello,
            || renderer.render_frame(&drawn, k),
            (log, &in_force, &truth),
        );
        let frame = Frame {
            index: k,
            t,
            image,
            received: Instant::now(),
        };
        let detail = if self.clock.is_lockstep() {
            format!("index {k} session {}", self.session.0)
        } else {
            format!("index {k}")
        };
        log.event(t, "frame", None, &in_force, &truth, &detail);
        if let Some(r) = self.recorder.as_mut() {
            r.write(&frame, &truth)
                .map_err(|e| EmulatorError::io("recording", e))?;
        }
        let camera = &self.camera;
        match self
            .faults
            .delivery(k, t, since_hello, || camera.cut(), (log, &in_force))
        {
            Delivery::Withhold => return Ok(()),
            Delivery::Delay(ms) => std::thread::sleep(Duration::from_secs_f64(ms * 1e-3)),
            Delivery::Send => {}
        }
        let bytes = encode_frame(&frame);
        self.commands_at_frame = Some(lock(&self.shared).commands);
        // lockstep: only to the camera of the frame's session, never a newer host's
        let to = self.clock.is_lockstep().then_some(self.session.1);
        self.camera.send(&bytes, to, t, &in_force, log);
        Ok(())
    }

    /// Zeroes the device and logs the end.
    fn finish(&self) {
        let mut sh = lock(&self.shared);
        sh.device.zero();
        self.log.event(
            self.clock.t(),
            "end",
            None,
            sh.device.currents(),
            self.plant.positions(),
            "emulator stopped; currents zero",
        );
    }
}

/// The camera model of `params` that an emulated frame shows: its latency and detection noise
/// and bias; misses and swaps are left to the detector on the rendered frame.
pub fn seen_by(params: &CameraParams, seed: u64) -> Camera {
    let mut p = params.clone();
    p.misses.enabled = false;
    p.swaps.enabled = false;
    Camera::new(p, seed)
}

/// The preset the emulated coil and agents follow: `preset` with the scenario's medium, and
/// without the preset's slew limits. The host's coil driver already limits every current's
/// rate to the rig file's `slew_a_per_s` (the amplifier's V/L, the same physics), so a second
/// slew limit in the plant would count it twice; the coil's first-order lag (L/R) stays.
pub fn emulated_preset(
    scenario: &magbench_env::Scenario,
    preset: &DisturbancePreset,
) -> DisturbancePreset {
    let mut p = scenario.plant_preset(preset);
    p.coil_lag.field_slew_mt_per_s = 0.0;
    p.coil_lag.gradient_slew_mt_per_m_per_s = 0.0;
    p
}
