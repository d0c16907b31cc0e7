//! What every plant term is: a preset table with an on/off switch, checked values, and
//! (optionally) a per-run contribution to the equations of motion.
//!
//! A term is one file holding a type that implements [`Term`], plus one line of the term
//! table in `plant/mod.rs` (`table_name: module::Type,`). The table makes the preset's
//! `[table_name]` table, the term's name in [`super::DisturbancePreset::TERMS`] (so presets,
//! `preset show` and the ablation see it), its check, and its draw at the start of each run.
//! docs/plant.md, "Adding a plant term", walks through it.

use std::fmt::Debug;
use std::sync::Arc;

use rand_chacha::ChaCha8Rng;
use serde::Serialize;
use serde::de::DeserializeOwned;

use super::heterogeneity::AgentFactors;
use super::medium::Medium;
use super::streams::named_stream;
use crate::input::Rejection;
use crate::math::Vec2;
use crate::physics::PhysicalParams;

/// A term of the simulated plant: the values of its preset table.
pub trait Term:
    Debug + Clone + PartialEq + Default + Serialize + DeserializeOwned + Send + Sync + 'static
{
    /// Whether the term acts.
    fn enabled(&self) -> bool;

    /// Switches the term on or off, keeping its values.
    fn set_enabled(&mut self, on: bool);

    /// Checks the term's values; a rejection names the field within the term's table
    /// (`field_ut`, not `ambient_field.field_ut`: the table adds its name).
    fn check(&self) -> Result<(), Rejection> {
        Ok(())
    }

    /// The term's contribution to one run's equations of motion, drawn at the start of the
    /// run (only while the term is on); `None` when it adds nothing there (a term acting
    /// through a dedicated part of [`super::dynamics`], the field model or the camera).
    fn draw(&self, _run: &RunContext<'_>) -> Option<Arc<dyn Contribution>> {
        None
    }
}

/// What a term sees when it is drawn for one run.
#[derive(Debug, Clone, Copy)]
pub struct RunContext<'a> {
    /// The term's table name (it names the term's random stream).
    pub name: &'static str,
    /// The physical preset.
    pub params: &'a PhysicalParams,
    /// Where the agents move.
    pub medium: &'a Medium,
    /// The drawn per-agent factors (moment, mobility, contact angle).
    pub factors: &'a AgentFactors,
    /// Number of agents.
    pub n: usize,
    /// The run's seed.
    pub seed: u64,
}

impl RunContext<'_> {
    /// The term's own random stream of this run: switching another term off leaves its draws
    /// unchanged.
    pub fn rng(&self) -> ChaCha8Rng {
        named_stream(self.seed, self.name)
    }
}

/// A term's part of the equations of motion of one run, in velocity units of a nominal agent
/// (BL/s), as [`super::dynamics`] writes them.
pub trait Contribution: Debug + Send + Sync {
    /// A force on agent `i` at `p` (BL) at time `t` (s): it moves the agent through its
    /// mobility and the others through the hydrodynamic coupling.
    fn force(&self, _i: usize, _p: Vec2, _t: f64) -> Vec2 {
        Vec2::zeros()
    }

    /// A velocity that carries agent `i` at `p` at time `t` (a flow of the liquid).
    fn velocity(&self, _i: usize, _p: Vec2, _t: f64) -> Vec2 {
        Vec2::zeros()
    }
}

/// The [`Term::enabled`] and [`Term::set_enabled`] of a term whose switch is its `enabled`
/// field: `impl Term for T { switch_is_enabled_field!(); … }`.
macro_rules! switch_is_enabled_field {
    () => {
        fn enabled(&self) -> bool {
            self.enabled
        }

        fn set_enabled(&mut self, on: bool) {
            self.enabled = on;
        }
    };
}
pub(crate) use switch_is_enabled_field;
