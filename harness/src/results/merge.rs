//! Merging shard folders into one results folder.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use magbench_env::InputError;

use super::manifest::{Manifest, Session, host, now};
use super::store;
use crate::CliError;
use crate::run::{ProgressRow, RunRecord};

/// Merges the results folders `shards` (of the same experiment) into `out`, which must not
/// hold results, and writes its derived files, holding `out`'s lock throughout (exit 2 if
/// another process holds it). Only whole runs are taken (one row, and exactly the trace
/// points the row records); a run found in several folders is taken from the first.
pub fn merge(shards: &[PathBuf], out: &Path) -> Result<Manifest, CliError> {
    if shards.is_empty() {
        return Err(CliError::arg(
            "DIR",
            "give at least one results folder to merge",
        ));
    }
    std::fs::create_dir_all(out)
        .map_err(|e| CliError::Failed(format!("{}: {e}", out.display())))?;
    let _lock = super::lock::exclusive(out, "merge", "--out")?;
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
        // Read only, whole runs: a task may still be writing `s`.
        let (whole, trace, partial) = whole_runs(store::read_runs(s)?, store::read_progress(s)?);
        if partial > 0 {
            eprintln!(
                "note: {}: {partial} runs left out: their rows are doubled or their traces \
                 incomplete (`bench --resume` on that folder repairs them)",
                s.display()
            );
        }
        let ids: BTreeSet<String> = whole
            .iter()
            .filter(|r| !runs.contains_key(&r.run_id))
            .map(|r| r.run_id.clone())
            .collect();
        progress.extend(trace.into_iter().filter(|p| ids.contains(&p.run_id)));
        for r in whole.into_iter().filter(|r| ids.contains(&r.run_id)) {
            crate::replay::files::copy_run(s, out, r.run)?;
            runs.insert(r.run_id.clone(), r);
        }
    }
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
    m.files.clear();
    m.write(out)?;
    store::write_sorted(out, runs.into_values().collect(), progress)?;
    super::finalize(out)?;
    super::verify::require_sound(out, false)?;
    Manifest::read(out)
}

/// The whole runs of one folder's rows and trace points: runs with one row whose trace has
/// exactly the points the row records (any trace for rows of older versions, which record
/// none), with their trace points; and how many runs were left out.
pub fn whole_runs(
    runs: Vec<RunRecord>,
    progress: Vec<ProgressRow>,
) -> (Vec<RunRecord>, Vec<ProgressRow>, usize) {
    let mut rows: BTreeMap<String, usize> = BTreeMap::new();
    for r in &runs {
        *rows.entry(r.run_id.clone()).or_default() += 1;
    }
    let mut points: BTreeMap<&str, u64> = BTreeMap::new();
    for p in &progress {
        *points.entry(&p.run_id).or_default() += 1;
    }
    let keep: BTreeSet<String> = runs
        .iter()
        .filter(|r| rows[&r.run_id] == 1)
        .filter(|r| {
            r.progress_rows
                .is_none_or(|k| points.get(&*r.run_id).copied().unwrap_or(0) == k)
        })
        .map(|r| r.run_id.clone())
        .collect();
    let left_out = rows.len() - keep.len();
    let progress = progress
        .into_iter()
        .filter(|p| keep.contains(&p.run_id))
        .collect();
    let runs = runs
        .into_iter()
        .filter(|r| keep.contains(&r.run_id))
        .collect();
    (runs, progress, left_out)
}
