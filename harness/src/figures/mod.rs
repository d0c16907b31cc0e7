//! The paper figures (`magbench figures`), regenerated from fixed seeds:
//!
//! - `fig1-force-along-path`: the achievable pair force at waypoints of a planned path, the
//!   radial attractive and repulsive parts shaded and the transverse directions marked;
//! - `fig4a-cspace`: the C-space path (x_c, r, φ), planned and tracked;
//! - `fig4b-world`: the world view, planned paths per agent and tracked paths;
//! - `force-ellipse`: the force ellipse in (f_r, f_φ) as ψ sweeps, ψ = ±54.74° marked;
//! - `larc-margin`: the LARC margin against ψ;
//! - `micro-factory`: the micro-factory maze with both agents' planned and tracked paths;
//! - `team-velocity-set`: three agents' achievable side-length rates, field in the plane against
//!   field elevated (an equilateral triangle and an L).
//!
//! Every figure is written as SVG (vector, for publication) and PNG.

pub mod cspace;
pub mod data;
pub mod forces;
pub mod larc;
pub mod team;

use std::path::{Path, PathBuf};

use crate::Error;
use crate::plot::world::WorldPlot;
use crate::plot::{save, with_ext};
use data::{FigureRun, TrackedRun, plan_and_track};

use crate::registry::Registry;

/// The fixed runs behind the figures.
pub const OPEN_FIELD: FigureRun<'static> = FigureRun {
    scenario: "open-field",
    planner: ("goal-zoom-rrt", &[]),
    iterations: 3000,
    tracker: "obc",
    preset: "realistic",
    seed: 0,
};

/// The micro-factory run (`iterations` may be overridden).
pub const MICRO_FACTORY: FigureRun<'static> = FigureRun {
    scenario: "micro-factory",
    planner: ("goal-zoom-rrt", &[]),
    iterations: 200_000,
    tracker: "obc",
    preset: "realistic",
    seed: 1,
};

fn world_fig(run: &TrackedRun, title: String) -> WorldPlot<'_> {
    let mut p = WorldPlot::scenario(&run.scenario);
    let n = run.scenario.agents();
    p.planned = (0..n).map(|i| run.planned_path(i)).collect();
    p.tracked = (0..n).map(|i| run.tracked_path(i)).collect();
    p.title = Some(title);
    p
}

/// Writes every figure into `out`; returns the files written. `maze_iterations` overrides the
/// micro-factory planner's iteration limit; the planner and tracker come from `registry`.
pub fn write_all(
    out: &Path,
    maze_iterations: Option<u64>,
    registry: &Registry,
    log: &dyn Fn(&str),
) -> Result<Vec<PathBuf>, Error> {
    let mut files = vec![];
    let mut add = |v: Vec<PathBuf>| files.extend(v);
    log("force-ellipse, larc-margin");
    add(save(&forces::ForceEllipse, &out.join("force-ellipse"))?);
    add(save(
        &larc::LarcFigure {
            separations: vec![1.5, 2.0, 3.0],
        },
        &out.join("larc-margin"),
    )?);
    log("team-velocity-set");
    add(save(
        &team::TeamVelocityFigure { side: 2.5 },
        &out.join("team-velocity-set"),
    )?);

    log("open-field: plan (goal-zoom-rrt, seed 0) and track (obc, realistic)");
    let run = plan_and_track(&OPEN_FIELD, registry)?;
    let kappa = run.scenario.physics.kappa();
    let n = run.plan_samples.len();
    let waypoints: Vec<[magbench_env::Vec2; 2]> = (1..=7)
        .map(|k| k * (n - 1) / 8)
        .map(|k| [run.plan_samples[k].1[0], run.plan_samples[k].1[1]])
        .collect();
    let r_min = waypoints
        .iter()
        .map(|w| (w[1] - w[0]).norm())
        .fold(f64::INFINITY, f64::min);
    let fig1 = forces::ForceAlongPath {
        world: &run.scenario.world,
        planned: (0..2).map(|i| run.planned_path(i)).collect(),
        waypoints,
        kappa,
        scale: 2.5 / (2.0 * kappa / r_min.powi(4)),
        starts: run.scenario.start.clone(),
        goals: run.scenario.legs.iter().map(|l| l.goal.clone()).collect(),
        title: "Achievable pair force along a planned path (open-field)".into(),
    };
    add(save(&fig1, &out.join("fig1-force-along-path"))?);
    let cs = cspace::CSpaceFigure {
        title: "C-space path (x_c, r, φ), planned and tracked (open-field)".into(),
        note: format!("{}, RMS error {:.3} BL", run.label, run.rms_error),
        planned: cspace::local_path(&run.plan_samples),
        tracked: cspace::local_path(&run.tracked),
    };
    add(save(&cs, &out.join("fig4a-cspace"))?);
    add(save(
        &world_fig(&run, format!("open-field: {}", run.label)),
        &out.join("fig4b-world"),
    )?);

    let maze = FigureRun {
        iterations: maze_iterations.unwrap_or(MICRO_FACTORY.iterations),
        ..MICRO_FACTORY
    };
    log(&format!(
        "micro-factory: plan (goal-zoom-rrt, seed {}, up to {} iterations) and track (obc, realistic)",
        maze.seed, maze.iterations
    ));
    let run = plan_and_track(&maze, registry)?;
    let title = format!(
        "micro-factory: {}{}",
        run.label,
        if run.reached_goal {
            ", goal reached"
        } else {
            ", goal not reached"
        }
    );
    add(save(&world_fig(&run, title), &out.join("micro-factory"))?);
    Ok(files)
}

/// The SVG of each figure (for listings).
pub fn svgs(files: &[PathBuf]) -> Vec<&PathBuf> {
    files
        .iter()
        .filter(|f| f.extension().is_some_and(|e| e == "svg"))
        .collect()
}

/// `stem.svg`.
pub fn svg_of(stem: &Path) -> PathBuf {
    with_ext(stem, "svg")
}
