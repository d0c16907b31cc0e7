//! `magbench merge`: join shard results folders into one.

use std::path::PathBuf;

use clap::Args;

use crate::Error;
use crate::output::outln;
use crate::results::merge::merge;

/// Arguments of `magbench merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Results folders of the shards (same experiment).
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// The merged results folder (must not hold results yet).
    #[arg(long)]
    pub out: PathBuf,
}

/// Runs `magbench merge`.
pub fn run(a: MergeArgs) -> Result<(), Error> {
    crate::output::prepare_dir(&a.out, "--out")?;
    let m = merge(&a.dirs, &a.out)?;
    outln!(
        "{}: merged {} folders into {}: {} of {} runs",
        m.experiment.name,
        a.dirs.len(),
        a.out.display(),
        m.runs_done,
        m.experiment.runs_total
    );
    if m.runs_done < m.experiment.runs_total {
        eprintln!(
            "warning: {} runs are missing (a shard not merged, or not finished: rerun it with --resume)",
            m.experiment.runs_total - m.runs_done
        );
    }
    Ok(())
}
