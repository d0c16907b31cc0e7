//! Making the run files of an interrupted results folder consistent before a resume.
//!
//! `runs.csv`, `progress.csv` and the rows' trace counts are checked against each other:
//!
//! - a line cut short at the end of either file is dropped (and so its run runs again);
//! - a header cut short means the file held no complete row;
//! - a run is kept only if it has exactly one row and exactly `progress_rows` trace points in
//!   `progress.csv`; any other run (a missing or truncated trace, a doubled row or trace) runs
//!   again, and its partial rows and trace points are removed;
//! - trace points of runs without a row (in flight when the sweep stopped, or whose `runs.csv`
//!   was lost) are removed.
//!
//! So a resume never doubles a run and never keeps a run without its whole trace.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use magbench_env::InputError;

use super::store::{self, PROGRESS, RUNS};
use crate::Error;
use crate::run::{ProgressRow, RunRecord};

/// The runs a folder may hold: those of one experiment (or shard of it).
#[derive(Debug, Clone)]
pub struct Expected {
    /// The experiment's name (the `experiment` column).
    pub experiment: String,
    /// Run id → index in the run matrix.
    pub runs: BTreeMap<String, usize>,
}

/// What a repair found.
#[derive(Debug, Clone, Default)]
pub struct Repaired {
    /// Ids of the finished runs that were kept.
    pub done: BTreeSet<String>,
    /// What was dropped or rebuilt, one line each.
    pub notes: Vec<String>,
}

fn read_opt(path: &Path) -> Result<Option<String>, Error> {
    match std::fs::read(path) {
        Ok(b) => String::from_utf8(b).map(Some).map_err(|_| {
            Error::Input(InputError::new(
                path.display().to_string(),
                "",
                "not UTF-8 text: the file is damaged; write to a new --out folder",
            ))
        }),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(Error::Failed(format!("{}: {e}", path.display()))),
    }
}

fn other_version(path: &Path) -> Error {
    Error::Input(InputError::new(
        path.display().to_string(),
        "header",
        "the columns differ from this version of magbench; write to a new --out folder",
    ))
}

/// The complete rows of a run file, and the bytes of a line cut short at its end.
struct Loaded<T> {
    rows: Vec<T>,
    torn_tail: usize,
    /// The file exists but its header was cut short (or it is empty).
    torn_header: bool,
    exists: bool,
}

fn load<T>(
    path: &Path,
    text: Option<String>,
    torn_header: impl Fn(&str) -> bool,
    header_ok: impl Fn(&str) -> bool,
    parse: impl Fn(&Path, &str) -> Result<Vec<T>, Error>,
) -> Result<Loaded<T>, Error> {
    let Some(text) = text else {
        return Ok(Loaded {
            rows: vec![],
            torn_tail: 0,
            torn_header: false,
            exists: false,
        });
    };
    if text.is_empty() || torn_header(&text) {
        return Ok(Loaded {
            rows: vec![],
            torn_tail: 0,
            torn_header: true,
            exists: true,
        });
    }
    let n = store::complete_len(&text);
    let header = text.split('\n').next().unwrap_or_default();
    if n == 0 || !header_ok(header) {
        return Err(other_version(path));
    }
    Ok(Loaded {
        rows: parse(path, &text[..n])?,
        torn_tail: text.len() - n,
        torn_header: false,
        exists: true,
    })
}

/// Counts of one kind of damage, with the first run it hit.
#[derive(Default)]
struct Tally(usize, String);

impl Tally {
    fn add(&mut self, id: &str) {
        if self.0 == 0 {
            self.1 = id.to_string();
        }
        self.0 += 1;
    }

    fn note(&self, notes: &mut Vec<String>, what: &str) {
        if self.0 > 0 {
            notes.push(format!(
                "{} {what} (first: {}); they run again",
                self.0, self.1
            ));
        }
    }
}

/// Makes the run files of `dir` consistent after an interruption (see the module doc) and
/// returns the ids of the finished runs it kept. With `expected`, a row of a run that is not
/// in it (another experiment's results) is an error (exit 2).
pub fn repair(dir: &Path, expected: Option<&Expected>) -> Result<Repaired, Error> {
    let runs_path = dir.join(RUNS);
    let progress_path = dir.join(PROGRESS);
    let runs = load(
        &runs_path,
        read_opt(&runs_path)?,
        store::is_torn_runs_header,
        |h| store::header_agents(h).is_some(),
        store::parse_runs,
    )?;
    let progress = load(
        &progress_path,
        read_opt(&progress_path)?,
        store::is_torn_progress_header,
        |h| h == store::progress_header(),
        store::parse_progress,
    )?;
    let mut notes = vec![];
    if let Some(exp) = expected {
        for (i, r) in runs.rows.iter().enumerate() {
            if exp.runs.get(&r.run_id) != Some(&r.run) || r.experiment != exp.experiment {
                return Err(Error::Input(InputError::new(
                    runs_path.display().to_string(),
                    format!("row {}", i + 1),
                    format!(
                        "run {} (index {}, experiment {:?}) is not a run of experiment {:?} \
                         as given (or of this shard): the folder holds other results; write to \
                         a new --out folder",
                        r.run_id, r.run, r.experiment, exp.experiment
                    ),
                )));
            }
        }
    }
    let mut rows_of: BTreeMap<&str, usize> = BTreeMap::new();
    for r in &runs.rows {
        *rows_of.entry(&r.run_id).or_default() += 1;
    }
    let mut trace: BTreeMap<&str, (u64, bool)> = BTreeMap::new();
    let index: BTreeMap<&str, usize> = runs.rows.iter().map(|r| (&*r.run_id, r.run)).collect();
    for p in &progress.rows {
        let t = trace.entry(&p.run_id).or_insert((0, true));
        t.0 += 1;
        t.1 &= index.get(&*p.run_id) == Some(&p.run);
    }
    let (mut doubled, mut short, mut long) = (Tally::default(), Tally::default(), Tally::default());
    let mut done = BTreeSet::new();
    for r in &runs.rows {
        let (n, same_index) = trace.get(&*r.run_id).copied().unwrap_or((0, true));
        if rows_of[&*r.run_id] > 1 {
            if done.insert(r.run_id.clone()) {
                doubled.add(&r.run_id);
            }
            continue;
        }
        match r.progress_rows {
            Some(k) if k == n && same_index => {
                done.insert(r.run_id.clone());
            }
            Some(k) if k < n || !same_index => long.add(&r.run_id),
            _ => short.add(&r.run_id),
        }
    }
    // the doubled runs went in only to be counted once
    done.retain(|id| rows_of[&**id] == 1);
    let kept_runs: Vec<&RunRecord> = runs
        .rows
        .iter()
        .filter(|r| done.contains(&r.run_id))
        .collect();
    let kept_progress: Vec<&ProgressRow> = progress
        .rows
        .iter()
        .filter(|p| done.contains(&p.run_id))
        .collect();
    let orphans = progress
        .rows
        .iter()
        .filter(|p| !index.contains_key(&*p.run_id))
        .count();

    if runs.torn_header {
        notes.push(format!(
            "{RUNS}: the header was cut short: no run had finished"
        ));
    }
    if runs.torn_tail > 0 {
        notes.push(format!(
            "{RUNS}: dropped a line cut short at the end ({} bytes)",
            runs.torn_tail
        ));
    }
    if progress.torn_header {
        notes.push(format!("{PROGRESS}: the header was cut short: rebuilt"));
    }
    if progress.torn_tail > 0 {
        notes.push(format!(
            "{PROGRESS}: dropped a line cut short at the end ({} bytes)",
            progress.torn_tail
        ));
    }
    if !progress.exists && !runs.rows.is_empty() {
        notes.push(format!("{PROGRESS}: missing: rebuilt"));
    }
    if orphans > 0 {
        notes.push(format!(
            "{PROGRESS}: dropped {orphans} trace points of runs without a row in {RUNS} \
             (in flight when the sweep stopped, or their rows were lost)"
        ));
    }
    doubled.note(&mut notes, "runs had several rows in runs.csv");
    short.note(
        &mut notes,
        "runs had fewer trace points in progress.csv than their row records",
    );
    long.note(
        &mut notes,
        "runs had more trace points in progress.csv than their row records",
    );

    if progress.torn_header
        || progress.torn_tail > 0
        || kept_progress.len() != progress.rows.len()
        || (!progress.exists && runs.exists)
    {
        store::write_atomic(&progress_path, &store::progress_header(), &kept_progress)?;
    }
    if runs.torn_header {
        std::fs::remove_file(&runs_path)
            .map_err(|e| Error::Failed(format!("{}: {e}", runs_path.display())))?;
    } else if runs.torn_tail > 0 || kept_runs.len() != runs.rows.len() {
        let agents = store::file_agents(dir);
        let kept: Vec<RunRecord> = kept_runs.into_iter().cloned().collect();
        store::write_runs_atomic(&runs_path, agents, &kept)?;
    }
    Ok(Repaired { done, notes })
}

#[cfg(test)]
mod tests {
    use std::fs::OpenOptions;
    use std::io::Write;

    use super::*;
    use crate::run::RunOutput;
    use store::{RunWriter, read_progress, read_runs, runs_header};

    /// Run `i` of [`store::tests::out`] with an error text that needs quoting.
    fn out(i: usize) -> RunOutput {
        let mut o = store::tests::out(i);
        o.record.error = "a \"quoted\"\nerror".into();
        o
    }

    fn append(dir: &Path, name: &str, bytes: &[u8]) {
        OpenOptions::new()
            .append(true)
            .open(dir.join(name))
            .unwrap()
            .write_all(bytes)
            .unwrap();
    }

    fn csv_rows<T: serde::Serialize>(rows: &[T]) -> Vec<u8> {
        let mut w = csv::WriterBuilder::new()
            .has_headers(false)
            .from_writer(vec![]);
        for r in rows {
            w.serialize(r).unwrap();
        }
        w.into_inner().unwrap()
    }

    fn ids(dir: &Path) -> Vec<String> {
        repair(dir, None).unwrap().done.into_iter().collect()
    }

    #[test]
    fn partial_lines_and_orphan_progress_are_dropped() {
        let dir = tempfile::tempdir().unwrap();
        let mut w = RunWriter::open(dir.path(), 0).unwrap();
        w.write(&out(0)).unwrap();
        w.write(&out(1)).unwrap();
        drop(w);
        // A run killed after its progress rows, and a torn runs.csv line cut inside the quoted
        // error (after its newline, so a plain last-newline cut would take it as complete).
        append(dir.path(), PROGRESS, &csv_rows(&out(2).progress));
        let line = store::run_bytes(&[out(2).record], 0);
        let cut = line.windows(2).position(|w| w == b"\ne").unwrap() + 1;
        append(dir.path(), RUNS, &line[..cut]);
        let r = repair(dir.path(), None).unwrap();
        assert_eq!(r.done.len(), 2, "{:?}", r.notes);
        assert_eq!(r.notes.len(), 2, "{:?}", r.notes);
        assert_eq!(read_runs(dir.path()).unwrap().len(), 2);
        assert_eq!(read_progress(dir.path()).unwrap().len(), 6);
        // Appending after a repair gives well-formed files.
        let mut w = RunWriter::open(dir.path(), 0).unwrap();
        w.write(&out(2)).unwrap();
        assert_eq!(read_runs(dir.path()).unwrap().len(), 3);
        let again = repair(dir.path(), None).unwrap();
        assert_eq!((again.done.len(), again.notes.len()), (3, 0));
    }

    #[test]
    fn a_torn_header_means_no_finished_run() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join(RUNS), &runs_header(0)[..10]).unwrap();
        assert!(ids(dir.path()).is_empty());
        RunWriter::open(dir.path(), 0)
            .unwrap()
            .write(&out(0))
            .unwrap();
        assert_eq!(read_runs(dir.path()).unwrap().len(), 1);
    }

    #[test]
    fn a_run_whose_trace_is_short_long_or_doubled_runs_again() {
        let dir = tempfile::tempdir().unwrap();
        let mut w = RunWriter::open(dir.path(), 0).unwrap();
        for i in 0..4 {
            w.write(&out(i)).unwrap();
        }
        drop(w);
        // run 0 loses a trace point, run 1 gets one more, run 2's row is doubled
        let mut p = read_progress(dir.path()).unwrap();
        p.remove(0);
        p.push(out(1).progress[0].clone());
        store::write_atomic(&dir.path().join(PROGRESS), &store::progress_header(), &p).unwrap();
        let mut row = out(2).record;
        row.progress_rows = Some(3);
        append(dir.path(), RUNS, &store::run_bytes(&[row], 0));
        let r = repair(dir.path(), None).unwrap();
        assert_eq!(r.done.into_iter().collect::<Vec<_>>(), ["s|p|-|-|3"]);
        assert_eq!(r.notes.len(), 3, "{:?}", r.notes);
        assert_eq!(read_runs(dir.path()).unwrap().len(), 1);
        assert_eq!(read_progress(dir.path()).unwrap().len(), 3);
    }

    #[test]
    fn lost_runs_csv_drops_every_trace_and_lost_progress_redoes_traced_runs() {
        let dir = tempfile::tempdir().unwrap();
        let mut w = RunWriter::open(dir.path(), 0).unwrap();
        w.write(&out(0)).unwrap();
        let mut bare = out(1);
        bare.progress.clear();
        w.write(&bare).unwrap();
        drop(w);
        std::fs::remove_file(dir.path().join(PROGRESS)).unwrap();
        assert_eq!(ids(dir.path()), ["s|p|-|-|1"]);
        assert_eq!(read_progress(dir.path()).unwrap().len(), 0);
        let mut w = RunWriter::open(dir.path(), 0).unwrap();
        w.write(&out(0)).unwrap();
        drop(w);
        std::fs::remove_file(dir.path().join(RUNS)).unwrap();
        assert!(ids(dir.path()).is_empty());
        assert_eq!(read_progress(dir.path()).unwrap().len(), 0);
    }

    #[test]
    fn rows_of_another_experiment_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        RunWriter::open(dir.path(), 0)
            .unwrap()
            .write(&out(0))
            .unwrap();
        let exp = Expected {
            experiment: String::new(),
            runs: [("s|p|-|-|0".to_string(), 1)].into(),
        };
        let e = repair(dir.path(), Some(&exp)).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains("row 1"), "{e}");
    }
}
