//! Each OMPL planner's parameters, declared once under OMPL's own names and passed to OMPL's
//! `ParamSet` by name, plus the control-duration bounds every OMPL planner shares.
//!
//! Defaults are OMPL 1.5's, except SST's radii (magbench's `sst` defaults, so that the two
//! SSTs are compared at the same δ_BN and δ_s; both measure in the same metric, the Euclidean
//! distance over all agent positions) and the durations (magbench's planners' own defaults).

use magbench_env::coil::Planar;
use magbench_env::declare_params;
use magbench_env::params::{ParamSet, Reals};

use crate::Problem;
use crate::search_settings::{SearchSettings, check_durations, to_periods};

declare_params! {
    /// What every OMPL planner's controls share: the duration bounds, in seconds, used in whole
    /// control periods, and whether the field may leave the plane.
    #[derive(Debug, Clone, PartialEq)]
    pub struct Durations {
        /// Shortest control duration (s), rounded to whole control periods.
        #[param("min_duration", Reals::POSITIVE)]
        pub min_duration: f64 = SearchSettings::default().min_duration,
        /// Longest control duration (s), rounded to whole control periods.
        #[param("max_duration", Reals::POSITIVE)]
        pub max_duration: f64 = SearchSettings::default().max_duration,
        /// Whether the field stays in the plane: `auto` (two agents, or a medium that does not
        /// carry the out-of-plane force, yes; three or more at an interface no), `true` or
        /// `false`. Elevated, the control space gains α ∈ [0, alpha_max].
        #[param("planar")]
        pub planar: Planar = Planar::Auto,
    }
    check(Durations::check);
}

impl Durations {
    /// (min, max) control duration in the problem's control periods (OMPL's steps).
    pub fn steps(&self, problem: &Problem) -> (u32, u32) {
        (
            to_periods(self.min_duration, problem.control_period),
            to_periods(self.max_duration, problem.control_period),
        )
    }

    /// The largest elevation (rad) when the field may leave the plane for `problem`.
    pub fn alpha_max(&self, problem: &Problem) -> Option<f64> {
        (!self
            .planar
            .is_planar(problem.agents(), problem.model.carries_fz))
        .then_some(problem.alpha_max)
    }

    fn check(&self) -> Result<(), magbench_env::input::Rejection> {
        check_durations(self.min_duration, self.max_duration)
    }
}

/// Keys that magbench reads itself; every other parameter goes to OMPL by name.
pub const MAGBENCH_KEYS: [&str; 4] = ["min_duration", "max_duration", "stop_on_solution", "planar"];

/// An OMPL planner's parameters.
pub trait OmplParams: ParamSet + Clone + Default + Send + 'static {
    /// The control-duration bounds.
    fn durations(&self) -> &Durations;
    /// Stop at the first exact solution (only SST goes on after one).
    fn stop_on_solution(&self) -> bool {
        true
    }
    /// OMPL's parameters by OMPL's names, as text OMPL parses.
    fn ompl_params(&self) -> Vec<(String, String)> {
        self.params()
            .into_iter()
            .filter(|p| !MAGBENCH_KEYS.contains(&&*p.name))
            .map(|p| {
                let v = match p.value {
                    magbench_env::params::Value::Flag(b) => (b as u8).to_string(),
                    v => v.to_string(),
                };
                (p.name.to_string(), v)
            })
            .collect()
    }
}

declare_params! {
    /// OMPL's `control::RRT`.
    #[derive(Debug, Clone)]
    pub struct Rrt {
        /// Probability of steering toward a goal sample.
        #[param("goal_bias", Reals::closed(0.0, 1.0))]
        pub goal_bias: f64 = 0.05,
        /// Add the states inside each propagation to the tree.
        #[param("intermediate_states")]
        pub intermediate_states: bool = false,
        /// Control durations.
        #[params]
        pub durations: Durations,
    }
}

declare_params! {
    /// OMPL's `control::SST`.
    #[derive(Debug, Clone)]
    pub struct Sst {
        /// Probability of sampling the goal region.
        #[param("goal_bias", Reals::closed(0.0, 1.0))]
        pub goal_bias: f64 = 0.05,
        /// δ_BN: best-first selection radius (state-space distance, BL).
        #[param("selection_radius", Reals::POSITIVE)]
        pub selection_radius: f64 = 0.5,
        /// δ_s: witness spacing (state-space distance, BL).
        #[param("pruning_radius", Reals::POSITIVE)]
        pub pruning_radius: f64 = 0.25,
        /// Stop at the first solution instead of improving until the limits.
        #[param("stop_on_solution")]
        pub stop_on_solution: bool = false,
        /// Control durations.
        #[params]
        pub durations: Durations,
    }
}

declare_params! {
    /// OMPL's `control::KPIECE1` (grid over the agents' positions, 20 cells per side).
    #[derive(Debug, Clone)]
    pub struct Kpiece {
        /// Probability of extending from the goal-closest cell.
        #[param("goal_bias", Reals::closed(0.0, 1.0))]
        pub goal_bias: f64 = 0.05,
        /// Fraction of selections from the exterior cells.
        #[param("border_fraction", Reals::closed(0.0, 1.0))]
        pub border_fraction: f64 = 0.8,
        /// Closest samples kept for the goal bias.
        #[param("max_close_samples", 1..=100_000)]
        pub max_close_samples: usize = 30,
        /// Score factor of a cell after a failed extension.
        #[param("bad_score_factor", Reals::closed(0.0, 1.0))]
        pub bad_score_factor: f64 = 0.45,
        /// Score factor of a cell after a successful extension.
        #[param("good_score_factor", Reals::closed(0.0, 1.0))]
        pub good_score_factor: f64 = 0.9,
        /// Control durations.
        #[params]
        pub durations: Durations,
    }
}

declare_params! {
    /// OMPL's `control::EST` (grid over the agents' positions).
    #[derive(Debug, Clone)]
    pub struct Est {
        /// Probability of steering toward a goal sample.
        #[param("goal_bias", Reals::closed(0.0, 1.0))]
        pub goal_bias: f64 = 0.05,
        /// Largest distance to the sample a motion aims at (0: OMPL chooses).
        #[param("range", Reals::closed(0.0, f64::MAX))]
        pub range: f64 = 0.0,
        /// Control durations.
        #[params]
        pub durations: Durations,
    }
}

declare_params! {
    /// OMPL's `control::PDST` (subdivision of the agents' positions).
    #[derive(Debug, Clone)]
    pub struct Pdst {
        /// Probability of steering toward a goal sample.
        #[param("goal_bias", Reals::closed(0.0, 1.0))]
        pub goal_bias: f64 = 0.05,
        /// Control durations.
        #[params]
        pub durations: Durations,
    }
}

macro_rules! durations_of {
    ($($t:ty),*) => {$(
        impl OmplParams for $t {
            fn durations(&self) -> &Durations {
                &self.durations
            }
        }
    )*};
}
durations_of!(Rrt, Kpiece, Est, Pdst);

impl OmplParams for Sst {
    fn durations(&self) -> &Durations {
        &self.durations
    }
    fn stop_on_solution(&self) -> bool {
        self.stop_on_solution
    }
}
