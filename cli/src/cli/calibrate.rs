//! `magbench calibrate`: fits a preset to logged rig runs and writes it as a preset file.

use std::path::PathBuf;

use clap::{Args, Subcommand};
use magbench_drivers::fit::{FitError, FitOptions, calibrate, read_log};
use magbench_drivers::rigs::preset_named;
use magbench_env::Scenario;
use magbench_env::input::Bound;

use super::calibrate_plot::MotionFigure;
use crate::Error;
use crate::output::{outln, prepare_file};
use crate::registry::Registry;

/// `magbench calibrate`: a fit of logged runs, or `calibrate bench`.
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct CalibrateArgs {
    /// `bench`: the fit evaluated over random rigs (a log folder named `bench` is `./bench`).
    #[command(subcommand)]
    pub cmd: Option<CalibrateCmd>,
    /// Logged runs: folders holding rig-log.csv (from `rig run` or `rig excite`) or the CSV
    /// files themselves.
    #[arg(required = true)]
    pub logs: Vec<PathBuf>,
    /// The scenario the runs were made on (physics, workspace, agent count).
    #[arg(long, required = true)]
    pub scenario: Option<String>,
    /// The preset fitted: a built-in name or a preset file; what is not fitted keeps its value.
    #[arg(long, default_value = "hardware")]
    pub base: String,
    /// The fitted preset file.
    #[arg(long, required = true)]
    pub out: Option<PathBuf>,
    /// Frames per segment the fit predicts, each from a start state of its own.
    #[arg(long, default_value_t = magbench_drivers::fit::SEGMENT_FRAMES)]
    pub segment_frames: usize,
    /// Largest camera latency the fit may take (frames, fitted as a continuous number).
    #[arg(long, default_value_t = 4)]
    pub max_latency: usize,
    /// Hold a parameter at the base value, e.g. `gradient_gain.x` (repeatable).
    #[arg(long)]
    pub hold: Vec<String>,
}

/// What `magbench calibrate` can do besides a fit.
#[derive(Debug, Subcommand)]
pub enum CalibrateCmd {
    /// Evaluate `calibrate` over random rigs: excite and fit each, score every parameter
    /// against its truth; write a CSV, a summary table and a figure.
    Bench(super::calibrate_bench::BenchArgs),
}

/// Runs `magbench calibrate` (or `calibrate bench`).
pub fn run(a: CalibrateArgs, registry: &Registry) -> Result<(), Error> {
    if let Some(CalibrateCmd::Bench(b)) = a.cmd {
        return super::calibrate_bench::run(b, registry);
    }
    // clap requires both without a subcommand
    let scenario = a.scenario.as_deref().unwrap_or_default();
    let out = a.out.clone().unwrap_or_default();
    let scenario = Scenario::load(scenario)?;
    let base = preset_named(&a.base, "--base")?;
    for (name, bound, v) in [
        ("--segment-frames", SEGMENT_FRAMES, a.segment_frames),
        ("--max-latency", MAX_LATENCY, a.max_latency),
    ] {
        bound
            .check_count(name, v as u64)
            .map_err(|r| Error::arg(name, r.reason))?;
    }
    prepare_file(&out, "--out")?;
    let runs = a
        .logs
        .iter()
        .map(|p| read_log(p, scenario.agents()).map_err(Error::Input))
        .collect::<Result<Vec<_>, _>>()?;
    let sources: Vec<String> = runs.iter().map(|r| r.source.clone()).collect();
    let opts = FitOptions {
        segment_frames: a.segment_frames,
        max_latency: a.max_latency,
        hold: a.hold,
        ..FitOptions::default()
    };
    let mut fit = calibrate(&scenario, &base, runs, &opts).map_err(|e| match e {
        FitError::Input(i) => Error::Input(i),
        e @ FitError::NoSegments(_) => Error::arg("LOG_DIR", e.to_string()),
    })?;
    fit.preset.name = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "fitted".into());
    fit.preset.description = format!("{} fitted to {}", base.name, sources.join(", "));
    for l in fit.lines() {
        outln!("{l}");
    }
    std::fs::write(&out, fit.preset_file(&sources))
        .map_err(|e| Error::Failed(format!("{}: {e}", out.display())))?;
    outln!("preset       {}", out.display());
    let stem = out.with_extension("motion");
    let files = crate::plot::save(&MotionFigure::new(&fit.traces), &stem)?;
    for f in files {
        outln!("report       {}", f.display());
    }
    Ok(())
}

/// Frames one prediction may span: 10 s of a 60 fps camera (a longer prediction from one
/// observation drifts beyond what the fit can follow).
pub(super) const SEGMENT_FRAMES: Bound = Bound::closed(
    1.0,
    600.0,
    " frames",
    "10 s at 60 fps; a longer prediction drifts beyond what one observation pins",
);

/// Latencies the fit may take: every half frame up to it starts a quick fit of its own; 30
/// frames is half a second at 60 fps, far beyond any camera pipeline.
const MAX_LATENCY: Bound = Bound::closed(
    0.0,
    30.0,
    " frames",
    "each candidate is a fit of its own; half a second at 60 fps",
);
