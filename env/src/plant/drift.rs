//! A uniform, steady drift of the liquid: one velocity per run, added to every agent's.

use serde::{Deserialize, Serialize};

use super::term::Term;
use crate::input::Rejection;
use crate::input::bounds::within;

/// The uniform-drift term of a preset: one steady, uniform flow per run.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Drift {
    /// Whether the term acts.
    pub enabled: bool,
    /// Largest speed (BL/s); the speed is drawn uniformly in `[0, max]`, the direction
    /// uniformly.
    pub max_speed_bl_s: f64,
}

impl Term for Drift {
    super::term::switch_is_enabled_field!();

    fn check(&self) -> Result<(), Rejection> {
        within(
            "max_speed_bl_s",
            self.max_speed_bl_s,
            0.0,
            100.0,
            " BL/s",
        )
    }
}
