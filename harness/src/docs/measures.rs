//! The measurements of the book: each an experiment in `experiments/` and the table its runs
//! become. Adding one is one entry here and its `{{#include measured/NAME.md}}` in a chapter.

use super::ablation::ablation;
use super::table::Table;
use super::tables::{errors, planning, tracking};
use crate::run::RunRecord;

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
    pub table: fn(&[RunRecord]) -> Table,
}

/// Every measurement, in the order `docs measure` runs them.
pub static MEASURES: &[Measure] = &[
    Measure {
        name: "planners-success",
        experiment: "experiments/planners-success.toml",
        quick_seeds: 4,
        table: planning,
    },
    Measure {
        name: "trackers-50",
        experiment: "experiments/trackers-50.toml",
        quick_seeds: 3,
        table: tracking,
    },
    Measure {
        name: "cargo-delivery",
        experiment: "experiments/cargo-delivery.toml",
        quick_seeds: 2,
        table: tracking,
    },
    Measure {
        name: "seed-metric",
        experiment: "experiments/seed-metric.toml",
        quick_seeds: 4,
        table: errors,
    },
    Measure {
        name: "fidelity-hardware",
        experiment: "experiments/fidelity-hardware.toml",
        quick_seeds: 3,
        table: tracking,
    },
    Measure {
        name: "fidelity-short",
        experiment: "experiments/fidelity-short.toml",
        quick_seeds: 4,
        table: tracking,
    },
    Measure {
        name: "trio-planning",
        experiment: "experiments/trio-planning.toml",
        quick_seeds: 2,
        table: planning,
    },
    Measure {
        name: "quad-tracking",
        experiment: "experiments/quad-tracking.toml",
        quick_seeds: 2,
        table: tracking,
    },
    Measure {
        name: "ablation-obc",
        experiment: "experiments/ablation-obc.toml",
        quick_seeds: 1,
        table: ablation,
    },
    Measure {
        name: "ablation-lookahead",
        experiment: "experiments/ablation-lookahead.toml",
        quick_seeds: 1,
        table: ablation,
    },
    Measure {
        name: "ablation-open-loop",
        experiment: "experiments/ablation-open-loop.toml",
        quick_seeds: 2,
        table: ablation,
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
    }
}
