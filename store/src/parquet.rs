//! `runs.parquet`: a finished folder's runs in Parquet, beside `runs.csv`, for the tools that
//! read columnar files natively (polars, pandas with pyarrow, DuckDB, Arrow). `runs.csv`
//! stays the folder's crash-safe record, appended run by run; this file is written from it when
//! the folder is finalized, in run order, so both hold the same runs.
//!
//! The columns are `runs.csv`'s, in its order, typed: text, 64-bit integers, booleans and
//! doubles, nullable where a cell may be empty. The file's key–value metadata holds
//! `magbench.columns` (JSON: per column, its unit and label, from the metric and difficulty
//! tables; per-agent errors in BL) and `magbench.version`. Snappy compression, one row group
//! per [`ROW_GROUP`] runs.

use std::fs::File;
use std::path::Path;
use std::sync::Arc;

use parquet::basic::{Compression, Encoding, LogicalType, Repetition, Type as Physical};
use parquet::data_type::{BoolType, ByteArray, ByteArrayType, DoubleType, Int64Type};
use parquet::file::metadata::KeyValue;
use parquet::file::properties::WriterProperties;
use parquet::file::reader::{FileReader, SerializedFileReader};
use parquet::file::writer::SerializedFileWriter;
use parquet::record::RowAccessor;
use parquet::schema::types::{ColumnPath, Type};
use serde_json::{Value, json};

use magbench_analysis::metrics::Metric;
use magbench_analysis::metrics::difficulty::Measure;

use crate::Error;
use crate::record::RunRecord;
use crate::record::agent_columns;
use crate::temporary::Temporary;

/// `runs.parquet`.
pub const PARQUET: &str = "runs.parquet";
/// Runs per row group (docs/results.md, "`runs.parquet`": larger groups hold more memory).
pub const ROW_GROUP: usize = 8_192;

/// A column's type in the file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// UTF-8 text.
    Text,
    /// A 64-bit signed integer.
    Int,
    /// A boolean.
    Bool,
    /// A 64-bit float.
    Float,
}

/// The serde columns of [`RunRecord`] (the first columns of `runs.csv`), with their types and
/// whether a cell may be empty.
const RECORD: &[(&str, Kind, bool)] = &[
    ("run", Kind::Int, false),
    ("run_id", Kind::Text, false),
    ("experiment", Kind::Text, false),
    ("scenario", Kind::Text, false),
    ("agents", Kind::Int, false),
    ("planner", Kind::Text, false),
    ("planner_name", Kind::Text, false),
    ("planner_params", Kind::Text, false),
    ("tracker", Kind::Text, false),
    ("preset", Kind::Text, false),
    ("seed", Kind::Int, false),
    ("max_iterations", Kind::Int, true),
    ("time_limit_s", Kind::Float, true),
    ("status", Kind::Text, false),
    ("solved", Kind::Bool, false),
    ("approximate", Kind::Bool, false),
    ("progress_rows", Kind::Int, true),
    ("track_status", Kind::Text, false),
    ("reached_goal", Kind::Bool, true),
    ("worst_agent", Kind::Int, true),
    ("agent_contact", Kind::Bool, true),
    ("error", Kind::Text, false),
];

/// One column of the file.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// Its name (the `runs.csv` header's).
    pub name: String,
    /// Its type.
    pub kind: Kind,
    /// Whether a cell may be empty (null).
    pub nullable: bool,
    /// Its unit (empty: none).
    pub unit: &'static str,
    /// What it holds.
    pub label: &'static str,
}

/// The values of one column of a row group, of its type, without its nulls.
#[derive(Debug, Clone, PartialEq)]
pub enum Values {
    /// Text.
    Text(Vec<ByteArray>),
    /// 64-bit integers.
    Int(Vec<i64>),
    /// Booleans.
    Bool(Vec<bool>),
    /// Doubles.
    Float(Vec<f64>),
}

/// One column's cells in a row group: its values, and for a nullable column whether each cell
/// holds one (1) or is null (0).
#[derive(Debug, Clone, PartialEq)]
pub struct Cells {
    /// The values present, in row order.
    pub values: Values,
    /// Per row, 1 where a value is present and 0 where the cell is null; `None` for a column
    /// that cannot be null.
    pub present: Option<Vec<i16>>,
}

impl Cells {
    /// The cells of column `col` from their JSON values (null: an empty cell).
    fn from_json(col: &Column, cells: &[Value]) -> Cells {
        let present = cells.iter().filter(|v| !v.is_null());
        let values = match col.kind {
            Kind::Text => Values::Text(
                present
                    .map(|v| ByteArray::from(v.as_str().unwrap_or_default()))
                    .collect(),
            ),
            Kind::Int => Values::Int(present.map(|v| v.as_i64().unwrap_or_default()).collect()),
            Kind::Bool => Values::Bool(present.map(|v| v.as_bool().unwrap_or_default()).collect()),
            Kind::Float => Values::Float(present.map(|v| v.as_f64().unwrap_or(f64::NAN)).collect()),
        };
        let present = col
            .nullable
            .then(|| cells.iter().map(|v| i16::from(!v.is_null())).collect());
        Cells { values, present }
    }
}

/// The columns of a file with per-agent columns for `agents` agents, in `runs.csv`'s order.
pub fn columns(agents: usize) -> Vec<Column> {
    let record = RECORD.iter().map(|&(name, kind, nullable)| Column {
        name: name.into(),
        kind,
        nullable,
        unit: if name == "time_limit_s" { "s" } else { "" },
        label: "",
    });
    let metrics = Metric::ALL.iter().map(|m| {
        let d = m.def();
        Column {
            name: d.column.into(),
            kind: Kind::Float,
            nullable: true,
            unit: d.unit,
            label: d.label,
        }
    });
    let measures = Measure::ALL.iter().map(|m| {
        let d = m.def();
        Column {
            name: d.column.into(),
            kind: Kind::Float,
            nullable: true,
            unit: d.unit,
            label: d.label,
        }
    });
    let labels = [
        "agent's RMS path error, observed",
        "agent's largest path error, observed",
        "agent's RMS path error, true",
        "agent's largest path error, true",
    ];
    let per_agent = (0..agents).flat_map(move |i| {
        agent_columns(i)
            .into_iter()
            .zip(labels)
            .map(|(name, label)| Column {
                name,
                kind: Kind::Float,
                nullable: true,
                unit: "BL",
                label,
            })
    });
    record
        .chain(metrics)
        .chain(measures)
        .chain(per_agent)
        .collect()
}

/// The schema named `name` of the columns `cols`.
fn schema(name: &str, cols: &[Column]) -> Result<Type, parquet::errors::ParquetError> {
    let fields = cols
        .iter()
        .map(|c| {
            let (physical, logical) = match c.kind {
                Kind::Text => (Physical::BYTE_ARRAY, Some(LogicalType::String)),
                Kind::Int => (Physical::INT64, None),
                Kind::Bool => (Physical::BOOLEAN, None),
                Kind::Float => (Physical::DOUBLE, None),
            };
            let repetition = if c.nullable {
                Repetition::OPTIONAL
            } else {
                Repetition::REQUIRED
            };
            Type::primitive_type_builder(&c.name, physical)
                .with_repetition(repetition)
                .with_logical_type(logical)
                .build()
                .map(Arc::new)
        })
        .collect::<Result<Vec<_>, _>>()?;
    Type::group_type_builder(name).with_fields(fields).build()
}

/// The serde columns of `rows`, a column at a time in the order of [`RECORD`], from each row's
/// serde form.
fn serde_columns(rows: &[RunRecord]) -> Vec<Vec<Value>> {
    let mut out: Vec<Vec<Value>> = RECORD
        .iter()
        .map(|_| Vec::with_capacity(rows.len()))
        .collect();
    for r in rows {
        let mut o = match serde_json::to_value(r) {
            Ok(Value::Object(o)) => o,
            _ => serde_json::Map::new(),
        };
        for (c, (name, _, _)) in out.iter_mut().zip(RECORD) {
            c.push(o.remove(*name).unwrap_or(Value::Null));
        }
    }
    out
}

/// The cells of one column over `rows`: a serde column taken from `serde` ([`serde_columns`]).
fn cells(rows: &[RunRecord], serde: &mut [Vec<Value>], index: usize) -> Vec<Value> {
    let records = RECORD.len();
    let metrics = Metric::ALL.len();
    let measures = Measure::ALL.len();
    let num = |v: Option<f64>| v.map_or(Value::Null, |x| json!(x));
    match index {
        i if i < records => std::mem::take(&mut serde[i]),
        i if i < records + metrics => {
            let m = Metric::ALL[i - records];
            rows.iter().map(|r| num(r.get(m))).collect()
        }
        i if i < records + metrics + measures => {
            let m = Measure::ALL[i - records - metrics];
            rows.iter().map(|r| num(r.difficulty.get(m))).collect()
        }
        i => {
            let k = i - records - metrics - measures;
            rows.iter()
                .map(|r| num(r.per_agent.get(k / 4).and_then(|a| a.values()[k % 4])))
                .collect()
        }
    }
}

fn failed(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Failed(format!("{}: {e}", path.display()))
}

/// The writer properties of a magbench Parquet file with columns `cols`: Snappy compression,
/// and the key–value metadata `magbench.columns` (each column's unit and label, JSON) and
/// `magbench.version`; `encodings` sets a column's encoding in place of the dictionary.
pub(super) fn properties(cols: &[Column], encodings: &[(&str, Encoding)]) -> WriterProperties {
    let meta: serde_json::Map<String, Value> = cols
        .iter()
        .map(|c| (c.name.clone(), json!({"unit": c.unit, "label": c.label})))
        .collect();
    let mut b = WriterProperties::builder();
    for &(name, encoding) in encodings {
        let column = ColumnPath::from(name);
        b = b
            .set_column_dictionary_enabled(column.clone(), false)
            .set_column_encoding(column, encoding);
    }
    b.set_compression(Compression::SNAPPY)
        .set_created_by(format!("magbench {}", env!("CARGO_PKG_VERSION")))
        .set_key_value_metadata(Some(vec![
            KeyValue::new("magbench.columns".into(), Value::Object(meta).to_string()),
            KeyValue::new(
                "magbench.version".into(),
                env!("CARGO_PKG_VERSION").to_string(),
            ),
        ]))
        .build()
}

/// A Parquet file being written to a temporary file beside `path`, renamed to `path` by
/// [`Atomic::finish`]; a file dropped unfinished (an error on the way) is removed.
pub(super) struct Atomic {
    writer: SerializedFileWriter<File>,
    cols: Vec<Column>,
    tmp: Temporary,
    path: std::path::PathBuf,
}

impl Atomic {
    /// Starts the file at `path` with the columns `cols` in a schema named `name`, each column
    /// dictionary-encoded but those given an encoding in `encodings`.
    pub(super) fn create(
        path: &Path,
        name: &str,
        cols: Vec<Column>,
        encodings: &[(&str, Encoding)],
    ) -> Result<Atomic, Error> {
        let tmp = Temporary::new(path.with_extension("parquet.tmp"));
        let pq = |e: parquet::errors::ParquetError| failed(tmp.path(), e);
        let schema = Arc::new(schema(name, &cols).map_err(pq)?);
        let file = File::create(tmp.path()).map_err(|e| failed(tmp.path(), e))?;
        let props = Arc::new(properties(&cols, encodings));
        let writer = SerializedFileWriter::new(file, schema, props).map_err(pq)?;
        Ok(Atomic {
            writer,
            cols,
            tmp,
            path: path.to_path_buf(),
        })
    }

    /// Writes one row group: `cells(column, i)` gives column `i`'s cells, for each column in
    /// order.
    pub(super) fn row_group(
        &mut self,
        mut cells: impl FnMut(&Column, usize) -> Cells,
    ) -> Result<(), Error> {
        let pq = |e: parquet::errors::ParquetError| failed(self.tmp.path(), e);
        let mut g = self.writer.next_row_group().map_err(pq)?;
        let mut index = 0;
        while let Some(mut cw) = g.next_column().map_err(pq)? {
            let Cells { values, present } = cells(&self.cols[index], index);
            let defs = present.as_deref();
            match values {
                Values::Text(v) => cw.typed::<ByteArrayType>().write_batch(&v, defs, None),
                Values::Int(v) => cw.typed::<Int64Type>().write_batch(&v, defs, None),
                Values::Bool(v) => cw.typed::<BoolType>().write_batch(&v, defs, None),
                Values::Float(v) => cw.typed::<DoubleType>().write_batch(&v, defs, None),
            }
            .map_err(pq)?;
            cw.close().map_err(pq)?;
            index += 1;
        }
        g.close().map_err(pq)?;
        Ok(())
    }

    /// Closes the file, syncs it and renames it to its path.
    pub(super) fn finish(self) -> Result<(), Error> {
        let Atomic {
            writer, tmp, path, ..
        } = self;
        let file = writer.into_inner().map_err(|e| failed(tmp.path(), e))?;
        file.sync_all().map_err(|e| failed(tmp.path(), e))?;
        drop(file);
        std::fs::rename(tmp.path(), &path).map_err(|e| failed(&path, e))?;
        crate::store::sync_dir(&path)
    }
}

/// A Parquet file written a row group at a time: rows are pushed in order, and whenever
/// `size` are held they are written as one row group (by `group`), so that no more than a row
/// group is held.
pub(super) struct Grouped<T> {
    file: Atomic,
    rows: Vec<T>,
    size: usize,
    group: fn(&mut Atomic, &[T]) -> Result<(), Error>,
}

impl<T> Grouped<T> {
    /// Writes `file` in row groups of `size` rows, each by `group`.
    pub(super) fn new(
        file: Atomic,
        size: usize,
        group: fn(&mut Atomic, &[T]) -> Result<(), Error>,
    ) -> Grouped<T> {
        Grouped {
            file,
            rows: Vec::with_capacity(size.min(4096)),
            size,
            group,
        }
    }

    /// Adds the next row.
    pub(super) fn push(&mut self, row: T) -> Result<(), Error> {
        self.rows.push(row);
        if self.rows.len() == self.size {
            self.flush()?;
        }
        Ok(())
    }

    fn flush(&mut self) -> Result<(), Error> {
        if !self.rows.is_empty() {
            (self.group)(&mut self.file, &self.rows)?;
            self.rows.clear();
        }
        Ok(())
    }

    /// Writes the last row group, syncs the file and renames it to its path.
    pub(super) fn finish(mut self) -> Result<(), Error> {
        self.flush()?;
        self.file.finish()
    }
}

/// One row group of runs.
fn runs_group(file: &mut Atomic, group: &[RunRecord]) -> Result<(), Error> {
    let mut serde = serde_columns(group);
    file.row_group(|col, index| Cells::from_json(col, &cells(group, &mut serde, index)))
}

/// A `runs.parquet` being written (to a temporary file, renamed by [`Writer::finish`]), a row
/// group of [`ROW_GROUP`] runs at a time, so that no more than a row group is held.
pub struct Writer(Grouped<RunRecord>);

impl Writer {
    /// Starts the file at `path`, with per-agent columns for `agents` agents.
    pub fn create(path: &Path, agents: usize) -> Result<Writer, Error> {
        let file = Atomic::create(path, "runs", columns(agents), &[])?;
        Ok(Writer(Grouped::new(file, ROW_GROUP, runs_group)))
    }

    /// Adds the next run.
    pub fn push(&mut self, run: RunRecord) -> Result<(), Error> {
        self.0.push(run)
    }

    /// Writes the last row group, syncs the file and renames it to its path.
    pub fn finish(self) -> Result<(), Error> {
        self.0.finish()
    }
}

/// What [`check`] reads of a `runs.parquet`.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Rows in the file.
    pub rows: usize,
    /// Its column names, in order.
    pub columns: Vec<String>,
}

/// Reads the `runs.parquet` at `path` a row at a time, handing each row's `run_id` to
/// `each_id` in order: its rows and columns, or an error naming the reason when it is not a
/// whole Parquet file of runs.
pub fn check(path: &Path, mut each_id: impl FnMut(&str)) -> Result<Summary, String> {
    let file = File::open(path).map_err(|e| e.to_string())?;
    let reader = SerializedFileReader::new(file).map_err(|e| format!("not a Parquet file: {e}"))?;
    let meta = reader.metadata().file_metadata();
    let columns: Vec<String> = meta
        .schema_descr()
        .columns()
        .iter()
        .map(|c| c.name().to_string())
        .collect();
    let id = columns
        .iter()
        .position(|c| c == "run_id")
        .ok_or("no run_id column")?;
    let mut rows = 0;
    for row in reader.get_row_iter(None).map_err(|e| e.to_string())? {
        let row = row.map_err(|e| format!("a row does not read: {e}"))?;
        each_id(row.get_string(id).map_err(|e| format!("run_id: {e}"))?);
        rows += 1;
    }
    Ok(Summary { rows, columns })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::store;

    #[test]
    fn the_record_columns_are_the_csv_headers_first_columns() {
        let header = store::runs_header(3);
        let names: Vec<String> = columns(3).into_iter().map(|c| c.name).collect();
        assert_eq!(names.join(","), header);
    }

    #[test]
    fn runs_round_trip_with_their_ids_and_a_torn_file_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let rows: Vec<RunRecord> = (0..5)
            .map(|i| {
                let mut r = store::tests::out(i).record;
                r.set(Metric::RmsError, (i % 2 == 0).then_some(0.25 * i as f64));
                r
            })
            .collect();
        let path = dir.path().join(PARQUET);
        let mut w = Writer::create(&path, 0).unwrap();
        for r in &rows {
            w.push(r.clone()).unwrap();
        }
        w.finish().unwrap();
        let mut ids = vec![];
        let s = check(&path, |id| ids.push(id.to_string())).unwrap();
        assert_eq!(s.rows, 5);
        assert_eq!(s.columns.join(","), store::runs_header(0));
        assert_eq!(
            ids,
            rows.iter().map(|r| r.run_id.clone()).collect::<Vec<_>>()
        );
        let bytes = std::fs::read(&path).unwrap();
        std::fs::write(&path, &bytes[..bytes.len() / 2]).unwrap();
        let e = check(&path, |_| {}).unwrap_err();
        assert!(e.starts_with("not a Parquet file"), "{e}");
        assert!(!dir.path().join("runs.parquet.tmp").exists());
    }
}
