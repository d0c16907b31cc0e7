//! The simulated plant: the same physics as the planning model, plus what the real world adds.
//!
//! A [`DisturbancePreset`] names the disturbances: per-run model mismatch (moment and drag),
//! field-angle error (a per-run bias and per-step jitter), a slow uniform drift flow, Brownian
//! motion at the physical diffusion constant, and the [`CameraParams`] of the camera that
//! observes the plant. Under [`DisturbancePreset::ideal`] the plant integrates exactly the
//! planning model's arithmetic, so an open-loop replay reproduces a plan bit for bit.

mod camera;
mod preset;
mod sim;

pub use camera::{Camera, CameraParams, Observation};
pub use preset::DisturbancePreset;
pub use sim::Plant;
