//! A results folder's run files put in their canonical order on disk — `runs.csv` by run index,
//! `progress.csv` by run, iteration and time (stable: rows with equal keys keep their order) —
//! without holding their rows: each file is read once for the byte ranges of its records and
//! their keys, and rewritten (atomically) by copying the ranges in order. A file already in
//! order is left as it is; one whose last line is cut short loses that line.
//!
//! A run's progress rows are written in one append, in order, so `progress.csv` is indexed by
//! runs (one byte range per stretch of a run's rows) and only a run whose rows are out of order
//! or in several stretches has its rows read and sorted, on their own.

use std::cmp::Ordering;
use std::fs::File;
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::Path;

use crate::Error;
use crate::store::{self, PROGRESS, RUNS, Snapshot, bad_row, failed};

/// A byte range of a file.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Range {
    start: u64,
    end: u64,
}

/// A progress row's order within its run: iteration, then time.
#[derive(Debug, Clone, Copy)]
struct Point {
    iteration: u64,
    time_s: f64,
}

impl Point {
    fn cmp(&self, other: &Point) -> Ordering {
        self.iteration
            .cmp(&other.iteration)
            .then(self.time_s.total_cmp(&other.time_s))
    }
}

/// One stretch of consecutive `progress.csv` rows of one run.
#[derive(Debug, Clone, Copy)]
struct Stretch {
    run: usize,
    range: Range,
    /// Whether its rows are in order.
    ordered: bool,
}

/// Sorts `runs.csv` and `progress.csv` of `dir` (writing each with this version's header
/// when it is missing or has no complete line).
pub fn sort_files(dir: &Path) -> Result<(), Error> {
    sort_runs(&dir.join(RUNS))?;
    sort_progress(&dir.join(PROGRESS))
}

/// A file's header: its byte range and its columns.
struct Head {
    range: Range,
    columns: csv::StringRecord,
}

/// Reads `snap` once: hands `visit` what `key` reads from each record after the header (under
/// the header) and the record's byte range, in file order; the header (`None`: no complete
/// line).
fn records<K>(
    snap: &Snapshot,
    key: impl Fn(&csv::StringRecord, &csv::StringRecord) -> Result<K, String>,
    mut visit: impl FnMut(K, Range),
) -> Result<Option<Head>, Error> {
    let path = snap.path();
    let mut rd = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(snap.reader()?);
    let (mut header, mut rec) = (csv::StringRecord::new(), csv::StringRecord::new());
    let read = |rd: &mut csv::Reader<_>, rec: &mut csv::StringRecord, row: usize| {
        let start = rd.position().byte();
        let more = rd
            .read_record(rec)
            .map_err(|e| bad_row(path, row, e.to_string()))?;
        Ok::<_, Error>(more.then(|| Range {
            start,
            end: rd.position().byte(),
        }))
    };
    let Some(range) = read(&mut rd, &mut header, 0)? else {
        return Ok(None);
    };
    let mut row = 1;
    while let Some(r) = read(&mut rd, &mut rec, row)? {
        visit(key(&header, &rec).map_err(|e| bad_row(path, row, e))?, r);
        row += 1;
    }
    Ok(Some(Head {
        range,
        columns: header,
    }))
}

/// The value of column `name` of `rec` under `header`, parsed.
fn cell<T: std::str::FromStr>(
    header: &csv::StringRecord,
    rec: &csv::StringRecord,
    name: &str,
) -> Result<T, String>
where
    T::Err: std::fmt::Display,
{
    let c = header
        .iter()
        .position(|h| h == name)
        .ok_or_else(|| format!("no column `{name}`"))?;
    let v = rec.get(c).unwrap_or_default();
    v.parse().map_err(|e| format!("{name}: {v:?}: {e}"))
}

fn sort_runs(path: &Path) -> Result<(), Error> {
    let Some(snap) = Snapshot::open(path)? else {
        return replace(path, |w| write_line(w, &store::runs_header(0)));
    };
    let mut rows: Vec<(usize, Range)> = vec![];
    let found = records(
        &snap,
        |h, r| cell::<usize>(h, r, "run"),
        |k, r| rows.push((k, r)),
    )?;
    let Some(head) = found else {
        return replace(path, |w| write_line(w, &store::runs_header(0)));
    };
    if snap.is_whole() && rows.windows(2).all(|w| w[0].0 <= w[1].0) {
        return Ok(());
    }
    rows.sort_by_key(|r| r.0);
    let mut src = snap.reader()?.into_inner();
    replace(path, |w| {
        copy(&mut src, path, head.range, w)?;
        rows.iter().try_for_each(|r| copy(&mut src, path, r.1, w))
    })
}

fn sort_progress(path: &Path) -> Result<(), Error> {
    let header = store::progress_header();
    let Some(snap) = Snapshot::open(path)? else {
        return replace(path, |w| write_line(w, &header));
    };
    let key = |h: &csv::StringRecord, r: &csv::StringRecord| {
        Ok((
            cell::<usize>(h, r, "run")?,
            Point {
                iteration: cell(h, r, "iteration")?,
                time_s: cell(h, r, "time_s")?,
            },
        ))
    };
    // the stretches are built as the rows are read: the index holds one entry per stretch
    let mut stretches: Vec<Stretch> = vec![];
    let mut last: Option<Point> = None;
    let found = records(&snap, key, |(run, p), range| {
        match stretches.last_mut() {
            Some(s) if s.run == run => {
                s.ordered &= last.is_none_or(|l| l.cmp(&p) != Ordering::Greater);
                s.range.end = range.end;
            }
            _ => stretches.push(Stretch {
                run,
                range,
                ordered: true,
            }),
        }
        last = Some(p);
    })?;
    let Some(head) = found else {
        return replace(path, |w| write_line(w, &header));
    };
    let sorted =
        stretches.windows(2).all(|w| w[0].run < w[1].run) && stretches.iter().all(|s| s.ordered);
    if snap.is_whole() && sorted {
        return Ok(());
    }
    stretches.sort_by_key(|s| s.run);
    let mut src = snap.reader()?.into_inner();
    replace(path, |w| {
        copy(&mut src, path, head.range, w)?;
        let mut i = 0;
        while i < stretches.len() {
            let run = stretches[i].run;
            let n = stretches[i..].iter().take_while(|s| s.run == run).count();
            let group = &stretches[i..i + n];
            if let [one] = group
                && one.ordered
            {
                copy(&mut src, path, one.range, w)?;
            } else {
                write_run_sorted(&mut src, path, &head.columns, group, w)?;
            }
            i += n;
        }
        Ok(())
    })
}

/// Writes the rows of `group` (one run's stretches, in file order) sorted by iteration and
/// time, stably.
fn write_run_sorted(
    src: &mut std::io::BufReader<File>,
    path: &Path,
    header: &csv::StringRecord,
    group: &[Stretch],
    w: &mut dyn Write,
) -> Result<(), Error> {
    let mut rows: Vec<(Point, Vec<u8>)> = vec![];
    for s in group {
        let bytes = read_range(src, s.range, path)?;
        let mut rd = csv::ReaderBuilder::new()
            .has_headers(false)
            .from_reader(bytes.as_slice());
        let mut rec = csv::StringRecord::new();
        loop {
            let start = rd.position().byte() as usize;
            if !rd
                .read_record(&mut rec)
                .map_err(|e| bad_row(path, 0, e.to_string()))?
            {
                break;
            }
            let end = rd.position().byte() as usize;
            let p = Point {
                iteration: cell(header, &rec, "iteration").map_err(|e| bad_row(path, 0, e))?,
                time_s: cell(header, &rec, "time_s").map_err(|e| bad_row(path, 0, e))?,
            };
            rows.push((p, bytes[start..end].to_vec()));
        }
    }
    rows.sort_by(|a, b| a.0.cmp(&b.0));
    for (_, line) in rows {
        w.write_all(&line).map_err(|e| failed(path, e))?;
    }
    Ok(())
}

fn read_range(src: &mut std::io::BufReader<File>, r: Range, path: &Path) -> Result<Vec<u8>, Error> {
    let mut buf = vec![0; (r.end - r.start) as usize];
    src.seek(SeekFrom::Start(r.start))
        .and_then(|_| src.read_exact(&mut buf))
        .map_err(|e| failed(path, e))?;
    Ok(buf)
}

fn copy(
    src: &mut std::io::BufReader<File>,
    path: &Path,
    r: Range,
    w: &mut dyn Write,
) -> Result<(), Error> {
    let buf = read_range(src, r, path)?;
    w.write_all(&buf).map_err(|e| failed(path, e))
}

fn write_line(w: &mut dyn Write, line: &str) -> Result<(), Error> {
    writeln!(w, "{line}").map_err(|e| Error::Failed(format!("writing a header: {e}")))
}

/// Replaces the file at `path` with what `write` writes, atomically: a temporary file beside
/// it, synced, then renamed over it.
fn replace(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> Result<(), Error>,
) -> Result<(), Error> {
    let tmp = path.with_extension("csv.tmp");
    {
        let f = File::create(&tmp).map_err(|e| failed(&tmp, e))?;
        let mut w = BufWriter::new(f);
        write(&mut w)?;
        let f = w.into_inner().map_err(|e| failed(&tmp, e.error()))?;
        f.sync_all().map_err(|e| failed(&tmp, e))?;
    }
    std::fs::rename(&tmp, path).map_err(|e| failed(path, e))?;
    store::sync_dir(path)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::ProgressRow;
    use crate::store::tests::out;
    use crate::store::{RunWriter, read_progress, read_runs};

    /// The rows of `dir` sorted in memory, as the files should be after [`sort_files`].
    fn sorted_in_memory(dir: &Path) -> (Vec<usize>, Vec<(usize, u64, u64)>) {
        let mut runs: Vec<usize> = read_runs(dir).unwrap().iter().map(|r| r.run).collect();
        runs.sort();
        let mut p: Vec<ProgressRow> = read_progress(dir).unwrap();
        p.sort_by(|a, b| {
            (a.run, a.iteration)
                .cmp(&(b.run, b.iteration))
                .then(a.time_s.total_cmp(&b.time_s))
        });
        let p = p
            .iter()
            .map(|r| (r.run, r.iteration, r.time_s.to_bits()))
            .collect();
        (runs, p)
    }

    fn on_disk(dir: &Path) -> (Vec<usize>, Vec<(usize, u64, u64)>) {
        let runs = read_runs(dir).unwrap().iter().map(|r| r.run).collect();
        let p = read_progress(dir)
            .unwrap()
            .iter()
            .map(|r| (r.run, r.iteration, r.time_s.to_bits()))
            .collect();
        (runs, p)
    }

    #[test]
    fn files_out_of_order_are_sorted_as_in_memory_and_sorted_files_are_left_alone() {
        let dir = tempfile::tempdir().unwrap();
        let mut w = RunWriter::open(dir.path(), 0).unwrap();
        // runs finished out of order, one with an error message over two lines
        for i in [3, 0, 2, 1, 5, 4] {
            let mut o = out(i);
            if i == 2 {
                o.record.error = "first line\nsecond, \"quoted\"".into();
            }
            w.write_out(&o).unwrap();
        }
        drop(w);
        let want = sorted_in_memory(dir.path());
        let before = std::fs::read(dir.path().join(RUNS)).unwrap();
        sort_files(dir.path()).unwrap();
        assert_eq!(on_disk(dir.path()), want);
        assert_eq!(want.0, vec![0, 1, 2, 3, 4, 5]);
        let after = std::fs::read(dir.path().join(RUNS)).unwrap();
        assert_ne!(before, after);
        assert_eq!(
            before.len(),
            after.len(),
            "every byte kept, in another order"
        );
        let r = read_runs(dir.path()).unwrap();
        assert_eq!(r[2].error, "first line\nsecond, \"quoted\"");
        // sorted already: neither file is rewritten
        let inode = |f: &str| {
            use std::os::unix::fs::MetadataExt;
            std::fs::metadata(dir.path().join(f)).unwrap().ino()
        };
        let (a, b) = (inode(RUNS), inode(PROGRESS));
        sort_files(dir.path()).unwrap();
        assert_eq!((inode(RUNS), inode(PROGRESS)), (a, b));
    }

    #[test]
    fn a_run_whose_trace_is_out_of_order_or_split_is_sorted_stably_and_a_cut_line_dropped() {
        let dir = tempfile::tempdir().unwrap();
        let mut w = RunWriter::open(dir.path(), 0).unwrap();
        w.write_out(&out(1)).unwrap();
        w.write_out(&out(0)).unwrap();
        drop(w);
        let path = dir.path().join(PROGRESS);
        let mut text = std::fs::read_to_string(&path).unwrap();
        // run 1's trace again, later and out of order (equal keys keep the file's order),
        // then a line cut short
        text += "1,a,20,1.5,4.0\n1,b,5,0.5,\n1,c,20,1.5,3.0\n0,s|p|-|-|0,3";
        std::fs::write(&path, &text).unwrap();
        sort_files(dir.path()).unwrap();
        let rows = read_progress(dir.path()).unwrap();
        let got: Vec<(usize, u64, &str)> = rows
            .iter()
            .map(|r| (r.run, r.iteration, r.run_id.as_str()))
            .collect();
        let id0 = "s|p|-|-|0";
        let id1 = "s|p|-|-|1";
        assert_eq!(
            got,
            vec![
                (0, 0, id0),
                (0, 10, id0),
                (0, 20, id0),
                (1, 0, id1),
                (1, 5, "b"),
                (1, 10, id1),
                (1, 20, "a"),
                (1, 20, "c"),
                (1, 20, id1),
            ]
        );
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.ends_with('\n') && !text.contains(",3\n"), "{text}");
    }

    #[test]
    fn missing_files_or_headers_cut_short_are_written_as_headers() {
        let dir = tempfile::tempdir().unwrap();
        sort_files(dir.path()).unwrap();
        let header = |f: &str| std::fs::read_to_string(dir.path().join(f)).unwrap();
        assert_eq!(header(RUNS), format!("{}\n", store::runs_header(0)));
        assert_eq!(header(PROGRESS), format!("{}\n", store::progress_header()));
        std::fs::write(dir.path().join(PROGRESS), "run,run_i").unwrap();
        sort_files(dir.path()).unwrap();
        assert_eq!(header(PROGRESS), format!("{}\n", store::progress_header()));
    }
}
