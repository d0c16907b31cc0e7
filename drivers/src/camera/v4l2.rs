//! A V4L2 camera (Linux video devices), 8-bit grey frames. Cargo feature `v4l2`.

use std::time::Duration;

use image::GrayImage;
use v4l::buffer::Type;
use v4l::io::mmap::Stream;
use v4l::io::traits::CaptureStream;
use v4l::video::Capture;
use v4l::{Device, FourCC};

use super::{Camera, CameraError};
use crate::frame::Frame;
use crate::rigfile::CameraConfig;

/// A V4L2 capture device delivering `GREY` (8-bit luminance) frames of the rig's sensor size.
pub struct V4l2Camera {
    stream: Stream<'static>,
    path: String,
    size: (u32, u32),
}

impl V4l2Camera {
    /// Opens `path` and asks for the rig's size in the `GREY` format.
    pub fn open(path: &str, cfg: &CameraConfig) -> Result<Self, CameraError> {
        let lost = |e: std::io::Error| CameraError::Lost(format!("{path}: {e}"));
        let dev = Device::with_path(path).map_err(lost)?;
        let mut fmt = dev.format().map_err(lost)?;
        fmt.width = cfg.size_px[0];
        fmt.height = cfg.size_px[1];
        fmt.fourcc = FourCC::new(b"GREY");
        let fmt = dev.set_format(&fmt).map_err(lost)?;
        if fmt.fourcc != FourCC::new(b"GREY") {
            return Err(CameraError::Lost(format!(
                "{path}: the device does not deliver 8-bit grey (GREY) frames"
            )));
        }
        let stream = Stream::with_buffers(&dev, Type::VideoCapture, 4).map_err(lost)?;
        Ok(Self {
            stream,
            path: path.to_string(),
            size: (fmt.width, fmt.height),
        })
    }
}

impl Camera for V4l2Camera {
    fn next_frame(&mut self, timeout: Duration) -> Result<Frame, CameraError> {
        self.stream.set_timeout(timeout);
        let (buf, meta) = self.stream.next().map_err(|e| match e.kind() {
            std::io::ErrorKind::TimedOut => CameraError::Timeout(timeout.as_millis() as u64),
            _ => CameraError::Lost(format!("{}: {e}", self.path)),
        })?;
        let (w, h) = self.size;
        let n = (w * h) as usize;
        if buf.len() < n {
            return Err(CameraError::Lost(format!(
                "{}: short frame ({} of {n} bytes)",
                self.path,
                buf.len()
            )));
        }
        let t = meta.timestamp.sec as f64 + meta.timestamp.usec as f64 * 1e-6;
        let image = GrayImage::from_raw(w, h, buf[..n].to_vec()).expect("size checked");
        Ok(Frame {
            index: meta.sequence as u64,
            t,
            image,
            received: std::time::Instant::now(),
        })
    }

    fn describe(&self) -> String {
        format!("V4L2 camera {}", self.path)
    }
}
