//! The host's per-run CSV log: every observation, every command and every fault.
//!
//! Columns: `wall_s` (since the rig opened), `t_s` (frame capture time, device clock), `kind`
//! (`observation`, `command`, `fault` or `stop`: the field was zeroed), `frame`, per agent `x{i}_bl,y{i}_bl` (empty when
//! missed), `theta,alpha,gx,gy` (the command), `currents_a` (`;`-separated), `clamped`
//! (`current`, `slew` or empty), `tries`, `latency_ms` (frame arrival to command sent),
//! `message`.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;
use std::time::Instant;

use magbench_env::{Control, Vec2};

use crate::coil_driver::CoilCommand;

/// The CSV log of a rig run.
pub struct RigLog {
    out: BufWriter<File>,
    agents: usize,
    start: Instant,
}

impl RigLog {
    /// Creates the log for `agents` agents.
    pub fn create(path: &Path, agents: usize, start: Instant) -> std::io::Result<Self> {
        let mut out = BufWriter::new(File::create(path)?);
        write!(out, "wall_s,t_s,kind,frame")?;
        for i in 0..agents {
            write!(out, ",x{i}_bl,y{i}_bl")?;
        }
        writeln!(
            out,
            ",theta,alpha,gx,gy,currents_a,clamped,tries,latency_ms,message"
        )?;
        Ok(Self { out, agents, start })
    }

    fn head(&mut self, t: f64, kind: &str, frame: Option<u64>) {
        let w = self.start.elapsed().as_secs_f64();
        let f = frame.map(|f| f.to_string()).unwrap_or_default();
        let _ = write!(self.out, "{w:.6},{t:.6},{kind},{f}");
    }

    /// One observation.
    pub fn observation(&mut self, t: f64, frame: u64, agents: &[Option<Vec2>]) {
        self.head(t, "observation", Some(frame));
        for i in 0..self.agents {
            match agents.get(i).copied().flatten() {
                Some(p) => {
                    let _ = write!(self.out, ",{:.5},{:.5}", p.x, p.y);
                }
                None => {
                    let _ = write!(self.out, ",,");
                }
            }
        }
        let _ = writeln!(self.out, ",,,,,,,,,");
    }

    /// One command sent.
    pub fn command(
        &mut self,
        t: f64,
        frame: Option<u64>,
        u: &Control,
        c: &CoilCommand,
        tries: u32,
        latency_ms: Option<f64>,
    ) {
        self.head(t, "command", frame);
        let _ = write!(self.out, "{}", ",".repeat(2 * self.agents));
        let cur = c
            .currents
            .iter()
            .map(|x| format!("{x:.4}"))
            .collect::<Vec<_>>()
            .join(";");
        let clamped = match (c.clamped.current, c.clamped.slew) {
            (true, true) => "current+slew",
            (true, false) => "current",
            (false, true) => "slew",
            _ => "",
        };
        let lat = latency_ms.map(|l| format!("{l:.4}")).unwrap_or_default();
        let _ = writeln!(
            self.out,
            ",{:.6},{:.6},{:.6},{:.6},{cur},{clamped},{tries},{lat},",
            u.theta, u.alpha, u.grad[0], u.grad[1]
        );
    }

    /// One command given to a rig without coil currents (a simulated rig): empty `currents_a`.
    pub fn command_without_currents(&mut self, t: f64, frame: Option<u64>, u: &Control) {
        self.head(t, "command", frame);
        let _ = write!(self.out, "{}", ",".repeat(2 * self.agents));
        let _ = writeln!(
            self.out,
            ",{:.6},{:.6},{:.6},{:.6},,,1,,",
            u.theta, u.alpha, u.grad[0], u.grad[1]
        );
    }

    /// One fault.
    pub fn fault(&mut self, t: f64, frame: Option<u64>, message: &str) {
        self.head(t, "fault", frame);
        let _ = write!(self.out, "{}", ",".repeat(2 * self.agents));
        let _ = writeln!(self.out, ",,,,,,,,,{}", message.replace([',', '\n'], " "));
        let _ = self.out.flush();
    }

    /// The field was zeroed (a stop), with the reason.
    pub fn stop(&mut self, t: f64, message: &str) {
        self.head(t, "stop", None);
        let _ = write!(self.out, "{}", ",".repeat(2 * self.agents));
        let _ = writeln!(self.out, ",,,,,,,,,{}", message.replace([',', '\n'], " "));
        let _ = self.out.flush();
    }

    /// Writes buffered lines to disk.
    pub fn flush(&mut self) {
        let _ = self.out.flush();
    }
}
