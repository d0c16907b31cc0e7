//! The executor seam: checks components by name and runs one [`RunSpec`].

use std::cell::RefCell;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Once;

use magbench_env::input::Rejection;

use super::{ProgressRow, RunError, RunRecord, RunSpec, Status, Variant};

/// What one run produced.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOutput {
    /// The result row.
    pub record: RunRecord,
    /// The planner's progress trace.
    pub progress: Vec<ProgressRow>,
    /// What the run's replay page shows (`replays/` of the results folder), if the executor
    /// records it.
    pub replay: Option<Box<crate::replay::ReplayData>>,
    /// The tracked run's replan log: every replan, its reason, wall and CPU time and work
    /// (empty for a planning run or an executor that does not track).
    pub replans: Vec<magbench_trackers::ReplanRecord>,
}

/// Runs single runs. Implementations must make the output depend only on the spec (apart from
/// wall-clock columns), so that runs can execute in any order on any number of threads.
pub trait Executor: Sync {
    /// A short name for manifests (`real`, `fake`).
    fn name(&self) -> &str;
    /// Checks that a planner exists and accepts these parameters; a rejection's field is the
    /// parameter's key (empty for the planner itself).
    fn check_planner(&self, v: &Variant) -> Result<(), Rejection>;
    /// Checks that a tracker exists and accepts these parameters (a rejection as for planners).
    fn check_tracker(&self, v: &Variant) -> Result<(), Rejection>;
    /// Checks what only a whole run can tell (a planner's or tracker's elevation setting against
    /// the run's scenario and preset); the error is (field, reason).
    fn check_run(&self, _spec: &RunSpec) -> Result<(), (String, String)> {
        Ok(())
    }
    /// The planner and tracker of `spec` whose runs go one at a time (a Python plugin holds
    /// the GIL), by name: a sweep runs no two such runs at once and says so in its report.
    fn one_at_a_time(&self, _spec: &RunSpec) -> Vec<String> {
        vec![]
    }
    /// Executes one run. An `Err` becomes a `crash` row.
    fn execute(&self, spec: &RunSpec) -> Result<RunOutput, RunError>;
}

/// The row of `spec` with its input columns filled and no result yet.
pub fn base_record(spec: &RunSpec) -> RunRecord {
    let mut r = RunRecord::example();
    r.run = spec.index;
    r.run_id = spec.id();
    r.experiment = spec.experiment.clone();
    r.scenario = spec.scenario_label.clone();
    r.agents = spec.scenario.agents();
    r.planner = spec.planner.label();
    r.planner_name = spec.planner.name.clone();
    r.planner_params = spec.planner.params_text();
    r.tracker = spec.tracker.as_ref().map(|t| t.label()).unwrap_or_default();
    r.preset = spec.preset.clone().unwrap_or_default();
    r.seed = spec.seed;
    r.max_iterations = spec.limits.iterations;
    r.time_limit_s = spec.limits.time_s;
    r
}

thread_local! {
    /// Inside [`execute_caught`] on this thread: the message of the latest panic.
    static CAUGHT: RefCell<Option<Option<String>>> = const { RefCell::new(None) };
}

static HOOK: Once = Once::new();

/// Installs (once) a panic hook that stays quiet for panics inside [`execute_caught`], whose
/// message and location go into the run's `error` column instead, and defers to the previous
/// hook for every other panic.
fn install_hook() {
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let caught = CAUGHT.with(|c| {
                let mut c = c.borrow_mut();
                if let Some(slot) = c.as_mut() {
                    let msg = info
                        .payload()
                        .downcast_ref::<String>()
                        .cloned()
                        .or_else(|| info.payload().downcast_ref::<&str>().map(|s| s.to_string()))
                        .unwrap_or_else(|| "unknown panic".into());
                    let at = info
                        .location()
                        .map(|l| format!(" at {}:{}", l.file(), l.line()))
                        .unwrap_or_default();
                    *slot = Some(format!("panic: {msg}{at}"));
                    true
                } else {
                    false
                }
            });
            if !caught {
                previous(info);
            }
        }));
    });
}

/// Executes `spec`, turning an error or a panic into a `crash` row so that one bad run never
/// ends a sweep.
pub fn execute_caught(ex: &dyn Executor, spec: &RunSpec) -> RunOutput {
    install_hook();
    CAUGHT.with(|c| *c.borrow_mut() = Some(None));
    let out = catch_unwind(AssertUnwindSafe(|| ex.execute(spec)));
    let hooked = CAUGHT.with(|c| c.borrow_mut().take()).flatten();
    let error = match out {
        Ok(Ok(mut o)) => {
            o.record.error = one_line(&o.record.error);
            return o;
        }
        Ok(Err(e)) => e.to_string(),
        Err(panic) => hooked.unwrap_or_else(|| {
            let msg = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "unknown panic".into());
            format!("panic: {msg}")
        }),
    };
    let mut r = base_record(spec);
    r.status = Status::Crash;
    r.error = one_line(&error);
    RunOutput {
        record: r,
        progress: vec![],
        replay: None,
        replans: vec![],
    }
}

/// `s` on one line (newlines become ` / `), so that every CSV record is one line.
pub fn one_line(s: &str) -> String {
    s.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(" / ")
}
