//! The hardware rig: coil session + camera + detector, observed and commanded frame by frame.
//!
//! Every exit path leaves the field at zero: [`HardwareRig::stop`] (idempotent), any error
//! (the rig zeroes before returning it), `Drop` (so a panic unwinding through the loop zeroes
//! too), Ctrl-C (the abort flag makes the keep-alive thread zero at once), a stalled loop (the
//! host hold timeout) and a dead host (the device watchdog).

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use magbench_env::plant::Observation;
use magbench_env::{Control, Vec2};

use crate::camera::{self, Camera, CameraError};
use crate::coil_session::CoilSession;
use crate::detector::Detector;
use crate::link::LinkError;
use crate::rig_log::RigLog;
use crate::rigfile::RigConfig;

/// Why the hardware rig stopped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HardwareError {
    /// The coil link failed (the field was zeroed if the link still answered).
    #[error("{0}; field zeroed")]
    Coil(#[from] LinkError),
    /// The camera failed.
    #[error("{0}; field zeroed")]
    Camera(#[from] CameraError),
    /// The camera kept delivering the same frame.
    #[error("camera stuck: {0} identical frames in a row; field zeroed")]
    Stuck(u32),
    /// The device or the host safety checks zeroed the field under the loop.
    #[error("{0}; field zeroed")]
    Safety(String),
    /// The Ctrl-C handler could not be installed, so the rig was not opened.
    #[error("{0}; the rig was not opened")]
    Interrupt(#[from] crate::interrupt::InterruptError),
}

/// Counters of one run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RigStats {
    /// Frames received.
    pub frames: u64,
    /// Frames the source never delivered (gaps in the frame index).
    pub dropped_frames: u64,
    /// Frames received but skipped because the host was busy (e.g. planning); the newest wins.
    pub skipped_frames: u64,
    /// Frames that repeated the previous one (stuck camera).
    pub stuck_frames: u64,
    /// Agent detections missing.
    pub missed_detections: u64,
    /// Commands sent.
    pub commands: u64,
    /// Commands clamped by the current or slew limit.
    pub clamped_commands: u64,
    /// Faults logged.
    pub faults: u64,
    /// Frame arrival to command sent, per command that followed a frame (ms).
    pub latencies_ms: Vec<f64>,
}

/// A rig of real (or emulated) hardware.
pub struct HardwareRig {
    coil: CoilSession,
    camera: Box<dyn Camera>,
    detector: Detector,
    period: f64,
    frame_timeout: Duration,
    stuck_limit: u32,
    last_index: Option<u64>,
    last_hash: Option<u32>,
    stuck_run: u32,
    arrival: Option<(Instant, u64, f64)>,
    last_command: Option<f64>,
    t_origin: Option<f64>,
    stats: RigStats,
    log: Option<RigLog>,
    stopped: bool,
    latency: f64,
    corrupt_seen: u64,
    skipped_seen: u64,
}

impl HardwareRig {
    /// Opens the rig: the coil link (HELLO, zero), the camera and a detector primed with the
    /// agents' expected positions (BL). `field_mt` is the field magnitude; `abort` (Ctrl-C)
    /// zeroes the field from the keep-alive thread. `log` receives every observation,
    /// command and fault.
    pub fn open(
        rig: &RigConfig,
        field_mt: f64,
        prior: &[Vec2],
        abort: Arc<AtomicBool>,
        log: Option<&Path>,
    ) -> Result<Self, HardwareError> {
        Self::open_with_clock(rig, field_mt, prior, abort, log, crate::clock::wall())
    }

    /// [`HardwareRig::open`] with the clock of the safety timers (hold timeout, heartbeat)
    /// given: a test injects a [`crate::clock::ManualClock`].
    pub fn open_with_clock(
        rig: &RigConfig,
        field_mt: f64,
        prior: &[Vec2],
        abort: Arc<AtomicBool>,
        log: Option<&Path>,
        clock: Arc<dyn crate::clock::Clock>,
    ) -> Result<Self, HardwareError> {
        let coil = CoilSession::open(&rig.coil, field_mt, abort, clock)?;
        let camera = camera::open(&rig.camera)?;
        let start = Instant::now();
        let log = match log {
            Some(p) => Some(
                RigLog::create(p, prior.len(), start)
                    .map_err(|e| HardwareError::Safety(format!("{}: {e}", p.display())))?,
            ),
            None => None,
        };
        Ok(Self {
            coil,
            camera,
            detector: Detector::new(rig.detector.clone(), rig.pixels.clone(), prior),
            period: 1.0 / rig.camera.fps,
            frame_timeout: Duration::from_millis(rig.camera.frame_timeout_ms as u64),
            stuck_limit: rig.camera.stuck_frames,
            last_index: None,
            last_hash: None,
            stuck_run: 0,
            arrival: None,
            last_command: None,
            t_origin: None,
            stats: RigStats::default(),
            log,
            stopped: false,
            latency: rig.camera.latency_s,
            corrupt_seen: 0,
            skipped_seen: 0,
        })
    }

    /// Capture to delivery latency of the camera pipeline (s), from the rig file.
    pub fn latency(&self) -> f64 {
        self.latency
    }

    /// Seconds between observations.
    pub fn frame_period(&self) -> f64 {
        self.period
    }

    /// The run's counters.
    pub fn stats(&self) -> &RigStats {
        &self.stats
    }

    /// A description of the coil link and camera.
    pub fn describe(&self) -> String {
        format!(
            "coil {}, camera {}",
            self.coil.describe(),
            self.camera.describe()
        )
    }

    /// Makes the next observation time 0 (call when tracking starts).
    pub fn reset_clock(&mut self) {
        self.t_origin = None;
    }

    fn fault(&mut self, t: f64, frame: Option<u64>, msg: &str) {
        self.stats.faults += 1;
        if let Some(l) = self.log.as_mut() {
            l.fault(t, frame, msg);
        }
    }

    /// Zeroes the field, logs the reason, and returns the error.
    fn fail(&mut self, e: HardwareError) -> HardwareError {
        let t = self.arrival.map(|a| a.2).unwrap_or(0.0);
        self.fault(t, None, &e.to_string());
        let z = self.coil.zero();
        self.stopped = true;
        if let Some(l) = self.log.as_mut() {
            l.stop(t, if z.is_ok() { "field zeroed (acknowledged)" } else { "field zero sent, not acknowledged (the device zeroes on disconnect and on its watchdog)" });
        }
        e
    }

    fn check_safety(&mut self) -> Result<(), HardwareError> {
        let t = self.arrival.map(|a| a.2).unwrap_or(0.0);
        for f in self.coil.take_faults() {
            self.fault(t, None, &f);
            if f.contains("watchdog") || f.contains("hold timeout") || f.contains("interrupted") {
                return Err(self.fail(HardwareError::Safety(f)));
            }
        }
        if let Some(f) = self.coil.fatal() {
            return Err(self.fail(HardwareError::Coil(LinkError::Lost(f))));
        }
        Ok(())
    }

    /// Blocks until the next frame and returns what the detector found in it.
    pub fn observe(&mut self) -> Result<Observation, HardwareError> {
        self.check_safety()?;
        loop {
            let frame = match self.camera.next_frame(self.frame_timeout) {
                Ok(f) => f,
                Err(e) => return Err(self.fail(e.into())),
            };
            let arrived = frame.received;
            self.stats.frames += 1;
            let origin = *self.t_origin.get_or_insert(frame.t);
            let t = frame.t - origin;
            if let Some(last) = self.last_index {
                if frame.index <= last {
                    self.fault(
                        t,
                        Some(frame.index),
                        &format!("frame {} arrived after frame {last}: skipped", frame.index),
                    );
                    continue;
                }
                if frame.index > last + 1 {
                    let gap = frame.index - last - 1;
                    let skipped_now = self.camera.skipped_frames();
                    let skipped = (skipped_now - self.skipped_seen).min(gap);
                    self.skipped_seen = skipped_now;
                    self.stats.skipped_frames += skipped;
                    let dropped = gap - skipped;
                    if dropped > 0 {
                        self.stats.dropped_frames += dropped;
                        self.fault(
                            t,
                            Some(frame.index),
                            &format!("{dropped} frame(s) dropped before frame {}", frame.index),
                        );
                    }
                    if skipped > 0 {
                        self.fault(
                            t,
                            Some(frame.index),
                            &format!("{skipped} frame(s) skipped while the host was busy, before frame {}", frame.index),
                        );
                    }
                }
            }
            self.last_index = Some(frame.index);
            let corrupt = self.camera.corrupt_frames();
            if corrupt > self.corrupt_seen {
                let k = corrupt - self.corrupt_seen;
                self.corrupt_seen = corrupt;
                self.fault(
                    t,
                    Some(frame.index),
                    &format!("{k} corrupted frame(s) skipped"),
                );
            }
            let hash = crc32fast::hash(frame.image.as_raw());
            let n = self.detector_agents();
            let agents = if self.last_hash == Some(hash) {
                self.stuck_run += 1;
                self.stats.stuck_frames += 1;
                self.fault(
                    t,
                    Some(frame.index),
                    "frame identical to the previous one (stuck camera): no detection",
                );
                if self.stuck_run + 1 >= self.stuck_limit {
                    return Err(self.fail(HardwareError::Stuck(self.stuck_run + 1)));
                }
                vec![None; n]
            } else {
                self.stuck_run = 0;
                self.detector.detect(&frame.image).agents
            };
            self.last_hash = Some(hash);
            self.stats.missed_detections += agents.iter().filter(|a| a.is_none()).count() as u64;
            if let Some(l) = self.log.as_mut() {
                l.observation(t, frame.index, &agents);
            }
            self.arrival = Some((arrived, frame.index, t));
            return Ok(Observation { t, agents });
        }
    }

    fn detector_agents(&self) -> usize {
        self.detector.agents()
    }

    /// Sends a coil command (clamped to the rig's limits, and flagged in the log if it was).
    pub fn command(&mut self, u: &Control) -> Result<(), HardwareError> {
        self.check_safety()?;
        // the slew limit counts rig time: frame capture times (the device clock), so an
        // emulator running faster than real time limits the same physical ramps
        let t_now = self.arrival.map(|a| a.2);
        let dt = match (t_now, self.last_command) {
            (Some(t), Some(prev)) => (t - prev).max(0.0),
            _ => self.period,
        };
        let (cmd, ack) = match self.coil.command(u, dt) {
            Ok(r) => r,
            Err(e) => return Err(self.fail(e.into())),
        };
        let sent = ack.sent;
        if let Some(t) = t_now {
            self.last_command = Some(t);
        }
        self.stopped = false;
        self.stats.commands += 1;
        let (frame, t, latency) = match self.arrival.take() {
            Some((a, f, t)) => {
                let l = sent.duration_since(a).as_secs_f64() * 1e3;
                self.stats.latencies_ms.push(l);
                (Some(f), t, Some(l))
            }
            None => (None, self.last_index.map(|_| 0.0).unwrap_or(0.0), None),
        };
        if let Some(l) = self.log.as_mut() {
            l.command(t, frame, u, &cmd, ack.tries, latency);
        }
        if cmd.clamped.any() {
            self.stats.clamped_commands += 1;
            let what = if cmd.clamped.current {
                "current limit"
            } else {
                "slew limit"
            };
            self.fault(t, frame, &format!("command clamped by the {what}"));
        }
        if ack.tries > 1 {
            self.fault(
                t,
                frame,
                &format!(
                    "command needed {} tries (corrupted or lost frames)",
                    ack.tries
                ),
            );
        }
        if ack.watchdog_tripped() {
            return Err(self.fail(HardwareError::Safety(
                "the device watchdog had zeroed the currents".into(),
            )));
        }
        Ok(())
    }

    /// Zeroes the field. Idempotent.
    pub fn stop(&mut self) -> Result<(), HardwareError> {
        let r = self.coil.zero();
        if !self.stopped {
            let t = self.arrival.map(|a| a.2).unwrap_or(0.0);
            if let Some(l) = self.log.as_mut() {
                l.stop(
                    t,
                    if r.is_ok() {
                        "stop: field zeroed (acknowledged)"
                    } else {
                        "stop: field zero not acknowledged"
                    },
                );
            }
        }
        self.stopped = true;
        r.map(|_| ()).map_err(HardwareError::from)
    }
}

impl Drop for HardwareRig {
    fn drop(&mut self) {
        let _ = self.coil.zero();
        if let Some(l) = self.log.as_mut() {
            l.flush();
        }
    }
}

/// The tracking loop's view: every hardware failure is fatal to the run (recoverable faults —
/// dropped, corrupted or stuck frames, resent messages — are handled and logged inside).
impl magbench_trackers::Rig for HardwareRig {
    fn frame_period(&self) -> f64 {
        HardwareRig::frame_period(self)
    }

    fn observe(&mut self) -> Result<Observation, magbench_trackers::RigError> {
        HardwareRig::observe(self).map_err(|e| magbench_trackers::RigError::Fatal(e.to_string()))
    }

    fn command(&mut self, u: &Control) -> Result<(), magbench_trackers::RigError> {
        HardwareRig::command(self, u).map_err(|e| magbench_trackers::RigError::Fatal(e.to_string()))
    }

    fn stop(&mut self) -> Result<(), magbench_trackers::RigError> {
        HardwareRig::stop(self).map_err(|e| magbench_trackers::RigError::Fatal(e.to_string()))
    }

    fn latency(&self) -> f64 {
        HardwareRig::latency(self)
    }
}
