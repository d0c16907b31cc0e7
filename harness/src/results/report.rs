//! `report.html`.

use std::path::Path;

use super::manifest::Manifest;
use super::plots::PlotFile;
use crate::CliError;
use crate::run::RunRecord;

/// Writes `dir/report.html`.
pub fn write(
    dir: &Path,
    _m: &Manifest,
    _runs: &[RunRecord],
    _plots: &[PlotFile],
) -> Result<(), CliError> {
    std::fs::write(
        dir.join("report.html"),
        "<!doctype html><title>report</title>",
    )
    .map_err(|e| CliError::Failed(e.to_string()))
}
