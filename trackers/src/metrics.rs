//! How well a plan was followed, scored as a rig scores it.
//!
//! **Tracking error.** At every control tick the positions of the agents are compared with the
//! reference of the plan being followed (the polyline through its integration samples,
//! [`crate::Reference`]; after a replan or a new leg, the new plan's). The three errors and
//! their exact definitions are in [`crate::scoring`]: the **path** error (each agent against
//! any point of its own path), the **team-synchronous** error (the team against the nearest
//! common point of the team path, the seed's `‖q_a − q_iτ‖`) and the **time-indexed** error
//! (the team against the reference at the same elapsed time); and against the plan's
//! **nodes** rather than its reference, the **node** error (the team against its nearest plan
//! node, the seed's `‖q_a − q_iτ‖` of Sec. III-B, which its ≈ 0.2 BL figure reports).
//!
//! Every headline figure uses the **observed** positions — the raw detections at capture
//! time, what a rig's camera measures — so a simulated run and a hardware run report the same
//! quantity. A missed detection gives no path sample for that agent, and no team sample for
//! that frame. The time-indexed error compares a detection with the reference at its capture
//! time. `rms_error_true_bl` keeps the path error of the true positions (when the rig knows
//! them: a simulation) — the tracking itself without the camera's noise.
//!
//! RMS is the root mean square over samples: over ticks and agents for the path error, over
//! ticks for the team errors; max is the largest sample.
//!
//! **Per agent.** Each agent's path error is also kept on its own ([`AgentError`], observed and
//! true), and the **worst agent** is the one with the largest RMS path error: in a team of
//! three or more the team's RMS can hide one agent that drifts while the others follow.

use serde::{Deserialize, Serialize};

/// Per-run metrics: every field a scalar (or an optional scalar), so one run is one CSV row.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrackMetrics {
    /// How the run ended (see [`RunStatus`]).
    pub status: RunStatus,
    /// The final goal region holds the team at the end (true state when known, else observed).
    pub reached_goal: bool,
    /// Seconds from the first tick until the final goal was reached.
    pub time_to_goal_s: Option<f64>,
    /// Largest agent distance from its final goal centre at the end (BL).
    pub final_goal_distance_bl: f64,
    /// Legs completed.
    pub legs_completed: usize,
    /// Legs in the scenario.
    pub legs: usize,
    /// RMS path error of the observed positions, over ticks and agents (BL).
    pub rms_error_bl: f64,
    /// Largest path error of any observed agent position (BL).
    pub max_error_bl: f64,
    /// RMS path error of the worst agent, observed positions (BL).
    pub rms_error_worst_agent_bl: f64,
    /// The worst agent (0-based): the largest RMS path error of its observed positions;
    /// `None` without any sample.
    pub worst_agent: Option<usize>,
    /// RMS path error of the true positions, over ticks and agents (BL); `None` when the rig
    /// does not know them (a physical rig).
    pub rms_error_true_bl: Option<f64>,
    /// Largest path error of any true agent position (BL); `None` as `rms_error_true_bl`.
    pub max_error_true_bl: Option<f64>,
    /// RMS path error of the worst agent by its true positions (the largest true RMS of any
    /// agent, BL); `None` as `rms_error_true_bl`.
    pub rms_error_true_worst_agent_bl: Option<f64>,
    /// RMS team-synchronous error of the observed positions, over ticks (BL).
    pub rms_error_sync_bl: f64,
    /// RMS time-indexed error of the observed positions, over ticks (BL).
    pub rms_error_time_bl: f64,
    /// RMS node error of the observed positions, over ticks (BL): the team against its nearest
    /// node of the plan being followed, the seed's tracking error.
    pub rms_error_node_bl: f64,
    /// RMS node error of the true positions, over ticks (BL); `None` as `rms_error_true_bl`.
    pub rms_error_node_true_bl: Option<f64>,
    /// Two agents touched (and stuck): a failed run.
    pub agent_contact: bool,
    /// Wall contact events.
    pub wall_contacts: usize,
    /// Frames with at least one missed detection (or no frame at all).
    pub missed_frames: usize,
    /// Missed agent detections.
    pub missed_detections: usize,
    /// Recoverable rig faults.
    pub rig_faults: usize,
    /// Replans (one per leg after the first, plus those for a persistent tracking error).
    pub replans: usize,
    /// Replans triggered by a persistent tracking error.
    pub error_replans: usize,
    /// Control ticks run.
    pub ticks: usize,
    /// Run length in rig time (s): the tracking time.
    pub duration_s: f64,
    /// Wall time spent planning, all plans (s).
    pub planning_time_s: f64,
    /// Wall time spent in the tracker's commands (s).
    pub tracker_compute_s: f64,
    /// Planning time plus tracking time (s), counting once the planning that a rig's running
    /// clock (a physical rig's) has in the tracking time already.
    pub total_time_s: f64,
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RunStatus {
    /// The team reached the final goal (and held it for the hold time).
    ReachedGoal,
    /// An open-loop tracker played its plan to the end outside the goal.
    PlanFinished,
    /// The time limit passed.
    Timeout,
    /// Two agents touched and stuck.
    AgentContact,
    /// No plan could be made.
    PlanningFailed,
    /// The rig failed fatally.
    RigFault,
    /// The run was cancelled (Ctrl-C).
    Cancelled,
}

impl RunStatus {
    /// The kebab-case name.
    pub fn as_str(&self) -> &'static str {
        match self {
            RunStatus::ReachedGoal => "reached-goal",
            RunStatus::PlanFinished => "plan-finished",
            RunStatus::Timeout => "timeout",
            RunStatus::AgentContact => "agent-contact",
            RunStatus::PlanningFailed => "planning-failed",
            RunStatus::RigFault => "rig-fault",
            RunStatus::Cancelled => "cancelled",
        }
    }
}

/// One agent's path error (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct AgentError {
    /// The agent (0-based, as in `ticks.csv`).
    pub agent: usize,
    /// RMS over ticks of the observed positions (BL).
    pub rms_bl: f64,
    /// Largest sample of the observed positions (BL).
    pub max_bl: f64,
    /// Samples (ticks with a detection of this agent).
    pub samples: usize,
    /// RMS over ticks of the true positions (BL); `None` when the rig does not know them.
    pub rms_true_bl: Option<f64>,
    /// Largest sample of the true positions (BL); `None` as `rms_true_bl`.
    pub max_true_bl: Option<f64>,
}

/// The worst of `agents`: the index and RMS of the largest observed RMS path error (the first
/// of equals), `None` when no agent has a sample.
pub fn worst_agent(agents: &[AgentError]) -> Option<(usize, f64)> {
    agents
        .iter()
        .filter(|a| a.samples > 0)
        .fold(None, |best: Option<&AgentError>, a| match best {
            Some(b) if b.rms_bl >= a.rms_bl => Some(b),
            _ => Some(a),
        })
        .map(|a| (a.agent, a.rms_bl))
}

/// Accumulates per-agent error samples.
#[derive(Debug, Clone, Default)]
pub struct ErrorAccumulator {
    sum_sq: Vec<f64>,
    max: Vec<f64>,
    count: Vec<usize>,
}

impl ErrorAccumulator {
    /// An accumulator for `agents` agents.
    pub fn new(agents: usize) -> Self {
        ErrorAccumulator {
            sum_sq: vec![0.0; agents],
            max: vec![0.0; agents],
            count: vec![0; agents],
        }
    }

    /// Adds one sample of agent `i`.
    pub fn add(&mut self, i: usize, e: f64) {
        self.sum_sq[i] += e * e;
        self.max[i] = self.max[i].max(e);
        self.count[i] += 1;
    }

    /// Per-agent figures.
    pub fn per_agent(&self) -> Vec<AgentError> {
        (0..self.sum_sq.len())
            .map(|i| AgentError {
                agent: i,
                rms_bl: if self.count[i] > 0 {
                    (self.sum_sq[i] / self.count[i] as f64).sqrt()
                } else {
                    0.0
                },
                max_bl: self.max[i],
                samples: self.count[i],
                rms_true_bl: None,
                max_true_bl: None,
            })
            .collect()
    }

    /// RMS over all samples of all agents.
    pub fn rms(&self) -> f64 {
        let n: usize = self.count.iter().sum();
        if n == 0 {
            0.0
        } else {
            (self.sum_sq.iter().sum::<f64>() / n as f64).sqrt()
        }
    }

    /// Largest sample of any agent.
    pub fn max(&self) -> f64 {
        self.max.iter().copied().fold(0.0, f64::max)
    }
}

/// Accumulates the samples of one team-wide error (one per tick).
#[derive(Debug, Clone, Copy, Default)]
pub struct TeamAccumulator {
    sum_sq: f64,
    count: usize,
}

impl TeamAccumulator {
    /// Adds one sample.
    pub fn add(&mut self, e: f64) {
        self.sum_sq += e * e;
        self.count += 1;
    }

    /// RMS over the samples (0 without any).
    pub fn rms(&self) -> f64 {
        if self.count == 0 {
            0.0
        } else {
            (self.sum_sq / self.count as f64).sqrt()
        }
    }

    /// Samples added.
    pub fn samples(&self) -> usize {
        self.count
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rms_and_max() {
        let mut a = ErrorAccumulator::new(2);
        for e in [0.0, 3.0, 4.0] {
            a.add(0, e);
        }
        a.add(1, 1.0);
        let p = a.per_agent();
        assert!((p[0].rms_bl - (25.0f64 / 3.0).sqrt()).abs() < 1e-12);
        assert_eq!(p[0].max_bl, 4.0);
        assert!((a.rms() - (26.0f64 / 4.0).sqrt()).abs() < 1e-12);
        assert_eq!(a.max(), 4.0);
        assert_eq!(p[1].agent, 1);
        assert_eq!(worst_agent(&p), Some((0, p[0].rms_bl)));
        let mut t = TeamAccumulator::default();
        assert_eq!(t.rms(), 0.0);
        t.add(3.0);
        t.add(4.0);
        assert!((t.rms() - 12.5f64.sqrt()).abs() < 1e-12);
        assert_eq!(t.samples(), 2);
    }

    #[test]
    fn the_worst_agent_is_the_largest_rms_with_samples() {
        let mut a = ErrorAccumulator::new(4);
        a.add(0, 0.1);
        a.add(1, 0.3);
        a.add(2, 0.3);
        // agent 3 has no sample: never the worst
        let p = a.per_agent();
        assert_eq!(worst_agent(&p), Some((1, 0.3)));
        assert_eq!(worst_agent(&ErrorAccumulator::new(3).per_agent()), None);
    }

    #[test]
    fn metrics_serialize_flat() {
        let m = TrackMetrics {
            status: RunStatus::ReachedGoal,
            reached_goal: true,
            time_to_goal_s: None,
            final_goal_distance_bl: 0.1,
            legs_completed: 1,
            legs: 1,
            rms_error_bl: 0.05,
            max_error_bl: 0.2,
            rms_error_worst_agent_bl: 0.06,
            worst_agent: Some(1),
            rms_error_true_bl: Some(0.04),
            max_error_true_bl: Some(0.15),
            rms_error_true_worst_agent_bl: Some(0.05),
            rms_error_sync_bl: 0.07,
            rms_error_time_bl: 0.3,
            rms_error_node_bl: 0.2,
            rms_error_node_true_bl: Some(0.19),
            agent_contact: false,
            wall_contacts: 0,
            missed_frames: 1,
            missed_detections: 1,
            rig_faults: 0,
            replans: 0,
            error_replans: 0,
            ticks: 10,
            duration_s: 1.0,
            planning_time_s: 0.01,
            tracker_compute_s: 0.001,
            total_time_s: 1.01,
        };
        let mut w = csv::Writer::from_writer(vec![]);
        w.serialize(&m).unwrap();
        let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
        assert!(text.starts_with("status,reached_goal,"), "{text}");
        assert!(text.contains("reached-goal,true,,0.1"), "{text}");
    }
}
