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
//! bit. One term per file, each a [`Term`] listed once in `plant_terms!`; [`dynamics`] puts
//! them together.

/// The plant terms, one line each: `table_name: module::Type,` — the preset's `[table_name]`
/// table, the term's name in [`DisturbancePreset::TERMS`] (in this order) and its Rust type,
/// a [`Term`] in `plant/module.rs`. The line declares the module and re-exports the type;
/// the preset's fields, switches, checks and per-run draws are made from this list.
/// `plant_terms!(then)` calls the macro `then!` with the list.
macro_rules! plant_terms {
    ($then:ident) => {
        $then! {
            coil_lag: coil_lag::CoilLag,
            magnet_lag: magnet_lag::MagnetLag,
            field_error: field_error::FieldError,
            nonuniform_field: nonuniform::NonuniformField,
            coil_calibration: calibration::CoilCalibration,
            ambient_field: ambient::AmbientField,
            heterogeneity: heterogeneity::Heterogeneity,
            hydrodynamics: hydrodynamics::Hydrodynamics,
            capillary: capillary::Capillary,
            drift: drift::Drift,
            flow: flow::Flow,
            brownian: brownian::Brownian,
        }
    };
}

/// Declares each term's module and re-exports its type.
macro_rules! term_modules {
    ($($name:ident : $module:ident :: $ty:ident,)*) => {
        $(
            mod $module;
            pub use $module::$ty;
        )*
    };
}

plant_terms!(term_modules);

mod camera;
pub mod dynamics;
mod field;
mod fitted;
mod medium;
pub mod pinning;
mod pixels;
mod preset;
mod sim;
mod streams;
mod term;
mod walls;

pub use crate::input::Rejection;
pub use camera::{Camera, CameraParams, DetectionNoise, Latency, Misses, Observation, Swaps};
pub use capillary::CapillaryLaw;
pub use coil_lag::AxisResponse;
pub use field::{CoilOutput, FieldModel};
pub use fitted::Fitted;
pub use flow::FlowField;
pub use heterogeneity::{AgentFactors, Spread};
pub use hydrodynamics::rotne_prager;
pub use magnet_lag::rotation_time;
pub use medium::{GRAVITY, Interface, Medium};
pub use pinning::{PinningLaw, Tilt};
pub use pixels::{Pixels, centroid_rms_px};
pub use preset::{CoilRange, DisturbancePreset};
pub use sim::{AGENT_RADIUS_BL, Plant};
pub use term::{Contribution, RunContext, Term};
pub use walls::Walls;
