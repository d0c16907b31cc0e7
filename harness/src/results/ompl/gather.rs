//! The runs of the OMPL logs, gathered one at a time in the folder's one pass over its runs:
//! each planner configuration's name, settings, property names and whether it tracks a cost
//! are held in memory, and each run's two lines (its properties and its progress) are written
//! to a temporary file beside the logs, which [`super::write`] reads back a configuration at a
//! time. Memory holds one file position per run.

use std::collections::HashMap;
use std::fs::File;
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::Path;

use super::{block_name, progress_line, properties, settings};
use crate::Error;
use crate::results::temporary::Temporary;
use crate::results::traces::TracePoint;
use crate::run::RunRecord;

/// The temporary file of the runs' lines (not hashed by `results verify`: it ends in `.tmp`).
const LINES: &str = "ompl.log.runs.tmp";

/// One OMPL planner configuration.
pub(super) struct Block {
    /// Its scenario.
    pub scenario: String,
    /// Its name within one scenario's log, and qualified by its scenario.
    pub name: [String; 2],
    /// Its common properties.
    pub settings: Vec<(String, String)>,
    /// Its run properties' names, in the order of each run's line.
    pub names: Vec<&'static str>,
    /// Each run's lines' position in the temporary file.
    pub runs: Vec<u64>,
    /// Some run has a cost at more than one point of its progress trace (a planner that stops
    /// at its first solution has one at most).
    pub tracks_cost: bool,
}

/// The runs of the OMPL logs of a results folder, gathered one at a time.
pub struct Gather {
    lines: Lines,
    out: BufWriter<File>,
    at: u64,
    blocks: Vec<Block>,
    index: HashMap<String, usize>,
}

/// The failure to write or read the temporary file at `path`.
fn failed(path: &Path, e: std::io::Error) -> Error {
    Error::Failed(format!("{}: {e}", path.display()))
}

impl Gather {
    /// Starts gathering the runs of results folder `dir`.
    pub fn create(dir: &Path) -> Result<Gather, Error> {
        let tmp = Temporary::new(dir.join(LINES));
        let file = File::options()
            .read(true)
            .write(true)
            .create(true)
            .truncate(true)
            .open(tmp.path())
            .map_err(|e| failed(tmp.path(), e))?;
        let out = file.try_clone().map_err(|e| failed(tmp.path(), e))?;
        Ok(Gather {
            lines: Lines { tmp, file },
            out: BufWriter::new(out),
            at: 0,
            blocks: vec![],
            index: HashMap::new(),
        })
    }

    /// Adds run `r`, whose progress trace is `points`.
    pub fn push(&mut self, r: &RunRecord, points: &[TracePoint]) -> Result<(), Error> {
        let qualified = block_name(r, true);
        let i = match self.index.get(&qualified) {
            Some(i) => *i,
            None => {
                self.blocks.push(Block {
                    scenario: r.scenario.clone(),
                    name: [block_name(r, false), qualified.clone()],
                    settings: settings(r),
                    names: properties(r).into_keys().collect(),
                    runs: vec![],
                    tracks_cost: false,
                });
                self.index.insert(qualified, self.blocks.len() - 1);
                self.blocks.len() - 1
            }
        };
        let b = &mut self.blocks[i];
        // every run of a configuration has the same property names (they depend on whether it tracks)
        let p = properties(r);
        let mut line = String::new();
        for n in &b.names {
            line += p.get(n).map(String::as_str).unwrap_or("");
            line += "; ";
        }
        b.tracks_cost |= points.iter().filter(|p| p.best_cost.is_some()).count() > 1;
        let progress = progress_line(points);
        b.runs.push(self.at);
        for part in [&line, &progress] {
            let len = u32::try_from(part.len()).map_err(|_| {
                Error::Failed(format!(
                    "{}: run {}: a line of {} bytes",
                    self.lines.tmp.path().display(),
                    r.run,
                    part.len()
                ))
            })?;
            self.out
                .write_all(&len.to_le_bytes())
                .and_then(|()| self.out.write_all(part.as_bytes()))
                .map_err(|e| failed(self.lines.tmp.path(), e))?;
            self.at += 4 + part.len() as u64;
        }
        Ok(())
    }

    /// The gathered configurations, in order of first appearance, and their runs' lines.
    pub fn finish(self) -> Result<Gathered, Error> {
        let Gather {
            lines, out, blocks, ..
        } = self;
        out.into_inner()
            .map_err(|e| failed(lines.tmp.path(), e.into_error()))?;
        let mut scenarios: Vec<String> = vec![];
        for b in &blocks {
            if !scenarios.contains(&b.scenario) {
                scenarios.push(b.scenario.clone());
            }
        }
        Ok(Gathered {
            lines,
            blocks,
            scenarios,
        })
    }
}

/// The runs' lines in the temporary file, removed when dropped (also when gathering or
/// writing fails).
pub(super) struct Lines {
    tmp: Temporary,
    file: File,
}

impl Lines {
    /// A line of the run at `at`: its properties (`Line::Run`) or its progress.
    pub fn read(&mut self, at: u64, line: Line) -> std::io::Result<String> {
        self.file.seek(SeekFrom::Start(at))?;
        let mut len = [0; 4];
        self.file.read_exact(&mut len)?;
        if line == Line::Progress {
            self.file
                .seek(SeekFrom::Current(i64::from(u32::from_le_bytes(len))))?;
            self.file.read_exact(&mut len)?;
        }
        let mut text = vec![0; u32::from_le_bytes(len) as usize];
        self.file.read_exact(&mut text)?;
        String::from_utf8(text).map_err(std::io::Error::other)
    }
}

/// Which of a run's two lines to read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Line {
    /// Its run properties.
    Run,
    /// Its progress.
    Progress,
}

/// The configurations of a results folder's OMPL logs, ready to write ([`super::write`]).
pub struct Gathered {
    pub(super) lines: Lines,
    pub(super) blocks: Vec<Block>,
    /// The scenarios, in order of first appearance.
    pub(super) scenarios: Vec<String>,
}
