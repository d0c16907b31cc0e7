//! `magbench results verify DIR`: check a results folder.

use std::path::PathBuf;

use clap::Subcommand;

use super::output::outln;
use crate::CliError;
use crate::results::{lock, verify};

/// Results-folder subcommands.
#[derive(Debug, Subcommand)]
pub enum ResultsCmd {
    /// Check a results folder: its manifest, one row per run, one whole trace per run, and the
    /// files' hashes; print what is wrong. Exit 1 if anything is, 2 for bad input (no such
    /// folder, not a results folder, or a bench or merge writing it now).
    Verify {
        /// The results folder.
        dir: PathBuf,
    },
}

/// Runs a results subcommand.
pub fn run(cmd: ResultsCmd) -> Result<(), CliError> {
    match cmd {
        ResultsCmd::Verify { dir } => {
            let _lock = lock::shared(&dir, "DIR")?;
            let v = verify::verify(&dir)?;
            for n in &v.notes {
                eprintln!("note: {}: {n}", dir.display());
            }
            let problems = v.all_problems();
            if problems.is_empty() {
                let hashes = match v.files_hashed {
                    0 => "no file hashes to check".to_string(),
                    n => format!("{n} files match the manifest's hashes"),
                };
                outln!(
                    "{}: ok: {} runs, {} trace points, {hashes}",
                    dir.display(),
                    v.runs,
                    v.trace_points,
                );
                return Ok(());
            }
            for p in &problems {
                outln!("{}: {p}", dir.display());
            }
            Err(CliError::Failed(format!(
                "{}: {} problems found",
                dir.display(),
                problems.len()
            )))
        }
    }
}
