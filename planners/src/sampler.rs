//! State samplers: the whole space, and the goal-zoom region.

use std::f64::consts::PI;

use magbench_env::{Goal, Vec2};
use rand::RngExt;

use crate::guide::Guide;
use crate::{Problem, Rng};

/// Samples team states for one problem.
#[derive(Debug, Clone)]
pub struct StateSampler {
    width: f64,
    height: f64,
    r_min: f64,
    r_max: f64,
    agents: usize,
}

/// A point uniform in the disk of radius `radius` about `center`.
#[inline]
pub fn in_disk(rng: &mut Rng, center: Vec2, radius: f64) -> Vec2 {
    let r = radius * rng.random::<f64>().sqrt();
    let a = rng.random_range(-PI..PI);
    center + Vec2::new(a.cos(), a.sin()) * r
}

impl StateSampler {
    /// The sampler of `problem`'s world and proximity range.
    pub fn new(problem: &Problem) -> Self {
        StateSampler {
            width: problem.world.width,
            height: problem.world.height,
            r_min: problem.checker.r_min,
            r_max: problem.checker.r_max,
            agents: problem.agents(),
        }
    }

    /// A state from the whole space: the centroid uniform over the world; for two agents the
    /// separation uniform in the proximity range and the heading uniform — the seed's
    /// `q = (x_c, y_c, r, φ)`; for more agents, offsets uniform in the disk of radius r_max/2
    /// about the centroid, re-centred.
    pub fn uniform(&self, rng: &mut Rng, out: &mut [Vec2]) {
        let c = Vec2::new(
            rng.random_range(0.0..self.width),
            rng.random_range(0.0..self.height),
        );
        self.about(rng, c, out);
    }

    /// A state with centroid `c` and the relative state drawn as [`StateSampler::uniform`]
    /// draws it.
    pub fn about(&self, rng: &mut Rng, c: Vec2, out: &mut [Vec2]) {
        if self.agents == 2 {
            let r = rng.random_range(self.r_min..self.r_max);
            let phi = rng.random_range(-PI..PI);
            let h = Vec2::new(phi.cos(), phi.sin()) * (0.5 * r);
            out[0] = c - h;
            out[1] = c + h;
        } else {
            let mut mean = Vec2::zeros();
            for p in out.iter_mut() {
                *p = in_disk(rng, Vec2::zeros(), 0.5 * self.r_max);
                mean += *p;
            }
            mean /= self.agents as f64;
            for p in out.iter_mut() {
                *p += c - mean;
            }
        }
    }

    /// A state from the goal-zoom region: each agent uniform in the disk of radius `radius`
    /// about its goal centre.
    pub fn zoom(&self, rng: &mut Rng, goal: &Goal, radius: f64, out: &mut [Vec2]) {
        for (p, g) in out.iter_mut().zip(&goal.agents) {
            *p = in_disk(rng, *g, radius);
        }
    }
}

/// Draws with `draw` until the state is valid (the seed rejects samples in obstacles), at most
/// `tries` times. Returns false when no draw was valid.
#[inline]
pub fn valid_sample(
    problem: &Problem,
    tries: usize,
    out: &mut [Vec2],
    mut draw: impl FnMut(&mut [Vec2]),
) -> bool {
    for _ in 0..tries {
        draw(out);
        if problem.checker.is_valid(out) {
            return true;
        }
    }
    false
}

/// Rejection tries per sample before an iteration gives up on sampling.
pub const SAMPLE_TRIES: usize = 1000;

/// Share of the whole-space draws a guide replaces with a centroid near the guide path.
pub const GUIDE_SHARE: f64 = 0.7;

/// The seed's randomStateGoalZoom: a biased coin toss picks the goal-zoom region (with
/// probability `bias`) or the whole space; samples in obstacles or outside the proximity range
/// are redrawn. With a [`Guide`], a second coin replaces [`GUIDE_SHARE`] of the whole-space
/// draws by states whose centroid lies near the guide path ahead of the tree.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GoalZoom {
    /// Probability of sampling the zoom region.
    pub bias: f64,
    /// Radius of each agent's disk about its goal centre (BL).
    pub radius: f64,
}

impl GoalZoom {
    /// Draws a valid sample into `out`; false if none was found in [`SAMPLE_TRIES`] draws.
    /// With `guide`, [`GUIDE_SHARE`] of the whole-space draws come from the guide; without
    /// one the random stream is the seed's.
    pub fn sample(
        &self,
        problem: &Problem,
        sampler: &StateSampler,
        guide: Option<&Guide>,
        rng: &mut Rng,
        out: &mut [Vec2],
    ) -> bool {
        let zoom = rng.random::<f64>() < self.bias;
        let guide = guide.filter(|_| !zoom && rng.random::<f64>() < GUIDE_SHARE);
        valid_sample(problem, SAMPLE_TRIES, out, |s| {
            if zoom {
                sampler.zoom(rng, &problem.goal, self.radius, s)
            } else if let Some(g) = guide {
                let c = g.centroid(rng);
                sampler.about(rng, c, s)
            } else {
                sampler.uniform(rng, s)
            }
        })
    }
}
