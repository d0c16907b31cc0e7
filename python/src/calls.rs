//! The module's functions: `plan`, `track`, `main` (the whole command line) and
//! `experiment_name`. Each calls one function of the harness with the GIL released.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;

use magbench::Error;
use magbench::api::{TrackRequest, plan_leg, track_plan};
use magbench_env::{MAX_AGENTS, Vec2};
use magbench_planners::Limits;
use magbench_trackers::TrackOutcome;
use numpy::PyArray1;
use numpy::PyArray2;
use numpy::ndarray::Array2;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::arrays::{ArrayIn, CONTROL_LEN, read_state, state_vec};
use crate::errors::{bad_arg, cli_error, input_error};
use crate::plan::Plan;
use crate::scenario::Scenario;

/// Runs `f` without the GIL; a panic becomes a failure naming `what`.
pub fn detached<T: Send>(
    py: Python<'_>,
    what: &str,
    f: impl FnOnce() -> Result<T, Error> + Send,
) -> PyResult<T> {
    let r = py.detach(|| {
        catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|payload| {
            let msg = payload
                .downcast_ref::<String>()
                .map(String::as_str)
                .or_else(|| payload.downcast_ref::<&str>().copied())
                .unwrap_or("unknown panic");
            Err(Error::Failed(format!("internal error in {what}: {msg}")))
        })
    });
    r.map_err(|e| cli_error(py, e))
}

/// `key=value` parameters from a dict (booleans as `true`/`false`).
pub fn kv_params(params: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(String, String)>> {
    let mut out = vec![];
    if let Some(d) = params {
        for (k, v) in d.iter() {
            let key: String = k.str()?.extract()?;
            let value: String = match v.extract::<bool>() {
                Ok(b) if v.is_instance_of::<pyo3::types::PyBool>() => b.to_string(),
                _ => v.str()?.extract()?,
            };
            out.push((key, value));
        }
    }
    Ok(out)
}

/// Plans the scenario's leg with `planner` (a registry name: a built-in or a registered
/// Python planner) and `params`, under the default setup of `magbench plan` (60 fps frames,
/// the default plant; with `preset`, that preset's camera frames, medium and coil, as `magbench
/// track --preset` plans). Limits: `max_iterations` and/or `time_limit_s` (200000 iterations when
/// neither is given). `start` replaces the scenario's start (for later legs).
#[pyfunction]
#[pyo3(signature = (scenario, planner, *, seed = 0, time_limit_s = None, max_iterations = None, params = None, start = None, preset = None))]
#[allow(clippy::too_many_arguments)]
pub fn plan(
    py: Python<'_>,
    scenario: &Scenario,
    planner: &str,
    seed: u64,
    time_limit_s: Option<f64>,
    max_iterations: Option<u64>,
    params: Option<&Bound<'_, PyDict>>,
    start: Option<ArrayIn>,
    preset: Option<&str>,
) -> PyResult<Plan> {
    let mut setup = scenario.setup.clone();
    if let Some(name) = preset {
        let p = magbench_env::plant::DisturbancePreset::resolve(name)
            .map_err(|e| bad_arg(py, "preset", e.to_string()))?;
        setup = setup
            .in_frames_of(1.0 / p.camera.fps)
            .on_plant(&p.medium, p.coil.alpha_max_deg);
    }
    if max_iterations == Some(0) {
        return Err(bad_arg(py, "max_iterations", "must be at least 1, got 0"));
    }
    let time_limit = match time_limit_s {
        Some(t) => Some(
            magbench::run::spec::time_limit(t)
                .map_err(|r| bad_arg(py, "time_limit_s", r.reason))?,
        ),
        None => None,
    };
    if max_iterations.is_some() || time_limit.is_some() {
        setup.limits = Limits {
            max_iterations,
            time_limit,
        };
    }
    let n = scenario.agents();
    let start = match start {
        Some(a) => {
            let mut buf = [Vec2::zeros(); MAX_AGENTS];
            let v = a.as_array();
            if v.ndim() != 1 {
                return Err(bad_arg(
                    py,
                    "start",
                    format!("expected one state, got shape {:?}", v.shape()),
                ));
            }
            read_state(
                py,
                "start",
                v.into_dimensionality().expect("one dimension"),
                &mut buf[..n],
            )?;
            Some(buf[..n].to_vec())
        }
        None => None,
    };
    let params = kv_params(params)?;
    let mut p = crate::registry::planner(py, planner, &params)?;
    let s = scenario.full(py)?.clone();
    let leg = scenario.leg;
    let planned = detached(py, "plan", || {
        plan_leg(&s, leg, start.as_deref(), p.as_mut(), &setup, seed)
    })?;
    let mut plan = Plan::from_result(planned.validated.result, planner, &s.name);
    plan.stop_reason = planned.stopped;
    Ok(plan)
}

/// Tracks `plan` in closed loop against the simulated plant under `preset` (`ideal`,
/// `realistic`, `hardware` or a preset file) with `tracker` and `params` (the tracker's and
/// the loop's), as `magbench track --plan` does. `planner` (with `planner_params`) makes new
/// legs and replans; without it the loop does not replan. Returns `(metrics_json, traces,
/// plans)`; `magbench.track` wraps them.
#[pyfunction]
#[pyo3(signature = (scenario, plan, *, tracker = "obc", preset = "realistic", seed = 0, params = None, planner = None, planner_params = None))]
#[allow(clippy::too_many_arguments)]
pub fn track<'py>(
    py: Python<'py>,
    scenario: &Scenario,
    plan: &Plan,
    tracker: &str,
    preset: &str,
    seed: u64,
    params: Option<&Bound<'py, PyDict>>,
    planner: Option<&str>,
    planner_params: Option<&Bound<'py, PyDict>>,
) -> PyResult<(String, Bound<'py, PyDict>, Bound<'py, PyList>)> {
    let s = scenario.full(py)?.clone();
    if let Some(made_for) = &plan.scenario {
        if *made_for != s.name {
            return Err(input_error(
                py,
                &magbench_env::InputError::new(
                    "<plan>",
                    "scenario",
                    format!("the plan was made for scenario {made_for}, not {}", s.name),
                ),
            ));
        }
    }
    if scenario.leg != 0 {
        return Err(bad_arg(
            py,
            "scenario",
            "track runs the whole scenario from its first leg: load it with leg=0",
        ));
    }
    let n = scenario.agents();
    if plan.plan.states[0].len() != n {
        return Err(input_error(
            py,
            &magbench_env::InputError::new(
                "<plan>",
                "states",
                format!(
                    "the plan is for {} agent(s); scenario {} has {n}",
                    plan.plan.states[0].len(),
                    s.name
                ),
            ),
        ));
    }
    let params = kv_params(params)?;
    let (tracker_box, options) = crate::registry::tracker(py, tracker, &params)?;
    let replanner = match planner {
        Some(name) => Some(crate::registry::planner(
            py,
            name,
            &kv_params(planner_params)?,
        )?),
        None => None,
    };
    let setup = scenario.setup.clone();
    let the_plan = plan.plan.clone();
    let preset = preset.to_string();
    let s2 = s.clone();
    let outcome = detached(py, "track", move || {
        track_plan(TrackRequest {
            scenario: &s2,
            plan: the_plan,
            plan_source: "<plan>",
            tracker: tracker_box,
            options,
            preset: &preset,
            seed,
            planner: replanner,
            setup,
        })
    })?;
    let metrics = metrics_json(&outcome, tracker, &s.name, seed);
    let traces = traces(py, &outcome, n)?;
    let plans = PyList::empty(py);
    for p in &outcome.plans {
        let d = PyDict::new(py);
        d.set_item("leg", p.leg)?;
        d.set_item("start_t_s", p.start_t)?;
        d.set_item(
            "reason",
            serde_json::to_value(p.reason)
                .ok()
                .and_then(|v| v.as_str().map(String::from)),
        )?;
        d.set_item("solved", p.solved)?;
        d.set_item("planning_time_s", p.planning_time_s)?;
        d.set_item(
            "plan",
            Plan {
                plan: p.plan.clone(),
                result: None,
                stop_reason: None,
                planner: planner.map(String::from),
                scenario: Some(s.name.clone()),
            },
        )?;
        plans.append(d)?;
    }
    Ok((metrics, traces, plans))
}

/// The run's metrics as JSON text: its identity, every metric, the per-agent errors and the
/// loop's message.
fn metrics_json(out: &TrackOutcome, tracker: &str, scenario: &str, seed: u64) -> String {
    let mut v = serde_json::json!({"scenario": scenario, "tracker": tracker, "seed": seed});
    if let (Some(o), Ok(serde_json::Value::Object(m))) =
        (v.as_object_mut(), serde_json::to_value(&out.metrics))
    {
        o.extend(m);
        o.insert(
            "per_agent".into(),
            serde_json::to_value(&out.per_agent).unwrap_or_default(),
        );
        o.insert("message".into(), serde_json::json!(out.message));
    }
    v.to_string()
}

/// The per-tick traces as numpy arrays: `t`, `leg`, `plan`, `progress_s`, `estimate`,
/// `observed` (NaN where missed), `truth`, `error` (per agent), `command` (T, 4), `in_goal`,
/// `compute_us`, and `mode` (a list of names).
fn traces<'py>(py: Python<'py>, out: &TrackOutcome, n: usize) -> PyResult<Bound<'py, PyDict>> {
    let ticks = &out.ticks;
    let t = ticks.len();
    let d = PyDict::new(py);
    let col = |f: &dyn Fn(&magbench_trackers::TickRecord) -> f64| -> Vec<f64> {
        ticks.iter().map(f).collect()
    };
    let mat = |w: usize, f: &dyn Fn(&magbench_trackers::TickRecord) -> Vec<f64>| {
        let flat: Vec<f64> = ticks.iter().flat_map(f).collect();
        PyArray2::from_owned_array(
            py,
            Array2::from_shape_vec((t, w), flat).expect("rows of one width"),
        )
    };
    d.set_item("t", PyArray1::from_vec(py, col(&|k| k.t)))?;
    d.set_item(
        "leg",
        PyArray1::from_vec(py, ticks.iter().map(|k| k.leg as i64).collect()),
    )?;
    d.set_item(
        "plan",
        PyArray1::from_vec(py, ticks.iter().map(|k| k.plan as i64).collect()),
    )?;
    d.set_item("progress_s", PyArray1::from_vec(py, col(&|k| k.progress_s)))?;
    d.set_item("estimate", mat(2 * n, &|k| state_vec(&k.estimate)))?;
    d.set_item(
        "observed",
        mat(2 * n, &|k| {
            k.observed
                .iter()
                .flat_map(|p| p.map_or([f64::NAN; 2], |p| [p.x, p.y]))
                .collect()
        }),
    )?;
    d.set_item(
        "truth",
        mat(2 * n, &|k| {
            k.truth
                .as_ref()
                .map_or(vec![f64::NAN; 2 * n], |s| state_vec(s))
        }),
    )?;
    d.set_item("error", mat(n, &|k| k.error.clone()))?;
    d.set_item(
        "command",
        mat(CONTROL_LEN, &|k| {
            crate::arrays::control_arr(&k.command).to_vec()
        }),
    )?;
    d.set_item(
        "in_goal",
        PyArray1::from_vec(py, ticks.iter().map(|k| k.in_goal).collect()),
    )?;
    d.set_item("compute_us", PyArray1::from_vec(py, col(&|k| k.compute_us)))?;
    d.set_item("mode", ticks.iter().map(|k| k.mode).collect::<Vec<_>>())?;
    Ok(d)
}

/// Runs the `magbench` command line with `args` (without the program name), with the
/// planners and trackers registered from Python. Bad input raises `InputError`, a failure
/// `MagbenchError`; `--help` prints and returns.
#[pyfunction]
pub fn main(py: Python<'_>, args: Vec<String>) -> PyResult<()> {
    crate::registry::run_cli(py, args)
}

/// The name of the experiment in `path` (its results go to `results/<name>` by default).
#[pyfunction]
pub fn experiment_name(py: Python<'_>, path: PathBuf) -> PyResult<String> {
    crate::registry::experiment_name(py, &path)
}
