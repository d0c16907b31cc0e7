//! The runs' progress traces, as the OMPL log and the plots read them from `progress.csv`.
//! The folder's pass over its runs reads the file once beside `runs.csv`, both in run order,
//! a run's trace at a time ([`InOrder`]); the plots read the traces of the runs they draw,
//! from where that pass found them ([`Traces::at`], 24 bytes a run), so that the memory
//! neither takes grows with the number of runs or points. One CSV reader serves every read of
//! [`Traces`]: it is moved to a stretch's offset, not built anew.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::SeekFrom;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use crate::Error;
use crate::record::ProgressRow;
use crate::store::{PROGRESS, Snapshot, bad_row, failed};

/// One point of a run's progress trace.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TracePoint {
    /// Iterations done.
    pub iteration: u64,
    /// Seconds since the start of planning.
    pub time_s: f64,
    /// Best exact-solution cost so far (`None` before the first solution).
    pub best_cost: Option<f64>,
}

impl From<&ProgressRow> for TracePoint {
    fn from(r: &ProgressRow) -> Self {
        TracePoint {
            iteration: r.iteration,
            time_s: r.time_s,
            best_cost: r.best_cost,
        }
    }
}

/// Where one run's trace is in `progress.csv`: its rows, consecutive from a byte offset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stretch {
    /// The run.
    pub run: usize,
    /// Byte offset of its first row.
    pub offset: u64,
    /// Rows.
    pub rows: u64,
}

/// Where the traces are.
#[derive(Debug, Default)]
enum Source {
    /// No traces (a folder without `progress.csv`).
    #[default]
    None,
    /// Every trace in memory, by run.
    Memory(BTreeMap<usize, Vec<TracePoint>>),
    /// The stretches of some runs of a `progress.csv`, by run, and a reader of the file.
    File {
        path: PathBuf,
        reader: Mutex<csv::Reader<File>>,
        stretches: Vec<Stretch>,
    },
}

/// The progress traces of some runs of a results folder, by run index, each in the order of
/// its rows.
#[derive(Debug, Default)]
pub struct Traces(Source);

impl Traces {
    /// The traces of `rows`, held in memory.
    pub fn from_rows<'a>(rows: impl IntoIterator<Item = &'a ProgressRow>) -> Self {
        let mut t: BTreeMap<usize, Vec<TracePoint>> = BTreeMap::new();
        for r in rows {
            t.entry(r.run).or_default().push(r.into());
        }
        Traces(Source::Memory(t))
    }

    /// The traces at `stretches` (one per run, as [`InOrder::trace`] finds them) of the
    /// `progress.csv` of `dir`, read from the file when asked for; none without the file.
    pub fn at(dir: &Path, mut stretches: Vec<Stretch>) -> Result<Self, Error> {
        let path = dir.join(PROGRESS);
        let file = match File::open(&path) {
            Ok(f) => f,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Traces::default()),
            Err(e) => return Err(failed(&path, e)),
        };
        stretches.sort_by_key(|s| s.run);
        let reader = csv::ReaderBuilder::new()
            .has_headers(false)
            .from_reader(file);
        Ok(Traces(Source::File {
            path,
            reader: Mutex::new(reader),
            stretches,
        }))
    }

    /// The trace of run `run` (empty without one).
    pub fn get(&self, run: usize) -> Result<Vec<TracePoint>, Error> {
        match &self.0 {
            Source::None => Ok(vec![]),
            Source::Memory(t) => Ok(t.get(&run).cloned().unwrap_or_default()),
            Source::File {
                path,
                reader,
                stretches,
            } => {
                let Ok(i) = stretches.binary_search_by_key(&run, |s| s.run) else {
                    return Ok(vec![]);
                };
                let mut reader = reader.lock().unwrap_or_else(|p| p.into_inner());
                let mut out = vec![];
                read_stretch(path, &mut reader, &stretches[i], &mut out)?;
                Ok(out)
            }
        }
    }
}

/// A `progress.csv` in run order (as [`crate::sort`] leaves it) read once, a run's trace at a
/// time, beside `runs.csv` in the same order: it holds the one row it has read ahead, and
/// hands every row it reads, of runs asked for or not, to a reader of every row (such as
/// [`crate::progress_parquet::Writer`]).
pub struct InOrder {
    path: PathBuf,
    /// `None`: no `progress.csv`.
    reader: Option<csv::Reader<std::io::Take<std::io::BufReader<File>>>>,
    headers: csv::StringRecord,
    record: csv::StringRecord,
    /// Rows read.
    row: usize,
    /// The row read ahead, and its byte offset.
    ahead: Option<(ProgressRow, u64)>,
    /// The run of the last row read.
    last: Option<usize>,
}

impl InOrder {
    /// Opens the `progress.csv` of `dir` (none: no traces) at its first row.
    pub fn open(dir: &Path) -> Result<InOrder, Error> {
        let path = dir.join(PROGRESS);
        let mut reader = match Snapshot::open(&path)? {
            Some(s) => Some(csv::Reader::from_reader(s.reader()?)),
            None => None,
        };
        let headers = match &mut reader {
            Some(r) => r
                .headers()
                .map_err(|e| bad_row(&path, 0, e.to_string()))?
                .clone(),
            None => csv::StringRecord::new(),
        };
        let mut t = InOrder {
            path,
            reader,
            headers,
            record: csv::StringRecord::new(),
            row: 0,
            ahead: None,
            last: None,
        };
        t.read_ahead()?;
        Ok(t)
    }

    /// Reads the next row into `ahead` (`None` at the end), refusing a row of an earlier run
    /// than the one before it.
    fn read_ahead(&mut self) -> Result<(), Error> {
        let Some(reader) = &mut self.reader else {
            return Ok(());
        };
        if !reader
            .read_record(&mut self.record)
            .map_err(|e| bad_row(&self.path, self.row + 1, e.to_string()))?
        {
            self.ahead = None;
            return Ok(());
        }
        self.row += 1;
        let p: ProgressRow = self
            .record
            .deserialize(Some(&self.headers))
            .map_err(|e| bad_row(&self.path, self.row, e.to_string()))?;
        if let Some(before) = self.last.filter(|b| p.run < *b) {
            return Err(bad_row(
                &self.path,
                self.row,
                format!("run {} after run {before}: not in run order", p.run),
            ));
        }
        self.last = Some(p.run);
        let offset = self.record.position().map_or(0, |p| p.byte());
        self.ahead = Some((p, offset));
        Ok(())
    }

    /// The trace of run `run` and where it is, handing each row read to `each`: the rows of
    /// earlier runs not asked for, then the trace's. Runs are asked for in increasing order;
    /// a run asked for again, or after a later one, has an empty trace.
    pub fn trace(
        &mut self,
        run: usize,
        each: &mut impl FnMut(ProgressRow) -> Result<(), Error>,
    ) -> Result<(Vec<TracePoint>, Stretch), Error> {
        let mut at = Stretch {
            run,
            offset: 0,
            rows: 0,
        };
        let mut points = vec![];
        while let Some((p, offset)) = self.ahead.take_if(|(p, _)| p.run <= run) {
            if p.run == run {
                if points.is_empty() {
                    at.offset = offset;
                }
                points.push(TracePoint::from(&p));
                at.rows += 1;
            }
            each(p)?;
            self.read_ahead()?;
        }
        Ok((points, at))
    }

    /// Hands the rows not read yet (of runs after the last asked for) to `each`.
    pub fn finish(
        mut self,
        each: &mut impl FnMut(ProgressRow) -> Result<(), Error>,
    ) -> Result<(), Error> {
        while let Some((p, _)) = self.ahead.take() {
            each(p)?;
            self.read_ahead()?;
        }
        Ok(())
    }
}

/// Appends the points of stretch `s` to `out`, read by `reader` from the file at `path` (moved
/// to the stretch unless it is there: the stretches of runs read in order follow each other).
fn read_stretch(
    path: &Path,
    reader: &mut csv::Reader<File>,
    s: &Stretch,
    out: &mut Vec<TracePoint>,
) -> Result<(), Error> {
    if reader.position().byte() != s.offset {
        let mut at = csv::Position::new();
        at.set_byte(s.offset);
        reader
            .seek_raw(SeekFrom::Start(s.offset), at)
            .map_err(|e| failed(path, e))?;
    }
    let mut record = csv::ByteRecord::new();
    for _ in 0..s.rows {
        if !reader
            .read_byte_record(&mut record)
            .map_err(|e| failed(path, e))?
        {
            return Err(failed(path, "the file is shorter than when it was read"));
        }
        out.push(point(&record).map_err(|e| failed(path, e))?);
    }
    Ok(())
}

/// The trace point of a `progress.csv` record (its columns in [`ProgressRow`]'s order: run,
/// run id, iteration, time, best cost).
fn point(record: &csv::ByteRecord) -> Result<TracePoint, String> {
    fn cell<T: std::str::FromStr>(record: &csv::ByteRecord, i: usize) -> Result<Option<T>, String>
    where
        T::Err: std::fmt::Display,
    {
        let v = record.get(i).ok_or("a row with too few cells")?;
        let v = std::str::from_utf8(v).map_err(|e| e.to_string())?;
        if v.is_empty() {
            return Ok(None);
        }
        v.parse().map(Some).map_err(|e| format!("{v:?}: {e}"))
    }
    Ok(TracePoint {
        iteration: cell(record, 2)?.ok_or("no iteration")?,
        time_s: cell(record, 3)?.ok_or("no time")?,
        best_cost: cell(record, 4)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(run: usize, iteration: u64, best_cost: Option<f64>) -> ProgressRow {
        ProgressRow {
            run,
            run_id: format!("r{run}"),
            iteration,
            time_s: iteration as f64 / 10.0,
            best_cost,
        }
    }

    /// Writes `rows` as the `progress.csv` of `dir`.
    fn write(dir: &Path, rows: &[ProgressRow]) {
        let mut text = crate::store::progress_header();
        text.push('\n');
        text.push_str(std::str::from_utf8(&crate::store::progress_bytes(rows)).unwrap());
        std::fs::write(dir.join(PROGRESS), text).unwrap();
    }

    #[test]
    fn traces_read_in_order_are_those_in_memory_and_read_again_where_they_were_found() {
        let dir = tempfile::tempdir().unwrap();
        // run 2 has points and is not asked for; runs 1 and 4 are asked for and have none
        let rows = [
            row(0, 1, None),
            row(0, 2, Some(5.0)),
            row(2, 1, Some(3.0)),
            row(3, 1, None),
            row(3, 3, Some(4.5)),
            row(5, 7, None),
        ];
        write(dir.path(), &rows);
        let memory = Traces::from_rows(&rows);
        let mut each = vec![];
        let mut hand = |r: ProgressRow| {
            each.push(r);
            Ok::<(), Error>(())
        };
        let mut t = InOrder::open(dir.path()).unwrap();
        let mut found = vec![];
        for run in [0, 1, 3, 4] {
            let (points, at) = t.trace(run, &mut hand).unwrap();
            assert_eq!(points, memory.get(run).unwrap(), "run {run}");
            assert_eq!((at.run, at.rows), (run, points.len() as u64));
            found.push(at);
        }
        // asked for again: nothing more
        assert!(t.trace(3, &mut hand).unwrap().0.is_empty());
        t.finish(&mut hand).unwrap();
        assert_eq!(each, rows, "every row handed on once, in the file's order");
        let again = Traces::at(dir.path(), found).unwrap();
        for run in 0..6 {
            let want = if [0, 1, 3, 4].contains(&run) {
                memory.get(run).unwrap()
            } else {
                vec![]
            };
            assert_eq!(again.get(run).unwrap(), want, "run {run}");
        }
        // no file: no traces
        let empty = tempfile::tempdir().unwrap();
        let mut t = InOrder::open(empty.path()).unwrap();
        assert!(t.trace(0, &mut |_| Ok(())).unwrap().0.is_empty());
        assert!(
            Traces::at(empty.path(), vec![])
                .unwrap()
                .get(0)
                .unwrap()
                .is_empty()
        );
    }

    #[test]
    fn a_bad_row_or_a_file_out_of_run_order_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let text = format!(
            "{}\n0,r0,1,0.1,\n0,r0,two,0.2,\n",
            crate::store::progress_header()
        );
        std::fs::write(dir.path().join(PROGRESS), text).unwrap();
        let mut none = |_: ProgressRow| Ok::<(), Error>(());
        let e = InOrder::open(dir.path())
            .and_then(|mut t| t.trace(0, &mut none))
            .unwrap_err()
            .to_string();
        assert!(e.contains("progress.csv") && e.contains("row 2"), "{e}");
        write(dir.path(), &[row(1, 1, None), row(0, 1, None)]);
        let e = InOrder::open(dir.path())
            .and_then(|mut t| t.trace(1, &mut none))
            .unwrap_err()
            .to_string();
        assert!(e.contains("row 2") && e.contains("not in run order"), "{e}");
        // an error of the reader of each row stops the read with it
        let mut full = |_: ProgressRow| Err::<(), Error>(Error::Failed("full".into()));
        let e = InOrder::open(dir.path()).and_then(|mut t| t.trace(1, &mut full));
        assert_eq!(
            e.unwrap_err().to_string(),
            Error::Failed("full".into()).to_string()
        );
    }
}
