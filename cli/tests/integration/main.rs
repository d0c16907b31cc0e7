//! The command line's integration tests, a module per file, in one binary.
//!
//! Cargo runs test binaries one after another; in one binary the tests of every file share
//! the test threads, so a file whose tests wait (on Slurm, a browser, a child process) no
//! longer holds a core idle. Run one file's tests with a filter:
//! `cargo test -p magbench --test integration FILE::`.
//!
//! `calibrate.rs` and `calibrate_bench_segments.rs` stay binaries of their own because
//! `cargo xtask measure` runs them by name, `plugin_crate.rs` because `.ci/run` runs it after
//! the others, and `rig_emulator.rs` because its lockstep emulators need the cores to
//! themselves (its module docs).

#[path = "../common/mod.rs"]
mod common;
#[path = "../slurm/mod.rs"]
mod slurm;

mod bad_input;
mod bench_cli;
mod bench_fake;
mod bench_kill;
mod bench_mixed;
mod bench_real;
mod bounded_input;
mod calibrate_bench;
mod cli_preset;
mod cli_scenario;
mod cli_track;
mod difficulty_columns;
mod docs_links;
mod figures;
mod labels_cli;
mod mutation;
mod mutation_commands;
mod ompl_log;
mod pipeline;
mod plan_cli;
mod plannerarena;
mod plot_world;
mod plugin_rig;
mod readme_examples;
mod regress_baseline;
mod regress_cli;
mod replay_browser;
mod replays;
mod report_agents;
mod results_crash;
mod results_formations;
mod results_scaling;
mod rig_cli;
mod scenario_generate;
mod slurm_array;
mod slurm_scale;
