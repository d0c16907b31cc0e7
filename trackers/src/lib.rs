//! # magbench-trackers
//!
//! Plan tracking in closed loop: a [`Tracker`] turns the estimated team state into one coil
//! command per camera frame, and the one tracking loop ([`track`]) drives any [`Rig`] — the
//! simulated [`SimRig`] (env's plant and camera under a disturbance preset) or a physical rig
//! from the drivers crate — and measures the run ([`TrackMetrics`]).
//!
//! - [`rig`]: the rig seam ([`Rig`], [`RigError`]) and [`SimRig`];
//! - [`reference`]: a plan resampled at every integration step, the paths the error is
//!   measured against;
//! - [`estimator`]: latency compensation and missed detections;
//! - [`optimizer`]: the OBC's brute-force field-angle search with the closed-form pull;
//! - [`trackers`]: [`OpenLoop`], [`Obc`], [`Lookahead`], [`Formation`], [`Mppi`], one file each,
//!   by name in [`registry::Trackers`];
//! - [`run`]: the loop, replanning, and [`metrics`], scored per frame by [`scoring`];
//! - [`plan_file`]: plans as JSON, read back bit for bit.

#![warn(missing_docs)]

pub mod closed_loop;
pub mod estimator;
pub mod log;
pub mod metrics;
pub mod optimizer;
pub mod plan_file;
pub mod reference;
pub mod registry;
pub mod rig;
pub mod scoring;
pub mod sim_rig;
pub mod tracker;
pub mod trackers;

pub use closed_loop::{LoopOptions, Mission, TrackOutcome, reference_for, simulate, track};
pub use log::{PlanReason, PlanRecord, ReplanHow, ReplanRecord, TickRecord, write_ticks_csv};
pub use metrics::{AgentError, RunStatus, TrackMetrics, worst_agent};
pub use optimizer::{ObcOptimizer, ObcWeights};
pub use reference::Reference;
pub use registry::{TrackerSpec, Trackers};
pub use rig::{GroundTruth, Rig, RigError};
pub use sim_rig::SimRig;
pub use tracker::{Tick, Tracker, TrackerContext, TrackerStatus};
pub use trackers::{Formation, Lookahead, Mppi, Obc, OpenLoop};
