//! `ompl:<name>`: OMPL 1.5's control planners (RRT, SST, KPIECE1, EST, PDST) on magbench's own
//! model (cargo feature `ompl`; Debian `libompl-dev`).
//!
//! ```text
//! OMPL(problem, planner, params, seed)
//!   state space   ← ℝ^{2N}: the agents' positions, bounded by the world's rectangle
//!   control space ← (θ_B, g_x, g_y) ∈ [−π, π] × [−G, G]²   (planar: α = 0), or
//!                   (θ_B, g_x, g_y, α) ∈ … × [0, α_max]   when `planar` frees the elevation
//!   step          ← the control period; durations ∈ [min_duration, max_duration] in steps
//!   propagator(x, u, step):  x' ← PlanningModel (exact pair flow or RK4), and the motion
//!                            x → x' checked continuously (ValidityChecker::edge_valid or
//!                            motion.rs' checked RK4); a refused motion gives x' = NaN
//!   validity(x):             finite and ValidityChecker::is_valid
//!   goal(x):                 every agent within the tolerance of its goal centre
//!   termination:             magbench's iteration and time limits, one tick per iteration
//!   every RNG of the planner and its samplers ← derived from seed
//!   path ← planner.solve();  plan ← replay of path's controls, one edge per step (path.rs)
//! ```
//!
//! **Edges are checked by magbench's continuous check.** OMPL's control planners grow the tree
//! with `propagateWhileValid`: one propagation step at a time, each step's end checked by the
//! state validity checker, stopping before the first invalid one. The propagator is magbench's
//! checked propagation of that one step, and it marks a step whose motion fails the check with
//! a NaN state that the validity checker refuses. So every step OMPL keeps — and every edge is
//! a chain of kept steps — passed magbench's continuous collision and proximity check, not only
//! at its end. OMPL's MotionValidator (straight-line interpolation) plays no part: control
//! planners never call it.
//!
//! **Progress.** Every OMPL planner evaluates its termination condition once per iteration of
//! its main loop; magbench's condition counts these as iterations, stops at the iteration or
//! time limit and records the progress trace. RRT, KPIECE1, EST and PDST stop at their first
//! exact solution; SST reports each improvement, whose cost magbench measures under the
//! problem's objective (OMPL's SST itself minimises state-space path length).
//!
//! **Seeds.** `ompl::RNG::setSeed` is process-wide and works only before the first RNG exists;
//! instead the shim reseeds (`setLocalSeed`) the planner's own RNG, every state and control
//! sampler (through allocators) and the goal sampler, each from the problem's seed. Same seed,
//! same plan — in one process, many runs, any threads.

mod ffi;
mod params;
mod path;

use std::ffi::{CStr, CString};

use magbench_env::params::{ParamError, ParamInfo, ParamSet};

use crate::result::{Best, finish};
use crate::{Planner, PlannerResult, Problem, plan_cost};

pub use params::{Durations, Est, Kpiece, OmplParams, Pdst, Rrt, Sst};

use ffi::{CProblem, CResult, Callbacks, SolveContext, mb_ompl_free, mb_ompl_solve};

/// OMPL's counts at the end of a run.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct OmplStats {
    /// Vertices of OMPL's planner data; for SST, the motions in its tree.
    pub vertices: u64,
    /// SST: witnesses.
    pub witnesses: u64,
    /// SST: tree leaves that represent no witness — dominated nodes that SST's pruning should
    /// have removed.
    pub dominated: u64,
}

/// One of OMPL's control planners, as a magbench planner.
#[derive(Debug, Clone)]
pub struct Ompl<P> {
    name: &'static str,
    planner: &'static str,
    /// Its parameters.
    pub params: P,
}

impl<P: OmplParams> Ompl<P> {
    /// OMPL planner `planner` (`rrt`, `sst`, `kpiece`, `est`, `pdst`) registered as `name`.
    pub fn new(name: &'static str, planner: &'static str) -> Self {
        Ompl {
            name,
            planner,
            params: P::default(),
        }
    }

    /// Runs OMPL's planner on `problem`; also returns OMPL's counts.
    pub fn solve_with_stats(&mut self, problem: &Problem) -> (PlannerResult, OmplStats) {
        let alpha_max = self.params.durations().alpha_max(problem);
        let dims = if alpha_max.is_some() {
            ffi::ELEVATED_DIMS
        } else {
            ffi::PLANAR_DIMS
        };
        let run = SolveContext::new(problem, dims);
        let callbacks = Callbacks::of(&run);
        let (min_steps, max_steps) = self.params.durations().steps(problem);
        let owned = Owned::new(
            problem,
            self.planner,
            &self.params.ompl_params(),
            (min_steps, max_steps),
        );
        let mut cproblem = owned.c_problem(problem, dims);
        cproblem.stop_on_solution = self.params.stop_on_solution() as i32;
        // SAFETY: every pointer lives until the call returns; the result is zeroed by the shim.
        let mut r: CResult = unsafe { std::mem::zeroed() };
        let code = unsafe { mb_ompl_solve(&cproblem, &callbacks, &mut r) };
        let stats = OmplStats {
            vertices: r.vertices,
            witnesses: r.witnesses,
            dominated: r.dominated,
        };
        let found = if code != 0 {
            // SAFETY: the shim wrote a NUL-terminated message.
            let why = unsafe { CStr::from_ptr(r.error.as_ptr()) }.to_string_lossy();
            Err(Some(path::OmplError::Shim(why.into_owned())))
        } else if r.status == 0 {
            Err(None)
        } else {
            let n2 = 2 * problem.agents();
            // SAFETY: the shim filled `edges` controls and steps and `edges + 1` states.
            let (controls, steps, states) = unsafe {
                (
                    std::slice::from_raw_parts(r.controls, dims * r.edges),
                    std::slice::from_raw_parts(r.steps, r.edges),
                    std::slice::from_raw_parts(r.states, n2 * (r.edges + 1)),
                )
            };
            path::from_ompl(problem, dims, controls, steps, Some(states)).map_err(Some)
        };
        // SAFETY: frees what the shim allocated (null pointers are fine).
        unsafe { mb_ompl_free(&mut r) };
        if let Err(Some(why)) = &found {
            eprintln!("warning: {}: {why}", self.name);
        }
        let live = run.live.into_inner();
        let best = match found {
            Ok(steps_plan) => {
                let plan = steps_plan;
                let solved = problem.goal.contains(plan.end());
                let cost = plan_cost(problem, &plan);
                Best { plan, solved, cost }
            }
            Err(_) => Best {
                plan: crate::Plan::at(&problem.start),
                solved: false,
                cost: 0.0,
            },
        };
        let mut progress = live.progress;
        let first = match (live.first, best.solved) {
            (Some(f), true) => Some(f),
            (None, true) => Some((live.iterations, progress.elapsed())),
            _ => None,
        };
        progress.record(live.iterations, best.solved_cost());
        let nodes = stats.vertices as usize;
        (
            finish(
                problem,
                best,
                live.iterations,
                nodes,
                progress,
                first,
                alpha_max,
            ),
            stats,
        )
    }
}

/// The buffers a [`CProblem`] points into.
struct Owned {
    planner: CString,
    start: Vec<f64>,
    goal: Vec<f64>,
    _names: Vec<CString>,
    _values: Vec<CString>,
    name_ptrs: Vec<*const std::ffi::c_char>,
    value_ptrs: Vec<*const std::ffi::c_char>,
    steps: (u32, u32),
}

impl Owned {
    fn new(
        problem: &Problem,
        planner: &str,
        params: &[(String, String)],
        steps: (u32, u32),
    ) -> Self {
        let flat =
            |v: &[magbench_env::Vec2]| -> Vec<f64> { v.iter().flat_map(|p| [p.x, p.y]).collect() };
        let c = |s: &str| CString::new(s).expect("no NUL in names and numbers");
        let names: Vec<CString> = params.iter().map(|(k, _)| c(k)).collect();
        let values: Vec<CString> = params.iter().map(|(_, v)| c(v)).collect();
        Owned {
            planner: c(planner),
            start: flat(&problem.start),
            goal: flat(&problem.goal.agents),
            name_ptrs: names.iter().map(|c| c.as_ptr()).collect(),
            value_ptrs: values.iter().map(|c| c.as_ptr()).collect(),
            _names: names,
            _values: values,
            steps,
        }
    }

    /// The problem with `dims`-dimensional controls, pointing into `self`.
    fn c_problem(&self, problem: &Problem, dims: usize) -> CProblem {
        CProblem {
            planner: self.planner.as_ptr(),
            agents: problem.agents(),
            width: problem.world.width,
            height: problem.world.height,
            start: self.start.as_ptr(),
            goal_centres: self.goal.as_ptr(),
            goal_tolerance: problem.goal.tolerance,
            gradient_limit: problem.model.coil.gradient_limit(),
            step: problem.control_period,
            min_steps: self.steps.0,
            max_steps: self.steps.1,
            seed: problem.seed,
            stop_on_solution: 0,
            n_params: self.name_ptrs.len(),
            param_names: self.name_ptrs.as_ptr(),
            param_values: self.value_ptrs.as_ptr(),
            control_dims: dims,
            alpha_max: problem.alpha_max,
        }
    }
}

/// One propagation step of one control period from `start` under `u` through OMPL's
/// `SpaceInformation::propagate` (OMPL's StatePropagator calling back into magbench), repeated
/// `repeats` times: the end state and the time the repeats took (for the C ABI's overhead).
pub fn propagate_through_ompl(
    problem: &Problem,
    start: &[magbench_env::Vec2],
    u: &magbench_env::Control,
    repeats: u64,
) -> Option<(Vec<magbench_env::Vec2>, std::time::Duration)> {
    let run = SolveContext::new(problem, ffi::ELEVATED_DIMS);
    let callbacks = Callbacks::of(&run);
    let owned = Owned::new(problem, "rrt", &[], (1, 1));
    let cproblem = owned.c_problem(problem, ffi::ELEVATED_DIMS);
    let x: Vec<f64> = start.iter().flat_map(|p| [p.x, p.y]).collect();
    let control = [u.theta, u.grad[0], u.grad[1], u.alpha];
    let mut out = vec![0.0; x.len()];
    // SAFETY: every pointer lives until the call returns; `out` holds 2N doubles.
    let ns = unsafe {
        ffi::mb_ompl_propagate(
            &cproblem,
            &callbacks,
            x.as_ptr(),
            control.as_ptr(),
            out.as_mut_ptr(),
            repeats,
        )
    };
    let end = out
        .chunks_exact(2)
        .map(|p| magbench_env::Vec2::new(p[0], p[1]))
        .collect();
    (ns >= 0).then(|| (end, std::time::Duration::from_nanos(ns as u64)))
}

impl<P: OmplParams> ParamSet for Ompl<P> {
    fn params(&self) -> Vec<ParamInfo> {
        self.params.params()
    }
    fn set_param(&mut self, key: &str, value: &str) -> Result<(), ParamError> {
        self.params.set_param(key, value)
    }
    fn check_params(&self) -> Result<(), magbench_env::input::Rejection> {
        self.params.check_params()
    }
}

impl<P: OmplParams> Planner for Ompl<P> {
    fn name(&self) -> &str {
        self.name
    }

    fn solve(&mut self, problem: &Problem) -> PlannerResult {
        self.solve_with_stats(problem).0
    }
}

#[cfg(test)]
mod tests;
