//! Merging shard folders into one results folder.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use magbench_env::InputError;

use super::manifest::{Manifest, Session, host, now};
use super::store;
use crate::CliError;

/// Merges the results folders `shards` (of the same experiment) into `out`, which must not
/// exist or be empty, and writes its derived files. Runs found in several folders must agree
/// on every column but wall-clock times; the first copy is kept.
pub fn merge(shards: &[PathBuf], out: &Path) -> Result<Manifest, CliError> {
    if shards.is_empty() {
        return Err(CliError::arg(
            "DIR",
            "give at least one results folder to merge",
        ));
    }
    if out.join(super::MANIFEST).exists() {
        return Err(CliError::Input(InputError::new(
            out.display().to_string(),
            "--out",
            "already holds results; choose another --out",
        )));
    }
    let t0 = std::time::Instant::now();
    let mut manifests = vec![];
    for s in shards {
        manifests.push(Manifest::read(s)?);
    }
    let first = manifests[0].clone();
    for (s, m) in shards.iter().zip(&manifests) {
        if m.experiment.sha256 != first.experiment.sha256 {
            return Err(CliError::Input(InputError::new(
                s.display().to_string(),
                "manifest.json",
                format!(
                    "experiment {} (sha256 {}) differs from {} in {}",
                    m.experiment.name,
                    &m.experiment.sha256[..12],
                    &first.experiment.sha256[..12],
                    shards[0].display()
                ),
            )));
        }
    }
    let mut runs = BTreeMap::new();
    let mut progress = vec![];
    for s in shards {
        // Read only (complete rows, first copy of a run): a task may still be writing `s`.
        let mut ids = std::collections::BTreeSet::new();
        let kept: Vec<_> = store::read_runs(s)?
            .into_iter()
            .filter(|r| !runs.contains_key(&r.run_id) && ids.insert(r.run_id.clone()))
            .collect();
        progress.extend(
            store::read_progress(s)?
                .into_iter()
                .filter(|p| ids.contains(&p.run_id)),
        );
        for r in kept {
            runs.insert(r.run_id.clone(), r);
        }
    }
    std::fs::create_dir_all(out)
        .map_err(|e| CliError::Failed(format!("{}: {e}", out.display())))?;
    let mut m = first.clone();
    m.shard = None;
    m.merged_from = shards.iter().map(|s| s.display().to_string()).collect();
    m.started = manifests
        .iter()
        .map(|m| m.started.clone())
        .min()
        .unwrap_or_else(now);
    m.sessions = manifests.iter().flat_map(|m| m.sessions.clone()).collect();
    m.threads = manifests.iter().map(|m| m.threads).max().unwrap_or(1);
    m.sessions.push(Session {
        kind: "merge".into(),
        started: now(),
        finished: Some(now()),
        threads: 1,
        runs_executed: 0,
        wall_time_s: Some(t0.elapsed().as_secs_f64()),
        host: host(),
    });
    m.write(out)?;
    store::write_sorted(out, runs.into_values().collect(), progress)?;
    super::finalize(out)?;
    Manifest::read(out)
}
