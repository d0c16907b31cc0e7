//! The C ABI between magbench and the OMPL shim (`planners/ompl/shim.cpp`).
//!
//! OMPL calls back into magbench through [`Callbacks`]: one propagation step through the
//! problem's `PlanningModel` checked by magbench's continuous edge check, the state check, the
//! goal, a tick per planner iteration (limits and progress) and SST's improved solutions. The
//! context behind `ctx` is a [`SolveContext`]; every callback takes it shared, and what changes
//! during a run sits in a `RefCell` (OMPL calls back from the solving thread only, never
//! reentrantly).

use std::cell::RefCell;
use std::ffi::{c_char, c_int, c_void};

use magbench_env::{Control, MAX_AGENTS, Vec2};

use crate::Problem;
use crate::motion::propagate_valid;
use crate::progress::Progress;

use super::path::from_ompl;
use crate::plan_cost;

/// Control dimensions in the plane: θ_B, g_x, g_y (α = 0).
pub const PLANAR_DIMS: usize = 3;

/// Control dimensions with the elevation free: θ_B, g_x, g_y, α.
pub const ELEVATED_DIMS: usize = 4;

/// magbench's side of the ABI (`struct mb_callbacks`).
#[repr(C)]
pub struct Callbacks {
    /// The [`SolveContext`].
    pub ctx: *mut c_void,
    /// One propagation step; 0 when magbench's edge check refuses it.
    pub propagate: extern "C" fn(*mut c_void, *const f64, *const f64, f64, *mut f64) -> c_int,
    /// The state check.
    pub valid: extern "C" fn(*mut c_void, *const f64) -> c_int,
    /// Largest agent distance from its goal centre (BL).
    pub goal_distance: extern "C" fn(*mut c_void, *const f64) -> f64,
    /// Every agent in its goal disk.
    pub goal_satisfied: extern "C" fn(*mut c_void, *const f64) -> c_int,
    /// One evaluation of the termination condition; nonzero stops the planner.
    pub tick: extern "C" fn(*mut c_void) -> c_int,
    /// An improved solution (SST): its controls (the run's dimensions per edge) and steps.
    pub solution: extern "C" fn(*mut c_void, usize, *const f64, *const u32),
}

/// One planning problem (`struct mb_problem`).
#[repr(C)]
pub struct CProblem {
    /// OMPL planner: `rrt`, `sst`, `kpiece`, `est` or `pdst`.
    pub planner: *const c_char,
    /// Agents N (the state space has 2N dimensions).
    pub agents: usize,
    /// The world's width (BL).
    pub width: f64,
    /// The world's height (BL).
    pub height: f64,
    /// Start positions, 2N.
    pub start: *const f64,
    /// Goal centres, 2N.
    pub goal_centres: *const f64,
    /// Goal tolerance (BL).
    pub goal_tolerance: f64,
    /// The coil's gradient limit (T/m).
    pub gradient_limit: f64,
    /// OMPL's propagation step: the control period (s).
    pub step: f64,
    /// Shortest control duration (steps).
    pub min_steps: u32,
    /// Longest control duration (steps).
    pub max_steps: u32,
    /// Seed of every RNG of the run.
    pub seed: u64,
    /// SST: stop at the first solution.
    pub stop_on_solution: c_int,
    /// Number of OMPL parameters.
    pub n_params: usize,
    /// Their OMPL names.
    pub param_names: *const *const c_char,
    /// Their values as text.
    pub param_values: *const *const c_char,
    /// [`PLANAR_DIMS`] or [`ELEVATED_DIMS`].
    pub control_dims: usize,
    /// The largest elevation α (rad) with [`ELEVATED_DIMS`].
    pub alpha_max: f64,
}

/// What a run found (`struct mb_result`).
#[repr(C)]
pub struct CResult {
    /// 0: no path, 1: approximate, 2: exact.
    pub status: c_int,
    /// Vertices of OMPL's planner data (SST: motions in its tree).
    pub vertices: u64,
    /// SST: witnesses.
    pub witnesses: u64,
    /// SST: leaves that represent no witness (what pruning would remove).
    pub dominated: u64,
    /// Edges of the path.
    pub edges: usize,
    /// Controls, `control_dims` per edge.
    pub controls: *mut f64,
    /// Steps per edge.
    pub steps: *mut u32,
    /// States, 2N per waypoint.
    pub states: *mut f64,
    /// Why the shim failed (NUL-terminated).
    pub error: [c_char; 512],
}

unsafe extern "C" {
    /// Runs OMPL's planner; 0 on success.
    pub fn mb_ompl_solve(p: *const CProblem, cb: *const Callbacks, r: *mut CResult) -> c_int;
    /// Frees a result's arrays.
    pub fn mb_ompl_free(r: *mut CResult);
    /// One propagation step through OMPL, `repeats` times; nanoseconds of the loop, or −1.
    pub fn mb_ompl_propagate(
        p: *const CProblem,
        cb: *const Callbacks,
        state: *const f64,
        control: *const f64,
        result: *mut f64,
        repeats: u64,
    ) -> i64;
}

/// What changes while OMPL runs.
pub struct Live {
    /// Limits and the progress trace.
    pub progress: Progress,
    /// Planner iterations started (termination-condition evaluations that let it go on).
    pub iterations: u64,
    /// Best exact-solution cost under the problem's objective (SST's improvements).
    pub best: Option<f64>,
    /// Iteration and time of the first exact solution.
    pub first: Option<(u64, f64)>,
}

/// The context of one OMPL run.
pub struct SolveContext<'a> {
    /// The problem.
    pub problem: &'a Problem,
    /// Control dimensions: [`PLANAR_DIMS`] or [`ELEVATED_DIMS`].
    pub dims: usize,
    /// What changes.
    pub live: RefCell<Live>,
}

impl<'a> SolveContext<'a> {
    /// A run of `problem` with `dims`-dimensional controls whose clock starts now.
    pub fn new(problem: &'a Problem, dims: usize) -> Self {
        SolveContext {
            problem,
            dims,
            live: RefCell::new(Live {
                progress: Progress::start(problem),
                iterations: 0,
                best: None,
                first: None,
            }),
        }
    }
}

/// A state of `n` agents from OMPL's 2N values.
///
/// # Safety
/// `x` points to `2 * n` readable doubles.
unsafe fn read(x: *const f64, n: usize) -> [Vec2; MAX_AGENTS] {
    let v = unsafe { std::slice::from_raw_parts(x, 2 * n) };
    let mut s = [Vec2::zeros(); MAX_AGENTS];
    for (p, xy) in s.iter_mut().zip(v.chunks_exact(2)) {
        *p = Vec2::new(xy[0], xy[1]);
    }
    s
}

/// The control of OMPL's (θ_B, g_x, g_y) — planar — or (θ_B, g_x, g_y, α).
pub fn control(u: &[f64]) -> Control {
    Control {
        alpha: if u.len() == ELEVATED_DIMS { u[3] } else { 0.0 },
        ..Control::planar(u[0], u[1], u[2])
    }
}

/// # Safety
/// `ctx` is the `SolveContext` the callbacks were made for.
unsafe fn run<'a>(ctx: *mut c_void) -> &'a SolveContext<'a> {
    unsafe { &*(ctx as *const SolveContext) }
}

extern "C" fn propagate(
    ctx: *mut c_void,
    state: *const f64,
    u: *const f64,
    duration: f64,
    result: *mut f64,
) -> c_int {
    // SAFETY: the shim passes the run's context, 2N-double states and controls of the run's
    // dimensions.
    let (run, x, u) = unsafe {
        let run = run(ctx);
        let u = std::slice::from_raw_parts(u, run.dims);
        (run, read(state, run.problem.agents()), control(u))
    };
    let n = run.problem.agents();
    let mut out = [Vec2::zeros(); MAX_AGENTS];
    let ok = propagate_valid(run.problem, &x[..n], &u, duration, &mut out[..n]);
    // SAFETY: `result` holds 2N doubles.
    let r = unsafe { std::slice::from_raw_parts_mut(result, 2 * n) };
    for (xy, p) in r.chunks_exact_mut(2).zip(&out[..n]) {
        xy[0] = p.x;
        xy[1] = p.y;
    }
    ok as c_int
}

extern "C" fn valid(ctx: *mut c_void, state: *const f64) -> c_int {
    // SAFETY: as in `propagate`.
    let (run, x) = unsafe {
        let run = run(ctx);
        (run, read(state, run.problem.agents()))
    };
    run.problem.checker.is_valid(&x[..run.problem.agents()]) as c_int
}

extern "C" fn goal_distance(ctx: *mut c_void, state: *const f64) -> f64 {
    // SAFETY: as in `propagate`.
    let (run, x) = unsafe {
        let run = run(ctx);
        (run, read(state, run.problem.agents()))
    };
    run.problem.goal.distance(&x[..run.problem.agents()])
}

extern "C" fn goal_satisfied(ctx: *mut c_void, state: *const f64) -> c_int {
    // SAFETY: as in `propagate`.
    let (run, x) = unsafe {
        let run = run(ctx);
        (run, read(state, run.problem.agents()))
    };
    run.problem.goal.contains(&x[..run.problem.agents()]) as c_int
}

extern "C" fn tick(ctx: *mut c_void) -> c_int {
    // SAFETY: as in `propagate`.
    let run = unsafe { run(ctx) };
    let mut live = run.live.borrow_mut();
    if live.progress.done(live.iterations) {
        return 1;
    }
    live.iterations += 1;
    let (i, best) = (live.iterations, live.best);
    live.progress.record(i, best);
    0
}

extern "C" fn solution(ctx: *mut c_void, edges: usize, controls: *const f64, steps: *const u32) {
    // SAFETY: the shim passes a control of the run's dimensions and one step count per edge.
    let (run, controls, steps) = unsafe {
        let run = run(ctx);
        (
            run,
            std::slice::from_raw_parts(controls, run.dims * edges),
            std::slice::from_raw_parts(steps, edges),
        )
    };
    let Ok(plan) = from_ompl(run.problem, run.dims, controls, steps, None) else {
        return;
    };
    if !run.problem.goal.contains(plan.end()) {
        return;
    }
    let cost = plan_cost(run.problem, &plan);
    let mut live = run.live.borrow_mut();
    if live.best.is_none_or(|b| cost < b) {
        live.best = Some(cost);
        let (i, t) = (live.iterations, live.progress.elapsed());
        live.first = live.first.or(Some((i, t)));
        live.progress.record(i, Some(cost));
    }
}

impl Callbacks {
    /// The callbacks of `run`.
    pub fn of(run: &SolveContext) -> Self {
        Callbacks {
            ctx: run as *const SolveContext as *mut c_void,
            propagate,
            valid,
            goal_distance,
            goal_satisfied,
            tick,
            solution,
        }
    }
}
