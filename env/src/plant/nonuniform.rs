//! Field non-uniformity: with the gradient coils on, the field is not the same everywhere.
//!
//! A Maxwell pair's gradient is a field that grows away from its centre, so an agent at `x`
//! feels `B(x) = B₀ b̂ + ∇B · (x − x_c)`: its own field direction (its moment follows it) and,
//! through `(m·∇)B`, its own pull. `x_c` is the coil centre: the map is centred on it, up to a
//! per-run placement offset. At 85 mT/m and 10 BL (5 mm) from the centre, ∇B·(x − x_c) is
//! 0.43 mT against B₀ = 5 mT: up to 4.9° of field-angle bend.

use serde::{Deserialize, Serialize};

use super::term::Term;
use crate::input::Rejection;
use crate::input::bounds::within;

/// The field-non-uniformity term of a preset.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NonuniformField {
    /// Whether the term acts.
    pub enabled: bool,
    /// Standard deviation, per axis, of the per-run offset of the coil centre from the map's
    /// centre (mm).
    pub centre_offset_mm: f64,
}

impl Term for NonuniformField {
    super::term::switch_is_enabled_field!();

    fn check(&self) -> Result<(), Rejection> {
        within(
            "centre_offset_mm",
            self.centre_offset_mm,
            0.0,
            100.0,
            " mm",
        )
    }
}
