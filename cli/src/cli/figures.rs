//! `magbench figures`: the paper figures from fixed seeds.

use std::path::PathBuf;

use clap::Args;

use super::number::count;
use crate::Error;
use crate::figures::{svgs, write_all};
use crate::output::outln;
use crate::registry::Registry;
use crate::run::spec::ITERATIONS;

/// Arguments of `magbench figures`.
#[derive(Debug, Args)]
pub struct FiguresArgs {
    /// Output folder.
    #[arg(long, default_value = "results/figures")]
    pub out: PathBuf,
    /// Iteration limit of the micro-factory plan (default 200000).
    #[arg(long)]
    pub maze_iterations: Option<u64>,
}

/// Runs `magbench figures`.
pub fn run(a: FiguresArgs, registry: &Registry) -> Result<(), Error> {
    if let Some(n) = a.maze_iterations {
        count("--maze-iterations", &ITERATIONS, n)?;
    }
    crate::output::prepare_dir(&a.out, "--out")?;
    let files = write_all(&a.out, a.maze_iterations, registry, &|m| eprintln!("{m}"))?;
    for f in svgs(&files) {
        outln!("{}  (+ .png)", f.display());
    }
    Ok(())
}
