//! The tracking loop: one loop for every rig, every tracker and every scenario.
//!
//! Per control tick: observe → estimate (latency and misses, [`Estimator`]) → score the error
//! → goal, contact, time and replan checks → the tracker's command → send it. The rig is
//! stopped (zero field) on every exit path: a normal end, a fault, a cancel and a panic (a
//! guard stops it while unwinding).
//!
//! Replanning uses a [`Planner`]: at the start of every leg after the first, from the current
//! estimate and against that leg's obstacles (`Problem::from_scenario(scenario, leg,
//! Some(start), seed)`), and when the tracking error (of the estimate) stays above
//! `replan_error` for longer than `replan_after`.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use magbench_env::plant::{DisturbancePreset, Observation};
use magbench_env::{Control, Goal, PlanningModel, Scenario, ValidityChecker, Vec2};
use magbench_planners::{Limits, Plan, Planner, Problem};

use crate::estimator::Estimator;
use crate::log::{PlanReason, PlanRecord, TickRecord};
use crate::metrics::{AgentError, ErrorAccumulator, RunStatus, TrackMetrics};
use crate::reference::Reference;
use crate::rig::{Rig, RigError};
use crate::sim_rig::SimRig;
use crate::tracker::{Tick, Tracker, TrackerContext};

/// Settings of the loop (not of a tracker); set by `--param` like tracker parameters.
#[derive(Debug, Clone)]
pub struct LoopOptions {
    /// Tracking error (BL, largest agent distance from its path, of the estimate) that counts
    /// as persistent when it lasts `replan_after` seconds.
    pub replan_error: f64,
    /// Seconds the error must stay above `replan_error` before a replan; 0 disables.
    pub replan_after: f64,
    /// Most replans for a persistent error per run.
    pub max_replans: usize,
    /// Time limit per plan: `time_factor` × its duration + `time_slack` seconds.
    pub time_factor: f64,
    /// See `time_factor` (s).
    pub time_slack: f64,
    /// Seconds the team must stay in the goal region to complete a leg.
    pub hold: f64,
    /// The estimate must be this far inside the goal tolerance (BL).
    pub goal_margin: f64,
    /// How much a measurement moves the estimator's prior (1 = take it as it is).
    pub obs_weight: f64,
    /// Keep the per-tick log.
    pub record_ticks: bool,
    /// Set to end the run (Ctrl-C).
    pub cancel: Option<Arc<AtomicBool>>,
}

impl Default for LoopOptions {
    fn default() -> Self {
        LoopOptions {
            replan_error: 1.0,
            replan_after: 2.0,
            max_replans: 5,
            time_factor: 3.0,
            time_slack: 20.0,
            hold: 0.5,
            goal_margin: 0.05,
            obs_weight: 1.0,
            record_ticks: true,
            cancel: None,
        }
    }
}

/// What to do: the scenario, its first plan (or a planner to make it), and the planner for
/// replans.
pub struct Mission<'a> {
    /// The scenario (legs, goals, maps, physics).
    pub scenario: &'a Scenario,
    /// The first leg's plan, if it is already made.
    pub plan: Option<Plan>,
    /// Wall time that first plan took (s), for the metrics.
    pub plan_time_s: f64,
    /// Whether that first plan was an exact solution.
    pub plan_solved: bool,
    /// The planner for the first plan (when `plan` is `None`), new legs and replans.
    pub planner: Option<&'a mut dyn Planner>,
    /// Limits of every planning call (the problem's defaults if `None`).
    pub limits: Option<Limits>,
    /// Seed of the run; replans use seeds derived from it.
    pub seed: u64,
}

impl<'a> Mission<'a> {
    /// A mission that tracks `plan` with no replanning.
    pub fn with_plan(scenario: &'a Scenario, plan: Plan) -> Self {
        Mission {
            scenario,
            plan: Some(plan),
            plan_time_s: 0.0,
            plan_solved: true,
            planner: None,
            limits: None,
            seed: 0,
        }
    }
}

/// Everything a run produced.
#[derive(Debug, Clone)]
pub struct TrackOutcome {
    /// The run's metrics.
    pub metrics: TrackMetrics,
    /// Per-agent tracking error.
    pub per_agent: Vec<AgentError>,
    /// The plans tracked, in order.
    pub plans: Vec<PlanRecord>,
    /// The per-tick log (empty unless `record_ticks`).
    pub ticks: Vec<TickRecord>,
    /// A message for an abnormal end (a rig fault, a planning failure).
    pub message: Option<String>,
}

/// The reference the loop tracks for `plan`: the plan resampled at every integration step and,
/// when the plan ends inside `goal` (anywhere within the tolerance of the goal centres), a
/// settle segment from its end to the goal centres at half the largest pull speed, so that
/// closed-loop trackers finish by holding the team at the centres.
pub fn reference_for(plan: &Plan, model: &PlanningModel, goal: &Goal) -> Reference {
    let r = Reference::from_plan(plan, model);
    if goal.contains(r.end()) && goal.agents.len() == r.agents() {
        let speed = 0.5 * model.kinematics.pull_coeff * model.coil.gradient_limit();
        r.with_settle(&goal.agents, speed, model.dt)
    } else {
        r
    }
}

/// Stops the rig when dropped (also while unwinding from a panic).
struct StopGuard<'r> {
    rig: &'r mut dyn Rig,
}

impl Drop for StopGuard<'_> {
    fn drop(&mut self) {
        let _ = self.rig.stop();
    }
}

/// Simulates a run: a [`SimRig`] of `scenario` under `preset` with `seed`, then [`track`].
pub fn simulate(
    mission: Mission,
    tracker: &mut dyn Tracker,
    preset: &DisturbancePreset,
    opts: &LoopOptions,
) -> TrackOutcome {
    let mut rig = SimRig::new(mission.scenario, preset, mission.seed);
    track(&mut rig, tracker, mission, opts)
}

/// Runs `tracker` on `rig` until the final goal, a failure, the time limit or a cancel; the
/// rig is stopped on every exit path.
pub fn track(
    rig: &mut dyn Rig,
    tracker: &mut dyn Tracker,
    mission: Mission,
    opts: &LoopOptions,
) -> TrackOutcome {
    let guard = StopGuard { rig };
    let mut run = Run::new(mission, opts);
    run.drive(&mut *guard.rig, tracker);
    if let Err(e) = guard.rig.stop() {
        run.note(format!("stopping the rig failed: {e}"));
    }
    drop(guard);
    run.finish()
}

/// The state of one run.
struct Run<'a> {
    mission: Mission<'a>,
    opts: LoopOptions,
    model: PlanningModel,
    agents: usize,
    leg: usize,
    checker: ValidityChecker,
    reference: Option<Reference>,
    ref_start: f64,
    plans: Vec<PlanRecord>,
    ticks: Vec<TickRecord>,
    errors: ErrorAccumulator,
    status: Option<RunStatus>,
    message: Option<String>,
    t_first: Option<f64>,
    now: f64,
    last_estimate: Vec<Vec2>,
    last_truth: Option<Vec<Vec2>>,
    last_observed: Vec<Option<Vec2>>,
    time_to_goal: Option<f64>,
    legs_completed: usize,
    missed_frames: usize,
    missed_detections: usize,
    rig_faults: usize,
    error_replans: usize,
    planning_time: f64,
    tracker_time: f64,
    tick_count: usize,
    last_compute: f64,
    wall_contacts: usize,
    agent_contact: bool,
    observed_contact_frames: usize,
    observed_touching: Vec<bool>,
    in_goal_since: Option<f64>,
    error_high_since: Option<f64>,
    error_source_true: bool,
}

impl<'a> Run<'a> {
    fn new(mission: Mission<'a>, opts: &LoopOptions) -> Self {
        let s = mission.scenario;
        let n = s.agents();
        Run {
            model: PlanningModel::new(&s.physics),
            agents: n,
            leg: 0,
            checker: s.checker_for_leg(0),
            reference: None,
            ref_start: 0.0,
            plans: vec![],
            ticks: vec![],
            errors: ErrorAccumulator::new(n),
            status: None,
            message: None,
            t_first: None,
            now: 0.0,
            last_estimate: s.start.clone(),
            last_truth: None,
            last_observed: vec![None; n],
            time_to_goal: None,
            legs_completed: 0,
            missed_frames: 0,
            missed_detections: 0,
            rig_faults: 0,
            error_replans: 0,
            planning_time: mission.plan_time_s,
            tracker_time: 0.0,
            tick_count: 0,
            last_compute: 0.0,
            wall_contacts: 0,
            agent_contact: false,
            observed_contact_frames: 0,
            observed_touching: vec![false; n],
            in_goal_since: None,
            error_high_since: None,
            error_source_true: false,
            mission,
            opts: opts.clone(),
        }
    }

    fn note(&mut self, m: String) {
        self.message = Some(match self.message.take() {
            Some(old) => format!("{old}; {m}"),
            None => m,
        });
    }

    fn end(&mut self, status: RunStatus) {
        self.status.get_or_insert(status);
    }

    /// The tick loop.
    fn drive(&mut self, rig: &mut dyn Rig, tracker: &mut dyn Tracker) {
        let period = rig.frame_period();
        let mut est = Estimator::new(
            self.model.clone(),
            rig.latency(),
            self.opts.obs_weight,
            &self.mission.scenario.start,
        );
        while self.status.is_none() {
            if self
                .opts
                .cancel
                .as_ref()
                .is_some_and(|c| c.load(Ordering::Relaxed))
            {
                self.end(RunStatus::Cancelled);
                break;
            }
            let obs = match rig.observe() {
                Ok(o) if o.agents.len() == self.agents => o,
                Ok(o) => {
                    self.note(format!(
                        "the rig reported {} agents, the scenario has {}",
                        o.agents.len(),
                        self.agents
                    ));
                    self.end(RunStatus::RigFault);
                    break;
                }
                Err(RigError::Recoverable(_)) => {
                    // no frame this tick: every agent counts as missed, the model predicts
                    self.rig_faults += 1;
                    Observation {
                        t: self.now + period - rig.latency(),
                        agents: vec![None; self.agents],
                    }
                }
                Err(e) => {
                    self.note(e.to_string());
                    self.end(RunStatus::RigFault);
                    break;
                }
            };
            let misses = obs.agents.iter().filter(|a| a.is_none()).count();
            self.missed_detections += misses;
            self.missed_frames += usize::from(misses > 0);
            let (now, x) = est.update(&obs);
            self.now = now;
            let t0 = *self.t_first.get_or_insert(now);
            let truth = rig.ground_truth();
            if self.reference.is_none() && !self.first_plan(&x, tracker, period) {
                break;
            }
            self.tick_count += 1;
            let errors = self.score(&obs, truth.as_ref());
            if let Some(g) = &truth {
                self.wall_contacts = g.wall_contacts;
                self.agent_contact |= g.agent_contact;
                self.last_truth = Some(g.positions.clone());
            } else {
                self.observed_contacts(&obs);
            }
            self.last_estimate = x.clone();
            self.last_observed = obs.agents.clone();
            // the tick's command, or None when the run ends at this tick
            let (in_goal, command) = 'tick: {
                if self.agent_contact {
                    self.end(RunStatus::AgentContact);
                    break 'tick (false, None);
                }
                let in_goal = self.goal_check(&x, now, t0, rig, tracker, period);
                if self.status.is_some() {
                    break 'tick (in_goal, None);
                }
                let reference = self.reference.as_ref().expect("a reference");
                if now - self.ref_start
                    > self.opts.time_factor * reference.duration() + self.opts.time_slack
                {
                    self.end(RunStatus::Timeout);
                    break 'tick (in_goal, None);
                }
                self.error_replan(&x, now, tracker, period);
                let mut u = self.tracker_command(tracker, &x, &obs, period);
                if tracker.finished() {
                    // an open-loop plan played to its end: the leg is done if the team is in
                    // the goal
                    if self.mission.scenario.legs[self.leg].goal.contains(&x) {
                        self.complete_leg(&x, now, t0, rig, tracker, period);
                    }
                    if self.status.is_some() || tracker.finished() {
                        self.end(RunStatus::PlanFinished);
                        break 'tick (in_goal, None);
                    }
                    u = self.tracker_command(tracker, &x, &obs, period);
                }
                (in_goal, Some(u))
            };
            let truth = truth.map(|g| g.positions);
            let Some(u) = command else {
                self.log(&x, &obs, truth, errors, None, tracker, in_goal);
                break;
            };
            match rig.command(&u) {
                Ok(()) => {}
                Err(RigError::Recoverable(_)) => self.rig_faults += 1,
                Err(e) => {
                    self.note(e.to_string());
                    self.end(RunStatus::RigFault);
                }
            }
            est.command_sent(now, &u);
            self.log(&x, &obs, truth, errors, Some(u), tracker, in_goal);
        }
    }

    /// The tracker's command for this tick (timed).
    fn tracker_command(
        &mut self,
        tracker: &mut dyn Tracker,
        x: &[Vec2],
        obs: &Observation,
        period: f64,
    ) -> Control {
        let reference = self.reference.as_ref().expect("a reference");
        let ctx = TrackerContext {
            reference,
            model: &self.model,
            checker: &self.checker,
            period,
            goal: &self.mission.scenario.legs[self.leg].goal,
        };
        let started = Instant::now();
        let u = tracker.command(
            &ctx,
            &Tick {
                t: self.now - self.ref_start,
                estimate: x,
                observation: obs,
            },
        );
        let dt = started.elapsed().as_secs_f64();
        self.tracker_time += dt;
        self.last_compute = dt;
        u
    }

    /// Tracks the mission's plan, or plans leg 0 from the first estimate.
    fn first_plan(&mut self, x: &[Vec2], tracker: &mut dyn Tracker, period: f64) -> bool {
        let now = self.now;
        match self.mission.plan.take() {
            Some(p) => {
                let solved = self.mission.plan_solved;
                let t = self.mission.plan_time_s;
                self.adopt(p, PlanReason::Initial, solved, t, now, tracker, period);
                true
            }
            None => {
                if self.replan(x, PlanReason::Initial, tracker, period) {
                    true
                } else {
                    self.end(RunStatus::PlanningFailed);
                    false
                }
            }
        }
    }

    /// Starts following `plan`.
    #[allow(clippy::too_many_arguments)]
    fn adopt(
        &mut self,
        plan: Plan,
        reason: PlanReason,
        solved: bool,
        time: f64,
        now: f64,
        tracker: &mut dyn Tracker,
        period: f64,
    ) {
        let reference = reference_for(
            &plan,
            &self.model,
            &self.mission.scenario.legs[self.leg].goal,
        );
        let ctx = TrackerContext {
            reference: &reference,
            model: &self.model,
            checker: &self.checker,
            period,
            goal: &self.mission.scenario.legs[self.leg].goal,
        };
        tracker.reset(&ctx);
        self.reference = Some(reference);
        self.ref_start = now;
        self.error_high_since = None;
        self.plans.push(PlanRecord {
            leg: self.leg,
            start_t: now - self.t_first.unwrap_or(now),
            reason,
            solved,
            planning_time_s: time,
            plan,
        });
    }

    /// Plans the current leg from `x`; false when no usable plan came back.
    fn replan(
        &mut self,
        x: &[Vec2],
        reason: PlanReason,
        tracker: &mut dyn Tracker,
        period: f64,
    ) -> bool {
        let Some(planner) = self.mission.planner.as_deref_mut() else {
            self.note(format!(
                "a {} plan was needed but there is no planner",
                reason_name(reason)
            ));
            return false;
        };
        let sc = self.mission.scenario;
        let mut start = x.to_vec();
        for p in &mut start {
            if let Some(q) = self.checker.collision.push_out(*p) {
                *p = q;
            }
        }
        let k = self.plans.len() as u64;
        let seed = self
            .mission
            .seed
            .wrapping_add(k.wrapping_mul(0x9E37_79B9_7F4A_7C15));
        let mut problem = Problem::from_scenario(sc, self.leg, Some(&start), seed);
        if let Some(l) = self.mission.limits {
            problem.limits = l;
        }
        let started = Instant::now();
        let result = planner.solve(&problem);
        self.planning_time += started.elapsed().as_secs_f64();
        let usable = (result.solved || result.approximate) && result.plan.edges() > 0;
        if !usable {
            self.note(format!(
                "{} planning for leg {} found no plan",
                reason_name(reason),
                self.leg + 1
            ));
            return false;
        }
        let now = self.now;
        self.adopt(
            result.plan,
            reason,
            result.solved,
            result.time_s,
            now,
            tracker,
            period,
        );
        true
    }

    /// Per-agent error of this tick against the current path, added to the accumulator.
    fn score(&mut self, obs: &Observation, truth: Option<&crate::rig::GroundTruth>) -> Vec<f64> {
        let reference = self.reference.as_ref().expect("a reference");
        self.error_source_true = truth.is_some();
        let mut out = vec![f64::NAN; self.agents];
        for (i, e) in out.iter_mut().enumerate() {
            let p = match truth {
                Some(g) => Some(g.positions[i]),
                None => obs.agents[i],
            };
            if let Some(p) = p {
                *e = reference.distance_to_path(i, p);
                self.errors.add(i, *e);
            }
        }
        out
    }

    /// Agent and wall contact as seen by the camera (a rig that does not know the truth).
    fn observed_contacts(&mut self, obs: &Observation) {
        let mut touching = false;
        for i in 0..self.agents {
            for j in (i + 1)..self.agents {
                if let (Some(a), Some(b)) = (obs.agents[i], obs.agents[j]) {
                    touching |= (b - a).norm() <= 1.05;
                }
            }
        }
        self.observed_contact_frames = if touching {
            self.observed_contact_frames + 1
        } else {
            0
        };
        self.agent_contact |= self.observed_contact_frames >= 3;
        for (i, p) in obs.agents.iter().enumerate() {
            if let Some(p) = p {
                let t = self.checker.collision.clearance(*p) <= 0.0;
                if t && !self.observed_touching[i] {
                    self.wall_contacts += 1;
                }
                self.observed_touching[i] = t;
            }
        }
    }

    /// Goal bookkeeping: completes legs (switching the map and replanning) and the run.
    fn goal_check(
        &mut self,
        x: &[Vec2],
        now: f64,
        t0: f64,
        rig: &mut dyn Rig,
        tracker: &mut dyn Tracker,
        period: f64,
    ) -> bool {
        let sc = self.mission.scenario;
        let goal = &sc.legs[self.leg].goal;
        let inside = goal.distance(x) <= goal.tolerance - self.opts.goal_margin;
        if !inside {
            self.in_goal_since = None;
            return false;
        }
        let since = *self.in_goal_since.get_or_insert(now);
        if now - since + 1e-9 < self.opts.hold {
            return true;
        }
        self.complete_leg(x, now, t0, rig, tracker, period);
        true
    }

    /// The current leg is done: ends the run after the last leg, else switches the map and
    /// plans the next leg from `x`.
    fn complete_leg(
        &mut self,
        x: &[Vec2],
        now: f64,
        t0: f64,
        rig: &mut dyn Rig,
        tracker: &mut dyn Tracker,
        period: f64,
    ) {
        let sc = self.mission.scenario;
        self.legs_completed += 1;
        self.in_goal_since = None;
        if self.leg + 1 == sc.legs.len() {
            self.time_to_goal = Some(now - t0);
            self.end(RunStatus::ReachedGoal);
            return;
        }
        self.leg += 1;
        self.checker = sc.checker_for_leg(self.leg);
        match rig.set_world(&sc.world_for_leg(self.leg)) {
            Ok(()) => {}
            Err(RigError::Recoverable(_)) => self.rig_faults += 1,
            Err(e) => {
                self.note(e.to_string());
                self.end(RunStatus::RigFault);
                return;
            }
        }
        if !self.replan(x, PlanReason::Leg, tracker, period) {
            self.end(RunStatus::PlanningFailed);
        }
    }

    /// Replans when the estimate has stayed far from the path for too long.
    fn error_replan(&mut self, x: &[Vec2], now: f64, tracker: &mut dyn Tracker, period: f64) {
        if self.opts.replan_after <= 0.0 || self.mission.planner.is_none() {
            return;
        }
        let reference = self.reference.as_ref().expect("a reference");
        let e = (0..self.agents)
            .map(|i| reference.distance_to_path(i, x[i]))
            .fold(0.0, f64::max);
        if e <= self.opts.replan_error {
            self.error_high_since = None;
            return;
        }
        let since = *self.error_high_since.get_or_insert(now);
        if now - since >= self.opts.replan_after && self.error_replans < self.opts.max_replans {
            self.error_replans += 1;
            if !self.replan(x, PlanReason::Error, tracker, period) {
                self.error_high_since = None;
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn log(
        &mut self,
        x: &[Vec2],
        obs: &Observation,
        truth: Option<Vec<Vec2>>,
        error: Vec<f64>,
        u: Option<Control>,
        tracker: &dyn Tracker,
        in_goal: bool,
    ) {
        if !self.opts.record_ticks {
            return;
        }
        let st = tracker.status();
        let progress_s = self.reference.as_ref().map_or(0.0, |r| r.time(st.progress));
        self.ticks.push(TickRecord {
            t: self.now - self.t_first.unwrap_or(self.now),
            leg: self.leg,
            plan: self.plans.len().saturating_sub(1),
            mode: if u.is_some() { st.mode } else { "end" },
            progress_s,
            estimate: x.to_vec(),
            observed: obs.agents.clone(),
            truth,
            error,
            command: u.unwrap_or_default(),
            in_goal,
            targets: st.targets,
            compute_us: if u.is_some() {
                self.last_compute * 1e6
            } else {
                0.0
            },
        });
    }

    fn finish(self) -> TrackOutcome {
        let sc = self.mission.scenario;
        let goal = sc.final_goal();
        let final_state = self
            .last_truth
            .clone()
            .unwrap_or_else(|| self.last_estimate.clone());
        let final_distance = goal.distance(&final_state);
        let status = self.status.unwrap_or(RunStatus::Timeout);
        let reached = status == RunStatus::ReachedGoal && goal.contains(&final_state);
        let duration = self.t_first.map_or(0.0, |t0| self.now - t0);
        let per_agent = self.errors.per_agent();
        let metrics = TrackMetrics {
            status,
            reached_goal: reached,
            time_to_goal_s: if reached { self.time_to_goal } else { None },
            final_goal_distance_bl: final_distance,
            legs_completed: self.legs_completed,
            legs: sc.legs.len(),
            rms_error_bl: self.errors.rms(),
            max_error_bl: self.errors.max(),
            rms_error_worst_agent_bl: per_agent.iter().map(|a| a.rms_bl).fold(0.0, f64::max),
            error_source: if self.error_source_true {
                "true"
            } else {
                "observed"
            }
            .into(),
            agent_contact: self.agent_contact,
            wall_contacts: self.wall_contacts,
            missed_frames: self.missed_frames,
            missed_detections: self.missed_detections,
            rig_faults: self.rig_faults,
            replans: self.plans.len().saturating_sub(1),
            error_replans: self.error_replans,
            ticks: self.tick_count,
            duration_s: duration,
            planning_time_s: self.planning_time,
            tracker_compute_s: self.tracker_time,
            total_time_s: self.planning_time + duration,
        };
        TrackOutcome {
            metrics,
            per_agent,
            plans: self.plans,
            ticks: self.ticks,
            message: self.message,
        }
    }
}

fn reason_name(r: PlanReason) -> &'static str {
    match r {
        PlanReason::Initial => "initial",
        PlanReason::Leg => "new-leg",
        PlanReason::Error => "error",
    }
}
