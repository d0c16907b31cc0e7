//! `magbench rig redetect`: the detector rerun on recorded frames, with the error against the
//! truth when the recording has it (emulator recordings do).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Duration;

use magbench_env::Vec2;

use crate::camera::{Camera, CameraError, RecordedCamera};
use crate::detector::Detector;
use crate::rigfile::RigConfig;

/// What a detection rerun found.
#[derive(Debug, Clone, PartialEq)]
pub struct RedetectReport {
    /// Frames processed.
    pub frames: usize,
    /// Agent detections made.
    pub detections: usize,
    /// Agent detections missing.
    pub missed: usize,
    /// RMS and largest centre error in pixels, when the recording has the truth.
    pub error_px: Option<(f64, f64)>,
    /// Mean detection time per frame (ms).
    pub mean_detect_ms: f64,
}

/// Why a detection rerun stopped.
#[derive(Debug, thiserror::Error)]
pub enum RedetectError {
    /// The recorded frames cannot be read.
    #[error(transparent)]
    Camera(#[from] CameraError),
    /// The recording has no truth to start from and no start was given.
    #[error(
        "{}: the recording has no true positions; give --scenario for the agents' start",
        dir.display()
    )]
    NoStart {
        /// The recording's folder.
        dir: PathBuf,
    },
    /// The output file cannot be written.
    #[error("{}: {source}", path.display())]
    Write {
        /// The output file.
        path: PathBuf,
        /// The I/O failure.
        source: std::io::Error,
    },
}

/// The error of writing `path`.
fn write_err(path: &Path) -> impl Fn(std::io::Error) -> RedetectError + '_ {
    move |source| RedetectError::Write {
        path: path.to_path_buf(),
        source,
    }
}

/// Detects the agents in every frame of `dir`; `prior` primes identities (default: the truth
/// of the first frame). Writes `index,t_s,x0_bl,y0_bl,...` lines to `out` when given.
pub fn redetect(
    rig: &RigConfig,
    dir: &Path,
    prior: Option<&[Vec2]>,
    out: Option<&Path>,
) -> Result<RedetectReport, RedetectError> {
    let mut cam = RecordedCamera::open(dir, rig.camera.fps)?;
    let entries = cam.entries().to_vec();
    let prior: Vec<Vec2> = match prior {
        Some(p) => p.to_vec(),
        None if !entries[0].truth.is_empty() => entries[0].truth.clone(),
        None => {
            return Err(RedetectError::NoStart {
                dir: dir.to_path_buf(),
            });
        }
    };
    let n = prior.len();
    let mut det = Detector::new(rig.detector.clone(), rig.pixels.clone(), &prior);
    let mut w = match out {
        Some(p) => {
            let mut f = std::io::BufWriter::new(std::fs::File::create(p).map_err(write_err(p))?);
            let cols: Vec<String> = (0..n).map(|i| format!(",x{i}_bl,y{i}_bl")).collect();
            writeln!(f, "index,t_s{}", cols.concat()).map_err(write_err(p))?;
            Some(f)
        }
        None => None,
    };
    let (mut frames, mut detections, mut missed) = (0, 0, 0);
    let (mut sum2, mut maxe, mut counted) = (0.0, 0.0f64, 0usize);
    let mut detect_s = 0.0;
    for e in &entries {
        let f = match cam.next_frame(Duration::ZERO) {
            Ok(f) => f,
            Err(CameraError::Ended) => break,
            Err(err) => return Err(err.into()),
        };
        let t0 = std::time::Instant::now();
        let d = det.detect(&f.image);
        detect_s += t0.elapsed().as_secs_f64();
        frames += 1;
        for (i, p) in d.px.iter().enumerate() {
            match p {
                Some(p) => {
                    detections += 1;
                    if let Some(truth) = e.truth.get(i) {
                        let err = (p - rig.pixels.to_px(*truth)).norm();
                        sum2 += err * err;
                        maxe = maxe.max(err);
                        counted += 1;
                    }
                }
                None => missed += 1,
            }
        }
        if let (Some(w), Some(p)) = (w.as_mut(), out) {
            let cols: Vec<String> = d
                .agents
                .iter()
                .map(|a| {
                    a.map(|p| format!(",{:.5},{:.5}", p.x, p.y))
                        .unwrap_or(",,".into())
                })
                .collect();
            writeln!(w, "{},{}{}", f.index, f.t, cols.concat()).map_err(write_err(p))?;
        }
    }
    Ok(RedetectReport {
        frames,
        detections,
        missed,
        error_px: (counted > 0).then(|| ((sum2 / counted as f64).sqrt(), maxe)),
        mean_detect_ms: detect_s * 1e3 / frames.max(1) as f64,
    })
}
