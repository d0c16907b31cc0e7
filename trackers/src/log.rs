//! The per-tick log of a run and its CSV form.

use std::io::Write;

use magbench_env::{Control, Vec2};
use magbench_planners::Plan;

/// One control tick of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct TickRecord {
    /// Rig time since the first tick (s).
    pub t: f64,
    /// Leg being driven (0-based).
    pub leg: usize,
    /// Index of the plan being tracked in [`crate::TrackOutcome::plans`].
    pub plan: usize,
    /// Tracker mode.
    pub mode: &'static str,
    /// Reference time of the tracker's progress (s into the plan).
    pub progress_s: f64,
    /// The estimate the tracker acted on.
    pub estimate: Vec<Vec2>,
    /// The raw observation (capture-time positions; `None` = missed).
    pub observed: Vec<Option<Vec2>>,
    /// The true positions, when the rig knows them.
    pub truth: Option<Vec<Vec2>>,
    /// Per-agent tracking error (BL; NaN when there was no sample).
    pub error: Vec<f64>,
    /// The command sent.
    pub command: Control,
    /// The estimate was inside the current leg's goal.
    pub in_goal: bool,
    /// Per-agent targets of the tracker, if it has targets.
    pub targets: Option<Vec<Vec2>>,
}

impl TickRecord {
    /// The positions the metrics use: true if known, else the estimate.
    pub fn position(&self, i: usize) -> Vec2 {
        self.truth.as_ref().map_or(self.estimate[i], |t| t[i])
    }
}

/// Why a plan was made.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum PlanReason {
    /// The first plan of the run.
    Initial,
    /// The start of a new leg, from the observed state.
    Leg,
    /// A persistent tracking error.
    Error,
}

/// A plan the run tracked.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanRecord {
    /// Leg it was made for.
    pub leg: usize,
    /// Rig time (since the first tick) at which tracking it began (s).
    pub start_t: f64,
    /// Why it was made.
    pub reason: PlanReason,
    /// Whether the planner solved the problem exactly.
    pub solved: bool,
    /// Planning wall time (s).
    pub planning_time_s: f64,
    /// The plan.
    pub plan: Plan,
}

fn opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |x| format!("{x}"))
}

/// Writes the tick log as CSV: one row per tick; per-agent columns are suffixed by the agent
/// index (`x0_est`, `y0_est`, `x0_obs`, …, `err0`). Missing values are empty.
pub fn write_ticks_csv<W: Write>(w: W, ticks: &[TickRecord]) -> csv::Result<()> {
    let mut out = csv::Writer::from_writer(w);
    let n = ticks.first().map_or(0, |t| t.estimate.len());
    let mut header: Vec<String> = [
        "t_s",
        "leg",
        "plan",
        "mode",
        "progress_s",
        "theta_rad",
        "gx_t_per_m",
        "gy_t_per_m",
        "in_goal",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    for i in 0..n {
        for s in ["est", "obs", "true", "target"] {
            header.push(format!("x{i}_{s}"));
            header.push(format!("y{i}_{s}"));
        }
        header.push(format!("err{i}_bl"));
    }
    out.write_record(&header)?;
    for t in ticks {
        let mut row = vec![
            format!("{}", t.t),
            t.leg.to_string(),
            t.plan.to_string(),
            t.mode.to_string(),
            format!("{}", t.progress_s),
            format!("{}", t.command.theta),
            format!("{}", t.command.grad[0]),
            format!("{}", t.command.grad[1]),
            t.in_goal.to_string(),
        ];
        for i in 0..n {
            row.push(format!("{}", t.estimate[i].x));
            row.push(format!("{}", t.estimate[i].y));
            row.push(opt(t.observed[i].map(|p| p.x)));
            row.push(opt(t.observed[i].map(|p| p.y)));
            row.push(opt(t.truth.as_ref().map(|p| p[i].x)));
            row.push(opt(t.truth.as_ref().map(|p| p[i].y)));
            row.push(opt(t.targets.as_ref().map(|p| p[i].x)));
            row.push(opt(t.targets.as_ref().map(|p| p[i].y)));
            row.push(if t.error[i].is_nan() {
                String::new()
            } else {
                format!("{}", t.error[i])
            });
        }
        out.write_record(&row)?;
    }
    out.flush()?;
    Ok(())
}
