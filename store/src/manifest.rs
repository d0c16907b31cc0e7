//! `manifest.json`: what was run, by which code, where, with how many threads, and when.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::SystemTime;

use serde::{Deserialize, Serialize};

use crate::Error;

/// `manifest.json`.
pub const MANIFEST: &str = "manifest.json";

/// The experiment as run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExperimentInfo {
    /// Name.
    pub name: String,
    /// Description.
    pub description: String,
    /// The file it was read from.
    pub source: String,
    /// SHA-256 of the file's content.
    pub sha256: String,
    /// The file's content.
    pub content: String,
    /// Scenario labels.
    pub scenarios: Vec<String>,
    /// Planner variant labels.
    pub planners: Vec<String>,
    /// Tracker variant labels.
    pub trackers: Vec<String>,
    /// Presets.
    pub presets: Vec<String>,
    /// With a `[tracking]` table: the planners whose plans are tracked (every planner also has
    /// planning runs). Absent when top-level trackers track every run, or nothing is tracked.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tracked_plans: Option<Vec<String>>,
    /// Seeds.
    pub seeds: Vec<u64>,
    /// Iteration limit.
    pub max_iterations: Option<u64>,
    /// Time limit (s).
    pub time_limit_s: Option<f64>,
    /// Runs in the full matrix.
    pub runs_total: usize,
}

/// The machine.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HostInfo {
    /// Host name.
    pub name: String,
    /// Operating system and architecture.
    pub os: String,
    /// Logical CPUs.
    pub cpus: usize,
    /// CPU model (from /proc/cpuinfo where available).
    pub cpu_model: String,
}

/// One invocation of `bench` (the first run, or a `--resume`) or a `merge`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Session {
    /// `bench`, `bench --resume` or `merge`.
    pub kind: String,
    /// Start (RFC 3339, UTC).
    pub started: String,
    /// End, if it ended normally.
    pub finished: Option<String>,
    /// Worker threads.
    pub threads: usize,
    /// Runs executed by this session.
    pub runs_executed: usize,
    /// Wall time (s).
    pub wall_time_s: Option<f64>,
    /// Host.
    pub host: HostInfo,
}

/// `manifest.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Version of the magbench binary.
    pub magbench_version: String,
    /// The experiment.
    pub experiment: ExperimentInfo,
    /// `git rev-parse HEAD` of the source tree ("unknown" outside git), `+dirty` with local changes.
    pub git_revision: String,
    /// Versions of key crates (from Cargo.lock at build time).
    pub crate_versions: BTreeMap<String, String>,
    /// Executor (`real`, or `fake` in tests).
    pub executor: String,
    /// `[index, count]` (1-based) for a shard.
    pub shard: Option<[usize; 2]>,
    /// Shard folders this folder was merged from.
    pub merged_from: Vec<String>,
    /// Start of the first session.
    pub started: String,
    /// End of the session that completed the folder.
    pub finished: Option<String>,
    /// Threads of the latest session.
    pub threads: usize,
    /// Host of the latest session.
    pub host: HostInfo,
    /// Runs in this folder.
    pub runs_done: usize,
    /// Of which crashed.
    pub runs_failed: usize,
    /// Every session, in order.
    pub sessions: Vec<Session>,
    /// Planners and trackers whose runs went one at a time, by name: they hold a global lock
    /// (a Python plugin holds the GIL), so the sweep ran no two of their runs at once.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub one_at_a_time: Vec<String>,
    /// SHA-256 of each file of the folder (but this manifest and the lock file) when it was
    /// finalized, by path relative to the folder; `results verify` checks them.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub files: BTreeMap<String, String>,
    /// The replay policy of the latest sweep (docs/replay.md), e.g. `failed+sample:30`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub replays: Option<String>,
}

/// Now, RFC 3339 UTC to the second.
pub fn now() -> String {
    humantime::format_rfc3339_seconds(SystemTime::now()).to_string()
}

/// The current host.
pub fn host() -> HostInfo {
    let cpu_model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, v)| v.trim().to_string())
        })
        .unwrap_or_default();
    HostInfo {
        name: gethostname::gethostname().to_string_lossy().to_string(),
        os: format!("{} {}", std::env::consts::OS, std::env::consts::ARCH),
        cpus: std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1),
        cpu_model,
    }
}

/// The git revision of the source tree this binary was built from (`+dirty` when a tracked
/// file differs from it).
pub fn git_revision() -> String {
    git_revision_outside(&[])
}

/// The git revision, `+dirty` only when a tracked file outside the `excluded` folders (relative
/// to the repository root) differs from it: `cargo xtask measure` excludes the files it writes.
pub fn git_revision_outside(excluded: &[&str]) -> String {
    let dir = env!("CARGO_MANIFEST_DIR");
    let run = |args: &[&str]| {
        std::process::Command::new("git")
            .arg("-C")
            .arg(dir)
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    match run(&["rev-parse", "HEAD"]) {
        Some(rev) if !rev.is_empty() => {
            let mut status = vec![
                "status".to_string(),
                "--porcelain".into(),
                "--untracked-files=no".into(),
                "--".into(),
                ":(top)".into(),
            ];
            status.extend(excluded.iter().map(|e| format!(":(top,exclude){e}")));
            let args: Vec<&str> = status.iter().map(String::as_str).collect();
            let dirty = run(&args).is_some_and(|s| !s.is_empty());
            if dirty { format!("{rev}+dirty") } else { rev }
        }
        _ => "unknown".into(),
    }
}

/// Versions of key crates.
pub fn crate_versions() -> BTreeMap<String, String> {
    env!("MAGBENCH_CRATE_VERSIONS")
        .split(';')
        .filter_map(|kv| kv.split_once('='))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

impl Manifest {
    /// A new manifest for a sweep of `experiment` starting now, by `executor` on `threads`
    /// threads (of shard `shard`), keeping replays by the policy `replays`.
    pub fn new(
        experiment: ExperimentInfo,
        executor: &str,
        threads: usize,
        shard: Option<[usize; 2]>,
        replays: String,
    ) -> Manifest {
        let host = host();
        let started = now();
        Manifest {
            magbench_version: env!("CARGO_PKG_VERSION").to_string(),
            experiment,
            git_revision: git_revision(),
            crate_versions: crate_versions(),
            executor: executor.to_string(),
            shard,
            merged_from: vec![],
            started: started.clone(),
            finished: None,
            threads,
            host: host.clone(),
            runs_done: 0,
            runs_failed: 0,
            sessions: vec![],
            one_at_a_time: vec![],
            files: BTreeMap::new(),
            replays: Some(replays),
        }
    }

    /// Reads `dir/manifest.json`.
    pub fn read(dir: &Path) -> Result<Manifest, Error> {
        let path = dir.join(MANIFEST);
        let text = std::fs::read_to_string(&path).map_err(|e| {
            Error::Input(magbench_env::InputError::new(
                path.display().to_string(),
                "",
                format!("cannot read: {e}"),
            ))
        })?;
        serde_json::from_str(&text).map_err(|e| {
            Error::Input(magbench_env::InputError::new(
                path.display().to_string(),
                "",
                format!("not a magbench manifest: {e}"),
            ))
        })
    }

    /// Writes `dir/manifest.json` atomically.
    pub fn write(&self, dir: &Path) -> Result<(), Error> {
        let path = dir.join(MANIFEST);
        let tmp = dir.join("manifest.json.tmp");
        let text =
            serde_json::to_string_pretty(self).map_err(|e| Error::Failed(e.to_string()))? + "\n";
        let written = std::fs::File::create(&tmp).and_then(|mut f| {
            std::io::Write::write_all(&mut f, text.as_bytes())?;
            f.sync_all()
        });
        written.map_err(|e| Error::Failed(format!("{}: {e}", tmp.display())))?;
        std::fs::rename(&tmp, &path)
            .map_err(|e| Error::Failed(format!("{}: {e}", path.display())))?;
        crate::store::sync_dir(&path)
    }
}
