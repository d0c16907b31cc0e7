//! The search settings every planner embeds: EXTEND's tries and edge durations
//! (the seed's Algorithm 3) and the goal-zoom sampler (Algorithm 2). Declared once, so every
//! planner takes `k`, `min_duration`, `max_duration`, `goal_bias`, `zoom_radius`, `timing`,
//! `planar`, `guide` and `aim` alike. (Post-processing, `shortcut` and `straighten`, is the
//! run's step, crate::post_process, not a search setting.)
//!
//! `planar` says whether EXTEND draws the field elevation too: `auto` (the default) keeps two
//! agents in the plane — the random stream is then exactly the planar one — and draws
//! (θ_B, α, G_x, G_y) for three or more when their medium carries the out-of-plane force (the
//! problem's model says), with α in [0, α_max] of the planning setup.
//!
//! Durations are given in seconds and used in whole control periods of the problem (the
//! camera frames of the rig that will run the plan): the nearest whole number, at least one.

use magbench_env::coil::Planar;
use magbench_env::declare_params;
use magbench_env::input::Rejection;
use magbench_env::params::Reals;

use crate::Problem;
use crate::extend::{Extend, Timing};
use crate::guide::Guide;
use crate::sampler::GoalZoom;

declare_params! {
    /// The search settings every planner embeds (EXTEND's tries and durations, goal zoom).
    #[derive(Debug, Clone, PartialEq)]
    pub struct SearchSettings {
        /// EXTEND's random (control, duration) tries per call (the seed's k; 1 = SST's
        /// Monte-Carlo propagation).
        #[param("k", 1..=100_000)]
        pub tries: usize = 12,
        /// Shortest edge (s), rounded to whole control periods (camera frames).
        #[param("min_duration", Reals::POSITIVE)]
        pub min_duration: f64 = 0.25,
        /// Longest edge (s; SST's T_prop), rounded to whole control periods (camera frames).
        #[param("max_duration", Reals::POSITIVE)]
        pub max_duration: f64 = 2.0,
        /// Probability of sampling the goal-zoom region.
        #[param("goal_bias", Reals::closed(0.0, 1.0))]
        pub goal_bias: f64 = 0.2,
        /// Radius of each agent's goal-zoom disk about its goal centre (BL).
        #[param("zoom_radius", Reals::POSITIVE)]
        pub zoom_radius: f64 = 1.5,
        /// Each EXTEND try's duration: random (the seed's) or closest (the period at which the
        /// try passes closest to its target).
        #[param("timing")]
        pub timing: Timing = Timing::Random,
        /// Whether the field stays in the plane: `auto` (two agents, or a medium that does not
        /// carry the out-of-plane force, yes; three or more at an interface no), `true` or
        /// `false` (refused in bulk).
        #[param("planar")]
        pub planar: Planar = Planar::Auto,
        /// Whether the sampler draws part of its whole-space samples near a shortest centroid
        /// path from start to goal, ahead of the tree (crate::guide; a heuristic only).
        #[param("guide")]
        pub guide: bool = false,
        /// Whether each EXTEND try's gradients are aimed: the field and duration random, the
        /// gradients the ones that carry the centroid closest to the target's (random timing
        /// only).
        #[param("aim")]
        pub aim: bool = false,
    }
    check(SearchSettings::check);
}

impl SearchSettings {
    /// EXTEND with these settings in the problem's control periods.
    pub fn extend(&self, problem: &Problem) -> Extend {
        self.extend_with(problem, self.tries)
    }

    /// EXTEND with `tries` tries and these durations and timing (RRT*'s CONNECT seeds).
    pub fn extend_with(&self, problem: &Problem, tries: usize) -> Extend {
        Extend {
            tries,
            min_periods: to_periods(self.min_duration, problem.control_period),
            max_periods: to_periods(self.max_duration, problem.control_period),
            timing: self.timing,
            alpha_max: self.elevation_free(problem).then_some(problem.alpha_max),
            aim: self.aim,
        }
    }

    /// Whether EXTEND may tilt the field for `problem`: its team size under `planar` and its
    /// medium.
    pub fn elevation_free(&self, problem: &Problem) -> bool {
        !self
            .planar
            .is_planar(problem.agents(), problem.model.carries_fz)
    }

    /// The goal-zoom sampler.
    pub fn zoom(&self) -> GoalZoom {
        GoalZoom {
            bias: self.goal_bias,
            radius: self.zoom_radius,
        }
    }

    /// The guide path of `problem` when `guide` is on and the map leaves one.
    pub fn guide(&self, problem: &Problem) -> Option<Guide> {
        if self.guide {
            Guide::new(problem)
        } else {
            None
        }
    }

    fn check(&self) -> Result<(), Rejection> {
        check_durations(self.min_duration, self.max_duration)?;
        if self.aim && self.timing == Timing::Closest {
            // a try's gradients are aimed over its duration, which `closest` picks after them
            return Err(Rejection::new(
                "aim",
                "aim=true needs timing=random (timing=closest picks each try's duration after its control)",
            ));
        }
        Ok(())
    }
}

/// The one rule between an edge's duration bounds (s): the shortest may not exceed the longest.
pub fn check_durations(min_duration: f64, max_duration: f64) -> Result<(), Rejection> {
    if min_duration > max_duration {
        return Err(Rejection::new(
            "",
            format!("min_duration {min_duration} exceeds max_duration {max_duration}"),
        ));
    }
    Ok(())
}

/// `seconds` in whole control periods of `period` seconds: the nearest whole number, at least
/// one.
pub fn to_periods(seconds: f64, period: f64) -> u32 {
    ((seconds / period).round() as u32).max(1)
}
