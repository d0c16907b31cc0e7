//! `progress.parquet`: a finished folder's progress traces in Parquet, beside `progress.csv`,
//! as `runs.parquet` holds its runs ([`crate::parquet`]). `progress.csv` stays the crash-safe
//! record; this file is written from it when the folder is finalized, in its order (by run,
//! then iteration and time), a row group of [`ROW_GROUP`] points at a time, so no more than a
//! row group is held whatever the number of runs.
//!
//! The columns are `progress.csv`'s: `run` and `iteration` (64-bit integers), `run_id`
//! (text), `time_s` and `best_cost` (doubles; `best_cost` null before the run's first
//! solution), with the same `magbench.columns` and `magbench.version` metadata as
//! `runs.parquet`.

use std::path::Path;

use parquet::basic::Encoding;

use crate::Error;
use crate::parquet::{Atomic, Cells, Column, Grouped, Kind, Values};
use crate::record::ProgressRow;

/// `progress.parquet`.
pub const PROGRESS_PARQUET: &str = "progress.parquet";
/// Trace points per row group.
pub const ROW_GROUP: usize = 65_536;

/// The columns not dictionary-encoded, and their encodings.
const ENCODINGS: &[(&str, Encoding)] = &[
    ("iteration", Encoding::DELTA_BINARY_PACKED),
    ("time_s", Encoding::BYTE_STREAM_SPLIT),
    ("run", Encoding::DELTA_BINARY_PACKED),
];

/// The columns of the file, in `progress.csv`'s order.
pub fn columns() -> Vec<Column> {
    let column = |name: &str, kind, nullable, unit, label| Column {
        name: name.into(),
        kind,
        nullable,
        unit,
        label,
    };
    vec![
        column("run", Kind::Int, false, "", "the run's index"),
        column("run_id", Kind::Text, false, "", "the run's id"),
        column("iteration", Kind::Int, false, "", "iterations done"),
        column(
            "time_s",
            Kind::Float,
            false,
            "s",
            "seconds since the start of planning",
        ),
        column(
            "best_cost",
            Kind::Float,
            true,
            "",
            "best exact-solution cost so far (in the unit of the run's objective)",
        ),
    ]
}

/// The cells of column `index` of `rows`, typed as [`columns`] gives them.
fn cells(rows: &[ProgressRow], index: usize) -> Cells {
    let values = match index {
        0 => Values::Int(rows.iter().map(|r| r.run as i64).collect()),
        1 => Values::Text(rows.iter().map(|r| r.run_id.as_str().into()).collect()),
        2 => Values::Int(rows.iter().map(|r| r.iteration as i64).collect()),
        3 => Values::Float(rows.iter().map(|r| r.time_s).collect()),
        _ => Values::Float(rows.iter().filter_map(|r| r.best_cost).collect()),
    };
    let present = (index == 4).then(|| {
        rows.iter()
            .map(|r| i16::from(r.best_cost.is_some()))
            .collect()
    });
    Cells { values, present }
}

/// One row group of points.
fn group(file: &mut Atomic, rows: &[ProgressRow]) -> Result<(), Error> {
    file.row_group(|_, index| cells(rows, index))
}

/// A `progress.parquet` being written, a row group of [`ROW_GROUP`] points at a time: points
/// are pushed in order and a row group is written whenever one is full, so that the writer
/// holds no more than a row group.
pub struct Writer(Grouped<ProgressRow>);

impl Writer {
    /// Starts the file at `path` (written to a temporary file, renamed by [`Writer::finish`]).
    pub fn create(path: &Path) -> Result<Writer, Error> {
        let file = Atomic::create(path, "progress", columns(), ENCODINGS)?;
        Ok(Writer(Grouped::new(file, ROW_GROUP, group)))
    }

    /// Adds the next point.
    pub fn push(&mut self, row: ProgressRow) -> Result<(), Error> {
        self.0.push(row)
    }

    /// Writes the last row group, syncs the file and renames it to its path.
    pub fn finish(self) -> Result<(), Error> {
        self.0.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::store;
    use parquet::file::reader::{FileReader, SerializedFileReader};
    use parquet::record::RowAccessor;

    #[test]
    fn the_columns_are_the_csv_header() {
        let names: Vec<String> = columns().into_iter().map(|c| c.name).collect();
        assert_eq!(names.join(","), store::progress_header());
    }

    #[test]
    fn points_round_trip_with_their_empty_costs_across_row_groups() {
        let dir = tempfile::tempdir().unwrap();
        let rows: Vec<ProgressRow> = (0..ROW_GROUP + 3)
            .map(|i| ProgressRow {
                run: i / 7,
                run_id: format!("r{}", i / 7),
                iteration: (i % 7) as u64,
                time_s: 0.5 * i as f64,
                best_cost: (i % 3 != 0).then_some(i as f64),
            })
            .collect();
        let path = dir.path().join(PROGRESS_PARQUET);
        let mut w = Writer::create(&path).unwrap();
        for r in &rows {
            w.push(r.clone()).unwrap();
        }
        w.finish().unwrap();
        let reader = SerializedFileReader::new(std::fs::File::open(&path).unwrap()).unwrap();
        assert_eq!(reader.metadata().num_row_groups(), 2);
        let read: Vec<ProgressRow> = reader
            .get_row_iter(None)
            .unwrap()
            .map(|r| {
                let r = r.unwrap();
                ProgressRow {
                    run: r.get_long(0).unwrap() as usize,
                    run_id: r.get_string(1).unwrap().clone(),
                    iteration: r.get_long(2).unwrap() as u64,
                    time_s: r.get_double(3).unwrap(),
                    best_cost: r.get_double(4).ok(),
                }
            })
            .collect();
        assert_eq!(read, rows);
        assert!(!dir.path().join("progress.parquet.tmp").exists());
    }

    #[test]
    fn a_writer_dropped_unfinished_leaves_no_file_and_no_temporary_one() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(PROGRESS_PARQUET);
        let mut w = Writer::create(&path).unwrap();
        // a whole row group written, then an error on the way drops the writer
        for i in 0..ROW_GROUP + 1 {
            w.push(ProgressRow {
                run: i,
                run_id: format!("r{i}"),
                iteration: 1,
                time_s: 0.1,
                best_cost: None,
            })
            .unwrap();
        }
        assert!(dir.path().join("progress.parquet.tmp").exists());
        drop(w);
        assert!(!path.exists());
        assert!(!dir.path().join("progress.parquet.tmp").exists());
    }
}
