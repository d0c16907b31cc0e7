//! `serpentine`: k walls across the field, their gaps at alternate ends, so the path winds
//! back and forth and grows as k.

use rand::RngExt;

use super::place::{pair_in_box, passage, rect};
use super::{Family, Refusal, Rng};
use crate::declare_params;
use crate::params::Reals;
use crate::physics::PhysicalParams;
use crate::scenario::Draft;

declare_params! {
    /// The parameters of `serpentine`.
    #[derive(Debug, Clone)]
    pub struct Serpentine {
        /// Number of walls k.
        #[param("walls", 1..=32)]
        pub walls: usize = 2,
        /// Width of each wall's gap (BL).
        #[param("gap", Reals::closed(0.5, 50.0))]
        pub gap: f64 = 4.0,
        /// Thickness of each wall (BL).
        #[param("thickness", Reals::closed(0.2, 10.0))]
        pub thickness: f64 = 1.0,
        /// Free width between walls, and of the first and last chamber (BL).
        #[param("spacing", Reals::closed(0.5, 50.0))]
        pub spacing: f64 = 6.0,
        /// Height of the field (BL).
        #[param("height", Reals::closed(4.0, 200.0))]
        pub height: f64 = 16.0,
    }
}

impl Family for Serpentine {
    fn feasible(&self, physics: &PhysicalParams) -> Result<(), Refusal> {
        passage("gap", "a gap", self.gap, physics)?;
        passage("spacing", "a spacing", self.spacing, physics)?;
        if self.gap > self.height - 1.0 {
            return Err(Refusal::new(
                "gap",
                format!(
                    "a gap of {} BL leaves less than 1 BL of wall in a field {} BL high",
                    self.gap, self.height
                ),
            ));
        }
        Ok(())
    }

    fn build(&self, rng: &mut Rng, physics: &PhysicalParams) -> Result<Draft, Refusal> {
        let (s, t, h) = (self.spacing, self.thickness, self.height);
        let width = (self.walls + 1) as f64 * s + self.walls as f64 * t;
        let top_first = rng.random_bool(0.5);
        let obstacles = (0..self.walls)
            .map(|i| {
                let x0 = (i + 1) as f64 * s + i as f64 * t;
                if (i % 2 == 0) == top_first {
                    rect(x0, 0.0, x0 + t, h - self.gap)
                } else {
                    rect(x0, self.gap, x0 + t, h)
                }
            })
            .collect();
        Ok(Draft {
            name: String::new(),
            description: format!(
                "serpentine: {} wall(s) {t} BL thick, {} BL gaps at alternate ends, {s} BL apart",
                self.walls, self.gap
            ),
            width,
            height: h,
            obstacles,
            medium: None,
            start: pair_in_box(rng, (0.0, 0.0, s, h), physics),
            goal: pair_in_box(rng, (width - s, 0.0, width, h), physics),
            tolerance: 0.5,
        })
    }

    fn hardest(&self) -> &'static str {
        "gap"
    }
}
