//! The metric table: every per-run metric declared once ([`table`]), with its name, unit,
//! direction, per-run computation, aggregation, CSV column, plot, report column, OMPL
//! property and whether `regress` gates it.
//!
//! Everything that lists metrics iterates over [`Metric::ALL`]: the executor fills a run's
//! [`Values`] through each entry's [`Compute`], `runs.csv` writes and reads one column per
//! entry, and the summaries, `regress`, the plots, the report and `ompl.log` take their lists
//! from the table. Adding a metric is one entry in [`table`] and its computation (see
//! `docs/results.md`, "The metric table").
//!
//! [`difficulty`] is the same kind of table for the difficulty measures of a run's scenario.

pub mod difficulty;
pub mod path;
pub mod slot;
mod table;
mod values;

pub use table::{Metric, TABLE};
pub use values::{PathFacts, PlanFacts, TrackFacts, Values};

/// Which way is better.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Smaller values are better (errors, times, costs).
    Lower,
    /// Larger values are better (clearances, margins).
    Higher,
}

/// How a configuration's runs are summarised (report, summaries).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Aggregation {
    /// Median with the interquartile range, over the runs that have a value.
    Median,
    /// The sum over the runs (event counts).
    Sum,
}

/// What `regress` does with a metric.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Regress {
    /// Compared, and a regression fails the check.
    Gated,
    /// A wall-clock time: compared with the time tolerance, failing the check only with
    /// `--gate-time` (machines differ).
    WallClock,
    /// Compared and shown, never failing the check.
    Shown,
    /// Not compared.
    Off,
}

/// How a run's value is computed: from which facts of the run.
#[derive(Clone, Copy)]
pub enum Compute {
    /// From the planner's results (every run that planned).
    Plan(fn(&PlanFacts) -> Option<f64>),
    /// From the plan and the world (every run with a plan of at least one edge).
    Path(fn(&PathFacts) -> Option<f64>),
    /// From the tracking loop (tracked runs).
    Track(fn(&TrackFacts) -> Option<f64>),
}

impl std::fmt::Debug for Compute {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Compute::Plan(_) => "Plan",
            Compute::Path(_) => "Path",
            Compute::Track(_) => "Track",
        })
    }
}

/// A box plot of a metric: one box per configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Plot {
    /// File stem under `plots/<scenario>/`.
    pub stem: &'static str,
    /// Title after `<scenario>: `.
    pub title: &'static str,
    /// Drawn even when no run has a value (otherwise left out).
    pub always: bool,
}

/// One metric's declaration.
#[derive(Debug, Clone, Copy)]
pub struct Def {
    /// The `runs.csv` column, also the name `regress` shows.
    pub column: &'static str,
    /// Short human name (report column, plot axis).
    pub label: &'static str,
    /// Unit (`BL`, `s`, `rad`, ...; empty for counts).
    pub unit: &'static str,
    /// Which way is better.
    pub direction: Direction,
    /// The per-run computation.
    pub compute: Compute,
    /// The per-configuration summary.
    pub aggregation: Aggregation,
    /// What `regress` does with it.
    pub regress: Regress,
    /// A wall-clock time: it differs between two executions of the same run.
    pub wall_clock: bool,
    /// Its box plot, if any.
    pub plot: Option<Plot>,
    /// Digits of its report column; `None`: not in the report's table.
    pub report: Option<usize>,
    /// The OMPL run property (name and type, e.g. `best cost REAL`), if any.
    pub ompl: Option<&'static str>,
    /// The definition (the entry's doc comment).
    pub doc: &'static str,
}

impl Def {
    /// A metric with a median summary, not compared by `regress`, without plot, report column
    /// or OMPL property.
    pub const fn new(
        column: &'static str,
        label: &'static str,
        unit: &'static str,
        direction: Direction,
        compute: Compute,
    ) -> Def {
        Def {
            column,
            label,
            unit,
            direction,
            compute,
            aggregation: Aggregation::Median,
            regress: Regress::Off,
            wall_clock: false,
            plot: None,
            report: None,
            ompl: None,
            doc: "",
        }
    }

    /// With `regress` handling `r` (a [`Regress::WallClock`] metric is a wall-clock time).
    pub const fn regress(self, r: Regress) -> Def {
        Def {
            regress: r,
            wall_clock: self.wall_clock || matches!(r, Regress::WallClock),
            ..self
        }
    }

    /// A wall-clock time (left out where two executions of a run are compared).
    pub const fn wall_clock(self) -> Def {
        Def {
            wall_clock: true,
            ..self
        }
    }

    /// Summarised by `a`.
    pub const fn aggregate(self, a: Aggregation) -> Def {
        Def {
            aggregation: a,
            ..self
        }
    }

    /// With a box plot.
    pub const fn plot(self, stem: &'static str, title: &'static str, always: bool) -> Def {
        Def {
            plot: Some(Plot {
                stem,
                title,
                always,
            }),
            ..self
        }
    }

    /// With a report column of `digits` digits.
    pub const fn report(self, digits: usize) -> Def {
        Def {
            report: Some(digits),
            ..self
        }
    }

    /// With the OMPL run property `p`.
    pub const fn ompl(self, p: &'static str) -> Def {
        Def {
            ompl: Some(p),
            ..self
        }
    }

    /// With the definition `doc`.
    pub const fn doc(self, doc: &'static str) -> Def {
        Def { doc, ..self }
    }

    /// True for a metric of the tracking loop (only tracked runs have it).
    pub fn tracking(&self) -> bool {
        matches!(self.compute, Compute::Track(_))
    }

    /// `label (unit)`, or the label of a unitless metric: a plot axis or report header.
    pub fn axis(&self) -> String {
        if self.unit.is_empty() {
            self.label.to_string()
        } else {
            format!("{} ({})", self.label, self.unit)
        }
    }
}

impl Metric {
    /// Its declaration.
    pub fn def(self) -> &'static Def {
        &TABLE[self as usize]
    }

    /// The metric of CSV column `column`.
    pub fn by_column(column: &str) -> Option<Metric> {
        Metric::ALL
            .iter()
            .copied()
            .find(|m| m.def().column == column)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_are_unique_and_every_entry_documented() {
        let mut seen = std::collections::BTreeSet::new();
        for m in Metric::ALL {
            let d = m.def();
            assert!(seen.insert(d.column), "column {} twice", d.column);
            assert!(!d.doc.trim().is_empty(), "{} has no doc", d.column);
            assert_eq!(Metric::by_column(d.column), Some(*m));
        }
        assert_eq!(Metric::ALL.len(), TABLE.len());
    }

    #[test]
    fn ompl_properties_have_a_type_and_are_unique() {
        let mut seen = std::collections::BTreeSet::new();
        for m in Metric::ALL {
            if let Some(p) = m.def().ompl {
                assert!(
                    p.ends_with(" REAL") || p.ends_with(" INTEGER") || p.ends_with(" BOOLEAN"),
                    "{p}"
                );
                assert!(seen.insert(p), "{p} twice");
            }
        }
    }

    #[test]
    fn every_column_is_named_in_the_docs() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/results.md");
        let text = std::fs::read_to_string(path).unwrap();
        for m in Metric::ALL {
            let c = m.def().column;
            let tracking = m.def().tracking();
            // the tracking metrics are defined in docs/tracking.md and named there
            assert!(
                tracking || text.contains(&format!("`{c}`")),
                "docs/results.md does not name `{c}`"
            );
        }
    }
}
