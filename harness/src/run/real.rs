//! The real executor: planners and trackers by name from its [`Registry`] (the built-ins of
//! `magbench-planners` and `magbench-trackers`, and a plugin's), the physics from `magbench-env`.
//!
//! Three parameter keys of a planner variant set the run's planning setup rather than the
//! planner ([`SETUP_KEYS`]): `objective` (`path-length`, `duration`, `control-effort`),
//! `metric` (`positions`, `centroid-shape:W_C:W_S`) and `flow` (`pair-adaptive`, `pair-exact`,
//! `rk4`). Every planning call of the run — each leg, and in a tracked run each replan — is made
//! under that one setup ([`setup`]), in whole frames of the preset's camera when the run is tracked,
//! through the run's [`Pipeline`] (its seed rule, start rule, validator and post-processing). A
//! scenario with several legs is planned leg by leg, each leg from the end of the previous
//! leg's plan with the full limits; the run is solved when every leg is, and its iterations,
//! nodes, times, costs and progress add up over the legs.
//!
//! With a tracker, the run plans the first leg (the planner columns describe that plan), then
//! tracks it in closed loop against env's simulated plant under the run's disturbance preset
//! (`magbench_trackers::simulate`, seeded by the run's seed); the tracking loop replans each
//! later leg from the observed state, and on a persistent tracking error, with the same planner
//! and setup.

use std::sync::Arc;
use std::time::Duration;

use std::time::Instant;

use magbench_env::input::Rejection;
use magbench_env::plant::DisturbancePreset;
use magbench_planners::ElevationRefused;
use magbench_planners::setup::SETUP_KEYS;
use magbench_planners::{Limits, Plan, Planner, PlannerResult, PlanningSetup};
use magbench_trackers::{RunStatus, simulate};

use super::executor::base_record;
use super::{Executor, ProgressRow, RunError, RunOutput, RunSpec, Status, Variant};
use crate::metrics::{PathFacts, PlanFacts, TrackFacts};
use crate::pipeline::{Failure, LegPlan, Pipeline};
use crate::registry::Registry;
use crate::replay::{LegTree, ReplayData};

/// Runs real planners and trackers, resolved by name in its registry.
#[derive(Debug, Clone, Default)]
pub struct RealExecutor {
    registry: Registry,
}

impl RealExecutor {
    /// The executor of the planners and trackers of `registry`.
    pub fn new(registry: Registry) -> Self {
        RealExecutor { registry }
    }

    /// Its registry.
    pub fn registry(&self) -> &Registry {
        &self.registry
    }
}

fn planner_params(v: &Variant) -> Vec<(String, String)> {
    v.params_as_strings()
        .into_iter()
        .filter(|(k, _)| !SETUP_KEYS.contains(&k.as_str()))
        .collect()
}

/// A fresh planner of the run's variant from `registry`, its setup keys left out.
fn new_planner(registry: &Registry, spec: &RunSpec) -> Result<Box<dyn Planner>, RunError> {
    registry
        .planners()
        .create_in(
            &spec.experiment,
            &spec.planner.name,
            &planner_params(&spec.planner),
        )
        .map_err(RunError::Component)
}

/// The setup keys of `v` set on `setup`; errors name `source` and the key.
fn configure(setup: &mut PlanningSetup, v: &Variant, source: &str) -> Result<(), RunError> {
    for key in SETUP_KEYS {
        if let Some(value) = v.params.get(key) {
            setup
                .set(source, key, &value.to_string())
                .map_err(RunError::Setup)?;
        }
    }
    Ok(())
}

/// The planning setup of every planning call of the run: the experiment's limits, the
/// planner variant's setup keys, its preset's medium and coil (ideal's, bulk and tri-axial, for
/// a planning-only run) and, for a tracked run, the frame period of its preset.
pub fn setup(spec: &RunSpec) -> Result<PlanningSetup, RunError> {
    let mut setup = PlanningSetup {
        limits: Limits {
            max_iterations: spec.limits.iterations,
            time_limit: spec.limits.time_s.map(Duration::from_secs_f64),
        },
        ..PlanningSetup::default()
    };
    configure(&mut setup, &spec.planner, &spec.experiment)?;
    let preset = plant(spec);
    if spec.tracker.is_some() {
        setup = setup.in_frames_of(1.0 / preset.camera.fps);
    }
    Ok(setup.on_plant(&preset.medium, preset.coil.alpha_max_deg))
}

/// The run's disturbance preset (ideal when the run names none).
fn plant(spec: &RunSpec) -> Arc<DisturbancePreset> {
    spec.plant
        .clone()
        .unwrap_or_else(|| Arc::new(DisturbancePreset::ideal()))
}

/// The run's pipeline: its scenario, planning `setup` and seed.
fn pipeline<'a>(spec: &'a RunSpec, setup: &PlanningSetup) -> Pipeline<'a> {
    Pipeline::new(&spec.scenario, setup.clone(), spec.seed)
}

/// A pipeline failure as the run's error (a crash row).
fn failed(f: Failure) -> RunError {
    RunError::InvalidPlan {
        leg: f.leg(),
        error: f.plan_error(),
    }
}

/// Plans leg `leg` of the run's scenario from `start` with a fresh planner of the run from
/// `registry` ([`Pipeline::plan_leg`]). A plan the validator refuses is an error (a crash
/// row); a plan without motion is a result (a timeout), not followable.
fn plan_leg(
    registry: &Registry,
    spec: &RunSpec,
    pipe: &Pipeline,
    leg: usize,
    start: Option<&[magbench_env::Vec2]>,
) -> Result<LegPlan, RunError> {
    let mut planner = new_planner(registry, spec)?;
    pipe.plan_leg(planner.as_mut(), leg, start).map_err(failed)
}

/// Plans every leg of the run's scenario in turn under `setup` (stopping at an unsolved leg),
/// each from the end of the previous leg's plan; returns each leg's result.
pub fn plan_legs(
    registry: &Registry,
    spec: &RunSpec,
    setup: &PlanningSetup,
) -> Result<Vec<PlannerResult>, RunError> {
    let legs = planned_legs(registry, spec, setup)?;
    Ok(legs.into_iter().map(|l| l.validated.result).collect())
}

/// [`plan_legs`], keeping each leg's [`LegPlan`] (its search tree and stop reason).
fn planned_legs(
    registry: &Registry,
    spec: &RunSpec,
    setup: &PlanningSetup,
) -> Result<Vec<LegPlan>, RunError> {
    let pipe = pipeline(spec, setup);
    pipe.plan_legs(|leg, start| plan_leg(registry, spec, &pipe, leg, start))
}

/// Writes why the planner of `leg` stopped unsolved, when it said, to the `error` column.
fn record_stop(rec: &mut super::RunRecord, leg: &LegPlan) {
    if let Some(why) = &leg.stopped {
        rec.error = format!("leg {}: {why}", leg.leg + 1);
    }
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

/// Fills the path-quality metrics of `rec` from `plan`, the first leg's plan, in the first
/// leg's world (a later leg may switch the map).
fn fill_path(rec: &mut super::RunRecord, plan: &Plan, setup: &PlanningSetup, spec: &RunSpec) {
    let problem = setup.problem(&spec.scenario, 0, None, spec.seed);
    rec.metrics.fill_path(&PathFacts {
        plan,
        checker: &problem.checker,
    });
}

/// Fills the planner columns of `rec` and returns the joined progress trace.
fn fill_planning(
    legs: &[PlannerResult],
    all_legs: usize,
    spec: &RunSpec,
    rec: &mut super::RunRecord,
) -> Vec<ProgressRow> {
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
    // Progress and the first solution of the whole run: offsets of the earlier legs, and the
    // earlier legs' costs added once the last leg is solved.
    let (mut it0, mut t0, mut c0) = (0u64, 0.0, 0.0);
    let mut first_solution = None;
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
            first_solution = Some((it0 + it, t0 + t));
        }
        it0 += r.iterations;
        t0 += r.time_s;
        c0 += r.cost.unwrap_or(0.0);
    }
    rec.metrics.fill_plan(&PlanFacts {
        legs,
        solved,
        first_solution: first_solution.filter(|_| solved),
    });
    progress
}

/// A registry's error as a rejection within one component: `param.KEY` → `KEY`.
fn component_rejection(e: magbench_env::InputError) -> Rejection {
    let field = e.field.strip_prefix("param.").unwrap_or("");
    Rejection::new(field, e.reason)
}

impl Executor for RealExecutor {
    fn name(&self) -> &str {
        "real"
    }

    fn check_planner(&self, v: &Variant) -> Result<(), Rejection> {
        self.registry
            .planners()
            .create_in("", &v.name, &planner_params(v))
            .map_err(component_rejection)?;
        configure(&mut PlanningSetup::default(), v, "")
            .map_err(|r| Rejection::new("", r.to_string()))
    }

    fn check_tracker(&self, v: &Variant) -> Result<(), Rejection> {
        self.registry
            .trackers()
            .spec(&v.name, &v.params_as_strings(), "")
            .map(|_| ())
            .map_err(component_rejection)
    }

    fn one_at_a_time(&self, spec: &RunSpec) -> Vec<String> {
        self.registry.one_at_a_time(
            &spec.planner.name,
            spec.tracker.as_ref().map(|t| t.name.as_str()),
        )
    }

    fn check_run(&self, spec: &RunSpec) -> Result<(), (String, String)> {
        let setup = setup(spec).map_err(|r| ("planners".to_string(), r.to_string()))?;
        let mut sets = vec![(
            "planners",
            &spec.planner,
            self.registry
                .planners()
                .create_in("", &spec.planner.name, &planner_params(&spec.planner))
                .map_err(|e| ("planners".to_string(), e.reason))?
                .params(),
        )];
        if let Some(t) = &spec.tracker {
            let tracker = self
                .registry
                .trackers()
                .spec(&t.name, &t.params_as_strings(), "")
                .map_err(|e| ("trackers".to_string(), e.reason))?;
            sets.push(("trackers", t, tracker.build().params()));
        }
        let preset = spec.preset.as_deref().unwrap_or("ideal");
        for (field, v, params) in sets {
            setup.check_settings(&spec.scenario, &params).map_err(|e| {
                let why = match e {
                    ElevationRefused::Planar(r) => format!("planar: {r}"),
                    ElevationRefused::AlphaMax(r) | ElevationRefused::SetupAlphaMax(r) => {
                        format!("alpha_max: {r} (preset {preset}: coil.alpha_max_deg)")
                    }
                };
                (field.to_string(), format!("{}: {why}", v.label()))
            })?;
        }
        Ok(())
    }

    fn execute(&self, spec: &RunSpec) -> Result<RunOutput, RunError> {
        let mut rec = base_record(spec);
        let setup = setup(spec)?;
        let Some(tv) = &spec.tracker else {
            let n = spec.scenario.legs.len();
            let planned = planned_legs(&self.registry, spec, &setup)?;
            if let Some(last) = planned.last() {
                record_stop(&mut rec, last);
            }
            let (mut legs, mut trees) = (vec![], vec![]);
            for l in planned {
                legs.push(l.validated.result);
                trees.extend(l.tree);
            }
            let progress = fill_planning(&legs, n, spec, &mut rec);
            fill_path(&mut rec, &legs[0].plan, &setup, spec);
            let shown: Vec<&PlannerResult> = legs.iter().collect();
            let model = setup.model(&spec.scenario);
            let replay = ReplayData::planned(&spec.scenario, spec.id(), &shown, &trees, &model);
            return Ok(RunOutput {
                record: rec,
                progress,
                replay: Some(Box::new(replay)),
                replans: vec![],
            });
        };
        let pipe = pipeline(spec, &setup);
        let planned = plan_leg(&self.registry, spec, &pipe, 0, None)?;
        record_stop(&mut rec, &planned);
        let LegPlan {
            validated: first,
            tree,
            ..
        } = planned;
        let model = setup.model(&spec.scenario);
        let trees: Vec<LegTree> = tree.into_iter().collect();
        let progress = fill_planning(std::slice::from_ref(&first.result), 1, spec, &mut rec);
        fill_path(&mut rec, &first.result.plan, &setup, spec);
        let tspec = self
            .registry
            .trackers()
            .spec(&tv.name, &tv.params_as_strings(), &spec.experiment)
            .map_err(RunError::Component)?;
        let first = match first.followable() {
            Ok(first) => first,
            Err(e) => {
                // nothing to follow: the run ends before tracking
                rec.track_status = RunStatus::PlanningFailed.as_str().to_string();
                rec.error = if rec.error.is_empty() {
                    e.to_string()
                } else {
                    format!("{e}; {}", rec.error)
                };
                return Ok(RunOutput {
                    record: rec,
                    progress,
                    replay: None,
                    replans: vec![],
                });
            }
        };
        let preset = plant(spec);
        let mut planner = new_planner(&self.registry, spec)?;
        let mission = pipe.mission(first, Some(planner.as_mut()));
        let mut tracker = tspec.build();
        let mut opts = tspec.loop_options();
        opts.record_ticks = true;
        let t0 = Instant::now();
        let out = simulate(mission, tracker.as_mut(), &preset, &opts);
        let m = &out.metrics;
        rec.track_status = m.status.as_str().to_string();
        rec.reached_goal = Some(m.reached_goal);
        rec.worst_agent = m.worst_agent.map(|i| i as u64);
        rec.per_agent = out.per_agent.iter().map(Into::into).collect();
        rec.agent_contact = Some(m.agent_contact);
        rec.metrics.fill_track(&TrackFacts {
            metrics: m,
            wall_s: t0.elapsed().as_secs_f64(),
        });
        if let Some(msg) = &out.message {
            rec.error = msg.clone();
        }
        let replay = ReplayData::tracked(&spec.scenario, spec.id(), &out, &trees, &model);
        Ok(RunOutput {
            record: rec,
            progress,
            replay: Some(Box::new(replay)),
            replans: out.replans,
        })
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::experiment::Experiment;

    #[test]
    fn a_run_plans_under_its_variants_setup_keys_limits_and_presets_frames() {
        let text = r#"
scenarios = ["cargo-delivery"]
planners = ["rrt-star{objective=\"duration\", flow=\"rk4\", metric=\"centroid-shape:1:2\", k=3}"]
seeds = 1
[limits]
iterations = 1234
[tracking]
trackers = ["obc"]
presets = ["realistic"]
"#;
        let e = Experiment::parse(
            text,
            "x.toml",
            Path::new("."),
            "x",
            &RealExecutor::default(),
        )
        .unwrap();
        let runs = e.runs();
        assert_eq!(runs.len(), 2, "a planning run and a tracked run");
        for spec in &runs {
            let s = setup(spec).unwrap();
            assert_eq!(s.objective, "duration");
            assert_eq!(s.flow, magbench_env::model::Flow::Rk4);
            assert_eq!(s.limits.max_iterations, Some(1234));
            assert_eq!(
                s.control_period,
                1.0 / 60.0,
                "the realistic preset's camera"
            );
        }
        // the setup keys do not reach the planner, the planner's own parameters do
        assert_eq!(
            planner_params(&runs[0].planner),
            [("k".to_string(), "3".to_string())]
        );
    }

    /// A planner that stops unsolved and says why leaves its reason in the `error` column,
    /// planned only and tracked; a solved run leaves the column empty.
    #[test]
    fn an_unsolved_runs_stop_reason_is_its_error() {
        let text = r#"
scenarios = ["micro-factory", "open-field"]
planners = ["trajopt{max_subproblems=5}"]
seeds = 1
[limits]
iterations = 100
[tracking]
trackers = ["open-loop"]
presets = ["ideal"]
"#;
        let ex = RealExecutor::default();
        let e = Experiment::parse(text, "x.toml", Path::new("."), "x", &ex).unwrap();
        let mut unsolved = 0;
        for spec in e.runs() {
            let rec = ex.execute(&spec).unwrap().record;
            if rec.solved {
                assert_eq!(rec.error, "", "{}", spec.id());
            } else {
                unsolved += 1;
                assert!(
                    rec.error.contains("leg 1: trajopt: no feasible plan; "),
                    "{}: {}",
                    spec.id(),
                    rec.error
                );
            }
        }
        assert_eq!(unsolved, 2, "micro-factory, planned and tracked");
    }
}
