//! The camera server: the frame stream's TCP end, one host at a time.

use std::io::Write;
use std::net::{TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use super::clock::DeviceClock;
use super::error::EmulatorError;
use super::log::EventLog;

/// Streams encoded frames to the connected host.
pub struct CameraServer {
    addr: String,
    client: Arc<Mutex<Option<TcpStream>>>,
    /// Hosts accepted so far.
    accepted: Arc<AtomicU64>,
}

impl CameraServer {
    /// Listens on `listen` and accepts hosts until `stop` (a new host replaces the old one).
    pub fn start(
        listen: &str,
        stop: Arc<AtomicBool>,
        log: Arc<EventLog>,
        clock: Arc<DeviceClock>,
    ) -> Result<Self, EmulatorError> {
        let what = || format!("camera listen {listen}");
        let listener = TcpListener::bind(listen).map_err(|e| EmulatorError::io(what(), e))?;
        let addr = listener
            .local_addr()
            .map_err(|e| EmulatorError::io(what(), e))?
            .to_string();
        listener
            .set_nonblocking(true)
            .map_err(|e| EmulatorError::io(what(), e))?;
        let client: Arc<Mutex<Option<TcpStream>>> = Arc::new(Mutex::new(None));
        let accepted = Arc::new(AtomicU64::new(0));
        let (c, n) = (client.clone(), accepted.clone());
        std::thread::spawn(move || {
            while !stop.load(Ordering::Relaxed) {
                match listener.accept() {
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
                        let mut client = lock(&c);
                        *client = Some(s);
                        n.fetch_add(1, Ordering::Release);
                    }
                    Err(_) => std::thread::sleep(Duration::from_millis(5)),
                }
            }
        });
        Ok(Self {
            addr,
            client,
            accepted,
        })
    }

    /// The address hosts connect to.
    pub fn addr(&self) -> &str {
        &self.addr
    }

    /// True while a host is connected.
    pub fn connected(&self) -> bool {
        lock(&self.client).is_some()
    }

    /// How many hosts it has accepted: the number of the connection it streams to now.
    pub fn accepted(&self) -> u64 {
        self.accepted.load(Ordering::Acquire)
    }

    /// Cuts the stream (the host sees it close).
    pub fn cut(&self) {
        *lock(&self.client) = None;
    }

    /// Cuts the stream of the `accepted`-th host unless a newer one has connected (a host is
    /// accepted under the same lock, so none slips in between the test and the cut); true
    /// when it cut.
    pub fn cut_unless_newer(&self, accepted: u64) -> bool {
        let mut client = lock(&self.client);
        let cut = self.accepted() == accepted;
        if cut {
            *client = None;
        }
        cut
    }

    /// Sends one encoded frame to the connected host, or only to the `to`-th host accepted
    /// when `to` is given; a host that has gone is logged (at device time `t`, currents
    /// `in_force`) and dropped.
    pub fn send(&self, bytes: &[u8], to: Option<u64>, t: f64, in_force: &[f64], log: &EventLog) {
        let mut client = lock(&self.client);
        if to.is_some_and(|n| n != self.accepted()) {
            return;
        }
        if let Some(s) = client.as_mut()
            && let Err(e) = s.write_all(bytes)
        {
            log.event(t, "camera_disconnect", None, in_force, &[], &e.to_string());
            *client = None;
        }
    }
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clock::ManualClock;

    /// Waits until the server has accepted `n` hosts; fails (does not hang) after a generous
    /// deadline.
    fn accepted(server: &CameraServer, n: u64) {
        let start = std::time::Instant::now();
        while server.accepted() < n {
            assert!(
                start.elapsed() < Duration::from_secs(30),
                "the server accepted {} of {n} hosts",
                server.accepted()
            );
            std::thread::yield_now();
        }
    }

    #[test]
    fn a_stream_is_cut_only_while_no_newer_host_has_connected() {
        let dir = tempfile::tempdir().unwrap();
        let clock: Arc<dyn crate::clock::Clock> = Arc::new(ManualClock::default());
        let log = Arc::new(EventLog::create(&dir.path().join("log.csv"), clock.clone()).unwrap());
        let stop = Arc::new(AtomicBool::new(false));
        let device = Arc::new(DeviceClock::lockstep(clock));
        let server = CameraServer::start("127.0.0.1:0", stop.clone(), log, device).unwrap();
        let _first = TcpStream::connect(server.addr()).unwrap();
        accepted(&server, 1);
        let _second = TcpStream::connect(server.addr()).unwrap();
        accepted(&server, 2);
        // the first host's session ended after the second connected: the second keeps its stream
        assert!(!server.cut_unless_newer(1));
        assert!(server.connected());
        assert!(server.cut_unless_newer(2));
        assert!(!server.connected());
        stop.store(true, Ordering::Relaxed);
    }
}
