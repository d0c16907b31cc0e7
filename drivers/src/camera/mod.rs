//! Cameras: where frames come from, behind the [`Camera`] trait.

mod recorded;
mod recorder;
mod stream;
#[cfg(feature = "v4l2")]
mod v4l2;

pub use recorded::{RecordedCamera, read_index};
pub use recorder::FrameRecorder;
pub use stream::StreamCamera;
#[cfg(feature = "v4l2")]
pub use v4l2::V4l2Camera;

use std::time::Duration;

use crate::frame::Frame;
use crate::rigfile::{CameraConfig, CameraSource};

/// Why no frame came.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CameraError {
    /// No frame within the timeout.
    #[error("no camera frame for {0} ms")]
    Timeout(u64),
    /// The source failed or closed.
    #[error("camera lost ({0})")]
    Lost(String),
    /// A recording has no more frames.
    #[error("end of recorded frames")]
    Ended,
}

/// A source of grey-level frames.
pub trait Camera: Send {
    /// Blocks until the next frame, at most `timeout`.
    fn next_frame(&mut self, timeout: Duration) -> Result<Frame, CameraError>;
    /// Frames that arrived corrupted and were skipped so far.
    fn corrupt_frames(&self) -> u64 {
        0
    }
    /// Frames received but overwritten before the host asked for them (the host was busy).
    fn skipped_frames(&self) -> u64 {
        0
    }
    /// A short description for messages.
    fn describe(&self) -> String;
}

/// Opens the camera a rig file names.
pub fn open(cfg: &CameraConfig) -> Result<Box<dyn Camera>, CameraError> {
    match &cfg.source {
        CameraSource::Emulator(addr) => Ok(Box::new(StreamCamera::connect(
            addr,
            Duration::from_secs(2),
        )?)),
        CameraSource::Recorded(dir) => Ok(Box::new(RecordedCamera::open(dir, cfg.fps)?)),
        #[cfg(feature = "v4l2")]
        CameraSource::V4l2(dev) => Ok(Box::new(V4l2Camera::open(dev, cfg)?)),
        #[cfg(not(feature = "v4l2"))]
        CameraSource::V4l2(dev) => Err(CameraError::Lost(format!(
            "{dev}: this magbench was built without V4L2 support (cargo feature `v4l2` of magbench-drivers)"
        ))),
    }
}
