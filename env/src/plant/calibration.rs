//! Coil calibration errors: what the coil really produces for a command.
//!
//! Each Helmholtz axis has a gain error (`B_k = (1 + g_k) B_k,cmd`) and the y axis is not quite
//! at 90° to the x axis (skew δ); each Maxwell axis has a gain error, and each gradient command
//! leaks into the in-plane shear component `∂B_x/∂y = ∂B_y/∂x` (cross-talk). The realised
//! gradient stays curl- and divergence-free (symmetric, trace zero). All are drawn per run; the
//! gradient axes' gains may also be off by a fixed amount (a coil known to be 5% off its
//! calibration), common to every run.

use serde::{Deserialize, Serialize};

use super::term::Term;
use crate::input::bounds::within;
use crate::input::{Bound, Rejection};

/// The fixed gradient gain offsets a preset accepts.
const GAIN_OFFSET: Bound = Bound::closed(
    -0.5,
    0.5,
    "",
    "a coil more than 50% off its calibration needs a new calibration, not an offset",
);

/// The coil-calibration term of a preset.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoilCalibration {
    /// Whether the term acts.
    pub enabled: bool,
    /// Standard deviation of each field axis's relative gain error.
    pub axis_gain_error: f64,
    /// Standard deviation of the angle by which the y field axis departs from 90° to x
    /// (degrees).
    pub axis_skew_deg: f64,
    /// Standard deviation of each gradient axis's relative gain error.
    pub gradient_gain_error: f64,
    /// Standard deviation of the shear gradient each gradient command leaks, as a fraction of
    /// that command.
    pub gradient_crosstalk: f64,
    /// Fixed relative gain offset of each gradient axis (x, y), added to the drawn error.
    #[serde(default)]
    pub gradient_gain_offset: [f64; 2],
}

impl Term for CoilCalibration {
    super::term::switch_is_enabled_field!();

    fn check(&self) -> Result<(), Rejection> {
        within(
            "axis_gain_error",
            self.axis_gain_error,
            0.0,
            0.5,
            "",
        )?;
        within(
            "axis_skew_deg",
            self.axis_skew_deg,
            0.0,
            20.0,
            "°",
        )?;
        within(
            "gradient_gain_error",
            self.gradient_gain_error,
            0.0,
            0.5,
            "",
        )?;
        within(
            "gradient_crosstalk",
            self.gradient_crosstalk,
            0.0,
            0.5,
            "",
        )?;
        for g in self.gradient_gain_offset {
            GAIN_OFFSET.check("gradient_gain_offset", g)?;
        }
        Ok(())
    }
}
