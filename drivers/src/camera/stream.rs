//! The emulator's frame stream over TCP.

use std::io::{BufReader, ErrorKind};
use std::net::TcpStream;
use std::time::{Duration, Instant};

use super::{Camera, CameraError};
use crate::frame::{Frame, ReadFrame, read_frame};
use crate::transport::connect_tcp;

/// A camera that reads the frame-stream records (see [`crate::frame`]) from a TCP address.
pub struct StreamCamera {
    reader: BufReader<TcpStream>,
    addr: String,
    corrupt: u64,
}

impl StreamCamera {
    /// Connects to a frame stream.
    pub fn connect(addr: &str, timeout: Duration) -> Result<Self, CameraError> {
        let s = connect_tcp(addr, timeout).map_err(|e| CameraError::Lost(e.to_string()))?;
        Ok(Self {
            reader: BufReader::with_capacity(1 << 20, s),
            addr: addr.to_string(),
            corrupt: 0,
        })
    }
}

impl Camera for StreamCamera {
    fn next_frame(&mut self, timeout: Duration) -> Result<Frame, CameraError> {
        let deadline = Instant::now() + timeout;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Err(CameraError::Timeout(timeout.as_millis() as u64));
            }
            self.reader
                .get_ref()
                .set_read_timeout(Some(left))
                .map_err(|e| CameraError::Lost(e.to_string()))?;
            match read_frame(&mut self.reader, 16384) {
                Ok(ReadFrame::Frame(f)) => return Ok(f),
                Ok(ReadFrame::Corrupt) => self.corrupt += 1,
                Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {
                    return Err(CameraError::Timeout(timeout.as_millis() as u64));
                }
                Err(e) if e.kind() == ErrorKind::UnexpectedEof => {
                    return Err(CameraError::Lost(format!(
                        "frame stream {} closed",
                        self.addr
                    )));
                }
                Err(e) => {
                    return Err(CameraError::Lost(format!(
                        "frame stream {}: {e}",
                        self.addr
                    )));
                }
            }
        }
    }

    fn corrupt_frames(&self) -> u64 {
        self.corrupt
    }

    fn describe(&self) -> String {
        format!("frame stream {}", self.addr)
    }
}
