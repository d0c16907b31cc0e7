//! The metrics recorder: everything a run counts, times and logs, turned into
//! [`TrackMetrics`] at the end.
//!
//! The loop reports events to it (an observation, a rig fault, a plan, a tracker command, the
//! end of a tick); the recorder alone decides what they add up to. A new metric is a field
//! here and a line in [`Recorder::finish`].

use magbench_env::plant::Observation;
use magbench_env::{Control, Goal, Vec2};

use super::TrackOutcome;
use super::tick::TickContext;
use crate::log::{PlanRecord, ReplanRecord, TickRecord};
use crate::metrics::{
    AgentError, ErrorAccumulator, RunStatus, TeamAccumulator, TrackMetrics, worst_agent,
};
use crate::reference::Reference;
use crate::scoring;
use crate::tracker::TrackerStatus;

/// Counts, times and logs of one run.
#[derive(Debug, Clone)]
pub struct Recorder {
    record_ticks: bool,
    /// Path error of the observed positions.
    errors: ErrorAccumulator,
    /// Path error of the true positions (when the rig knows them).
    true_errors: Option<ErrorAccumulator>,
    /// Team-synchronous error of the observed positions.
    sync_errors: TeamAccumulator,
    /// Time-indexed error of the observed positions.
    time_errors: TeamAccumulator,
    /// Node error of the observed positions.
    node_errors: TeamAccumulator,
    /// Node error of the true positions (when the rig knows them).
    node_true_errors: Option<TeamAccumulator>,
    plans: Vec<PlanRecord>,
    replans: Vec<ReplanRecord>,
    ticks: Vec<TickRecord>,
    /// The run's notes in the order they first came, each with how many times it came.
    notes: Vec<(String, usize)>,
    tick_count: usize,
    missed_frames: usize,
    missed_detections: usize,
    rig_faults: usize,
    planning_time: f64,
    /// Wall time of the planning calls since the last tick (s).
    planning_since_tick: f64,
    /// Rig time that passed while the loop planned (s): already in the run's duration.
    planning_in_rig_time: f64,
    tracker_time: f64,
    last_compute: f64,
    /// The team's last known state: the truth when the rig knows it, else the estimate.
    last_estimate: Vec<Vec2>,
    last_truth: Option<Vec<Vec2>>,
}

/// What the loop knows at the end that the recorder does not count itself.
pub struct RunEnd<'a> {
    /// How the run ended.
    pub status: RunStatus,
    /// The final goal.
    pub goal: &'a Goal,
    /// Legs completed, of how many.
    pub legs: (usize, usize),
    /// Rig time from the first tick to the final goal, if it was reached.
    pub time_to_goal: Option<f64>,
    /// Rig time from the first tick to the last (s).
    pub duration: f64,
    /// Agent contact happened.
    pub agent_contact: bool,
    /// Wall contact events.
    pub wall_contacts: usize,
    /// Replans for a persistent tracking error.
    pub error_replans: usize,
}

impl Recorder {
    /// A recorder for a team starting at `start`; `planning_time` is the wall time of the plan
    /// made before the loop (s); `record_ticks` keeps the per-tick log.
    pub fn new(start: &[Vec2], planning_time: f64, record_ticks: bool) -> Self {
        Self {
            record_ticks,
            errors: ErrorAccumulator::new(start.len()),
            true_errors: None,
            sync_errors: TeamAccumulator::default(),
            time_errors: TeamAccumulator::default(),
            node_errors: TeamAccumulator::default(),
            node_true_errors: None,
            plans: vec![],
            replans: vec![],
            ticks: vec![],
            notes: Vec::new(),
            tick_count: 0,
            missed_frames: 0,
            missed_detections: 0,
            rig_faults: 0,
            planning_time,
            planning_since_tick: 0.0,
            planning_in_rig_time: 0.0,
            tracker_time: 0.0,
            last_compute: 0.0,
            last_estimate: start.to_vec(),
            last_truth: None,
        }
    }

    /// Adds `m` to the run's message; a note that came before is counted, not repeated.
    pub fn note(&mut self, m: String) {
        match self.notes.iter_mut().find(|(n, _)| *n == m) {
            Some((_, times)) => *times += 1,
            None => self.notes.push((m, 1)),
        }
    }

    /// The run's message: its notes joined by "; ", each repeated one followed by how many
    /// times it came.
    fn message(&self) -> Option<String> {
        let parts: Vec<String> = self
            .notes
            .iter()
            .map(|(m, times)| match times {
                1 => m.clone(),
                _ => format!("{m} ({times} times)"),
            })
            .collect();
        (!parts.is_empty()).then(|| parts.join("; "))
    }

    /// A recoverable rig fault.
    pub fn rig_fault(&mut self) {
        self.rig_faults += 1;
    }

    /// An observation arrived (or a frame was missing: every agent `None`).
    pub fn observation(&mut self, obs: &Observation) {
        let misses = obs.agents.iter().filter(|a| a.is_none()).count();
        self.missed_detections += misses;
        self.missed_frames += usize::from(misses > 0);
    }

    /// A planning call in the loop took `wall_s` seconds of wall time.
    pub fn planning(&mut self, wall_s: f64) {
        self.planning_time += wall_s;
        self.planning_since_tick += wall_s;
    }

    /// The next tick came `gap` seconds of rig time after the previous one, `period` apart
    /// nominally. A rig whose clock keeps running while the host plans (a physical rig) shows
    /// the planning as a longer gap; that rig time is in the run's duration already, so the
    /// total time must not count it twice. A simulated rig's clock stands still while the
    /// host plans: its gaps are one period, and nothing is taken off.
    pub fn tick_gap(&mut self, gap: f64, period: f64) {
        let planned = std::mem::take(&mut self.planning_since_tick);
        let extra = gap - period;
        if planned > 0.0 && extra > 0.5 * period {
            self.planning_in_rig_time += planned.min(extra);
        }
    }

    /// A plan was adopted.
    pub fn plan(&mut self, p: PlanRecord) {
        self.plans.push(p);
    }

    /// A replan was made (adopted or not).
    pub fn replan(&mut self, r: ReplanRecord) {
        self.replans.push(r);
    }

    /// Plans adopted so far.
    pub fn plans(&self) -> usize {
        self.plans.len()
    }

    /// The tracker's command took `wall_s` seconds.
    pub fn tracker_compute(&mut self, wall_s: f64) {
        self.tracker_time += wall_s;
        self.last_compute = wall_s;
    }

    /// Scores a tick against the reference adopted at rig time `start` (see
    /// [`crate::scoring`]): the observed positions' path errors (a missed detection gives no
    /// sample), their team-synchronous, time-indexed and node errors (a frame with a miss gives
    /// no team sample) and the true positions' path and node errors when the rig knows them.
    /// Returns the
    /// per-agent path errors of the observed positions (NaN where missed) and remembers the
    /// team's state.
    pub fn score(&mut self, tick: &TickContext, reference: &Reference, start: f64) -> Vec<f64> {
        self.tick_count += 1;
        let observed = &tick.observation.agents;
        let mut out = vec![f64::NAN; observed.len()];
        for (i, (e, p)) in out.iter_mut().zip(observed).enumerate() {
            if let Some(p) = p {
                *e = reference.distance_to_path(i, *p);
                self.errors.add(i, *e);
            }
        }
        if let Some(team) = observed.iter().copied().collect::<Option<Vec<Vec2>>>() {
            self.sync_errors
                .add(scoring::synchronous_error(reference, &team));
            let t = tick.observation.t - start;
            self.time_errors
                .add(scoring::time_indexed_error(reference, t, &team));
            self.node_errors.add(scoring::node_error(reference, &team));
        }
        if let Some(g) = tick.truth.as_ref() {
            let acc = self
                .true_errors
                .get_or_insert_with(|| ErrorAccumulator::new(g.positions.len()));
            for (i, e) in scoring::path_errors(reference, &g.positions)
                .into_iter()
                .enumerate()
            {
                acc.add(i, e);
            }
            self.node_true_errors
                .get_or_insert_with(TeamAccumulator::default)
                .add(scoring::node_error(reference, &g.positions));
            self.last_truth = Some(g.positions.clone());
        }
        self.last_estimate = tick.estimate.clone();
        out
    }

    /// Logs the end of a tick: what the tracker did and the command sent (`None`: the run
    /// ended at this tick).
    #[allow(clippy::too_many_arguments)]
    pub fn tick(
        &mut self,
        tick: &TickContext,
        leg: usize,
        reference: Option<&Reference>,
        status: TrackerStatus,
        error: Vec<f64>,
        command: Option<Control>,
        in_goal: bool,
    ) {
        if !self.record_ticks {
            return;
        }
        self.ticks.push(TickRecord {
            t: tick.elapsed(),
            leg,
            plan: self.plans.len().saturating_sub(1),
            mode: if command.is_some() {
                status.mode
            } else {
                "end"
            },
            progress_s: reference.map_or(0.0, |r| r.time(status.progress)),
            estimate: tick.estimate.clone(),
            observed: tick.observation.agents.clone(),
            truth: tick.truth.as_ref().map(|g| g.positions.clone()),
            error,
            command: command.unwrap_or_default(),
            in_goal,
            targets: status.targets,
            compute_us: if command.is_some() {
                self.last_compute * 1e6
            } else {
                0.0
            },
        });
    }

    /// Each agent's path error: observed, and true when the rig knows the truth.
    fn per_agent(&self) -> Vec<AgentError> {
        let truth = self.true_errors.as_ref().map(ErrorAccumulator::per_agent);
        let mut out = self.errors.per_agent();
        for (a, t) in out.iter_mut().zip(truth.iter().flatten()) {
            a.rms_true_bl = Some(t.rms_bl);
            a.max_true_bl = Some(t.max_bl);
        }
        out
    }

    /// Everything the run produced.
    pub fn finish(self, end: RunEnd) -> TrackOutcome {
        let message = self.message();
        let per_agent = self.per_agent();
        let final_state = self.last_truth.unwrap_or(self.last_estimate);
        let reached = end.status == RunStatus::ReachedGoal && end.goal.contains(&final_state);
        // the duration is rig time; planning that the rig's clock did not run through is added
        let total = self.planning_time + end.duration;
        let total = if self.planning_in_rig_time > 0.0 {
            total - self.planning_in_rig_time
        } else {
            total
        };
        let metrics = TrackMetrics {
            status: end.status,
            reached_goal: reached,
            time_to_goal_s: if reached { end.time_to_goal } else { None },
            final_goal_distance_bl: end.goal.distance(&final_state),
            legs_completed: end.legs.0,
            legs: end.legs.1,
            rms_error_bl: self.errors.rms(),
            max_error_bl: self.errors.max(),
            rms_error_worst_agent_bl: per_agent.iter().map(|a| a.rms_bl).fold(0.0, f64::max),
            worst_agent: worst_agent(&per_agent).map(|(i, _)| i),
            rms_error_true_bl: self.true_errors.as_ref().map(ErrorAccumulator::rms),
            max_error_true_bl: self.true_errors.as_ref().map(ErrorAccumulator::max),
            rms_error_true_worst_agent_bl: per_agent
                .iter()
                .map(|a| a.rms_true_bl)
                .reduce(|a, b| Some(a?.max(b?)))
                .flatten(),
            rms_error_sync_bl: self.sync_errors.rms(),
            rms_error_time_bl: self.time_errors.rms(),
            rms_error_node_bl: self.node_errors.rms(),
            rms_error_node_true_bl: self.node_true_errors.as_ref().map(TeamAccumulator::rms),
            agent_contact: end.agent_contact,
            wall_contacts: end.wall_contacts,
            missed_frames: self.missed_frames,
            missed_detections: self.missed_detections,
            rig_faults: self.rig_faults,
            replans: self.plans.len().saturating_sub(1),
            error_replans: end.error_replans,
            ticks: self.tick_count,
            duration_s: end.duration,
            planning_time_s: self.planning_time,
            tracker_compute_s: self.tracker_time,
            total_time_s: total,
        };
        TrackOutcome {
            message,
            metrics,
            per_agent,
            plans: self.plans,
            replans: self.replans,
            ticks: self.ticks,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_note_that_comes_again_is_counted_not_repeated() {
        let mut rec = Recorder::new(&[Vec2::zeros(), Vec2::new(2.0, 0.0)], 0.0, false);
        assert_eq!(rec.message(), None);
        let invalid = "error planning for leg 1: the observed state is not valid";
        rec.note(invalid.into());
        rec.note("stopping the rig failed: timeout".into());
        for _ in 0..26 {
            rec.note(invalid.into());
        }
        assert_eq!(
            rec.message().as_deref(),
            Some(
                "error planning for leg 1: the observed state is not valid (27 times); \
                 stopping the rig failed: timeout"
            )
        );
    }
}
