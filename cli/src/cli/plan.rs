//! `magbench plan`: plan a scenario with one planner and report (or write) the result.
//!
//! A scenario with several legs is planned leg by leg, each leg from where the previous plan
//! ends; planning stops at the first leg that is not solved.
//!
//! `plan` has no rig: it plans for the default preset's plant (`realistic`, the default of
//! `magbench track`): bulk liquid unless the scenario's `[medium]` says otherwise, and a
//! tri-axial coil (elevation range 90°). So `planar = auto` frees the elevation only for three
//! or more agents in a scenario at an interface; the summary says whether it was free and why.
//! When a plan tilts the field further than the medium lets the magnets tilt (contact-line
//! pinning at an interface), a warning on stderr names the α asked and the tilt reached.

use std::path::{Path, PathBuf};

use clap::Args;
use magbench_env::coil::{Planar, elevation_params};
use magbench_env::math::centroid;
use magbench_env::plant::{Medium, Tilt};
use magbench_env::{MAX_AGENTS, PhysicalParams, Scenario, Vec2};
use magbench_planners::{Plan, Planner, PlannerResult, Planners, PlanningSetup, Problem};
use serde_json::{Value, json};

use super::number::checked;
use super::setup::{SetupArgs, check_elevation};
use crate::Error;
use crate::output::{out, outln};
use crate::pipeline::{Failure, Pipeline};
use crate::plot::world::{WorldPlot, render};
use crate::registry::Registry;
use crate::replay::tree_svg::{TreePicture, svg_paths};
use crate::replay::{LegTree, ReplayData, TreeFile, page};

/// Arguments of `magbench plan`.
#[derive(Debug, Args)]
pub struct PlanArgs {
    /// A built-in scenario name or a scenario file.
    #[arg(required_unless_present = "list")]
    pub scenario: Option<String>,
    /// The planner: a name (goal-zoom-rrt, rrt-star, informed-rrt-star, sst, formation-rrt or a
    /// plugin's; see --list) or a label with parameters as experiment files write it,
    /// `goal-zoom-rrt{aim=true,guide=true}`.
    #[arg(long, required_unless_present = "list")]
    pub planner: Option<String>,
    /// Seed of the run: leg k (from 0) is planned with seed + k·1000003, as a sweep's run of
    /// this seed plans it.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Planner limits per leg, objective, metric and flow.
    #[command(flatten)]
    pub setup: SetupArgs,
    /// A planner parameter, key=value (repeatable; see --list). Added to those of a --planner
    /// label; a key in both is refused.
    #[arg(long = "param", value_name = "KEY=VALUE")]
    pub params: Vec<String>,
    /// Camera frames per second of the rig that will run the plan: every edge lasts a whole
    /// number of its frames (default 60, the presets' camera).
    #[arg(long, default_value_t = 60.0)]
    pub fps: f64,
    /// Print exactly one JSON object on stdout instead of a summary.
    #[arg(long)]
    pub json: bool,
    /// Write the plan (JSON and CSV), the result with its progress trace, and a world plot
    /// with the tree, the plan's agent paths, start and goal here.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Write the planner's search tree of every leg here (JSON: nodes, parents, controls,
    /// durations; docs/replay.md) and its picture next to it (SVG).
    #[arg(long, value_name = "FILE")]
    pub tree: Option<PathBuf>,
    /// List the planners and their parameters with defaults, and exit.
    #[arg(long)]
    pub list: bool,
}

/// One planned leg.
struct LegRun {
    problem: Problem,
    result: PlannerResult,
    tree: Vec<(Vec2, Vec2)>,
    /// The whole tree, when the planner keeps one.
    tree_data: Option<LegTree>,
    /// Why the planner stopped unsolved, when it says.
    stopped: Option<String>,
}

impl AsRef<PlannerResult> for LegRun {
    fn as_ref(&self) -> &PlannerResult {
        &self.result
    }
}

/// Runs `magbench plan` with the planners of `registry`.
pub fn run(a: PlanArgs, registry: &Registry) -> Result<(), Error> {
    if a.list {
        out!("{}", planner_list(registry.planners()));
        return Ok(());
    }
    let (Some(scenario_name), Some(label)) = (a.scenario.as_deref(), a.planner.as_deref()) else {
        return Err(Error::arg(
            "SCENARIO",
            "a scenario and --planner are required",
        ));
    };
    let scenario = Scenario::load(scenario_name)?;
    let (planner_name, params) = super::label::named("--planner", label, "--param", &a.params)?;
    let planner_name = planner_name.as_str();
    let planner = registry.planners().create(planner_name, &params)?;
    // the bound of a rig file's `camera.fps`: the rig that runs the plan has one of those
    checked("--fps", &magbench_drivers::rigfile::FPS, a.fps)?;
    let setup = a.setup.setup()?.in_frames_of(1.0 / a.fps);
    check_elevation(
        &setup,
        &scenario,
        &[("param", planner.params())],
        "the default tri-axial coil",
    )?;
    let elevation = elevation_json(&setup, &scenario, &elevation_params(&planner.params()).0);
    if let Some(dir) = &a.out {
        crate::output::prepare_dir(dir, "--out")?;
    }
    if let Some(file) = &a.tree {
        let dir = file.parent().filter(|d| !d.as_os_str().is_empty());
        if dir.is_some_and(|d| !d.is_dir()) {
            return Err(Error::arg(
                "--tree",
                format!("{}: its folder does not exist", file.display()),
            ));
        }
    }

    let pipe = Pipeline::new(&scenario, setup.clone(), a.seed);
    let progress = super::progress::Progress::new(!a.json);
    let legs = scenario.legs.len();
    let runs = pipe.plan_legs(|leg, start| {
        let prefix = if legs > 1 {
            format!("leg {}/{legs}", leg + 1)
        } else {
            "planning".to_string()
        };
        // a fresh planner for every leg, as a sweep plans
        let mut planner = registry.planners().create(planner_name, &params)?;
        let planned = magbench_planners::progress::observe(progress.planning(prefix), || {
            pipe.plan_leg(planner.as_mut(), leg, start)
        })
        .map_err(|f| match f {
            Failure::InvalidStart { leg } => Error::Failed(format!(
                "leg {}: the previous leg ends in a state that is invalid in this leg's map",
                leg + 1
            )),
            // never hand out a plan the validator refuses (a plan without motion is reported)
            Failure::InvalidPlan { leg, error } => Error::Failed(format!(
                "leg {}: {planner_name} returned an invalid plan: {error}",
                leg + 1
            )),
        })?;
        Ok::<_, Error>(LegRun {
            tree: tree_edges(&*planner),
            problem: planned.problem,
            result: planned.validated.result,
            tree_data: planned.tree,
            stopped: planned.stopped,
        })
    })?;

    progress.clear();
    let plans = runs.iter().map(|r| &r.result.plan);
    if let Some(w) = tilt_warning(setup.medium_of(&scenario), &scenario.physics, plans) {
        eprintln!("{w}");
    }
    let mut summary = summary_json(&scenario, planner_name, &a, &runs);
    summary["elevation"] = elevation;
    if let Some(dir) = &a.out {
        write_outputs(
            dir,
            &scenario,
            &setup.model(&scenario),
            planner_name,
            &summary,
            &runs,
        )?;
    }
    if let Some(file) = &a.tree {
        write_tree(file, &scenario, planner_name, &runs)?;
    }
    if a.json {
        outln!("{}", serde_json::to_string(&summary).expect("json"));
    } else {
        out!("{}", summary_text(&summary, &runs));
        if let Some(dir) = &a.out {
            outln!("wrote       {}", dir.display());
        }
    }
    Ok(())
}

/// The planners of `planners` and their parameters, for `--list`.
pub fn planner_list(planners: &Planners) -> String {
    let mut s = String::new();
    for (name, summary, params) in planners.list() {
        s += &format!("{name}\n    {summary}\n");
        for p in params {
            s += &p.listing_line([20, 10, 16]);
        }
    }
    s += "objectives: path-length (default), duration, control-effort (--objective)\n";
    s += "metrics:    positions (default), centroid-shape:W_CENTROID:W_SHAPE (--metric)\n";
    s += "flows:      pair-adaptive (default), pair-exact, rk4 (--flow)\n";
    s
}

/// The planner's tree projected on the team's centroid (at most 20000 edges, evenly chosen).
fn tree_edges(planner: &dyn Planner) -> Vec<(Vec2, Vec2)> {
    let Some(tree) = planner.tree() else {
        return vec![];
    };
    let edges: Vec<(u32, u32)> = tree.edges().collect();
    let stride = edges.len().div_ceil(20_000).max(1);
    edges
        .iter()
        .step_by(stride)
        .map(|&(p, c)| (centroid(tree.state(p)), centroid(tree.state(c))))
        .collect()
}

/// Whether the planner could tilt the field for this scenario, and why: `free`, `reason`, the
/// `medium` the agents are in and the largest elevation `alpha_max_deg` (when free).
fn elevation_json(setup: &PlanningSetup, s: &Scenario, planar: &Option<Planar>) -> Value {
    let medium = setup.medium_of(s).kind();
    let (free, reason) = match planar {
        Some(p) => setup.elevation(s, *p),
        None => (false, "the planner samples in-plane controls only"),
    };
    json!({
        "free": free,
        "reason": reason,
        "medium": medium,
        "alpha_max_deg": free.then_some(setup.alpha_max_deg),
    })
}

/// A warning when the plans (one per leg) tilt the field further out of the plane than the
/// magnets follow in `medium` (contact-line pinning at an interface,
/// [`magbench_env::plant::pinning`]): the largest |α| they command, its leg, and the tilt the
/// medium gives for it.
fn tilt_warning<'a>(
    medium: &Medium,
    p: &PhysicalParams,
    plans: impl Iterator<Item = &'a Plan>,
) -> Option<String> {
    let tilt = Tilt::of(medium, p)?;
    let (leg, alpha) = plans
        .enumerate()
        .flat_map(|(k, plan)| plan.controls.iter().map(move |u| (k + 1, u.alpha.abs())))
        .fold((0, 0.0f64), |best, x| if x.1 > best.1 { x } else { best });
    let achieved = tilt.achieved(alpha);
    if alpha == 0.0 || achieved >= alpha {
        return None;
    }
    let holds = if tilt.lag >= std::f64::consts::FRAC_PI_2 {
        "keeps its moment in the plane".to_string()
    } else {
        format!(
            "holds its moment {:.1}° below the field's elevation",
            tilt.lag.to_degrees()
        )
    };
    Some(format!(
        "warning: leg {leg} tilts the field to α = {:.1}°, but at this interface a magnet tilts to {:.1}° only: the contact line's pinning torque ({:.2} nN·m, contact-angle hysteresis) against the magnetic torque mB ({:.2} nN·m) {holds}; the out-of-plane moves of this plan will not happen as planned",
        alpha.to_degrees(),
        achieved.to_degrees(),
        tilt.pinning_torque * 1e9,
        tilt.magnetic_torque * 1e9,
    ))
}

fn summary_json(s: &Scenario, planner: &str, a: &PlanArgs, runs: &[LegRun]) -> Value {
    let solved = runs.len() == s.legs.len() && runs.iter().all(|r| r.result.solved);
    let last = runs.last().expect("at least one leg is planned");
    let cost: Option<f64> = if solved {
        runs.iter().map(|r| r.result.cost).sum()
    } else {
        None
    };
    let mut v = json!({
        "scenario": s.name,
        "planner": planner,
        "seed": a.seed,
        "solved": solved,
        "approximate": !solved,
        "iterations": runs.iter().map(|r| r.result.iterations).sum::<u64>(),
        "nodes": runs.iter().map(|r| r.result.nodes).sum::<usize>(),
        "time_s": runs.iter().map(|r| r.result.time_s).sum::<f64>(),
        "cost": cost,
        "goal_distance": last.result.goal_distance,
        "stop_reason": last.stopped,
    });
    if s.legs.len() > 1 {
        v["legs"] = runs
            .iter()
            .enumerate()
            .map(|(k, r)| {
                json!({
                    "leg": k + 1,
                    "solved": r.result.solved,
                    "iterations": r.result.iterations,
                    "nodes": r.result.nodes,
                    "time_s": r.result.time_s,
                    "cost": r.result.cost,
                    "goal_distance": r.result.goal_distance,
                    "stop_reason": r.stopped,
                })
            })
            .collect();
    }
    v
}

fn summary_text(v: &Value, runs: &[LegRun]) -> String {
    let e = &v["elevation"];
    let mut s = format!(
        "scenario    {}\nplanner     {}  (seed {})\nelevation   {} ({}; {} medium)\n",
        v["scenario"].as_str().unwrap_or(""),
        v["planner"].as_str().unwrap_or(""),
        v["seed"],
        match e["alpha_max_deg"].as_f64() {
            Some(a) => format!("free, α in [0, {a}]°"),
            None => "in the plane (α = 0)".to_string(),
        },
        e["reason"].as_str().unwrap_or(""),
        e["medium"].as_str().unwrap_or(""),
    );
    for (k, r) in runs.iter().enumerate() {
        let res = &r.result;
        let what = if res.solved {
            "solved"
        } else {
            "NOT solved (closest approach)"
        };
        let first = res
            .first_solution
            .map(|(i, t)| format!(", first solution at iteration {i} ({t:.3} s)"))
            .unwrap_or_default();
        s += &format!(
            "leg {}       {what}: {} edges, {:.2} s of motion, cost {}, goal distance {:.3} BL\n            {} iterations, {} nodes, {:.3} s{first}\n",
            k + 1,
            res.plan.edges(),
            res.plan.duration(),
            res.cost.map_or("-".to_string(), |c| format!(
                "{c:.3} ({})",
                r.problem.objective.name()
            )),
            res.goal_distance,
            res.iterations,
            res.nodes,
            res.time_s,
        );
        if let Some(why) = &r.stopped {
            s += &format!("            stopped: {why}\n");
        }
    }
    s
}

/// The plan's agent paths along its integration samples (for the plot).
fn agent_paths(problem: &Problem, plan: &Plan) -> Vec<Vec<Vec2>> {
    let n = problem.agents();
    let mut paths: Vec<Vec<Vec2>> = plan.start().iter().map(|p| vec![*p]).collect();
    let mut out = [Vec2::zeros(); MAX_AGENTS];
    for (k, (u, &d)) in plan.controls.iter().zip(&plan.durations).enumerate() {
        problem
            .model
            .propagate_with(&plan.states[k], u, d, &mut out[..n], |s| {
                for (path, p) in paths.iter_mut().zip(s) {
                    path.push(*p);
                }
                true
            });
    }
    paths
}

/// Writes the tree file `file` and its picture(s) next to it.
fn write_tree(file: &Path, s: &Scenario, planner: &str, runs: &[LegRun]) -> Result<(), Error> {
    let trees: Vec<LegTree> = runs.iter().filter_map(|r| r.tree_data.clone()).collect();
    if trees.is_empty() {
        eprintln!(
            "note: {planner} keeps no search tree; {} has no legs",
            file.display()
        );
    }
    TreeFile::new(&s.name, planner, s.agents(), trees).write(file)?;
    let with_tree: Vec<&LegRun> = runs.iter().filter(|r| r.tree_data.is_some()).collect();
    for (r, path) in with_tree.iter().zip(svg_paths(file, with_tree.len())) {
        let tree = r.tree_data.as_ref().expect("filtered");
        crate::replay::tree_svg::write(
            &TreePicture {
                world: &r.problem.world,
                tree,
                planned: agent_paths(&r.problem, &r.result.plan),
                goal: r.problem.goal.clone(),
                title: format!(
                    "{} leg {} · {planner} · tree of {} nodes (centroids)",
                    s.name,
                    tree.leg,
                    tree.nodes()
                ),
            },
            &path,
        )?;
    }
    Ok(())
}

fn write_outputs(
    dir: &Path,
    s: &Scenario,
    model: &magbench_env::PlanningModel,
    planner: &str,
    summary: &Value,
    runs: &[LegRun],
) -> Result<(), Error> {
    let results: Vec<&PlannerResult> = runs.iter().map(|r| &r.result).collect();
    let trees: Vec<LegTree> = runs.iter().filter_map(|r| r.tree_data.clone()).collect();
    page::write(
        &dir.join("replay.html"),
        &ReplayData::planned(
            s,
            format!("{} · {planner}", s.name),
            &results,
            &trees,
            model,
        ),
    )?;
    let fail =
        |what: &Path, e: &dyn std::fmt::Display| Error::Failed(format!("{}: {e}", what.display()));
    let multi = s.legs.len() > 1;
    let mut result = summary.clone();
    result["progress"] = runs
        .iter()
        .map(|r| {
            r.result
                .progress
                .iter()
                .map(|p| json!({"iteration": p.iteration, "time_s": p.time_s, "best_cost": p.best_cost}))
                .collect::<Vec<_>>()
        })
        .collect();
    let path = dir.join("result.json");
    std::fs::write(&path, serde_json::to_string_pretty(&result).expect("json"))
        .map_err(|e| fail(&path, &e))?;
    for (k, r) in runs.iter().enumerate() {
        let stem = if multi {
            format!("plan-leg{}", k + 1)
        } else {
            "plan".to_string()
        };
        let path = dir.join(format!("{stem}.json"));
        std::fs::write(
            &path,
            magbench_trackers::plan_file::plan_json_for(&r.result.plan, s, k + 1),
        )
        .map_err(|e| fail(&path, &e))?;
        let path = dir.join(format!("{stem}.csv"));
        std::fs::write(&path, r.result.plan.to_csv()).map_err(|e| fail(&path, &e))?;

        let world = &r.problem.world;
        let mut plot = WorldPlot::new(world);
        plot.tree = r.tree.clone();
        plot.planned = agent_paths(&r.problem, &r.result.plan);
        plot.starts = r.problem.start.clone();
        plot.goals = vec![r.problem.goal.clone()];
        let status = if r.result.solved {
            "solved".to_string()
        } else {
            format!("not solved, {:.2} BL from the goal", r.result.goal_distance)
        };
        plot.title = Some(format!(
            "{}{} · {planner} · {status} · tree of {} nodes (centroids)",
            s.name,
            if multi {
                format!(" leg {}", k + 1)
            } else {
                String::new()
            },
            r.result.nodes
        ));
        let stem = if multi {
            format!("world-leg{}", k + 1)
        } else {
            "world".to_string()
        };
        render(&plot, &dir.join(stem))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use magbench_planners::planners::GoalZoomRrt;

    use super::*;

    #[test]
    fn the_list_shows_a_plugin_with_its_parameters() {
        let mut registry = Registry::builtin();
        registry
            .add_planner("my-rrt", "a plugin's RRT", || {
                Box::new(GoalZoomRrt::default())
            })
            .unwrap();
        let list = planner_list(registry.planners());
        let at = list.find("my-rrt\n    a plugin's RRT\n").expect(&list);
        assert!(list[at..].contains("goal_bias"), "{list}");
        assert!(
            list.find("goal-zoom-rrt\n").unwrap() < at,
            "built-ins first"
        );
        assert!(!planner_list(Registry::builtin().planners()).contains("my-rrt"));
    }

    #[test]
    fn a_plan_tilting_the_field_at_a_pinning_interface_is_warned_about() {
        use magbench_env::Control;
        use magbench_env::plant::DisturbancePreset;
        let p = PhysicalParams::default();
        let plan = |alpha: f64| Plan {
            made_for: None,
            flow: Default::default(),
            alpha_max: Some(1.0),
            states: vec![vec![Vec2::zeros(); 3]; 3],
            controls: vec![
                Control::planar(0.1, 0.0, 0.0),
                Control {
                    theta: 0.2,
                    alpha,
                    grad: [0.0, 0.0],
                },
            ],
            durations: vec![1.0, 1.0],
        };
        let interface = DisturbancePreset::hardware().medium;
        let (flat, tilted) = (plan(0.0), plan(-0.6));
        let w = tilt_warning(&interface, &p, [&flat, &tilted].into_iter()).expect("a warning");
        assert!(
            w.starts_with("warning: leg 2 tilts the field to α = 34.4°"),
            "{w}"
        );
        assert!(w.contains("tilts to 0.0° only"), "{w}");
        assert!(w.contains("(2.22 nN·m") && w.contains("(2.09 nN·m)"), "{w}");
        assert!(w.contains("keeps its moment in the plane"), "{w}");
        // no tilt asked, or nothing pins the magnets: no warning
        assert!(tilt_warning(&interface, &p, [&flat].into_iter()).is_none());
        assert!(tilt_warning(&Medium::Bulk, &p, [&tilted].into_iter()).is_none());
    }
}
