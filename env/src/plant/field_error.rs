//! Field-angle error: a per-run rotation between the coil's frame and the camera's, and white
//! jitter of the field angle at every integration step.

use serde::{Deserialize, Serialize};

use super::term::Term;
use crate::input::Rejection;
use crate::input::bounds::non_negative;

/// The field-angle-error term of a preset.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FieldError {
    /// Whether the term acts.
    pub enabled: bool,
    /// Standard deviation of the per-run angle between the coil's and the camera's x axes
    /// (degrees).
    pub angle_bias_deg: f64,
    /// Standard deviation of the white field-angle jitter, drawn every integration step
    /// (degrees).
    pub angle_jitter_deg: f64,
}

impl Term for FieldError {
    super::term::switch_is_enabled_field!();

    fn check(&self) -> Result<(), Rejection> {
        non_negative("angle_bias_deg", self.angle_bias_deg)?;
        non_negative("angle_jitter_deg", self.angle_jitter_deg)
    }
}

impl FieldError {
    /// Standard deviation of the per-run bias (radians); 0 when off.
    pub fn bias_sd(&self) -> f64 {
        if self.enabled {
            self.angle_bias_deg.to_radians()
        } else {
            0.0
        }
    }

    /// Standard deviation of the per-step jitter (radians); 0 when off.
    pub fn jitter_sd(&self) -> f64 {
        if self.enabled {
            self.angle_jitter_deg.to_radians()
        } else {
            0.0
        }
    }
}
