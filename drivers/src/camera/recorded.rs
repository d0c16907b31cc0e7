//! Replays a folder of recorded frames (PGM or PNG) for offline reprocessing.

use std::path::{Path, PathBuf};
use std::time::Duration;

use magbench_env::{InputError, Vec2};

use super::{Camera, CameraError};
use crate::frame::Frame;

/// One recorded frame on disk.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordedEntry {
    /// Frame index.
    pub index: u64,
    /// Capture time (s).
    pub t: f64,
    /// Image file.
    pub path: PathBuf,
    /// True agent positions (BL), when the recording has them (emulator recordings do).
    pub truth: Vec<Vec2>,
}

/// Reads and checks a recording's `frames.csv` (`index,t_s,file[,x0_bl,y0_bl,...]`): every
/// time and true position finite, positions in pairs. Errors name the file, the line and column.
pub fn read_index(dir: &Path) -> Result<Vec<RecordedEntry>, InputError> {
    let path = dir.join("frames.csv");
    let file = path.display().to_string();
    let text = magbench_env::input::read_text(&path, &file)?;
    let mut rd = csv::Reader::from_reader(text.as_bytes());
    let mut v = Vec::new();
    for (line, rec) in rd.records().enumerate() {
        let at = |col: &str| format!("line {}: {col}", line + 2);
        let rec = rec.map_err(|e| InputError::new(&file, at("row"), e.to_string()))?;
        let number = |k: usize, col: &str| -> Result<f64, InputError> {
            let x: f64 = rec
                .get(k)
                .and_then(|s| s.trim().parse().ok())
                .ok_or_else(|| InputError::new(&file, at(col), "missing or not a number"))?;
            if x.is_finite() {
                Ok(x)
            } else {
                Err(InputError::new(
                    &file,
                    at(col),
                    format!("must be finite, got {x}"),
                ))
            }
        };
        let index: u64 = rec
            .get(0)
            .and_then(|s| s.trim().parse().ok())
            .ok_or_else(|| InputError::new(&file, at("index"), "not a whole number ≥ 0"))?;
        let t = number(1, "t_s")?;
        let name = rec
            .get(2)
            .ok_or_else(|| InputError::new(&file, at("file"), "missing"))?;
        if (rec.len() - 3) % 2 != 0 {
            return Err(InputError::new(
                &file,
                at("positions"),
                format!(
                    "true positions come in (x, y) pairs, got {} numbers",
                    rec.len() - 3
                ),
            ));
        }
        let mut truth = Vec::with_capacity((rec.len() - 3) / 2);
        for k in (3..rec.len()).step_by(2) {
            let i = (k - 3) / 2;
            truth.push(Vec2::new(
                number(k, &format!("x{i}_bl"))?,
                number(k + 1, &format!("y{i}_bl"))?,
            ));
        }
        v.push(RecordedEntry {
            index,
            t,
            path: dir.join(name),
            truth,
        });
    }
    Ok(v)
}

/// A camera over a folder of frames: `frames.csv` (`index,t_s,file[,x0_bl,y0_bl,...]`) when
/// present, else every `.pgm`/`.png` file in name order at the nominal frame rate.
pub struct RecordedCamera {
    dir: PathBuf,
    entries: Vec<RecordedEntry>,
    next: usize,
}

impl RecordedCamera {
    /// Lists a recording.
    pub fn open(dir: &Path, fps: f64) -> Result<Self, CameraError> {
        let lost = |e: String| CameraError::Lost(format!("{}: {e}", dir.display()));
        let index = dir.join("frames.csv");
        let entries = if index.exists() {
            read_index(dir).map_err(|e| CameraError::Lost(e.to_string()))?
        } else {
            let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
                .map_err(|e| lost(e.to_string()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| {
                    p.extension().is_some_and(|x| {
                        x.eq_ignore_ascii_case("pgm") || x.eq_ignore_ascii_case("png")
                    })
                })
                .collect();
            files.sort();
            files
                .into_iter()
                .enumerate()
                .map(|(k, path)| RecordedEntry {
                    index: k as u64,
                    t: k as f64 / fps,
                    path,
                    truth: vec![],
                })
                .collect()
        };
        if entries.is_empty() {
            return Err(lost(
                "no frames (no frames.csv and no .pgm/.png files)".into(),
            ));
        }
        Ok(Self {
            dir: dir.to_path_buf(),
            entries,
            next: 0,
        })
    }

    /// The recording's entries.
    pub fn entries(&self) -> &[RecordedEntry] {
        &self.entries
    }
}

impl Camera for RecordedCamera {
    fn next_frame(&mut self, _timeout: Duration) -> Result<Frame, CameraError> {
        let e = self.entries.get(self.next).ok_or(CameraError::Ended)?;
        self.next += 1;
        let img = image::open(&e.path)
            .map_err(|err| CameraError::Lost(format!("{}: {err}", e.path.display())))?;
        Ok(Frame {
            index: e.index,
            t: e.t,
            image: img.to_luma8(),
            received: std::time::Instant::now(),
        })
    }

    fn describe(&self) -> String {
        format!("recorded frames in {}", self.dir.display())
    }
}
