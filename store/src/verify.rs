//! Checking a results folder: the manifest, one row per run, one whole trace per run, and the
//! files' hashes recorded in the manifest.

use std::collections::BTreeMap;
use std::path::Path;

use magbench_env::InputError;
use sha2::{Digest, Sha256};

use crate::Error;
use crate::manifest::{MANIFEST, Manifest};
use crate::parquet::PARQUET;
use crate::store::{self, PROGRESS, RUNS, Snapshot};

/// What [`verify`] found.
#[derive(Debug, Clone, Default)]
pub struct Verified {
    /// What is wrong, one line each, but missing runs.
    pub problems: Vec<String>,
    /// Runs missing from the folder, or that it is not finished (`None`: every run is there).
    pub incomplete: Option<String>,
    /// What could not be checked, one line each.
    pub notes: Vec<String>,
    /// Rows in `runs.csv`.
    pub runs: usize,
    /// Rows in `progress.csv`.
    pub trace_points: usize,
    /// Files whose hash matched the manifest's.
    pub files_hashed: usize,
}

impl Verified {
    /// Every problem: [`Verified::problems`] and [`Verified::incomplete`] (empty: the folder is
    /// sound and complete).
    pub fn all_problems(&self) -> Vec<String> {
        self.problems
            .iter()
            .cloned()
            .chain(self.incomplete.clone())
            .collect()
    }
}

/// Files of a folder left out of the hashes: the manifest itself, the lock and temporaries.
fn hashed(name: &str) -> bool {
    name != MANIFEST
        && name != crate::lock::LOCK
        && name != ".magbench-write-test"
        && !name.ends_with(".tmp")
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Hex SHA-256 of the file at `path`, read a block at a time.
fn hash_file(path: &Path) -> std::io::Result<String> {
    use std::io::Read;
    let mut f = std::fs::File::open(path)?;
    let mut h = Sha256::new();
    let mut buf = vec![0; 1 << 16];
    loop {
        match f.read(&mut buf)? {
            0 => return Ok(hex(&h.finalize())),
            n => h.update(&buf[..n]),
        }
    }
}

/// Hex SHA-256 of files, by path relative to their folder with `/` separators.
pub type FileHashes = BTreeMap<String, String>;

/// SHA-256 of every file under `dir` (but the manifest, the lock and temporary files), by path
/// relative to `dir` with `/` separators.
pub fn file_hashes(dir: &Path) -> Result<FileHashes, Error> {
    let mut out = BTreeMap::new();
    let mut stack = vec![(dir.to_path_buf(), String::new())];
    let io = |p: &Path, e: std::io::Error| Error::Failed(format!("{}: {e}", p.display()));
    while let Some((d, prefix)) = stack.pop() {
        for entry in std::fs::read_dir(&d).map_err(|e| io(&d, e))? {
            let entry = entry.map_err(|e| io(&d, e))?;
            let name = entry.file_name().to_string_lossy().to_string();
            let rel = format!("{prefix}{name}");
            let kind = entry.file_type().map_err(|e| io(&entry.path(), e))?;
            if kind.is_dir() {
                stack.push((entry.path(), format!("{rel}/")));
            } else if kind.is_file() && hashed(&rel) {
                out.insert(
                    rel,
                    hash_file(&entry.path()).map_err(|e| io(&entry.path(), e))?,
                );
            }
        }
    }
    Ok(out)
}

/// Problems of one kind: how many, and the first few.
pub(super) struct Kind {
    /// What they are.
    pub what: String,
    items: Vec<String>,
    /// How many.
    pub count: usize,
}

const SHOWN: usize = 5;

impl Kind {
    pub fn new(what: &str) -> Kind {
        Kind {
            what: what.to_string(),
            items: vec![],
            count: 0,
        }
    }

    /// Counts `item`, keeping the first [`SHOWN`] (a folder of another experiment has a
    /// problem in every row).
    pub fn push(&mut self, item: String) {
        self.push_with(|| item);
    }

    /// [`Kind::push`], making the item only if it is shown.
    pub fn push_with(&mut self, item: impl FnOnce() -> String) {
        if self.items.len() < SHOWN {
            self.items.push(item());
        }
        self.count += 1;
    }

    /// Adds the line of these problems to `problems`, if there are any.
    pub fn report(self, problems: &mut Vec<String>) {
        if self.count == 0 {
            return;
        }
        let n = self.count;
        let mut line = format!("{}: {}", self.what, self.items.join("; "));
        if n > SHOWN {
            line += &format!("; and {} more", n - SHOWN);
        }
        problems.push(line);
    }
}

fn name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default()
}

/// Longest first line read to tell a cut header from another version's (bytes).
const FIRST_LINE_MAX: u64 = 1 << 16;

/// The file's first line (at most [`FIRST_LINE_MAX`] bytes of it), lossily decoded.
fn first_line(snap: &Snapshot) -> String {
    use std::io::{BufRead, Read};
    let mut buf = vec![];
    if let Ok(f) = std::fs::File::open(snap.path()) {
        let _ = std::io::BufReader::new(f)
            .take(FIRST_LINE_MAX)
            .read_until(b'\n', &mut buf);
    }
    let text = String::from_utf8_lossy(&buf);
    text.trim_end_matches('\n').to_string()
}

/// A run file opened for its rows, with problems for a file that cannot be read, a cut header
/// and a line cut short at the end, and a note for another version's header; `None` when it
/// has no rows to read (no file, or a header cut short).
fn open_rows(
    path: &Path,
    torn_header: impl Fn(&str) -> bool,
    header_ok: impl Fn(&str) -> bool,
    problems: &mut Vec<String>,
    notes: &mut Vec<String>,
) -> Option<Snapshot> {
    let file = name(path);
    let snap = match Snapshot::open(path) {
        Ok(Some(s)) => s,
        Ok(None) => return None,
        Err(e) => {
            problems.push(format!("{file}: cannot read: {e}"));
            return None;
        }
    };
    let first = first_line(&snap);
    if snap.complete_len() == 0 && (snap.size() == 0 || torn_header(&first)) {
        problems.push(format!("{file}: the header is cut short"));
        return None;
    }
    if !header_ok(&first) {
        notes.push(format!(
            "{file}: the columns of another version of magbench (read by name)"
        ));
    }
    if !snap.is_whole() {
        problems.push(format!(
            "{file}: ends in a line cut short ({} bytes): `bench --resume` repairs it",
            snap.size() - snap.complete_len()
        ));
    }
    Some(snap)
}

/// Checks the results folder `dir`: the manifest reads; `runs.csv` has one row per run index
/// (and run id within it), each a run of the manifest's experiment (and shard), and, once the
/// folder is finished, every run and the manifest's counts; `progress.csv` holds exactly each
/// run's `progress_rows` trace points and none of runs without a row
/// ([`crate::verify_rows`]); `runs.parquet` holds the runs of `runs.csv` in its order; and the
/// files hash as the manifest records. Errors only for bad input (no such folder, not a results
/// folder).
pub fn verify(dir: &Path) -> Result<Verified, Error> {
    if !dir.is_dir() {
        return Err(Error::Input(InputError::new(
            dir.display().to_string(),
            "DIR",
            "not a folder",
        )));
    }
    if ![MANIFEST, RUNS, PROGRESS]
        .iter()
        .any(|f| dir.join(f).exists())
    {
        return Err(Error::Input(InputError::new(
            dir.display().to_string(),
            "DIR",
            format!("not a results folder: no {MANIFEST}, {RUNS} or {PROGRESS}"),
        )));
    }
    let mut v = Verified::default();
    let p = &mut v.problems;
    let manifest = match Manifest::read(dir) {
        Ok(m) => Some(m),
        Err(e) => {
            p.push(e.to_string());
            None
        }
    };
    let runs_path = dir.join(RUNS);
    if !runs_path.exists() {
        p.push(format!("{RUNS}: missing"));
    }
    let runs = open_rows(
        &runs_path,
        store::is_torn_runs_header,
        |h| store::header_agents(h).is_some(),
        p,
        &mut v.notes,
    );
    let progress_path = dir.join(PROGRESS);
    let progress = open_rows(
        &progress_path,
        store::is_torn_progress_header,
        |h| h == store::progress_header(),
        p,
        &mut v.notes,
    );
    let checked = crate::verify_rows::check(runs.as_ref(), progress.as_ref(), manifest.as_ref())?;
    if !progress_path.exists() && checked.traced {
        p.push(format!("{PROGRESS}: missing"));
    }
    (v.runs, v.trace_points) = (checked.rows, checked.points());
    let ids = checked.ids;
    v.incomplete = checked.report(manifest.as_ref(), p, &mut v.notes);
    check_parquet(dir, v.runs, ids, p);
    if let Some(m) = &manifest {
        v.files_hashed = check_hashes(dir, m, p, &mut v.notes)?;
    }
    Ok(v)
}

/// `runs.parquet`, when the folder has one: a whole Parquet file holding the `rows` runs of
/// `runs.csv`, in its order (the hash of its run ids is `ids`, as [`crate::verify_rows`]
/// hashes them).
fn check_parquet(dir: &Path, rows: usize, ids: [u8; 32], p: &mut Vec<String>) {
    let path = dir.join(PARQUET);
    if !path.exists() {
        return;
    }
    let mut hash = Sha256::new();
    match crate::parquet::check(&path, |id| crate::verify_rows::hash_id(&mut hash, id)) {
        Err(e) => p.push(format!("{PARQUET}: {e}")),
        Ok(s) if s.rows != rows || <[u8; 32]>::from(hash.finalize()) != ids => p.push(format!(
            "{PARQUET}: {} runs, not the {rows} runs of {RUNS} in their order",
            s.rows
        )),
        Ok(_) => {}
    }
}

/// Runs [`verify`] on `dir` and fails (exit 1) listing the problems if it finds any; missing
/// runs count only if `complete` is asked.
pub fn require_sound(dir: &Path, complete: bool) -> Result<(), Error> {
    let v = verify(dir)?;
    let problems = if complete {
        v.all_problems()
    } else {
        v.problems
    };
    if problems.is_empty() {
        return Ok(());
    }
    Err(Error::Failed(format!(
        "results verify {} found {} problems:\n  {}",
        dir.display(),
        problems.len(),
        problems.join("\n  ")
    )))
}

/// Whether run index `i` is a run of the manifest's experiment (and of its shard).
pub(super) fn in_slice(m: &Manifest, i: usize) -> bool {
    i < m.experiment.runs_total && m.shard.is_none_or(|[k, n]| i % n == k - 1)
}

fn check_hashes(
    dir: &Path,
    m: &Manifest,
    p: &mut Vec<String>,
    notes: &mut Vec<String>,
) -> Result<usize, Error> {
    if m.files.is_empty() {
        if m.finished.is_none() {
            // an unfinished folder has no hashes yet; that is reported as unfinished
            return Ok(0);
        }
        notes.push(format!(
            "{MANIFEST} records no file hashes (not finalized, or an older version): files not \
             hashed"
        ));
        return Ok(0);
    }
    let now = file_hashes(dir)?;
    let mut missing = Kind::new("files listed in the manifest but missing");
    let mut changed = Kind::new("files changed since the folder was finalized");
    let mut ok = 0;
    for (f, h) in &m.files {
        match now.get(f) {
            None => missing.push(f.clone()),
            Some(x) if x != h => changed.push(f.clone()),
            Some(_) => ok += 1,
        }
    }
    missing.report(p);
    changed.report(p);
    Ok(ok)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hashes_skip_the_manifest_the_lock_and_temporaries_and_recurse() {
        let dir = tempfile::tempdir().unwrap();
        for f in [MANIFEST, crate::lock::LOCK, "runs.csv.tmp", "runs.csv"] {
            std::fs::write(dir.path().join(f), "x").unwrap();
        }
        std::fs::create_dir(dir.path().join("plots")).unwrap();
        std::fs::write(dir.path().join("plots/a.svg"), "").unwrap();
        let h = file_hashes(dir.path()).unwrap();
        assert_eq!(h.keys().collect::<Vec<_>>(), ["plots/a.svg", "runs.csv"]);
        assert_eq!(
            h["plots/a.svg"],
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
        );
    }

    #[test]
    fn bad_input_is_exit_2() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(verify(&dir.path().join("nope")).unwrap_err().exit_code(), 2);
        assert_eq!(verify(dir.path()).unwrap_err().exit_code(), 2);
    }
}
