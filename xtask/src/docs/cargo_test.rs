//! Running a test measurement: one cargo test (`cargo test … -- --exact NAME --nocapture`) or
//! one example (`cargo run --example E`) as a subprocess from the repository root, keeping the
//! Markdown table lines it prints.

use std::path::Path;

use thiserror::Error;

use super::cargo::{CargoError, command_line, run_cargo, table_text};

/// Why a test measurement failed.
#[derive(Debug, Error)]
pub enum TestError {
    /// cargo could not run, or the build, the test or the example failed.
    #[error("test {name}: {source}")]
    Cargo {
        /// The test or example.
        name: String,
        /// Why.
        source: CargoError,
    },
    /// The test or example printed no Markdown table line (`| … |`).
    #[error("test {name}: `{command}` printed no Markdown table (`| … |` lines on stdout)")]
    NoTable {
        /// The test or example.
        name: String,
        /// The command line.
        command: String,
    },
}

impl From<TestError> for magbench::Error {
    fn from(e: TestError) -> Self {
        magbench::Error::Failed(e.to_string())
    }
}

/// Which target of a crate a test measurement runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// `--lib`: the test is a unit test of the crate's library (its full path, such as
    /// `ompl::tests::sst_node_counts`).
    Lib,
    /// `--test FILE`: the test is in `tests/FILE.rs` of the crate.
    Test(&'static str),
    /// `cargo run --example E`: the example prints the table; no test name.
    Example(&'static str),
}

/// One cargo test or example of a test measurement.
#[derive(Debug, Clone)]
pub struct TestRun<'a> {
    /// The crate (`-p`).
    pub package: &'a str,
    /// The target of the crate.
    pub target: Target,
    /// The test's exact name within the target (unused for an example).
    pub test: &'a str,
    /// Run it although it is `#[ignore]`d (`-- --ignored`).
    pub ignored: bool,
    /// A release build (`--release`: figures of time); else a debug build.
    pub release: bool,
    /// The cargo feature of the crate it needs.
    pub feature: Option<&'a str>,
    /// The repository root (cargo's working directory).
    pub root: &'a Path,
    /// Echo the stdout to stderr while it runs.
    pub echo: bool,
}

impl TestRun<'_> {
    /// The test's name, or the example's, for errors.
    pub fn name(&self) -> &str {
        match self.target {
            Target::Example(e) => e,
            Target::Lib | Target::Test(_) => self.test,
        }
    }
}

/// The cargo arguments of `r`: `test -p P [--release] [--features F] (--lib | --test FILE) --
/// [--ignored] --exact NAME --nocapture`, or `run -p P [--release] [--features F] --example
/// E`.
pub fn cargo_args(r: &TestRun) -> Vec<String> {
    let verb = match r.target {
        Target::Example(_) => "run",
        Target::Lib | Target::Test(_) => "test",
    };
    let mut a: Vec<String> = vec![verb.into(), "-p".into(), r.package.into()];
    if r.release {
        a.push("--release".into());
    }
    if let Some(f) = r.feature {
        a.extend(["--features".into(), f.into()]);
    }
    match r.target {
        Target::Example(e) => a.extend(["--example".into(), e.into()]),
        Target::Lib | Target::Test(_) => {
            match r.target {
                Target::Test(file) => a.extend(["--test".into(), file.into()]),
                _ => a.push("--lib".into()),
            }
            a.push("--".into());
            if r.ignored {
                a.push("--ignored".into());
            }
            a.extend(["--exact".into(), r.test.into(), "--nocapture".into()]);
        }
    }
    a
}

/// Runs the test or example and returns its Markdown table lines, one per line.
pub fn run_test(r: &TestRun) -> Result<String, TestError> {
    let args = cargo_args(r);
    let stdout = run_cargo(r.root, &args, &[], r.echo).map_err(|source| TestError::Cargo {
        name: r.name().to_string(),
        source,
    })?;
    table_text(&stdout).ok_or_else(|| TestError::NoTable {
        name: r.name().to_string(),
        command: command_line(&args),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(target: Target, release: bool) -> TestRun<'static> {
        TestRun {
            package: "magbench-planners",
            target,
            test: "ompl::tests::sst_node_counts",
            ignored: true,
            release,
            feature: Some("ompl"),
            root: Path::new("."),
            echo: false,
        }
    }

    #[test]
    fn the_command_names_crate_target_feature_and_test() {
        assert_eq!(
            cargo_args(&run(Target::Lib, false)).join(" "),
            "test -p magbench-planners --features ompl --lib -- --ignored --exact \
             ompl::tests::sst_node_counts --nocapture"
        );
        let mut t = run(Target::Test("detector_accuracy"), false);
        t.feature = None;
        t.ignored = false;
        assert_eq!(
            cargo_args(&t).join(" "),
            "test -p magbench-planners --test detector_accuracy -- --exact \
             ompl::tests::sst_node_counts --nocapture"
        );
        let e = run(Target::Example("detect_timing"), true);
        assert_eq!(
            cargo_args(&e).join(" "),
            "run -p magbench-planners --release --features ompl --example detect_timing"
        );
        assert_eq!(e.name(), "detect_timing");
    }
}
