//! The two folders' manifests, compared before their runs: a comparison of results from
//! different experiment files, scenarios, limits, presets, seeds, executors or magbench
//! versions is listed (a warning, or an error under `--strict`).

use std::path::Path;

use crate::Error;
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

/// Each compared field of a manifest: its name and its value as text.
type Field = (&'static str, fn(&Manifest) -> String);

/// The fields [`differences`] compares, in the order they are listed.
const FIELDS: [Field; 10] = [
    ("experiment file (sha256)", |m| {
        let e = &m.experiment;
        format!("{} ({})", short(&e.sha256), e.source)
    }),
    ("scenarios", |m| format!("{:?}", m.experiment.scenarios)),
    ("planners", |m| format!("{:?}", m.experiment.planners)),
    ("trackers", |m| format!("{:?}", m.experiment.trackers)),
    ("presets", |m| format!("{:?}", m.experiment.presets)),
    ("seeds", |m| seeds(&m.experiment.seeds)),
    ("limits.iterations", |m| {
        m.experiment
            .max_iterations
            .map_or("none".into(), |v| v.to_string())
    }),
    ("limits.time_s", |m| {
        m.experiment
            .time_limit_s
            .map_or("none".into(), |v| format!("{v} s"))
    }),
    ("executor", |m| m.executor.clone()),
    ("magbench version", |m| m.magbench_version.clone()),
];

/// The differences between two manifests.
pub fn differences(b: &Manifest, c: &Manifest) -> Vec<String> {
    FIELDS
        .iter()
        .filter_map(|(what, show)| {
            let (x, y) = (show(b), show(c));
            (x != y).then(|| format!("{what}: baseline {x}, candidate {y}"))
        })
        .collect()
}

/// Reads and compares the manifests of the `baseline` and `candidate` folders. A missing
/// manifest is a difference (nothing can be checked); an unreadable one is bad input.
pub fn check(baseline: &Path, candidate: &Path) -> Result<ManifestCheck, Error> {
    let read = |d: &Path| -> Result<Option<Manifest>, Error> {
        if d.join(MANIFEST).exists() {
            Ok(Some(Manifest::read(d)?))
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
