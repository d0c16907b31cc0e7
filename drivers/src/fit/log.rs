//! Reads a rig log (`rig-log.csv`, as `rig run`, `rig check` and `rig excite` write it) into
//! frames: what was observed, and which command was in force until the next frame.

use std::path::Path;

use magbench_env::{Control, InputError, Vec2};

/// One observed frame of a logged run.
#[derive(Debug, Clone, PartialEq)]
pub struct LoggedFrame {
    /// Frame index (gaps are dropped frames).
    pub frame: u64,
    /// Capture time (s).
    pub t: f64,
    /// Observed position per agent (`None`: missed).
    pub agents: Vec<Option<Vec2>>,
    /// The command in force from this frame to the next (`None`: field off).
    pub command: Option<Control>,
}

/// One logged run.
#[derive(Debug, Clone, PartialEq)]
pub struct LoggedRun {
    /// Where it was read from.
    pub source: String,
    /// Its frames, in order.
    pub frames: Vec<LoggedFrame>,
}

/// Reads `rig-log.csv` from `path` (a file, or a folder that holds one) for `agents` agents;
/// a file that cannot be read or is not a rig log is an [`InputError`] naming it.
pub fn read_log(path: &Path, agents: usize) -> Result<LoggedRun, InputError> {
    let file = if path.is_dir() {
        path.join("rig-log.csv")
    } else {
        path.to_path_buf()
    };
    let name = file.display().to_string();
    let mut rd = csv::ReaderBuilder::new()
        .flexible(false)
        .from_path(&file)
        .map_err(|e| InputError::new(&name, "", e.to_string()))?;
    let head = rd
        .headers()
        .map_err(|e| InputError::new(&name, "header", e.to_string()))?
        .clone();
    let col = |c: &str| {
        head.iter().position(|h| h == c).ok_or_else(|| {
            InputError::new(
                &name,
                "header",
                format!("no column `{c}` (not a rig log?); the scenario has {agents} agents"),
            )
        })
    };
    let (kind, frame, t) = (col("kind")?, col("frame")?, col("t_s")?);
    let xy: Vec<(usize, usize)> = (0..agents)
        .map(|i| Ok((col(&format!("x{i}_bl"))?, col(&format!("y{i}_bl"))?)))
        .collect::<Result<_, InputError>>()?;
    let (th, al, gx, gy) = (col("theta")?, col("alpha")?, col("gx")?, col("gy")?);
    let mut frames: Vec<LoggedFrame> = vec![];
    let mut in_force: Option<Control> = None;
    for (line, rec) in rd.records().enumerate() {
        let rec =
            rec.map_err(|e| InputError::new(&name, format!("line {}", line + 2), e.to_string()))?;
        let at = |c: usize, what: &str| -> Result<f64, InputError> {
            let s = rec.get(c).unwrap_or("");
            s.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    InputError::new(
                        &name,
                        format!("line {}: {what}", line + 2),
                        format!("not a finite number: `{s}`"),
                    )
                })
        };
        match rec.get(kind).unwrap_or("") {
            "observation" => {
                let mut pos = Vec::with_capacity(agents);
                for &(cx, cy) in &xy {
                    pos.push(match (rec.get(cx), rec.get(cy)) {
                        (Some(""), _) | (_, Some("")) | (None, _) | (_, None) => None,
                        _ => Some(Vec2::new(at(cx, "x")?, at(cy, "y")?)),
                    });
                }
                frames.push(LoggedFrame {
                    frame: at(frame, "frame")? as u64,
                    t: at(t, "t_s")?,
                    agents: pos,
                    command: in_force,
                });
            }
            "command" => {
                let u = Control {
                    theta: at(th, "theta")?,
                    alpha: at(al, "alpha")?,
                    grad: [at(gx, "gx")?, at(gy, "gy")?],
                };
                in_force = Some(u);
                if let Some(f) = frames.last_mut() {
                    f.command = Some(u);
                }
            }
            "stop" => {
                in_force = None;
                if let Some(f) = frames.last_mut() {
                    f.command = None;
                }
            }
            _ => {}
        }
    }
    if frames.len() < 2 {
        return Err(InputError::new(
            &name,
            "",
            "fewer than 2 observations (not a rig log of a run?)",
        ));
    }
    Ok(LoggedRun {
        source: name,
        frames,
    })
}
