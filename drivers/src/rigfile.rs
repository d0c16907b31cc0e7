//! The rig file (TOML): coil link and calibration, camera source, pixel calibration, detector.
//!
//! Parsed with `deny_unknown_fields` and validated like scenario files: every rejection is an
//! [`InputError`] `FILE: FIELD: REASON`. See docs/rigs.md for the format.

use std::path::{Path, PathBuf};

use magbench_env::InputError;
use magbench_env::check::{Bound, Checker, Fixed, parse_toml, read_text};
use serde::Deserialize;

use crate::calibration::Calibration;
use crate::pixel_map::PixelMap;

/// Pixels per body length: an agent 1000 px across fills a whole sensor side; beyond it the
/// emulator's agent patches (side ≈ px_per_bl + 8 blur) outgrow the memory budget.
pub const PX_PER_BL: Bound = Bound::above(
    0.0,
    1000.0,
    " px/BL",
    "an agent 1000 px across already fills a sensor side",
);

/// Optical blur σ (pixels) of the detector model and the emulator: a blur of 50 px wipes out
/// any agent a detector can find, and the blur kernel's cost grows with it.
pub const BLUR_PX: Bound = Bound::closed(
    0.0,
    50.0,
    " px",
    "a blur of 50 px wipes out any agent a detector can find, and its cost grows with it",
);

/// Camera frame rate (frames per second): a frame every 10 s tracks nothing; 10 kHz is a
/// high-speed camera.
pub const FPS: Bound = Bound::closed(
    0.1,
    10_000.0,
    " fps",
    "a frame every 10 s tracks nothing, 10 kHz is a high-speed camera",
);

/// Most pixels of one frame: 32 Mpx (a 16-byte-per-pixel emulator frame is 512 MiB, a
/// quarter of the memory budget).
pub const MAX_FRAME_PIXELS: u64 = 1 << 25;

/// A validated rig description.
#[derive(Debug, Clone, PartialEq)]
pub struct RigConfig {
    /// Rig name (free text).
    pub name: String,
    /// Where the rig file came from.
    pub source: String,
    /// The coil link, calibration and limits.
    pub coil: CoilConfig,
    /// Where frames come from.
    pub camera: CameraConfig,
    /// Pixel ↔ BL calibration.
    pub pixels: PixelMap,
    /// Detector parameters.
    pub detector: DetectorConfig,
}

/// Where the coil driver is reached.
#[derive(Debug, Clone, PartialEq)]
pub enum CoilEndpoint {
    /// A serial port (or a pseudo-terminal) at a baud rate.
    Serial {
        /// Device path, e.g. `/dev/ttyUSB0`.
        path: String,
        /// Baud rate.
        baud: u32,
    },
    /// A TCP address `HOST:PORT`.
    Tcp(String),
}

/// The coil link, its calibration and its limits.
#[derive(Debug, Clone, PartialEq)]
pub struct CoilConfig {
    /// Where the coil driver is.
    pub endpoint: CoilEndpoint,
    /// Host heartbeat period (ms) when no command is sent.
    pub heartbeat_ms: u32,
    /// Device watchdog (ms): the device zeroes its currents after this long without a message.
    pub watchdog_ms: u32,
    /// Time to wait for an acknowledgement before resending (ms).
    pub ack_timeout_ms: u32,
    /// Resends of one message before the link is declared lost.
    pub retries: u32,
    /// Host-side hold timeout (ms): a non-zero field with no new command for this long is zeroed.
    pub hold_timeout_ms: u32,
    /// Field magnitude (mT); `None` takes the scenario's `physics.field_mt`.
    pub field_mt: Option<f64>,
    /// Largest field elevation |α| the coil can set (degrees, in [0, 90]): 90 for a tri-axial
    /// Helmholtz coil (the default), 0 for a planar coil set. Plans and trackers stay within it.
    pub alpha_max_deg: f64,
    /// Currents ↔ field and gradient.
    pub calibration: Calibration,
    /// Largest |current| per channel (A).
    pub current_limit_a: Vec<f64>,
    /// Largest current change rate per channel (A/s).
    pub slew_a_per_s: f64,
}

/// Where frames come from.
#[derive(Debug, Clone, PartialEq)]
pub enum CameraSource {
    /// The emulator's frame stream at a TCP address.
    Emulator(String),
    /// A folder of recorded PGM/PNG frames.
    Recorded(PathBuf),
    /// A V4L2 device (cargo feature `v4l2`).
    V4l2(String),
}

/// The camera.
#[derive(Debug, Clone, PartialEq)]
pub struct CameraConfig {
    /// Frame source.
    pub source: CameraSource,
    /// Nominal frame rate (frames per second).
    pub fps: f64,
    /// Sensor size in pixels `[width, height]`.
    pub size_px: [u32; 2],
    /// No frame for this long is a camera failure (ms).
    pub frame_timeout_ms: u32,
    /// This many identical (stuck) frames in a row is a camera failure.
    pub stuck_frames: u32,
    /// Capture to delivery latency of the camera pipeline (s), predicted over by the tracker.
    pub latency_s: f64,
}

/// Dark or bright agents on the background.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Polarity {
    /// Agents darker than the background.
    Dark,
    /// Agents brighter than the background.
    Bright,
}

/// Detector parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct DetectorConfig {
    /// Dark or bright agents.
    pub polarity: Polarity,
    /// Agent radius in pixels.
    pub radius_px: f64,
    /// Edge blur (Gaussian σ, pixels) of the disk model.
    pub blur_px: f64,
    /// Grey level separating agents from the background.
    pub threshold: u8,
    /// Largest move of an agent between two frames (BL) kept as the same agent.
    pub max_jump_bl: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RigFile {
    #[serde(default)]
    name: String,
    coil: CoilFile,
    camera: CameraFile,
    pixels: PixelsFile,
    detector: DetectorFile,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CoilFile {
    port: Option<String>,
    address: Option<String>,
    #[serde(default = "default_baud")]
    baud: u32,
    #[serde(default = "default_heartbeat")]
    heartbeat_ms: u32,
    #[serde(default = "default_watchdog")]
    watchdog_ms: u32,
    #[serde(default = "default_ack_timeout")]
    ack_timeout_ms: u32,
    #[serde(default = "default_retries")]
    retries: u32,
    #[serde(default = "default_hold_timeout")]
    hold_timeout_ms: u32,
    field_mt: Option<f64>,
    #[serde(default = "default_alpha_max")]
    alpha_max_deg: f64,
    calibration: CalibrationFile,
    limits: LimitsFile,
}

fn default_alpha_max() -> f64 {
    magbench_env::coil::COIL_ALPHA_MAX_DEG
}
fn default_baud() -> u32 {
    115_200
}
fn default_heartbeat() -> u32 {
    50
}
fn default_watchdog() -> u32 {
    200
}
fn default_ack_timeout() -> u32 {
    10
}
fn default_retries() -> u32 {
    2
}
fn default_hold_timeout() -> u32 {
    250
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CalibrationFile {
    field_mt_per_a: Option<Fixed<f64, 3>>,
    gradient_mt_per_m_per_a: Option<Fixed<f64, 2>>,
    matrix: Option<Vec<Vec<f64>>>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum OneOrMany {
    One(f64),
    Many(Vec<f64>),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LimitsFile {
    current_a: OneOrMany,
    slew_a_per_s: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraFile {
    source: String,
    address: Option<String>,
    folder: Option<String>,
    device: Option<String>,
    #[serde(default = "default_fps")]
    fps: f64,
    size_px: Fixed<u32, 2>,
    #[serde(default = "default_frame_timeout")]
    frame_timeout_ms: u32,
    #[serde(default = "default_stuck")]
    stuck_frames: u32,
    #[serde(default)]
    latency_ms: f64,
}

fn default_fps() -> f64 {
    60.0
}
fn default_frame_timeout() -> u32 {
    100
}
fn default_stuck() -> u32 {
    30
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PixelsFile {
    px_per_bl: f64,
    origin_px: Fixed<f64, 2>,
    #[serde(default)]
    rotation_deg: f64,
    #[serde(default = "default_true")]
    flip_y: bool,
}

fn default_true() -> bool {
    true
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DetectorFile {
    polarity: String,
    radius_px: f64,
    #[serde(default = "default_blur")]
    blur_px: f64,
    threshold: u8,
    #[serde(default = "default_jump")]
    max_jump_bl: f64,
}

fn default_blur() -> f64 {
    1.0
}
fn default_jump() -> f64 {
    1.0
}

impl RigConfig {
    /// Reads and validates a rig file.
    pub fn load(path: &Path) -> Result<RigConfig, InputError> {
        let file = path.display().to_string();
        let text = read_text(path, &file)?;
        let mut cfg = Self::parse(&text, &file)?;
        // a recorded-frames folder is relative to the rig file
        if let CameraSource::Recorded(p) = &cfg.camera.source
            && p.is_relative()
            && let Some(dir) = path.parent()
        {
            cfg.camera.source = CameraSource::Recorded(dir.join(p));
        }
        Ok(cfg)
    }

    /// Parses and validates rig TOML `text`; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<RigConfig, InputError> {
        let raw: RigFile = parse_toml(text, file)?;
        let ck = Checker::new(file);
        let coil = coil(ck, raw.coil)?;
        let camera = camera(ck, raw.camera)?;
        let pixels = pixels(ck, raw.pixels)?;
        let detector = detector(ck, raw.detector)?;
        Ok(RigConfig {
            name: raw.name,
            source: file.to_string(),
            coil,
            camera,
            pixels,
            detector,
        })
    }

    /// The rig file text with the coil endpoint and camera address replaced (for a live emulator).
    pub fn with_endpoints(
        text: &str,
        coil: &CoilEndpoint,
        camera_address: Option<&str>,
    ) -> Result<String, EndpointsError> {
        let mut doc: toml::Table = toml::from_str(text)?;
        let coil_t = doc
            .get_mut("coil")
            .and_then(|c| c.as_table_mut())
            .ok_or(EndpointsError::NoTable("coil"))?;
        coil_t.remove("port");
        coil_t.remove("address");
        match coil {
            CoilEndpoint::Serial { path, .. } => coil_t.insert("port".into(), path.clone().into()),
            CoilEndpoint::Tcp(a) => coil_t.insert("address".into(), a.clone().into()),
        };
        if let Some(addr) = camera_address {
            let cam = doc
                .get_mut("camera")
                .and_then(|c| c.as_table_mut())
                .ok_or(EndpointsError::NoTable("camera"))?;
            cam.insert("source".into(), "emulator".into());
            cam.insert("address".into(), addr.into());
        }
        Ok(toml::to_string(&doc)?)
    }
}

/// Why [`RigConfig::with_endpoints`] cannot rewrite a rig file's text.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EndpointsError {
    /// The text is not TOML.
    #[error("{0}")]
    Parse(#[from] toml::de::Error),
    /// The rewritten table cannot be written back as TOML.
    #[error("{0}")]
    Write(#[from] toml::ser::Error),
    /// The text lacks a table (`coil`, `camera`).
    #[error("no [{0}] table")]
    NoTable(&'static str),
}

fn coil(ck: Checker, c: CoilFile) -> Result<CoilConfig, InputError> {
    let endpoint = match (c.port, c.address) {
        (Some(path), None) => {
            if c.baud == 0 {
                return Err(ck.err("coil.baud", "must be > 0"));
            }
            CoilEndpoint::Serial { path, baud: c.baud }
        }
        (None, Some(a)) => {
            if !a.contains(':') {
                return Err(ck.err("coil.address", format!("must be HOST:PORT, got {a:?}")));
            }
            CoilEndpoint::Tcp(a)
        }
        (Some(_), Some(_)) => {
            return Err(ck.err("coil", "has both `port` and `address`; give one"));
        }
        (None, None) => {
            return Err(ck.err("coil", "needs `port` (serial) or `address` (TCP)"));
        }
    };
    for (f, x) in [
        ("coil.heartbeat_ms", c.heartbeat_ms),
        ("coil.watchdog_ms", c.watchdog_ms),
        ("coil.ack_timeout_ms", c.ack_timeout_ms),
        ("coil.hold_timeout_ms", c.hold_timeout_ms),
    ] {
        if x == 0 {
            return Err(ck.err(f, "must be > 0"));
        }
    }
    if c.heartbeat_ms * 2 > c.watchdog_ms {
        return Err(ck.err(
                "coil.heartbeat_ms",
                format!("must be at most half of watchdog_ms = {} so one lost heartbeat does not trip it, got {}", c.watchdog_ms, c.heartbeat_ms),
            ));
    }
    if c.watchdog_ms > u16::MAX as u32 {
        return Err(ck.err(
            "coil.watchdog_ms",
            format!("must be ≤ {}, got {}", u16::MAX, c.watchdog_ms),
        ));
    }
    if let Some(f) = c.field_mt {
        ck.positive("coil.field_mt", f)?;
        ck.bound(
            "coil.field_mt",
            f,
            &Bound::above(
                0.0,
                magbench_env::physics::MAX_FIELD_MT,
                " mT",
                "1 T is beyond what coil systems for microrobots make",
            ),
        )?;
    }
    if !(c.alpha_max_deg.is_finite() && (0.0..=90.0).contains(&c.alpha_max_deg)) {
        return Err(ck.err(
                "coil.alpha_max_deg",
                format!(
                    "must be an elevation in [0, 90]° (90 for a tri-axial coil, 0 for a planar coil set), got {}",
                    c.alpha_max_deg
                ),
            ));
    }
    let calibration = calibration(ck, &c.calibration)?;
    let n = calibration.channels();
    let current_limit_a = match c.limits.current_a {
        OneOrMany::One(x) => vec![ck.positive("coil.limits.current_a", x)?; n],
        OneOrMany::Many(v) => {
            if v.len() != n {
                return Err(ck.err(
                    "coil.limits.current_a",
                    format!(
                        "has {} limits but the calibration has {n} channels",
                        v.len()
                    ),
                ));
            }
            for (i, x) in v.iter().enumerate() {
                ck.positive(&format!("coil.limits.current_a[{i}]"), *x)?;
            }
            v
        }
    };
    let slew_a_per_s = ck.positive("coil.limits.slew_a_per_s", c.limits.slew_a_per_s)?;
    Ok(CoilConfig {
        endpoint,
        heartbeat_ms: c.heartbeat_ms,
        watchdog_ms: c.watchdog_ms,
        ack_timeout_ms: c.ack_timeout_ms,
        retries: c.retries,
        hold_timeout_ms: c.hold_timeout_ms,
        field_mt: c.field_mt,
        alpha_max_deg: c.alpha_max_deg,
        calibration,
        current_limit_a,
        slew_a_per_s,
    })
}

fn calibration(ck: Checker, c: &CalibrationFile) -> Result<Calibration, InputError> {
    let f = "coil.calibration";
    match (&c.field_mt_per_a, &c.gradient_mt_per_m_per_a, &c.matrix) {
        (Some(Fixed(b)), Some(Fixed(g)), None) => {
            for (i, x) in b.iter().enumerate() {
                ck.positive(&format!("{f}.field_mt_per_a[{i}]"), *x)?;
            }
            for (i, x) in g.iter().enumerate() {
                ck.positive(&format!("{f}.gradient_mt_per_m_per_a[{i}]"), *x)?;
            }
            Ok(Calibration::per_axis(*b, *g))
        }
        (None, None, Some(m)) => {
            if m.len() != 5 {
                return Err(ck.err(
                    format!("{f}.matrix"),
                    format!(
                        "needs 5 rows (Bx, By, Bz in mT/A; Gx, Gy in mT/m/A), got {}",
                        m.len()
                    ),
                ));
            }
            let n = m[0].len();
            if !(5..=32).contains(&n) {
                return Err(ck.err(
                    format!("{f}.matrix[0]"),
                    format!("needs 5 to 32 channels (columns), got {n}"),
                ));
            }
            for (i, row) in m.iter().enumerate() {
                if row.len() != n {
                    return Err(ck.err(
                        format!("{f}.matrix[{i}]"),
                        format!("has {} columns, row 0 has {n}", row.len()),
                    ));
                }
                for (j, x) in row.iter().enumerate() {
                    ck.finite(&format!("{f}.matrix[{i}][{j}]"), *x)?;
                }
            }
            Calibration::matrix(m).map_err(|r| ck.err(format!("{f}.matrix"), r.to_string()))
        }
        (None, None, None) => Err(ck.err(
            f,
            "needs `field_mt_per_a` and `gradient_mt_per_m_per_a`, or `matrix`",
        )),
        (_, _, Some(_)) => Err(ck.err(f, "has both per-axis constants and `matrix`; give one")),
        (None, Some(_), None) => Err(ck.err(
            format!("{f}.field_mt_per_a"),
            "missing (needed with gradient_mt_per_m_per_a)",
        )),
        (Some(_), None, None) => Err(ck.err(
            format!("{f}.gradient_mt_per_m_per_a"),
            "missing (needed with field_mt_per_a)",
        )),
    }
}

fn camera(ck: Checker, c: CameraFile) -> Result<CameraConfig, InputError> {
    let fps = ck.bound("camera.fps", c.fps, &FPS)?;
    let need = |v: Option<String>, key: &str| {
        v.ok_or_else(|| {
            ck.err(
                format!("camera.{key}"),
                format!("missing (needed by source = {:?})", c.source),
            )
        })
    };
    let source = match c.source.as_str() {
        "emulator" => CameraSource::Emulator(need(c.address, "address")?),
        "recorded" => CameraSource::Recorded(PathBuf::from(need(c.folder, "folder")?)),
        "v4l2" => CameraSource::V4l2(need(c.device, "device")?),
        other => {
            return Err(ck.err(
                "camera.source",
                format!("unknown source {other:?}; use emulator, recorded or v4l2"),
            ));
        }
    };
    let [w, h] = c.size_px.0;
    if !(8..=16384).contains(&w) || !(8..=16384).contains(&h) {
        return Err(ck.err(
            "camera.size_px",
            format!("each side must be 8 to 16384 pixels, got {w} x {h}"),
        ));
    }
    if w as u64 * h as u64 > MAX_FRAME_PIXELS {
        return Err(ck.err(
                "camera.size_px",
                format!(
                    "a frame has at most {MAX_FRAME_PIXELS} pixels (32 Mpx: an emulated frame takes 16 bytes a pixel, a quarter of the {} GiB memory budget), got {w} x {h}",
                    magbench_env::check::MEMORY_BUDGET_BYTES >> 30
                ),
            ));
    }
    if c.frame_timeout_ms == 0 {
        return Err(ck.err("camera.frame_timeout_ms", "must be > 0"));
    }
    if c.stuck_frames < 2 {
        return Err(ck.err(
            "camera.stuck_frames",
            format!("must be ≥ 2, got {}", c.stuck_frames),
        ));
    }
    if !(c.latency_ms.is_finite() && (0.0..=1000.0).contains(&c.latency_ms)) {
        return Err(ck.err(
            "camera.latency_ms",
            format!("must be 0 to 1000 ms, got {}", c.latency_ms),
        ));
    }
    Ok(CameraConfig {
        source,
        fps,
        size_px: c.size_px.0,
        frame_timeout_ms: c.frame_timeout_ms,
        stuck_frames: c.stuck_frames,
        latency_s: c.latency_ms * 1e-3,
    })
}

fn pixels(ck: Checker, p: PixelsFile) -> Result<PixelMap, InputError> {
    let scale = ck.bound("pixels.px_per_bl", p.px_per_bl, &PX_PER_BL)?;
    let ox = ck.finite("pixels.origin_px[0]", p.origin_px.0[0])?;
    let oy = ck.finite("pixels.origin_px[1]", p.origin_px.0[1])?;
    let rot = ck.finite("pixels.rotation_deg", p.rotation_deg)?;
    Ok(PixelMap::new(scale, [ox, oy], rot.to_radians(), p.flip_y))
}

fn detector(ck: Checker, d: DetectorFile) -> Result<DetectorConfig, InputError> {
    let polarity = match d.polarity.as_str() {
        "dark" => Polarity::Dark,
        "bright" => Polarity::Bright,
        other => {
            return Err(ck.err(
                "detector.polarity",
                format!("must be \"dark\" or \"bright\", got {other:?}"),
            ));
        }
    };
    let radius_px = ck.positive("detector.radius_px", d.radius_px)?;
    if radius_px < 2.0 {
        return Err(ck.err(
            "detector.radius_px",
            format!("must be ≥ 2 pixels for sub-pixel detection, got {radius_px}"),
        ));
    }
    let blur_px = ck.positive("detector.blur_px", d.blur_px)?;
    ck.bound("detector.blur_px", blur_px, &BLUR_PX)?;
    if radius_px > 0.5 * PX_PER_BL.hi {
        return Err(ck.err(
            "detector.radius_px",
            format!(
                "must be at most {} px (half of pixels.px_per_bl's bound), got {radius_px}",
                0.5 * PX_PER_BL.hi
            ),
        ));
    }
    let max_jump_bl = ck.positive("detector.max_jump_bl", d.max_jump_bl)?;
    Ok(DetectorConfig {
        polarity,
        radius_px,
        blur_px,
        threshold: d.threshold,
        max_jump_bl,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) const EXAMPLE: &str = include_str!("../../rigs/emulator.toml");

    #[test]
    fn the_example_rig_file_is_valid() {
        let r = RigConfig::parse(EXAMPLE, "emulator.toml").unwrap();
        assert_eq!(r.coil.calibration.channels(), 5);
        assert_eq!(r.coil.watchdog_ms, 200);
        assert_eq!(r.coil.alpha_max_deg, 90.0);
        assert!(matches!(r.camera.source, CameraSource::Emulator(_)));
    }

    fn err(text: &str) -> String {
        RigConfig::parse(text, "r.toml").unwrap_err().to_string()
    }

    #[test]
    fn errors_name_file_field_and_reason() {
        let bad = EXAMPLE.replace("px_per_bl = 10.0", "px_per_bl = -1.0");
        assert_eq!(
            err(&bad),
            "r.toml: pixels.px_per_bl: must be in (0, 1000] px/BL: an agent 1000 px across already fills a sensor side, got -1"
        );
        let bad = EXAMPLE.replace("[pixels]", "[pixels]\ncolour = 3");
        assert!(
            err(&bad).starts_with("r.toml: pixels.colour: unknown field `colour`"),
            "{}",
            err(&bad)
        );
        let bad = EXAMPLE.replace("polarity = \"dark\"", "polarity = \"grey\"");
        assert!(err(&bad).starts_with("r.toml: detector.polarity: "));
        let bad = EXAMPLE.replace("current_a = 8.0", "current_a = [8.0, 8.0]");
        assert!(
            err(&bad).starts_with("r.toml: coil.limits.current_a: has 2 limits"),
            "{}",
            err(&bad)
        );
        let bad = EXAMPLE.replace("alpha_max_deg = 90.0", "alpha_max_deg = 120.0");
        assert!(
            err(&bad).starts_with("r.toml: coil.alpha_max_deg: must be an elevation in [0, 90]")
        );
        let bad = EXAMPLE.replace("heartbeat_ms = 50", "heartbeat_ms = 150");
        assert!(err(&bad).starts_with("r.toml: coil.heartbeat_ms: must be at most half"));
    }

    #[test]
    fn endpoints_can_be_replaced() {
        let text = RigConfig::with_endpoints(
            EXAMPLE,
            &CoilEndpoint::Serial {
                path: "/tmp/pty".into(),
                baud: 115200,
            },
            Some("127.0.0.1:9"),
        )
        .unwrap();
        let r = RigConfig::parse(&text, "x").unwrap();
        assert_eq!(
            r.coil.endpoint,
            CoilEndpoint::Serial {
                path: "/tmp/pty".into(),
                baud: 115200
            }
        );
        assert_eq!(
            r.camera.source,
            CameraSource::Emulator("127.0.0.1:9".into())
        );
    }
}
