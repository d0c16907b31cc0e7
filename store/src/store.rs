//! The files of a results folder that hold runs: `runs.csv` and `progress.csv`.
//!
//! Crash safety: each finished run appends its progress rows, then its `runs.csv` row (which
//! records how many progress rows the run has, `progress_rows`), each in one write of whole
//! lines, then syncs both files. A kill at any byte leaves each file a prefix of what would
//! have been written; [`crate::repair`] (called before resuming) drops a partial last line,
//! progress rows without their run's row, and runs whose trace is not exactly `progress_rows`
//! long, so those runs run again and none is doubled or lost.
//!
//! Columns: the serde columns of [`RunRecord`], one per metric of the table
//! ([`magbench_analysis::metrics`]), one per difficulty measure of the run's scenario
//! ([`magbench_analysis::metrics::difficulty`]), then the per-agent columns.
//!
//! Per-agent columns: after the fixed columns of [`RunRecord`], `runs.csv` has the columns of
//! [`agent_columns`] for agents `0..n`, `n` the largest team the experiment tracks (0 for
//! planning only). A run of a smaller team leaves the columns of the agents it lacks empty, so
//! one file has one header whatever its teams. The header names `n`: resuming and rewriting
//! keep it.

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};

use magbench_analysis::metrics::Metric;
use magbench_analysis::metrics::difficulty::Measure;

use crate::Error;
use crate::record::{AgentErrors, agent_columns};
use crate::record::{ProgressRow, RunRecord};

/// `runs.csv`.
pub const RUNS: &str = "runs.csv";
/// `progress.csv`.
pub const PROGRESS: &str = "progress.csv";

pub(super) fn failed(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Failed(format!("{}: {e}", path.display()))
}

fn header_line<T: serde::Serialize>(example: &T) -> String {
    let mut w = csv::Writer::from_writer(vec![]);
    w.serialize(example).expect("serialize");
    let text = String::from_utf8(w.into_inner().expect("flush")).expect("utf8");
    text.lines().next().unwrap_or_default().to_string()
}

/// The header of a `runs.csv` with per-agent columns for `agents` agents.
pub fn runs_header(agents: usize) -> String {
    let mut h = header_line(&RunRecord::example());
    for m in Metric::ALL {
        h.push(',');
        h.push_str(m.def().column);
    }
    for m in Measure::ALL {
        h.push(',');
        h.push_str(m.def().column);
    }
    for i in 0..agents {
        for c in agent_columns(i) {
            h.push(',');
            h.push_str(&c);
        }
    }
    h
}

/// The number of agents whose columns `header` (a `runs.csv` header line) has, if it is a
/// header of this version.
pub fn header_agents(header: &str) -> Option<usize> {
    let n = header
        .split(',')
        .filter(|c| c.starts_with("rms_error_agent"))
        .count();
    (runs_header(n) == header).then_some(n)
}

/// Agents whose columns a torn header is checked against: more than any scenario has.
const TORN_HEADER_AGENTS: usize = 64;

/// True if `text` (a whole `runs.csv`) is a header cut short: no complete line, and a prefix
/// of this version's header.
pub fn is_torn_runs_header(text: &str) -> bool {
    complete_len(text) == 0 && runs_header(TORN_HEADER_AGENTS).starts_with(text)
}

/// True if `text` (a whole `progress.csv`) is a header cut short.
pub fn is_torn_progress_header(text: &str) -> bool {
    complete_len(text) == 0 && progress_header().starts_with(text)
}

/// The per-agent columns a set of runs needs: the largest tracked team.
pub fn tracked_agents<'a>(runs: impl IntoIterator<Item = &'a RunRecord>) -> usize {
    runs.into_iter()
        .filter(|r| !r.tracker.is_empty())
        .map(|r| r.agents)
        .max()
        .unwrap_or(0)
}

/// The per-agent columns of the existing `runs.csv` of `dir` (0 without one).
pub fn file_agents(dir: &Path) -> usize {
    first_line(&dir.join(RUNS))
        .ok()
        .flatten()
        .and_then(|h| header_agents(&h))
        .unwrap_or(0)
}

/// Longest first line [`first_line`] reads (bytes): far more than the header of a `runs.csv`
/// with per-agent columns for the largest team.
const MAX_HEADER_BYTES: u64 = 1 << 20;

/// The first line of the file at `path` without its line end (all of the file if it has no
/// line end, up to [`MAX_HEADER_BYTES`]), or `None` if there is no file.
pub fn first_line(path: &Path) -> Result<Option<String>, Error> {
    use std::io::{BufRead, Read};
    let f = match File::open(path) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(failed(path, e)),
    };
    let mut line = vec![];
    std::io::BufReader::new(f.take(MAX_HEADER_BYTES))
        .read_until(b'\n', &mut line)
        .map_err(|e| failed(path, e))?;
    if line.last() == Some(&b'\n') {
        line.pop();
    }
    Ok(Some(String::from_utf8_lossy(&line).into_owned()))
}

/// `runs.csv` rows: the serde columns, the metric columns, the difficulty columns, then
/// `agents` agents' per-agent columns.
pub fn run_bytes(rows: &[RunRecord], agents: usize) -> Vec<u8> {
    let mut out = vec![];
    for r in rows {
        let mut line = record_bytes(std::slice::from_ref(r));
        // the csv writer ends a record with one '\n'; the extra cells are plain numbers
        debug_assert_eq!(line.last(), Some(&b'\n'));
        line.pop();
        let cells = Metric::ALL
            .iter()
            .map(|m| r.get(*m))
            .chain(Measure::ALL.iter().map(|m| r.difficulty.get(*m)))
            .chain(
                (0..agents).flat_map(|i| r.per_agent.get(i).copied().unwrap_or_default().values()),
            );
        for v in cells {
            line.push(b',');
            if let Some(v) = v {
                line.extend(format!("{v}").bytes());
            }
        }
        line.push(b'\n');
        out.extend(line);
    }
    out
}

/// The header of `progress.csv`.
pub fn progress_header() -> String {
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
    agents: usize,
    stall_after: Option<u64>,
}

/// The environment variable that makes a [`RunWriter`] stop for good after appending this many
/// bytes of runs (a write that crosses the mark is cut there), announcing it on stderr: the
/// crash tests kill the process then, which leaves exactly the files of a kill at that byte.
pub const STALL_ENV: &str = "MAGBENCH_STALL_AT_BYTE";

impl RunWriter {
    /// Opens (creating with headers if needed) the run files of `dir` for appending, with
    /// per-agent columns for `agents` agents (the largest team the experiment tracks). Call
    /// [`crate::repair::repair`] first on a folder that may hold an interrupted sweep.
    pub fn open(dir: &Path, agents: usize) -> Result<RunWriter, Error> {
        std::fs::create_dir_all(dir).map_err(|e| failed(dir, e))?;
        let runs = open_with_header(&dir.join(RUNS), &runs_header(agents))?;
        let progress = open_with_header(&dir.join(PROGRESS), &progress_header())?;
        Ok(RunWriter {
            runs,
            progress,
            dir: dir.to_path_buf(),
            agents,
            stall_after: std::env::var(STALL_ENV).ok().and_then(|v| v.parse().ok()),
        })
    }

    /// Writes one finished run: progress rows first, then the run's row (the commit mark, with
    /// the number of progress rows), then syncs both files. What the folder holds of the run
    /// besides (its replay page) is written before, so that a run with a row has all of it.
    pub fn write(&mut self, record: &RunRecord, progress: &[ProgressRow]) -> Result<(), Error> {
        let mut record = record.clone();
        record.progress_rows = Some(progress.len() as u64);
        if !progress.is_empty() {
            self.append(PROGRESS, &record_bytes(progress))?;
        }
        self.append(RUNS, &run_bytes(std::slice::from_ref(&record), self.agents))?;
        for (f, name) in [(&self.progress, PROGRESS), (&self.runs, RUNS)] {
            f.sync_data().map_err(|e| failed(&self.dir.join(name), e))?;
        }
        Ok(())
    }

    fn append(&mut self, name: &str, bytes: &[u8]) -> Result<(), Error> {
        let f = if name == RUNS {
            &mut self.runs
        } else {
            &mut self.progress
        };
        let path = self.dir.join(name);
        if let Some(left) = self.stall_after.as_mut() {
            if bytes.len() as u64 > *left {
                let cut = *left as usize;
                f.write_all(&bytes[..cut]).map_err(|e| failed(&path, e))?;
                eprintln!("{STALL_ENV}: stalled in {name} after {cut} bytes of a write");
                loop {
                    std::thread::park();
                }
            }
            *left -= bytes.len() as u64;
        }
        f.write_all(bytes).map_err(|e| failed(&path, e))
    }
}

fn open_with_header(path: &Path, header: &str) -> Result<File, Error> {
    let existing = first_line(path)?.unwrap_or_default();
    let mut f = OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .map_err(|e| failed(path, e))?;
    if existing.is_empty() {
        f.write_all(format!("{header}\n").as_bytes())
            .map_err(|e| failed(path, e))?;
        f.sync_data().map_err(|e| failed(path, e))?;
    } else if existing != header {
        return Err(Error::Input(magbench_env::InputError::new(
            path.display().to_string(),
            "header",
            "the columns differ from this version of magbench; write to a new --out folder",
        )));
    }
    Ok(f)
}

/// Fewer bytes than any `runs.csv` row has: one separator per column (the serde, metric and
/// difficulty columns alone are more than 70).
const MIN_ROW_BYTES: u64 = 64;

/// Reads the complete rows of `runs.csv` (a trailing partial line is ignored), one at a time,
/// with their difficulty and per-agent columns (a file without them, e.g. of an older
/// version, gives none).
pub fn read_runs(dir: &Path) -> Result<Vec<RunRecord>, Error> {
    let Some(s) = Snapshot::open(&dir.join(RUNS))? else {
        return Ok(vec![]);
    };
    // as many as the file has rows (a vector that grows by doubling would hold up to twice),
    // but no more than its bytes allow: a row has a cell per column, so at least
    // `MIN_ROW_BYTES` bytes of separators, whatever blank lines the file holds
    let rows = s
        .lines()
        .saturating_sub(1)
        .min(s.complete_len() / MIN_ROW_BYTES);
    let mut runs = Vec::with_capacity(rows as usize);
    for r in s.runs()? {
        runs.push(r?);
    }
    Ok(runs)
}

/// Parses the complete rows `text` (header first) of the `runs.csv` at `path`.
pub fn parse_runs(path: &Path, text: &str) -> Result<Vec<RunRecord>, Error> {
    RunRows::new(path, text.as_bytes())?.collect()
}

pub(super) fn bad_row(path: &Path, row: usize, e: String) -> Error {
    Error::Input(magbench_env::InputError::new(
        path.display().to_string(),
        format!("row {row}"),
        e,
    ))
}

/// The rows of a `runs.csv`, read one at a time from `R` (complete lines only, header first):
/// the serde columns, then the metric, difficulty and per-agent columns the header has.
pub struct RunRows<R: std::io::Read> {
    path: PathBuf,
    reader: csv::Reader<R>,
    headers: csv::StringRecord,
    /// The column of each metric the header has.
    metrics: Vec<(Metric, usize)>,
    /// The column of each difficulty measure the header has (none in files of older versions).
    measures: Vec<(Measure, usize)>,
    /// The column of each per-agent value, for every agent the header has.
    agents: Vec<[Option<usize>; 4]>,
    /// Rows read so far.
    row: usize,
    record: csv::StringRecord,
}

impl<R: std::io::Read> RunRows<R> {
    /// Reads the header of the `runs.csv` at `path` (named in errors) from `input`.
    pub fn new(path: &Path, input: R) -> Result<RunRows<R>, Error> {
        let mut reader = csv::Reader::from_reader(input);
        let headers = reader
            .headers()
            .map_err(|e| bad_row(path, 0, e.to_string()))?
            .clone();
        let col = |name: &str| headers.iter().position(|h| h == name);
        let metrics = Metric::ALL
            .iter()
            .filter_map(|m| Some((*m, col(m.def().column)?)))
            .collect();
        let measures = Measure::ALL
            .iter()
            .filter_map(|m| Some((*m, col(m.def().column)?)))
            .collect();
        let agents = (0..)
            .map(|a| agent_columns(a).map(|c| col(&c)))
            .take_while(|c| c[0].is_some())
            .collect();
        Ok(RunRows {
            path: path.to_path_buf(),
            reader,
            headers,
            metrics,
            measures,
            agents,
            row: 0,
            record: csv::StringRecord::new(),
        })
    }

    fn parse(&self) -> Result<RunRecord, Error> {
        let (row, i) = (&self.record, self.row);
        let headers = &self.headers;
        let bad = |e: String| bad_row(&self.path, i, e);
        let mut r: RunRecord = row
            .deserialize(Some(headers))
            .map_err(|e| bad(e.to_string()))?;
        let cell = |c: Option<usize>| -> Result<Option<f64>, Error> {
            let Some(c) = c else { return Ok(None) };
            match row.get(c).filter(|v| !v.is_empty()) {
                None => Ok(None),
                Some(v) => v
                    .parse()
                    .map(Some)
                    .map_err(|e| bad(format!("{}: {v:?}: {e}", &headers[c]))),
            }
        };
        for &(m, c) in &self.metrics {
            r.set(m, cell(Some(c))?);
        }
        for &(m, c) in &self.measures {
            r.difficulty.set(m, cell(Some(c))?);
        }
        r.per_agent.reserve_exact(self.agents.len());
        for cols in &self.agents {
            let mut v = [None; 4];
            for (v, &c) in v.iter_mut().zip(cols) {
                *v = cell(c)?;
            }
            r.per_agent.push(AgentErrors::from_values(v));
        }
        // a run of a smaller team: no trailing empty agents
        while r
            .per_agent
            .last()
            .is_some_and(|a| a.values().iter().all(Option::is_none))
        {
            r.per_agent.pop();
        }
        r.per_agent.shrink_to_fit();
        Ok(r)
    }
}

impl<R: std::io::Read> Iterator for RunRows<R> {
    type Item = Result<RunRecord, Error>;

    fn next(&mut self) -> Option<Self::Item> {
        self.row += 1;
        match self.reader.read_record(&mut self.record) {
            Ok(false) => None,
            Ok(true) => Some(self.parse()),
            Err(e) => Some(Err(bad_row(&self.path, self.row, e.to_string()))),
        }
    }
}

/// A CSV file that another process may still append to (or replace), opened once: its
/// complete lines as they were when it was opened (up to its last line end outside quotes;
/// what follows is a line cut short), which every [`Snapshot::reader`] reads again, whatever
/// is written to the file later.
pub struct Snapshot {
    path: PathBuf,
    file: File,
    len: u64,
    /// The file's length when it was opened: more than `len` when its last line is cut short.
    size: u64,
    /// Its complete lines.
    lines: u64,
}

impl Snapshot {
    /// Opens the file at `path` and finds the end of its complete lines (`None`: no file).
    pub fn open(path: &Path) -> Result<Option<Snapshot>, Error> {
        use std::io::{BufRead, BufReader};
        let file = match File::open(path) {
            Ok(f) => f,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(failed(path, e)),
        };
        let mut r = BufReader::new(&file);
        let (mut quoted, mut len, mut at, mut lines) = (false, 0u64, 0u64, 0u64);
        loop {
            let buf = r.fill_buf().map_err(|e| failed(path, e))?;
            if buf.is_empty() {
                break;
            }
            for &b in buf {
                at += 1;
                match b {
                    b'"' => quoted = !quoted,
                    b'\n' if !quoted => {
                        len = at;
                        lines += 1;
                    }
                    _ => {}
                }
            }
            let n = buf.len();
            r.consume(n);
        }
        Ok(Some(Snapshot {
            path: path.to_path_buf(),
            file,
            len,
            size: at,
            lines,
        }))
    }

    /// The length of its complete lines (bytes).
    pub fn complete_len(&self) -> u64 {
        self.len
    }

    /// The number of its complete lines (the header is one).
    pub fn lines(&self) -> u64 {
        self.lines
    }

    /// The file's length when it was opened (bytes).
    pub fn size(&self) -> u64 {
        self.size
    }

    /// Whether the file ended in a complete line when it was opened.
    pub fn is_whole(&self) -> bool {
        self.len == self.size
    }

    /// The file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The complete lines, from the start; one reader at a time (they share the file offset).
    pub fn reader(&self) -> Result<std::io::Take<std::io::BufReader<File>>, Error> {
        use std::io::{Read, Seek};
        let mut f = self.file.try_clone().map_err(|e| failed(&self.path, e))?;
        f.rewind().map_err(|e| failed(&self.path, e))?;
        Ok(std::io::BufReader::new(f).take(self.len))
    }

    /// The rows of this `runs.csv`, read one at a time.
    pub fn runs(&self) -> Result<RunRows<std::io::Take<std::io::BufReader<File>>>, Error> {
        RunRows::new(&self.path, self.reader()?)
    }

    /// The rows of this `progress.csv`, read one at a time.
    pub fn progress(
        &self,
    ) -> Result<impl Iterator<Item = Result<ProgressRow, Error>> + use<>, Error> {
        let path = self.path.clone();
        Ok(csv::Reader::from_reader(self.reader()?)
            .into_deserialize()
            .enumerate()
            .map(move |(i, r)| r.map_err(|e| bad_row(&path, i + 1, e.to_string()))))
    }
}

/// `progress.csv` rows, without a header.
pub fn progress_bytes(rows: &[ProgressRow]) -> Vec<u8> {
    record_bytes(rows)
}

/// Reads the complete rows of `progress.csv`, one at a time.
pub fn read_progress(dir: &Path) -> Result<Vec<ProgressRow>, Error> {
    match Snapshot::open(&dir.join(PROGRESS))? {
        Some(s) => s.progress()?.collect(),
        None => Ok(vec![]),
    }
}

/// The length of the complete lines of CSV `text`: up to its last line end outside quotes
/// (the rest is a line cut short).
pub fn complete_len(text: &str) -> usize {
    let mut quoted = false;
    let mut end = 0;
    for (i, b) in text.bytes().enumerate() {
        match b {
            b'"' => quoted = !quoted,
            b'\n' if !quoted => end = i + 1,
            _ => {}
        }
    }
    end
}

/// The complete lines of CSV `text`.
pub fn complete_part(text: &str) -> &str {
    &text[..complete_len(text)]
}

/// Parses the complete rows `text` (header first) of the `progress.csv` at `path`.
pub fn parse_progress(path: &Path, text: &str) -> Result<Vec<ProgressRow>, Error> {
    parse_rows(path, text)
}

fn parse_rows<T: serde::de::DeserializeOwned>(path: &Path, text: &str) -> Result<Vec<T>, Error> {
    let mut rd = csv::Reader::from_reader(text.as_bytes());
    let mut out = vec![];
    for (i, r) in rd.deserialize().enumerate() {
        out.push(r.map_err(|e| {
            Error::Input(magbench_env::InputError::new(
                path.display().to_string(),
                format!("row {}", i + 1),
                e.to_string(),
            ))
        })?);
    }
    Ok(out)
}

/// Replaces `path` with `header` and `rows`, atomically (write a temporary file, then rename).
pub fn write_atomic<T: serde::Serialize>(
    path: &Path,
    header: &str,
    rows: &[T],
) -> Result<(), Error> {
    replace_atomic(path, header, record_bytes(rows))
}

/// Replaces the `runs.csv` at `path` with `rows` and per-agent columns for `agents` agents,
/// atomically.
pub fn write_runs_atomic(path: &Path, agents: usize, rows: &[RunRecord]) -> Result<(), Error> {
    replace_atomic(path, &runs_header(agents), run_bytes(rows, agents))
}

fn replace_atomic(path: &Path, header: &str, rows: Vec<u8>) -> Result<(), Error> {
    let mut r = Replacement::create(path, header)?;
    r.write(&rows)?;
    r.commit()
}

/// A file written beside the file it replaces (`.csv.tmp`) and renamed over it once whole, so
/// that the folder holds the old file or the new one, never a part; removed if dropped before
/// [`Replacement::commit`].
pub struct Replacement {
    path: PathBuf,
    tmp: PathBuf,
    out: Option<std::io::BufWriter<File>>,
}

impl Replacement {
    /// Starts the replacement of `path`, with the line `header`.
    pub fn create(path: &Path, header: &str) -> Result<Replacement, Error> {
        let tmp = path.with_extension("csv.tmp");
        let f = File::create(&tmp).map_err(|e| failed(&tmp, e))?;
        let mut r = Replacement {
            path: path.to_path_buf(),
            tmp,
            out: Some(std::io::BufWriter::new(f)),
        };
        r.write(format!("{header}\n").as_bytes())?;
        Ok(r)
    }

    /// Appends `bytes` (whole lines).
    pub fn write(&mut self, bytes: &[u8]) -> Result<(), Error> {
        let out = self.out.as_mut().expect("written before the commit");
        out.write_all(bytes).map_err(|e| failed(&self.tmp, e))
    }

    /// Syncs the new file and renames it over the old one.
    pub fn commit(mut self) -> Result<(), Error> {
        let out = self.out.take().expect("committed once");
        let f = out.into_inner().map_err(|e| failed(&self.tmp, e.error()))?;
        f.sync_all().map_err(|e| failed(&self.tmp, e))?;
        std::fs::rename(&self.tmp, &self.path).map_err(|e| failed(&self.path, e))?;
        sync_dir(&self.path)
    }
}

impl Drop for Replacement {
    fn drop(&mut self) {
        if self.out.is_some() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// Syncs the folder holding `path`, so that a rename into it is durable.
pub fn sync_dir(path: &Path) -> Result<(), Error> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    // a folder that cannot be opened or synced (some file systems) is left as it is
    if let Ok(d) = File::open(dir) {
        let _ = d.sync_all();
    }
    Ok(())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::record::Status;

    /// A finished run as the tests write it.
    pub(crate) struct Out {
        pub(crate) record: RunRecord,
        pub(crate) progress: Vec<ProgressRow>,
    }

    impl RunWriter {
        /// Writes the run `o`.
        pub(crate) fn write_out(&mut self, o: &Out) -> Result<(), Error> {
            self.write(&o.record, &o.progress)
        }
    }

    /// Run `i` of a small exact result with three progress rows.
    pub(crate) fn out(i: usize) -> Out {
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
        Out {
            record: r,
            progress,
        }
    }

    fn tracked(i: usize, agents: usize) -> Out {
        let mut o = out(i);
        o.record.tracker = "obc".into();
        o.record.agents = agents;
        o.record.set(Metric::RmsError, Some(0.1 + agents as f64));
        o.record.set(Metric::ClearanceMin, Some(1.0 / 3.0));
        o.record
            .difficulty
            .set(Measure::FreeFraction, Some(0.1 * agents as f64));
        o.record
            .difficulty
            .set(Measure::ShapeChangeBl, Some(1.0 / 7.0));
        o.record.per_agent = (0..agents)
            .map(|a| AgentErrors {
                rms_bl: Some(0.1 * (a + 1) as f64),
                max_bl: Some(0.5 + a as f64),
                rms_true_bl: (a != 1).then_some(0.05),
                max_true_bl: Some(0.25),
            })
            .collect();
        o
    }

    #[test]
    fn per_agent_columns_span_the_largest_team_and_round_trip() {
        let dir = tempfile::tempdir().unwrap();
        let mut w = RunWriter::open(dir.path(), 4).unwrap();
        for (i, n) in [(0, 2), (1, 4), (2, 3)] {
            w.write_out(&tracked(i, n)).unwrap();
        }
        w.write_out(&out(3)).unwrap();
        drop(w);
        let text = std::fs::read_to_string(dir.path().join(RUNS)).unwrap();
        let header = text.lines().next().unwrap();
        let last = Measure::ALL.last().unwrap().def().column;
        assert!(header.ends_with(&format!(",{last},rms_error_agent0_bl,max_error_agent0_bl,rms_error_true_agent0_bl,max_error_true_agent0_bl,rms_error_agent1_bl,max_error_agent1_bl,rms_error_true_agent1_bl,max_error_true_agent1_bl,rms_error_agent2_bl,max_error_agent2_bl,rms_error_true_agent2_bl,max_error_true_agent2_bl,rms_error_agent3_bl,max_error_agent3_bl,rms_error_true_agent3_bl,max_error_true_agent3_bl")), "{header}");
        // one header, every row as wide: absent agents are empty cells
        let mut rd = csv::Reader::from_reader(text.as_bytes());
        let width = rd.headers().unwrap().len();
        let rows: Vec<csv::StringRecord> = rd.records().map(|r| r.unwrap()).collect();
        assert!(rows.iter().all(|r| r.len() == width));
        assert!((width - 8..width).all(|c| rows[0][c].is_empty()));
        assert!(!rows[0][width - 9].is_empty());
        let back = read_runs(dir.path()).unwrap();
        for (i, n) in [(0, 2), (1, 4), (2, 3)] {
            let mut want = tracked(i, n).record;
            want.progress_rows = Some(3);
            assert_eq!(back[i], want);
        }
        assert!(back[3].per_agent.is_empty());
        // resuming keeps the header; sorting into run order keeps the columns
        RunWriter::open(dir.path(), 4).unwrap();
        crate::sort::sort_files(dir.path()).unwrap();
        assert_eq!(read_runs(dir.path()).unwrap(), back);
        let again = std::fs::read_to_string(dir.path().join(RUNS)).unwrap();
        assert_eq!(again.lines().next().unwrap(), header);
        // another team size on resume is another version of the file
        assert!(RunWriter::open(dir.path(), 3).is_err());
    }

    #[test]
    fn blank_lines_reserve_no_more_rows_than_the_bytes_allow() {
        let dir = tempfile::tempdir().unwrap();
        let mut text = runs_header(0);
        text.push_str(&"\n".repeat(1_000_000));
        let bytes = text.len();
        std::fs::write(dir.path().join(RUNS), text).unwrap();
        let runs = read_runs(dir.path()).unwrap();
        assert!(runs.is_empty());
        assert!(
            runs.capacity() <= bytes / MIN_ROW_BYTES as usize,
            "{}",
            runs.capacity()
        );
        assert!(runs_header(0).split(',').count() as u64 > MIN_ROW_BYTES);
    }

    #[test]
    fn a_file_without_per_agent_columns_still_reads() {
        // the header of a version before the per-agent and worst-agent columns
        let dir = tempfile::tempdir().unwrap();
        let old = "run,run_id,experiment,scenario,agents,planner,planner_name,planner_params,tracker,preset,seed,max_iterations,time_limit_s,status,solved,approximate,iterations,nodes,plan_time_s,cost,goal_distance,first_solution_iteration,first_solution_time_s,plan_edges,plan_duration_s,track_status,reached_goal,time_to_goal_s,rms_error_bl,max_error_bl,rms_error_worst_agent_bl,rms_error_true_bl,rms_error_sync_bl,rms_error_time_bl,legs_completed,final_distance_bl,agent_contact,wall_contacts,missed_frames,replans,track_duration_s,track_time_s,error\n0,a|b|obc|realistic|0,ci,open-field,2,goal-zoom-rrt,goal-zoom-rrt,,obc,realistic,0,3000,,exact,true,false,10,11,0.1,5.0,0.1,3,0.01,4,5.0,reached-goal,true,6.0,0.07,0.2,0.08,0.06,0.09,0.3,1,0.1,false,0,2,0,6.0,0.5,\n";
        std::fs::write(dir.path().join(RUNS), old).unwrap();
        let r = read_runs(dir.path()).unwrap();
        assert_eq!(r.len(), 1);
        assert_eq!(r[0].get(Metric::RmsErrorWorstAgent), Some(0.08));
        assert_eq!(r[0].get(Metric::Iterations), Some(10.0));
        assert_eq!(
            (r[0].worst_agent, r[0].get(Metric::RmsErrorTrueWorstAgent)),
            (None, None)
        );
        assert!(r[0].per_agent.is_empty());
        assert!(
            r[0].difficulty.is_empty(),
            "no difficulty columns, no values"
        );
    }
}
