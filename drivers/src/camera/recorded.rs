//! Replays a folder of recorded frames (PGM or PNG) for offline reprocessing.

use std::path::{Path, PathBuf};
use std::time::Duration;

use magbench_env::Vec2;

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
            let mut rd = csv::Reader::from_path(&index).map_err(|e| lost(e.to_string()))?;
            let mut v = Vec::new();
            for (line, rec) in rd.records().enumerate() {
                let rec = rec.map_err(|e| lost(e.to_string()))?;
                let bad = |what: &str| lost(format!("frames.csv line {}: bad {what}", line + 2));
                let index: u64 = rec
                    .get(0)
                    .and_then(|s| s.parse().ok())
                    .ok_or_else(|| bad("index"))?;
                let t: f64 = rec
                    .get(1)
                    .and_then(|s| s.parse().ok())
                    .ok_or_else(|| bad("t_s"))?;
                let file = rec.get(2).ok_or_else(|| bad("file"))?;
                let nums: Vec<f64> = rec
                    .iter()
                    .skip(3)
                    .map(|s| s.parse().map_err(|_| bad("position")))
                    .collect::<Result<_, _>>()?;
                let truth = nums
                    .chunks_exact(2)
                    .map(|c| Vec2::new(c[0], c[1]))
                    .collect();
                v.push(RecordedEntry {
                    index,
                    t,
                    path: dir.join(file),
                    truth,
                });
            }
            v
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
