//! Experiment files: which scenarios, planners (with parameter variants), trackers, presets
//! and seeds to run, and the planner limits. See docs/benchmarks.md ("Experiment files") for the format.
//!
//! ```toml
//! name = "default"                       # optional, defaults to the file name
//! description = "all planners on the built-in scenarios"
//! scenarios = ["micro-factory", "scenarios/my-maze.toml"]   # names or paths
//! planners = ["goal-zoom-rrt{k=5}", "goal-zoom-rrt{k=20}", { name = "sst", params = { pruning_radius = 0.5 } }]
//! trackers = ["obc", "lookahead{gain=0.5}"] # optional: plan, then track in closed loop
//! presets = ["ideal", "realistic"]          # with trackers; default ["ideal"]
//! seeds = 10                                # a count (seeds 0..9) or a list [1, 5, 9]
//! replays = "failed+sample:30"              # which runs get a replay page (the default)
//! [limits]
//! iterations = 20000                        # and/or
//! time = 5.0                                # seconds of planning
//! ```
//!
//! Top-level `trackers` make every run a tracked run. To compare every planner by planning runs
//! and track only some planners' plans, in the same results, give a `[tracking]` table instead:
//!
//! ```toml
//! scenarios = ["micro-factory"]
//! planners = ["goal-zoom-rrt", "rrt-star", "sst"]
//! seeds = 10
//! [limits]
//! iterations = 5000
//! [tracking]
//! plans = ["goal-zoom-rrt"]          # planners (labels as in `planners`) whose plans are tracked; default all
//! trackers = ["obc", "lookahead"]
//! presets = ["ideal", "realistic"]   # default ["ideal"]
//! ```
//!
//! Every planner then has its planning runs (untracked), and each planner in `plans` also its
//! tracked runs with every tracker and preset.

mod file;
mod matrix;
pub use file::{MAX_RUNS, MAX_SEEDS, SEED_COUNT};
pub use matrix::Matrix;
pub mod generated;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use magbench_env::plant::DisturbancePreset;
use magbench_env::{InputError, Scenario};
use sha2::{Digest, Sha256};

use magbench_store::manifest::{ExperimentInfo, Manifest};

use crate::run::{Executor, RunLimits, RunSpec, Variant};

/// A preset as an experiment names it (a built-in name or a file) and the loaded preset.
pub type LabelledPreset = (String, Arc<DisturbancePreset>);

/// A validated experiment.
#[derive(Debug, Clone)]
pub struct Experiment {
    /// Its name (the results folder is `results/<name>/` by default).
    pub name: String,
    /// Free text.
    pub description: String,
    /// Where it was read from.
    pub source: String,
    /// The file's exact text (hashed and stored in the manifest).
    pub text: String,
    /// Scenarios: the label as written and the loaded scenario.
    pub scenarios: Vec<(String, Arc<Scenario>)>,
    /// Planner variants.
    pub planners: Vec<Variant>,
    /// Tracker variants (empty: planning only).
    pub trackers: Vec<Variant>,
    /// Disturbance presets (empty without trackers).
    pub presets: Vec<LabelledPreset>,
    /// Which runs there are besides the plain planning runs.
    pub tracking: Tracking,
    /// Seeds.
    pub seeds: Vec<u64>,
    /// Planner limits.
    pub limits: RunLimits,
    /// Which runs get a replay page (`replays`; `bench --replays` replaces it).
    pub replays: crate::replay::ReplayPolicy,
}

impl Experiment {
    /// The experiment as a results folder's manifest records it.
    pub fn info(&self) -> ExperimentInfo {
        ExperimentInfo {
            name: self.name.clone(),
            description: self.description.clone(),
            source: self.source.clone(),
            sha256: self.hash(),
            content: self.text.clone(),
            scenarios: self.scenarios.iter().map(|(l, _)| l.clone()).collect(),
            planners: self.planners.iter().map(|p| p.label()).collect(),
            trackers: self.trackers.iter().map(|t| t.label()).collect(),
            presets: self.presets.iter().map(|(l, _)| l.clone()).collect(),
            tracked_plans: match &self.tracking {
                Tracking::Plans(p) => Some(p.clone()),
                Tracking::None | Tracking::Every => None,
            },
            seeds: self.seeds.clone(),
            max_iterations: self.limits.iterations,
            time_limit_s: self.limits.time_s,
            runs_total: self.run_count(),
        }
    }

    /// A new manifest for a sweep of this experiment starting now, by `executor` on `threads`
    /// threads (of shard `shard`).
    pub fn manifest(&self, executor: &str, threads: usize, shard: Option<[usize; 2]>) -> Manifest {
        Manifest::new(
            self.info(),
            executor,
            threads,
            shard,
            self.replays.to_string(),
        )
    }

    /// Reads and validates an experiment file; scenario paths are relative to the file's folder
    /// (or to the working directory).
    pub fn load(path: &Path, ex: &dyn Executor) -> Result<Experiment, InputError> {
        let file = path.display().to_string();
        let text = magbench_env::input::read_text(path, &file)?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().to_string())
            .unwrap_or_else(|| "experiment".into());
        Experiment::parse(&text, &file, &base, &stem, ex)
    }

    /// Parses and validates experiment TOML `text` (named `file` in errors).
    pub fn parse(
        text: &str,
        file: &str,
        base_dir: &Path,
        default_name: &str,
        ex: &dyn Executor,
    ) -> Result<Experiment, InputError> {
        file::parse(text, file, base_dir, default_name, ex)
    }

    /// SHA-256 of the file's text, in hex.
    pub fn hash(&self) -> String {
        hex(&Sha256::digest(self.text.as_bytes()))
    }

    /// The run matrix, made run by run.
    pub fn matrix(&self) -> Matrix<'_> {
        Matrix::of(self)
    }

    /// The full run matrix in a fixed order: scenario, planner, tracker, preset, seed (a
    /// planner's planning runs before its tracked runs).
    pub fn runs(&self) -> Vec<RunSpec> {
        self.runs_of(None)
    }

    /// The runs of shard `k` of `n` (`Some((k, n))`, 1-based: the runs whose index is `k − 1`
    /// modulo `n`) of the run matrix, or the whole matrix; only those runs are made.
    pub fn runs_of(&self, shard: Option<(usize, usize)>) -> Vec<RunSpec> {
        let m = self.matrix();
        m.indices(shard).map(|i| m.spec(i)).collect()
    }

    /// The runs of the matrix, in order, whose index and seed `keep` accepts; only those runs
    /// are made.
    pub fn runs_where(&self, keep: impl Fn(usize, u64) -> bool) -> Vec<RunSpec> {
        let m = self.matrix();
        (0..m.len())
            .filter(|&i| keep(i, m.seed(i)))
            .map(|i| m.spec(i))
            .collect()
    }

    /// The number of runs of the matrix.
    pub fn run_count(&self) -> usize {
        self.matrix().len()
    }

    /// The number of runs of shard `k` of `n` (as [`Experiment::runs_of`]), or of the matrix.
    pub fn run_count_of(&self, shard: Option<(usize, usize)>) -> usize {
        self.matrix().indices(shard).len()
    }

    /// The index and id (`scenario|planner|tracker|preset|seed`, as [`RunSpec::id`]) of every
    /// run of the matrix, in order, without making the runs.
    pub fn run_ids(&self) -> impl Iterator<Item = (usize, String)> + '_ {
        let m = self.matrix();
        (0..m.len()).map(move |i| (i, m.id(i)))
    }
}

/// Which runs an experiment has besides planning runs.
#[derive(Debug, Clone, PartialEq)]
pub enum Tracking {
    /// No trackers: every run is a planning run.
    None,
    /// Top-level `trackers`: every run plans, then tracks (no planning-only runs).
    Every,
    /// A `[tracking]` table: every planner has its planning runs, and the planners with these
    /// labels also their tracked runs.
    Plans(Vec<String>),
}

impl Tracking {
    /// True when the matrix has planning-only runs.
    pub fn has_planning_runs(&self) -> bool {
        !matches!(self, Tracking::Every)
    }

    /// True when planner `p`'s plans are tracked.
    pub fn tracks(&self, p: &Variant) -> bool {
        match self {
            Tracking::None => false,
            Tracking::Every => true,
            Tracking::Plans(labels) => labels.contains(&p.label()),
        }
    }
}

/// Lower-case hex of `bytes`.
pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Resolves a preset label: a built-in name, a file relative to `base_dir`, a file relative
/// to the working directory, or `BASE:VARIANT`, an ablation variant of the preset `BASE`
/// ([`crate::ablation::variant`]: `hardware:no-flow`).
pub fn resolve_preset(label: &str, base_dir: &Path) -> Result<DisturbancePreset, InputError> {
    if let Some(p) = DisturbancePreset::by_name(label) {
        return Ok(p);
    }
    let rel: PathBuf = base_dir.join(label);
    if rel.exists() {
        return DisturbancePreset::load(&rel);
    }
    if let Some((base, name)) = label
        .rsplit_once(':')
        .filter(|_| !Path::new(label).exists())
    {
        let p = resolve_preset(base, base_dir)?;
        return crate::ablation::variant(&p, name).ok_or_else(|| {
            let names: Vec<String> = crate::ablation::variants(&p)
                .into_iter()
                .map(|v| v.name)
                .collect();
            InputError::new(
                label,
                "",
                format!(
                    "preset {base} has no ablation variant `{name}`; it has {}",
                    names.join(", ")
                ),
            )
        });
    }
    if !Path::new(label).exists() {
        return Err(InputError::new(
            label,
            "",
            format!(
                "unknown preset: neither a built-in preset ({}) nor a file",
                DisturbancePreset::NAMES.join(", ")
            ),
        ));
    }
    DisturbancePreset::load(Path::new(label))
}

/// Resolves a scenario label: a built-in name, a path relative to `base_dir`, or a path
/// relative to the working directory.
pub fn resolve_scenario(label: &str, base_dir: &Path) -> Result<Scenario, InputError> {
    if magbench_env::scenario::builtin_source(label).is_some() {
        return Scenario::load(label);
    }
    let rel: PathBuf = base_dir.join(label);
    if rel.exists() {
        return Scenario::load(&rel.display().to_string());
    }
    Scenario::load(label)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::real::RealExecutor;

    /// The TOML example of this file's documentation that follows the line containing
    /// `after`.
    fn doc_example(after: &str) -> String {
        include_str!("mod.rs")
            .lines()
            .map_while(|l| l.strip_prefix("//!"))
            .skip_while(|l| !l.contains(after))
            .skip_while(|l| !l.contains("```toml"))
            .skip(1)
            .take_while(|l| !l.contains("```"))
            .map(|l| format!("{}\n", l.trim_start()))
            .collect()
    }

    fn parse(example: &str) -> Experiment {
        Experiment::parse(
            example,
            "doc",
            Path::new("."),
            "doc",
            &RealExecutor::default(),
        )
        .unwrap_or_else(|e| panic!("{e}\n{example}"))
    }

    /// The example at the top of this file is a valid experiment (it went stale once: `sst`
    /// has no `delta`).
    #[test]
    fn the_documented_example_is_valid() {
        let example =
            doc_example("Experiment files").replace("\"scenarios/my-maze.toml\"", "\"open-field\"");
        assert!(example.contains("planners"), "{example}");
        assert_eq!(parse(&example).planners.len(), 3);
    }

    /// The `[tracking]` example of this file is valid too.
    #[test]
    fn the_documented_tracking_example_is_valid() {
        let example = doc_example("[tracking]` table");
        assert!(example.contains("[tracking]"), "{example}");
        // 3 planners × 10 planning runs + goal-zoom-rrt × 2 trackers × 2 presets × 10
        let e = parse(&example);
        assert_eq!(e.runs().len(), 30 + 40);
        // the matrix's count, ids and shards without making every run agree with the runs
        let all = e.runs();
        assert_eq!(e.run_count(), all.len());
        let ids: Vec<(usize, String)> = all.iter().map(|r| (r.index, r.id())).collect();
        assert_eq!(e.run_ids().collect::<Vec<_>>(), ids);
        for n in [1, 3, 7] {
            let mut shards: Vec<usize> = (1..=n)
                .flat_map(|k| e.runs_of(Some((k, n))).into_iter().map(|r| r.index))
                .collect();
            assert!(
                e.runs_of(Some((2.min(n), n)))
                    .iter()
                    .all(|r| r.index % n == 2.min(n) - 1)
            );
            shards.sort();
            assert_eq!(shards, (0..all.len()).collect::<Vec<_>>());
            for k in 1..=n {
                assert_eq!(e.run_count_of(Some((k, n))), e.runs_of(Some((k, n))).len());
            }
        }
        assert_eq!(e.run_count_of(None), all.len());
        // the documented order: a planner's planning runs, then its tracked runs, seeds inside
        let order: Vec<(&str, &str, &str)> = all
            .iter()
            .step_by(e.seeds.len())
            .map(|r| {
                let t = r.tracker.as_ref().map_or("-", |t| t.name.as_str());
                (
                    r.planner.name.as_str(),
                    t,
                    r.preset.as_deref().unwrap_or("-"),
                )
            })
            .collect();
        assert_eq!(
            order,
            [
                ("goal-zoom-rrt", "-", "-"),
                ("goal-zoom-rrt", "obc", "ideal"),
                ("goal-zoom-rrt", "obc", "realistic"),
                ("goal-zoom-rrt", "lookahead", "ideal"),
                ("goal-zoom-rrt", "lookahead", "realistic"),
                ("rrt-star", "-", "-"),
                ("sst", "-", "-"),
            ]
        );
        assert!(
            all.iter()
                .enumerate()
                .all(|(i, r)| r.index == i && r.seed == e.seeds[i % e.seeds.len()])
        );
        // a run's index from its id, and none for an id of no run
        let m = e.matrix();
        assert!(all.iter().all(|r| m.index_of(&r.id()) == Some(r.index)));
        for id in [
            "micro-factory|sst|-|-|10",
            "micro-factory|sst|obc|ideal|0",
            "x",
            "",
        ] {
            assert_eq!(m.index_of(id), None, "{id}");
        }
        let first = e.seeds[0];
        let firsts = e.runs_where(|_, seed| seed == first);
        assert_eq!(firsts.len() * e.seeds.len(), all.len());
        assert!(
            firsts
                .iter()
                .all(|r| r.seed == first && all[r.index].id() == r.id())
        );
    }

    #[test]
    fn a_preset_label_can_name_an_ablation_variant() {
        let here = Path::new(".");
        let p = resolve_preset("hardware:no-camera-noise", here).unwrap();
        assert_eq!(p.name, "hardware:no-camera-noise");
        assert_eq!(p.enabled("camera.noise"), Some(false));
        assert_eq!(p.enabled("flow"), Some(true));
        let e = resolve_preset("hardware:no-drift", here).unwrap_err();
        assert!(e.to_string().contains("only-flow"), "{e}");
        assert!(resolve_preset("nowhere:all", here).is_err());
    }
}
