//! Fitted values: what `magbench calibrate` measured on one rig, in place of per-run draws.
//!
//! The other terms describe a population of rigs (a spread, drawn per run from the seed). A
//! calibrated rig is one member of it: its agents' own moments and drags, its gradient axes'
//! own gains, its own field-angle bias and drift. When `[fitted]` is on, each value it gives
//! replaces the corresponding draw (per-agent moment and mobility factors of
//! `heterogeneity`, the gradient gains of `coil_calibration`, the bias of `field_error`, the
//! uniform `drift`); a value it leaves out is drawn from the preset. Everything else (axis gains
//! and skew, cross-talk, jitter, contact angles, the varying flow) is still drawn.

use serde::{Deserialize, Serialize};

use crate::input::Rejection;
use crate::input::bounds::within;

/// The `[fitted]` table of a preset.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Fitted {
    /// Whether the fitted values replace the draws.
    pub enabled: bool,
    /// Per-agent moment factors (1 = the scenario's agent); empty: drawn.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub moment: Vec<f64>,
    /// Per-agent drag factors (1 = the scenario's agent; mobility is its inverse); empty:
    /// drawn.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub drag: Vec<f64>,
    /// Gain of each gradient axis (x, y; 1 = as commanded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gradient_gain: Option<[f64; 2]>,
    /// Rotation of the coil frame against the camera's (degrees).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub field_bias_deg: Option<f64>,
    /// Uniform drift velocity (BL/s, x and y).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drift_bl_s: Option<[f64; 2]>,
}

impl Fitted {
    /// True when the table is off and empty (it is then not written out).
    pub fn is_off(&self) -> bool {
        *self == Self::default()
    }

    /// Checks every value; returns (field, reason).
    pub fn check(&self) -> Result<(), Rejection> {
        for &m in &self.moment {
            within("fitted.moment", m, 0.01, 100.0, "")?;
        }
        for &d in &self.drag {
            within("fitted.drag", d, 0.01, 100.0, "")?;
        }
        for g in self.gradient_gain.iter().flatten() {
            within("fitted.gradient_gain", *g, 0.01, 100.0, "")?;
        }
        if let Some(b) = self.field_bias_deg {
            within("fitted.field_bias_deg", b, -180.0, 180.0, "°")?;
        }
        for v in self.drift_bl_s.iter().flatten() {
            within("fitted.drift_bl_s", *v, -100.0, 100.0, " BL/s")?;
        }
        Ok(())
    }

    /// The fitted value of agent `i` in `values`, when on and given.
    fn agent(&self, values: &[f64], i: usize) -> Option<f64> {
        (self.enabled).then(|| values.get(i).copied()).flatten()
    }

    /// Agent `i`'s fitted moment factor.
    pub fn moment_of(&self, i: usize) -> Option<f64> {
        self.agent(&self.moment, i)
    }

    /// Agent `i`'s fitted mobility factor (1/drag).
    pub fn mobility_of(&self, i: usize) -> Option<f64> {
        self.agent(&self.drag, i).map(|d| 1.0 / d)
    }

    /// The fitted gradient gains, when on.
    pub fn gradient_gain(&self) -> Option<[f64; 2]> {
        self.gradient_gain.filter(|_| self.enabled)
    }

    /// The fitted field bias (radians), when on.
    pub fn field_bias(&self) -> Option<f64> {
        self.field_bias_deg
            .filter(|_| self.enabled)
            .map(f64::to_radians)
    }

    /// The fitted drift (BL/s), when on.
    pub fn drift(&self) -> Option<[f64; 2]> {
        self.drift_bl_s.filter(|_| self.enabled)
    }
}
