//! Checking a results folder: the manifest, one row per run, one whole trace per run, and the
//! files' hashes recorded in the manifest.

use std::collections::BTreeMap;
use std::path::Path;

use magbench_env::InputError;
use sha2::{Digest, Sha256};

use super::manifest::{MANIFEST, Manifest};
use super::parquet::PARQUET;
use super::store::{self, PROGRESS, RUNS};
use crate::CliError;
use crate::run::{ProgressRow, RunRecord, Status};

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
        && name != super::lock::LOCK
        && name != ".magbench-write-test"
        && !name.ends_with(".tmp")
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Hex SHA-256 of files, by path relative to their folder with `/` separators.
pub type FileHashes = BTreeMap<String, String>;

/// SHA-256 of every file under `dir` (but the manifest, the lock and temporary files), by path
/// relative to `dir` with `/` separators.
pub fn file_hashes(dir: &Path) -> Result<FileHashes, CliError> {
    let mut out = BTreeMap::new();
    let mut stack = vec![(dir.to_path_buf(), String::new())];
    let io = |p: &Path, e: std::io::Error| CliError::Failed(format!("{}: {e}", p.display()));
    while let Some((d, prefix)) = stack.pop() {
        for entry in std::fs::read_dir(&d).map_err(|e| io(&d, e))? {
            let entry = entry.map_err(|e| io(&d, e))?;
            let name = entry.file_name().to_string_lossy().to_string();
            let rel = format!("{prefix}{name}");
            let kind = entry.file_type().map_err(|e| io(&entry.path(), e))?;
            if kind.is_dir() {
                stack.push((entry.path(), format!("{rel}/")));
            } else if kind.is_file() && hashed(&rel) {
                let bytes = std::fs::read(entry.path()).map_err(|e| io(&entry.path(), e))?;
                out.insert(rel, hex(&Sha256::digest(&bytes)));
            }
        }
    }
    Ok(out)
}

/// Problems of one kind: how many, and the first few.
struct Kind {
    what: String,
    items: Vec<String>,
}

const SHOWN: usize = 5;

impl Kind {
    fn new(what: &str) -> Kind {
        Kind {
            what: what.to_string(),
            items: vec![],
        }
    }

    fn push(&mut self, item: String) {
        self.items.push(item);
    }

    fn report(self, problems: &mut Vec<String>) {
        if self.items.is_empty() {
            return;
        }
        let n = self.items.len();
        let mut line = format!("{}: {}", self.what, self.items[..n.min(SHOWN)].join("; "));
        if n > SHOWN {
            line += &format!("; and {} more", n - SHOWN);
        }
        problems.push(line);
    }
}

fn read_text(path: &Path, problems: &mut Vec<String>) -> Option<String> {
    match std::fs::read(path) {
        Ok(b) => match String::from_utf8(b) {
            Ok(t) => Some(t),
            Err(_) => {
                problems.push(format!("{}: not UTF-8 text", name(path)));
                None
            }
        },
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => {
            problems.push(format!("{}: cannot read: {e}", name(path)));
            None
        }
    }
}

fn name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default()
}

/// The complete rows of a run file, with problems for a cut header and a line cut short at
/// the end, and a note for another version's header.
fn rows<T>(
    path: &Path,
    text: Option<String>,
    torn_header: impl Fn(&str) -> bool,
    header_ok: impl Fn(&str) -> bool,
    parse: impl Fn(&Path, &str) -> Result<Vec<T>, CliError>,
    problems: &mut Vec<String>,
    notes: &mut Vec<String>,
) -> Option<Vec<T>> {
    let file = name(path);
    let text = text?;
    if text.is_empty() || torn_header(&text) {
        problems.push(format!("{file}: the header is cut short"));
        return Some(vec![]);
    }
    let n = store::complete_len(&text);
    if !header_ok(text.split('\n').next().unwrap_or_default()) {
        notes.push(format!(
            "{file}: the columns of another version of magbench (read by name)"
        ));
    }
    if n < text.len() {
        problems.push(format!(
            "{file}: ends in a line cut short ({} bytes): `bench --resume` repairs it",
            text.len() - n
        ));
    }
    match parse(path, &text[..n]) {
        Ok(r) => Some(r),
        Err(e) => {
            problems.push(format!("{file}: {e}"));
            None
        }
    }
}

/// Checks the results folder `dir`: the manifest reads; `runs.csv` has one row per run id and
/// index, each a run of the manifest's experiment (and shard), and, once the folder is
/// finished, every run and the manifest's counts; `progress.csv` holds exactly each run's
/// `progress_rows` trace points and none of runs without a row; and the files hash as the
/// manifest records. Errors only for bad input (no such folder, not a results folder).
pub fn verify(dir: &Path) -> Result<Verified, CliError> {
    if !dir.is_dir() {
        return Err(CliError::Input(InputError::new(
            dir.display().to_string(),
            "DIR",
            "not a folder",
        )));
    }
    if ![MANIFEST, RUNS, PROGRESS]
        .iter()
        .any(|f| dir.join(f).exists())
    {
        return Err(CliError::Input(InputError::new(
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
    let runs_text = read_text(&dir.join(RUNS), p);
    if runs_text.is_none() && !p.iter().any(|l| l.starts_with(RUNS)) {
        p.push(format!("{RUNS}: missing"));
    }
    let runs: Vec<RunRecord> = rows(
        &dir.join(RUNS),
        runs_text,
        store::is_torn_runs_header,
        |h| store::header_agents(h).is_some(),
        store::parse_runs,
        p,
        &mut v.notes,
    )
    .unwrap_or_default();
    let progress_text = read_text(&dir.join(PROGRESS), p);
    let traced = runs.iter().any(|r| r.progress_rows != Some(0));
    if progress_text.is_none() && traced && !p.iter().any(|l| l.starts_with(PROGRESS)) {
        p.push(format!("{PROGRESS}: missing"));
    }
    let progress: Vec<ProgressRow> = rows(
        &dir.join(PROGRESS),
        progress_text,
        store::is_torn_progress_header,
        |h| h == store::progress_header(),
        store::parse_progress,
        p,
        &mut v.notes,
    )
    .unwrap_or_default();
    v.runs = runs.len();
    v.trace_points = progress.len();

    v.incomplete = check_rows(&runs, manifest.as_ref(), p);
    check_traces(&runs, &progress, p, &mut v.notes);
    check_parquet(dir, &runs, p);
    if let Some(m) = &manifest {
        v.files_hashed = check_hashes(dir, m, p, &mut v.notes)?;
    }
    Ok(v)
}

/// `runs.parquet`, when the folder has one: a whole Parquet file holding the runs of
/// `runs.csv`, in its order.
fn check_parquet(dir: &Path, runs: &[RunRecord], p: &mut Vec<String>) {
    let path = dir.join(PARQUET);
    if !path.exists() {
        return;
    }
    match super::parquet::check(&path) {
        Err(e) => p.push(format!("{PARQUET}: {e}")),
        Ok(s) if !s.run_ids.iter().eq(runs.iter().map(|r| &r.run_id)) => p.push(format!(
            "{PARQUET}: {} runs, not the {} runs of {RUNS} in their order",
            s.rows,
            runs.len()
        )),
        Ok(_) => {}
    }
}

/// Runs [`verify`] on `dir` and fails (exit 1) listing the problems if it finds any; missing
/// runs count only if `complete` is asked.
pub fn require_sound(dir: &Path, complete: bool) -> Result<(), CliError> {
    let v = verify(dir)?;
    let problems = if complete {
        v.all_problems()
    } else {
        v.problems
    };
    if problems.is_empty() {
        return Ok(());
    }
    Err(CliError::Failed(format!(
        "results verify {} found {} problems:\n  {}",
        dir.display(),
        problems.len(),
        problems.join("\n  ")
    )))
}

/// Checks the rows against each other and the manifest; returns what is missing.
fn check_rows(
    runs: &[RunRecord],
    manifest: Option<&Manifest>,
    p: &mut Vec<String>,
) -> Option<String> {
    let mut by_id: BTreeMap<&str, usize> = BTreeMap::new();
    let mut by_index: BTreeMap<usize, usize> = BTreeMap::new();
    for r in runs {
        *by_id.entry(&r.run_id).or_default() += 1;
        *by_index.entry(r.run).or_default() += 1;
    }
    let mut doubled = Kind::new(&format!("{RUNS}: run ids with several rows"));
    for (id, n) in &by_id {
        if *n > 1 {
            doubled.push(format!("{id} ({n} rows)"));
        }
    }
    doubled.report(p);
    let mut doubled = Kind::new(&format!("{RUNS}: run indices with several rows"));
    for (i, n) in &by_index {
        if *n > 1 {
            doubled.push(format!("{i} ({n} rows)"));
        }
    }
    doubled.report(p);
    let m = manifest?;
    let total = m.experiment.runs_total;
    let in_slice = |i: usize| i < total && m.shard.is_none_or(|[k, n]| i % n == k - 1);
    let mut foreign = Kind::new(&format!(
        "{RUNS}: rows that are not runs of experiment {:?}{}",
        m.experiment.name,
        m.shard
            .map(|[k, n]| format!(" shard {k}/{n}"))
            .unwrap_or_default()
    ));
    for r in runs {
        if r.experiment != m.experiment.name || !in_slice(r.run) {
            foreign.push(format!(
                "{} (index {}, experiment {:?})",
                r.run_id, r.run, r.experiment
            ));
        }
    }
    foreign.report(p);
    let expected = (0..total).filter(|&i| in_slice(i)).count();
    if m.finished.is_none() {
        return Some(format!(
            "not finished: {} of {expected} runs done (`bench --resume` completes it)",
            by_index.len()
        ));
    }
    let lacking: Vec<usize> = (0..total)
        .filter(|&i| in_slice(i) && !by_index.contains_key(&i))
        .collect();
    let mut missing = vec![];
    let mut kind = Kind::new(&format!(
        "{RUNS}: {} of {expected} runs missing, indices",
        lacking.len()
    ));
    for i in &lacking {
        kind.push(i.to_string());
    }
    kind.report(&mut missing);
    if m.runs_done != runs.len() {
        p.push(format!(
            "{MANIFEST}: runs_done is {}, {RUNS} has {} rows",
            m.runs_done,
            runs.len()
        ));
    }
    let crashed = runs.iter().filter(|r| r.status == Status::Crash).count();
    if m.runs_failed != crashed {
        p.push(format!(
            "{MANIFEST}: runs_failed is {}, {RUNS} has {crashed} crashed runs",
            m.runs_failed
        ));
    }
    missing.pop()
}

fn check_traces(
    runs: &[RunRecord],
    progress: &[ProgressRow],
    p: &mut Vec<String>,
    notes: &mut Vec<String>,
) {
    let index: BTreeMap<&str, usize> = runs.iter().map(|r| (&*r.run_id, r.run)).collect();
    let mut count: BTreeMap<&str, u64> = BTreeMap::new();
    let mut orphans = Kind::new(&format!(
        "{PROGRESS}: trace points of runs without a row in {RUNS}"
    ));
    let mut misplaced = Kind::new(&format!(
        "{PROGRESS}: trace points whose run index differs from their run's row"
    ));
    for (i, t) in progress.iter().enumerate() {
        match index.get(&*t.run_id) {
            None => orphans.push(format!("row {} ({})", i + 1, t.run_id)),
            Some(&k) if k != t.run => misplaced.push(format!(
                "row {} ({}: index {}, its row says {k})",
                i + 1,
                t.run_id,
                t.run
            )),
            Some(_) => {}
        }
        *count.entry(&t.run_id).or_default() += 1;
    }
    orphans.report(p);
    misplaced.report(p);
    let mut wrong = Kind::new("runs whose trace in progress.csv is not as long as their row says");
    let mut unknown = 0;
    for r in runs {
        let n = count.get(&*r.run_id).copied().unwrap_or(0);
        match r.progress_rows {
            Some(k) if k != n => wrong.push(format!("{}: {n} points, its row says {k}", r.run_id)),
            Some(_) => {}
            None => unknown += 1,
        }
    }
    wrong.report(p);
    if unknown > 0 {
        notes.push(format!(
            "{unknown} rows of {RUNS} have no progress_rows (an older version): their trace \
             lengths are not checked"
        ));
    }
}

fn check_hashes(
    dir: &Path,
    m: &Manifest,
    p: &mut Vec<String>,
    notes: &mut Vec<String>,
) -> Result<usize, CliError> {
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
        for f in [
            MANIFEST,
            super::super::lock::LOCK,
            "runs.csv.tmp",
            "runs.csv",
        ] {
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
