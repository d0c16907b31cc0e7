//! The rig file (TOML): coil link and calibration, camera source, pixel calibration, detector.
//!
//! Parsed with `deny_unknown_fields` and validated like scenario files: every rejection is an
//! [`InputError`] `FILE: FIELD: REASON`. See docs/rigs.md for the format.

use std::path::{Path, PathBuf};

use magbench_env::InputError;
use magbench_env::input::bounds::number;
use magbench_env::input::{Bound, Fixed, InputChecks, parse_toml, read_text};
use serde::Deserialize;

use crate::calibration::Calibration;
use crate::pixel_map::PixelMap;
use crate::protocol::{AckStatus, Message, WATCHDOG_MAX_MS, WATCHDOG_MIN_MS, encode};

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

/// Longest host hold timeout (ms): the device's longest watchdog
/// ([`WATCHDOG_MAX_MS`]). The hold timeout and the watchdog guard the same hazard, a field that
/// nothing steers: a live host whose control loop stalled (its keep-alive thread still satisfying
/// the watchdog) must zero the field no later than the device zeroes it for a dead host.
pub const MAX_HOLD_TIMEOUT_MS: u32 = WATCHDOG_MAX_MS as u32;

/// Largest current limit per channel (A): coil drivers for microrobots supply tens of amperes;
/// 1 kA per channel is beyond any of them.
pub const CURRENT_LIMIT_A: Bound = Bound::above(
    0.0,
    1000.0,
    " A",
    "1 kA a channel is beyond any coil driver for microrobots",
);

/// Largest current slew limit (A/s): a swing across the widest current range
/// (2 × [`CURRENT_LIMIT_A`]'s 1 kA) within the shortest frame ([`FPS`]'s 10 kHz: 0.1 ms) is
/// 2 × 10⁷ A/s. A larger limit never binds, so it would claim a protection it does not give.
pub const SLEW_A_PER_S: Bound = Bound::above(
    0.0,
    2.0e7,
    " A/s",
    "a swing of 2 kA (±1 kA, coil.limits.current_a's bound) in 0.1 ms (a frame at 10 kHz, camera.fps's bound); a larger limit never binds",
);

/// Image rotation (degrees): one turn either way; a larger angle only loses precision.
pub const ROTATION_DEG: Bound = Bound::closed(
    -360.0,
    360.0,
    "°",
    "one turn either way covers every orientation",
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
        let ck = InputChecks::new(file);
        let coil = coil(ck, raw.coil)?;
        let camera = camera(ck, raw.camera)?;
        loop_timing(ck, &coil, &camera)?;
        let pixels = pixels(ck, raw.pixels)?;
        let detector = detector(ck, raw.detector, &camera, &pixels)?;
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

fn coil(ck: InputChecks, c: CoilFile) -> Result<CoilConfig, InputError> {
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
    timers(ck, &c)?;
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
    if let CoilEndpoint::Serial { baud: b, .. } = &endpoint {
        baud(ck, *b, n, c.ack_timeout_ms)?;
    }
    let current_limit_a = match c.limits.current_a {
        OneOrMany::One(x) => vec![ck.bound("coil.limits.current_a", x, &CURRENT_LIMIT_A)?; n],
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
                ck.bound(&format!("coil.limits.current_a[{i}]"), *x, &CURRENT_LIMIT_A)?;
            }
            v
        }
    };
    let slew_a_per_s = ck.bound(
        "coil.limits.slew_a_per_s",
        c.limits.slew_a_per_s,
        &SLEW_A_PER_S,
    )?;
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

/// The coil link's timers, each bounded by what it is for; every sum and product is taken in
/// `u64`, so no accepted `u32` can wrap it.
fn timers(ck: InputChecks, c: &CoilFile) -> Result<(), InputError> {
    let (lo, hi) = (u32::from(WATCHDOG_MIN_MS), u32::from(WATCHDOG_MAX_MS));
    if !(lo..=hi).contains(&c.watchdog_ms) {
        return Err(ck.err(
            "coil.watchdog_ms",
            format!(
                "must be in [{lo}, {hi}] ms: the device clamps the watchdog it is asked for to this range, so another value is not the one in force, got {}",
                c.watchdog_ms
            ),
        ));
    }
    let (heartbeat, watchdog) = (u64::from(c.heartbeat_ms), u64::from(c.watchdog_ms));
    if heartbeat * 2 > watchdog {
        return Err(ck.err(
            "coil.heartbeat_ms",
            format!(
                "must be at most half of watchdog_ms = {watchdog} so one lost heartbeat does not trip it, got {heartbeat}"
            ),
        ));
    }
    let ack = u64::from(c.ack_timeout_ms);
    if heartbeat + ack > watchdog {
        return Err(ck.err(
            "coil.ack_timeout_ms",
            format!(
                "must be at most watchdog_ms − heartbeat_ms = {} ms so the resend of a lost heartbeat reaches the device before its watchdog trips, got {ack}",
                watchdog - heartbeat
            ),
        ));
    }
    let hold = u64::from(c.hold_timeout_ms);
    if hold > u64::from(MAX_HOLD_TIMEOUT_MS) {
        return Err(ck.err(
            "coil.hold_timeout_ms",
            format!(
                "must be at most {MAX_HOLD_TIMEOUT_MS} ms: a stalled control loop may keep the field on no longer than the device's longest watchdog keeps it on for a dead host, got {hold}"
            ),
        ));
    }
    let give_up = (u64::from(c.retries) + 1) * ack;
    if give_up > hold {
        return Err(ck.err(
            "coil.retries",
            format!(
                "(retries + 1) × ack_timeout_ms = {give_up} ms must be at most hold_timeout_ms = {hold} ms: while a message waits for its acknowledgement nothing can zero the field, got retries = {}",
                c.retries
            ),
        ));
    }
    Ok(())
}

/// The serial link must carry the longest exchange (SET_CURRENTS of every channel and its ACK,
/// 10 bits a byte) within `ack_timeout_ms`, or every message would time out.
fn baud(
    ck: InputChecks,
    baud: u32,
    channels: usize,
    ack_timeout_ms: u32,
) -> Result<(), InputError> {
    let ack = Message::Ack {
        seq: 0,
        status: AckStatus::Ok,
        flags: 0,
        device_ms: 0,
    };
    let bytes = (encode(0, &Message::SetCurrents(vec![0.0; channels])).len()
        + encode(0, &ack).len()) as u64;
    if bytes * 10 * 1000 > u64::from(baud) * u64::from(ack_timeout_ms) {
        return Err(ck.err(
            "coil.baud",
            format!(
                "must carry a SET_CURRENTS of {channels} channels and its ACK ({bytes} bytes, 10 bits a byte) within ack_timeout_ms = {ack_timeout_ms}: that needs at least {} baud, got {baud}",
                (bytes * 10 * 1000).div_ceil(u64::from(ack_timeout_ms))
            ),
        ));
    }
    Ok(())
}

/// The bounds that tie the coil timers to the camera: the loop renews the field once a frame.
fn loop_timing(
    ck: InputChecks,
    coil: &CoilConfig,
    camera: &CameraConfig,
) -> Result<(), InputError> {
    let period_ms = 1000.0 / camera.fps;
    let hold = coil.hold_timeout_ms;
    if f64::from(hold) <= period_ms {
        return Err(ck.err(
            "coil.hold_timeout_ms",
            format!(
                "must be longer than one frame period (1000 / camera.fps = {} ms): the loop renews the field once a frame, got {hold}",
                number(period_ms)
            ),
        ));
    }
    let ft = camera.frame_timeout_ms;
    if f64::from(ft) <= period_ms {
        return Err(ck.err(
            "camera.frame_timeout_ms",
            format!(
                "must be longer than one frame period (1000 / camera.fps = {} ms) or every frame is late, got {ft}",
                number(period_ms)
            ),
        ));
    }
    if ft > hold {
        return Err(ck.err(
            "camera.frame_timeout_ms",
            format!(
                "must be at most coil.hold_timeout_ms = {hold}: frames that stop for longer have the field zeroed by the hold timeout first, so a longer wait only delays the stop, got {ft}"
            ),
        ));
    }
    let blind_ms = f64::from(camera.stuck_frames) * 1000.0 / camera.fps;
    if blind_ms > f64::from(MAX_HOLD_TIMEOUT_MS) {
        return Err(ck.err(
            "camera.stuck_frames",
            format!(
                "must be at most {} at {} fps: the loop steers on a frozen image until the count is reached, and may do so for at most {MAX_HOLD_TIMEOUT_MS} ms (the longest the field may go unsteered, coil.hold_timeout_ms's bound), got {} ({} ms)",
                (f64::from(MAX_HOLD_TIMEOUT_MS) * camera.fps / 1000.0).floor(),
                number(camera.fps),
                camera.stuck_frames,
                number(blind_ms),
            ),
        ));
    }
    Ok(())
}

fn calibration(ck: InputChecks, c: &CalibrationFile) -> Result<Calibration, InputError> {
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

fn camera(ck: InputChecks, c: CameraFile) -> Result<CameraConfig, InputError> {
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
                    magbench_env::input::MEMORY_BUDGET_BYTES >> 30
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

fn pixels(ck: InputChecks, p: PixelsFile) -> Result<PixelMap, InputError> {
    let scale = ck.bound("pixels.px_per_bl", p.px_per_bl, &PX_PER_BL)?;
    let ox = ck.finite("pixels.origin_px[0]", p.origin_px.0[0])?;
    let oy = ck.finite("pixels.origin_px[1]", p.origin_px.0[1])?;
    let rot = ck.bound("pixels.rotation_deg", p.rotation_deg, &ROTATION_DEG)?;
    Ok(PixelMap::new(scale, [ox, oy], rot.to_radians(), p.flip_y))
}

fn detector(
    ck: InputChecks,
    d: DetectorFile,
    camera: &CameraConfig,
    pixels: &PixelMap,
) -> Result<DetectorConfig, InputError> {
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
    let [w, h] = camera.size_px;
    let diagonal_bl = f64::from(w).hypot(f64::from(h)) / pixels.px_per_bl;
    if max_jump_bl > diagonal_bl {
        return Err(ck.err(
            "detector.max_jump_bl",
            format!(
                "must be at most the sensor's diagonal ({diagonal_bl:.1} BL at pixels.px_per_bl = {}): a longer move leaves the image, got {}",
                number(pixels.px_per_bl),
                number(max_jump_bl)
            ),
        ));
    }
    if !(1..=254).contains(&d.threshold) {
        return Err(ck.err(
            "detector.threshold",
            format!(
                "must be in [1, 254]: 0 and 255 are the ends of the grey range and separate nothing from the background, got {}",
                d.threshold
            ),
        ));
    }
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

    /// The example with `from` replaced by `to` (which must be in it).
    fn with(from: &str, to: &str) -> String {
        assert!(EXAMPLE.contains(from), "{from}");
        EXAMPLE.replace(from, to)
    }

    #[test]
    fn a_heartbeat_that_wraps_32_bits_is_refused() {
        // 2 × 2147483698 wraps to 100 in 32 bits, which is at most half of 200
        let e = err(&with("heartbeat_ms = 50", "heartbeat_ms = 2147483698"));
        assert!(
            e.starts_with("r.toml: coil.heartbeat_ms: must be at most half of watchdog_ms = 200"),
            "{e}"
        );
        assert!(e.ends_with("got 2147483698"), "{e}");
        let e = err(&with(
            "heartbeat_ms = 50",
            &format!("heartbeat_ms = {}", u32::MAX),
        ));
        assert!(e.starts_with("r.toml: coil.heartbeat_ms: "), "{e}");
        // exactly half is accepted
        RigConfig::parse(&with("heartbeat_ms = 50", "heartbeat_ms = 100"), "r.toml").unwrap();
    }

    #[test]
    fn a_watchdog_outside_what_the_device_enforces_is_refused() {
        for w in ["65535", "1001", "19", "4294967295"] {
            let e = err(&with("watchdog_ms = 200", &format!("watchdog_ms = {w}")));
            assert!(
                e.starts_with(&format!(
                    "r.toml: coil.watchdog_ms: must be in [{WATCHDOG_MIN_MS}, {WATCHDOG_MAX_MS}] ms: the device clamps"
                )),
                "{e}"
            );
            assert!(e.ends_with(&format!("got {w}")), "{e}");
        }
        let r = RigConfig::parse(&with("watchdog_ms = 200", "watchdog_ms = 1000"), "r.toml");
        assert_eq!(r.unwrap().coil.watchdog_ms, u32::from(WATCHDOG_MAX_MS));
    }

    #[test]
    fn a_hold_timeout_beyond_the_safety_limit_is_refused() {
        for h in ["1000000000", "1001"] {
            let e = err(&with(
                "hold_timeout_ms = 250",
                &format!("hold_timeout_ms = {h}"),
            ));
            assert_eq!(
                e,
                format!(
                    "r.toml: coil.hold_timeout_ms: must be at most {MAX_HOLD_TIMEOUT_MS} ms: a stalled control loop may keep the field on no longer than the device's longest watchdog keeps it on for a dead host, got {h}"
                )
            );
        }
        let r = RigConfig::parse(
            &with("hold_timeout_ms = 250", "hold_timeout_ms = 1000"),
            "r.toml",
        );
        assert_eq!(r.unwrap().coil.hold_timeout_ms, MAX_HOLD_TIMEOUT_MS);
        // at 2 fps the loop renews the field every 500 ms, after the 250 ms hold
        let e = err(&with("fps = 60.0", "fps = 2.0"));
        assert!(
            e.starts_with("r.toml: coil.hold_timeout_ms: must be longer than one frame period"),
            "{e}"
        );
    }

    #[test]
    fn link_timers_that_would_outlast_the_watchdog_or_the_hold_are_refused() {
        // a lost heartbeat's resend (after 50 + 151 ms) would come after the 200 ms watchdog
        let e = err(&with("ack_timeout_ms = 20", "ack_timeout_ms = 151"));
        assert!(
            e.starts_with(
                "r.toml: coil.ack_timeout_ms: must be at most watchdog_ms − heartbeat_ms = 150 ms"
            ),
            "{e}"
        );
        let e = err(&with(
            "ack_timeout_ms = 20",
            &format!("ack_timeout_ms = {}", u32::MAX),
        ));
        assert!(e.starts_with("r.toml: coil.ack_timeout_ms: "), "{e}");
        // 4294967295 + 1 retries would wrap 32 bits to 0
        let e = err(&with("retries = 3", &format!("retries = {}", u32::MAX)));
        assert!(
            e.starts_with("r.toml: coil.retries: (retries + 1) × ack_timeout_ms = 85899345920 ms must be at most hold_timeout_ms = 250 ms"),
            "{e}"
        );
        let e = err(&with("retries = 3", "retries = 12"));
        assert!(
            e.starts_with("r.toml: coil.retries: (retries + 1) × ack_timeout_ms = 260 ms"),
            "{e}"
        );
        RigConfig::parse(&with("retries = 3", "retries = 11"), "r.toml").unwrap();
    }

    #[test]
    fn a_serial_link_too_slow_for_the_ack_timeout_is_refused() {
        let serial = with("address = \"127.0.0.1:7700\"", "port = \"/dev/ttyUSB0\"");
        let r = RigConfig::parse(&serial, "r.toml").unwrap();
        assert!(matches!(
            r.coil.endpoint,
            CoilEndpoint::Serial { baud: 115_200, .. }
        ));
        // 5 channels: SET_CURRENTS 31 bytes + ACK 18 bytes = 490 bits, 25.5 ms at 19200 baud
        let slow = serial.replace("heartbeat_ms = 50", "baud = 19200\nheartbeat_ms = 50");
        let e = err(&slow);
        assert_eq!(
            e,
            "r.toml: coil.baud: must carry a SET_CURRENTS of 5 channels and its ACK (49 bytes, 10 bits a byte) within ack_timeout_ms = 20: that needs at least 24500 baud, got 19200"
        );
        RigConfig::parse(
            &serial.replace("heartbeat_ms = 50", "baud = 24500\nheartbeat_ms = 50"),
            "r.toml",
        )
        .unwrap();
    }

    #[test]
    fn camera_timers_are_bounded_by_the_frame_period_and_the_hold() {
        let e = err(&with("frame_timeout_ms = 100", "frame_timeout_ms = 16"));
        assert!(
            e.starts_with("r.toml: camera.frame_timeout_ms: must be longer than one frame period"),
            "{e}"
        );
        let e = err(&with(
            "frame_timeout_ms = 100",
            &format!("frame_timeout_ms = {}", u32::MAX),
        ));
        assert!(
            e.starts_with(
                "r.toml: camera.frame_timeout_ms: must be at most coil.hold_timeout_ms = 250"
            ),
            "{e}"
        );
        // 61 frames at 60 fps are more than a second of steering on a frozen image
        let e = err(&with("stuck_frames = 30", "stuck_frames = 61"));
        assert!(
            e.starts_with("r.toml: camera.stuck_frames: must be at most 60 at 60 fps"),
            "{e}"
        );
        RigConfig::parse(&with("stuck_frames = 30", "stuck_frames = 60"), "r.toml").unwrap();
        let e = err(&with(
            "stuck_frames = 30",
            &format!("stuck_frames = {}", u32::MAX),
        ));
        assert!(e.starts_with("r.toml: camera.stuck_frames: "), "{e}");
    }

    #[test]
    fn currents_angles_thresholds_and_jumps_are_bounded() {
        let e = err(&with("current_a = 8.0", "current_a = 1e300"));
        assert!(
            e.starts_with("r.toml: coil.limits.current_a: must be in (0, 1000] A: 1 kA a channel"),
            "{e}"
        );
        let e = err(&with(
            "current_a = 8.0",
            "current_a = [8.0, 8.0, 8.0, 8.0, 1e4]",
        ));
        assert!(
            e.starts_with("r.toml: coil.limits.current_a[4]: must be in (0, 1000] A"),
            "{e}"
        );
        let e = err(&with("rotation_deg = 0.0", "rotation_deg = 1e300"));
        assert!(
            e.starts_with("r.toml: pixels.rotation_deg: must be in [-360, 360]°"),
            "{e}"
        );
        for t in ["0", "255"] {
            let e = err(&with("threshold = 120", &format!("threshold = {t}")));
            assert!(
                e.starts_with("r.toml: detector.threshold: must be in [1, 254]"),
                "{e}"
            );
        }
        // the 520 × 340 px sensor at 10 px/BL is 62.1 BL across its diagonal
        let e = err(&with("max_jump_bl = 1.0", "max_jump_bl = 63.0"));
        assert!(
            e.starts_with(
                "r.toml: detector.max_jump_bl: must be at most the sensor's diagonal (62.1"
            ),
            "{e}"
        );
        RigConfig::parse(&with("max_jump_bl = 1.0", "max_jump_bl = 62.0"), "r.toml").unwrap();
        for slew in ["2.1e7", "1e300", "0.0", "-1.0", "nan"] {
            let e = err(&with(
                "slew_a_per_s = 1000.0",
                &format!("slew_a_per_s = {slew}"),
            ));
            assert!(
                e.starts_with("r.toml: coil.limits.slew_a_per_s: must be in (0, 20000000] A/s"),
                "{e}"
            );
        }
        RigConfig::parse(
            &with("slew_a_per_s = 1000.0", "slew_a_per_s = 2e7"),
            "r.toml",
        )
        .unwrap();
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
