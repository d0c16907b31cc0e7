//! The emulator's event log: one CSV line per event, flushed at once (a killed emulator loses
//! nothing).
//!
//! Columns: `wall_s` (since start), `t_s` (device time), `event`, `seq`, `currents_a`
//! (`;`-separated, the currents in force after the event), `positions_bl` (`x;y;...`, frame
//! events), `detail`.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;
use std::sync::Mutex;
use std::time::Instant;

/// A thread-safe CSV event log.
pub struct EventLog {
    out: Mutex<BufWriter<File>>,
    start: Instant,
}

/// The log's header line.
pub const LOG_HEADER: &str = "wall_s,t_s,event,seq,currents_a,positions_bl,detail";

impl EventLog {
    /// Creates the log file.
    pub fn create(path: &Path, start: Instant) -> std::io::Result<Self> {
        let mut out = BufWriter::new(File::create(path)?);
        writeln!(out, "{LOG_HEADER}")?;
        out.flush()?;
        Ok(Self {
            out: Mutex::new(out),
            start,
        })
    }

    /// Appends one event.
    pub fn event(
        &self,
        t: f64,
        event: &str,
        seq: Option<u16>,
        currents: &[f64],
        positions: &[magbench_env::Vec2],
        detail: &str,
    ) {
        let wall = self.start.elapsed().as_secs_f64();
        let cur = currents
            .iter()
            .map(|c| format!("{c:.4}"))
            .collect::<Vec<_>>()
            .join(";");
        let pos = positions
            .iter()
            .map(|p| format!("{:.5};{:.5}", p.x, p.y))
            .collect::<Vec<_>>()
            .join(";");
        let seq = seq.map(|s| s.to_string()).unwrap_or_default();
        let detail = detail.replace([',', '\n'], " ");
        let mut out = self.out.lock().unwrap_or_else(|e| e.into_inner());
        let _ = writeln!(out, "{wall:.6},{t:.6},{event},{seq},{cur},{pos},{detail}");
        let _ = out.flush();
    }
}
