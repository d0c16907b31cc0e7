//! A temporary file of a results folder (its name ends in `.tmp`, which `results verify` does
//! not hash), removed when its guard is dropped: on an error on the way, and after it has been
//! read or renamed (when there is nothing left to remove).

use std::path::{Path, PathBuf};

/// The path of a temporary file, removed when dropped.
#[derive(Debug)]
pub struct Temporary(PathBuf);

impl Temporary {
    /// Guards the temporary file at `path`.
    pub fn new(path: PathBuf) -> Temporary {
        Temporary(path)
    }

    /// Its path.
    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}
