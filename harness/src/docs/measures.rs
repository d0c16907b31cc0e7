//! The measurements of the book: each an experiment in `experiments/` and the table its runs
//! become. Adding one is one entry here and its `{{#include measured/NAME.md}}` in a chapter.

use std::path::Path;

use super::ablation::ablation;
use super::convergence::convergence;
use super::replans::replan_latency;
use super::table::Table;
use super::tables::{errors, first_solution, planning, tracking};
use crate::CliError;
use crate::run::{RunOutput, RunRecord};
use Kind::{Folder, Outputs, Runs};

/// How a measurement's runs become its table.
#[derive(Debug, Clone, Copy)]
pub enum Kind {
    /// A sweep of the experiment; the table comes from its `runs.csv` rows.
    Runs(fn(&[RunRecord]) -> Table),
    /// A sweep of the experiment; the table comes from its results folder (`progress.csv` as
    /// well as the `runs.csv` rows, given).
    Folder(fn(&Path, &[RunRecord]) -> Result<Table, CliError>),
    /// The experiment's runs, each run's whole output kept (its replan log too); no results
    /// folder is written.
    Outputs(fn(&[RunOutput]) -> Table),
}

/// One measurement: `magbench docs measure --only NAME` writes `docs/measured/NAME.md`.
#[derive(Debug, Clone, Copy)]
pub struct Measure {
    /// The file's stem.
    pub name: &'static str,
    /// The experiment run, relative to the repository root.
    pub experiment: &'static str,
    /// Seeds kept under `--quick` (the first ones of the experiment's).
    pub quick_seeds: usize,
    /// How the runs become the file's table.
    pub table: Kind,
    /// The cargo feature of `magbench` its planners need (`None`: the default build has them).
    pub feature: Option<&'static str>,
}

impl Measure {
    /// Whether this build can run it: it needs no feature, or the build has that feature.
    pub fn available(&self) -> bool {
        match self.feature {
            None => true,
            Some("ompl") => cfg!(feature = "ompl"),
            Some(_) => false,
        }
    }
}

/// Every measurement, in the order `docs measure` runs them.
pub static MEASURES: &[Measure] = &[
    Measure {
        name: "planners-success",
        experiment: "experiments/planners-success.toml",
        quick_seeds: 4,
        table: Runs(planning),
        feature: None,
    },
    Measure {
        name: "trackers-50",
        experiment: "experiments/trackers-50.toml",
        quick_seeds: 3,
        table: Runs(tracking),
        feature: None,
    },
    Measure {
        name: "cargo-delivery",
        experiment: "experiments/cargo-delivery.toml",
        quick_seeds: 2,
        table: Runs(tracking),
        feature: None,
    },
    Measure {
        name: "seed-metric",
        experiment: "experiments/seed-metric.toml",
        quick_seeds: 4,
        table: Runs(errors),
        feature: None,
    },
    Measure {
        name: "fidelity-hardware",
        experiment: "experiments/fidelity-hardware.toml",
        quick_seeds: 3,
        table: Runs(tracking),
        feature: None,
    },
    Measure {
        name: "fidelity-short",
        experiment: "experiments/fidelity-short.toml",
        quick_seeds: 4,
        table: Runs(tracking),
        feature: None,
    },
    Measure {
        name: "trio-planning",
        experiment: "experiments/trio-planning.toml",
        quick_seeds: 2,
        table: Runs(planning),
        feature: None,
    },
    Measure {
        name: "trio-tracking",
        experiment: "experiments/trio-tracking.toml",
        quick_seeds: 1,
        table: Runs(tracking),
        feature: None,
    },
    Measure {
        name: "quad-tracking",
        experiment: "experiments/quad-tracking.toml",
        quick_seeds: 2,
        table: Runs(tracking),
        feature: None,
    },
    Measure {
        name: "planners-convergence",
        experiment: "experiments/planners-convergence.toml",
        quick_seeds: 2,
        table: Folder(convergence),
        feature: None,
    },
    Measure {
        name: "informed",
        experiment: "experiments/informed.toml",
        quick_seeds: 2,
        table: Folder(convergence),
        feature: None,
    },
    Measure {
        name: "replan-latency",
        experiment: "experiments/replan.toml",
        quick_seeds: 2,
        table: Outputs(replan_latency),
        feature: None,
    },
    Measure {
        name: "vs-ompl",
        experiment: "experiments/vs-ompl.toml",
        quick_seeds: 2,
        table: Runs(first_solution),
        feature: Some("ompl"),
    },
    Measure {
        name: "ablation-obc",
        experiment: "experiments/ablation-obc.toml",
        quick_seeds: 1,
        table: Runs(ablation),
        feature: None,
    },
    Measure {
        name: "ablation-lookahead",
        experiment: "experiments/ablation-lookahead.toml",
        quick_seeds: 1,
        table: Runs(ablation),
        feature: None,
    },
    Measure {
        name: "ablation-open-loop",
        experiment: "experiments/ablation-open-loop.toml",
        quick_seeds: 2,
        table: Runs(ablation),
        feature: None,
    },
];

/// The measurement called `name`.
pub fn find(name: &str) -> Option<&'static Measure> {
    MEASURES.iter().find(|m| m.name == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_experiments_exist() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        for (i, m) in MEASURES.iter().enumerate() {
            assert!(root.join(m.experiment).is_file(), "{}", m.experiment);
            assert!(m.quick_seeds > 0, "{}", m.name);
            assert!(
                MEASURES[..i].iter().all(|o| o.name != m.name),
                "{} twice",
                m.name
            );
        }
        assert!(find("seed-metric").is_some() && find("nope").is_none());
        assert!(find("seed-metric").unwrap().available());
        assert_eq!(find("vs-ompl").unwrap().available(), cfg!(feature = "ompl"));
    }
}
