//! Plan → track → write outputs: the one runner behind `magbench track` (a simulated rig) and
//! `magbench rig run` (a coil-and-camera rig, or the emulator), planning and tracking through
//! the run's [`Pipeline`] (a plan file is checked by its start rule first).
//!
//! The rig comes from the registry's rigs ([`magbench_drivers::rigs::Rigs`]), so this runner,
//! like the command line, does not know which rigs exist.

use std::path::{Path, PathBuf};

use magbench_drivers::rigs::RigDescription;
use magbench_drivers::{RigStats, stats};
use magbench_env::{Scenario, Vec2};
use magbench_planners::{FirstPlan, Limits, Planner, PlanningSetup, Unusable};
use magbench_trackers::plan_file::{check_origin, check_plan, plan_json_for, read_plan};
use magbench_trackers::{
    RunStatus, TrackOutcome, TrackerSpec, reference_for, track, write_ticks_csv,
};
use serde_json::{Value, json};

use crate::Error;
use crate::output::{emit, prepare_dir};
use crate::pipeline::{Failure, Pipeline};
use crate::plot::anim::{Frame, GifOptions, render_gif};
use crate::plot::world::{WorldPlot, render};
use crate::registry::Registry;
use crate::replay::{LegTree, ReplayData, page};

/// One plan-track run, as the command line asked for it.
pub struct TrackRun<'a> {
    /// Where the planner and tracker names were resolved.
    pub registry: &'a Registry,
    /// The scenario.
    pub scenario: &'a Scenario,
    /// The rig, loaded from its description by the registry.
    pub rig: Box<dyn RigDescription>,
    /// The planner of the first plan (unless `plan` is given) and of every replan: a name or a
    /// label `name{key=value,…}`.
    pub planner: Option<String>,
    /// The planner's `key=value` parameters (`--planner-param`), added to its label's.
    pub planner_params: &'a [String],
    /// A plan file to track instead of planning the first leg.
    pub plan: Option<PathBuf>,
    /// Track a plan file made for another scenario, team or start, with a warning.
    pub force: bool,
    /// The tracker and its (and the loop's) parameters.
    pub tracker: TrackerSpec,
    /// Seed of the planner and of the simulated disturbances.
    pub seed: u64,
    /// What every planning call is made under (its control period becomes the rig's).
    pub setup: PlanningSetup,
    /// The output folder.
    pub out: Option<PathBuf>,
    /// Also write a GIF of each leg into the output folder.
    pub gif: bool,
    /// Print one JSON object instead of a summary.
    pub json: bool,
}

/// The tracker `label` (`--tracker`: a name or `name{key=value,…}`) of `registry` with its
/// (and the loop's) `--param key=value` options added.
pub fn tracker_spec(
    registry: &Registry,
    label: &str,
    params: &[String],
) -> Result<TrackerSpec, Error> {
    let (name, params) = super::label::named("--tracker", label, "--param", params)?;
    Ok(registry.trackers().spec(&name, &params, "<command line>")?)
}

/// Runs it: open the rig, find the start, make (or read) the first plan, track it, stop the
/// rig, write the outputs and print the summary.
pub fn run(r: TrackRun) -> Result<(), Error> {
    let s = r.scenario;
    let named = match &r.planner {
        Some(label) => Some(super::label::named(
            "--planner",
            label,
            "--planner-param",
            r.planner_params,
        )?),
        None => None,
    };
    let mut planner = match &named {
        Some((name, params)) => Some(r.registry.planners().create(name, params)?),
        None => None,
    };
    // every plan, the first and each replan, is in whole frames of the rig that runs it, for
    // its medium and within its coil's elevation range
    let plant = r.rig.plant();
    let setup = r
        .setup
        .clone()
        .in_frames_of(r.rig.frame_period())
        .on_plant(&plant.medium, plant.coil_alpha_max_deg);
    let mut sets = vec![];
    if let Some(p) = &planner {
        sets.push(("planner-param", p.params()));
    }
    sets.push(("param", r.tracker.build().params()));
    super::setup::check_elevation(&setup, s, &sets, &plant.coil_source)?;
    let pipe = Pipeline::new(s, setup.clone(), r.seed);
    // a plan file, validated under the rig's setup: its frames, medium and coil
    let given = match &r.plan {
        Some(path) => {
            let plan = read_plan(path, s.agents())?;
            let file = path.display().to_string();
            match check_origin(&plan, s, &file) {
                Err(e) if r.force => eprintln!("warning: {e} (tracked anyway: --force)"),
                origin => origin?,
            }
            check_plan(&plan, s, &file, &setup)?;
            Some(plan)
        }
        None => None,
    };
    if let Some(dir) = &r.out {
        prepare_dir(dir, "--out")?;
    }
    let mut rig = r.rig.open(s, r.seed, r.out.as_deref())?;
    if let Some(d) = rig.describe() {
        eprintln!("rig: {d}");
    }
    // the start: the scenario's, or as the rig observes it (the field is zero meanwhile)
    let observed = rig.observe_start(s).map_err(|e| {
        let _ = rig.stop();
        Error::from(e)
    })?;
    if let Some(start) = &observed {
        eprintln!("observed start: {}", describe_start(start, &s.start));
    }
    let first = match (given, planner.as_mut()) {
        (Some(plan), _) => {
            let solved = s.legs[0].goal.contains(plan.end());
            (FirstPlan::given(plan, solved), None)
        }
        (None, None) => {
            let _ = rig.stop();
            return Err(Error::arg(
                "--planner",
                "a planner or a plan file (--plan) is needed",
            ));
        }
        (None, Some(planner)) => {
            let planned = {
                let progress = super::progress::Progress::new(!r.json);
                let planned = magbench_planners::progress::observe(
                    progress.planning("planning".into()),
                    || pipe.plan_leg(planner.as_mut(), 0, observed.as_deref()),
                );
                progress.clear();
                planned
            };
            let planned = match planned {
                Ok(planned) => planned,
                Err(f) => {
                    let _ = rig.stop();
                    let name = planner.name();
                    return Err(Error::Failed(match f {
                        Failure::InvalidStart { .. } => format!(
                            "{name}: the {} start is invalid in the first leg's map (collision or proximity range)",
                            if observed.is_some() {
                                "observed"
                            } else {
                                "scenario's"
                            }
                        ),
                        Failure::InvalidPlan { error, .. } => {
                            format!("{name}: {}", Unusable::Invalid(error))
                        }
                    }));
                }
            };
            let checked = planned.validated;
            let result = &checked.result;
            if rig.describe().is_some() {
                eprintln!(
                    "plan: {} in {:.2} s ({} edges, {:.1} s long)",
                    if result.solved {
                        "solved"
                    } else if result.approximate {
                        "approximate"
                    } else {
                        "not found"
                    },
                    result.time_s,
                    result.plan.edges(),
                    result.plan.duration()
                );
            }
            let name = planner.name().to_string();
            let tree = planned.tree;
            match checked.followable() {
                Ok(first) => (first, tree),
                Err(e) => {
                    let _ = rig.stop();
                    let from = if observed.is_some() {
                        "observed"
                    } else {
                        "scenario's"
                    };
                    return Err(Error::Failed(match e {
                        Unusable::NoMotion => format!(
                            "{name} found no plan from the {from} start{}",
                            if setup.limits == Limits::default() {
                                String::new()
                            } else {
                                format!(" within its limits ({:?})", setup.limits)
                            }
                        ),
                        Unusable::Invalid(_) => format!("{name}: {e}"),
                    }));
                }
            }
        }
    };
    let (first, tree) = first;
    let trees: Vec<LegTree> = tree.into_iter().collect();
    let solved = first.solved;
    let model = setup.model(s);
    let mission = pipe.mission(first, planner.as_deref_mut().map(|p| p as &mut dyn Planner));
    let mut tracker = r.tracker.build();
    let mut opts = r.tracker.loop_options();
    opts.record_ticks = r.out.is_some();
    opts.cancel = rig.cancel_flag();
    let progress = super::progress::Progress::new(!r.json);
    let outcome = magbench_planners::progress::observe(progress.tracking(), || {
        track(rig.as_rig(), tracker.as_mut(), mission, &opts)
    });
    progress.clear();
    let stopped = rig.stop();
    let rig_stats = rig.stats();
    let planner_label = named.as_ref().map_or("file", |(name, _)| name.as_str());
    let summary = summary_json(
        &r,
        planner_label,
        &rig.label(),
        solved,
        &outcome,
        observed.as_deref(),
        rig_stats.as_ref(),
    );
    let log = rig.log_path();
    drop(rig);
    if let Some(dir) = &r.out {
        write_outputs(
            dir,
            (s, &model),
            &outcome,
            &summary,
            planner_label,
            &r.tracker.label(),
            (&trees, r.gif),
        )?;
    }
    if r.json {
        emit(&format!(
            "{}\n",
            serde_json::to_string(&summary).expect("json")
        ))?;
    } else {
        emit(&summary_text(&summary, &outcome))?;
        if let Some(st) = &rig_stats {
            emit(&rig_text(st))?;
        }
        if let Some(l) = log {
            emit(&format!("log           {}\n", l.display()))?;
        }
    }
    if outcome.metrics.status == RunStatus::RigFault {
        return Err(Error::Failed(format!(
            "rig fault: {}",
            outcome.message.unwrap_or_else(|| "unknown".into())
        )));
    }
    if let Err(e) = stopped {
        return Err(Error::Failed(format!("stopping the rig: {e}")));
    }
    Ok(())
}

/// `(x, y) (x, y) (at most D BL from the scenario's start)`.
fn describe_start(start: &[Vec2], scenario_start: &[Vec2]) -> String {
    let offset = start
        .iter()
        .zip(scenario_start)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max);
    format!(
        "{} (at most {offset:.3} BL from the scenario's start)",
        start
            .iter()
            .map(|p| format!("({:.3}, {:.3})", p.x, p.y))
            .collect::<Vec<_>>()
            .join(" ")
    )
}

/// The `--json` object and `metrics.json`: the run's identity, then every metric, the
/// parameters, and what the rig observed and counted.
fn summary_json(
    r: &TrackRun,
    planner: &str,
    rig_label: &str,
    solved: bool,
    out: &TrackOutcome,
    observed: Option<&[Vec2]>,
    rig: Option<&RigStats>,
) -> Value {
    let mut v = json!({
        "scenario": r.scenario.name,
        "planner": planner,
        "tracker": r.tracker.name(),
        "tracker_label": r.tracker.label(),
        "seed": r.seed,
        "preset": rig_label,
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
            r.tracker
                .values()
                .iter()
                .map(|p| (p.name.to_string(), json!(p.value)))
                .collect(),
        );
        o.insert("message".into(), json!(out.message));
        o.insert(
            "replan_log".into(),
            serde_json::to_value(&out.replans).expect("serialize"),
        );
        if let Some(start) = observed {
            o.insert(
                "observed_start".into(),
                json!(start.iter().map(|p| [p.x, p.y]).collect::<Vec<_>>()),
            );
        }
        if let Some(st) = rig {
            let lat = |q: f64| stats::percentile(&st.latencies_ms, q);
            o.insert(
                "rig".into(),
                json!({
                    "frames": st.frames,
                    "dropped_frames": st.dropped_frames,
                    "skipped_frames": st.skipped_frames,
                    "stuck_frames": st.stuck_frames,
                    "missed_detections": st.missed_detections,
                    "commands": st.commands,
                    "clamped_commands": st.clamped_commands,
                    "faults": st.faults,
                    "latency_median_ms": lat(0.5),
                    "latency_p99_ms": lat(0.99),
                }),
            );
        }
    }
    v
}

/// The summary printed without `--json`: the run's identity from `v`, the metrics from `out`.
pub(crate) fn summary_text(v: &Value, out: &TrackOutcome) -> String {
    let g = |k: &str| v.get(k).cloned().unwrap_or(Value::Null);
    let m = &out.metrics;
    let f = |x: f64| format!("{x:.3}");
    let fo = |x: Option<f64>| x.map_or("-".to_string(), f);
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
        m.status.as_str(),
        m.reached_goal,
        m.legs_completed,
        m.legs,
        g("solved")
    );
    s += &format!(
        "error         RMS {} BL, max {} BL (observed positions to the planned path; true positions: RMS {} BL)\n",
        f(m.rms_error_bl),
        f(m.max_error_bl),
        fo(m.rms_error_true_bl),
    );
    if let Some(w) = m.worst_agent {
        let rms: Vec<String> = out.per_agent.iter().map(|a| f(a.rms_bl)).collect();
        s += &format!(
            "per agent     RMS {} BL (agents 1–{}); worst agent {}: RMS {} BL (true positions: {} BL)\n",
            rms.join(", "),
            rms.len(),
            w + 1,
            f(m.rms_error_worst_agent_bl),
            fo(m.rms_error_true_worst_agent_bl),
        );
    }
    s += &format!(
        "team error    synchronous RMS {} BL, time-indexed RMS {} BL, node RMS {} BL (the seed's)\n",
        f(m.rms_error_sync_bl),
        f(m.rms_error_time_bl),
        f(m.rms_error_node_bl),
    );
    s += &format!(
        "goal          final distance {} BL, time to goal {} s\n",
        f(m.final_goal_distance_bl),
        fo(m.time_to_goal_s)
    );
    s += &format!(
        "events        agent contact {}, wall contacts {}, missed frames {}, replans {}\n",
        m.agent_contact, m.wall_contacts, m.missed_frames, m.replans
    );
    s += &format!(
        "time          tracking {} s, planning {} s, tracker compute {} s\n",
        f(m.duration_s),
        f(m.planning_time_s),
        f(m.tracker_compute_s)
    );
    if let Some(msg) = &out.message {
        s += &format!("note          {msg}\n");
    }
    s
}

/// The rig's counters, for the summary.
fn rig_text(st: &RigStats) -> String {
    let mut s = format!(
        "rig           {} frames ({} dropped, {} skipped while planning or busy, {} stuck), {} missed detections, {} commands ({} clamped), {} faults\n",
        st.frames,
        st.dropped_frames,
        st.skipped_frames,
        st.stuck_frames,
        st.missed_detections,
        st.commands,
        st.clamped_commands,
        st.faults
    );
    let lat = |q: f64| stats::percentile(&st.latencies_ms, q);
    if let (Some(m), Some(p)) = (lat(0.5), lat(0.99)) {
        s += &format!(
            "latency       frame arrival → command sent: median {m:.3} ms, p99 {p:.3} ms\n"
        );
    }
    s
}

/// Writes `what` to `path`, naming the path on failure.
fn write(path: &Path, what: impl AsRef<[u8]>) -> Result<(), Error> {
    std::fs::write(path, what).map_err(|e| Error::Failed(format!("{}: {e}", path.display())))
}

/// Writes ticks.csv, metrics.json, plans.json, plan.json, replay.html (with `trees`), the
/// world plot(s) and, if `gif`, the GIF(s); `model` is the planning model of the plans.
fn write_outputs(
    dir: &Path,
    (s, model): (&Scenario, &magbench_env::PlanningModel),
    out: &TrackOutcome,
    summary: &Value,
    planner: &str,
    tracker: &str,
    (trees, gif): (&[LegTree], bool),
) -> Result<(), Error> {
    let title = format!("{} · {planner} + {tracker}", s.name);
    page::write(
        &dir.join("replay.html"),
        &ReplayData::tracked(s, title, out, trees, model),
    )?;
    let ticks = dir.join("ticks.csv");
    let csv_file = std::fs::File::create(&ticks)
        .map_err(|e| Error::Failed(format!("{}: {e}", ticks.display())))?;
    write_ticks_csv(std::io::BufWriter::new(csv_file), &out.ticks)
        .map_err(|e| Error::Failed(format!("{}: {e}", ticks.display())))?;
    write(
        &dir.join("metrics.json"),
        serde_json::to_string_pretty(summary).expect("json"),
    )?;
    let plans: Vec<Value> = out
        .plans
        .iter()
        .map(|p| json!({"leg": p.leg, "start_t_s": p.start_t, "reason": p.reason, "solved": p.solved, "planning_time_s": p.planning_time_s, "plan": p.plan}))
        .collect();
    write(
        &dir.join("plans.json"),
        serde_json::to_string_pretty(&plans).expect("json"),
    )?;
    if let Some(first) = out.plans.first() {
        write(&dir.join("plan.json"), plan_json_for(&first.plan, s, 1))?;
    }
    let legs = s.legs.len();
    for leg in 0..legs {
        let ticks: Vec<_> = out.ticks.iter().filter(|t| t.leg == leg).collect();
        if ticks.is_empty() {
            continue;
        }
        let world = s.world_for_leg(leg);
        let mut plot = WorldPlot::new(&world);
        let leg_name = |prefix: &str, single: &str, ext: &str| {
            if legs > 1 {
                format!("{prefix}-leg{}{ext}", leg + 1)
            } else {
                format!("{single}{ext}")
            }
        };
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
        plot.planned = planned_paths(out, s, leg, model);
        plot.starts = ticks[0].estimate.clone();
        plot.tracked = (0..s.agents())
            .map(|i| ticks.iter().map(|t| t.position(i)).collect())
            .collect();
        render(&plot, &dir.join(leg_name("world", "world", "")))?;
        if !gif {
            continue;
        }
        let frames: Vec<Frame> = ticks
            .iter()
            .map(|t| Frame {
                time_s: t.t,
                agents: (0..s.agents()).map(|i| t.position(i)).collect(),
            })
            .collect();
        render_gif(
            &plot,
            &frames,
            &dir.join(leg_name("run", "run", ".gif")),
            &GifOptions::default(),
        )?;
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
