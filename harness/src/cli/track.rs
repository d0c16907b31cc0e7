//! `magbench track`: plan, then track the plan in closed loop against the simulated plant.

use std::path::{Path, PathBuf};

use clap::Args;
use magbench_env::plant::DisturbancePreset;
use magbench_env::{Scenario, Vec2};
use magbench_planners::{Limits, Planner, Problem};
use magbench_trackers::plan_file::{plan_json, read_plan};
use magbench_trackers::registry::parse_param;
use magbench_trackers::{
    Mission, TrackOutcome, TrackerSpec, reference_for, simulate, write_ticks_csv,
};
use serde_json::{Value, json};

use crate::CliError;
use crate::plot::anim::{Frame, GifOptions, render_gif};
use crate::plot::world::{WorldPlot, render};

/// Arguments of `magbench track`.
#[derive(Debug, Args)]
pub struct TrackArgs {
    /// A built-in scenario name or a scenario file.
    pub scenario: String,
    /// The planner that makes the plan (and every replan); goal-zoom-rrt unless --plan is given.
    #[arg(long)]
    pub planner: Option<String>,
    /// The tracker: open-loop, obc or lookahead.
    #[arg(long)]
    pub tracker: String,
    /// Seed of the planner and of the simulated disturbances.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Disturbance preset of the simulated plant and camera: ideal or realistic.
    #[arg(long, default_value = "realistic")]
    pub preset: String,
    /// A tracker or loop parameter, key=value (repeatable).
    #[arg(long = "param", value_name = "KEY=VALUE")]
    pub params: Vec<String>,
    /// A planner parameter, key=value (repeatable).
    #[arg(long = "planner-param", value_name = "KEY=VALUE")]
    pub planner_params: Vec<String>,
    /// Track this plan (JSON, as written by `track --out` or `plan --out`) instead of planning
    /// the first leg; the planner, if given, still makes the replans.
    #[arg(long, value_name = "FILE")]
    pub plan: Option<PathBuf>,
    /// Planner iteration limit of every planning call.
    #[arg(long)]
    pub max_iters: Option<u64>,
    /// Planner time limit of every planning call (s).
    #[arg(long)]
    pub time_limit: Option<f64>,
    /// Print one JSON object on stdout instead of a summary.
    #[arg(long)]
    pub json: bool,
    /// Write the per-tick CSV, the metrics, the plans, a world plot and a GIF of the run here.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

fn kv_list(list: &[String]) -> Result<Vec<(String, String)>, CliError> {
    list.iter()
        .map(|kv| parse_param(kv, "<command line>").map_err(CliError::from))
        .collect()
}

/// The planner of that name from the planners' registry.
fn make_planner(name: &str, params: &[(String, String)]) -> Result<Box<dyn Planner>, CliError> {
    Ok(magbench_planners::registry::create(name, params)?)
}

fn limits(a: &TrackArgs) -> Result<Option<Limits>, CliError> {
    if a.max_iters.is_none() && a.time_limit.is_none() {
        return Ok(None);
    }
    if let Some(t) = a.time_limit.filter(|t| !t.is_finite() || *t <= 0.0) {
        return Err(CliError::arg(
            "--time-limit",
            format!("must be a number of seconds > 0, got {t}"),
        ));
    }
    Ok(Some(Limits {
        max_iterations: a.max_iters,
        time_limit: a.time_limit.map(std::time::Duration::from_secs_f64),
    }))
}

/// Runs `magbench track`.
pub fn run(a: TrackArgs) -> Result<(), CliError> {
    let scenario = Scenario::load(&a.scenario)?;
    let preset = DisturbancePreset::by_name(&a.preset).ok_or_else(|| {
        CliError::arg(
            "--preset",
            format!(
                "unknown preset `{}` (known: {})",
                a.preset,
                DisturbancePreset::NAMES.join(", ")
            ),
        )
    })?;
    let spec = TrackerSpec::parse(&a.tracker, &kv_list(&a.params)?, "<command line>")?;
    let limits = limits(&a)?;
    // without a plan file, the seed's planner makes the plan unless another is named
    let planner_name = match (&a.planner, &a.plan) {
        (Some(name), _) => Some(name.as_str()),
        (None, None) => Some("goal-zoom-rrt"),
        (None, Some(_)) => None,
    };
    let mut planner = match planner_name {
        Some(name) => Some(make_planner(name, &kv_list(&a.planner_params)?)?),
        None => None,
    };
    let given = match &a.plan {
        Some(p) => Some(read_plan(p, scenario.agents())?),
        None => None,
    };
    // the first plan: from the file, or planned from the scenario's start (as `magbench plan`)
    let (plan, plan_time, solved) = match given {
        Some(p) => {
            let ok = scenario.legs[0].goal.contains(p.end());
            (p, 0.0, ok)
        }
        None => {
            let planner = planner.as_mut().expect("checked above");
            let mut problem = Problem::from_scenario(&scenario, 0, None, a.seed);
            if let Some(l) = limits {
                problem.limits = l;
            }
            let r = planner.solve(&problem);
            (r.plan, r.time_s, r.solved)
        }
    };
    let mission = Mission {
        scenario: &scenario,
        plan: Some(plan),
        plan_time_s: plan_time,
        plan_solved: solved,
        planner: planner.as_deref_mut().map(|p| p as &mut dyn Planner),
        limits,
        seed: a.seed,
    };
    let mut tracker = spec.build();
    let mut opts = spec.loop_options();
    opts.record_ticks = a.out.is_some();
    let out = simulate(mission, tracker.as_mut(), &preset, &opts);
    let summary = summary_json(&a, &scenario, &spec, solved, &out);
    if let Some(dir) = &a.out {
        write_outputs(
            dir,
            &scenario,
            &out,
            &summary,
            a.planner.as_deref().unwrap_or("file"),
            &spec.label(),
        )?;
    }
    let text = if a.json {
        format!(
            "{}\n",
            serde_json::to_string(&summary).map_err(|e| CliError::Failed(e.to_string()))?
        )
    } else {
        summary_text(&summary)
    };
    emit(&text)
}

/// Writes `text` to stdout; a closed pipe (`| head`) is not an error.
fn emit(text: &str) -> Result<(), CliError> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}

/// The `--json` object: the run's identity, then every metric.
fn summary_json(
    a: &TrackArgs,
    s: &Scenario,
    spec: &TrackerSpec,
    solved: bool,
    out: &TrackOutcome,
) -> Value {
    let mut v = json!({
        "scenario": s.name,
        "planner": a.planner.as_deref().unwrap_or("file"),
        "tracker": spec.name,
        "tracker_label": spec.label(),
        "seed": a.seed,
        "preset": a.preset,
        "solved": solved,
    });
    let m = serde_json::to_value(&out.metrics).expect("metrics serialize");
    if let (Value::Object(o), Value::Object(mm)) = (&mut v, m) {
        o.extend(mm);
        o.insert(
            "per_agent".into(),
            serde_json::to_value(&out.per_agent).expect("serialize"),
        );
        o.insert(
            "params".into(),
            spec.values
                .iter()
                .map(|(k, x)| ((*k).to_string(), json!(x)))
                .collect(),
        );
        o.insert("message".into(), json!(out.message));
    }
    v
}

pub(crate) fn summary_text(v: &Value) -> String {
    let g = |k: &str| v.get(k).cloned().unwrap_or(Value::Null);
    let f = |k: &str| g(k).as_f64().map_or("-".to_string(), |x| format!("{x:.3}"));
    let mut s = String::new();
    s += &format!(
        "{} · planner {} · tracker {} · preset {} · seed {}\n",
        g("scenario").as_str().unwrap_or(""),
        g("planner").as_str().unwrap_or(""),
        g("tracker_label").as_str().unwrap_or(""),
        g("preset").as_str().unwrap_or(""),
        g("seed")
    );
    s += &format!(
        "status        {}  (reached goal: {}, legs {}/{}, plan solved: {})\n",
        g("status").as_str().unwrap_or(""),
        g("reached_goal"),
        g("legs_completed"),
        g("legs"),
        g("solved")
    );
    s += &format!(
        "error         RMS {} BL, max {} BL (distance to the planned path, {} positions)\n",
        f("rms_error_bl"),
        f("max_error_bl"),
        g("error_source").as_str().unwrap_or("")
    );
    s += &format!(
        "goal          final distance {} BL, time to goal {} s\n",
        f("final_goal_distance_bl"),
        f("time_to_goal_s")
    );
    s += &format!(
        "events        agent contact {}, wall contacts {}, missed frames {}, replans {}\n",
        g("agent_contact"),
        g("wall_contacts"),
        g("missed_frames"),
        g("replans")
    );
    s += &format!(
        "time          tracking {} s, planning {} s, tracker compute {} s\n",
        f("duration_s"),
        f("planning_time_s"),
        f("tracker_compute_s")
    );
    if let Some(m) = g("message").as_str() {
        s += &format!("note          {m}\n");
    }
    s
}

/// Writes ticks.csv, metrics.json, plans.json, the world plot(s) and the GIF(s).
fn write_outputs(
    dir: &Path,
    s: &Scenario,
    out: &TrackOutcome,
    summary: &Value,
    planner: &str,
    tracker: &str,
) -> Result<(), CliError> {
    std::fs::create_dir_all(dir)?;
    let csv_file = std::fs::File::create(dir.join("ticks.csv"))?;
    write_ticks_csv(std::io::BufWriter::new(csv_file), &out.ticks)
        .map_err(|e| CliError::Failed(e.to_string()))?;
    std::fs::write(
        dir.join("metrics.json"),
        serde_json::to_string_pretty(summary).expect("json"),
    )?;
    let plans: Vec<Value> = out
        .plans
        .iter()
        .map(|p| json!({"leg": p.leg, "start_t_s": p.start_t, "reason": p.reason, "solved": p.solved, "planning_time_s": p.planning_time_s, "plan": p.plan}))
        .collect();
    std::fs::write(
        dir.join("plans.json"),
        serde_json::to_string_pretty(&plans).expect("json"),
    )?;
    if let Some(first) = out.plans.first() {
        std::fs::write(dir.join("plan.json"), plan_json(&first.plan))?;
    }
    let model = magbench_env::PlanningModel::new(&s.physics);
    let legs = s.legs.len();
    for leg in 0..legs {
        let world = s.world_for_leg(leg);
        let mut plot = WorldPlot::new(&world);
        plot.title = Some(format!(
            "{}{} · {planner} + {tracker}",
            s.name,
            if legs > 1 {
                format!(" leg {}", leg + 1)
            } else {
                String::new()
            }
        ));
        plot.goals = vec![s.legs[leg].goal.clone()];
        plot.planned = planned_paths(out, s, leg, &model);
        let ticks: Vec<_> = out.ticks.iter().filter(|t| t.leg == leg).collect();
        if ticks.is_empty() {
            continue;
        }
        plot.starts = ticks[0].estimate.clone();
        plot.tracked = (0..s.agents())
            .map(|i| ticks.iter().map(|t| t.position(i)).collect())
            .collect();
        let stem = if legs > 1 {
            format!("world-leg{}", leg + 1)
        } else {
            "world".to_string()
        };
        render(&plot, &dir.join(&stem))?;
        let frames: Vec<Frame> = ticks
            .iter()
            .map(|t| Frame {
                time_s: t.t,
                agents: (0..s.agents()).map(|i| t.position(i)).collect(),
            })
            .collect();
        let gif = if legs > 1 {
            format!("run-leg{}.gif", leg + 1)
        } else {
            "run.gif".to_string()
        };
        render_gif(&plot, &frames, &dir.join(gif), &GifOptions::default())?;
    }
    Ok(())
}

/// Each agent's planned path during `leg`: every plan of the leg, cut where the next plan took
/// over (at the tracker's progress then), joined in order.
fn planned_paths(
    out: &TrackOutcome,
    s: &Scenario,
    leg: usize,
    model: &magbench_env::PlanningModel,
) -> Vec<Vec<Vec2>> {
    let agents = s.agents();
    let mut paths = vec![vec![]; agents];
    let idx: Vec<usize> = (0..out.plans.len())
        .filter(|&p| out.plans[p].leg == leg)
        .collect();
    for (n, &p) in idx.iter().enumerate() {
        let r = reference_for(&out.plans[p].plan, model, &s.legs[leg].goal);
        let upto = match idx.get(n + 1) {
            Some(&next) => out
                .ticks
                .iter()
                .rev()
                .find(|t| t.plan == p && t.t < out.plans[next].start_t + 1e-9)
                .map_or(r.last(), |t| r.index_at(t.progress_s)),
            None => r.last(),
        };
        for (i, path) in paths.iter_mut().enumerate() {
            path.extend((0..=upto).map(|k| r.point(k, i)));
        }
    }
    paths
}
