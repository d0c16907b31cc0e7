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

    /// Sends one encoded frame; a host that has gone is logged (at device time `t`, currents
    /// `in_force`) and dropped.
    pub fn send(&self, bytes: &[u8], t: f64, in_force: &[f64], log: &EventLog) {
        let mut client = lock(&self.client);
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
