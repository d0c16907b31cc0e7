//! Merging shard folders into one results folder.
//!
//! The shards' `runs.csv` and `progress.csv` are read row by row and merged by run index (a
//! k-way merge): a shard in run order holds one run in memory at a time, so the merge of the
//! run files holds a run per shard, whatever the number of runs; a shard out of run order (a
//! task at several threads that did not finish) is read whole and sorted first. The merged
//! folder's derived files are then written by [`super::finalize`], which reads all its runs.

use std::cmp::{Ordering, Reverse};
use std::collections::BinaryHeap;
use std::io::Write;
use std::path::{Path, PathBuf};

use magbench_env::InputError;

use super::manifest::{Manifest, Session, host, now};
use super::store;
use crate::Error;
use crate::run::{ProgressRow, RunRecord};

/// Merges the results folders `shards` (of the same experiment) into `out`, which must not
/// hold results, and writes its derived files, holding `out`'s lock throughout (exit 2 if
/// another process holds it). Only whole runs are taken (one row, and exactly the trace
/// points the row records); a run found in several folders is taken from the first.
pub fn merge(shards: &[PathBuf], out: &Path) -> Result<Manifest, Error> {
    if shards.is_empty() {
        return Err(Error::arg(
            "DIR",
            "give at least one results folder to merge",
        ));
    }
    std::fs::create_dir_all(out).map_err(|e| Error::Failed(format!("{}: {e}", out.display())))?;
    let _lock = super::lock::exclusive(out, "merge", "--out")?;
    if out.join(super::MANIFEST).exists() {
        return Err(Error::Input(InputError::new(
            out.display().to_string(),
            "--out",
            "already holds results; choose another --out",
        )));
    }
    let t0 = std::time::Instant::now();
    let mut manifests = vec![];
    for s in shards {
        manifests.push(Manifest::read(s)?);
    }
    let first = manifests[0].clone();
    for (s, m) in shards.iter().zip(&manifests) {
        let this = env!("CARGO_PKG_VERSION");
        if m.magbench_version != this {
            return Err(Error::Input(InputError::new(
                s.join(super::MANIFEST).display().to_string(),
                "magbench_version",
                format!(
                    "written by magbench {}, and this is magbench {this}: merge shards with the \
                     version that ran them",
                    m.magbench_version
                ),
            )));
        }
        if m.experiment.sha256 != first.experiment.sha256 {
            return Err(Error::Input(InputError::new(
                s.display().to_string(),
                "manifest.json",
                format!(
                    "experiment {} (sha256 {}) differs from {} in {}",
                    m.experiment.name,
                    &m.experiment.sha256[..12],
                    &first.experiment.sha256[..12],
                    shards[0].display()
                ),
            )));
        }
    }
    let mut revisions: Vec<&str> = manifests.iter().map(|m| m.git_revision.as_str()).collect();
    revisions.sort();
    revisions.dedup();
    if revisions.len() > 1 {
        eprintln!(
            "note: the shards were run by {} builds of magbench {} (git revisions {}): their runs \
             may differ by more than their seeds",
            revisions.len(),
            first.magbench_version,
            revisions.join(", ")
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
        streams.push(s.whole_runs()?);
    }
    // A k-way merge by run index: the next run is the smallest head, the first folder's on a
    // tie, and a run index already written is skipped (the same run in a later folder).
    let mut heads: BinaryHeap<Reverse<(usize, usize)>> = BinaryHeap::new();
    let mut pending: Vec<Option<WholeRun>> = Vec::with_capacity(streams.len());
    for (k, st) in streams.iter_mut().enumerate() {
        let head = st.next().transpose()?;
        if let Some(h) = &head {
            heads.push(Reverse((h.record.run, k)));
        }
        pending.push(head);
    }
    let mut last: Option<usize> = None;
    while let Some(Reverse((run, k))) = heads.pop() {
        let w = pending[k].take().expect("a head for every heap entry");
        if last != Some(run) {
            crate::replay::files::copy_run(&shards[k], out, run)?;
            progress_out.write(&store::progress_bytes(&w.trace))?;
            runs_out.write(&store::run_bytes(std::slice::from_ref(&w.record), agents))?;
            last = Some(run);
        }
        if let Some(h) = streams[k].next().transpose()? {
            heads.push(Reverse((h.record.run, k)));
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
    let mut m = first.clone();
    m.shard = None;
    m.merged_from = shards.iter().map(|s| s.display().to_string()).collect();
    m.started = manifests
        .iter()
        .map(|m| m.started.clone())
        .min()
        .unwrap_or_else(now);
    m.sessions = manifests.iter().flat_map(|m| m.sessions.clone()).collect();
    m.threads = manifests.iter().map(|m| m.threads).max().unwrap_or(1);
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
    super::finalize(out)?;
    super::verify::require_sound(out, false)?;
    Manifest::read(out)
}

/// One shard folder's run files, opened once, and what a first read of them found.
struct Source {
    runs: Option<store::Snapshot>,
    progress: Option<store::Snapshot>,
    /// Whether `runs.csv` is in run order and `progress.csv` in (run, iteration, time) order,
    /// as a finished folder and a task at one thread write them.
    sorted: bool,
    /// The largest tracked team of its rows.
    agents: usize,
}

/// The order of progress rows in a finished folder: by run, iteration, then time.
fn progress_order(a: &ProgressRow, b: &ProgressRow) -> Ordering {
    (a.run, a.iteration)
        .cmp(&(b.run, b.iteration))
        .then(a.time_s.total_cmp(&b.time_s))
}

impl Source {
    /// Opens the run files of `dir` (`runs.csv` first: a run's progress rows are written before
    /// its row, so every row read has its trace in the `progress.csv` opened after it) and reads
    /// them once, row by row, for their order and teams.
    fn open(dir: &Path) -> Result<Source, Error> {
        let runs = store::Snapshot::open(&dir.join(store::RUNS))?;
        let progress = store::Snapshot::open(&dir.join(store::PROGRESS))?;
        let (mut sorted, mut agents, mut prev) = (true, 0, None);
        if let Some(r) = &runs {
            for row in r.runs()? {
                let row = row?;
                sorted &= prev.is_none_or(|p| p <= row.run);
                prev = Some(row.run);
                agents = agents.max(store::tracked_agents([&row]));
            }
        }
        if let Some(p) = &progress {
            let mut prev: Option<ProgressRow> = None;
            for row in p.progress()? {
                let row = row?;
                sorted &= prev
                    .as_ref()
                    .is_none_or(|p| progress_order(p, &row) != Ordering::Greater);
                prev = Some(row);
            }
        }
        Ok(Source {
            runs,
            progress,
            sorted,
            agents,
        })
    }

    /// The folder's whole runs in run order: streamed from files already in order, else read
    /// whole and sorted (one folder's runs: a task that ran several threads and did not finish).
    fn whole_runs(&self) -> Result<WholeRuns, Error> {
        let (runs, progress): (RowIter<RunRecord>, RowIter<ProgressRow>) = if self.sorted {
            (
                match &self.runs {
                    Some(r) => Box::new(r.runs()?),
                    None => Box::new(std::iter::empty()),
                },
                match &self.progress {
                    Some(p) => Box::new(p.progress()?),
                    None => Box::new(std::iter::empty()),
                },
            )
        } else {
            let mut runs = match &self.runs {
                Some(r) => r.runs()?.collect::<Result<Vec<_>, _>>()?,
                None => vec![],
            };
            let mut progress = match &self.progress {
                Some(p) => p.progress()?.collect::<Result<Vec<_>, _>>()?,
                None => vec![],
            };
            runs.sort_by_key(|r| r.run);
            progress.sort_by(progress_order);
            (
                Box::new(runs.into_iter().map(Ok)),
                Box::new(progress.into_iter().map(Ok)),
            )
        };
        Ok(WholeRuns {
            runs: runs.peekable(),
            progress: progress.peekable(),
            left_out: 0,
        })
    }
}

type RowIter<T> = Box<dyn Iterator<Item = Result<T, Error>>>;

/// One run's row and its trace.
pub struct WholeRun {
    /// The row.
    pub record: RunRecord,
    /// Its progress rows, in order.
    pub trace: Vec<ProgressRow>,
}

/// The whole runs of one folder's rows and trace points, both in run order, one run at a time:
/// runs with one row whose trace has exactly the points the row records (any trace for rows of
/// older versions, which record none). Trace points of runs without a row are skipped.
pub struct WholeRuns {
    runs: std::iter::Peekable<RowIter<RunRecord>>,
    progress: std::iter::Peekable<RowIter<ProgressRow>>,
    /// Runs left out so far: doubled rows, or a trace of another length than the row records.
    pub left_out: usize,
}

impl Iterator for WholeRuns {
    type Item = Result<WholeRun, Error>;

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            let record = match self.runs.next()? {
                Ok(r) => r,
                Err(e) => return Some(Err(e)),
            };
            let mut rows = 1;
            while let Some(Ok(r)) = self.runs.peek() {
                if r.run != record.run {
                    break;
                }
                rows += 1;
                self.runs.next();
            }
            let mut trace = vec![];
            while let Some(p) = self.progress.peek() {
                match p {
                    Ok(p) if p.run > record.run => break,
                    Ok(p) if p.run == record.run => {}
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
            let whole = record.progress_rows.is_none_or(|k| trace.len() as u64 == k);
            if rows == 1 && whole {
                return Some(Ok(WholeRun { record, trace }));
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
    use crate::results::store::RunWriter;
    use crate::results::store::tests::out;

    fn runs_of(dir: &Path) -> (Vec<usize>, Vec<usize>, usize, bool) {
        let s = Source::open(dir).unwrap();
        let mut w = s.whole_runs().unwrap();
        let mut runs = vec![];
        let mut points = vec![];
        for r in w.by_ref() {
            let r = r.unwrap();
            runs.push(r.record.run);
            points.extend(r.trace.iter().map(|p| p.run));
        }
        (runs, points, w.left_out, s.sorted)
    }

    #[test]
    fn whole_runs_stream_in_order_and_leave_out_torn_and_doubled_runs() {
        let dir = tempfile::tempdir().unwrap();
        let mut w = RunWriter::open(dir.path(), 0).unwrap();
        for i in [0, 1, 3] {
            w.write(&out(i)).unwrap();
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
            w.write(&out(i)).unwrap();
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
}
