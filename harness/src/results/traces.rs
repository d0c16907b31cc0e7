//! The runs' progress traces, as the plots and the OMPL log read them from `progress.csv`:
//! an index of where each run's rows are in the file (24 bytes a stretch of rows), each trace
//! read from the file when asked for, so that the memory they take does not grow with the
//! number of points. One CSV reader serves every read: it is moved to a stretch's offset, not
//! built anew.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::SeekFrom;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use super::store::{PROGRESS, Snapshot, bad_row, failed};
use crate::Error;
use crate::run::ProgressRow;

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

/// A stretch of consecutive rows of one run in `progress.csv`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Stretch {
    run: usize,
    /// Byte offset of its first row.
    offset: u64,
    /// Rows.
    rows: u64,
}

/// Where the traces are.
#[derive(Debug, Default)]
enum Source {
    /// No traces (a folder without `progress.csv`).
    #[default]
    None,
    /// Every trace in memory, by run.
    Memory(BTreeMap<usize, Vec<TracePoint>>),
    /// The stretches of a `progress.csv`, by run and then by place in the file, and a reader of
    /// the file without its header.
    File {
        path: PathBuf,
        reader: Mutex<csv::Reader<File>>,
        stretches: Vec<Stretch>,
    },
}

/// The progress traces of a results folder, by run index, each in the order of its rows.
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

    /// The index of the complete rows of the `progress.csv` of `dir` (none without the file),
    /// read one row at a time; every row is checked here, so that [`Traces::get`] only reads.
    pub fn read(dir: &Path) -> Result<Self, Error> {
        Traces::read_each(dir, |_| Ok(()))
    }

    /// [`Traces::read`], handing each row to `each` as it is read (in the file's order): a
    /// reader of every row, such as [`super::progress_parquet::Writer`], shares the one pass.
    pub fn read_each(
        dir: &Path,
        mut each: impl FnMut(ProgressRow) -> Result<(), Error>,
    ) -> Result<Self, Error> {
        let path = dir.join(PROGRESS);
        let Some(s) = Snapshot::open(&path)? else {
            return Ok(Traces::default());
        };
        let mut reader = csv::Reader::from_reader(s.reader()?);
        let headers = reader
            .headers()
            .map_err(|e| bad_row(&path, 0, e.to_string()))?
            .clone();
        let mut stretches: Vec<Stretch> = vec![];
        let mut record = csv::StringRecord::new();
        let mut row = 0;
        while reader
            .read_record(&mut record)
            .map_err(|e| bad_row(&path, row + 1, e.to_string()))?
        {
            row += 1;
            let p: ProgressRow = record
                .deserialize(Some(&headers))
                .map_err(|e| bad_row(&path, row, e.to_string()))?;
            let offset = record.position().map_or(0, |p| p.byte());
            match stretches.last_mut() {
                Some(s) if s.run == p.run => s.rows += 1,
                _ => stretches.push(Stretch {
                    run: p.run,
                    offset,
                    rows: 1,
                }),
            }
            each(p)?;
        }
        // a run's stretches stay in file order (the sort is stable)
        stretches.sort_by_key(|s| s.run);
        stretches.shrink_to_fit();
        let file = File::open(&path).map_err(|e| failed(&path, e))?;
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
                let from = stretches.partition_point(|s| s.run < run);
                let mut reader = reader.lock().unwrap_or_else(|p| p.into_inner());
                let mut out = vec![];
                for s in stretches[from..].iter().take_while(|s| s.run == run) {
                    read_stretch(path, &mut reader, s, &mut out)?;
                }
                Ok(out)
            }
        }
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

    #[test]
    fn a_trace_read_from_the_file_is_the_trace_in_memory() {
        let dir = tempfile::tempdir().unwrap();
        // run 1's rows in two stretches, with run 0's between them
        let rows = [
            row(1, 1, None),
            row(1, 2, Some(5.0)),
            row(0, 1, Some(3.0)),
            row(1, 3, Some(4.5)),
            row(2, 7, None),
        ];
        let mut text = super::super::store::progress_header();
        text.push('\n');
        text.push_str(std::str::from_utf8(&super::super::store::progress_bytes(&rows)).unwrap());
        std::fs::write(dir.path().join(PROGRESS), text).unwrap();
        let mut each = vec![];
        let file = Traces::read_each(dir.path(), |r| {
            each.push(r);
            Ok(())
        })
        .unwrap();
        assert_eq!(each, rows, "every row handed on, in the file's order");
        let memory = Traces::from_rows(&rows);
        for run in 0..4 {
            assert_eq!(
                file.get(run).unwrap(),
                memory.get(run).unwrap(),
                "run {run}"
            );
        }
        assert_eq!(file.get(1).unwrap().len(), 3);
        assert!(file.get(3).unwrap().is_empty());
    }

    #[test]
    fn a_bad_row_is_named_when_the_index_is_read() {
        let dir = tempfile::tempdir().unwrap();
        let text = format!(
            "{}\n0,r0,1,0.1,\n0,r0,two,0.2,\n",
            super::super::store::progress_header()
        );
        std::fs::write(dir.path().join(PROGRESS), text).unwrap();
        let e = Traces::read(dir.path()).unwrap_err().to_string();
        assert!(e.contains("progress.csv") && e.contains("row 2"), "{e}");
        // an error of the reader of each row stops the read with it
        let e = Traces::read_each(dir.path(), |_| Err(Error::Failed("full".into())));
        assert_eq!(
            e.unwrap_err().to_string(),
            Error::Failed("full".into()).to_string()
        );
    }
}
