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

use crate::Error;
use crate::record::ProgressRow;
use crate::store::{self, PROGRESS, RUNS, Replacement, Snapshot};

/// The runs a folder may hold: those of one experiment (or shard of it).
pub struct Expected<'a> {
    /// The experiment's name (the `experiment` column).
    pub experiment: &'a str,
    /// The index in the run matrix of the run with this id, if the folder may hold it.
    pub index_of: &'a dyn Fn(&str) -> Option<usize>,
}

/// What a repair found.
#[derive(Debug, Clone, Default)]
pub struct Repaired {
    /// Indices of the finished runs that were kept, in increasing order.
    pub done: Vec<usize>,
    /// What was dropped or rebuilt, one line each.
    pub notes: Vec<String>,
}

fn other_version(path: &Path) -> Error {
    Error::Input(InputError::new(
        path.display().to_string(),
        "header",
        "the columns differ from this version of magbench; write to a new --out folder",
    ))
}

/// A run file as an interruption left it.
enum RunFile {
    /// There is none.
    Missing,
    /// It is empty, or its header was cut short: it holds no complete row.
    TornHeader,
    /// Its complete lines, and the bytes of a line cut short after them.
    Rows(Snapshot, u64),
}

impl RunFile {
    /// Opens the run file at `path`; a header that is whole but not `header_ok` is an error.
    fn open(
        path: &Path,
        torn_header: impl Fn(&str) -> bool,
        header_ok: impl Fn(&str) -> bool,
    ) -> Result<RunFile, Error> {
        let Some(snap) = Snapshot::open(path)? else {
            return Ok(RunFile::Missing);
        };
        let first = store::first_line(path)?.unwrap_or_default();
        if snap.lines() == 0 {
            // the whole file is its first line, unless it is longer than any header
            if snap.size() == first.len() as u64 && torn_header(&first) {
                return Ok(RunFile::TornHeader);
            }
            return Err(other_version(path));
        }
        if !header_ok(&first) {
            return Err(other_version(path));
        }
        let tail = snap.size() - snap.complete_len();
        Ok(RunFile::Rows(snap, tail))
    }

    fn exists(&self) -> bool {
        !matches!(self, RunFile::Missing)
    }

    fn snapshot(&self) -> Option<&Snapshot> {
        match self {
            RunFile::Rows(s, _) => Some(s),
            _ => None,
        }
    }

    fn torn_tail(&self) -> u64 {
        match self {
            RunFile::Rows(_, t) => *t,
            _ => 0,
        }
    }
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

/// What the run files hold of one run.
#[derive(Default, Clone, Copy)]
struct Held {
    /// Its rows in `runs.csv`.
    rows: u32,
    /// The trace points its (last) row records.
    recorded: Option<u64>,
    /// Its trace points in `progress.csv`.
    points: u64,
    /// Whether a trace point of its id gives another run index.
    misplaced: bool,
}

impl Held {
    /// Whether the run is whole: one row, and exactly the trace points it records.
    fn is_whole(&self) -> bool {
        self.rows == 1 && self.recorded == Some(self.points) && !self.misplaced
    }
}

/// Trace points written to a rewritten `progress.csv` at once.
const POINTS_PER_WRITE: usize = 4096;

/// Makes the run files of `dir` consistent after an interruption (see the module doc) and
/// returns the indices of the finished runs it kept. A row of a run that `expected` does not
/// hold (another experiment's results) is an error (exit 2). The files are read row by row,
/// and rewritten the same way if anything is dropped: what is held is a few numbers per run.
pub fn repair(dir: &Path, expected: &Expected) -> Result<Repaired, Error> {
    let runs_path = dir.join(RUNS);
    let progress_path = dir.join(PROGRESS);
    let runs = RunFile::open(&runs_path, store::is_torn_runs_header, |h| {
        store::header_agents(h).is_some()
    })?;
    let progress = RunFile::open(&progress_path, store::is_torn_progress_header, |h| {
        h == store::progress_header()
    })?;

    // every row of runs.csv: a run of the experiment, at its index
    let mut held: BTreeMap<usize, Held> = BTreeMap::new();
    let mut rows = 0usize;
    if let Some(s) = runs.snapshot() {
        for (i, r) in s.runs()?.enumerate() {
            let r = r?;
            if (expected.index_of)(&r.run_id) != Some(r.run) || r.experiment != expected.experiment
            {
                return Err(Error::Input(InputError::new(
                    runs_path.display().to_string(),
                    format!("row {}", i + 1),
                    format!(
                        "run {} (index {}, experiment {:?}) is not a run of experiment {:?} \
                         as given (or of this shard): the folder holds other results; write to \
                         a new --out folder",
                        r.run_id, r.run, r.experiment, expected.experiment
                    ),
                )));
            }
            let h = held.entry(r.run).or_default();
            h.rows += 1;
            h.recorded = r.progress_rows;
            rows += 1;
        }
    }
    // every trace point of progress.csv: counted to the run of its id
    let (mut points, mut orphans) = (0usize, 0usize);
    if let Some(s) = progress.snapshot() {
        for p in s.progress()? {
            let p = p?;
            points += 1;
            match (expected.index_of)(&p.run_id).and_then(|i| held.get_mut(&i).map(|h| (i, h))) {
                Some((i, h)) => {
                    h.points += 1;
                    h.misplaced |= p.run != i;
                }
                None => orphans += 1,
            }
        }
    }
    // in increasing order, as the map holds them
    let done: Vec<usize> = held
        .iter()
        .filter(|(_, h)| h.is_whole())
        .map(|(&i, _)| i)
        .collect();
    let kept_points: u64 = done.iter().map(|i| held[i].points).sum();

    // each damaged run once, in the order of runs.csv; and the kept rows, if any is dropped
    let (mut doubled, mut short, mut long) = (Tally::default(), Tally::default(), Tally::default());
    let rewrite_runs = runs.torn_tail() > 0 || done.len() != rows;
    let mut kept_rows = match (&runs, rewrite_runs) {
        (RunFile::Rows(..), true) => {
            let agents = store::file_agents(dir);
            Some((
                Replacement::create(&runs_path, &store::runs_header(agents))?,
                agents,
            ))
        }
        _ => None,
    };
    if let Some(s) = runs.snapshot() {
        let mut noted = BTreeSet::new();
        for r in s.runs()? {
            let r = r?;
            let h = held[&r.run];
            if h.is_whole() {
                if let Some((out, agents)) = kept_rows.as_mut() {
                    out.write(&store::run_bytes(std::slice::from_ref(&r), *agents))?;
                }
                continue;
            }
            if !noted.insert(r.run) {
                continue;
            }
            match r.progress_rows {
                _ if h.rows > 1 => doubled.add(&r.run_id),
                Some(k) if k < h.points || h.misplaced => long.add(&r.run_id),
                _ => short.add(&r.run_id),
            }
        }
    }

    let mut notes = vec![];
    if matches!(runs, RunFile::TornHeader) {
        notes.push(format!(
            "{RUNS}: the header was cut short: no run had finished"
        ));
    }
    if runs.torn_tail() > 0 {
        notes.push(format!(
            "{RUNS}: dropped a line cut short at the end ({} bytes)",
            runs.torn_tail()
        ));
    }
    if matches!(progress, RunFile::TornHeader) {
        notes.push(format!("{PROGRESS}: the header was cut short: rebuilt"));
    }
    if progress.torn_tail() > 0 {
        notes.push(format!(
            "{PROGRESS}: dropped a line cut short at the end ({} bytes)",
            progress.torn_tail()
        ));
    }
    if !progress.exists() && rows > 0 {
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

    if matches!(progress, RunFile::TornHeader)
        || progress.torn_tail() > 0
        || kept_points != points as u64
        || (!progress.exists() && runs.exists())
    {
        let mut out = Replacement::create(&progress_path, &store::progress_header())?;
        if let Some(s) = progress.snapshot() {
            let mut batch: Vec<ProgressRow> = Vec::with_capacity(POINTS_PER_WRITE);
            for p in s.progress()? {
                let p = p?;
                if (expected.index_of)(&p.run_id).is_some_and(|i| done.binary_search(&i).is_ok()) {
                    batch.push(p);
                }
                if batch.len() == POINTS_PER_WRITE {
                    out.write(&store::progress_bytes(&batch))?;
                    batch.clear();
                }
            }
            out.write(&store::progress_bytes(&batch))?;
        }
        out.commit()?;
    }
    if matches!(runs, RunFile::TornHeader) {
        std::fs::remove_file(&runs_path)
            .map_err(|e| Error::Failed(format!("{}: {e}", runs_path.display())))?;
    } else if let Some((out, _)) = kept_rows {
        out.commit()?;
    }
    Ok(Repaired { done, notes })
}

#[cfg(test)]
mod tests {
    use std::fs::OpenOptions;
    use std::io::Write;

    use super::*;
    use crate::store::tests::Out;
    use store::{RunWriter, read_progress, read_runs, runs_header};

    /// Run `i` of [`store::tests::out`] with an error text that needs quoting.
    fn out(i: usize) -> Out {
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

    /// Run `i` of the examples' experiment (unnamed) has the id `s|p|-|-|i`.
    fn index_of(id: &str) -> Option<usize> {
        id.strip_prefix("s|p|-|-|")?.parse().ok()
    }

    fn examples() -> Expected<'static> {
        Expected {
            experiment: "",
            index_of: &index_of,
        }
    }

    fn ids(dir: &Path) -> Vec<usize> {
        repair(dir, &examples()).unwrap().done.into_iter().collect()
    }

    #[test]
    fn partial_lines_and_orphan_progress_are_dropped() {
        let dir = tempfile::tempdir().unwrap();
        let mut w = RunWriter::open(dir.path(), 0).unwrap();
        w.write_out(&out(0)).unwrap();
        w.write_out(&out(1)).unwrap();
        drop(w);
        // A run killed after its progress rows, and a torn runs.csv line cut inside the quoted
        // error (after its newline, so a plain last-newline cut would take it as complete).
        append(dir.path(), PROGRESS, &csv_rows(&out(2).progress));
        let line = store::run_bytes(&[out(2).record], 0);
        let cut = line.windows(2).position(|w| w == b"\ne").unwrap() + 1;
        append(dir.path(), RUNS, &line[..cut]);
        let r = repair(dir.path(), &examples()).unwrap();
        assert_eq!(r.done.len(), 2, "{:?}", r.notes);
        assert_eq!(r.notes.len(), 2, "{:?}", r.notes);
        assert_eq!(read_runs(dir.path()).unwrap().len(), 2);
        assert_eq!(read_progress(dir.path()).unwrap().len(), 6);
        // Appending after a repair gives well-formed files.
        let mut w = RunWriter::open(dir.path(), 0).unwrap();
        w.write_out(&out(2)).unwrap();
        assert_eq!(read_runs(dir.path()).unwrap().len(), 3);
        let again = repair(dir.path(), &examples()).unwrap();
        assert_eq!((again.done.len(), again.notes.len()), (3, 0));
    }

    #[test]
    fn a_torn_header_means_no_finished_run() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join(RUNS), &runs_header(0)[..10]).unwrap();
        assert!(ids(dir.path()).is_empty());
        RunWriter::open(dir.path(), 0)
            .unwrap()
            .write_out(&out(0))
            .unwrap();
        assert_eq!(read_runs(dir.path()).unwrap().len(), 1);
    }

    #[test]
    fn a_run_whose_trace_is_short_long_or_doubled_runs_again() {
        let dir = tempfile::tempdir().unwrap();
        let mut w = RunWriter::open(dir.path(), 0).unwrap();
        for i in 0..4 {
            w.write_out(&out(i)).unwrap();
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
        let r = repair(dir.path(), &examples()).unwrap();
        assert_eq!(r.done.into_iter().collect::<Vec<_>>(), [3]);
        assert_eq!(r.notes.len(), 3, "{:?}", r.notes);
        assert_eq!(read_runs(dir.path()).unwrap().len(), 1);
        assert_eq!(read_progress(dir.path()).unwrap().len(), 3);
    }

    #[test]
    fn lost_runs_csv_drops_every_trace_and_lost_progress_redoes_traced_runs() {
        let dir = tempfile::tempdir().unwrap();
        let mut w = RunWriter::open(dir.path(), 0).unwrap();
        w.write_out(&out(0)).unwrap();
        let mut bare = out(1);
        bare.progress.clear();
        w.write_out(&bare).unwrap();
        drop(w);
        std::fs::remove_file(dir.path().join(PROGRESS)).unwrap();
        assert_eq!(ids(dir.path()), [1]);
        assert_eq!(read_progress(dir.path()).unwrap().len(), 0);
        let mut w = RunWriter::open(dir.path(), 0).unwrap();
        w.write_out(&out(0)).unwrap();
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
            .write_out(&out(0))
            .unwrap();
        // the row's id names index 0, which this experiment does not hold
        let none = |_: &str| None;
        let exp = Expected {
            experiment: "",
            index_of: &none,
        };
        let e = repair(dir.path(), &exp).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains("row 1"), "{e}");
    }
}
