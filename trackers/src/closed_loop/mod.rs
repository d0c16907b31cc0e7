//! The tracking loop: one loop for every rig, every tracker and every scenario.
//!
//! It reads like the seed's Fig. 3A: the **planner** makes a plan (the first one, one per new
//! leg, and one when the tracking error persists); the **tracker**, whose model-based command
//! is the proximity controller, turns the estimate into one coil command per camera frame;
//! the **rig** applies it; the camera's frame comes back as **visual feedback**.
//!
//! Per control tick: visual feedback ([`feedback`]: observe, estimate) →
//! score the tick ([`recorder`]) and detect contact ([`contact`]) → the goal, time and replan
//! rules ([`course`], [`replanner`]) → the tracker's command → send it. The rig is stopped
//! (zero field) on every exit path: a normal end, a fault, a cancel and a panic (a guard stops
//! it while unwinding).
//!
//! Replanning uses a [`Planner`]: at the start of every leg after the first, from the current
//! estimate and against that leg's obstacles, and when the tracking error (of the estimate)
//! stays above `replan_error` for longer than `replan_after`; such a replan first repairs the
//! plan being followed (`replan_mode`, [`replanner`]). Every plan is made under the
//! mission's [`PlanningSetup`] (`setup.problem(scenario, leg, Some(start), seed)`) in whole
//! frames of the rig, and followed only if [`magbench_planners::validate_result`] accepts it.

pub mod contact;
pub mod course;
pub mod cpu_clock;
pub mod feedback;
pub mod recorder;
pub mod replanner;
pub mod tick;

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use magbench_env::params::Reals;
use magbench_env::plant::DisturbancePreset;
use magbench_env::{Control, Goal, PlanningModel, Scenario, declare_params};
use magbench_planners::{FirstPlan, Plan, Planner, PlanningSetup};

use self::contact::ContactDetector;
use self::course::{Course, GoalHold};
use self::feedback::Feedback;
use self::recorder::{Recorder, RunEnd};
use self::replanner::{ReplanMode, Replanner, StallReplan};
use self::tick::TickContext;
use crate::log::{PlanReason, PlanRecord, ReplanRecord, TickRecord};
use crate::metrics::{AgentError, RunStatus, TrackMetrics};
use crate::reference::Reference;
use crate::rig::{Rig, RigError};
use crate::sim_rig::SimRig;
use crate::tracker::{Tick, Tracker, TrackerContext};

/// Default of the loop parameter `replan_iterations`: a tenth of the planners' default
/// iteration limit, above the p95 of a pair's from-scratch drift replans (docs/replanning.md).
pub const REPLAN_ITERATIONS: usize = 20_000;

/// Largest `time_slack` (s of tracked time beyond `time_factor` × a plan's duration): ten
/// minutes, many times what the built-in scenarios' plans last. A run that does not reach its
/// goal lasts its whole allowance, and keeps a log row per camera frame of it: 1e6 s tracked
/// an unsolved plan for minutes of wall time.
pub const MAX_TIME_SLACK_S: f64 = 600.0;

declare_params! {
    /// Settings of the loop (not of a tracker); every tracker takes them as parameters, with
    /// its own defaults ([`Tracker::loop_options`]).
    #[derive(Debug, Clone)]
    pub struct LoopOptions {
        /// Tracking error (BL, largest agent distance from its path, of the estimate) that
        /// triggers a replan when it persists for `replan_after`.
        #[param("replan_error", Reals::closed(0.0, 1e3))]
        pub replan_error: f64 = 1.0,
        /// Seconds the error must persist before a replan; 0 = never.
        #[param("replan_after", Reals::closed(0.0, 1e6))]
        pub replan_after: f64 = 2.0,
        /// Most replans per run for a persistent error (no count where the stall rule applies:
        /// the time allowance of the leg's first plan bounds them).
        #[param("max_replans", 0..=10_000)]
        pub max_replans: usize = 5,
        /// Replan when the tracker's progress along the plan has not passed its best for
        /// `replan_after` s: `auto` (teams of three or more), `true` or `false`.
        #[param("replan_stall")]
        pub replan_stall: StallReplan = StallReplan::Auto,
        /// How a replan for a persistent error or a stall starts: `repair` (from the plan being
        /// followed: rejoin it, else a small tree onto its remaining waypoints, else from
        /// scratch) or `restart` (from scratch with the mission's planner).
        #[param("replan_mode")]
        pub replan_mode: ReplanMode = ReplanMode::Repair,
        /// Iterations of a repair's tree at most (0: rejoin or restart).
        #[param("repair_iterations", 0..=1_000_000)]
        pub repair_iterations: usize = 200,
        /// Iterations at most of the mission's planner in a replan for a persistent error or a
        /// stall (the run's own limit when that is lower); a new leg's plan has the run's
        /// limit. A replan that finds no plan within it is logged as failed and the team
        /// follows its plan until the next replan.
        #[param("replan_iterations", 1..=1_000_000)]
        pub replan_iterations: usize = REPLAN_ITERATIONS,
        /// Time limit per plan: time_factor × the plan's duration + time_slack (per leg, from
        /// its first plan, where the stall rule applies).
        #[param("time_factor", Reals::closed(1.0, 1e3))]
        pub time_factor: f64 = 3.0,
        /// See time_factor (s; at most 600, so that a run that misses its goal ends soon).
        #[param("time_slack", Reals::closed(0.0, MAX_TIME_SLACK_S))]
        pub time_slack: f64 = 20.0,
        /// Seconds the team must stay in a goal region to complete a leg.
        #[param("hold", Reals::closed(0.0, 1e3))]
        pub hold: f64 = 0.5,
        /// The estimate must be this far inside the goal tolerance (BL).
        #[param("goal_margin", Reals::closed(0.0, 10.0))]
        pub goal_margin: f64 = 0.05,
        /// How far a measurement moves the estimator's prior (1 = all the way).
        #[param("obs_weight", Reals::closed(0.001, 1.0))]
        pub obs_weight: f64 = 1.0,
        /// Keep the per-tick log.
        pub record_ticks: bool = true,
        /// Set to end the run (Ctrl-C).
        pub cancel: Option<Arc<AtomicBool>> = None,
    }
}

/// What to do: the scenario, its first plan, and the planner for new legs and replans.
pub struct Mission<'a> {
    /// The scenario (legs, goals, maps, physics).
    pub scenario: &'a Scenario,
    /// The first leg's plan ([`magbench_planners::solve_validated`], or a checked plan file).
    pub first: FirstPlan,
    /// The planner for new legs and replans.
    pub planner: Option<&'a mut dyn Planner>,
    /// What every planning call of the run is made under (objective, metric, limits, flow).
    /// The loop plans in whole frames of the rig it drives: the control period is the rig's.
    pub setup: PlanningSetup,
    /// Seed of the run; replans use seeds derived from it.
    pub seed: u64,
}

impl<'a> Mission<'a> {
    /// A mission that tracks `plan` with no replanning.
    pub fn with_plan(scenario: &'a Scenario, plan: Plan) -> Self {
        Mission {
            scenario,
            first: FirstPlan::given(plan, true),
            planner: None,
            setup: PlanningSetup::default(),
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
    /// Every replan (new legs, persistent errors, stalls), adopted or not, in order.
    pub replans: Vec<ReplanRecord>,
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
    let mut run = ClosedLoop::new(mission, opts, &*guard.rig, tracker);
    while run.status.is_none() {
        run.tick(&mut *guard.rig, tracker);
    }
    if let Err(e) = guard.rig.stop() {
        run.rec.note(format!("stopping the rig failed: {e}"));
    }
    drop(guard);
    run.finish()
}

/// The plan being followed, its reference and the rig time it started; and the time allowance
/// in force: the rig time it counts from and its length (s).
struct Following {
    plan: Plan,
    reference: Reference,
    start: Since,
    clock: (Since, f64),
}

/// A rig time: that of the run's first tick (the first plan starts there, before the rig's
/// clock is read), or a given one.
#[derive(Debug, Clone, Copy)]
enum Since {
    FirstTick,
    At(f64),
}

impl Since {
    /// The rig time (s).
    fn at(self, tick: &TickContext) -> f64 {
        match self {
            Since::FirstTick => tick.first,
            Since::At(t) => t,
        }
    }
}

/// One run: the planner side ([`Replanner`], the [`Course`] of legs, the plan followed), the
/// feedback side ([`Feedback`], [`ContactDetector`]) and the [`Recorder`].
struct ClosedLoop<'a> {
    opts: LoopOptions,
    model: PlanningModel,
    course: Course<'a>,
    replanner: Replanner<'a>,
    following: Following,
    feedback: Feedback,
    contacts: ContactDetector,
    rec: Recorder,
    status: Option<RunStatus>,
    /// The run's seed (the tracker's, for its own draws).
    seed: u64,
}

impl<'a> ClosedLoop<'a> {
    /// The run of `mission`, following its first plan from the first tick (`tracker` is reset
    /// on it).
    fn new(
        mission: Mission<'a>,
        opts: &LoopOptions,
        rig: &dyn Rig,
        tracker: &mut dyn Tracker,
    ) -> Self {
        let s = mission.scenario;
        let model = mission.setup.model(s);
        let course = Course::new(s, opts.hold, opts.goal_margin);
        let first = mission.first;
        let reference = reference_for(&first.plan, &model, course.goal());
        let allowance = opts.time_factor * reference.duration() + opts.time_slack;
        let mut run = ClosedLoop {
            course,
            replanner: Replanner::new(
                mission.planner,
                mission.setup.in_frames_of(rig.frame_period()),
                mission.seed,
                (opts.replan_error, opts.replan_after, opts.max_replans),
                opts.replan_stall.applies(s.agents()),
                opts.goal_margin,
                (
                    opts.replan_mode,
                    opts.repair_iterations as u64,
                    opts.replan_iterations as u64,
                ),
            ),
            following: Following {
                plan: first.plan.clone(),
                reference,
                start: Since::FirstTick,
                clock: (Since::FirstTick, allowance),
            },
            feedback: Feedback::new(
                &model,
                rig.frame_period(),
                rig.latency(),
                opts.obs_weight,
                &s.start,
            ),
            contacts: ContactDetector::new(s.agents()),
            rec: Recorder::new(&s.start, first.time_s, opts.record_ticks),
            status: None,
            seed: mission.seed,
            model,
            opts: opts.clone(),
        };
        tracker.reset(&run.tracker_context(&run.following.reference));
        run.replanner.plan_adopted();
        run.rec.plan(PlanRecord {
            leg: 0,
            start_t: 0.0,
            reason: PlanReason::Initial,
            solved: first.solved,
            planning_time_s: first.time_s,
            plan: first.plan,
        });
        run
    }

    /// Ends the run (the first reason given stands).
    fn end(&mut self, status: RunStatus) {
        self.status.get_or_insert(status);
    }

    /// A fatal fault: noted, and the run ends.
    fn fail(&mut self, message: String, status: RunStatus) {
        self.rec.note(message);
        self.end(status);
    }

    fn cancelled(&self) -> bool {
        self.opts
            .cancel
            .as_ref()
            .is_some_and(|c| c.load(Ordering::Relaxed))
    }

    /// One control tick: visual feedback → planner → tracker → rig.
    fn tick(&mut self, rig: &mut dyn Rig, tracker: &mut dyn Tracker) {
        if self.cancelled() {
            return self.end(RunStatus::Cancelled);
        }
        // visual feedback: the frame, through the estimator
        let tick = match self.feedback.sense(rig, &mut self.rec) {
            Ok(t) => t,
            Err(e) => return self.fail(e.to_string(), RunStatus::RigFault),
        };
        let following = &self.following;
        let errors = self
            .rec
            .score(&tick, &following.reference, following.start.at(&tick));
        self.contacts.update(
            tick.truth.as_ref(),
            &tick.observation,
            self.course.checker(),
        );
        // the goal, time and replan rules, then the tracker's command
        let (in_goal, command) = self.decide(&tick, rig, tracker);
        if let Some(u) = &command {
            match rig.command(u) {
                Ok(()) => {}
                Err(RigError::Recoverable(_)) => self.rec.rig_fault(),
                Err(e) => self.fail(e.to_string(), RunStatus::RigFault),
            }
            self.feedback.command_sent(u);
        }
        self.rec.tick(
            &tick,
            self.course.leg(),
            Some(&self.following.reference),
            tracker.status(),
            errors,
            command,
            in_goal,
        );
    }

    /// The tick's command, or `None` when the run ends at this tick; and whether the team is
    /// in the goal.
    fn decide(
        &mut self,
        tick: &TickContext,
        rig: &mut dyn Rig,
        tracker: &mut dyn Tracker,
    ) -> (bool, Option<Control>) {
        if self.contacts.agent_contact() {
            self.end(RunStatus::AgentContact);
            return (false, None);
        }
        let hold = self.course.hold(&tick.estimate, tick.now);
        if hold == GoalHold::Held {
            self.complete_leg(tick, rig, tracker);
        }
        let in_goal = hold != GoalHold::Outside;
        if self.status.is_some() {
            return (in_goal, None);
        }
        let (since, limit) = self.following.clock;
        if tick.now - since.at(tick) > limit {
            self.end(RunStatus::Timeout);
            return (in_goal, None);
        }
        self.error_replan(tick, tracker);
        self.stall_replan(tick, tracker);
        let mut u = self.command(tracker, tick);
        if tracker.finished() {
            // an open-loop plan played to its end: the leg is done if the team is in the goal
            if self.course.goal().contains(&tick.estimate) {
                self.complete_leg(tick, rig, tracker);
            }
            if self.status.is_some() || tracker.finished() {
                self.end(RunStatus::PlanFinished);
                return (in_goal, None);
            }
            u = self.command(tracker, tick);
        }
        (in_goal, Some(u))
    }

    /// The reference being followed.
    fn reference(&self) -> &Reference {
        &self.following.reference
    }

    /// What the tracker may use now.
    fn tracker_context<'r>(&'r self, reference: &'r Reference) -> TrackerContext<'r> {
        TrackerContext {
            reference,
            model: &self.model,
            world: self.course.world(),
            checker: self.course.checker(),
            period: self.feedback.period(),
            goal: self.course.goal(),
            seed: self.seed,
        }
    }

    /// The tracker's command for this tick (timed).
    fn command(&mut self, tracker: &mut dyn Tracker, tick: &TickContext) -> Control {
        let following = &self.following;
        let ctx = self.tracker_context(&following.reference);
        let started = Instant::now();
        let u = tracker.command(
            &ctx,
            &Tick {
                t: tick.now - following.start.at(tick),
                estimate: &tick.estimate,
                observation: &tick.observation,
            },
        );
        self.rec.tracker_compute(started.elapsed().as_secs_f64());
        u
    }

    /// Starts following `plan`.
    fn adopt(
        &mut self,
        plan: Plan,
        reason: PlanReason,
        solved: bool,
        time: f64,
        tick: &TickContext,
        tracker: &mut dyn Tracker,
    ) {
        let reference = reference_for(&plan, &self.model, self.course.goal());
        tracker.reset(&self.tracker_context(&reference));
        // the time allowance: the plan's own, except that where the stall rule applies a replan
        // within a leg keeps the allowance of the leg's first plan (replans are then bounded
        // by it, not by a count)
        let clock = if matches!(reason, PlanReason::Error | PlanReason::Stall)
            && self.replanner.watches_stall()
        {
            self.following.clock
        } else {
            (
                Since::At(tick.now),
                self.opts.time_factor * reference.duration() + self.opts.time_slack,
            )
        };
        self.following = Following {
            plan: plan.clone(),
            reference,
            start: Since::At(tick.now),
            clock,
        };
        self.replanner.plan_adopted();
        self.rec.plan(PlanRecord {
            leg: self.course.leg(),
            start_t: tick.elapsed(),
            reason,
            solved,
            planning_time_s: time,
            plan,
        });
    }

    /// Plans the current leg from the estimate; false when no usable plan came back.
    fn replan(
        &mut self,
        tick: &TickContext,
        reason: PlanReason,
        tracker: &mut dyn Tracker,
    ) -> bool {
        let result = self.replanner.plan(
            self.course.scenario(),
            self.course.leg(),
            self.course.checker(),
            (&tick.estimate, Some(&self.following.plan)),
            self.rec.plans(),
            (reason, tick.elapsed()),
            &mut self.rec,
        );
        match result {
            Some(r) => {
                self.adopt(r.plan, reason, r.solved, r.time_s, tick, tracker);
                true
            }
            None => false,
        }
    }

    /// The current leg is done: ends the run after the last leg, else switches the map and
    /// plans the next leg from the estimate.
    fn complete_leg(&mut self, tick: &TickContext, rig: &mut dyn Rig, tracker: &mut dyn Tracker) {
        let Some(world) = self.course.complete(tick.elapsed()) else {
            return self.end(RunStatus::ReachedGoal);
        };
        match rig.set_world(&world) {
            Ok(()) => {}
            Err(RigError::Recoverable(_)) => self.rec.rig_fault(),
            Err(e) => return self.fail(e.to_string(), RunStatus::RigFault),
        }
        if !self.replan(tick, PlanReason::Leg, tracker) {
            self.end(RunStatus::PlanningFailed);
        }
    }

    /// Replans when the estimate has stayed far from the path for too long.
    fn error_replan(&mut self, tick: &TickContext, tracker: &mut dyn Tracker) {
        if !self.replanner.watches_error() {
            return;
        }
        let reference = self.reference();
        let e = (0..tick.estimate.len())
            .map(|i| reference.distance_to_path(i, tick.estimate[i]))
            .fold(0.0, f64::max);
        if self.replanner.error_calls_for_replan(e, tick.now)
            && !self.replan(tick, PlanReason::Error, tracker)
        {
            self.replanner.error_replan_failed();
        }
    }

    /// Replans when the tracker has not got on along its plan for too long.
    fn stall_replan(&mut self, tick: &TickContext, tracker: &mut dyn Tracker) {
        let progress = tracker.status().progress;
        if self.replanner.stall_calls_for_replan(progress, tick.now)
            && !self.replan(tick, PlanReason::Stall, tracker)
        {
            self.replanner.stall_replan_failed(progress, tick.now);
        }
    }

    fn finish(self) -> TrackOutcome {
        let sc = self.course.scenario();
        self.rec.finish(RunEnd {
            status: self.status.unwrap_or(RunStatus::Timeout),
            goal: sc.final_goal(),
            legs: self.course.legs(),
            time_to_goal: self.course.time_to_goal(),
            duration: self.feedback.duration(),
            agent_contact: self.contacts.agent_contact(),
            wall_contacts: self.contacts.wall_contacts(),
            error_replans: self.replanner.error_replans(),
        })
    }
}
