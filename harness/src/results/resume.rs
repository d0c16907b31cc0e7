//! Opening a results folder for a sweep: locked, checked against the experiment, and (when
//! resuming) repaired, so that the sweep runs exactly the runs the folder lacks.

use std::path::Path;

use magbench_env::InputError;

use super::lock::{self, DirLock};
use super::manifest::{MANIFEST, Manifest};
use super::repair::{Expected, repair};
use super::store::{PROGRESS, RUNS};
use crate::Error;
use crate::experiment::{Experiment, Matrix};

/// A results folder opened for a sweep.
#[derive(Debug)]
pub struct Opened {
    /// The folder's manifest (read, rebuilt, or new).
    pub manifest: Manifest,
    /// Indices of the runs the folder already holds, whole, in increasing order.
    pub done: Vec<usize>,
    /// The folder's lock, held until this is dropped.
    pub lock: DirLock,
}

/// How a sweep opens its folder.
#[derive(Debug, Clone, Copy)]
pub struct OpenOptions<'a> {
    /// The executor's name (for a new manifest).
    pub executor: &'a str,
    /// Worker threads (for a new manifest).
    pub threads: usize,
    /// `[i, n]` of a shard.
    pub shard: Option<[usize; 2]>,
    /// Complete the results the folder holds instead of refusing it.
    pub resume: bool,
}

fn short(h: &str) -> &str {
    &h[..h.len().min(12)]
}

/// The manifest of `out` for resuming `e`: read and checked; rebuilt from `e` (with a note) if
/// it is missing or cut short.
fn resumed_manifest(out: &Path, e: &Experiment, o: &OpenOptions) -> Result<Manifest, Error> {
    let path = out.join(MANIFEST);
    let text = std::fs::read_to_string(&path).ok();
    let cut = text
        .as_deref()
        .map(|t| serde_json::from_str::<serde_json::Value>(t).is_err_and(|e| e.is_eof()));
    if text.is_none() || cut == Some(true) {
        eprintln!(
            "note: {}: {MANIFEST} {}: rebuilt from {} (the earlier sessions are not listed)",
            out.display(),
            if text.is_none() {
                "is missing"
            } else {
                "was cut short"
            },
            e.source
        );
        return Ok(e.manifest(o.executor, o.threads, o.shard));
    }
    let m = Manifest::read(out)?;
    if m.experiment.sha256 != e.hash() {
        return Err(Error::Input(InputError::new(
            out.display().to_string(),
            "--resume",
            format!(
                "the results are from another version of the experiment (sha256 {} vs {} now); use a new --out",
                short(&m.experiment.sha256),
                short(&e.hash())
            ),
        )));
    }
    if m.shard != o.shard {
        return Err(Error::Input(InputError::new(
            out.display().to_string(),
            "--shard",
            format!("the results are of shard {:?}, not {:?}", m.shard, o.shard),
        )));
    }
    // the folder changes again: it is finished (and its hashes hold) only when this sweep ends
    let mut m = m;
    m.finished = None;
    m.files.clear();
    Ok(m)
}

/// Creates `out` if needed, takes its lock (exit 2 if another process holds it), and returns
/// its manifest and the runs it holds whole. A folder that holds results needs `resume`; it
/// is then checked against `e` and its shard (`o.shard`) and repaired
/// ([`super::repair`]), and what the repair dropped is printed as notes on stderr.
pub fn open_for_sweep(out: &Path, e: &Experiment, o: &OpenOptions) -> Result<Opened, Error> {
    std::fs::create_dir_all(out)
        .map_err(|err| Error::Failed(format!("{}: {err}", out.display())))?;
    let lock = lock::exclusive(out, "bench", "--out")?;
    let holds = [MANIFEST, RUNS, PROGRESS]
        .iter()
        .any(|f| out.join(f).exists());
    if holds && !o.resume {
        return Err(Error::Input(InputError::new(
            out.display().to_string(),
            "--out",
            "already holds results: pass --resume to complete them, or choose another --out",
        )));
    }
    let manifest = if holds {
        resumed_manifest(out, e, o)?
    } else {
        e.manifest(o.executor, o.threads, o.shard)
    };
    let matrix = e.matrix();
    let shard = o.shard.map(|[k, n]| (k, n));
    let index_of = |id: &str| matrix.index_of(id).filter(|&i| Matrix::in_shard(i, shard));
    let expected = Expected {
        experiment: &e.name,
        index_of: &index_of,
    };
    let repaired = repair(out, &expected)?;
    for n in &repaired.notes {
        eprintln!("note: {}: {n}", out.display());
    }
    Ok(Opened {
        manifest,
        done: repaired.done,
        lock,
    })
}
