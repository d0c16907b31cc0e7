//! Running a bench measurement: `cargo bench` of one bench of crate `magbench-benches` as a
//! subprocess from the repository root, with criterion's output folder set by
//! `CRITERION_HOME`, then criterion's estimates read back into a table.

use std::path::{Path, PathBuf};

use thiserror::Error;

use super::cargo::{CargoError, own_table, run_cargo};
use super::criterion::{EstimatesError, estimates_table, read_estimates};

/// Why a bench measurement failed.
#[derive(Debug, Error)]
pub enum BenchError {
    /// `cargo bench` could not run or failed (build error, panic in the bench, missing
    /// feature dependency).
    #[error("bench {bench}: {source}")]
    Cargo {
        /// The bench.
        bench: String,
        /// Why.
        source: CargoError,
    },
    /// Criterion's results could not be read.
    #[error("bench {bench}: {source}")]
    Estimates {
        /// The bench.
        bench: String,
        /// Why.
        source: EstimatesError,
    },
}

impl From<BenchError> for magbench::Error {
    fn from(e: BenchError) -> Self {
        magbench::Error::Failed(e.to_string())
    }
}

/// One `cargo bench` of a bench measurement.
#[derive(Debug, Clone)]
pub struct BenchRun<'a> {
    /// The bench target.
    pub bench: &'a str,
    /// The cargo feature of `magbench-benches` it needs.
    pub feature: Option<&'a str>,
    /// Arguments for the bench after `--noplot`.
    pub args: &'a [&'a str],
    /// Criterion's ids of the benchmarks tabled.
    pub ids: &'a [&'a str],
    /// The repository root (cargo's working directory).
    pub root: &'a Path,
    /// Criterion's output folder (emptied first).
    pub criterion_home: PathBuf,
    /// Echo the bench's stdout to stderr while it runs.
    pub echo: bool,
}

/// The cargo arguments of `r`: `bench -p magbench-benches --bench B [--features F] -- --noplot
/// ARGS`.
pub fn cargo_args(r: &BenchRun) -> Vec<String> {
    let mut a: Vec<String> = ["bench", "-p", "magbench-benches", "--bench", r.bench]
        .map(String::from)
        .into();
    if let Some(f) = r.feature {
        a.extend(["--features".to_string(), f.to_string()]);
    }
    a.extend(["--".to_string(), "--noplot".to_string()]);
    a.extend(r.args.iter().map(|s| s.to_string()));
    a
}

/// Runs the bench and returns the Markdown body of its file: criterion's estimates of the
/// ids as a table, then the bench's own table lines, if any.
pub fn run_bench(r: &BenchRun) -> Result<String, BenchError> {
    let args = cargo_args(r);
    let estimates = |source| BenchError::Estimates {
        bench: r.bench.to_string(),
        source,
    };
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| estimates(EstimatesError::Read { path, source })
    };
    if r.criterion_home.exists() {
        std::fs::remove_dir_all(&r.criterion_home).map_err(io(&r.criterion_home))?;
    }
    std::fs::create_dir_all(&r.criterion_home).map_err(io(&r.criterion_home))?;
    // the bench runs in benches/: criterion needs an absolute folder
    let home = std::fs::canonicalize(&r.criterion_home).map_err(io(&r.criterion_home))?;
    let stdout = run_cargo(r.root, &args, &[("CRITERION_HOME", home.as_path())], r.echo).map_err(
        |source| BenchError::Cargo {
            bench: r.bench.to_string(),
            source,
        },
    )?;
    let mut body = String::new();
    if !r.ids.is_empty() {
        let e = read_estimates(&home, r.ids).map_err(estimates)?;
        body.push_str(&estimates_table(r.ids, &e).markdown());
    }
    let own = own_table(&stdout);
    if !own.is_empty() {
        if !body.is_empty() {
            body.push_str("\nThe bench's own figures:\n\n");
        }
        for l in own {
            body.push_str(l);
            body.push('\n');
        }
    }
    Ok(body)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_command_names_bench_feature_and_arguments() {
        let r = BenchRun {
            bench: "ompl_abi",
            feature: Some("ompl"),
            args: &["--quick"],
            ids: &[],
            root: Path::new("."),
            criterion_home: PathBuf::from("c"),
            echo: false,
        };
        assert_eq!(
            cargo_args(&r).join(" "),
            "bench -p magbench-benches --bench ompl_abi --features ompl -- --noplot --quick"
        );
    }
}
