//! A live coil session: the link, the driver arithmetic and a keep-alive thread with the
//! host-side safety checks.
//!
//! The keep-alive thread sends a heartbeat when the control loop has sent nothing for
//! `heartbeat_ms`, zeroes the field when a non-zero command has not been renewed for
//! `hold_timeout_ms` (a stalled control loop), and zeroes it at once when the abort flag
//! (Ctrl-C) is raised. Faults it sees are queued for the control loop to report.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::Duration;

use magbench_env::Control;

use crate::clock::Clock;
use crate::coil_driver::{CoilCommand, CoilDriver};
use crate::link::{AckInfo, CoilLink, LinkError};
use crate::protocol::{Message, PROTOCOL_VERSION};
use crate::rigfile::CoilConfig;
use crate::transport;

struct Inner {
    link: CoilLink,
    driver: CoilDriver,
    /// Clock time of the last message sent.
    last_tx: Duration,
    /// Clock time of the last command.
    last_command: Option<Duration>,
    field_on: bool,
    faults: Vec<String>,
    fatal: Option<String>,
}

/// A coil session (see the module documentation).
pub struct CoilSession {
    inner: Arc<Mutex<Inner>>,
    clock: Arc<dyn Clock>,
    quit: Arc<AtomicBool>,
    abort: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
    describe: String,
}

fn lock(m: &Mutex<Inner>) -> MutexGuard<'_, Inner> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

impl CoilSession {
    /// Opens the link, says HELLO (channel count, watchdog) and starts the keep-alive thread.
    /// `abort` zeroes the field from the keep-alive thread as soon as it is raised; `clock`
    /// times the heartbeat and the hold timeout.
    pub fn open(
        cfg: &CoilConfig,
        field_mt: f64,
        abort: Arc<AtomicBool>,
        clock: Arc<dyn Clock>,
    ) -> Result<Self, LinkError> {
        let io = transport::open(&cfg.endpoint, Duration::from_secs(2))
            .map_err(|e| LinkError::Lost(e.to_string()))?;
        let describe = io.describe();
        let mut link = CoilLink::new(
            io,
            Duration::from_millis(cfg.ack_timeout_ms as u64),
            cfg.retries,
        );
        let driver = CoilDriver::new(cfg, field_mt);
        // a device that has just been opened may need a moment: try HELLO a few times
        let mut hello = Err(LinkError::NoAck { seq: 0, tries: 0 });
        for _ in 0..5 {
            hello = link.request(&Message::Hello {
                version: PROTOCOL_VERSION,
                channels: driver.channels() as u8,
                watchdog_ms: cfg.watchdog_ms as u16,
            });
            if !matches!(hello, Err(LinkError::NoAck { .. })) {
                break;
            }
        }
        hello?;
        link.request(&Message::Zero)?;
        let inner = Arc::new(Mutex::new(Inner {
            link,
            driver,
            last_tx: clock.now(),
            last_command: None,
            field_on: false,
            faults: Vec::new(),
            fatal: None,
        }));
        let quit = Arc::new(AtomicBool::new(false));
        let thread = {
            let (inner, quit, abort, clock) =
                (inner.clone(), quit.clone(), abort.clone(), clock.clone());
            let heartbeat = Duration::from_millis(cfg.heartbeat_ms as u64);
            let hold = Duration::from_millis(cfg.hold_timeout_ms as u64);
            std::thread::Builder::new()
                .name("coil-keepalive".into())
                .spawn(move || keep_alive(&inner, &quit, &abort, &*clock, heartbeat, hold))
                .map_err(|e| LinkError::Lost(e.to_string()))?
        };
        Ok(Self {
            inner,
            clock,
            quit,
            abort,
            thread: Some(thread),
            describe,
        })
    }

    /// The link's description.
    pub fn describe(&self) -> &str {
        &self.describe
    }

    /// Sends currents for `u`, `dt` seconds after the previous command.
    pub fn command(&self, u: &Control, dt: f64) -> Result<(CoilCommand, AckInfo), LinkError> {
        let mut s = lock(&self.inner);
        if let Some(f) = &s.fatal {
            return Err(LinkError::Lost(f.clone()));
        }
        if self.abort.load(Ordering::Relaxed) {
            return Err(LinkError::Interrupted);
        }
        let Some(cmd) = s.driver.command(u, dt) else {
            drop(s);
            let _ = self.zero();
            return Err(LinkError::Refused {
                seq: 0,
                status: crate::protocol::AckStatus::BadPayload,
            });
        };
        let currents: Vec<f32> = cmd.currents.iter().map(|x| *x as f32).collect();
        let r = s.link.request(&Message::SetCurrents(currents));
        s.last_tx = self.clock.now();
        match r {
            Ok(ack) => {
                s.last_command = Some(self.clock.now());
                s.field_on = cmd.currents.iter().any(|c| *c != 0.0);
                Ok((cmd, ack))
            }
            Err(e) => {
                s.fatal = Some(e.to_string());
                let z = s.driver.zero();
                let _ = s.link.request(&Message::SetCurrents(
                    z.currents.iter().map(|x| *x as f32).collect(),
                ));
                Err(e)
            }
        }
    }

    /// Zeroes every current now (never slew-limited).
    pub fn zero(&self) -> Result<AckInfo, LinkError> {
        let mut s = lock(&self.inner);
        s.driver.zero();
        s.field_on = false;
        let r = s.link.request(&Message::Zero);
        s.last_tx = self.clock.now();
        r
    }

    /// Faults the keep-alive thread saw since the last call.
    pub fn take_faults(&self) -> Vec<String> {
        std::mem::take(&mut lock(&self.inner).faults)
    }

    /// The fault that ended the session, if any.
    pub fn fatal(&self) -> Option<String> {
        lock(&self.inner).fatal.clone()
    }

    /// Link trouble counters.
    pub fn link_stats(&self) -> crate::link::LinkStats {
        lock(&self.inner).link.stats()
    }
}

impl Drop for CoilSession {
    fn drop(&mut self) {
        let _ = self.zero();
        self.quit.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn keep_alive(
    inner: &Mutex<Inner>,
    quit: &AtomicBool,
    abort: &AtomicBool,
    clock: &dyn Clock,
    heartbeat: Duration,
    hold: Duration,
) {
    let tick = (heartbeat / 5).clamp(Duration::from_millis(1), Duration::from_millis(10));
    let mut aborted = false;
    while !quit.load(Ordering::Relaxed) {
        std::thread::sleep(tick);
        let mut s = lock(inner);
        if s.link.is_lost() {
            continue;
        }
        let now = clock.now();
        if abort.load(Ordering::Relaxed) && !aborted {
            aborted = true;
            s.driver.zero();
            s.field_on = false;
            let r = s.link.request(&Message::Zero);
            s.last_tx = now;
            s.faults.push(format!(
                "interrupted: field zeroed ({})",
                if r.is_ok() {
                    "acknowledged"
                } else {
                    "not acknowledged"
                }
            ));
            continue;
        }
        if s.field_on && s.last_command.is_some_and(|t| now.saturating_sub(t) > hold) {
            s.driver.zero();
            s.field_on = false;
            let r = s.link.request(&Message::Zero);
            s.last_tx = now;
            let msg = format!(
                "hold timeout: no command for more than {} ms, field zeroed",
                hold.as_millis()
            );
            s.faults.push(msg.clone());
            if r.is_err() {
                s.fatal = Some(msg);
            }
            continue;
        }
        if now.saturating_sub(s.last_tx) >= heartbeat {
            let r = s.link.request(&Message::Heartbeat);
            s.last_tx = now;
            match r {
                Ok(ack) if ack.watchdog_tripped() => s
                    .faults
                    .push("the device watchdog had zeroed the currents".into()),
                Ok(_) => {}
                Err(e) => {
                    s.faults.push(format!("heartbeat failed: {e}"));
                    s.fatal = Some(e.to_string());
                }
            }
        }
    }
}
