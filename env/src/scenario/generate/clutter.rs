//! `clutter`: random star-shaped polygons scattered over an open field until they cover a
//! given fraction of it, kept off the start and goal places.

use std::f64::consts::TAU;

use rand::RngExt;

use super::place::{pair_in_box, round_pt};
use super::{Family, Refusal, Rng};
use crate::declare_params;
use crate::math::Vec2;
use crate::params::Reals;
use crate::physics::PhysicalParams;
use crate::scenario::Draft;
use crate::scenario::file::MAX_OBSTACLES;
use crate::world::{Obstacle, signed_area};

declare_params! {
    /// The parameters of `clutter`.
    #[derive(Debug, Clone)]
    pub struct Clutter {
        /// Field width (BL).
        #[param("width", Reals::closed(10.0, 200.0))]
        pub width: f64 = 30.0,
        /// Field height (BL).
        #[param("height", Reals::closed(10.0, 200.0))]
        pub height: f64 = 20.0,
        /// Fraction of the field's area the obstacles cover (overlaps counted twice).
        #[param("density", Reals::closed(0.0, 0.6))]
        pub density: f64 = 0.15,
        /// Smallest obstacle radius (BL).
        #[param("size_min", Reals::closed(0.2, 20.0))]
        pub size_min: f64 = 0.5,
        /// Largest obstacle radius (BL).
        #[param("size_max", Reals::closed(0.2, 20.0))]
        pub size_max: f64 = 2.0,
    }
}

/// Width (BL) of the strips at the left and right ends where start and goal are placed; no
/// obstacle reaches into them.
const END: f64 = 5.0;

/// A star-shaped polygon of 3 to 8 vertices about `c`, at radii in `[0.6 R, R]`.
fn polygon(rng: &mut Rng, c: Vec2, radius: f64) -> Vec<Vec2> {
    let n = rng.random_range(3..=8usize);
    let turn = rng.random_range(0.0..TAU);
    (0..n)
        .map(|i| {
            let a = turn + (i as f64 + rng.random_range(0.0..0.7)) * TAU / n as f64;
            let r = radius * rng.random_range(0.6..=1.0);
            round_pt(c + Vec2::new(a.cos(), a.sin()) * r)
        })
        .collect()
}

impl Family for Clutter {
    fn feasible(&self, _: &PhysicalParams) -> Result<(), Refusal> {
        if self.size_min > self.size_max {
            return Err(Refusal::new(
                "size_max",
                format!(
                    "must be at least size_min = {} BL, got {}",
                    self.size_min, self.size_max
                ),
            ));
        }
        if 2.0 * END + 2.0 * self.size_max >= self.width {
            return Err(Refusal::new(
                "width",
                format!(
                    "{} BL leaves no room between the {END} BL start and goal strips for obstacles of radius {}",
                    self.width, self.size_max
                ),
            ));
        }
        Ok(())
    }

    fn build(&self, rng: &mut Rng, physics: &PhysicalParams) -> Result<Draft, Refusal> {
        let (w, h) = (self.width, self.height);
        let start = pair_in_box(rng, (0.0, 0.0, END, h), physics);
        let goal = pair_in_box(rng, (w - END, 0.0, w, h), physics);
        let target = self.density * w * h;
        let mut covered = 0.0;
        let mut obstacles = Vec::new();
        while covered < target {
            if obstacles.len() >= MAX_OBSTACLES {
                return Err(Refusal::new(
                    "density",
                    format!(
                        "{} needs more than the {MAX_OBSTACLES} obstacles a map may have at size_max = {}",
                        self.density, self.size_max
                    ),
                ));
            }
            let radius = rng.random_range(self.size_min..=self.size_max);
            let x = rng.random_range(END + radius..w - END - radius);
            let c = Vec2::new(x, rng.random_range(0.0..h));
            let v = polygon(rng, c, radius);
            covered += signed_area(&v).abs();
            obstacles.push(Obstacle::Polygon(v));
        }
        Ok(Draft {
            name: String::new(),
            description: format!(
                "clutter: {} random polygons of radius {}–{} BL covering {:.2} of a {w} x {h} BL field",
                obstacles.len(),
                self.size_min,
                self.size_max,
                covered / (w * h)
            ),
            width: w,
            height: h,
            obstacles,
            medium: None,
            start,
            goal,
            tolerance: 0.5,
        })
    }

    fn hardest(&self) -> &'static str {
        "density"
    }
}
