//! The checks of `results verify` that read rows: each row of `runs.csv` on its own (a crash, a
//! run of another experiment), the rows against each other and against the experiment's run
//! matrix (doubled, missing), and each run against its trace in `progress.csv`.
//!
//! A finished folder's two files are in run order ([`crate::sort`]), so the checks walk them
//! side by side and hold one run index at a time: memory does not grow with the number of
//! runs. Files out of order (a sweep that stopped while it ran several threads) are read into
//! memory, by run, and then walked the same way.

use std::collections::BTreeMap;
use std::iter::Peekable;

use sha2::{Digest, Sha256};

use crate::Error;
use crate::manifest::{MANIFEST, Manifest};
use crate::record::{RunRecord, Status};
use crate::store::{PROGRESS, RUNS, Snapshot};
use crate::verify::{Kind, in_slice};

/// What the walk keeps of a row of `runs.csv`.
#[derive(Debug, Clone, PartialEq)]
struct Row {
    run: usize,
    run_id: String,
    progress_rows: Option<u64>,
}

impl Row {
    fn key(&self) -> (usize, &str) {
        (self.run, &self.run_id)
    }
}

/// Consecutive points of `progress.csv` of one run index and run id.
#[derive(Debug, Clone, PartialEq)]
struct Trace {
    run: usize,
    run_id: String,
    /// The file row of its first point (1 is the row after the header).
    first: usize,
    points: u64,
}

impl Trace {
    fn key(&self) -> (usize, &str) {
        (self.run, &self.run_id)
    }
}

/// Why the side-by-side walk stopped before the end.
enum Stop {
    /// A file is not in run order.
    Unordered,
    /// A row of `runs.csv` does not read.
    Runs(Error),
    /// A row of `progress.csv` does not read.
    Progress(Error),
}

/// What the rows of `runs.csv` show one at a time, in the file's order.
struct Visits<'m> {
    manifest: Option<&'m Manifest>,
    rows: usize,
    crashed: usize,
    /// Some row records trace points (or does not say how many).
    traced: bool,
    /// Rows that are not runs of the manifest's experiment (and shard).
    foreign: Option<Kind>,
    /// The run ids in the file's order, hashed (each id's length, then its bytes).
    ids: Sha256,
}

impl<'m> Visits<'m> {
    fn new(manifest: Option<&'m Manifest>) -> Self {
        let foreign = manifest.map(|m| {
            Kind::new(&format!(
                "{RUNS}: rows that are not runs of experiment {:?}{}",
                m.experiment.name,
                m.shard
                    .map(|[k, n]| format!(" shard {k}/{n}"))
                    .unwrap_or_default()
            ))
        });
        Visits {
            manifest,
            rows: 0,
            crashed: 0,
            traced: false,
            foreign,
            ids: Sha256::new(),
        }
    }

    fn visit(&mut self, r: RunRecord) -> Row {
        self.rows += 1;
        self.crashed += usize::from(r.status == Status::Crash);
        self.traced |= r.progress_rows != Some(0);
        if let (Some(m), Some(kind)) = (self.manifest, self.foreign.as_mut())
            && (r.experiment != m.experiment.name || !in_slice(m, r.run))
        {
            kind.push(format!(
                "{} (index {}, experiment {:?})",
                r.run_id, r.run, r.experiment
            ));
        }
        hash_id(&mut self.ids, &r.run_id);
        Row {
            run: r.run,
            run_id: r.run_id,
            progress_rows: r.progress_rows,
        }
    }
}

/// Adds run id `id` to the hash of a sequence of ids.
pub(super) fn hash_id(h: &mut Sha256, id: &str) {
    h.update((id.len() as u64).to_le_bytes());
    h.update(id.as_bytes());
}

/// What the checks found; [`Checked::report`] turns it into problems and notes.
pub(super) struct Checked {
    /// Rows of `runs.csv` (none when a row does not read).
    pub rows: usize,
    /// Some row records trace points.
    pub traced: bool,
    /// The hash of the run ids of `runs.csv` in its order ([`hash_id`]).
    pub ids: [u8; 32],
    crashed: usize,
    foreign: Option<Kind>,
    walked: Walked,
    /// The rows or points that do not read.
    unreadable: Vec<String>,
}

impl Checked {
    /// Points of `progress.csv` (none when a row does not read).
    pub fn points(&self) -> usize {
        self.walked.points
    }
}

/// The rows of one run index and id that the walk is at.
struct Current {
    run: usize,
    run_id: String,
    /// The points of its trace.
    points: u64,
    /// Its rows so far.
    rows: usize,
    /// The rows of its run index so far, its own included.
    at_index: usize,
}

/// The walk over runs in (run index, run id) order and their traces in the same order.
struct Walk<'m, T: Iterator<Item = Result<Trace, Stop>>> {
    manifest: Option<&'m Manifest>,
    traces: Peekable<T>,
    current: Option<Current>,
    /// The first index of the matrix not yet passed.
    next: usize,
    found: Walked,
}

impl<'m, T: Iterator<Item = Result<Trace, Stop>>> Walk<'m, T> {
    fn new(manifest: Option<&'m Manifest>, traces: T) -> Self {
        Walk {
            manifest,
            traces: traces.peekable(),
            current: None,
            next: 0,
            found: Walked {
                points: 0,
                indices: 0,
                doubled_ids: Kind::new(&format!("{RUNS}: run ids with several rows")),
                doubled_indices: Kind::new(&format!("{RUNS}: run indices with several rows")),
                missing: Kind::new(""),
                orphans: Kind::new(&format!(
                    "{PROGRESS}: traces of runs without a row in {RUNS} (by run index and id)"
                )),
                wrong: Kind::new(
                    "runs whose trace in progress.csv is not as long as their row says",
                ),
                unknown: 0,
            },
        }
    }

    /// Takes the next row.
    fn row(&mut self, row: Row) -> Result<(), Stop> {
        let at_index = match self.current.take() {
            None => 1,
            Some(c) => {
                let last = (c.run, c.run_id.as_str());
                if row.key() < last {
                    return Err(Stop::Unordered);
                }
                if row.key() == last {
                    self.compare(&row, c.points);
                    self.current = Some(Current {
                        rows: c.rows + 1,
                        at_index: c.at_index + 1,
                        ..c
                    });
                    return Ok(());
                }
                self.end_id(&c);
                if row.run == c.run {
                    c.at_index + 1
                } else {
                    self.end_index(&c);
                    1
                }
            }
        };
        if at_index == 1 {
            self.found.indices += 1;
            self.pass_to(row.run);
        }
        self.orphans_before(row.key())?;
        let points = self.take_trace(row.key())?;
        self.compare(&row, points);
        self.current = Some(Current {
            run: row.run,
            run_id: row.run_id,
            points,
            rows: 1,
            at_index,
        });
        Ok(())
    }

    /// The trace points a row says, against the `points` its trace has.
    fn compare(&mut self, row: &Row, points: u64) {
        match row.progress_rows {
            Some(k) if k != points => self
                .found
                .wrong
                .push(format!("{}: {points} points, its row says {k}", row.run_id)),
            Some(_) => {}
            None => self.found.unknown += 1,
        }
    }

    fn end_id(&mut self, c: &Current) {
        if c.rows > 1 {
            self.found
                .doubled_ids
                .push(format!("{} ({} rows)", c.run_id, c.rows));
        }
    }

    fn end_index(&mut self, c: &Current) {
        if c.at_index > 1 {
            self.found
                .doubled_indices
                .push(format!("{} ({} rows)", c.run, c.at_index));
        }
    }

    /// Counts the indices of the matrix from the first not yet passed up to `run` (not
    /// included) as missing, and passes `run`.
    fn pass_to(&mut self, run: usize) {
        if let Some(m) = self.manifest {
            let end = run.min(m.experiment.runs_total);
            for i in (self.next..end).filter(|&i| in_slice(m, i)) {
                self.found.missing.push_with(|| i.to_string());
            }
            self.next = self.next.max(run.saturating_add(1));
        }
    }

    /// Takes the traces before `key`, which have no row.
    fn orphans_before(&mut self, key: (usize, &str)) -> Result<(), Stop> {
        loop {
            match self.traces.peek() {
                Some(Ok(t)) if t.key() < key => {}
                Some(Ok(_)) | None => return Ok(()),
                Some(Err(_)) => return Err(self.trace_error()),
            }
            if let Some(Ok(t)) = self.traces.next() {
                self.orphan(&t);
            }
        }
    }

    /// The error of the next trace, which a peek found to be one.
    fn trace_error(&mut self) -> Stop {
        self.traces
            .next()
            .and_then(Result::err)
            .unwrap_or(Stop::Unordered)
    }

    fn orphan(&mut self, t: &Trace) {
        self.found.points += t.points as usize;
        self.found.orphans.push(format!(
            "{} from row {} ({} points)",
            t.run_id, t.first, t.points
        ));
    }

    /// The points of the trace of `key` if it is the next one, else 0.
    fn take_trace(&mut self, key: (usize, &str)) -> Result<u64, Stop> {
        match self.traces.peek() {
            Some(Ok(t)) if t.key() == key => {
                let points = t.points;
                self.traces.next();
                self.found.points += points as usize;
                Ok(points)
            }
            Some(Err(_)) => Err(self.trace_error()),
            _ => Ok(0),
        }
    }

    /// Ends the walk: the last rows, the traces after them and the indices after the last.
    fn finish(mut self) -> Result<Walked, Stop> {
        if let Some(c) = self.current.take() {
            self.end_id(&c);
            self.end_index(&c);
        }
        while let Some(t) = self.traces.next() {
            self.orphan(&t?);
        }
        if let Some(m) = self.manifest {
            self.pass_to(m.experiment.runs_total);
        }
        Ok(self.found)
    }
}

/// What a whole walk found.
struct Walked {
    points: usize,
    indices: usize,
    doubled_ids: Kind,
    doubled_indices: Kind,
    missing: Kind,
    orphans: Kind,
    wrong: Kind,
    unknown: usize,
}

/// The points of `progress.csv` gathered into traces, as they come; a trace that does not
/// come after the one before it (by run index, then id) stops the walk.
struct Gathered<I: Iterator<Item = Result<crate::record::ProgressRow, Error>>> {
    points: Peekable<I>,
    row: usize,
    last: Option<(usize, String)>,
}

impl<I: Iterator<Item = Result<crate::record::ProgressRow, Error>>> Iterator for Gathered<I> {
    type Item = Result<Trace, Stop>;

    fn next(&mut self) -> Option<Self::Item> {
        let first = match self.points.next()? {
            Ok(p) => p,
            Err(e) => return Some(Err(Stop::Progress(e))),
        };
        self.row += 1;
        let mut t = Trace {
            run: first.run,
            run_id: first.run_id,
            first: self.row,
            points: 1,
        };
        if self
            .last
            .as_ref()
            .is_some_and(|(run, id)| (*run, id.as_str()) >= t.key())
        {
            return Some(Err(Stop::Unordered));
        }
        while self
            .points
            .next_if(|p| {
                p.as_ref()
                    .is_ok_and(|p| p.run == t.run && p.run_id == t.run_id)
            })
            .is_some()
        {
            self.row += 1;
            t.points += 1;
        }
        self.last = Some((t.run, t.run_id.clone()));
        Some(Ok(t))
    }
}

/// Checks the rows of `runs` and the points of `progress` (either absent: no rows) against
/// each other and against the manifest.
pub(super) fn check(
    runs: Option<&Snapshot>,
    progress: Option<&Snapshot>,
    manifest: Option<&Manifest>,
) -> Result<Checked, Error> {
    let mut visits = Visits::new(manifest);
    let walked = side_by_side(runs, progress, manifest, &mut visits);
    let (visits, walked, unreadable) = match walked {
        Ok(w) => (visits, w, vec![]),
        Err(Stop::Unordered) => in_memory(runs, progress, manifest)?,
        Err(Stop::Runs(e)) => {
            let (v, w, mut u) = in_memory(None, progress, manifest)?;
            u.insert(0, format!("{RUNS}: {e}"));
            (v, w, u)
        }
        Err(Stop::Progress(e)) => {
            let (v, w, mut u) = in_memory(runs, None, manifest)?;
            u.push(format!("{PROGRESS}: {e}"));
            (v, w, u)
        }
    };
    Ok(Checked {
        rows: visits.rows,
        traced: visits.traced,
        ids: visits.ids.finalize().into(),
        crashed: visits.crashed,
        foreign: visits.foreign,
        walked,
        unreadable,
    })
}

/// The walk over both files as they are, in one pass.
fn side_by_side(
    runs: Option<&Snapshot>,
    progress: Option<&Snapshot>,
    manifest: Option<&Manifest>,
    visits: &mut Visits,
) -> Result<Walked, Stop> {
    let points = match progress {
        Some(p) => Some(p.progress().map_err(Stop::Progress)?),
        None => None,
    };
    let traces = Gathered {
        points: points.into_iter().flatten().peekable(),
        row: 0,
        last: None,
    };
    let mut walk = Walk::new(manifest, traces);
    if let Some(r) = runs {
        for row in r.runs().map_err(Stop::Runs)? {
            walk.row(visits.visit(row.map_err(Stop::Runs)?))?;
        }
    }
    walk.finish()
}

/// The walk over both files read into memory and put in order; a file with a row that does
/// not read counts as empty, with its problem.
fn in_memory<'m>(
    runs: Option<&Snapshot>,
    progress: Option<&Snapshot>,
    manifest: Option<&'m Manifest>,
) -> Result<(Visits<'m>, Walked, Vec<String>), Error> {
    let mut unreadable = vec![];
    let mut visits = Visits::new(manifest);
    let mut rows = vec![];
    if let Some(r) = runs {
        let mut read = || -> Result<(), Error> {
            for row in r.runs()? {
                rows.push(visits.visit(row?));
            }
            Ok(())
        };
        if let Err(e) = read() {
            unreadable.push(format!("{RUNS}: {e}"));
            (visits, rows) = (Visits::new(manifest), vec![]);
        }
    }
    rows.sort_by(|a, b| a.key().cmp(&b.key()));
    let mut traces: BTreeMap<(usize, String), Trace> = BTreeMap::new();
    if let Some(p) = progress {
        let mut read = || -> Result<(), Error> {
            for (i, point) in p.progress()?.enumerate() {
                let point = point?;
                traces
                    .entry((point.run, point.run_id.clone()))
                    .or_insert(Trace {
                        run: point.run,
                        run_id: point.run_id,
                        first: i + 1,
                        points: 0,
                    })
                    .points += 1;
            }
            Ok(())
        };
        if let Err(e) = read() {
            unreadable.push(format!("{PROGRESS}: {e}"));
            traces.clear();
        }
    }
    let mut walk = Walk::new(manifest, traces.into_values().map(Ok));
    let walked = rows
        .into_iter()
        .try_for_each(|r| walk.row(r))
        .and_then(|()| walk.finish());
    match walked {
        Ok(w) => Ok((visits, w, unreadable)),
        Err(_) => Err(Error::Failed(
            "results verify: rows put in order came out of order".into(),
        )),
    }
}

impl Checked {
    /// The problems and notes of the checks, against the manifest `manifest`; returns what is
    /// missing (`None`: every run is there).
    pub fn report(
        self,
        manifest: Option<&Manifest>,
        p: &mut Vec<String>,
        notes: &mut Vec<String>,
    ) -> Option<String> {
        let Checked {
            rows,
            crashed,
            foreign,
            walked:
                Walked {
                    indices,
                    doubled_ids,
                    doubled_indices,
                    missing,
                    orphans,
                    wrong,
                    unknown,
                    ..
                },
            unreadable,
            ..
        } = self;
        p.extend(unreadable);
        doubled_ids.report(p);
        doubled_indices.report(p);
        let incomplete = manifest.and_then(|m| {
            if let Some(f) = foreign {
                f.report(p);
            }
            let total = m.experiment.runs_total;
            let expected = (0..total).filter(|&i| in_slice(m, i)).count();
            if m.finished.is_none() {
                return Some(format!(
                    "not finished: {indices} of {expected} runs done (`bench --resume` \
                     completes it)"
                ));
            }
            if m.runs_done != rows {
                p.push(format!(
                    "{MANIFEST}: runs_done is {}, {RUNS} has {rows} rows",
                    m.runs_done
                ));
            }
            if m.runs_failed != crashed {
                p.push(format!(
                    "{MANIFEST}: runs_failed is {}, {RUNS} has {crashed} crashed runs",
                    m.runs_failed
                ));
            }
            let mut missing = missing;
            missing.what = format!(
                "{RUNS}: {} of {expected} runs missing, indices",
                missing.count
            );
            let mut line = vec![];
            missing.report(&mut line);
            line.pop()
        });
        orphans.report(p);
        wrong.report(p);
        if unknown > 0 {
            notes.push(format!(
                "{unknown} rows of {RUNS} have no progress_rows (an older version): their trace \
                 lengths are not checked"
            ));
        }
        incomplete
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::ProgressRow;
    use crate::store::{self, tests::out};

    /// The manifest of a finished experiment of 8 runs (one scenario and planner, 8 seeds) that
    /// records 8 runs done.
    fn manifest() -> Manifest {
        let experiment = crate::manifest::ExperimentInfo {
            name: "t".into(),
            description: String::new(),
            source: "t.toml".into(),
            sha256: String::new(),
            content: String::new(),
            scenarios: vec!["open-field".into()],
            planners: vec!["fake".into()],
            trackers: vec![],
            presets: vec![],
            tracked_plans: None,
            seeds: (0..8).collect(),
            max_iterations: Some(10),
            time_limit_s: None,
            runs_total: 8,
        };
        let mut m = Manifest::new(experiment, "fake", 1, None, "none".into());
        m.finished = Some(crate::manifest::now());
        m.runs_done = 8;
        m
    }

    /// Writes the rows of `runs` (each run's three trace points once, and the points
    /// `extra`) into `dir`: the rows in `order` (positions in `runs`), each run's points where
    /// its first row is, and those of runs without a row at the end.
    fn write(dir: &std::path::Path, runs: &[usize], extra: &[ProgressRow], order: &[usize]) {
        let mut traces: BTreeMap<usize, Vec<ProgressRow>> = BTreeMap::new();
        for &i in runs {
            traces.entry(i).or_insert_with(|| out(i).progress);
        }
        for p in extra {
            traces.entry(p.run).or_default().push(p.clone());
        }
        let mut rows = vec![];
        let mut points = vec![];
        for &k in order {
            let mut r = out(runs[k]).record;
            r.experiment = "t".into();
            r.progress_rows = Some(3);
            points.extend(traces.remove(&r.run).unwrap_or_default());
            rows.push(r);
        }
        points.extend(traces.into_values().flatten());
        let mut text = format!("{}\n", store::runs_header(0)).into_bytes();
        text.extend(store::run_bytes(&rows, 0));
        std::fs::write(dir.join(RUNS), text).unwrap();
        let mut text = format!("{}\n", store::progress_header()).into_bytes();
        text.extend(store::progress_bytes(&points));
        std::fs::write(dir.join(PROGRESS), text).unwrap();
    }

    fn snapshots(dir: &std::path::Path) -> (Snapshot, Snapshot) {
        (
            Snapshot::open(&dir.join(RUNS)).unwrap().unwrap(),
            Snapshot::open(&dir.join(PROGRESS)).unwrap().unwrap(),
        )
    }

    /// The problems and what is missing, from files whose rows come in `order`.
    fn problems(
        runs: &[usize],
        extra: &[ProgressRow],
        order: &[usize],
    ) -> (Vec<String>, Option<String>, bool) {
        let dir = tempfile::tempdir().unwrap();
        write(dir.path(), runs, extra, order);
        let (r, p) = snapshots(dir.path());
        let m = manifest();
        let ordered =
            side_by_side(Some(&r), Some(&p), Some(&m), &mut Visits::new(Some(&m))).is_ok();
        let c = check(Some(&r), Some(&p), Some(&m)).unwrap();
        let (mut problems, mut notes) = (vec![], vec![]);
        let missing = c.report(Some(&m), &mut problems, &mut notes);
        (problems, missing, ordered)
    }

    fn point(run: usize, id: &str) -> ProgressRow {
        ProgressRow {
            run,
            run_id: id.into(),
            iteration: 0,
            time_s: 0.0,
            best_cost: None,
        }
    }

    /// A sound folder in run order is walked in one pass; the same rows out of order are
    /// read into memory and found sound all the same.
    #[test]
    fn a_folder_in_run_order_is_walked_in_one_pass_and_one_out_of_order_in_memory() {
        let all: Vec<usize> = (0..8).collect();
        let (p, missing, ordered) = problems(&all, &[], &all);
        assert_eq!((p, missing), (vec![], None));
        assert!(ordered);
        let shuffled = [3, 0, 7, 1, 6, 2, 5, 4];
        let (p, missing, ordered) = problems(&all, &[], &shuffled);
        assert_eq!((p, missing), (vec![], None));
        assert!(!ordered);
    }

    /// A doubled row, a missing run, a trace without a row and a trace of the wrong length are
    /// each found, the same whether the rows are in run order or not.
    #[test]
    fn doubled_missing_orphaned_and_short_are_found_in_either_order() {
        // runs 0…7 but 5, run 2's row twice, a point of a run without a row, one point more for run 6
        let runs = [0, 1, 2, 2, 3, 4, 6, 7];
        let extra = [point(9, "s|p|-|-|9"), point(6, "s|p|-|-|6")];
        let in_order: Vec<usize> = (0..runs.len()).collect();
        let (p, missing, ordered) = problems(&runs, &extra, &in_order);
        assert!(ordered);
        let want = [
            "runs.csv: run ids with several rows: s|p|-|-|2 (2 rows)",
            "runs.csv: run indices with several rows: 2 (2 rows)",
            "progress.csv: traces of runs without a row in runs.csv (by run index and id): s|p|-|-|9 from row 23 (1 points)",
            "runs whose trace in progress.csv is not as long as their row says: s|p|-|-|6: 4 points, its row says 3",
        ];
        assert_eq!(p, want);
        assert_eq!(
            missing.as_deref(),
            Some("runs.csv: 1 of 8 runs missing, indices: 5")
        );
        let (q, missing_q, ordered) = problems(&runs, &extra, &[7, 3, 0, 5, 2, 1, 6, 4]);
        assert!(!ordered);
        assert_eq!(missing_q, missing);
        // in memory, a trace's first row is where its first point is in the file
        let strip = |v: &[String]| -> Vec<String> {
            v.iter()
                .map(|l| l.split(" from row ").next().unwrap().to_string())
                .collect()
        };
        assert_eq!(strip(&q), strip(&p));
    }
}
