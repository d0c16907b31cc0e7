//! Merging shard folders into one results folder: the store merges the runs
//! ([`magbench_store::merge`]); the replay pages and scenario previews are copied with them, and
//! the merged folder's derived files written by [`super::finalize`].

use std::path::{Path, PathBuf};

use magbench_store::merge::Derived;

use crate::Error;
use crate::replay::files;
use crate::results::Manifest;

/// Merges the results folders `shards` (of the same experiment) into `out`, which must not
/// hold results, with each kept run's replay page and every scenario's preview, and writes its
/// derived files, holding `out`'s lock throughout (exit 2 if another process holds it). Only
/// whole runs are taken (one row, and exactly the trace points the row records); a run found
/// in several folders is taken from the first.
pub fn merge(shards: &[PathBuf], out: &Path) -> Result<Manifest, Error> {
    Ok(magbench_store::merge::merge(shards, out, &mut Pages)?)
}

/// What the harness adds to a results folder's runs: replay pages, scenario previews and the
/// derived files of [`super::finalize`].
struct Pages;

impl Derived for Pages {
    fn copy_shared(&mut self, shard: &Path, out: &Path) -> Result<(), magbench_store::Error> {
        Ok(files::copy_previews(shard, out)?)
    }

    fn copy_run(
        &mut self,
        shard: &Path,
        out: &Path,
        run: usize,
    ) -> Result<(), magbench_store::Error> {
        Ok(files::copy_run(shard, out, run)?)
    }

    fn finish(&mut self, out: &Path) -> Result<(), magbench_store::Error> {
        Ok(super::finalize(out)?)
    }
}
