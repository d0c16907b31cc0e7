//! `difficulty.csv` of a results folder: one row per scenario with its difficulty measures
//! (`magbench_env::scenario::difficulty`), the x axes of the plots against difficulty.

use std::path::Path;
use std::sync::Arc;

use magbench_env::scenario::Scenario;
use magbench_env::scenario::difficulty::{COLUMNS, measure};

use crate::CliError;

/// The file name in a results folder.
pub const FILE: &str = "difficulty.csv";

/// Difficulty measures by scenario: the columns of [`COLUMNS`], empty where undefined.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Table {
    /// `(scenario label, one value per column of COLUMNS)`.
    pub rows: Vec<(String, Vec<Option<f64>>)>,
}

impl Table {
    /// The values of column `c` (an index into [`COLUMNS`]) for scenario `label`.
    pub fn value(&self, label: &str, c: usize) -> Option<f64> {
        self.rows
            .iter()
            .find(|(l, _)| l == label)
            .and_then(|(_, v)| v.get(c).copied().flatten())
    }
}

/// Measures every scenario and writes `dir/difficulty.csv`.
pub fn write(dir: &Path, scenarios: &[(String, Arc<Scenario>)]) -> Result<(), CliError> {
    let path = dir.join(FILE);
    let fail = |e: &dyn std::fmt::Display| CliError::Failed(format!("{}: {e}", path.display()));
    let mut w = csv::Writer::from_writer(vec![]);
    let mut header = vec!["scenario"];
    header.extend(COLUMNS);
    w.write_record(&header).map_err(|e| fail(&e))?;
    for (label, sc) in scenarios {
        let mut row = vec![label.clone()];
        row.extend(measure(sc).columns().into_iter().map(|(_, v)| v));
        w.write_record(&row).map_err(|e| fail(&e))?;
    }
    let bytes = w.into_inner().map_err(|e| fail(&e))?;
    std::fs::write(&path, bytes).map_err(|e| fail(&e))
}

/// Reads `dir/difficulty.csv`; an empty table when the folder has none.
pub fn read(dir: &Path) -> Result<Table, CliError> {
    let path = dir.join(FILE);
    let Ok(text) = std::fs::read_to_string(&path) else {
        return Ok(Table::default());
    };
    let bad = |what: String| CliError::Failed(format!("{}: {what}", path.display()));
    let mut r = csv::Reader::from_reader(text.as_bytes());
    let header = r.headers().map_err(|e| bad(e.to_string()))?.clone();
    let index: Vec<Option<usize>> = COLUMNS
        .iter()
        .map(|c| header.iter().position(|h| h == *c))
        .collect();
    let mut rows = vec![];
    for rec in r.records() {
        let rec = rec.map_err(|e| bad(e.to_string()))?;
        let values = index
            .iter()
            .map(|i| i.and_then(|i| rec.get(i)).and_then(|v| v.parse().ok()))
            .collect();
        rows.push((rec.get(0).unwrap_or_default().to_string(), values));
    }
    Ok(Table { rows })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_the_measures_of_a_builtin() {
        let dir = tempfile::tempdir().unwrap();
        let sc = Scenario::load("narrow-passage").unwrap();
        write(dir.path(), &[("narrow-passage".into(), Arc::new(sc))]).unwrap();
        let t = read(dir.path()).unwrap();
        assert_eq!(t.rows.len(), 1);
        let c = COLUMNS
            .iter()
            .position(|c| *c == "narrowest_passage_bl")
            .unwrap();
        let v = t.value("narrow-passage", c).unwrap();
        assert!((v - 3.0).abs() < 0.25, "{v}");
        assert!(t.value("other", c).is_none());
    }
}
