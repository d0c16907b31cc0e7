//! Brownian motion at the physical diffusion constant `D = k_B T/σ` of the preset: after every
//! integration step of length `h` each agent moves by `√(2Dh)·N(0, 1)` per axis. For the
//! default preset D = 1.2e-10 BL²/s: negligible at this size, kept for smaller agents.

use serde::{Deserialize, Serialize};

use super::term::Term;

/// The Brownian-motion term of a preset (no parameter: D follows from the physical preset).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Brownian {
    /// Whether the term acts.
    pub enabled: bool,
}

impl Term for Brownian {
    super::term::switch_is_enabled_field!();
}
