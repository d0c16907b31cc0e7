//! The table of every per-run metric, in `runs.csv` column order. Each entry's doc comment is
//! its definition (it becomes [`super::Def::doc`]).

use super::Aggregation::Sum;
use super::Compute::{Path, Plan, Track};
use super::Direction::{Higher, Lower};
use super::Regress::{Gated, Shown, WallClock};
use super::{Def, path};

/// Declares [`Metric`] (one variant per entry) and [`TABLE`] (the entries, in the same order).
macro_rules! metrics {
    ($( $(#[doc = $doc:literal])+ $id:ident = $def:expr; )*) => {
        /// A metric of the table.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Metric {
            $( $(#[doc = $doc])+ $id, )*
        }

        impl Metric {
            /// Every metric, in table order.
            pub const ALL: &'static [Metric] = &[$(Metric::$id,)*];
        }

        /// Every metric's declaration, indexed by [`Metric`].
        pub static TABLE: [Def; Metric::ALL.len()] = [$( $def.doc(concat!($($doc, "\n"),+)), )*];
    };
}

fn count(n: usize) -> Option<f64> {
    Some(n as f64)
}

metrics! {
    /// Iterations run, over all legs planned.
    Iterations = Def::new("iterations", "iterations", "", Lower,
        Plan(|f| Some(f.legs.iter().map(|r| r.iterations as f64).sum())))
        .ompl("iterations INTEGER");
    /// Nodes in the planners' trees at the end, over all legs.
    Nodes = Def::new("nodes", "tree nodes", "", Lower,
        Plan(|f| Some(f.legs.iter().map(|r| r.nodes as f64).sum())))
        .ompl("graph states INTEGER");
    /// Planning wall time, over all legs (s).
    PlanTime = Def::new("plan_time_s", "planning time", "s", Lower,
        Plan(|f| Some(f.legs.iter().map(|r| r.time_s).sum())))
        .regress(WallClock).report(3).ompl("time REAL");
    /// Cost of the plan, the sum of the legs' (solved runs).
    Cost = Def::new("cost", "final cost", "", Lower,
        Plan(|f| if f.solved { f.legs.iter().map(|r| r.cost).sum() } else { None }))
        .regress(Gated).plot("final-cost", "final cost of solved runs", true).report(2)
        .ompl("best cost REAL");
    /// Largest distance of an agent from its goal centre at the end of the last leg's plan (BL).
    GoalDistance = Def::new("goal_distance", "goal distance of the plan", "BL", Lower,
        Plan(|f| f.legs.last().map(|r| r.goal_distance)))
        .ompl("solution difference REAL");
    /// Iteration of the run's first exact solution (solved runs).
    FirstSolutionIteration = Def::new("first_solution_iteration",
        "iterations to 1st solution", "", Lower, Plan(|f| f.first_solution.map(|s| s.0 as f64)))
        .regress(Gated).report(0).ompl("first solution iterations INTEGER");
    /// Time of the run's first exact solution (s; solved runs).
    FirstSolutionTime = Def::new("first_solution_time_s", "time to 1st solution", "s", Lower,
        Plan(|f| f.first_solution.map(|s| s.1)))
        .regress(WallClock).plot("time-to-first-solution", "time to first solution", true)
        .report(3).ompl("first solution time REAL");
    /// Edges in the plan, over all legs.
    PlanEdges = Def::new("plan_edges", "plan edges", "", Lower,
        Plan(|f| Some(f.legs.iter().map(|r| r.plan.edges() as f64).sum())))
        .ompl("solution segments INTEGER");
    /// Duration of the plan, over all legs (s of motion).
    PlanDuration = Def::new("plan_duration_s", "plan duration", "s", Lower,
        Plan(|f| Some(f.legs.iter().map(|r| r.plan.duration()).sum())))
        .ompl("solution duration REAL");
    /// Simulated time to reach the final goal (s).
    TimeToGoal = Def::new("time_to_goal_s", "time to goal", "s", Lower,
        Track(|f| f.metrics.time_to_goal_s))
        .report(1).ompl("tracking time to goal REAL");
    /// RMS path error of the observed positions, over agents and ticks (BL): what a rig
    /// measures (definitions: docs/tracking.md, "Metrics").
    RmsError = Def::new("rms_error_bl", "RMS error, observed", "BL", Lower,
        Track(|f| Some(f.metrics.rms_error_bl)))
        .regress(Gated).plot("rms-error", "RMS tracking error (observed positions)", true)
        .report(3).ompl("tracking rms error REAL");
    /// Largest path error of an observed position (BL).
    MaxError = Def::new("max_error_bl", "max error", "BL", Lower,
        Track(|f| Some(f.metrics.max_error_bl)))
        .regress(Gated).plot("max-error", "max tracking error", true).report(3)
        .ompl("tracking max error REAL");
    /// RMS path error of the worst agent (the largest RMS of any agent), observed positions (BL).
    RmsErrorWorstAgent = Def::new("rms_error_worst_agent_bl", "worst agent's RMS, observed",
        "BL", Lower, Track(|f| Some(f.metrics.rms_error_worst_agent_bl)))
        .regress(Gated)
        .plot("rms-error-worst-agent", "RMS tracking error of the worst agent (observed positions)", true)
        .report(3).ompl("tracking worst agent rms error REAL");
    /// RMS path error of the true positions (BL); empty when the rig does not know them.
    RmsErrorTrue = Def::new("rms_error_true_bl", "RMS error, true", "BL", Lower,
        Track(|f| f.metrics.rms_error_true_bl))
        .regress(Gated).plot("rms-error-true", "RMS tracking error (true positions)", true)
        .report(3);
    /// Largest path error of a true position (BL); empty as `rms_error_true_bl`.
    MaxErrorTrue = Def::new("max_error_true_bl", "max error, true", "BL", Lower,
        Track(|f| f.metrics.max_error_true_bl))
        .regress(Gated);
    /// RMS path error of the worst agent by its true positions (BL); empty as
    /// `rms_error_true_bl`.
    RmsErrorTrueWorstAgent = Def::new("rms_error_true_worst_agent_bl",
        "worst agent's RMS, true", "BL", Lower, Track(|f| f.metrics.rms_error_true_worst_agent_bl))
        .regress(Gated)
        .plot("rms-error-true-worst-agent", "RMS tracking error of the worst agent (true positions)", false);
    /// RMS team-synchronous error of the observed positions (BL): the team against the nearest
    /// common point of the team path.
    RmsErrorSync = Def::new("rms_error_sync_bl", "team-synchronous RMS", "BL", Lower,
        Track(|f| Some(f.metrics.rms_error_sync_bl)))
        .regress(Gated).plot("rms-error-sync", "team-synchronous RMS error (observed)", true)
        .report(3);
    /// RMS time-indexed error of the observed positions (BL): the team against the reference
    /// at the same elapsed time.
    RmsErrorTime = Def::new("rms_error_time_bl", "time-indexed RMS", "BL", Lower,
        Track(|f| Some(f.metrics.rms_error_time_bl)))
        .regress(Gated).plot("rms-error-time", "time-indexed RMS error (observed)", true)
        .report(3);
    /// RMS node error of the observed positions (BL): the team against its nearest node of the
    /// plan being followed, the seed's tracking error (Sec. III-B).
    RmsErrorNode = Def::new("rms_error_node_bl", "node RMS, the seed's", "BL", Lower,
        Track(|f| Some(f.metrics.rms_error_node_bl)))
        .regress(Gated).report(3);
    /// RMS node error of the true positions (BL); empty as `rms_error_true_bl`.
    RmsErrorNodeTrue = Def::new("rms_error_node_true_bl", "node RMS, true", "BL", Lower,
        Track(|f| f.metrics.rms_error_node_true_bl));
    /// Legs completed while tracking.
    LegsCompleted = Def::new("legs_completed", "legs completed", "", Higher,
        Track(|f| count(f.metrics.legs_completed)))
        .ompl("tracking legs completed INTEGER");
    /// Largest agent distance from its goal centre at the end of tracking (BL).
    FinalDistance = Def::new("final_distance_bl", "final goal distance", "BL", Lower,
        Track(|f| Some(f.metrics.final_goal_distance_bl)))
        .ompl("tracking final distance REAL");
    /// Wall contact events while tracking.
    WallContacts = Def::new("wall_contacts", "wall contacts", "", Lower,
        Track(|f| count(f.metrics.wall_contacts)))
        .aggregate(Sum).report(0).ompl("tracking wall contacts INTEGER");
    /// Frames with at least one missed detection (or no frame at all).
    MissedFrames = Def::new("missed_frames", "missed frames", "", Lower,
        Track(|f| count(f.metrics.missed_frames)))
        .aggregate(Sum).ompl("tracking missed frames INTEGER");
    /// Replans during tracking (one per leg after the first, plus those for a persistent
    /// tracking error).
    Replans = Def::new("replans", "replans", "", Lower, Track(|f| count(f.metrics.replans)))
        .aggregate(Sum).report(0).ompl("tracking replans INTEGER");
    /// Simulated duration of tracking (s).
    TrackDuration = Def::new("track_duration_s", "tracking duration", "s", Lower,
        Track(|f| Some(f.metrics.duration_s)))
        .ompl("tracking duration REAL");
    /// Tracking wall time (s).
    TrackTime = Def::new("track_time_s", "tracking wall time", "s", Lower,
        Track(|f| Some(f.wall_s)))
        .wall_clock().ompl("tracking time REAL");
    /// Path length: the sum over agents of the length of each agent's polyline through the
    /// plan's waypoints (BL). Bench-MR's path length; OMPL's `solution length`.
    PathLength = Def::new("path_length_bl", "path length", "BL", Lower,
        Path(|f| Some(path::length(f.plan))))
        .regress(Shown).plot("path-length", "path length of the plan (all agents)", false)
        .report(1).ompl("solution length REAL");
    /// Turning: the sum over agents of the turning angles at the interior waypoints of each
    /// agent's polyline (rad). Bench-MR's curvature of a polyline.
    Turning = Def::new("turning_rad", "total turning", "rad", Lower,
        Path(|f| Some(path::turning(f.plan))))
        .regress(Shown).ompl("solution turning REAL");
    /// Smoothness: OMPL's `PathGeometric::smoothness`, `Σ (2φ / (a + b))²` over consecutive
    /// segments of lengths a, b meeting at exterior angle φ, summed over agents (1/BL²; 0 is
    /// straight). OMPL's `solution smoothness`; Bench-MR's smoothness.
    Smoothness = Def::new("smoothness", "smoothness", "1/BL²", Lower,
        Path(|f| Some(path::smoothness(f.plan))))
        .regress(Shown).report(3).ompl("solution smoothness REAL");
    /// Cusps: waypoints at which an agent's direction turns by more than 90°, summed over
    /// agents. Bench-MR's cusps.
    Cusps = Def::new("cusps", "cusps", "", Lower, Path(|f| count(path::cusps(f.plan))))
        .regress(Shown).report(0).ompl("solution cusps INTEGER");
    /// Minimum clearance: the smallest distance of an agent's disk to a wall or obstacle
    /// along the plan (BL; chords sampled every 0.1 BL). OMPL's `solution clearance`;
    /// Bench-MR's minimum clearance.
    ClearanceMin = Def::new("clearance_min_bl", "min clearance", "BL", Higher,
        Path(|f| Some(path::clearance(f.plan, &f.checker.collision).0)))
        .regress(Shown).plot("clearance-min", "smallest clearance to walls along the plan", false)
        .report(2).ompl("solution clearance REAL");
    /// Mean clearance: the mean distance of the agents' disks to walls and obstacles over the
    /// sampled points of the plan (BL). Bench-MR's mean clearance.
    ClearanceMean = Def::new("clearance_mean_bl", "mean clearance", "BL", Higher,
        Path(|f| Some(path::clearance(f.plan, &f.checker.collision).1)))
        .regress(Shown).report(2).ompl("solution mean clearance REAL");
    /// Proximity margin: the smallest margin of any pair's distance d to the proximity range,
    /// min(d − r_min, r_max − d), along the plan (BL): how close the team came to contact or to
    /// losing each other. Empty for one agent.
    ProximityMargin = Def::new("proximity_margin_bl", "proximity margin", "BL", Higher,
        Path(|f| path::proximity_margin(f.plan, f.checker)))
        .regress(Shown).report(2).ompl("solution proximity margin REAL");
    /// Control switches: consecutive edges whose controls (θ_B, α, gradient) differ.
    ControlSwitches = Def::new("control_switches", "control switches", "", Lower,
        Path(|f| count(path::control_switches(f.plan))))
        .regress(Shown).ompl("solution control switches INTEGER");
    /// Field flips: consecutive edges whose commanded field angle θ_B differs by more than 90°.
    FieldFlips = Def::new("field_flips", "field flips", "", Lower,
        Path(|f| count(path::field_flips(f.plan))))
        .regress(Shown).report(0).ompl("solution field flips INTEGER");
    /// Field-angle variation: the total variation Σ|Δθ_B| of the commanded field angle between
    /// consecutive edges, per second of plan (rad/s).
    FieldVariation = Def::new("field_variation_rad_s", "field-angle variation", "rad/s", Lower,
        Path(|f| path::field_variation_rate(f.plan)))
        .regress(Shown).report(3).ompl("solution field variation REAL");
    /// The node error of a team exactly on the plan (BL): the part of `rms_error_node_bl` that
    /// is the plan's node spacing, not the tracking.
    NodeFloor = Def::new("node_floor_bl", "node RMS on the plan", "BL", Lower,
        Path(|f| path::node_floor(f.plan)))
        .regress(Shown);
}
