//! The two folders' manifests, compared before their runs: a comparison of results from
//! different experiment files, scenarios, limits, presets, seeds, executors or magbench
//! versions is listed (a warning, or an error under `--strict`).

use std::path::Path;

use crate::CliError;
use crate::results::{MANIFEST, Manifest};

/// What the manifests say about the comparison.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ManifestCheck {
    /// Each difference, as a line (`field: baseline …, candidate …`).
    pub differences: Vec<String>,
    /// The two builds' revisions (information: a candidate is usually another build).
    pub builds: Option<String>,
}

/// Seeds as a short text: `0..7 (8 seeds)` for a run of consecutive seeds, else the first few.
fn seeds(s: &[u64]) -> String {
    match s {
        [] => "none".into(),
        [a, .., b] if s.windows(2).all(|w| w[1] == w[0] + 1) => {
            format!("{a}..{b} ({} seeds)", s.len())
        }
        _ if s.len() <= 8 => format!("{s:?}"),
        _ => format!(
            "[{}, …] ({} seeds)",
            s[..6]
                .iter()
                .map(u64::to_string)
                .collect::<Vec<_>>()
                .join(", "),
            s.len()
        ),
    }
}

fn short(h: &str) -> &str {
    h.get(..12).unwrap_or(h)
}

/// A git revision shortened, keeping a `+dirty` mark.
fn revision(r: &str) -> String {
    match r.split_once('+') {
        Some((h, mark)) => format!("{}+{mark}", short(h)),
        None => short(r).to_string(),
    }
}

/// The differences between two manifests.
pub fn differences(b: &Manifest, c: &Manifest) -> Vec<String> {
    let (eb, ec) = (&b.experiment, &c.experiment);
    let mut out = vec![];
    let mut diff = |what: &str, x: String, y: String| {
        if x != y {
            out.push(format!("{what}: baseline {x}, candidate {y}"));
        }
    };
    diff(
        "experiment file (sha256)",
        format!("{} ({})", short(&eb.sha256), eb.source),
        format!("{} ({})", short(&ec.sha256), ec.source),
    );
    diff(
        "scenarios",
        format!("{:?}", eb.scenarios),
        format!("{:?}", ec.scenarios),
    );
    diff(
        "planners",
        format!("{:?}", eb.planners),
        format!("{:?}", ec.planners),
    );
    diff(
        "trackers",
        format!("{:?}", eb.trackers),
        format!("{:?}", ec.trackers),
    );
    diff(
        "presets",
        format!("{:?}", eb.presets),
        format!("{:?}", ec.presets),
    );
    diff("seeds", seeds(&eb.seeds), seeds(&ec.seeds));
    let it = |v: Option<u64>| v.map_or("none".into(), |v| v.to_string());
    diff(
        "limits.iterations",
        it(eb.max_iterations),
        it(ec.max_iterations),
    );
    let ts = |v: Option<f64>| v.map_or("none".into(), |v| format!("{v} s"));
    diff("limits.time_s", ts(eb.time_limit_s), ts(ec.time_limit_s));
    diff("executor", b.executor.clone(), c.executor.clone());
    diff(
        "magbench version",
        b.magbench_version.clone(),
        c.magbench_version.clone(),
    );
    out
}

/// Reads and compares the manifests of the `baseline` and `candidate` folders. A missing
/// manifest is a difference (nothing can be checked); an unreadable one is bad input.
pub fn check(baseline: &Path, candidate: &Path) -> Result<ManifestCheck, CliError> {
    let read = |d: &Path| -> Result<Option<Manifest>, CliError> {
        if d.join(MANIFEST).exists() {
            Manifest::read(d).map(Some)
        } else {
            Ok(None)
        }
    };
    let (b, c) = (read(baseline)?, read(candidate)?);
    let mut out = ManifestCheck::default();
    match (&b, &c) {
        (Some(b), Some(c)) => {
            out.differences = differences(b, c);
            out.builds = Some(format!(
                "builds: baseline {} (git {}), candidate {} (git {})",
                b.magbench_version,
                revision(&b.git_revision),
                c.magbench_version,
                revision(&c.git_revision)
            ));
        }
        _ => {
            for (m, d, side) in [(&b, baseline, "baseline"), (&c, candidate, "candidate")] {
                if m.is_none() {
                    out.differences.push(format!(
                        "{side} {} has no {MANIFEST}: its experiment, limits, seeds and build cannot be checked",
                        d.display()
                    ));
                }
            }
        }
    }
    Ok(out)
}
