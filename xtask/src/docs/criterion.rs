//! Criterion's results on disk: each benchmark's `new/benchmark.json` (its id) and
//! `new/estimates.json` (mean, median and their 95% confidence intervals, in ns), and the
//! table a bench measurement makes of them.

use std::path::{Path, PathBuf};

use serde::Deserialize;
use thiserror::Error;

use magbench::table::{Table, num};

/// Why criterion's results could not be read.
#[derive(Debug, Error)]
pub enum EstimatesError {
    /// A file could not be read.
    #[error("{path}: {source}")]
    Read {
        /// The file or folder.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// A file is not criterion's JSON.
    #[error("{path}: {source}")]
    Json {
        /// The file.
        path: PathBuf,
        /// The JSON error.
        source: serde_json::Error,
    },
    /// The bench wrote no results for a benchmark the measurement lists.
    #[error("{home}: no results for benchmark {id:?} (found: {found})")]
    Missing {
        /// Criterion's output folder.
        home: PathBuf,
        /// The benchmark's id.
        id: String,
        /// The ids that have results.
        found: String,
    },
}

/// A confidence interval of an estimate.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub struct Interval {
    /// Its level (0.95).
    pub confidence_level: f64,
    /// Lower end, ns.
    pub lower_bound: f64,
    /// Upper end, ns.
    pub upper_bound: f64,
}

/// One statistic of criterion's `estimates.json`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub struct Estimate {
    /// The estimate, ns.
    pub point_estimate: f64,
    /// Its bootstrap confidence interval.
    pub confidence_interval: Interval,
}

/// The statistics of `estimates.json` a measurement uses (the others are ignored).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub struct Estimates {
    /// Mean time per iteration.
    pub mean: Estimate,
    /// Median time per iteration.
    pub median: Estimate,
}

/// The id part of criterion's `benchmark.json`.
#[derive(Debug, Clone, Deserialize)]
struct BenchmarkJson {
    full_id: String,
}

/// Reads `estimates.json` text.
pub fn parse_estimates(text: &str, path: &Path) -> Result<Estimates, EstimatesError> {
    serde_json::from_str(text).map_err(|source| EstimatesError::Json {
        path: path.to_path_buf(),
        source,
    })
}

fn read(path: &Path) -> Result<String, EstimatesError> {
    std::fs::read_to_string(path).map_err(|source| EstimatesError::Read {
        path: path.to_path_buf(),
        source,
    })
}

/// Every benchmark under criterion's output folder `home`: (full id, folder holding `new/`),
/// found by the `new/benchmark.json` files up to four levels down.
pub fn benchmarks(home: &Path) -> Result<Vec<(String, PathBuf)>, EstimatesError> {
    let mut found = vec![];
    let mut stack = vec![(home.to_path_buf(), 0)];
    while let Some((dir, depth)) = stack.pop() {
        let file = dir.join("new/benchmark.json");
        if file.is_file() {
            let id: BenchmarkJson =
                serde_json::from_str(&read(&file)?).map_err(|source| EstimatesError::Json {
                    path: file.clone(),
                    source,
                })?;
            found.push((id.full_id, dir.clone()));
        }
        if depth >= 4 {
            continue;
        }
        let entries = std::fs::read_dir(&dir).map_err(|source| EstimatesError::Read {
            path: dir.clone(),
            source,
        })?;
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() && p.file_name().is_some_and(|n| n != "new" && n != "base") {
                stack.push((p, depth + 1));
            }
        }
    }
    found.sort();
    Ok(found)
}

/// The estimates of each benchmark `ids` (criterion's full ids, e.g. `propagate/exact/1s`),
/// in that order, from criterion's output folder `home`.
pub fn read_estimates(home: &Path, ids: &[&str]) -> Result<Vec<Estimates>, EstimatesError> {
    let all = benchmarks(home)?;
    ids.iter()
        .map(|id| {
            let (_, dir) = all.iter().find(|(f, _)| f == id).ok_or_else(|| {
                let found: Vec<&str> = all.iter().map(|(f, _)| f.as_str()).collect();
                EstimatesError::Missing {
                    home: home.to_path_buf(),
                    id: id.to_string(),
                    found: found.join(", "),
                }
            })?;
            let path = dir.join("new/estimates.json");
            parse_estimates(&read(&path)?, &path)
        })
        .collect()
}

/// A time in ns with 3 significant digits in ns, µs, ms or s.
pub fn duration(ns: f64) -> String {
    let (x, unit) = match ns.abs() {
        a if a < 1e3 => (ns, "ns"),
        a if a < 1e6 => (ns / 1e3, "µs"),
        a if a < 1e9 => (ns / 1e6, "ms"),
        _ => (ns / 1e9, "s"),
    };
    format!("{} {unit}", num(x))
}

/// The table of a bench measurement: per benchmark its id, mean, the mean's 95% confidence
/// interval and median.
pub fn estimates_table(ids: &[&str], estimates: &[Estimates]) -> Table {
    let mut t = Table::new(&["benchmark", "mean", "95% CI of the mean", "median"]);
    for (id, e) in ids.iter().zip(estimates) {
        let ci = e.mean.confidence_interval;
        t.row(vec![
            id.to_string(),
            duration(e.mean.point_estimate),
            format!(
                "{} – {}",
                duration(ci.lower_bound),
                duration(ci.upper_bound)
            ),
            duration(e.median.point_estimate),
        ]);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `estimates.json` as criterion 0.8 writes it (values in ns).
    const ESTIMATES: &str = r#"{"mean":{"confidence_interval":{"confidence_level":0.95,"lower_bound":8712.5,"upper_bound":8890.1},"point_estimate":8801.3,"standard_error":45.2},"median":{"confidence_interval":{"confidence_level":0.95,"lower_bound":8700.0,"upper_bound":8790.0},"point_estimate":8750.0,"standard_error":20.1},"median_abs_dev":{"confidence_interval":{"confidence_level":0.95,"lower_bound":50.0,"upper_bound":90.0},"point_estimate":70.0,"standard_error":10.0},"slope":null,"std_dev":{"confidence_interval":{"confidence_level":0.95,"lower_bound":300.0,"upper_bound":500.0},"point_estimate":400.0,"standard_error":50.0}}"#;

    #[test]
    fn estimates_json_reads_mean_interval_and_median() {
        let e = parse_estimates(ESTIMATES, Path::new("e.json")).unwrap();
        assert_eq!(e.mean.point_estimate, 8801.3);
        assert_eq!(e.mean.confidence_interval.lower_bound, 8712.5);
        assert_eq!(e.mean.confidence_interval.upper_bound, 8890.1);
        assert_eq!(e.mean.confidence_interval.confidence_level, 0.95);
        assert_eq!(e.median.point_estimate, 8750.0);
        let t = estimates_table(&["obc tick"], &[e]);
        assert_eq!(
            t.rows,
            vec![vec![
                "obc tick".to_string(),
                "8.80 µs".into(),
                "8.71 µs – 8.89 µs".into(),
                "8.75 µs".into()
            ]]
        );
        let bad = parse_estimates(r#"{"mean":{}}"#, Path::new("e.json")).unwrap_err();
        assert!(bad.to_string().starts_with("e.json: "), "{bad}");
    }

    #[test]
    fn durations_pick_their_unit() {
        assert_eq!(duration(592.4), "592 ns");
        assert_eq!(duration(13_050.0), "13.1 µs");
        assert_eq!(duration(12_600_000.0), "12.6 ms");
        assert_eq!(duration(2.5e9), "2.50 s");
    }

    #[test]
    fn benchmarks_are_found_by_their_full_id() {
        let home = tempfile::tempdir().unwrap();
        let put = |dir: &str, id: &str| {
            let d = home.path().join(dir).join("new");
            std::fs::create_dir_all(&d).unwrap();
            std::fs::write(
                d.join("benchmark.json"),
                format!(r#"{{"group_id":"g","function_id":null,"value_str":null,"throughput":null,"full_id":"{id}","directory_name":"{dir}","title":"{id}"}}"#),
            )
            .unwrap();
            std::fs::write(d.join("estimates.json"), ESTIMATES).unwrap();
        };
        put("propagate/exact_1s", "propagate/exact/1s");
        put("obc tick (micro-factory)", "obc tick (micro-factory)");
        let e = read_estimates(
            home.path(),
            &["propagate/exact/1s", "obc tick (micro-factory)"],
        )
        .unwrap();
        assert_eq!(e.len(), 2);
        let missing = read_estimates(home.path(), &["nearest/10k"]).unwrap_err();
        assert!(
            matches!(&missing, EstimatesError::Missing { id, .. } if id == "nearest/10k"),
            "{missing}"
        );
    }
}
