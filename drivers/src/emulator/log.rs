//! The emulator's event log: one CSV line per event, flushed at once (a killed emulator loses
//! nothing).
//!
//! Columns: `clock_s` (the emulator clock's time of the event — the clock its watchdog counts;
//! on a bench the wall clock since the emulator started), `t_s` (device time), `event`, `seq`,
//! `currents_a` (`;`-separated, the currents in force after the event), `positions_bl`
//! (`x;y;...`, frame events), `detail`.
//!
//! An event whose time the device itself read (a received message, a watchdog trip) is stamped
//! with that very reading, not with the time the line was written: a thread descheduled
//! between the two cannot make the log disagree with what the device decided.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use crate::clock::Clock;

/// Called after each event is written, with the event's name.
pub type OnEvent = Arc<dyn Fn(&str) + Send + Sync>;

/// A thread-safe CSV event log.
pub struct EventLog {
    out: Mutex<BufWriter<File>>,
    clock: Arc<dyn Clock>,
    on_event: Option<OnEvent>,
}

/// The log's header line.
pub const LOG_HEADER: &str = "clock_s,t_s,event,seq,currents_a,positions_bl,detail";

impl EventLog {
    /// Creates the log file; events are stamped by `clock`.
    pub fn create(path: &Path, clock: Arc<dyn Clock>) -> std::io::Result<Self> {
        let mut out = BufWriter::new(File::create(path)?);
        writeln!(out, "{LOG_HEADER}")?;
        out.flush()?;
        Ok(Self {
            out: Mutex::new(out),
            clock,
            on_event: None,
        })
    }

    /// The log, calling `on_event` after each event it writes.
    pub fn observed(self, on_event: Option<OnEvent>) -> Self {
        Self { on_event, ..self }
    }

    /// Appends one event, stamped now.
    pub fn event(
        &self,
        t: f64,
        event: &str,
        seq: Option<u16>,
        currents: &[f64],
        positions: &[magbench_env::Vec2],
        detail: &str,
    ) {
        self.event_at(self.clock.now(), t, event, seq, currents, positions, detail);
    }

    /// Appends one event that happened at `clock` (a reading of the log's clock).
    #[allow(clippy::too_many_arguments)]
    pub fn event_at(
        &self,
        clock: Duration,
        t: f64,
        event: &str,
        seq: Option<u16>,
        currents: &[f64],
        positions: &[magbench_env::Vec2],
        detail: &str,
    ) {
        let clock = clock.as_secs_f64();
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
        {
            let mut out = self.out.lock().unwrap_or_else(|e| e.into_inner());
            let _ = writeln!(out, "{clock:.6},{t:.6},{event},{seq},{cur},{pos},{detail}");
            let _ = out.flush();
        }
        if let Some(on_event) = &self.on_event {
            on_event(event);
        }
    }
}
