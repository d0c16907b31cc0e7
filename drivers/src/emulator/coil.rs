//! The coil server: the emulated coil driver on its link, one server for every transport.
//!
//! A [`CoilTransport`] hands out host connections (a TCP listener: one per connecting host; a
//! pseudo-terminal: the one line, once). The server serves each with the device protocol,
//! checks the watchdog all along, injects the link faults, and publishes every current change
//! to the plant stepper through [`DeviceShared`].

use std::net::TcpListener;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::clock::DeviceClock;
use super::device::{DeviceEvent, DeviceState};
use super::error::EmulatorError;
use super::faults::{Cut, FaultPlan, maybe_corrupt};
use super::io::DeviceIo;
use super::log::EventLog;
use crate::protocol::{Decoded, Decoder, encode};

/// The device state the coil server and the frame loop share.
pub struct DeviceShared {
    /// The coil driver.
    pub device: DeviceState,
    /// Each change of the currents, consumed by the plant stepper.
    pub changes: Vec<Change>,
    /// Device time of the first HELLO: fault times count from here.
    pub hello_t: Option<f64>,
    /// SET_CURRENTS messages (new or repeated) handled so far: the host's answers to frames,
    /// which lockstep waits for. A ZERO is not one: it ends a run (the host's last messages
    /// are ZEROs), and frames it released would depend on when the host closes its link.
    pub commands: u64,
    /// A host's session is open: it said HELLO on a link it has not closed.
    pub session_open: bool,
    /// Sessions opened so far.
    pub sessions: u64,
}

impl DeviceShared {
    /// Session `session` (the count of sessions when it opened) is still open.
    pub fn in_session(&self, session: u64) -> bool {
        self.session_open && self.sessions == session
    }

    /// Queues a change to `currents` at device time `t`.
    pub fn push_change(&mut self, t: f64, currents: &[f64]) {
        let commands_before = self.commands;
        self.changes.push(Change {
            t,
            currents: currents.to_vec(),
            commands_before,
        });
    }
}

/// A change of the device's currents, for the plant stepper.
#[derive(Debug, Clone)]
pub struct Change {
    /// Device time of the change (s).
    pub t: f64,
    /// The currents from then on (A).
    pub currents: Vec<f64>,
    /// Host commands handled before the message that made it: in lockstep a frame is stepped
    /// with the changes up to the host's answer to the frame before, and any that came after
    /// the answer wait for the next frame, however soon they arrive.
    pub commands_before: u64,
}

/// The shared device state behind its lock.
pub type Shared = Arc<Mutex<DeviceShared>>;

/// Locks the shared state (a panicked holder does not poison it for the others).
pub fn lock(s: &Mutex<DeviceShared>) -> MutexGuard<'_, DeviceShared> {
    s.lock().unwrap_or_else(|e| e.into_inner())
}

/// Where host connections come from.
pub trait CoilTransport: Send + 'static {
    /// The next host connection and a description of it, if one is waiting now.
    fn accept(&mut self) -> Option<(Box<dyn DeviceIo>, String)>;
}

/// Hosts connecting over TCP.
pub struct TcpTransport(TcpListener);

impl TcpTransport {
    /// Listens on `addr`; returns the transport and the bound address.
    pub fn bind(addr: &str) -> Result<(Self, String), EmulatorError> {
        let what = || format!("coil listen {addr}");
        let l = TcpListener::bind(addr).map_err(|e| EmulatorError::io(what(), e))?;
        let bound = l
            .local_addr()
            .map_err(|e| EmulatorError::io(what(), e))?
            .to_string();
        l.set_nonblocking(true)
            .map_err(|e| EmulatorError::io(what(), e))?;
        Ok((Self(l), bound))
    }
}

impl CoilTransport for TcpTransport {
    fn accept(&mut self) -> Option<(Box<dyn DeviceIo>, String)> {
        let (s, peer) = self.0.accept().ok()?;
        let _ = s.set_nonblocking(false);
        let _ = s.set_nodelay(true);
        Some((Box::new(s), peer.to_string()))
    }
}

/// The one line of a pseudo-terminal, handed out once (a host opens it as a serial port).
#[cfg(unix)]
pub struct PtyTransport(Option<super::io::pty::Pty>);

#[cfg(unix)]
impl PtyTransport {
    /// Opens a pseudo-terminal linked at `link`.
    pub fn open(link: &std::path::Path) -> Result<Self, EmulatorError> {
        super::io::pty::Pty::open(link)
            .map(|p| Self(Some(p)))
            .map_err(|e| EmulatorError::io(format!("pty {}", link.display()), e))
    }
}

#[cfg(unix)]
impl CoilTransport for PtyTransport {
    fn accept(&mut self) -> Option<(Box<dyn DeviceIo>, String)> {
        self.0
            .take()
            .map(|p| (Box::new(p) as Box<dyn DeviceIo>, "pty".into()))
    }
}

/// What the coil server needs besides its transport.
pub struct CoilServer {
    /// The shared device state.
    pub shared: Shared,
    /// The event log.
    pub log: Arc<EventLog>,
    /// The device clock.
    pub clock: Arc<DeviceClock>,
    /// The link faults to inject (corruption, a coil disconnect).
    pub faults: FaultPlan,
    /// Seed of the corruption draws.
    pub seed: u64,
    /// Ends the server.
    pub stop: Arc<AtomicBool>,
}

impl CoilServer {
    /// Serves hosts from `transport` on a thread of its own until `stop`; a cut link stays
    /// cut (as a pulled cable does).
    pub fn spawn(self, mut transport: impl CoilTransport) {
        std::thread::spawn(move || {
            let mut rng = ChaCha8Rng::seed_from_u64(self.seed ^ 0xFA_0175);
            let mut cut = false;
            while !self.stop.load(Ordering::Relaxed) {
                self.watchdog();
                match transport.accept() {
                    Some(_) if cut => {} // the cable stays cut
                    Some((mut io, peer)) => {
                        self.log
                            .event(self.clock.t(), "coil_connect", None, &[], &[], &peer);
                        cut = self.serve(io.as_mut(), &mut rng);
                    }
                    None => std::thread::sleep(Duration::from_millis(2)),
                }
            }
        });
    }

    /// Trips the watchdog if the host has been silent too long (no host connected: silent now).
    fn watchdog(&self) {
        self.watchdog_at(self.clock.timer());
    }

    /// Trips the watchdog if the host had been silent too long at clock time `now`.
    fn watchdog_at(&self, now: Duration) {
        let mut sh = lock(&self.shared);
        if sh.device.check_watchdog(now) {
            let t = self.clock.t();
            let silent = sh
                .device
                .last_rx()
                .map(|r| now.saturating_sub(r).as_secs_f64() * 1e3)
                .unwrap_or(0.0);
            let cur = sh.device.currents().to_vec();
            sh.push_change(t, &cur);
            self.log.event_at(
                now,
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

    /// The host closed its link, or the link failed: the currents are zeroed (`why`) and its
    /// session ends.
    fn end_session(&self, why: &str) {
        self.zero_on(why);
        lock(&self.shared).session_open = false;
    }

    /// Zeroes the currents on a link event `why`.
    fn zero_on(&self, why: &str) {
        let mut sh = lock(&self.shared);
        sh.device.zero();
        let cur = sh.device.currents().to_vec();
        let t = self.clock.t();
        sh.push_change(t, &cur);
        self.log.event(t, why, None, &cur, &[], "currents zeroed");
    }

    /// Serves one host connection until it closes or the link is cut; returns true when cut.
    ///
    /// The watchdog judges the silence at the clock reading taken before each read, once that
    /// read's bytes are handled: a message that was already waiting then (received, but not
    /// yet handled by a thread the machine was slow to schedule) counts as received, as on a
    /// device whose receiver works by interrupt.
    fn serve(&self, io: &mut dyn DeviceIo, rng: &mut ChaCha8Rng) -> bool {
        let mut dec = Decoder::new();
        let mut buf = [0u8; 512];
        let mut idle = Duration::ZERO;
        while !self.stop.load(Ordering::Relaxed) {
            let since_hello = lock(&self.shared).hello_t.map(|h| self.clock.t() - h);
            if let Some((tc, Cut::Coil)) = self.faults.disconnect
                && since_hello.is_some_and(|s| s >= tc)
            {
                self.zero_on("fault_disconnect");
                return true;
            }
            let before_read = self.clock.timer();
            let n = match io.read_timeout(&mut buf, Duration::from_millis(2)) {
                Ok(None) => {
                    idle += Duration::from_millis(2);
                    if idle >= Duration::from_millis(4) && dec.pending() > 0 {
                        dec.drop_stalled();
                    }
                    self.watchdog_at(before_read);
                    continue;
                }
                Ok(Some(0)) => {
                    self.end_session("coil_disconnect");
                    return false;
                }
                Ok(Some(n)) => n,
                Err(e) => {
                    self.end_session(&format!("coil_error {e}"));
                    return false;
                }
            };
            idle = Duration::ZERO;
            let chunk = &mut buf[..n];
            if maybe_corrupt(chunk, self.faults.corrupt, rng) {
                self.log.event(
                    self.clock.t(),
                    "fault_corrupt_rx",
                    None,
                    &[],
                    &[],
                    "one received byte flipped",
                );
            }
            dec.feed(chunk);
            while let Some(d) = dec.next_frame() {
                if !self.answer(io, d, rng) {
                    return false;
                }
            }
            self.watchdog_at(before_read);
        }
        false
    }

    /// Handles one decoded frame and sends the reply; false when the link failed.
    fn answer(&self, io: &mut dyn DeviceIo, d: Decoded, rng: &mut ChaCha8Rng) -> bool {
        let now = self.clock.timer();
        let t = self.clock.t();
        let (reply, seq, cur, event) = {
            let mut sh = lock(&self.shared);
            let seq = match &d {
                Decoded::Message { seq, .. } | Decoded::Invalid { seq, .. } => Some(*seq),
                _ => None,
            };
            let before = sh.device.currents().to_vec();
            let (reply, event) = sh.device.handle(d, now);
            let cur = sh.device.currents().to_vec();
            if cur != before {
                sh.push_change(t, &cur);
            }
            if matches!(event, DeviceEvent::Currents | DeviceEvent::Duplicate) {
                sh.commands += 1;
            }
            if matches!(event, DeviceEvent::Hello { .. }) {
                sh.hello_t.get_or_insert(t);
                if !sh.session_open {
                    sh.session_open = true;
                    sh.sessions += 1;
                }
            }
            (reply, seq, cur, event)
        };
        let (name, detail) = match &event {
            DeviceEvent::Hello { watchdog_ms } => ("hello", format!("watchdog {watchdog_ms} ms")),
            DeviceEvent::Currents => ("currents", String::new()),
            DeviceEvent::Duplicate => ("currents_repeat", String::new()),
            DeviceEvent::Heartbeat => ("heartbeat", String::new()),
            DeviceEvent::Zero => ("zero", String::new()),
            DeviceEvent::Refused(s) => ("refused", format!("{s:?}")),
            DeviceEvent::BadFrame => ("bad_frame", "checksum failed: NAK".into()),
        };
        // stamped with the reading the device judged the message by (its watchdog's clock)
        self.log.event_at(now, t, name, seq, &cur, &[], &detail);
        let mut bytes = encode(seq.unwrap_or(0), &reply);
        if maybe_corrupt(&mut bytes, self.faults.corrupt, rng) {
            self.log.event(
                t,
                "fault_corrupt_tx",
                seq,
                &cur,
                &[],
                "one reply byte flipped",
            );
        }
        if let Err(e) = io.send(&bytes) {
            self.end_session(&format!("coil_error {e}"));
            return false;
        }
        true
    }
}
