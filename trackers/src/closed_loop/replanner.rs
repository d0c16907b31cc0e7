//! The replanner: a new plan from the current estimate, at the start of every leg after the
//! first, when the tracking error stays high and (when asked) when the tracker stalls on its
//! plan, with the mission's planner and planning setup.
//!
//! A stall is the tracker's progress along the plan (the reference sample it is at) not
//! passing its best so far for `replan_after` seconds: the team cannot get back onto the plan
//! from where it is, although no agent may be far from its own path. For three agents or more
//! this is common (docs/physics.md, "Teams of three and more: measured"): a plan may pass through shapes
//! the real team cannot reach at all — the evenly spaced row is an invariant set of the
//! nominal model (by symmetry every command keeps it a row), so a plan from a row start stays
//! on it while the real, unequal agents bend out of it — and a new plan from the observed state
//! starts where the team is.
//!
//! A replan for a persistent error or a stall first repairs the plan being followed
//! (`replan_mode = repair`, [`magbench_planners::repair`]): it rejoins that plan from the
//! observed state, else grows a small tree from it onto the plan's remaining waypoints, and
//! only then plans from scratch with the mission's planner. A new leg is always planned from
//! scratch (its goal and map are new). Every plan, repaired or not, is followed only when
//! [`validate_result`] accepts it; every replan's wall time and work go to the run's log.

use std::time::Instant;

use magbench_env::params::{ParamType, Value, choose};
use magbench_env::{Scenario, ValidityChecker, Vec2};
use magbench_planners::repair::{Repair, RepairHow};
use magbench_planners::search_settings::SearchSettings;
use magbench_planners::seeds::replan_seed;
use magbench_planners::{
    Plan, Planner, PlannerResult, PlanningSetup, Problem, Unusable, validate_result,
};

use super::cpu_clock::thread_cpu_s;
use super::recorder::Recorder;
use crate::log::{PlanReason, ReplanHow, ReplanRecord};

/// Waypoints ahead of the nearest one that a repair's rejoin steers onto.
const REPAIR_AHEAD: usize = 8;

/// Whether a stall on the plan calls for a replan (loop parameter `replan_stall`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StallReplan {
    /// For teams of three or more agents (two agents: never).
    #[default]
    Auto,
    /// For every team.
    Yes,
    /// Never.
    No,
}

impl StallReplan {
    /// True when a team of `agents` replans on a stall.
    pub fn applies(self, agents: usize) -> bool {
        match self {
            StallReplan::Auto => agents >= 3,
            StallReplan::Yes => true,
            StallReplan::No => false,
        }
    }
}

impl ParamType for StallReplan {
    type Domain = ();

    fn parse(text: &str, _: &()) -> Result<Self, magbench_env::params::BadValue> {
        choose(
            text,
            &[
                ("auto", StallReplan::Auto),
                ("true", StallReplan::Yes),
                ("false", StallReplan::No),
            ],
        )
    }

    fn value(&self) -> Value {
        Value::Name(match self {
            StallReplan::Auto => "auto",
            StallReplan::Yes => "true",
            StallReplan::No => "false",
        })
    }

    fn describe(_: &()) -> String {
        "auto|true|false".into()
    }
}

/// How a replan for a persistent error or a stall starts (loop parameter `replan_mode`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ReplanMode {
    /// From the plan being followed: rejoin it, else a small tree onto it, else from scratch.
    #[default]
    Repair,
    /// From scratch with the mission's planner.
    Restart,
}

impl ParamType for ReplanMode {
    type Domain = ();

    fn parse(text: &str, _: &()) -> Result<Self, magbench_env::params::BadValue> {
        choose(
            text,
            &[
                ("repair", ReplanMode::Repair),
                ("restart", ReplanMode::Restart),
            ],
        )
    }

    fn value(&self) -> Value {
        Value::Name(match self {
            ReplanMode::Repair => "repair",
            ReplanMode::Restart => "restart",
        })
    }

    fn describe(_: &()) -> String {
        "repair|restart".into()
    }
}

/// Plans the current leg on demand, and watches for a persistent tracking error and a stall.
pub struct Replanner<'a> {
    planner: Option<&'a mut dyn Planner>,
    setup: PlanningSetup,
    seed: u64,
    replan_error: f64,
    replan_after: f64,
    max_replans: usize,
    error_high_since: Option<f64>,
    error_replans: usize,
    /// Watch the tracker's progress for a stall.
    stall: bool,
    /// How far inside its goal tolerance the loop needs the team (BL).
    goal_margin: f64,
    /// The best progress on the plan followed, and the rig time it was reached.
    best_progress: Option<(usize, f64)>,
    /// How a replan for an error or a stall starts.
    mode: ReplanMode,
    /// Iterations of a repair's tree at most.
    repair_iterations: u64,
    /// Iterations of the mission's planner at most in a replan for an error or a stall.
    replan_iterations: u64,
}

impl<'a> Replanner<'a> {
    /// A replanner with `planner` (none: every replan fails with a note), the `setup` of every
    /// planning call and the run's `seed`. A replan for the error comes when the error stays
    /// above `replan_error` BL for `replan_after` s (0: never), and, when `stall`, when the
    /// tracker's progress has not passed its best for `replan_after` s; at most `max_replans`
    /// times for both, unless the stall is watched (then the loop's time allowance bounds them).
    /// Such a replan starts as `mode` says, a repair's tree with at most `repair_iterations`,
    /// and plans from scratch with at most `replan_iterations` of the planner (or the setup's
    /// limit, when lower).
    pub fn new(
        planner: Option<&'a mut dyn Planner>,
        setup: PlanningSetup,
        seed: u64,
        (replan_error, replan_after, max_replans): (f64, f64, usize),
        stall: bool,
        goal_margin: f64,
        (mode, repair_iterations, replan_iterations): (ReplanMode, u64, u64),
    ) -> Self {
        Self {
            planner,
            setup,
            seed,
            replan_error,
            replan_after,
            max_replans,
            error_high_since: None,
            error_replans: 0,
            stall,
            goal_margin,
            best_progress: None,
            mode,
            repair_iterations,
            replan_iterations,
        }
    }

    /// A new plan is being followed: the error and stall watches start over.
    pub fn plan_adopted(&mut self) {
        self.error_high_since = None;
        self.best_progress = None;
    }

    /// Folds in the tracker's `progress` (reference sample) at rig time `now`; true when it has
    /// not passed its best for `replan_after` s, which calls for a replan now (and counts it).
    pub fn stall_calls_for_replan(&mut self, progress: usize, now: f64) -> bool {
        if !self.watches_stall() {
            return false;
        }
        match self.best_progress {
            Some((best, since)) if progress <= best => {
                if now - since >= self.replan_after && self.may_replan() {
                    self.count_replan();
                    return true;
                }
                false
            }
            _ => {
                self.best_progress = Some((progress, now));
                false
            }
        }
    }

    /// Whether the replan budget has room: `max_replans` per run; when the stall is watched,
    /// no count — the loop bounds a leg's replans by the leg's time allowance instead (a team
    /// that stalls on its plan needs a replan whenever it stalls, at most one per
    /// `replan_after` seconds).
    fn may_replan(&self) -> bool {
        self.stall || self.error_replans < self.max_replans
    }

    fn count_replan(&mut self) {
        self.error_replans += 1;
    }

    /// Whether the tracker's progress is watched for a stall.
    pub fn watches_stall(&self) -> bool {
        self.stall && self.watches_error()
    }

    /// A stall replan failed: the stall watch starts over from `progress` at `now`.
    pub fn stall_replan_failed(&mut self, progress: usize, now: f64) {
        self.best_progress = Some((progress, now));
    }

    /// Folds in this tick's tracking error `e` (BL, largest agent distance from its path, of
    /// the estimate) at rig time `now`; true when it calls for a replan now (and counts it).
    pub fn error_calls_for_replan(&mut self, e: f64, now: f64) -> bool {
        if e <= self.replan_error {
            self.error_high_since = None;
            return false;
        }
        let since = *self.error_high_since.get_or_insert(now);
        if now - since >= self.replan_after && self.may_replan() {
            self.count_replan();
            return true;
        }
        false
    }

    /// An error replan failed: the error watch starts over.
    pub fn error_replan_failed(&mut self) {
        self.error_high_since = None;
    }

    /// Watches the tracking error at all (a planner, and a positive `replan_after`).
    pub fn watches_error(&self) -> bool {
        self.replan_after > 0.0 && self.planner.is_some()
    }

    /// Plans leg `leg` of `scenario` from `x` (agents pushed out of any wall first) as the
    /// `k`-th plan of the run, at rig time `t_s`; a replan for an error or a stall first
    /// repairs `current`, the plan being followed. The whole wall time goes to `rec`, with a
    /// [`ReplanRecord`]; a missing planner or an unusable result is noted there and gives
    /// `None`. The plan is made to the goal shrunk by `goal_margin`, where the loop needs the
    /// team, when the stall is watched (a plan that ends in the margin band leaves a final
    /// shape correction a team of three may not manage) and when the start is already inside
    /// the tolerance but not that far inside (else the planner would be done before it
    /// starts).
    #[allow(clippy::too_many_arguments)]
    pub fn plan(
        &mut self,
        scenario: &Scenario,
        leg: usize,
        checker: &ValidityChecker,
        (x, current): (&[Vec2], Option<&Plan>),
        k: usize,
        (reason, t_s): (PlanReason, f64),
        rec: &mut Recorder,
    ) -> Option<PlannerResult> {
        let started = Instant::now();
        let cpu_started = thread_cpu_s();
        let mut record = ReplanRecord {
            t_s,
            leg,
            reason,
            how: ReplanHow::Failed,
            wall_s: 0.0,
            cpu_s: None,
            rejoins: 0,
            tree_iterations: 0,
            repair_edges: 0,
            planner_iterations: 0,
        };
        let result =
            self.plan_recorded(scenario, (leg, checker), (x, current), k, &mut record, rec);
        record.wall_s = started.elapsed().as_secs_f64();
        record.cpu_s = cpu_started.zip(thread_cpu_s()).map(|(a, b)| b - a);
        rec.planning(record.wall_s);
        rec.replan(record);
        result
    }

    /// [`Replanner::plan`], its work counted in `record`.
    fn plan_recorded(
        &mut self,
        scenario: &Scenario,
        (leg, checker): (usize, &ValidityChecker),
        (x, current): (&[Vec2], Option<&Plan>),
        k: usize,
        record: &mut ReplanRecord,
        rec: &mut Recorder,
    ) -> Option<PlannerResult> {
        let reason = record.reason;
        if self.planner.is_none() {
            rec.note(format!(
                "a {} plan was needed but there is no planner",
                reason_name(reason)
            ));
            return None;
        }
        let mut start = x.to_vec();
        for p in &mut start {
            if let Some(q) = checker.collision.push_out(*p) {
                *p = q;
            }
        }
        let seed = replan_seed(self.seed, k);
        let mut problem = self.setup.problem(scenario, leg, Some(&start), seed);
        if !problem.checker.is_valid(&problem.start) {
            // the validator (`validate_result`) refuses every plan from an invalid start (agents too close or too
            // far apart): the planner is not called
            rec.note(format!(
                "{} planning for leg {}: the observed state is not valid (the validator refuses every plan from it)",
                reason_name(reason),
                leg + 1
            ));
            return None;
        }
        let needed = problem.goal.tolerance - self.goal_margin;
        let inside = problem.goal.contains(&start) && problem.goal.distance(&start) > needed;
        if (self.stall || inside) && needed > 0.0 {
            problem.goal.tolerance = needed;
        }
        let drift = matches!(reason, PlanReason::Error | PlanReason::Stall);
        if drift {
            let limit = problem.limits.max_iterations.unwrap_or(u64::MAX);
            problem.limits.max_iterations = Some(limit.min(self.replan_iterations));
        }
        if let (ReplanMode::Repair, true, Some(plan)) = (self.mode, drift, current)
            && let Some((result, how)) = self.repair(&problem, plan, record, rec)
        {
            record.how = how;
            return Some(result);
        }
        let planner = self.planner.as_deref_mut()?;
        let result = planner.solve(&problem);
        record.planner_iterations = result.iterations;
        match validate_result(&problem, &result) {
            Ok(()) => {
                record.how = ReplanHow::Full;
                Some(result)
            }
            Err(e) => {
                rec.note(match e {
                    Unusable::NoMotion => format!(
                        "{} planning for leg {} found no plan",
                        reason_name(reason),
                        leg + 1
                    ),
                    Unusable::Invalid(_) => {
                        format!("{} planning for leg {}: {e}", reason_name(reason), leg + 1)
                    }
                });
                None
            }
        }
    }

    /// A repair of `plan` for `problem` that passes [`validate_result`], and how it was found;
    /// its work goes to `record`. A repaired plan the validator refuses (a bug) is noted.
    fn repair(
        &self,
        problem: &Problem,
        plan: &Plan,
        record: &mut ReplanRecord,
        rec: &mut Recorder,
    ) -> Option<(PlannerResult, ReplanHow)> {
        let mut extend = SearchSettings::default().extend(problem);
        extend.alpha_max = plan.alpha_max;
        let repair = Repair {
            extend,
            iterations: self.repair_iterations,
            ahead: REPAIR_AHEAD,
        };
        let r = repair.run(problem, plan);
        record.rejoins = r.rejoins;
        record.tree_iterations = r.iterations;
        record.repair_edges = r.edges;
        let (result, how) = r.found?;
        if let Err(e) = validate_result(problem, &result) {
            rec.note(format!("a repaired plan was refused: {e}"));
            return None;
        }
        let how = match how {
            RepairHow::Rejoin => ReplanHow::Rejoin,
            RepairHow::Tree => ReplanHow::Tree,
        };
        Some((result, how))
    }

    /// Replans started so far for a persistent error or a stall.
    pub fn error_replans(&self) -> usize {
        self.error_replans
    }
}

fn reason_name(r: PlanReason) -> &'static str {
    match r {
        PlanReason::Initial => "initial",
        PlanReason::Leg => "new-leg",
        PlanReason::Error => "error",
        PlanReason::Stall => "stall",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn replanner<'a>(stall: bool) -> Replanner<'a> {
        Replanner {
            planner: None,
            setup: PlanningSetup::default(),
            seed: 0,
            replan_error: 1.0,
            replan_after: 2.0,
            max_replans: 1,
            error_high_since: None,
            error_replans: 0,
            stall,
            goal_margin: 0.05,
            best_progress: None,
            mode: ReplanMode::Repair,
            repair_iterations: 200,
            replan_iterations: 20_000,
        }
    }

    /// The replan log of `rec`.
    fn log(rec: Recorder, goal: &magbench_env::Goal) -> Vec<ReplanRecord> {
        rec.finish(super::super::recorder::RunEnd {
            status: crate::RunStatus::Timeout,
            goal,
            legs: (0, 1),
            time_to_goal: None,
            duration: 0.0,
            agent_contact: false,
            wall_contacts: 0,
            error_replans: 0,
        })
        .replans
    }

    /// Near its plan, an error replan is a repair the validator accepts, without the planner;
    /// far from it, the repair's tree runs its budget and the planner plans from scratch; a new
    /// leg is always planned from scratch.
    #[test]
    fn a_drift_replan_repairs_near_the_plan_and_falls_back_far_from_it() {
        use magbench_planners::sampler::StateSampler;
        use rand::SeedableRng;
        let s = Scenario::load("micro-factory").unwrap();
        let mut planner = magbench_planners::Planners::builtin()
            .create("goal-zoom-rrt", &[])
            .unwrap();
        let setup = PlanningSetup::default();
        let first = planner.solve(&setup.problem(&s, 0, None, 5));
        assert!(first.solved);
        let plan = first.plan;
        let checker = s.checker_for_leg(0);
        let mut r = replanner(false);
        r.setup = setup.clone();
        r.planner = Some(planner.as_mut());
        r.repair_iterations = 20;
        let near: Vec<Vec2> = plan.states[plan.edges() / 2]
            .iter()
            .map(|p| p + Vec2::new(0.1, -0.1))
            .collect();
        let problem = setup.problem(&s, 0, Some(&near), 0);
        let sampler = StateSampler::new(&problem);
        let mut rng = magbench_planners::Rng::seed_from_u64(0);
        let mut far = vec![Vec2::zeros(); 2];
        loop {
            sampler.uniform(&mut rng, &mut far);
            let d = plan
                .states
                .iter()
                .map(|w| problem.metric.distance(&far, w))
                .fold(f64::INFINITY, f64::min);
            if d > 25.0 && checker.is_valid(&far) {
                break;
            }
        }
        let mut rec = Recorder::new(&s.start, 0.0, false);
        let cases = [
            (&near, PlanReason::Error),
            (&far, PlanReason::Error),
            (&near, PlanReason::Leg),
        ];
        let mut results = vec![];
        for (k, (x, reason)) in cases.into_iter().enumerate() {
            let got = r.plan(
                &s,
                0,
                &checker,
                (x, Some(&plan)),
                k + 1,
                (reason, 1.0),
                &mut rec,
            );
            results.push(got.expect("a plan"));
        }
        let log = log(rec, &s.legs[0].goal);
        assert_eq!(log.len(), 3);
        assert!(
            matches!(log[0].how, ReplanHow::Rejoin | ReplanHow::Tree),
            "{:?}",
            log[0]
        );
        assert_eq!(log[0].planner_iterations, 0);
        assert_eq!(log[1].how, ReplanHow::Full);
        assert_eq!(log[1].tree_iterations, 20, "the tree ran its budget");
        assert!(log[1].planner_iterations > 0);
        assert_eq!((log[2].how, log[2].rejoins), (ReplanHow::Full, 0));
        for ((x, _), result) in cases.iter().zip(&results) {
            let problem = setup.problem(&s, 0, Some(x), 0);
            assert_eq!(validate_result(&problem, result), Ok(()));
            assert_eq!(result.plan.start(), &x[..]);
        }
        assert!(log.iter().all(|l| l.wall_s > 0.0 && l.t_s == 1.0));
    }

    /// A stall or error replan from scratch spends at most `replan_iterations` of the planner
    /// (the run's limit is 200 000), counted in the replan log; a new leg's plan has the run's
    /// limit. Four agents of quad-square: goal-zoom-rrt needs hundreds of iterations there.
    #[test]
    fn a_drift_replan_spends_at_most_replan_iterations_of_the_planner() {
        let s = Scenario::load("quad-square").unwrap();
        let mut planner = magbench_planners::Planners::builtin()
            .create("goal-zoom-rrt", &[])
            .unwrap();
        let setup = PlanningSetup::default();
        assert_eq!(setup.limits.max_iterations, Some(200_000));
        let checker = s.checker_for_leg(0);
        let mut r = replanner(true);
        r.setup = setup;
        r.planner = Some(planner.as_mut());
        r.mode = ReplanMode::Restart;
        r.replan_iterations = 40;
        let mut rec = Recorder::new(&s.start, 0.0, false);
        let reasons = [PlanReason::Stall, PlanReason::Error, PlanReason::Leg];
        let got: Vec<bool> = reasons
            .iter()
            .enumerate()
            .map(|(k, &reason)| {
                r.plan(
                    &s,
                    0,
                    &checker,
                    (&s.start, None),
                    k + 1,
                    (reason, 1.0),
                    &mut rec,
                )
                .is_some()
            })
            .collect();
        let log = log(rec, &s.legs[0].goal);
        for l in &log[..2] {
            // 40 iterations do not reach the goal: at most the closest approach is followed
            assert_eq!(l.planner_iterations, 40, "{l:?}");
        }
        assert!(got[2], "a new leg plans with the run's limit");
        assert!(log[2].planner_iterations > 40, "{:?}", log[2]);
    }

    /// From an observed state the validator refuses (two agents closer than the checker's
    /// `r_min`), a replan fails at once, without the planner's iterations.
    #[test]
    fn a_replan_from_an_invalid_state_does_not_call_the_planner() {
        let s = Scenario::load("quad-square").unwrap();
        let mut planner = magbench_planners::Planners::builtin()
            .create("goal-zoom-rrt", &[])
            .unwrap();
        let checker = s.checker_for_leg(0);
        let mut x = s.start.clone();
        x[1] = x[0] + Vec2::new(0.5 * checker.r_min, 0.0);
        assert!(!checker.is_valid(&x));
        let mut r = replanner(true);
        r.planner = Some(planner.as_mut());
        let mut rec = Recorder::new(&s.start, 0.0, false);
        for (k, reason) in [PlanReason::Stall, PlanReason::Error]
            .into_iter()
            .enumerate()
        {
            assert!(
                r.plan(&s, 0, &checker, (&x, None), k + 1, (reason, 1.0), &mut rec)
                    .is_none()
            );
        }
        let log = log(rec, &s.legs[0].goal);
        for l in &log {
            assert_eq!(
                (l.how, l.planner_iterations),
                (ReplanHow::Failed, 0),
                "{l:?}"
            );
        }
    }

    #[test]
    fn auto_watches_stalls_of_teams_of_three_or_more_only() {
        assert!(!StallReplan::Auto.applies(2));
        assert!(StallReplan::Auto.applies(3) && StallReplan::Auto.applies(8));
        assert!(StallReplan::Yes.applies(2) && !StallReplan::No.applies(3));
        for v in [StallReplan::Auto, StallReplan::Yes, StallReplan::No] {
            let name = v.value().to_string();
            assert_eq!(StallReplan::parse(&name, &()), Ok(v));
        }
        assert!(StallReplan::parse("maybe", &()).is_err());
        for v in [ReplanMode::Repair, ReplanMode::Restart] {
            let name = v.value().to_string();
            assert_eq!(ReplanMode::parse(&name, &()), Ok(v));
        }
        assert!(ReplanMode::parse("scratch", &()).is_err());
    }

    /// A planner is needed to watch at all: with one, a stall of `replan_after` calls for a
    /// replan, progress restarts the watch, and a stall replan is not limited by the count.
    #[test]
    fn a_stall_of_replan_after_calls_for_a_replan() {
        let mut planner = magbench_planners::Planners::builtin()
            .create("goal-zoom-rrt", &[])
            .unwrap();
        let mut r = replanner(true);
        assert!(!r.stall_calls_for_replan(5, 0.0), "no planner: no watch");
        r.planner = Some(planner.as_mut());
        assert!(!r.stall_calls_for_replan(5, 0.0));
        assert!(!r.stall_calls_for_replan(5, 1.9));
        assert!(
            !r.stall_calls_for_replan(6, 1.95),
            "progress restarts the watch"
        );
        assert!(
            !r.stall_calls_for_replan(4, 3.9),
            "going back is no progress"
        );
        assert!(r.stall_calls_for_replan(6, 3.95));
        assert!(
            r.stall_calls_for_replan(6, 4.0),
            "no count: the time allowance bounds it"
        );
        r.plan_adopted();
        assert!(
            !r.stall_calls_for_replan(0, 4.1),
            "a new plan starts the watch over"
        );
        // without the stall rule nothing is watched, whatever the progress
        let mut q = replanner(false);
        let mut other = magbench_planners::Planners::builtin()
            .create("goal-zoom-rrt", &[])
            .unwrap();
        q.planner = Some(other.as_mut());
        assert!(!q.stall_calls_for_replan(1, 0.0) && !q.stall_calls_for_replan(1, 100.0));
    }
}
