//! Writes frames to a folder (binary PGM files plus `frames.csv`) for `magbench rig redetect`.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use magbench_env::Vec2;

use crate::frame::Frame;

/// Records frames as `frame_NNNNNNNN.pgm` and one `frames.csv` line each
/// (`index,t_s,file` and, when known, the true agent positions `x0_bl,y0_bl,...`).
pub struct FrameRecorder {
    dir: PathBuf,
    csv: BufWriter<File>,
    agents: usize,
}

impl FrameRecorder {
    /// Creates `dir` and its `frames.csv`; `agents` true positions follow each line (0 = none).
    pub fn create(dir: &Path, agents: usize) -> std::io::Result<Self> {
        std::fs::create_dir_all(dir)?;
        let mut csv = BufWriter::new(File::create(dir.join("frames.csv"))?);
        write!(csv, "index,t_s,file")?;
        for i in 0..agents {
            write!(csv, ",x{i}_bl,y{i}_bl")?;
        }
        writeln!(csv)?;
        Ok(Self {
            dir: dir.to_path_buf(),
            csv,
            agents,
        })
    }

    /// Writes one frame (and its true positions, if the recorder has agents).
    pub fn write(&mut self, f: &Frame, truth: &[Vec2]) -> std::io::Result<()> {
        let name = format!("frame_{:08}.pgm", f.index);
        let (w, h) = f.image.dimensions();
        let mut out = BufWriter::new(File::create(self.dir.join(&name))?);
        write!(out, "P5\n{w} {h}\n255\n")?;
        out.write_all(f.image.as_raw())?;
        out.flush()?;
        write!(self.csv, "{},{},{name}", f.index, f.t)?;
        for p in truth.iter().take(self.agents) {
            write!(self.csv, ",{},{}", p.x, p.y)?;
        }
        writeln!(self.csv)?;
        self.csv.flush()
    }
}
