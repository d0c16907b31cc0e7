//! A small ambient field (the Earth's and the building's) added to the coil's.

use serde::{Deserialize, Serialize};

use super::term::Term;
use crate::input::Rejection;
use crate::input::bounds::within;

/// The ambient-field term of a preset: a constant in-plane field of this magnitude, in a
/// direction drawn per run (the rig's orientation to north is arbitrary).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AmbientField {
    /// Whether the term acts.
    pub enabled: bool,
    /// In-plane magnitude (µT).
    pub field_ut: f64,
}

impl Term for AmbientField {
    super::term::switch_is_enabled_field!();

    fn check(&self) -> Result<(), Rejection> {
        within(
            "field_ut",
            self.field_ut,
            0.0,
            10_000.0,
            " µT",
        )
    }
}
