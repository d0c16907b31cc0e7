//! Every run's progress trace in memory, without the columns that repeat the run: what the
//! plots and the OMPL log read from `progress.csv`, at a third of its rows' size.

use std::collections::BTreeMap;
use std::path::Path;

use super::store::{PROGRESS, Snapshot};
use crate::Error;
use crate::run::ProgressRow;

/// One point of a run's progress trace.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TracePoint {
    /// Iterations done.
    pub iteration: u64,
    /// Seconds since the start of planning.
    pub time_s: f64,
    /// Best exact-solution cost so far (`None` before the first solution).
    pub best_cost: Option<f64>,
}

/// The progress traces of a results folder, by run index, each in the order of its rows.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Traces(BTreeMap<usize, Vec<TracePoint>>);

impl Traces {
    /// The traces of `rows`.
    pub fn from_rows<'a>(rows: impl IntoIterator<Item = &'a ProgressRow>) -> Self {
        let mut t = Traces::default();
        for r in rows {
            t.push(r);
        }
        t
    }

    /// The traces of the complete rows of the `progress.csv` of `dir`, read one row at a time
    /// (none without the file).
    pub fn read(dir: &Path) -> Result<Self, Error> {
        let mut t = Traces::default();
        if let Some(s) = Snapshot::open(&dir.join(PROGRESS))? {
            for r in s.progress()? {
                t.push(&r?);
            }
        }
        t.0.values_mut().for_each(|v| v.shrink_to_fit());
        Ok(t)
    }

    fn push(&mut self, r: &ProgressRow) {
        self.0.entry(r.run).or_default().push(TracePoint {
            iteration: r.iteration,
            time_s: r.time_s,
            best_cost: r.best_cost,
        });
    }

    /// The trace of run `run` (empty without one).
    pub fn get(&self, run: usize) -> &[TracePoint] {
        self.0.get(&run).map(Vec::as_slice).unwrap_or(&[])
    }

    /// Trace points in all.
    pub fn points(&self) -> usize {
        self.0.values().map(Vec::len).sum()
    }
}
