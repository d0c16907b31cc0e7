//! The time the safety timers count: the host's hold timeout and heartbeat, the device's
//! watchdog, and the emulator's frame pacing.
//!
//! On a rig it is the wall clock ([`WallClock`]). A test injects a [`ManualClock`] into the
//! host and an in-process emulator alike, and moves time itself: then "the loop stalled for
//! 300 ms" is a statement the test makes, not a sleep that a loaded machine can stretch.
//! (Waiting for bytes on a link stays in wall time: that is I/O, not a timer.)

use std::fmt::Debug;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// A monotonic clock.
pub trait Clock: Send + Sync + Debug {
    /// Time since the clock's epoch.
    fn now(&self) -> Duration;
}

/// The wall clock, from its creation.
#[derive(Debug, Clone, Copy)]
pub struct WallClock {
    start: Instant,
}

impl WallClock {
    /// A wall clock starting now.
    pub fn new() -> Self {
        Self {
            start: Instant::now(),
        }
    }
}

impl Default for WallClock {
    fn default() -> Self {
        Self::new()
    }
}

impl Clock for WallClock {
    fn now(&self) -> Duration {
        self.start.elapsed()
    }
}

/// A clock that moves only when told to ([`ManualClock::advance`]).
#[derive(Debug, Default)]
pub struct ManualClock {
    nanos: AtomicU64,
}

impl ManualClock {
    /// A manual clock at time zero.
    pub fn new() -> Self {
        Self::default()
    }

    /// Moves the clock forward by `d`.
    pub fn advance(&self, d: Duration) {
        let n = u64::try_from(d.as_nanos()).unwrap_or(u64::MAX);
        self.nanos.fetch_add(n, Ordering::SeqCst);
    }
}

impl Clock for ManualClock {
    fn now(&self) -> Duration {
        Duration::from_nanos(self.nanos.load(Ordering::SeqCst))
    }
}

/// A shared wall clock starting now.
pub fn wall() -> Arc<dyn Clock> {
    Arc::new(WallClock::new())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_manual_clock_moves_only_when_advanced() {
        let c = ManualClock::new();
        assert_eq!(c.now(), Duration::ZERO);
        c.advance(Duration::from_millis(250));
        c.advance(Duration::from_millis(50));
        assert_eq!(c.now(), Duration::from_millis(300));
        let w = WallClock::new();
        let a = w.now();
        assert!(w.now() >= a);
    }
}
