//! Command-line interface: one file per subcommand.

mod ablate;
mod bench;
mod calibrate;
mod calibrate_bench;
mod calibrate_bench_plot;
mod calibrate_plot;
mod figures;
mod label;
mod merge;
mod number;
mod plan;
mod plan_and_track;
mod preset;
mod profile;
mod progress;
mod regress;
mod results;
mod rig;
mod scenario;
mod setup;
mod stlc;
mod suite;
mod track;

use clap::{Parser, Subcommand};

use crate::Error;
use crate::registry::Registry;

/// magbench: plan, track and benchmark paths for teams of magnetic microrobots steered by one
/// global magnetic field.
///
/// Lengths are in body lengths (BL, one agent diameter), times in seconds. Scenarios are
/// built-in names (see `magbench scenario list`) or TOML files.
#[derive(Debug, Parser)]
#[command(name = "magbench", version, about, long_about)]
pub struct Args {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// List, show or check scenario files.
    #[command(subcommand)]
    Scenario(scenario::ScenarioCmd),
    /// List, show or check disturbance presets of the simulated plant.
    #[command(subcommand)]
    Preset(preset::PresetCmd),
    /// Small-time local controllability: the Lie-bracket rank test over ψ at separation r.
    Stlc(stlc::StlcArgs),
    /// Plan a scenario with one planner; report the result or write plan, trace and plot.
    Plan(plan::PlanArgs),
    /// Run an experiment (default experiments/default.toml) into results/<name>/.
    Bench(bench::BenchArgs),
    /// Ablate the plant: a tracker under a preset with each term off in turn and each alone.
    Ablate(ablate::AblateArgs),
    /// Join the results folders of shards (`bench --shard I/N`) into one.
    Merge(merge::MergeArgs),
    /// Compare a results folder against a baseline: regression, ok or inconclusive per metric.
    Regress(regress::RegressArgs),
    /// Check results folders (`results verify DIR`); fit scaling exponents (`results scaling`);
    /// print the comparison across problems (`results profile`).
    #[command(subcommand)]
    Results(results::ResultsCmd),
    /// Check or freeze the problem suites in suites/ (`bench --suite NAME` runs one).
    #[command(subcommand)]
    Suite(suite::SuiteCmd),
    /// Regenerate the paper figures (SVG and PNG) from fixed seeds.
    Figures(figures::FiguresArgs),
    /// Plan, then track the plan in closed loop against the simulated plant; report metrics.
    Track(Box<track::TrackArgs>),
    /// Physical runs: the rig emulator, rig bring-up checks and detection replay.
    #[command(subcommand)]
    Rig(rig::RigCmd),
    /// Fit a preset's parameters to logged rig runs (`rig run`, `rig excite`); `calibrate
    /// bench` evaluates the fit over random rigs.
    Calibrate(calibrate::CalibrateArgs),
}

/// Runs a parsed command line; planners and trackers are resolved by name in `registry`.
pub fn run(args: Args, registry: &Registry) -> Result<(), Error> {
    match args.command {
        Command::Scenario(c) => scenario::run(c),
        Command::Preset(c) => preset::run(c),
        Command::Stlc(a) => stlc::run(a),
        Command::Bench(a) => bench::run(a, registry),
        Command::Merge(a) => merge::run(a),
        Command::Ablate(a) => ablate::run(a, registry),
        Command::Regress(a) => regress::run(a),
        Command::Results(c) => results::run(c),
        Command::Suite(c) => suite::run(c),
        Command::Figures(a) => figures::run(a, registry),
        Command::Track(a) => track::run(*a, registry),
        Command::Plan(a) => plan::run(a, registry),
        Command::Rig(c) => rig::run(c, registry),
        Command::Calibrate(a) => calibrate::run(a, registry),
    }
}
