//! The real executor: planners from `magbench-planners`, trackers from `magbench-trackers`,
//! the plant from `magbench-env`.

use super::{Executor, RunOutput, RunSpec, Variant};

/// Runs real planners (and trackers) by registry name.
#[derive(Debug, Clone, Copy, Default)]
pub struct RealExecutor;

impl Executor for RealExecutor {
    fn name(&self) -> &str {
        "real"
    }

    fn check_planner(&self, v: &Variant) -> Result<(), String> {
        Err(format!(
            "unknown planner {:?}: the planner registry is not available in this build yet",
            v.name
        ))
    }

    fn check_tracker(&self, v: &Variant) -> Result<(), String> {
        Err(format!(
            "unknown tracker {:?}: the tracker registry is not available in this build yet",
            v.name
        ))
    }

    fn execute(&self, spec: &RunSpec) -> Result<RunOutput, String> {
        Err(format!("cannot run {}: no planner registry", spec.id()))
    }
}
