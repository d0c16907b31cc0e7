//! What a plugin needs to write a planner, a tracker or a rig, in one `use magbench::prelude::*;`.
//!
//! This is the stable surface for code outside the workspace: a plugin that uses only these
//! names (and `magbench::Cli`, [`crate::Registry`]) keeps building as magbench's internals move.
//! See `docs/plugins.md` and `examples/plugin-crate/`.
//!
//! **A planner** implements [`Planner`] (and [`ParamSet`], usually through
//! [`declare_params!`]): [`Planner::solve`] gets a [`Problem`] — the leg's start, [`Goal`],
//! world, planning model, validity checker, control period, [`Limits`] and seed — and returns a
//! [`PlannerResult`] holding a [`Plan`]. The problem's own operations are the ones the
//! built-in planners use:
//!
//! - sampling: [`StateSampler::uniform`] (the whole space), [`StateSampler::zoom`] (about the
//!   goal), [`valid_sample`] (redraw until valid), [`random_control`];
//! - propagation and checks: [`propagate`] (no check), [`propagate_valid`] (the motion check
//!   the planners use), [`propagate_checked`] (the same, with the path length),
//!   `problem.checker.is_valid(state)`, `problem.goal.contains(state)`;
//! - bookkeeping: [`Progress`] (limits and the cost-versus-iteration trace of the plots),
//!   [`plan_cost`] (the problem's objective), [`Rng`] seeded by `problem.seed`.
//!
//! Every plan is checked by the harness ([`validate_result`], [`validate_plan`]) before it is
//! scored or followed: edges of whole control periods, controls within the coil's limits,
//! every motion valid.
//!
//! **A tracker** implements [`Tracker`]: once per camera frame, [`Tracker::command`] gets the
//! [`TrackerContext`] (the [`Reference`] being followed, the model, the checker, the period,
//! the goal) and a [`Tick`] (time and estimated state) and returns a [`Control`].
//!
//! **A rig** implements [`RigKind`] (how it loads from its argument: a preset, a rig file) and
//! [`RigDescription`] (its frame period and plant, and [`RigDescription::open`], which gives a
//! [`RunRig`]: the loop's [`Rig`] — observe, command, stop — plus its label).

pub use magbench_drivers::rigs::{
    OpenError, RigDescription, RigKind, RigPlant, RunRig, SimulatedRig,
};
pub use magbench_env::declare_params;
pub use magbench_env::params::{ParamError, ParamInfo, ParamSet, Reals, Value};
pub use magbench_env::{Coil, Control, Goal, InputError, MAX_AGENTS, Scenario, Vec2};
pub use magbench_planners::motion::{
    propagate, propagate_checked, propagate_valid, random_control, random_elevated_control,
};
pub use magbench_planners::progress::Progress;
pub use magbench_planners::sampler::{StateSampler, valid_sample};
pub use magbench_planners::search_settings::SearchSettings;
pub use magbench_planners::{
    Limits, Plan, PlanError, Planner, PlannerResult, Problem, ProgressPoint, Rng, Unusable,
    plan_cost, validate_plan, validate_result,
};
pub use magbench_trackers::{
    GroundTruth, LoopOptions, Reference, Rig, RigError, SimRig, Tick, Tracker, TrackerContext,
    TrackerStatus,
};
pub use rand::{RngExt, SeedableRng};
