//! The simulated plant: the same physics as the planning model, plus what the real world adds.
//!
//! A [`DisturbancePreset`] is data (a TOML file per preset, `presets/`): one table per term,
//! each switched on and off on its own — coil dynamics, magnet rotation lag, field-angle error,
//! the gradient's non-uniform field, coil calibration errors, an ambient field, agent
//! heterogeneity, hydrodynamic interaction, capillary attraction at an interface, a uniform
//! drift, a flow varying in space and time, Brownian motion — and the [`CameraParams`] of the
//! camera that observes the plant (latency and its jitter, detection noise and its slow bias,
//! missed and swapped detections). Under [`DisturbancePreset::ideal`] the plant integrates
//! exactly the planning model's arithmetic, so an open-loop replay reproduces a plan bit for
//! bit. One term per file; [`dynamics`] puts them together.

mod ambient;
mod brownian;
mod calibration;
mod camera;
mod capillary;
mod coil_lag;
pub mod dynamics;
mod field;
mod field_error;
mod fitted;
mod flow;
mod heterogeneity;
mod hydrodynamics;
mod magnet_lag;
mod medium;
mod nonuniform;
mod preset;
mod sim;
mod streams;

pub use crate::check::Rejection;
pub use ambient::AmbientField;
pub use brownian::Brownian;
pub use calibration::CoilCalibration;
pub use camera::{Camera, CameraParams, DetectionNoise, Latency, Misses, Observation, Swaps};
pub use capillary::{Capillary, CapillaryLaw};
pub use coil_lag::{AxisResponse, CoilLag};
pub use field::{CoilOutput, FieldModel};
pub use field_error::FieldError;
pub use fitted::Fitted;
pub use flow::{Drift, Flow, FlowField};
pub use heterogeneity::{AgentFactors, Heterogeneity, Spread};
pub use hydrodynamics::{Hydrodynamics, rotne_prager};
pub use magnet_lag::{MagnetLag, rotation_time};
pub use medium::{GRAVITY, Interface, Medium};
pub use nonuniform::NonuniformField;
pub use preset::{CoilRange, DisturbancePreset};
pub use sim::{AGENT_RADIUS_BL, Plant};
