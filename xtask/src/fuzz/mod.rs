//! The input formats under fuzzing: scenario, experiment, rig and plan files, each through the
//! parser and validator a command runs on it.
//!
//! [`Target::run`] takes raw bytes (read as a file would be: invalid UTF-8 replaced) and must
//! return for every input — an `Err` is a fine answer, a panic, an abort or a hang is a bug.
//! Two drivers use it: the `cargo fuzz` targets in `fuzz/` (nightly, coverage-guided), and
//! the deterministic mutation test `cli/tests/integration/mutation.rs` (stable, in CI), which mutates
//! [`Target::seeds`] with [`mutate`]. `cli/tests/integration/mutation_commands.rs` then runs the
//! commands that use each accepted mutant ([`Target::commands`]) under a time and memory cap.

pub mod commands;
pub mod mutate;

use std::path::Path;
use std::sync::OnceLock;

use magbench_env::{InputError, Scenario};

use magbench::experiment::Experiment;
use magbench::run::real::RealExecutor;

pub use commands::stlc_command;
pub use mutate::mutate;

/// One input format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// Scenario TOML: parse and validate.
    Scenario,
    /// Experiment TOML: parse and validate (scenarios resolved, planners and trackers checked).
    Experiment,
    /// Rig TOML: parse and validate.
    Rig,
    /// Plan JSON: parse, then validate for open-field (replay included).
    Plan,
    /// Disturbance preset TOML: parse and validate.
    Preset,
}

impl Target {
    /// Every target.
    pub const ALL: [Target; 5] = [
        Target::Scenario,
        Target::Experiment,
        Target::Rig,
        Target::Plan,
        Target::Preset,
    ];

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            Target::Scenario => "scenario",
            Target::Experiment => "experiment",
            Target::Rig => "rig",
            Target::Plan => "plan",
            Target::Preset => "preset",
        }
    }

    /// The target of that name.
    pub fn by_name(name: &str) -> Option<Target> {
        Target::ALL.into_iter().find(|t| t.name() == name)
    }

    /// Parses and validates `data`; `Ok` when the input was accepted, else the input error a
    /// command would report. Data larger than the format's files may be is refused, as reading
    /// such a file is.
    pub fn run(self, data: &[u8]) -> Result<(), InputError> {
        let file = format!(
            "fuzz.{}",
            if self == Target::Plan { "json" } else { "toml" }
        );
        let max = magbench_env::input::file::MAX_INPUT_BYTES;
        if data.len() as u64 > max {
            return Err(InputError::new(
                file,
                "",
                format!("cannot read: larger than {} KiB", max >> 10),
            ));
        }
        let text = String::from_utf8_lossy(data);
        match self {
            Target::Scenario => magbench_env::scenario::parse_scenario(&text, &file).map(|_| ()),
            Target::Experiment => Experiment::parse(
                &text,
                &file,
                Path::new("."),
                "fuzz",
                &RealExecutor::default(),
            )
            .map(|_| ()),
            Target::Rig => magbench_drivers::RigConfig::parse(&text, &file).map(|_| ()),
            Target::Preset => {
                magbench_env::plant::DisturbancePreset::parse(&text, &file).map(|_| ())
            }
            Target::Plan => {
                let s = open_field();
                let plan = magbench_trackers::plan_file::parse_plan(&text, &file, s.agents())?;
                magbench_trackers::plan_file::check_plan(
                    &plan,
                    s,
                    &file,
                    &magbench_planners::PlanningSetup::default(),
                )
            }
        }
    }

    /// Valid inputs to start from: every built-in scenario, every experiment file of the
    /// repository, the example rig file, a planned open-field plan, and the built-in presets.
    pub fn seeds(self) -> Vec<String> {
        match self {
            Target::Scenario => magbench_env::scenario::builtin_names()
                .iter()
                .map(|n| {
                    magbench_env::scenario::builtin_source(n)
                        .expect("a built-in")
                        .to_string()
                })
                .collect(),
            Target::Experiment => [
                include_str!("../../../experiments/ci.toml"),
                include_str!("../../../experiments/default.toml"),
                include_str!("../../../experiments/trackers.toml"),
                include_str!("../../../experiments/cargo-delivery.toml"),
                include_str!("../../../experiments/informed.toml"),
                include_str!("../../../experiments/planners-success.toml"),
            ]
            .map(String::from)
            .to_vec(),
            Target::Rig => vec![include_str!("../../../rigs/emulator.toml").to_string()],
            Target::Plan => vec![plan_seed().to_string()],
            Target::Preset => magbench_env::plant::DisturbancePreset::NAMES
                .iter()
                .map(|n| {
                    magbench_env::plant::DisturbancePreset::builtin_text(n)
                        .expect("a built-in")
                        .to_string()
                })
                .collect(),
        }
    }
}

/// The scenario plans are checked against.
fn open_field() -> &'static Scenario {
    static S: OnceLock<Scenario> = OnceLock::new();
    S.get_or_init(|| Scenario::load("open-field").expect("a built-in"))
}

/// A plan of open-field from the seed's planner (deterministic: an iteration limit).
fn plan_seed() -> &'static str {
    static P: OnceLock<String> = OnceLock::new();
    P.get_or_init(|| {
        let s = open_field();
        let mut planner = magbench_planners::Planners::builtin()
            .create("goal-zoom-rrt", &[])
            .expect("a planner");
        let mut problem = magbench_planners::Problem::from_scenario(s, 0, None, 0);
        problem.limits = magbench_planners::Limits {
            max_iterations: Some(3000),
            time_limit: None,
        };
        let plan = planner.solve(&problem).plan;
        magbench_trackers::plan_file::plan_json(&plan)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_seed_is_accepted() {
        for t in Target::ALL {
            let seeds = t.seeds();
            assert!(!seeds.is_empty());
            for s in seeds {
                t.run(s.as_bytes())
                    .unwrap_or_else(|e| panic!("{}: a seed is refused: {e}", t.name()));
            }
        }
    }
}
