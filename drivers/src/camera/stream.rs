//! The emulator's frame stream over TCP, read by a background thread that keeps the newest
//! frames (like a camera driver's buffer ring), so a host that pauses (planning) or falls behind
//! gets the latest frame, never a backlog.

use std::collections::VecDeque;
use std::io::{BufReader, ErrorKind};
use std::net::{Shutdown, TcpStream};
use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::{Camera, CameraError};
use crate::frame::{Frame, ReadFrame, read_frame};
use crate::transport::connect_tcp;

/// Frames kept while the host is busy; older ones are overwritten.
const RING: usize = 3;

#[derive(Default)]
struct State {
    ring: VecDeque<Frame>,
    error: Option<CameraError>,
    corrupt: u64,
    skipped: u64,
}

/// A camera that reads the frame-stream records (see [`crate::frame`]) from a TCP address.
pub struct StreamCamera {
    shared: Arc<(Mutex<State>, Condvar)>,
    socket: TcpStream,
    reader: Option<JoinHandle<()>>,
    addr: String,
}

impl StreamCamera {
    /// Connects to a frame stream and starts reading it.
    pub fn connect(addr: &str, timeout: Duration) -> Result<Self, CameraError> {
        let s = connect_tcp(addr, timeout).map_err(|e| CameraError::Lost(e.to_string()))?;
        let socket = s
            .try_clone()
            .map_err(|e| CameraError::Lost(e.to_string()))?;
        let shared = Arc::new((Mutex::new(State::default()), Condvar::new()));
        let reader = {
            let (shared, addr) = (shared.clone(), addr.to_string());
            std::thread::Builder::new()
                .name("frame-stream".into())
                .spawn(move || read_loop(s, &shared, &addr))
                .map_err(|e| CameraError::Lost(e.to_string()))?
        };
        Ok(Self {
            shared,
            socket,
            reader: Some(reader),
            addr: addr.to_string(),
        })
    }
}

fn read_loop(s: TcpStream, shared: &(Mutex<State>, Condvar), addr: &str) {
    let mut r = BufReader::with_capacity(1 << 20, s);
    loop {
        let got = read_frame(&mut r, 16384);
        let (lock, cv) = shared;
        let mut st = lock.lock().unwrap_or_else(|e| e.into_inner());
        match got {
            Ok(ReadFrame::Frame(f)) => {
                st.ring.push_back(f);
                if st.ring.len() > RING {
                    st.ring.pop_front();
                    st.skipped += 1;
                }
            }
            Ok(ReadFrame::Corrupt) => st.corrupt += 1,
            Err(e) => {
                st.error = Some(CameraError::Lost(match e.kind() {
                    ErrorKind::UnexpectedEof => format!("frame stream {addr} closed"),
                    _ => format!("frame stream {addr}: {e}"),
                }));
                cv.notify_all();
                return;
            }
        }
        cv.notify_all();
    }
}

impl Camera for StreamCamera {
    fn next_frame(&mut self, timeout: Duration) -> Result<Frame, CameraError> {
        let deadline = Instant::now() + timeout;
        let (lock, cv) = &*self.shared;
        let mut st = lock.lock().unwrap_or_else(|e| e.into_inner());
        loop {
            // the newest frame; skipped older ones show as a gap in the frame index
            if let Some(f) = st.ring.pop_back() {
                st.skipped += st.ring.len() as u64;
                st.ring.clear();
                return Ok(f);
            }
            if let Some(e) = &st.error {
                return Err(e.clone());
            }
            let now = Instant::now();
            if now >= deadline {
                return Err(CameraError::Timeout(timeout.as_millis() as u64));
            }
            st = cv
                .wait_timeout(st, deadline - now)
                .unwrap_or_else(|e| e.into_inner())
                .0;
        }
    }

    fn corrupt_frames(&self) -> u64 {
        self.shared
            .0
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .corrupt
    }

    fn skipped_frames(&self) -> u64 {
        self.shared
            .0
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .skipped
    }

    fn describe(&self) -> String {
        format!("frame stream {}", self.addr)
    }
}

impl Drop for StreamCamera {
    fn drop(&mut self) {
        let _ = self.socket.shutdown(Shutdown::Both);
        if let Some(t) = self.reader.take() {
            let _ = t.join();
        }
    }
}
