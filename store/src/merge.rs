//! Merging shard folders into one results folder.
//!
//! The shards' `runs.csv` and `progress.csv` are read a record at a time and merged by run
//! index (a k-way merge); each record is copied as it is in its shard's file (widened with empty
//! cells when its header has fewer agents' columns), so the merged files hold the shards' bytes;
//! the rows of a file with another version's columns are read by name and written again.
//! A shard in run order holds one run in memory at a time, so the merge of the run files holds
//! a run per shard, whatever the number of runs; a shard out of run order (a task at several
//! threads that did not finish) is read whole and sorted first. Before anything is written,
//! every shard's rows are read once for their order and parsed whole (a bad row is refused
//! naming its shard's file). What a folder holds besides its runs (replay pages, scenario
//! previews, the report) is copied and written by the caller's [`Derived`].

use std::cmp::{Ordering, Reverse};
use std::collections::BinaryHeap;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use magbench_env::InputError;

use crate::Error;
use crate::manifest::{Manifest, Session, host, now};
use crate::store;

/// What a results folder holds besides its runs, which a merge copies from the shards and
/// derives once the runs are merged.
pub trait Derived {
    /// Copies what `shard` holds for all its runs (each scenario's preview) into `out`.
    fn copy_shared(&mut self, shard: &Path, out: &Path) -> Result<(), Error>;
    /// Copies what `shard` holds for run `run` (its replay page) into `out`.
    fn copy_run(&mut self, shard: &Path, out: &Path, run: usize) -> Result<(), Error>;
    /// Writes `out`'s derived files once its runs and manifest are written.
    fn finish(&mut self, out: &Path) -> Result<(), Error>;
}

/// Merges the results folders `shards` (of the same experiment) into `out`, which must not
/// hold results, and writes its derived files by `derived`, holding `out`'s lock throughout
/// (exit 2 if another process holds it). Only whole runs are taken (one row, and exactly the
/// trace points the row records); a run found in several folders is taken from the first.
pub fn merge(shards: &[PathBuf], out: &Path, derived: &mut dyn Derived) -> Result<Manifest, Error> {
    if shards.is_empty() {
        return Err(Error::Input(InputError::new(
            "<command line>",
            "DIR",
            "give at least one results folder to merge",
        )));
    }
    std::fs::create_dir_all(out).map_err(|e| Error::Failed(format!("{}: {e}", out.display())))?;
    let _lock = crate::lock::exclusive(out, "merge", "--out")?;
    if out.join(super::MANIFEST).exists() {
        return Err(Error::Input(InputError::new(
            out.display().to_string(),
            "--out",
            "already holds results; choose another --out",
        )));
    }
    let t0 = std::time::Instant::now();
    // Each shard's manifest is read, checked against the first and let go: a manifest lists
    // its experiment's seeds, which a million runs' experiment has by the hundred thousand.
    let first = Manifest::read(&shards[0])?;
    same_version(&shards[0], &first)?;
    let mut kept = Kept::of(&first);
    for s in &shards[1..] {
        let m = Manifest::read(s)?;
        same_version(s, &m)?;
        same_experiment(s, &m, (&shards[0], &first))?;
        kept.add(&m);
    }
    kept.revisions.sort();
    kept.revisions.dedup();
    if kept.revisions.len() > 1 {
        eprintln!(
            "note: the shards were run by {} builds of magbench {} (git revisions {}): their runs \
             may differ by more than their seeds",
            kept.revisions.len(),
            first.magbench_version,
            kept.revisions.join(", ")
        );
    }
    // Each shard's files are opened once, up to their complete lines: a task may still be
    // writing them, and every pass reads the same rows.
    let mut sources = vec![];
    for s in shards {
        sources.push(Source::open(s)?);
    }
    let agents = sources.iter().map(|s| s.agents).max().unwrap_or(0);
    let runs_tmp = out.join(format!("{}.tmp", store::RUNS));
    let progress_tmp = out.join(format!("{}.tmp", store::PROGRESS));
    let mut runs_out = Output::create(&runs_tmp, &store::runs_header(agents))?;
    let mut progress_out = Output::create(&progress_tmp, &store::progress_header())?;
    let mut streams = vec![];
    for s in &sources {
        streams.push(s.whole_runs(agents)?);
    }
    // A k-way merge by run index: the next run is the smallest head, the first folder's on a
    // tie, and a run index already written is skipped (the same run in a later folder).
    let mut heads: BinaryHeap<Reverse<(usize, usize)>> = BinaryHeap::new();
    let mut pending: Vec<Option<WholeRun>> = Vec::with_capacity(streams.len());
    for (k, st) in streams.iter_mut().enumerate() {
        let head = st.next().transpose()?;
        if let Some(h) = &head {
            heads.push(Reverse((h.row.key.run, k)));
        }
        pending.push(head);
    }
    for s in shards {
        derived.copy_shared(s, out)?;
    }
    let mut last: Option<usize> = None;
    while let Some(Reverse((run, k))) = heads.pop() {
        let w = pending[k].take().expect("a head for every heap entry");
        if last != Some(run) {
            derived.copy_run(&shards[k], out, run)?;
            for p in &w.trace {
                progress_out.write(&p.bytes)?;
            }
            runs_out.write(&w.row.bytes)?;
            last = Some(run);
        }
        if let Some(h) = streams[k].next().transpose()? {
            heads.push(Reverse((h.row.key.run, k)));
            pending[k] = Some(h);
        }
    }
    for (s, st) in shards.iter().zip(&streams) {
        if st.left_out > 0 {
            eprintln!(
                "note: {}: {} runs left out: their rows are doubled or their traces \
                 incomplete (`bench --resume` on that folder repairs them)",
                s.display(),
                st.left_out
            );
        }
    }
    runs_out.finish(&out.join(store::RUNS))?;
    progress_out.finish(&out.join(store::PROGRESS))?;
    let mut m = first;
    m.shard = None;
    m.merged_from = shards.iter().map(|s| s.display().to_string()).collect();
    (m.started, m.sessions, m.threads) = (kept.started, kept.sessions, kept.threads);
    m.sessions.push(Session {
        kind: "merge".into(),
        started: now(),
        finished: Some(now()),
        threads: 1,
        runs_executed: 0,
        wall_time_s: Some(t0.elapsed().as_secs_f64()),
        host: host(),
    });
    m.files.clear();
    m.write(out)?;
    derived.finish(out)?;
    crate::verify::require_sound(out, false)?;
    Manifest::read(out)
}

/// What the merged manifest takes of the shards' manifests: their first start, sessions,
/// most threads and git revisions.
struct Kept {
    started: String,
    sessions: Vec<Session>,
    threads: usize,
    revisions: Vec<String>,
}

impl Kept {
    /// What `m` gives.
    fn of(m: &Manifest) -> Kept {
        Kept {
            started: m.started.clone(),
            sessions: m.sessions.clone(),
            threads: m.threads,
            revisions: vec![m.git_revision.clone()],
        }
    }

    /// Adds what `m` gives.
    fn add(&mut self, m: &Manifest) {
        self.started = self.started.clone().min(m.started.clone());
        self.sessions.extend(m.sessions.iter().cloned());
        self.threads = self.threads.max(m.threads);
        self.revisions.push(m.git_revision.clone());
    }
}

/// Refuses shard `dir`, whose manifest is `m`, unless this version of magbench wrote it.
fn same_version(dir: &Path, m: &Manifest) -> Result<(), Error> {
    let this = env!("CARGO_PKG_VERSION");
    if m.magbench_version != this {
        return Err(Error::Input(InputError::new(
            dir.join(super::MANIFEST).display().to_string(),
            "magbench_version",
            format!(
                "written by magbench {}, and this is magbench {this}: merge shards with the \
                 version that ran them",
                m.magbench_version
            ),
        )));
    }
    Ok(())
}

/// Refuses shard `dir`, whose manifest is `m`, unless it ran the experiment of `first` (the
/// first shard's folder and manifest).
fn same_experiment(dir: &Path, m: &Manifest, first: (&Path, &Manifest)) -> Result<(), Error> {
    if m.experiment.sha256 != first.1.experiment.sha256 {
        return Err(Error::Input(InputError::new(
            dir.display().to_string(),
            "manifest.json",
            format!(
                "experiment {} (sha256 {}) differs from {} in {}",
                m.experiment.name,
                &m.experiment.sha256[..12],
                &first.1.experiment.sha256[..12],
                first.0.display()
            ),
        )));
    }
    Ok(())
}

/// One shard folder's run files, opened once, and what a first read of them found.
struct Source {
    runs: Option<store::Snapshot>,
    progress: Option<store::Snapshot>,
    /// Whether `runs.csv` is in run order and `progress.csv` in (run, iteration, time) order,
    /// as a finished folder and a task at one thread write them.
    sorted: bool,
    /// The per-agent columns of its `runs.csv` (0 without one; for a header of another
    /// version, the largest tracked team of its rows).
    agents: usize,
    /// Whether each file's header is this version's, so that its records are copied as they
    /// are (`runs.csv`, `progress.csv`); a file of another version's columns is read by name and
    /// written again.
    copied: [bool; 2],
}

impl Source {
    /// Opens the run files of `dir` (`runs.csv` first: a run's progress rows are written before
    /// its row, so every row read has its trace in the `progress.csv` opened after it) and reads
    /// them once, a record at a time, for their headers, order and cells.
    fn open(dir: &Path) -> Result<Source, Error> {
        let runs = store::Snapshot::open(&dir.join(store::RUNS))?;
        let progress = store::Snapshot::open(&dir.join(store::PROGRESS))?;
        let mut sorted = true;
        let (mut agents, mut copied) = (0, [true; 2]);
        if let Some(r) = &runs {
            let header = Records::runs(r)?.agents;
            // every row parsed whole: a shard's bad row is refused before anything is written
            let (mut prev, mut tracked) = (None, 0);
            for row in r.runs()? {
                let row = row?;
                sorted &= prev.is_none_or(|p| p <= row.run);
                prev = Some(row.run);
                tracked = tracked.max(store::tracked_agents([&row]));
            }
            agents = header.unwrap_or(tracked);
            copied[0] = header.is_some();
        }
        if let Some(p) = &progress {
            let mut rows = Records::progress(p)?;
            copied[1] = rows.agents.is_some();
            let mut prev: Option<Point> = None;
            let mut order = |point: Point| {
                sorted &= prev.is_none_or(|p| p.cmp(&point) != Ordering::Greater);
                prev = Some(point);
            };
            if copied[1] {
                while let Some((point, _)) = rows.next_key()? {
                    order(point);
                }
            } else {
                for row in p.progress()? {
                    order(Point::of(&row?));
                }
            }
        }
        Ok(Source {
            runs,
            progress,
            sorted,
            agents,
            copied,
        })
    }

    /// The folder's whole runs in run order, their rows widened to `agents` agents' columns:
    /// streamed from files already in order, else read whole and sorted (one folder's runs: a
    /// task that ran several threads and did not finish).
    fn whole_runs(&self, agents: usize) -> Result<WholeRuns, Error> {
        let widen = agents.saturating_sub(self.agents) * crate::record::agent_columns(0).len();
        let mut runs: RecordIter<RunKey> = match &self.runs {
            Some(r) if self.copied[0] => Box::new(Records::runs(r)?.widened(widen)),
            Some(r) => Box::new(r.runs()?.map(move |row| {
                let row = row?;
                Ok(Record {
                    key: RunKey {
                        run: row.run,
                        progress_rows: row.progress_rows,
                    },
                    bytes: store::run_bytes(std::slice::from_ref(&row), agents),
                })
            })),
            None => Box::new(std::iter::empty()),
        };
        let mut progress: RecordIter<Point> = match &self.progress {
            Some(p) if self.copied[1] => Box::new(Records::progress(p)?),
            Some(p) => Box::new(p.progress()?.map(|row| {
                let row = row?;
                Ok(Record {
                    key: Point::of(&row),
                    bytes: store::progress_bytes(std::slice::from_ref(&row)),
                })
            })),
            None => Box::new(std::iter::empty()),
        };
        if !self.sorted {
            let mut r = runs.collect::<Result<Vec<_>, _>>()?;
            let mut p = progress.collect::<Result<Vec<_>, _>>()?;
            r.sort_by_key(|r| r.key.run);
            p.sort_by(|a, b| a.key.cmp(&b.key));
            runs = Box::new(r.into_iter().map(Ok));
            progress = Box::new(p.into_iter().map(Ok));
        }
        Ok(WholeRuns {
            runs: runs.peekable(),
            progress: progress.peekable(),
            left_out: 0,
        })
    }
}

/// What the merge reads of a `runs.csv` row.
#[derive(Debug, Clone, Copy)]
struct RunKey {
    run: usize,
    /// The trace points the row records (`None`: a row of an older version).
    progress_rows: Option<u64>,
}

/// What the merge reads of a `progress.csv` row: its run, and its order within the run.
#[derive(Debug, Clone, Copy)]
struct Point {
    run: usize,
    iteration: u64,
    time_s: f64,
}

impl Point {
    /// The point of a progress row.
    fn of(row: &crate::record::ProgressRow) -> Point {
        Point {
            run: row.run,
            iteration: row.iteration,
            time_s: row.time_s,
        }
    }

    /// The order of progress rows in a finished folder: by run, iteration, then time.
    fn cmp(&self, other: &Point) -> Ordering {
        (self.run, self.iteration)
            .cmp(&(other.run, other.iteration))
            .then(self.time_s.total_cmp(&other.time_s))
    }
}

/// A record of a run file: its bytes as they are in the file (with its line end), and its key.
struct Record<K> {
    key: K,
    bytes: Vec<u8>,
}

type RecordIter<K> = Box<dyn Iterator<Item = Result<Record<K>, Error>>>;

/// The most columns a key reads.
const KEY_COLUMNS: usize = 4;

/// The records of a run file after its header, one at a time: each record's cells are read for
/// its key, and its bytes are copied from the file as they are.
struct Records<K> {
    path: PathBuf,
    cells: csv::Reader<std::io::Take<std::io::BufReader<std::fs::File>>>,
    /// The same bytes, read alongside the cells.
    bytes: std::io::Take<std::io::BufReader<std::fs::File>>,
    record: csv::ByteRecord,
    /// The key's columns in the header.
    columns: Vec<usize>,
    key: fn(&[Option<&str>]) -> Result<K, String>,
    row: usize,
    /// Empty cells appended to each record (the per-agent columns its header lacks).
    widen: usize,
    /// The per-agent columns of its header (`None`: not this version's header).
    agents: Option<usize>,
}

impl Records<RunKey> {
    /// The rows of `runs.csv`, copied as they are when its header is this version's.
    fn runs(snap: &store::Snapshot) -> Result<Records<RunKey>, Error> {
        Records::open(
            snap,
            &["run", "progress_rows"],
            |c| {
                Ok(RunKey {
                    run: parse("run", c[0])?,
                    progress_rows: c[1]
                        .filter(|v| !v.is_empty())
                        .map(|v| parse("progress_rows", Some(v)))
                        .transpose()?,
                })
            },
            store::header_agents,
        )
    }

    /// The same records, each widened by `cells` empty cells.
    fn widened(mut self, cells: usize) -> Self {
        self.widen = cells;
        self
    }
}

impl Records<Point> {
    /// The rows of `progress.csv`, copied as they are when its header is this version's.
    fn progress(snap: &store::Snapshot) -> Result<Records<Point>, Error> {
        Records::open(
            snap,
            &["run", "iteration", "time_s", "best_cost"],
            |c| {
                if let Some(v) = c[3].filter(|v| !v.is_empty()) {
                    parse::<f64>("best_cost", Some(v))?;
                }
                Ok(Point {
                    run: parse("run", c[0])?,
                    iteration: parse("iteration", c[1])?,
                    time_s: parse("time_s", c[2])?,
                })
            },
            |h| (h == store::progress_header()).then_some(0),
        )
    }
}

/// The value of cell `name` (`None`: the record has no such cell), parsed.
fn parse<T: std::str::FromStr>(name: &str, cell: Option<&str>) -> Result<T, String>
where
    T::Err: std::fmt::Display,
{
    let v = cell.ok_or_else(|| format!("no `{name}` cell"))?;
    v.parse().map_err(|e| format!("{name}: {v:?}: {e}"))
}

impl<K> Records<K> {
    /// Opens `snap`'s records after its header, which `agents` finds this version's (giving its
    /// per-agent columns) or not; `key` reads a record's key from its cells of `columns`.
    fn open(
        snap: &store::Snapshot,
        columns: &[&str],
        key: fn(&[Option<&str>]) -> Result<K, String>,
        agents: impl Fn(&str) -> Option<usize>,
    ) -> Result<Records<K>, Error> {
        debug_assert!(
            columns.len() <= KEY_COLUMNS,
            "a key of at most {KEY_COLUMNS} columns"
        );
        let path = snap.path().to_path_buf();
        let mut cells = csv::ReaderBuilder::new()
            .has_headers(false)
            .from_reader(snap.reader()?);
        let file = std::fs::File::open(&path).map_err(|e| store::failed(&path, e))?;
        let mut bytes = std::io::BufReader::new(file).take(snap.complete_len());
        let mut header = csv::StringRecord::new();
        let read = cells
            .read_record(&mut header)
            .map_err(|e| store::bad_row(&path, 0, e.to_string()))?;
        let len = cells.position().byte();
        std::io::copy(&mut (&mut bytes).take(len), &mut std::io::sink())
            .map_err(|e| store::failed(&path, e))?;
        let line = header.iter().collect::<Vec<_>>().join(",");
        let agents = if read { agents(&line) } else { Some(0) };
        let columns = columns
            .iter()
            .map(|c| header.iter().position(|h| h == *c).unwrap_or(usize::MAX))
            .collect();
        Ok(Records {
            path,
            cells,
            bytes,
            record: csv::ByteRecord::new(),
            columns,
            key,
            row: 0,
            widen: 0,
            agents,
        })
    }

    /// The next record's key and length in bytes (`None`: no more), its bytes not read.
    fn next_key(&mut self) -> Result<Option<(K, usize)>, Error> {
        let start = self.cells.position().byte();
        self.row += 1;
        let bad = |row, e: String| store::bad_row(&self.path, row, e);
        if !self
            .cells
            .read_byte_record(&mut self.record)
            .map_err(|e| bad(self.row, e.to_string()))?
        {
            return Ok(None);
        }
        let mut cells = [None; KEY_COLUMNS];
        for (cell, &c) in cells.iter_mut().zip(&self.columns) {
            *cell = self.record.get(c).and_then(|v| std::str::from_utf8(v).ok());
        }
        let key = (self.key)(&cells).map_err(|e| bad(self.row, e))?;
        Ok(Some((key, (self.cells.position().byte() - start) as usize)))
    }

    /// The next record (`None`: no more).
    fn next_record(&mut self) -> Result<Option<Record<K>>, Error> {
        let Some((key, len)) = self.next_key()? else {
            return Ok(None);
        };
        let mut bytes = vec![0; len];
        self.bytes
            .read_exact(&mut bytes)
            .map_err(|e| store::failed(&self.path, e))?;
        if self.widen > 0 && bytes.pop() == Some(b'\n') {
            bytes.extend(std::iter::repeat_n(b',', self.widen));
            bytes.push(b'\n');
        }
        Ok(Some(Record { key, bytes }))
    }
}

impl<K> Iterator for Records<K> {
    type Item = Result<Record<K>, Error>;

    fn next(&mut self) -> Option<Self::Item> {
        self.next_record().transpose()
    }
}

/// One run's row and its trace, as they are in its folder's files.
struct WholeRun {
    row: Record<RunKey>,
    trace: Vec<Record<Point>>,
}

/// The whole runs of one folder's rows and trace points, both in run order, one run at a time:
/// runs with one row whose trace has exactly the points the row records (any trace for rows of
/// older versions, which record none). Trace points of runs without a row are skipped.
struct WholeRuns {
    runs: std::iter::Peekable<RecordIter<RunKey>>,
    progress: std::iter::Peekable<RecordIter<Point>>,
    /// Runs left out so far: doubled rows, or a trace of another length than the row records.
    left_out: usize,
}

impl Iterator for WholeRuns {
    type Item = Result<WholeRun, Error>;

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            let row = match self.runs.next()? {
                Ok(r) => r,
                Err(e) => return Some(Err(e)),
            };
            let run = row.key.run;
            let mut rows = 1;
            while let Some(Ok(r)) = self.runs.peek() {
                if r.key.run != run {
                    break;
                }
                rows += 1;
                self.runs.next();
            }
            let mut trace = vec![];
            while let Some(p) = self.progress.peek() {
                match p {
                    Ok(p) if p.key.run > run => break,
                    Ok(p) if p.key.run == run => {}
                    Ok(_) => {
                        self.progress.next();
                        continue;
                    }
                    Err(_) => {
                        let Some(Err(e)) = self.progress.next() else {
                            unreachable!("the row just peeked")
                        };
                        return Some(Err(e));
                    }
                }
                if let Some(Ok(p)) = self.progress.next() {
                    trace.push(p);
                }
            }
            let whole = row
                .key
                .progress_rows
                .is_none_or(|k| trace.len() as u64 == k);
            if rows == 1 && whole {
                return Some(Ok(WholeRun { row, trace }));
            }
            self.left_out += 1;
        }
    }
}

/// A file written in whole, under a temporary name, then renamed into place.
struct Output {
    path: PathBuf,
    file: std::io::BufWriter<std::fs::File>,
}

impl Output {
    fn create(path: &Path, header: &str) -> Result<Output, Error> {
        let file = std::fs::File::create(path)
            .map_err(|e| Error::Failed(format!("{}: {e}", path.display())))?;
        let mut o = Output {
            path: path.to_path_buf(),
            file: std::io::BufWriter::new(file),
        };
        o.write(format!("{header}\n").as_bytes())?;
        Ok(o)
    }

    fn write(&mut self, bytes: &[u8]) -> Result<(), Error> {
        self.file
            .write_all(bytes)
            .map_err(|e| Error::Failed(format!("{}: {e}", self.path.display())))
    }

    /// Syncs the file and renames it to `to`.
    fn finish(self, to: &Path) -> Result<(), Error> {
        let fail = |e: std::io::Error| Error::Failed(format!("{}: {e}", self.path.display()));
        let file = self.file.into_inner().map_err(|e| fail(e.into_error()))?;
        file.sync_all().map_err(fail)?;
        std::fs::rename(&self.path, to).map_err(fail)?;
        store::sync_dir(to)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::store::RunWriter;
    use crate::store::tests::out;

    fn runs_of(dir: &Path) -> (Vec<usize>, Vec<usize>, usize, bool) {
        let s = Source::open(dir).unwrap();
        let mut w = s.whole_runs(s.agents).unwrap();
        let mut runs = vec![];
        let mut points = vec![];
        for r in w.by_ref() {
            let r = r.unwrap();
            runs.push(r.row.key.run);
            points.extend(r.trace.iter().map(|p| p.key.run));
        }
        (runs, points, w.left_out, s.sorted)
    }

    #[test]
    fn whole_runs_stream_in_order_and_leave_out_torn_and_doubled_runs() {
        let dir = tempfile::tempdir().unwrap();
        let mut w = RunWriter::open(dir.path(), 0).unwrap();
        for i in [0, 1, 3] {
            w.write_out(&out(i)).unwrap();
        }
        drop(w);
        // run 4's trace without its row, and half of a row: a run in flight
        let p = dir.path().join(store::PROGRESS);
        let mut trace = std::fs::read_to_string(&p).unwrap();
        trace += "4,s|p|-|-|4,0,0.0,\n";
        std::fs::write(&p, trace).unwrap();
        let r = dir.path().join(store::RUNS);
        let mut rows = std::fs::read_to_string(&r).unwrap();
        rows += "4,s|p|-|-|4,exp";
        std::fs::write(&r, rows).unwrap();
        assert_eq!(
            runs_of(dir.path()),
            (vec![0, 1, 3], vec![0, 0, 0, 1, 1, 1, 3, 3, 3], 0, true)
        );

        // out of order (several threads), run 1 doubled, run 2's trace a point short
        let dir = tempfile::tempdir().unwrap();
        let mut w = RunWriter::open(dir.path(), 0).unwrap();
        for i in [3, 1, 2, 0, 1] {
            w.write_out(&out(i)).unwrap();
        }
        drop(w);
        let p = dir.path().join(store::PROGRESS);
        let trace = std::fs::read_to_string(&p).unwrap();
        let first_of_2 = trace.find("\n2,").unwrap() + 1;
        let end = first_of_2 + trace[first_of_2..].find('\n').unwrap() + 1;
        std::fs::write(&p, format!("{}{}", &trace[..first_of_2], &trace[end..])).unwrap();
        let (runs, points, left_out, sorted) = runs_of(dir.path());
        assert_eq!((runs, left_out, sorted), (vec![0, 3], 2, false));
        assert_eq!(points, vec![0, 0, 0, 3, 3, 3]);
    }

    #[test]
    fn rows_are_copied_as_they_are_and_widened_to_the_widest_header() {
        let narrow = tempfile::tempdir().unwrap();
        let mut w = RunWriter::open(narrow.path(), 0).unwrap();
        w.write_out(&out(0)).unwrap();
        drop(w);
        let s = Source::open(narrow.path()).unwrap();
        assert_eq!(s.agents, 0);
        let rows = std::fs::read_to_string(narrow.path().join(store::RUNS)).unwrap();
        let row = rows.lines().nth(1).unwrap();
        let as_is = s.whole_runs(0).unwrap().next().unwrap().unwrap();
        assert_eq!(as_is.row.bytes, format!("{row}\n").into_bytes());
        let trace = std::fs::read_to_string(narrow.path().join(store::PROGRESS)).unwrap();
        let copied: Vec<u8> = as_is.trace.iter().flat_map(|p| p.bytes.clone()).collect();
        assert_eq!(copied, trace.split_once('\n').unwrap().1.as_bytes());
        // under a header with two agents' columns: eight empty cells more
        let wide = s.whole_runs(2).unwrap().next().unwrap().unwrap();
        let text = String::from_utf8(wide.row.bytes).unwrap();
        assert_eq!(text, format!("{row},,,,,,,,\n"));
        let header = csv::StringRecord::from(store::runs_header(2).split(',').collect::<Vec<_>>());
        let cells = csv::ReaderBuilder::new()
            .has_headers(false)
            .from_reader(text.as_bytes())
            .records()
            .next()
            .unwrap()
            .unwrap();
        assert_eq!(cells.len(), header.len());
    }

    #[test]
    fn rows_of_another_versions_columns_are_read_by_name_and_written_again() {
        let dir = tempfile::tempdir().unwrap();
        // the header of a version before the per-agent and worst-agent columns, and a row
        let old = "run,run_id,experiment,scenario,agents,planner,planner_name,planner_params,tracker,preset,seed,max_iterations,time_limit_s,status,solved,approximate,iterations,nodes,plan_time_s,cost,goal_distance,first_solution_iteration,first_solution_time_s,plan_edges,plan_duration_s,track_status,reached_goal,time_to_goal_s,rms_error_bl,max_error_bl,rms_error_worst_agent_bl,rms_error_true_bl,rms_error_sync_bl,rms_error_time_bl,legs_completed,final_distance_bl,agent_contact,wall_contacts,missed_frames,replans,track_duration_s,track_time_s,error\n0,a|b|obc|realistic|0,ci,open-field,2,goal-zoom-rrt,goal-zoom-rrt,,obc,realistic,0,3000,,exact,true,false,10,11,0.1,5.0,0.1,3,0.01,4,5.0,reached-goal,true,6.0,0.07,0.2,0.08,0.06,0.09,0.3,1,0.1,false,0,2,0,6.0,0.5,\n";
        std::fs::write(dir.path().join(store::RUNS), old).unwrap();
        let s = Source::open(dir.path()).unwrap();
        // its tracked team of two: two agents' columns
        assert_eq!((s.agents, s.copied), (2, [false, true]));
        let row = store::read_runs(dir.path()).unwrap().remove(0);
        let merged = s.whole_runs(2).unwrap().next().unwrap().unwrap();
        assert_eq!(merged.row.bytes, store::run_bytes(&[row], 2));
    }
}
