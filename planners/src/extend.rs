//! EXTEND, the seed's Algorithm 3: brute-force optimisation over random controls.
//!
//! From `q_near`, try `k` random (control, duration) pairs, propagate each through the planning
//! model and keep the one whose end is closest to the target under the problem's metric (the
//! seed's DISTANCE ρ = ‖P̃‖², P̃ = P_new − P_sample). Collision is checked by the caller on the
//! winner only, as in Algorithm 2. RRT* reuses it as its shooting steer.

use magbench_env::{Control, MAX_AGENTS, Vec2};
use rand::RngExt;

use crate::motion::{propagate, random_control};
use crate::{Problem, Rng};

/// The EXTEND optimiser's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extend {
    /// Random (control, duration) tries per call (the seed's k).
    pub tries: usize,
    /// Shortest duration, in control periods (≥ 1).
    pub min_periods: u32,
    /// Longest duration, in control periods.
    pub max_periods: u32,
}

/// The best try of one EXTEND call.
#[derive(Debug, Clone, Copy)]
pub struct Extension {
    /// The control of the best try.
    pub control: Control,
    /// Its duration in control periods.
    pub periods: u32,
    /// Its end state (first N entries).
    pub end: [Vec2; MAX_AGENTS],
    /// Its distance to the target under the problem's metric.
    pub distance: f64,
}

impl Extension {
    /// The end state of an N-agent team.
    pub fn end(&self, agents: usize) -> &[Vec2] {
        &self.end[..agents]
    }
}

impl Extend {
    /// A random duration in control periods, uniform in `[min_periods, max_periods]`.
    #[inline]
    pub fn random_periods(&self, rng: &mut Rng) -> u32 {
        rng.random_range(self.min_periods..=self.max_periods)
    }

    /// EXTEND(q_near, q_sample): the try whose end is closest to `target`.
    pub fn run(
        &self,
        problem: &Problem,
        rng: &mut Rng,
        near: &[Vec2],
        target: &[Vec2],
    ) -> Extension {
        let n = near.len();
        let g = problem.model.coil.gradient_limit();
        let mut best = Extension {
            control: Control::default(),
            periods: 0,
            end: [Vec2::zeros(); MAX_AGENTS],
            distance: f64::INFINITY,
        };
        let mut end = [Vec2::zeros(); MAX_AGENTS];
        for _ in 0..self.tries.max(1) {
            let u = random_control(rng, g);
            let periods = self.random_periods(rng);
            propagate(problem, near, &u, problem.periods(periods), &mut end[..n]);
            let d2 = problem.metric.distance_squared(&end[..n], target);
            if d2 < best.distance {
                best = Extension {
                    control: u,
                    periods,
                    end,
                    distance: d2,
                };
            }
        }
        best.distance = best.distance.sqrt();
        best
    }
}
