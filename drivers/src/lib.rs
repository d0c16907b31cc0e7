//! # magbench-drivers
//!
//! Running plans on a real coil-and-camera rig, and the emulator that stands in for one:
//!
//! - [`rigfile`]: the rig file (TOML), validated with `FILE: FIELD: REASON` errors;
//! - [`calibration`] and [`coil_driver`]: coil commands to channel currents, within limits;
//! - [`protocol`], [`transport`] and [`link`]: the coil driver's framed, checksummed,
//!   acknowledged wire protocol over a serial port or TCP;
//! - [`frame`] and [`camera`]: grey-level frames and where they come from (the emulator's
//!   stream, a recorded folder, a V4L2 device behind the `v4l2` feature);
//! - [`detector`] and [`pixel_map`]: sub-pixel agent centres and pixel ↔ BL calibration;
//! - [`clock`]: the time of the safety timers (wall, or a manual clock a test moves);
//! - [`coil_session`] and [`hardware`]: the hardware rig, which zeroes the field on every exit;
//! - [`rigs`]: the rigs by name (a simulated rig under a preset, a rig file, a plugin's), loaded and opened for a plan-track run;
//! - [`excite`], [`fit`] and [`watch`]: the identification trajectory, the fit of a preset to
//!   the logs, and a simulated rig watched for the moment its agents touch;
//! - [`check`] and [`redetect`]: rig bring-up and offline detection;
//! - [`emulator`]: the device side — protocol, watchdog, env's plant, rendered frames, faults.
//!
//! Lengths are in body lengths (BL) and times in seconds unless a name says otherwise.

#![warn(missing_docs)]

pub mod calibration;
pub mod camera;
pub mod check;
pub mod clock;
pub mod coil_driver;
pub mod coil_session;
pub mod detector;
pub mod emulator;
pub mod excite;
pub mod fit;
pub mod frame;
pub mod hardware;
pub mod interrupt;
pub mod link;
pub mod pixel_map;
pub mod protocol;
pub mod redetect;
pub mod rig_log;
pub mod rigfile;
pub mod rigs;
pub mod stats;
pub mod transport;
pub mod watch;

pub use calibration::Calibration;
pub use camera::{Camera, CameraError};
pub use coil_driver::{CoilCommand, CoilDriver};
pub use detector::{Detection, Detector};
pub use frame::Frame;
pub use hardware::{HardwareError, HardwareRig, RigStats};
pub use link::{CoilLink, LinkError};
pub use magbench_trackers::{Rig, RigError};
pub use pixel_map::PixelMap;
pub use rigfile::RigConfig;
