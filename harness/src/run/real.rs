//! The real executor: planners from `magbench-planners` (by registry name), the physics from
//! `magbench-env`.
//!
//! Two parameter keys of a planner variant set the problem rather than the planner:
//! `objective` (`path-length`, `duration`, `control-effort`) and `metric` (`positions`,
//! `centroid-shape:W_C:W_S`). A scenario with several legs is planned leg by leg, each leg
//! from the end of the previous leg's plan with the full limits; the run is solved when every
//! leg is, and its iterations, nodes, times, costs and progress add up over the legs.

use std::time::Duration;

use magbench_planners::registry;
use magbench_planners::{Limits, Plan, PlannerResult, Problem};

use super::executor::base_record;
use super::{Executor, ProgressRow, RunOutput, RunSpec, Status, Variant};

/// Runs real planners (and, once available, trackers) by registry name.
#[derive(Debug, Clone, Copy, Default)]
pub struct RealExecutor;

/// Keys of a planner variant that configure the problem, not the planner.
pub const PROBLEM_KEYS: [&str; 2] = ["objective", "metric"];

fn planner_params(v: &Variant) -> Vec<(String, String)> {
    v.params_as_strings()
        .into_iter()
        .filter(|(k, _)| !PROBLEM_KEYS.contains(&k.as_str()))
        .collect()
}

fn configure(problem: &mut Problem, v: &Variant, source: &str) -> Result<(), String> {
    if let Some(o) = v.params.get("objective") {
        registry::set_objective(source, problem, &o.to_string()).map_err(|e| e.reason)?;
    }
    if let Some(m) = v.params.get("metric") {
        registry::set_metric(source, problem, &m.to_string()).map_err(|e| e.reason)?;
    }
    Ok(())
}

/// The problem of leg `leg` of the run, from `start`.
pub fn problem(
    spec: &RunSpec,
    leg: usize,
    start: &[magbench_env::Vec2],
) -> Result<Problem, String> {
    let seed = spec.seed.wrapping_add(leg as u64 * 1_000_003);
    let mut p = Problem::from_scenario(&spec.scenario, leg, Some(start), seed);
    p.limits = Limits {
        max_iterations: spec.limits.iterations,
        time_limit: spec.limits.time_s.map(Duration::from_secs_f64),
    };
    configure(&mut p, &spec.planner, &spec.experiment)?;
    Ok(p)
}

/// Plans every leg of the run's scenario in turn; returns each leg's result.
pub fn plan_legs(spec: &RunSpec) -> Result<Vec<PlannerResult>, String> {
    let params = planner_params(&spec.planner);
    let mut start = spec.scenario.start.clone();
    let mut out = vec![];
    for leg in 0..spec.scenario.legs.len() {
        let mut planner = registry::create_in(&spec.experiment, &spec.planner.name, &params)
            .map_err(|e| e.reason)?;
        let p = problem(spec, leg, &start)?;
        let r = planner.solve(&p);
        let solved = r.solved;
        start = r.plan.end().to_vec();
        out.push(r);
        if !solved {
            break;
        }
    }
    Ok(out)
}

/// The plan of all legs joined end to end.
pub fn joined_plan(legs: &[PlannerResult]) -> Plan {
    let mut plan = Plan::at(legs[0].plan.start());
    for r in legs {
        for i in 0..r.plan.edges() {
            plan.push(
                r.plan.controls[i],
                r.plan.durations[i],
                r.plan.states[i + 1].clone(),
            );
        }
    }
    plan
}

/// Fills the planner columns of `rec` and returns the joined progress trace.
fn fill_planning(
    spec: &RunSpec,
    legs: &[PlannerResult],
    rec: &mut super::RunRecord,
) -> Vec<ProgressRow> {
    let all_legs = spec.scenario.legs.len();
    let solved = legs.len() == all_legs && legs.iter().all(|r| r.solved);
    let last = legs.last().expect("at least one leg");
    rec.solved = solved;
    rec.approximate = !solved && last.plan.edges() > 0;
    rec.status = if solved {
        Status::Exact
    } else if rec.approximate {
        Status::Approximate
    } else {
        Status::Timeout
    };
    rec.iterations = legs.iter().map(|r| r.iterations).sum();
    rec.nodes = legs.iter().map(|r| r.nodes as u64).sum();
    rec.plan_time_s = legs.iter().map(|r| r.time_s).sum();
    rec.cost = if solved {
        legs.iter().map(|r| r.cost).sum::<Option<f64>>()
    } else {
        None
    };
    rec.goal_distance = last.goal_distance;
    rec.plan_edges = legs.iter().map(|r| r.plan.edges() as u64).sum();
    rec.plan_duration_s = legs.iter().map(|r| r.plan.duration()).sum();
    // Progress and the first solution of the whole run: offsets of the earlier legs, and the
    // earlier legs' costs added once the last leg is solved.
    let (mut it0, mut t0, mut c0) = (0u64, 0.0, 0.0);
    let mut progress = vec![];
    for (i, r) in legs.iter().enumerate() {
        let final_leg = i + 1 == all_legs;
        for p in &r.progress {
            progress.push(ProgressRow {
                run: spec.index,
                run_id: rec.run_id.clone(),
                iteration: it0 + p.iteration,
                time_s: t0 + p.time_s,
                best_cost: if final_leg {
                    p.best_cost.map(|c| c0 + c)
                } else {
                    None
                },
            });
        }
        if let Some((it, t)) = r.first_solution.filter(|_| final_leg) {
            rec.first_solution_iteration = Some(it0 + it);
            rec.first_solution_time_s = Some(t0 + t);
        }
        it0 += r.iterations;
        t0 += r.time_s;
        c0 += r.cost.unwrap_or(0.0);
    }
    if !solved {
        rec.first_solution_iteration = None;
        rec.first_solution_time_s = None;
    }
    progress
}

impl Executor for RealExecutor {
    fn name(&self) -> &str {
        "real"
    }

    fn check_planner(&self, v: &Variant) -> Result<(), String> {
        registry::create_in("", &v.name, &planner_params(v)).map_err(|e| e.reason)?;
        let sc = magbench_env::Scenario::load("open-field").map_err(|e| e.to_string())?;
        let mut p = Problem::from_scenario(&sc, 0, None, 0);
        configure(&mut p, v, "")
    }

    fn check_tracker(&self, v: &Variant) -> Result<(), String> {
        Err(format!(
            "unknown tracker {:?}: the tracker registry is not available in this build yet",
            v.name
        ))
    }

    fn execute(&self, spec: &RunSpec) -> Result<RunOutput, String> {
        let mut rec = base_record(spec);
        let legs = plan_legs(spec)?;
        let progress = fill_planning(spec, &legs, &mut rec);
        if spec.tracker.is_some() {
            return Err("tracking is not available in this build yet".into());
        }
        Ok(RunOutput {
            record: rec,
            progress,
        })
    }
}
