//! The files of a results folder that hold runs: `runs.csv` and `progress.csv`.
//!
//! Crash safety: each finished run appends its progress rows, then its `runs.csv` row, each in
//! one write followed by a flush. A `runs.csv` row is the commit mark of a run. [`repair`]
//! (called before resuming) drops a trailing partial line and progress rows of runs that have
//! no `runs.csv` row, so an interrupted sweep loses only the runs that were in flight.

use std::collections::BTreeSet;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::CliError;
use crate::run::{ProgressRow, RunOutput, RunRecord};

/// `runs.csv`.
pub const RUNS: &str = "runs.csv";
/// `progress.csv`.
pub const PROGRESS: &str = "progress.csv";

fn failed(path: &Path, e: impl std::fmt::Display) -> CliError {
    CliError::Failed(format!("{}: {e}", path.display()))
}

fn header_line<T: serde::Serialize>(example: &T) -> String {
    let mut w = csv::Writer::from_writer(vec![]);
    w.serialize(example).expect("serialize");
    let text = String::from_utf8(w.into_inner().expect("flush")).expect("utf8");
    text.lines().next().unwrap_or_default().to_string()
}

fn runs_header() -> String {
    header_line(&RunRecord::example())
}

fn progress_header() -> String {
    header_line(&ProgressRow {
        run: 0,
        run_id: String::new(),
        iteration: 0,
        time_s: 0.0,
        best_cost: None,
    })
}

fn record_bytes<T: serde::Serialize>(rows: &[T]) -> Vec<u8> {
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(vec![]);
    for r in rows {
        w.serialize(r).expect("serialize a row");
    }
    w.into_inner().expect("flush to memory")
}

/// Appends finished runs to a results folder.
pub struct RunWriter {
    runs: File,
    progress: File,
    dir: PathBuf,
}

impl RunWriter {
    /// Opens (creating with headers if needed) the run files of `dir` for appending. Call
    /// [`repair`] first on a folder that may hold an interrupted sweep.
    pub fn open(dir: &Path) -> Result<RunWriter, CliError> {
        std::fs::create_dir_all(dir).map_err(|e| failed(dir, e))?;
        let runs = open_with_header(&dir.join(RUNS), &runs_header())?;
        let progress = open_with_header(&dir.join(PROGRESS), &progress_header())?;
        Ok(RunWriter {
            runs,
            progress,
            dir: dir.to_path_buf(),
        })
    }

    /// Writes one finished run: progress rows first, then the run's row (the commit mark).
    pub fn write(&mut self, out: &RunOutput) -> Result<(), CliError> {
        if !out.progress.is_empty() {
            self.progress
                .write_all(&record_bytes(&out.progress))
                .map_err(|e| failed(&self.dir.join(PROGRESS), e))?;
            self.progress
                .flush()
                .map_err(|e| failed(&self.dir.join(PROGRESS), e))?;
        }
        self.runs
            .write_all(&record_bytes(std::slice::from_ref(&out.record)))
            .map_err(|e| failed(&self.dir.join(RUNS), e))?;
        self.runs
            .flush()
            .map_err(|e| failed(&self.dir.join(RUNS), e))?;
        Ok(())
    }
}

fn open_with_header(path: &Path, header: &str) -> Result<File, CliError> {
    let existing = std::fs::read_to_string(path).unwrap_or_default();
    let mut f = OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .map_err(|e| failed(path, e))?;
    if existing.is_empty() {
        f.write_all(format!("{header}\n").as_bytes())
            .map_err(|e| failed(path, e))?;
        f.flush().map_err(|e| failed(path, e))?;
    } else if existing.lines().next() != Some(header) {
        return Err(CliError::Input(magbench_env::InputError::new(
            path.display().to_string(),
            "header",
            "the columns differ from this version of magbench; write to a new --out folder",
        )));
    }
    Ok(f)
}

/// Reads the complete rows of `runs.csv` (a trailing partial line is ignored).
pub fn read_runs(dir: &Path) -> Result<Vec<RunRecord>, CliError> {
    read_rows(&dir.join(RUNS))
}

/// Reads the complete rows of `progress.csv`.
pub fn read_progress(dir: &Path) -> Result<Vec<ProgressRow>, CliError> {
    read_rows(&dir.join(PROGRESS))
}

fn complete_part(text: &str) -> &str {
    match text.rfind('\n') {
        Some(i) => &text[..=i],
        None => "",
    }
}

fn read_rows<T: serde::de::DeserializeOwned>(path: &Path) -> Result<Vec<T>, CliError> {
    if !path.exists() {
        return Ok(vec![]);
    }
    let text = std::fs::read_to_string(path).map_err(|e| failed(path, e))?;
    let mut rd = csv::Reader::from_reader(complete_part(&text).as_bytes());
    let mut out = vec![];
    for (i, r) in rd.deserialize().enumerate() {
        out.push(r.map_err(|e| {
            CliError::Input(magbench_env::InputError::new(
                path.display().to_string(),
                format!("row {}", i + 1),
                e.to_string(),
            ))
        })?);
    }
    Ok(out)
}

/// Makes the run files of `dir` consistent after an interruption and returns the ids of the
/// finished runs: drops a trailing partial line, duplicate rows (keeping the first) and
/// progress rows of unfinished runs.
pub fn repair(dir: &Path) -> Result<BTreeSet<String>, CliError> {
    let runs_path = dir.join(RUNS);
    if !runs_path.exists() {
        return Ok(BTreeSet::new());
    }
    let text = std::fs::read_to_string(&runs_path).map_err(|e| failed(&runs_path, e))?;
    if !text.is_empty() && !text.starts_with(&runs_header()) {
        if runs_header().starts_with(text.trim_end_matches('\n')) {
            // Killed while writing the header: no run finished.
            std::fs::remove_file(&runs_path).map_err(|e| failed(&runs_path, e))?;
            let _ = std::fs::remove_file(dir.join(PROGRESS));
            return Ok(BTreeSet::new());
        }
        return Err(CliError::Input(magbench_env::InputError::new(
            runs_path.display().to_string(),
            "header",
            "the columns differ from this version of magbench; write to a new --out folder",
        )));
    }
    let runs: Vec<RunRecord> = read_runs(dir)?;
    let mut done = BTreeSet::new();
    let kept: Vec<RunRecord> = runs
        .into_iter()
        .filter(|r| done.insert(r.run_id.clone()))
        .collect();
    let progress: Vec<ProgressRow> = read_progress(dir)?;
    let n_progress = progress.len();
    let kept_progress: Vec<ProgressRow> = progress
        .into_iter()
        .filter(|p| done.contains(&p.run_id))
        .collect();
    let runs_dirty = complete_part(&text).len() != text.len()
        || kept.len() != text.lines().count().saturating_sub(1);
    let progress_text = std::fs::read_to_string(dir.join(PROGRESS)).unwrap_or_default();
    let progress_dirty = kept_progress.len() != n_progress
        || complete_part(&progress_text).len() != progress_text.len();
    if runs_dirty {
        write_atomic(&runs_path, &runs_header(), &kept)?;
    }
    if progress_dirty {
        write_atomic(&dir.join(PROGRESS), &progress_header(), &kept_progress)?;
    }
    Ok(done)
}

/// Replaces `path` with `header` and `rows`, atomically (write a temporary file, then rename).
pub fn write_atomic<T: serde::Serialize>(
    path: &Path,
    header: &str,
    rows: &[T],
) -> Result<(), CliError> {
    let tmp = path.with_extension("csv.tmp");
    let mut bytes = format!("{header}\n").into_bytes();
    bytes.extend(record_bytes(rows));
    {
        let mut f = File::create(&tmp).map_err(|e| failed(&tmp, e))?;
        f.write_all(&bytes).map_err(|e| failed(&tmp, e))?;
        f.sync_all().map_err(|e| failed(&tmp, e))?;
    }
    std::fs::rename(&tmp, path).map_err(|e| failed(path, e))
}

/// Rewrites `runs.csv` and `progress.csv` of `dir` with `runs` sorted by run index and
/// `progress` by (run, iteration): the canonical order of a finished results folder.
pub fn write_sorted(
    dir: &Path,
    mut runs: Vec<RunRecord>,
    mut progress: Vec<ProgressRow>,
) -> Result<(), CliError> {
    runs.sort_by_key(|r| r.run);
    progress.sort_by(|a, b| {
        (a.run, a.iteration)
            .cmp(&(b.run, b.iteration))
            .then(a.time_s.total_cmp(&b.time_s))
    });
    write_atomic(&dir.join(RUNS), &runs_header(), &runs)?;
    write_atomic(&dir.join(PROGRESS), &progress_header(), &progress)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::Status;

    fn out(i: usize) -> RunOutput {
        let mut r = RunRecord::example();
        r.run = i;
        r.run_id = format!("s|p|-|-|{i}");
        r.status = Status::Exact;
        let progress = (0..3)
            .map(|k| ProgressRow {
                run: i,
                run_id: r.run_id.clone(),
                iteration: k * 10,
                time_s: k as f64,
                best_cost: Some(5.0),
            })
            .collect();
        RunOutput {
            record: r,
            progress,
        }
    }

    #[test]
    fn repair_drops_partial_lines_and_orphan_progress() {
        let dir = tempfile::tempdir().unwrap();
        let mut w = RunWriter::open(dir.path()).unwrap();
        w.write(&out(0)).unwrap();
        w.write(&out(1)).unwrap();
        drop(w);
        // A run killed after its progress rows, and a torn runs.csv line.
        let mut p = OpenOptions::new()
            .append(true)
            .open(dir.path().join(PROGRESS))
            .unwrap();
        p.write_all(&record_bytes(&out(2).progress)).unwrap();
        let mut r = OpenOptions::new()
            .append(true)
            .open(dir.path().join(RUNS))
            .unwrap();
        let line = record_bytes(&[out(2).record]);
        r.write_all(&line[..line.len() / 2]).unwrap();
        drop((p, r));
        let done = repair(dir.path()).unwrap();
        assert_eq!(done.len(), 2);
        assert_eq!(read_runs(dir.path()).unwrap().len(), 2);
        assert_eq!(read_progress(dir.path()).unwrap().len(), 6);
        // Appending after a repair gives well-formed files.
        let mut w = RunWriter::open(dir.path()).unwrap();
        w.write(&out(2)).unwrap();
        assert_eq!(read_runs(dir.path()).unwrap().len(), 3);
        assert_eq!(repair(dir.path()).unwrap().len(), 3);
    }

    #[test]
    fn a_torn_header_means_no_finished_run() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join(RUNS), &runs_header()[..10]).unwrap();
        assert!(repair(dir.path()).unwrap().is_empty());
        RunWriter::open(dir.path()).unwrap().write(&out(0)).unwrap();
        assert_eq!(read_runs(dir.path()).unwrap().len(), 1);
    }
}
