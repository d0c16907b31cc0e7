//! The device clock: what time it is on the emulated rig.
//!
//! In real time, device time is the [`Clock`]'s time × `speed`. In lockstep, device time is the
//! time of the last frame sent: it advances one frame period at a time, when the host has
//! answered the last frame (or its clock's 50 ms have passed). The watchdog counts the
//! underlying [`Clock`] in both.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

use crate::clock::Clock;

/// How long (of the underlying clock) a lockstep frame waits for the host's command.
pub const LOCKSTEP_WAIT: Duration = Duration::from_millis(50);

/// The emulated rig's clock, shared by the frame loop and the coil server.
#[derive(Debug)]
pub struct DeviceClock {
    clock: Arc<dyn Clock>,
    speed: f64,
    /// Lockstep: the device time of the last frame (f64 bits).
    lockstep: Option<AtomicU64>,
}

impl DeviceClock {
    /// Device time runs `speed` times faster than `clock`.
    pub fn real_time(clock: Arc<dyn Clock>, speed: f64) -> Self {
        Self {
            clock,
            speed,
            lockstep: None,
        }
    }

    /// Device time is the time of the last frame sent ([`DeviceClock::frame_sent`]).
    pub fn lockstep(clock: Arc<dyn Clock>) -> Self {
        Self {
            clock,
            speed: 1.0,
            lockstep: Some(AtomicU64::new(0f64.to_bits())),
        }
    }

    /// True in lockstep.
    pub fn is_lockstep(&self) -> bool {
        self.lockstep.is_some()
    }

    /// Device time now (s).
    pub fn t(&self) -> f64 {
        match &self.lockstep {
            Some(v) => f64::from_bits(v.load(Ordering::Acquire)),
            None => self.clock.now().as_secs_f64() * self.speed,
        }
    }

    /// The underlying clock's time, which the watchdog counts.
    pub fn timer(&self) -> Duration {
        self.clock.now()
    }

    /// The frame of device time `t` is out (lockstep: device time is now `t`).
    pub fn frame_sent(&self, t: f64) {
        if let Some(v) = &self.lockstep {
            v.store(t.to_bits(), Ordering::Release);
        }
    }

    /// Real time: waits until device time `t` (or `stop`).
    pub fn wait_until(&self, t: f64, stop: &AtomicBool) {
        let target = Duration::from_secs_f64((t / self.speed).max(0.0));
        while !stop.load(Ordering::Relaxed) {
            let now = self.clock.now();
            if now >= target {
                return;
            }
            std::thread::sleep((target - now).min(Duration::from_millis(5)));
        }
    }

    /// Lockstep: waits until `answered` (the host's command) or [`LOCKSTEP_WAIT`] of the
    /// underlying clock (or `stop`).
    pub fn wait_for_host(&self, answered: impl Fn() -> bool, stop: &AtomicBool) {
        let deadline = self.clock.now() + LOCKSTEP_WAIT;
        while !answered() && self.clock.now() < deadline && !stop.load(Ordering::Relaxed) {
            std::thread::sleep(Duration::from_micros(100));
        }
    }
}
