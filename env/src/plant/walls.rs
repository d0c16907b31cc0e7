//! What the map's walls and obstacles are to the plant: physical (the agents slide along them)
//! or virtual (a planning constraint drawn on an open dish: the agents pass through them).
//!
//! Either way an agent that overlaps a wall or obstacle counts one wall contact per contact
//! event, so the metrics score a virtual wall crossed as a violation.

use serde::{Deserialize, Serialize};

/// The walls a preset models (`walls = "physical"` or `"virtual"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Walls {
    /// Solid walls: an agent that overlaps one is projected back into contact and slides.
    #[default]
    Physical,
    /// Walls the plant ignores (a maze drawn for the planner on an open dish); overlaps are
    /// still counted as wall contacts.
    Virtual,
}

impl Walls {
    /// True for the default, physical walls (what a preset file may leave out).
    pub fn is_physical(&self) -> bool {
        *self == Walls::Physical
    }
}
