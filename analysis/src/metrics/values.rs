//! A run's metric values, one slot per table entry, and the facts each kind of computation
//! reads.

use magbench_env::collision::ValidityChecker;
use magbench_planners::{Plan, PlannerResult};
use magbench_trackers::TrackMetrics;

use super::slot::Slot;
use super::{Compute, Metric};

/// What the planning of a run produced: each leg's result and the run's first solution.
#[derive(Debug, Clone, Copy)]
pub struct PlanFacts<'a> {
    /// Each planned leg's result, in order.
    pub legs: &'a [PlannerResult],
    /// Every leg of the run was planned and solved.
    pub solved: bool,
    /// Iteration and time (s) of the run's first exact solution (legs' offsets added).
    pub first_solution: Option<(u64, f64)>,
}

/// A plan and the world it moves in: what the path-quality metrics read.
#[derive(Debug, Clone, Copy)]
pub struct PathFacts<'a> {
    /// The plan (of all legs for a planning run; the first leg's for a tracked run).
    pub plan: &'a Plan,
    /// Walls, obstacles and the proximity range `(r_min, r_max)`.
    pub checker: &'a ValidityChecker,
}

/// What the tracking loop of a run produced.
#[derive(Debug, Clone, Copy)]
pub struct TrackFacts<'a> {
    /// The loop's metrics.
    pub metrics: &'a TrackMetrics,
    /// Wall time the tracking took (s).
    pub wall_s: f64,
}

/// The value of every metric of one run (`None`: the run has none, an empty CSV cell).
#[derive(Debug, Clone, PartialEq)]
pub struct Values([Slot; Metric::ALL.len()]);

impl Default for Values {
    fn default() -> Self {
        Values([Slot::EMPTY; Metric::ALL.len()])
    }
}

impl Values {
    /// The value of `m`.
    pub fn get(&self, m: Metric) -> Option<f64> {
        self.0[m as usize].get()
    }

    /// Sets the value of `m`.
    pub fn set(&mut self, m: Metric, v: Option<f64>) {
        self.0[m as usize] = Slot::new(v);
    }

    /// Sets every planning metric from `f`.
    pub fn fill_plan(&mut self, f: &PlanFacts) {
        for m in Metric::ALL {
            if let Compute::Plan(c) = m.def().compute {
                self.set(*m, c(f));
            }
        }
    }

    /// Sets every path-quality metric from `f` (none for a plan without an edge).
    pub fn fill_path(&mut self, f: &PathFacts) {
        if f.plan.edges() == 0 {
            return;
        }
        for m in Metric::ALL {
            if let Compute::Path(c) = m.def().compute {
                self.set(*m, c(f));
            }
        }
    }

    /// Sets every tracking metric from `f`.
    pub fn fill_track(&mut self, f: &TrackFacts) {
        for m in Metric::ALL {
            if let Compute::Track(c) = m.def().compute {
                self.set(*m, c(f));
            }
        }
    }
}
