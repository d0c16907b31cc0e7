//! EXTEND, the seed's Algorithm 3: brute-force optimisation over random controls.
//!
//! From `q_near`, try `k` random (control, duration) pairs, propagate each through the planning
//! model and keep the one whose end is closest to the target under the problem's metric (the
//! seed's DISTANCE ρ = ‖P̃‖², P̃ = P_new − P_sample). Collision is checked by the caller on the
//! winner only, as in Algorithm 2. RRT* reuses it as its shooting steer.

use magbench_env::{Control, MAX_AGENTS, Vec2};
use rand::RngExt;

use crate::motion::random_control;
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

    /// EXTEND(q_near, q_sample): the try whose end is closest to `target` (the first on ties).
    /// The tries are integrated together by `PlanningModel::propagate_many`, whose ends equal
    /// one-at-a-time propagation bit for bit.
    pub fn run(
        &self,
        problem: &Problem,
        rng: &mut Rng,
        near: &[Vec2],
        target: &[Vec2],
    ) -> Extension {
        let n = near.len();
        let g = problem.model.coil.gradient_limit();
        let k = self.tries.max(1);
        let mut controls = Vec::with_capacity(k);
        let mut periods = Vec::with_capacity(k);
        let mut durations = Vec::with_capacity(k);
        for _ in 0..k {
            controls.push(random_control(rng, g));
            let p = self.random_periods(rng);
            periods.push(p);
            durations.push(problem.periods(p));
        }
        let mut ends = vec![[Vec2::zeros(); MAX_AGENTS]; k];
        problem
            .model
            .propagate_many(near, &controls, &durations, &mut ends);
        let mut best = Extension {
            control: Control::default(),
            periods: 0,
            end: [Vec2::zeros(); MAX_AGENTS],
            distance: f64::INFINITY,
        };
        for i in 0..k {
            let d2 = problem.metric.distance_squared(&ends[i][..n], target);
            if d2 < best.distance {
                best = Extension {
                    control: controls[i],
                    periods: periods[i],
                    end: ends[i],
                    distance: d2,
                };
            }
        }
        best.distance = best.distance.sqrt();
        best
    }
}
