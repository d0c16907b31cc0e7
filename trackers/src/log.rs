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
    /// Wall time the tracker took for this tick's command (µs).
    pub compute_us: f64,
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
    /// A stall: no progress along the plan for the loop's `replan_after` (teams of three or
    /// more, the loop's `replan_stall`).
    Stall,
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

/// How a replan found its plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ReplanHow {
    /// Repair rejoined the plan being followed (its rest replayed, after a steer or none).
    Rejoin,
    /// Repair's small tree reached the plan being followed.
    Tree,
    /// The mission's planner, from scratch.
    Full,
    /// No usable plan came back.
    Failed,
}

/// One replan of a run: a new leg's plan, or a replan for a persistent error or a stall,
/// whether a plan came of it or not.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ReplanRecord {
    /// Rig time since the first tick when it was made (s).
    pub t_s: f64,
    /// Leg it was made for (0-based).
    pub leg: usize,
    /// Why it was made.
    pub reason: PlanReason,
    /// How its plan was found.
    pub how: ReplanHow,
    /// Its whole wall time: repair, the planner, and the validator (s).
    pub wall_s: f64,
    /// The same span's CPU time on the loop's thread (s), where the platform reports it: the
    /// time on a core of its own, whatever the load.
    pub cpu_s: Option<f64>,
    /// Rejoins repair tried (load-independent work).
    pub rejoins: u64,
    /// Iterations of repair's tree.
    pub tree_iterations: u64,
    /// Edges repair propagated and checked (its tree's, steers' and replayed ones).
    pub repair_edges: u64,
    /// Iterations of the mission's planner (0 when it was not called).
    pub planner_iterations: u64,
}

fn opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |x| format!("{x}"))
}

/// Writes the tick log as CSV: one row per tick; the command is `theta_rad` (in-plane field
/// angle θ_B), `alpha_rad` (the commanded elevation α out of the plane; 0 for planar
/// actuation) and the gradient; per-agent columns are suffixed by the agent index (`x0_est`,
/// `y0_est`, `x0_obs`, …, `err0_bl`). Missing values are empty.
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
        "alpha_rad",
        "gx_t_per_m",
        "gy_t_per_m",
        "in_goal",
        "compute_us",
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
            format!("{}", t.command.alpha),
            format!("{}", t.command.grad[0]),
            format!("{}", t.command.grad[1]),
            t.in_goal.to_string(),
            format!("{:.1}", t.compute_us),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_csv_records_the_commanded_elevation_next_to_theta() {
        let tick = TickRecord {
            t: 0.1,
            leg: 0,
            plan: 0,
            mode: "track",
            progress_s: 0.0,
            estimate: vec![Vec2::new(1.0, 2.0); 3],
            observed: vec![Some(Vec2::new(1.0, 2.0)), None, Some(Vec2::new(3.0, 4.0))],
            truth: None,
            error: vec![0.1, f64::NAN, 0.2],
            command: Control {
                theta: 0.5,
                alpha: 0.25,
                grad: [0.01, -0.02],
            },
            in_goal: false,
            targets: None,
            compute_us: 12.0,
        };
        let mut buf = vec![];
        write_ticks_csv(&mut buf, &[tick]).unwrap();
        let text = String::from_utf8(buf).unwrap();
        let mut rd = csv::Reader::from_reader(text.as_bytes());
        let header = rd.headers().unwrap().clone();
        let col = |name: &str| header.iter().position(|h| h == name).unwrap();
        assert_eq!(col("alpha_rad"), col("theta_rad") + 1);
        let row = rd.records().next().unwrap().unwrap();
        assert_eq!(&row[col("theta_rad")], "0.5");
        assert_eq!(&row[col("alpha_rad")], "0.25");
        // one block of columns per agent, the third agent's last
        assert_eq!(&row[col("err2_bl")], "0.2");
        assert_eq!(&row[col("x1_obs")], "");
        assert_eq!(header.len(), 11 + 3 * 9);
    }
}
