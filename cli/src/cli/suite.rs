//! `magbench suite`: check or freeze the frozen problem suites in `suites/` (`bench --suite
//! NAME` runs one).

use clap::Subcommand;

use crate::Error;
use crate::experiment::Experiment;
use crate::output::outln;
use crate::registry::Registry;
use crate::run::Executor;
use crate::suite::{Suite, locate};

/// Suite subcommands.
#[derive(Debug, Subcommand)]
pub enum SuiteCmd {
    /// Check a suite: its files against SHA256SUMS, SHA256SUMS against the manifest's hash, and
    /// the files against a fresh draw of the recipe. Exit 1 if anything differs.
    Check {
        /// A suite name (`suites/NAME`) or folder.
        suite: String,
    },
    /// Draw a suite's files from its recipe and record their hashes (for a new suite or a new
    /// version: a frozen version is never redrawn).
    Freeze {
        /// A suite name (`suites/NAME`) or folder.
        suite: String,
    },
}

/// Runs a suite subcommand.
pub fn run(cmd: SuiteCmd) -> Result<(), Error> {
    match cmd {
        SuiteCmd::Check { suite } => {
            let s = Suite::load(&locate(&suite))?;
            let problems = s.check(true)?;
            if problems.is_empty() {
                outln!(
                    "{} v{}: ok: {} files match SHA256SUMS, sha256 {}, and the recipe redraws them byte for byte",
                    s.name,
                    s.version,
                    s.stored_files().len(),
                    s.sha256
                );
                return Ok(());
            }
            for p in &problems {
                outln!("{}: {p}", s.file());
            }
            Err(Error::Failed(format!(
                "{}: {} problems",
                s.file(),
                problems.len()
            )))
        }
        SuiteCmd::Freeze { suite } => {
            let mut s = Suite::load(&locate(&suite))?;
            let hash = s.freeze()?;
            outln!(
                "{} v{}: {} files, sha256 {hash}",
                s.name,
                s.version,
                s.stored_files().len()
            );
            Ok(())
        }
    }
}

/// The experiment `bench --suite NAME` runs: the suite's stored files (checked against their
/// hashes; a mismatch is bad input) with its planners, seeds and limits.
pub fn experiment(name: &str, registry: &Registry, ex: &dyn Executor) -> Result<Experiment, Error> {
    let s = Suite::load(&locate(name))?;
    if let Some(p) = s.check(false)?.first() {
        return Err(Error::Input(magbench_env::InputError::new(
            s.file(),
            "sha256",
            format!("{p} (`magbench suite check {name}`)"),
        )));
    }
    let text = s.experiment_text(&|p| registry.planners().get(p).is_some());
    Ok(Experiment::parse(
        &text,
        &s.file(),
        &s.dir.join("scenarios"),
        &s.name,
        ex,
    )?)
}
