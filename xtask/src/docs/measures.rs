//! The measurements of the book: each an experiment in `experiments/` and the table its runs
//! become, a bench of `benches/` and the table of criterion's estimates, a cargo test or
//! example and the table it prints, a Python script and the table it prints, or a transcript
//! of magbench commands. Adding one is one
//! entry here and its `{{#include measured/NAME.md}}` in a chapter.

use std::path::Path;

use super::ablation::ablation;
pub use super::cargo_test::Target;
use super::convergence::convergence;
use super::cost_at_time::{by_family_at_times, cost_at_time};
use super::edge_tables::edge_length;
use super::planner_tables::{improvement, team_scaling};
use super::replans::replan_latency;
use super::tables::{errors, first_solution, loop_cost, planning, tracking};
use super::teams::{first_solution_work, team_runs};
use super::tracker_tables::comparison;
use super::transcript::Step;
use Kind::{Folder, Outputs, Runs};
use Source::{Bench, Python, Sweep, Test, Transcript};
use magbench::Error;
use magbench::run::{RunOutput, RunRecord};
use magbench::table::Table;

/// How a measurement's runs become its table.
#[derive(Debug, Clone, Copy)]
pub enum Kind {
    /// A sweep of the experiment; the table comes from its `runs.csv` rows.
    Runs(fn(&[RunRecord]) -> Table),
    /// A sweep of the experiment; the table comes from its results folder (`progress.csv` as
    /// well as the `runs.csv` rows, given).
    Folder(fn(&Path, &[RunRecord]) -> Result<Table, Error>),
    /// The experiment's runs, each run's whole output kept (its replan log too); no results
    /// folder is written.
    Outputs(fn(&[RunOutput]) -> Table),
}

/// Where a measurement's figures come from.
#[derive(Debug, Clone, Copy)]
pub enum Source {
    /// An experiment of `experiments/`, run by magbench itself.
    Sweep {
        /// The experiment run, relative to the repository root.
        experiment: &'static str,
        /// Seeds kept under `--quick` (the first ones of the experiment's).
        quick_seeds: usize,
        /// How the runs become the file's table.
        table: Kind,
        /// Figures of the sweep's results folder shown under the table: the stems of its
        /// `plots/SCENARIO/` files (`cost-vs-time`), each scenario's copied to
        /// `docs/measured/NAME/SCENARIO-STEM.svg` (empty: none).
        figures: &'static [&'static str],
    },
    /// A bench of crate `magbench-benches`, run from the repository root by
    /// `cargo bench -p magbench-benches --bench BENCH [--features F] -- --noplot ARGS`
    /// (release build). The file's first table holds criterion's estimates of `ids`; the lines
    /// of the bench's stdout that are Markdown table lines (`| … |`: figures a bench computes
    /// itself, such as percentiles of whole runs) follow as a second table. Under `--quick`
    /// the bench gets `quick_args` instead of `args` (criterion's `--quick`: a check that it
    /// runs, not figures).
    Bench {
        /// The bench target (a file `benches/benches/BENCH.rs`).
        bench: &'static str,
        /// Criterion's full ids of the benchmarks tabled, in table order (`group/function`
        /// for a benchmark of a group); empty for a bench that prints only its own table.
        ids: &'static [&'static str],
        /// Arguments for the bench after `--noplot`.
        args: &'static [&'static str],
        /// Arguments for the bench after `--noplot` under `--quick`.
        quick_args: &'static [&'static str],
    },
    /// A cargo test or example, run from the repository root by `cargo test -p PACKAGE
    /// [--release] [--features F] (--lib | --test FILE) -- [--ignored] --exact TEST
    /// --nocapture` or `cargo run -p PACKAGE [--release] [--features F] --example E`. The
    /// file is the Markdown table lines (`| … |`) it prints on stdout; printing none is an
    /// error. `--quick` runs it in full.
    Test {
        /// The crate.
        package: &'static str,
        /// Its library, a test file or an example.
        target: Target,
        /// The test's exact name within the target (empty for an example).
        test: &'static str,
        /// The test is `#[ignore]`d (kept out of `cargo test --workspace`): run it anyway.
        ignored: bool,
        /// A release build, for figures of time; a debug build for figures that do not
        /// depend on speed (accuracy, counts), which builds faster.
        release: bool,
    },
    /// A Python script of the repository, run from the repository root as `PYTHON SCRIPT ARGS`
    /// by the interpreter that `$MAGBENCH_PYTHON` names (default `python3`), which must import
    /// magbench (`pip install ./python`; else exit code 2 naming the variable). The file is
    /// the Markdown table lines (`| … |`) it prints on stdout; printing none is an error. The
    /// header names the interpreter and the magbench module it imported.
    Python {
        /// The script, relative to the repository root.
        script: &'static str,
        /// Its arguments; `{work}` stands for the measurement's folder in `--work` (emptied
        /// first).
        args: &'static [&'static str],
        /// Arguments added under `--quick` (empty: `--quick` runs it in full).
        quick_args: &'static [&'static str],
    },
    /// magbench command lines run one after another by this binary in a fresh temporary
    /// folder; the file is their output (a console block) and their wall times. `--quick`
    /// runs them in full (they are single runs, with nothing to shorten).
    Transcript {
        /// Repository files and folders the commands read, at the same relative paths in the
        /// temporary folder (a folder is linked, a file copied).
        files: &'static [&'static str],
        /// The working folder of the commands, relative to the temporary folder.
        cwd: &'static str,
        /// The commands.
        steps: &'static [Step],
    },
}

/// One measurement: `cargo xtask measure --only NAME` writes `docs/measured/NAME.md`.
#[derive(Debug, Clone, Copy)]
pub struct Measure {
    /// The file's stem.
    pub name: &'static str,
    /// What runs.
    pub source: Source,
    /// The cargo feature it needs (`None`: the default build has everything): of `magbench`
    /// for a sweep (this build must have it), of `magbench-benches` for a bench (passed to
    /// `cargo bench`), of the test's crate for a test (passed to cargo).
    pub feature: Option<&'static str>,
    /// The source its figures depend on besides its own file (see [`Measure::own_files`]):
    /// groups of git pathspecs relative to the repository root (`:!PATH` excludes).
    /// `cargo xtask stale` reports the file when any of them changed after the revision its
    /// header names.
    pub depends: &'static [&'static [&'static str]],
}

impl Measure {
    /// Whether `cargo xtask measure` without `--only` runs it: it needs no feature, or this build has
    /// that feature (for a bench, a build with the feature says its library, such as OMPL, is
    /// installed).
    pub fn available(&self) -> bool {
        match self.feature {
            None => true,
            Some("ompl") => cfg!(feature = "ompl"),
            Some(_) => false,
        }
    }

    /// Whether `cargo xtask measure --only NAME` can run it in this build: a bench or a test always
    /// (cargo builds it with its feature), anything else if [`Measure::available`].
    pub fn runnable(&self) -> bool {
        matches!(self.source, Bench { .. } | Test { .. }) || self.available()
    }

    /// The experiment file of a sweep, relative to the repository root.
    pub fn experiment(&self) -> Option<&'static str> {
        match self.source {
            Sweep { experiment, .. } => Some(experiment),
            Bench { .. } | Test { .. } | Python { .. } | Transcript { .. } => None,
        }
    }

    /// The repository files that are the measurement itself, as git pathspecs: its experiment,
    /// bench, test, example or script, or a transcript's files and renderer.
    pub fn own_files(&self) -> Vec<String> {
        match self.source {
            Sweep { experiment, .. } => vec![experiment.to_string()],
            Bench { bench, .. } => {
                vec![format!("benches/benches/{bench}.rs"), "benches/src".into()]
            }
            Test {
                package, target, ..
            } => {
                let dir = crate_dir(package);
                match target {
                    Target::Lib => vec![format!("{dir}/src")],
                    Target::Test(f) => vec![
                        format!("{dir}/tests/{f}.rs"),
                        format!("{dir}/tests/{f}"),
                        format!("{dir}/tests/common"),
                    ],
                    Target::Example(e) => vec![format!("{dir}/examples/{e}.rs")],
                }
            }
            Python { script, .. } => vec![script.to_string()],
            Transcript { files, .. } => files.iter().map(|f| f.to_string()).collect(),
        }
    }

    /// The files of [`NAMED_FILES`] its figures depend on, as git pathspecs: those of a group
    /// it declares whose names the text of what it runs holds anywhere ([`Measure::run_text`]),
    /// so that a name in a label, a parameter or another name counts; all of them if that text
    /// cannot be read.
    pub fn named_files(&self, root: &Path) -> Vec<&'static str> {
        let text = self.run_text(root);
        NAMED_FILES
            .iter()
            .filter(|(group, _, _)| self.depends.contains(group))
            .filter(|(_, name, _)| text.as_ref().is_none_or(|t| t.contains(name)))
            .map(|(_, _, file)| *file)
            .collect()
    }

    /// The text that says which components it runs, read under `root`: a sweep's experiment; a
    /// transcript's commands and the files and folders they read; a bench's file and the benches'
    /// library; a test file or example with its test folder and common module; a Python script
    /// and the modules beside it. `None` (it may run any) for a crate's unit tests, which live
    /// among every component's files, or when its main file cannot be read. No measurement
    /// picks components from the registry without naming them (a test checks the benches,
    /// examples and scripts for a registry listing).
    pub fn run_text(&self, root: &Path) -> Option<String> {
        let mut text = String::new();
        match self.source {
            Sweep { experiment, .. } => {
                text = std::fs::read_to_string(root.join(experiment)).ok()?;
            }
            Transcript { steps, files, .. } => {
                for step in steps {
                    let (Step::Run(c) | Step::Background { command: c, .. }) = step;
                    text.push_str(c);
                    text.push('\n');
                }
                for file in files {
                    read_into(&root.join(file), &mut text);
                }
            }
            Test {
                target: Target::Lib,
                ..
            } => return None,
            Python { script, .. } => {
                let path = root.join(script);
                text = std::fs::read_to_string(&path).ok()?;
                let dir = path.parent()?;
                for entry in std::fs::read_dir(dir).ok()?.flatten() {
                    let p = entry.path();
                    if p != path && p.extension().is_some_and(|e| e == "py") {
                        read_into(&p, &mut text);
                    }
                }
            }
            Bench { .. } | Test { .. } => {
                let own = self.own_files();
                text = std::fs::read_to_string(root.join(&own[0])).ok()?;
                for other in &own[1..] {
                    read_into(&root.join(other), &mut text);
                }
            }
        }
        Some(text)
    }

    /// What runs and what `--quick` keeps, for `cargo xtask measure --list`.
    pub fn describe(&self) -> String {
        match self.source {
            Sweep {
                experiment,
                quick_seeds,
                ..
            } => format!("{experiment}\t--quick: {quick_seeds} seeds"),
            Bench {
                bench, quick_args, ..
            } => format!(
                "cargo bench --bench {bench}\t--quick: bench arguments {:?}",
                quick_args.join(" ")
            ),
            Test {
                package,
                target,
                test,
                release,
                ..
            } => {
                let what = match target {
                    Target::Example(e) => format!("cargo run -p {package} --example {e}"),
                    Target::Lib => format!("cargo test -p {package} --lib {test}"),
                    Target::Test(f) => format!("cargo test -p {package} --test {f} {test}"),
                };
                let build = if release { "release" } else { "debug" };
                format!("{what} ({build} build)\t--quick: all of it")
            }
            Python {
                script,
                args,
                quick_args,
            } => {
                let quick = match quick_args {
                    [] => "all of it".to_string(),
                    q => format!("adds {:?}", q.join(" ")),
                };
                format!(
                    "${} {script} {}\t--quick: {quick}",
                    super::python::PYTHON_VAR,
                    args.join(" ")
                )
            }
            Transcript { steps, .. } => {
                format!("{} magbench commands\t--quick: all of them", steps.len())
            }
        }
    }
}

/// Appends the text of the file at `path`, or of every file under the folder at `path`, to
/// `text`; a path that is missing or not text adds nothing.
fn read_into(path: &Path, text: &mut String) {
    if path.is_dir() {
        let Ok(entries) = std::fs::read_dir(path) else {
            return;
        };
        let mut paths: Vec<_> = entries.flatten().map(|e| e.path()).collect();
        paths.sort();
        for p in paths {
            read_into(&p, text);
        }
    } else if let Ok(t) = std::fs::read_to_string(path) {
        text.push_str(&t);
        text.push('\n');
    }
}

/// The physics, the plant's presets, the dependencies' versions and the build profiles: every
/// measurement's figures depend on them. The scenario generator and the team rank test are
/// declared apart ([`GENERATOR`], [`CONTROLLABILITY`]) by the measurements that use them.
const PLANT: &[&str] = &[
    "env/src",
    "presets",
    // the dependencies' versions and the build profiles, which can move any figure
    "Cargo.lock",
    "Cargo.toml",
    ":!env/src/scenario/generate",
    ":!env/src/team_controllability.rs",
    // the spin of formations: only `magbench scenario show` and `check` print it, and no
    // measurement runs them
    ":!env/src/team_spin.rs",
    // the crate's module declarations and re-exports, which change nothing by themselves (a
    // test checks that the file holds nothing else)
    ":!env/src/lib.rs",
];
/// Everything a release build of the command line compiles: every crate's manifest and sources
/// and the workspace's settings (the build's time, not its figures).
const BUILD: &[&str] = &[
    "Cargo.lock",
    "Cargo.toml",
    ".cargo",
    "env",
    "planners",
    "trackers",
    "drivers",
    "analysis",
    "plot",
    "store",
    "harness",
    "cli",
    // the crates' tests and examples, which that build does not compile
    ":!env/tests",
    ":!env/examples",
    ":!planners/tests",
    ":!planners/examples",
    ":!trackers/tests",
    ":!drivers/tests",
    ":!drivers/examples",
    ":!cli/tests",
    ":!cli/examples",
];
/// The scenario generator: measurements of experiments with `[[generated]]` tables or suites.
const GENERATOR: &[&str] = &["env/src/scenario/generate"];
/// The Lie-bracket rank test of teams (`magbench stlc`, the formation study).
const CONTROLLABILITY: &[&str] = &["env/src/team_controllability.rs"];
/// The planners and the scenarios they plan on. The own files of the planners in
/// [`NAMED_FILES`] count only for the measurements that run them ([`Measure::named_files`]).
const PLANNING: &[&str] = &[
    "planners/src",
    "scenarios",
    ":!planners/src/planners/formation_rrt.rs",
    ":!planners/src/planners/rrt_star",
    ":!planners/src/planners/sst.rs",
    ":!planners/src/planners/trajopt.rs",
    ":!planners/src/trajopt",
];
/// Planners and trackers that run only where a measurement names them: the group that leaves
/// their files out, the name, and the files. goal-zoom RRT, OBC, lookahead and open-loop are not
/// among them: they are defaults (of `plan`, `track`, Python, the figures and the calibration
/// bench) or run inside others, so any measurement may run them. The trajectory optimiser
/// (planners/src/trajopt) runs only in the `trajopt` planner and in the pass a label asks for
/// with `trajopt=N` (off by default), so only a measurement whose text holds "trajopt" runs it.
const NAMED_FILES: &[(&[&str], &str, &str)] = &[
    (
        PLANNING,
        "formation-rrt",
        "planners/src/planners/formation_rrt.rs",
    ),
    // also informed-rrt-star's, whose name holds this one
    (PLANNING, "rrt-star", "planners/src/planners/rrt_star"),
    (PLANNING, "sst", "planners/src/planners/sst.rs"),
    (PLANNING, "trajopt", "planners/src/planners/trajopt.rs"),
    (PLANNING, "trajopt", "planners/src/trajopt"),
    (TRACKING, "formation", "trackers/src/trackers/formation.rs"),
    (TRACKING, "mppi", "trackers/src/trackers/mppi.rs"),
];
/// The trackers. The own files of the trackers in [`NAMED_FILES`] count only for the
/// measurements that run them ([`Measure::named_files`]).
const TRACKING: &[&str] = &[
    "trackers/src",
    ":!trackers/src/trackers/formation.rs",
    ":!trackers/src/trackers/mppi.rs",
];
/// What turns an experiment into runs and its runs into a table.
const SWEEP: &[&str] = &[
    "harness/src/run",
    "harness/src/pipeline",
    "harness/src/experiment",
    "analysis/src/metrics",
    "harness/src/results",
    // the module's declarations (a test checks that the file holds nothing else)
    ":!harness/src/results/mod.rs",
    // a results folder's figures and derived files and the check that ends `bench`: no table
    // depends on them (a measurement that shows them declares FIGURES or DERIVED); and `merge`,
    // which no sweep runs (a measurement that runs it declares DERIVED; a test checks)
    ":!harness/src/results/merge.rs",
    ":!harness/src/results/finalize.rs",
    ":!harness/src/results/plots.rs",
    ":!harness/src/results/report.rs",
    ":!harness/src/results/ompl",
    ":!harness/src/results/sample.rs",
    "store/src",
    // the crate's module declarations and re-exports (a test checks that the file holds nothing
    // else)
    ":!store/src/lib.rs",
    ":!store/src/merge.rs",
    ":!store/src/parquet.rs",
    ":!store/src/progress_parquet.rs",
    ":!store/src/temporary.rs",
    ":!store/src/traces.rs",
    ":!store/src/verify.rs",
    ":!store/src/verify_rows.rs",
    "analysis/src/stats",
    "analysis/src/table.rs",
    "harness/src/registry.rs",
    "xtask/src/docs/tables.rs",
    "xtask/src/docs/planner_tables.rs",
    "xtask/src/docs/teams.rs",
    "xtask/src/docs/convergence.rs",
    "xtask/src/docs/ablation.rs",
    "xtask/src/docs/replans.rs",
];
/// The edge-length study's table.
const EDGE_TABLES: &[&str] = &["xtask/src/docs/edge_tables.rs"];
/// The table of best cost at fixed times.
const COST_AT_TIME: &[&str] = &["xtask/src/docs/cost_at_time.rs"];
/// A results folder's figures, for a measurement that shows them (`figures` of a sweep).
const FIGURES: &[&str] = &["harness/src/results/plots.rs", "plot/src/plot"];
/// What a results folder derives from its runs for its readers besides the figures: the report
/// page, the OMPL log, `runs.parquet` and `progress.parquet`, what the figures, the report and
/// the log read (each configuration's counts and kept runs, the index of the progress traces,
/// temporary files), and the step that writes them once a folder's runs are all there (after sorting
/// its run files by `sort.rs`, of [`SWEEP`]; it records their counts and hashes in the
/// manifest, which only `merge`, `results verify` and `results plot` print), then the check of
/// the finished folder (`verify.rs`, `verify_rows.rs`: `bench` fails if it finds a problem,
/// and prints nothing otherwise). No table reads them (the tables read `runs.csv` and
/// `progress.csv`; a test checks) and no console line of a `bench` that succeeds shows them;
/// writing and checking them is part of a `bench` command's wall time. With them, the
/// merge of shard folders into one (`merge.rs`), which no sweep and no transcript runs. A
/// measurement that shows them, or runs `merge`, `results verify` or `results plot`, declares
/// this group.
const DERIVED: &[&str] = &[
    "harness/src/results/finalize.rs",
    "harness/src/results/merge.rs",
    "harness/src/results/report.rs",
    "harness/src/results/ompl",
    "harness/src/results/sample.rs",
    "store/src/merge.rs",
    "store/src/parquet.rs",
    "store/src/progress_parquet.rs",
    "store/src/temporary.rs",
    "store/src/traces.rs",
    "store/src/verify.rs",
    "store/src/verify_rows.rs",
];
/// The table of a suite's families.
const FAMILY_TABLES: &[&str] = &["xtask/src/docs/family_tables.rs", "suites/pair-100"];
/// The tracker comparison's table.
const TRACKER_TABLES: &[&str] = &["xtask/src/docs/tracker_tables.rs"];
/// The magbench commands a transcript runs (the whole harness), and how the transcript runs
/// them.
const CLI: &[&str] = &[
    "analysis/src",
    "plot/src",
    "store/src",
    "harness/src",
    "cli/src",
    "xtask/src/docs/transcript.rs",
    // the crates' module declarations and re-exports, which change nothing by themselves (a
    // test checks that the files hold nothing else)
    ":!analysis/src/lib.rs",
    ":!plot/src/lib.rs",
    ":!store/src/lib.rs",
    ":!harness/src/lib.rs",
    ":!cli/src/lib.rs",
    ":!harness/src/results/mod.rs",
    // a results folder's figures and derived files and the check that ends `bench` ([`FIGURES`],
    // [`DERIVED`]): no console line of a `bench` that succeeds depends on them (writing and
    // checking them is part of its wall time); and `merge`, which no transcript runs (a test
    // checks)
    ":!harness/src/results/merge.rs",
    ":!harness/src/results/finalize.rs",
    ":!harness/src/results/plots.rs",
    ":!harness/src/results/report.rs",
    ":!harness/src/results/ompl",
    ":!harness/src/results/sample.rs",
    ":!store/src/merge.rs",
    ":!store/src/parquet.rs",
    ":!store/src/progress_parquet.rs",
    ":!store/src/temporary.rs",
    ":!store/src/traces.rs",
    ":!store/src/verify.rs",
    ":!store/src/verify_rows.rs",
    // a replay page's data, packing and player (and the module's declarations): written into
    // pages, never printed
    ":!harness/src/replay/mod.rs",
    ":!harness/src/replay/data.rs",
    ":!harness/src/replay/pack.rs",
    ":!harness/src/replay/page.rs",
    ":!harness/src/replay/player.js",
    // `magbench scenario`: no transcript runs it (a test checks)
    ":!cli/src/cli/scenario.rs",
    // `magbench calibrate`: only the measurements that fit run it ([`FIT`])
    ":!cli/src/cli/calibrate.rs",
    ":!cli/src/cli/calibrate_plot.rs",
    // the calibration benchmark: only its own measurement runs it ([`CALIBRATION_BENCH`])
    ":!cli/src/cli/calibrate_bench",
    ":!cli/src/cli/calibrate_bench_plot.rs",
    // `magbench regress`: only the measurements that compare folders run it ([`REGRESS`])
    ":!harness/src/regress",
    ":!cli/src/cli/regress.rs",
];
/// `magbench calibrate bench`, which the `calibration-bench` transcript runs.
const CALIBRATION_BENCH: &[&str] = &[
    "cli/src/cli/calibrate_bench",
    "cli/src/cli/calibrate_bench_plot.rs",
];
/// The presets of the team-tracking diagnosis: the realistic preset without its agent
/// heterogeneity, and that heterogeneity alone.
const TEAM_PRESETS: &[&str] = &[
    "docs/presets/realistic-without-heterogeneity.toml",
    "docs/presets/heterogeneity-alone.toml",
];
/// `magbench regress`, its analysis, and the CI experiment it is sized for.
const REGRESS: &[&str] = &[
    "harness/src/regress",
    "cli/src/cli/regress.rs",
    "experiments/ci.toml",
];
/// The rig: drivers, emulator and the rig files; the calibration's fit is [`FIT`].
const RIG: &[&str] = &["drivers/src", "rigs", ":!drivers/src/fit"];
/// The ranges of the calibration benchmark in bulk with hydrodynamic interaction.
const BULK_HYDRO_RANGES: &[&str] = &["docs/calibration/bench-bulk-hydro.toml"];
/// The calibration's fit and `magbench calibrate` (its report and figure): only the
/// measurements that fit depend on them (a test checks every transcript that runs
/// `calibrate` and every test target that calls the fit).
const FIT: &[&str] = &[
    "drivers/src/fit",
    "cli/src/cli/calibrate.rs",
    "cli/src/cli/calibrate_plot.rs",
];
/// The Python binding: its Rust core and the package's own modules, which every script that
/// imports `magbench` runs (`mb.plan`'s argument handling, the results loader, the plugins).
const PYTHON: &[&str] = &["python/src", "python/magbench"];

/// The folder of a workspace crate, by its package name.
fn crate_dir(package: &str) -> &str {
    match package {
        "magbench" => "cli",
        "magbench-benches" => "benches",
        p => p.strip_prefix("magbench-").unwrap_or(p),
    }
}

/// Criterion's `--quick`: the `quick_args` of a criterion bench.
/// The files of the calibration walkthrough's emulated rig: the rig files, the scenarios, and
/// the truth and base presets.
const WALKTHROUGH_FILES: &[&str] = &[
    "rigs",
    "scenarios",
    "docs/calibration/truth.toml",
    "docs/calibration/base.toml",
];

/// The walkthrough's rig: the emulator serving the truth preset with its camera, in lockstep.
const WALKTHROUGH_EMULATOR: Step = Step::Background {
    command: "rig emulate --rig ../../rigs/emulator.toml open-field --lockstep \
              --preset truth.toml --preset-camera --write-rig live.toml --log emu.csv",
    ready: "live.toml",
};

const QUICK: &[&str] = &["--quick"];

/// Every measurement, in the order `cargo xtask measure` runs them.
pub static MEASURES: &[Measure] = &[
    Measure {
        name: "planners-success",
        source: Sweep {
            experiment: "experiments/planners-success.toml",
            quick_seeds: 4,
            table: Runs(planning),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "trackers-50",
        source: Sweep {
            experiment: "experiments/trackers-50.toml",
            quick_seeds: 3,
            table: Runs(tracking),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "trackers-mpc",
        source: Sweep {
            experiment: "experiments/trackers-mpc.toml",
            quick_seeds: 2,
            table: Runs(comparison),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP, TRACKER_TABLES],
    },
    Measure {
        name: "cargo-delivery",
        source: Sweep {
            experiment: "experiments/cargo-delivery.toml",
            quick_seeds: 2,
            table: Runs(tracking),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "seed-metric",
        source: Sweep {
            experiment: "experiments/seed-metric.toml",
            quick_seeds: 4,
            table: Runs(errors),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "fidelity-hardware",
        source: Sweep {
            experiment: "experiments/fidelity-hardware.toml",
            quick_seeds: 3,
            table: Runs(tracking),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "fidelity-short",
        source: Sweep {
            experiment: "experiments/fidelity-short.toml",
            quick_seeds: 4,
            table: Runs(tracking),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "trio-planning",
        source: Sweep {
            experiment: "experiments/trio-planning.toml",
            quick_seeds: 2,
            table: Runs(planning),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "trio-tracking",
        source: Sweep {
            experiment: "experiments/trio-tracking.toml",
            quick_seeds: 1,
            table: Runs(tracking),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "quad-tracking",
        source: Sweep {
            experiment: "experiments/quad-tracking.toml",
            quick_seeds: 2,
            table: Runs(tracking),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "trio-stall",
        source: Sweep {
            experiment: "experiments/trio-stall.toml",
            quick_seeds: 1,
            table: Runs(team_runs),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "trio-open-loop",
        source: Sweep {
            experiment: "experiments/trio-open-loop.toml",
            quick_seeds: 2,
            table: Runs(team_runs),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "team-stall",
        source: Test {
            package: "magbench",
            target: Target::Example("team_stall"),
            test: "",
            ignored: false,
            release: true,
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "extend",
        source: Sweep {
            experiment: "experiments/extend.toml",
            quick_seeds: 2,
            table: Runs(first_solution_work),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "trio-alpha-max",
        source: Sweep {
            experiment: "experiments/trio-alpha-max.toml",
            quick_seeds: 1,
            table: Runs(team_runs),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "team-elevation",
        source: Sweep {
            experiment: "experiments/team-elevation.toml",
            quick_seeds: 1,
            table: Runs(first_solution_work),
            figures: &[],
        },
        feature: Some("ompl"),
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "stlc-teams",
        source: Transcript {
            files: &[],
            cwd: ".",
            steps: &[
                Step::Run("stlc --agents 3"),
                Step::Run("stlc --agents 3 --r 2.5"),
                Step::Run("stlc --agents 4"),
                Step::Run("stlc --agents 4 --alpha-max 45"),
            ],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, CLI, CONTROLLABILITY],
    },
    Measure {
        name: "planners-convergence",
        source: Sweep {
            experiment: "experiments/planners-convergence.toml",
            quick_seeds: 2,
            table: Folder(convergence),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "informed",
        source: Sweep {
            experiment: "experiments/informed.toml",
            quick_seeds: 2,
            table: Folder(convergence),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "replan-latency",
        source: Sweep {
            experiment: "experiments/replan.toml",
            quick_seeds: 2,
            table: Outputs(replan_latency),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "replan-latency-team",
        source: Sweep {
            experiment: "experiments/replan-team.toml",
            quick_seeds: 1,
            table: Outputs(replan_latency),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "vs-ompl",
        source: Sweep {
            experiment: "experiments/vs-ompl.toml",
            quick_seeds: 2,
            table: Runs(first_solution),
            figures: &[],
        },
        feature: Some("ompl"),
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "ablation-obc",
        source: Sweep {
            experiment: "experiments/ablation-obc.toml",
            quick_seeds: 1,
            table: Runs(ablation),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "ablation-lookahead",
        source: Sweep {
            experiment: "experiments/ablation-lookahead.toml",
            quick_seeds: 1,
            table: Runs(ablation),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "ablation-open-loop",
        source: Sweep {
            experiment: "experiments/ablation-open-loop.toml",
            quick_seeds: 2,
            table: Runs(ablation),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "obc-grid",
        source: Sweep {
            experiment: "experiments/obc-grid.toml",
            quick_seeds: 2,
            table: Runs(loop_cost),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "trio-loop-cost",
        source: Sweep {
            experiment: "experiments/trio-tracking.toml",
            quick_seeds: 1,
            table: Runs(loop_cost),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "calibration-walkthrough",
        source: Transcript {
            files: WALKTHROUGH_FILES,
            cwd: "docs/calibration",
            steps: &[
                WALKTHROUGH_EMULATOR,
                Step::Run("rig excite --rig live.toml open-field --out exc --duration 60 --seed 2"),
                Step::Run("calibrate exc --scenario open-field --base base.toml --out fitted.toml"),
                Step::Run(
                    "track ../../scenarios/short-open.toml --tracker obc --preset fitted.toml",
                ),
                Step::Run(
                    "track ../../scenarios/short-open.toml --tracker obc --preset truth.toml",
                ),
                Step::Run("track ../../scenarios/short-open.toml --tracker obc --preset base.toml"),
            ],
        },
        feature: None,
        depends: &[PLANT, RIG, CLI, FIT],
    },
    Measure {
        name: "calibration-runs",
        source: Transcript {
            files: WALKTHROUGH_FILES,
            cwd: "docs/calibration",
            steps: &[
                WALKTHROUGH_EMULATOR,
                Step::Run(
                    "rig run --rig live.toml open-field --planner goal-zoom-rrt --tracker obc --seed 0 --out run0",
                ),
                Step::Run(
                    "rig run --rig live.toml open-field --planner goal-zoom-rrt --tracker obc --seed 1 --out run1",
                ),
                Step::Run(
                    "rig run --rig live.toml open-field --planner goal-zoom-rrt --tracker obc --seed 2 --out run2",
                ),
                Step::Run(
                    "rig run --rig live.toml open-field --planner goal-zoom-rrt --tracker obc --seed 3 --out run3",
                ),
                Step::Run(
                    "calibrate run0 run1 run2 run3 --scenario open-field --base base.toml --out from-runs.toml",
                ),
                Step::Run(
                    "track ../../scenarios/short-open.toml --tracker obc --preset from-runs.toml",
                ),
                Step::Run(
                    "rig run --rig-type simulated --rig truth.toml open-field --planner goal-zoom-rrt --tracker obc --seed 0 --out sim0",
                ),
                Step::Run(
                    "rig run --rig-type simulated --rig truth.toml open-field --planner goal-zoom-rrt --tracker obc --seed 1 --out sim1",
                ),
                Step::Run(
                    "rig run --rig-type simulated --rig truth.toml open-field --planner goal-zoom-rrt --tracker obc --seed 2 --out sim2",
                ),
                Step::Run(
                    "rig run --rig-type simulated --rig truth.toml open-field --planner goal-zoom-rrt --tracker obc --seed 3 --out sim3",
                ),
                Step::Run(
                    "calibrate sim0 sim1 sim2 sim3 --scenario open-field --base base.toml --out from-simulated-runs.toml",
                ),
            ],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, RIG, CLI, FIT],
    },
    Measure {
        name: "calibration-interface",
        source: Transcript {
            files: &["rigs", "scenarios", "docs/calibration/interface-truth.toml"],
            cwd: "docs/calibration",
            steps: &[
                Step::Background {
                    command: "rig emulate --rig ../../rigs/emulator.toml open-field --lockstep \
                              --preset interface-truth.toml --preset-camera --write-rig live.toml --log emu.csv",
                    ready: "live.toml",
                },
                Step::Run("rig excite --rig live.toml open-field --out exc --duration 90 --seed 2"),
                Step::Run("calibrate exc --scenario open-field --base hardware --out fitted.toml"),
            ],
        },
        feature: None,
        depends: &[PLANT, RIG, CLI, FIT],
    },
    Measure {
        name: "scaling",
        source: Transcript {
            files: &["experiments/scaling.toml"],
            cwd: ".",
            steps: &[
                Step::Run("bench experiments/scaling.toml --out scaling --threads 2 --quiet"),
                Step::Run("results scaling scaling --family serpentine --by walls"),
                Step::Run("results scaling scaling --family corridor --by length"),
                Step::Run("results scaling scaling --family team --by agents"),
            ],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, CLI, GENERATOR],
    },
    Measure {
        name: "pair-100-profile",
        source: Transcript {
            files: &["suites"],
            cwd: ".",
            steps: &[
                Step::Run("bench --suite pair-100 --out pair-100 --threads 2 --quiet --shard 1/2"),
                Step::Run("results profile pair-100"),
            ],
        },
        feature: Some("ompl"),
        depends: &[PLANT, PLANNING, TRACKING, CLI, GENERATOR],
    },
    Measure {
        name: "bench-threads",
        source: Transcript {
            files: &["experiments/ci.toml"],
            cwd: ".",
            steps: &[
                Step::Run("bench experiments/ci.toml --out t1 --threads 1 --quiet"),
                Step::Run("bench experiments/ci.toml --out t2 --threads 2 --quiet"),
            ],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, CLI],
    },
    Measure {
        name: "main-job",
        source: Transcript {
            files: &[],
            cwd: ".",
            steps: &[Step::Run("bench --out default --threads 2 --quiet")],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, CLI],
    },
    Measure {
        name: "fresh-clone",
        source: Test {
            package: "xtask",
            target: Target::Example("fresh_clone"),
            test: "",
            ignored: false,
            release: true,
        },
        feature: None,
        depends: &[BUILD, PLANT, PLANNING, TRACKING, CLI],
    },
    Measure {
        name: "replay-gif",
        source: Transcript {
            files: &[],
            cwd: ".",
            steps: &[
                Step::Run("track open-field --tracker obc --out plain"),
                Step::Run("track open-field --tracker obc --out gif --gif"),
            ],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, CLI],
    },
    Measure {
        name: "rig-latency",
        source: Transcript {
            files: &["rigs"],
            cwd: ".",
            steps: &[
                Step::Background {
                    command: "rig emulate --rig rigs/emulator.toml micro-factory \
                              --write-rig live.toml",
                    ready: "live.toml",
                },
                Step::Run("rig check --rig live.toml micro-factory --duration 30"),
                Step::Background {
                    command: "rig emulate --rig rigs/emulator.toml micro-factory --lockstep \
                              --write-rig lockstep.toml",
                    ready: "lockstep.toml",
                },
                Step::Run(
                    "rig run --rig lockstep.toml micro-factory --planner goal-zoom-rrt \
                     --tracker obc --out run1",
                ),
            ],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, RIG, CLI],
    },
    Measure {
        name: "bench-planning",
        source: Bench {
            bench: "planning",
            ids: &[
                "propagate/rk4/step",
                "propagate/rk4/period",
                "propagate/rk4/1s",
                "propagate/exact/period",
                "propagate/exact/1s",
                "propagate/exact/any",
                "path_length/exact/1s",
                "extend/default",
                "extend/k12/batch",
                "extend/k12/scalar",
                "nearest/10k",
                "motion_valid/rk4/1s",
                "motion_valid/exact/1s",
                "goal_zoom_rrt/micro_factory",
            ],
            args: &[],
            quick_args: QUICK,
        },
        feature: None,
        depends: &[PLANT, PLANNING],
    },
    Measure {
        name: "steering",
        source: Sweep {
            experiment: "experiments/steering.toml",
            quick_seeds: 2,
            table: Runs(first_solution),
            figures: &[],
        },
        feature: Some("ompl"),
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "shortcut",
        source: Sweep {
            experiment: "experiments/shortcut.toml",
            quick_seeds: 2,
            table: Runs(improvement),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "shortcut-budget",
        source: Sweep {
            experiment: "experiments/shortcut-budget.toml",
            quick_seeds: 2,
            table: Runs(improvement),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "trajopt",
        source: Sweep {
            experiment: "experiments/trajopt.toml",
            quick_seeds: 2,
            table: Runs(improvement),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "cost-at-time",
        source: Sweep {
            experiment: "experiments/cost-at-time.toml",
            quick_seeds: 2,
            table: Folder(cost_at_time),
            figures: &["cost-vs-time"],
        },
        feature: Some("ompl"),
        depends: &[PLANT, PLANNING, TRACKING, SWEEP, COST_AT_TIME, FIGURES],
    },
    Measure {
        name: "trajopt-pair-100",
        source: Sweep {
            experiment: "experiments/trajopt-pair-100.toml",
            quick_seeds: 1,
            table: Folder(by_family_at_times),
            figures: &[],
        },
        feature: Some("ompl"),
        depends: &[
            PLANT,
            PLANNING,
            TRACKING,
            SWEEP,
            FAMILY_TABLES,
            COST_AT_TIME,
        ],
    },
    Measure {
        name: "straighten-teams",
        source: Sweep {
            experiment: "experiments/straighten-teams.toml",
            quick_seeds: 2,
            table: Runs(improvement),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "shortcut-tracking",
        source: Sweep {
            experiment: "experiments/shortcut-tracking.toml",
            quick_seeds: 2,
            table: Runs(team_runs),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "shortcut-plans",
        source: Test {
            package: "magbench-planners",
            target: Target::Example("shortcut_plans"),
            test: "",
            ignored: false,
            release: true,
        },
        feature: None,
        depends: &[PLANT, PLANNING],
    },
    Measure {
        name: "chaos",
        source: Test {
            package: "magbench-planners",
            target: Target::Example("chaos"),
            test: "",
            ignored: false,
            release: true,
        },
        feature: None,
        depends: &[PLANT, PLANNING],
    },
    Measure {
        name: "regress-power",
        source: Test {
            package: "magbench",
            target: Target::Example("regress_power"),
            test: "",
            ignored: false,
            release: true,
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP, REGRESS],
    },
    Measure {
        name: "edge-length",
        source: Sweep {
            experiment: "experiments/edge-length.toml",
            quick_seeds: 2,
            table: Runs(edge_length),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP, EDGE_TABLES],
    },
    Measure {
        name: "guide",
        source: Sweep {
            experiment: "experiments/guide.toml",
            quick_seeds: 2,
            table: Runs(planning),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "aim",
        source: Sweep {
            experiment: "experiments/aim.toml",
            quick_seeds: 2,
            table: Runs(first_solution_work),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "sampling",
        source: Sweep {
            experiment: "experiments/sampling.toml",
            quick_seeds: 2,
            table: Runs(first_solution_work),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "aim-edge-length",
        source: Sweep {
            experiment: "experiments/aim-edge-length.toml",
            quick_seeds: 2,
            table: Runs(first_solution_work),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "aim-tracking",
        source: Sweep {
            experiment: "experiments/aim-tracking.toml",
            quick_seeds: 2,
            table: Runs(team_runs),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "team-scaling",
        source: Sweep {
            experiment: "experiments/team-scaling.toml",
            quick_seeds: 2,
            table: Runs(team_scaling),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP],
    },
    Measure {
        name: "team-sizes",
        source: Transcript {
            files: &["experiments/team-sizes.toml"],
            cwd: ".",
            steps: &[
                Step::Run("bench experiments/team-sizes.toml --out team-sizes --threads 2 --quiet"),
                Step::Run("results scaling team-sizes --family team --by agents"),
            ],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, CLI, GENERATOR],
    },
    Measure {
        name: "team-large",
        source: Transcript {
            files: &["experiments/team-large.toml"],
            cwd: ".",
            steps: &[
                Step::Run("bench experiments/team-large.toml --out team-large --threads 2 --quiet"),
                Step::Run("results scaling team-large --family team --by agents"),
            ],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, CLI, GENERATOR],
    },
    Measure {
        name: "team-edge",
        source: Transcript {
            files: &["experiments/team-edge.toml"],
            cwd: ".",
            steps: &[
                Step::Run("bench experiments/team-edge.toml --out team-edge --threads 2 --quiet"),
                Step::Run("results scaling team-edge --family team --by agents"),
            ],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, CLI, GENERATOR],
    },
    Measure {
        name: "team-proximity",
        source: Transcript {
            files: &["docs/teams"],
            cwd: ".",
            steps: &[
                Step::Run(
                    "plan docs/teams/ring-of-eight.toml --planner formation-rrt --max-iters 40000 --seed 0 --out eight",
                ),
                Step::Run(
                    "plan docs/teams/ring-of-ten.toml --planner formation-rrt --max-iters 40000 --seed 0 --out ten",
                ),
                Step::Run(
                    "plan docs/teams/ring-of-ten-r-max-8.toml --planner formation-rrt --max-iters 40000 --seed 0 --out ten-r-max-8",
                ),
                Step::Run(
                    "plan docs/teams/ring-of-ten-r-min-1.05.toml --planner formation-rrt --max-iters 40000 --seed 0 --out ten-r-min",
                ),
            ],
        },
        feature: None,
        depends: &[PLANT, PLANNING, CLI],
    },
    Measure {
        name: "formations",
        source: Transcript {
            files: &["experiments/formations.toml"],
            cwd: ".",
            steps: &[
                Step::Run("bench experiments/formations.toml --out formations --threads 2 --quiet"),
                Step::Run("results formations formations"),
            ],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, CLI, GENERATOR, CONTROLLABILITY],
    },
    Measure {
        name: "team-tracking",
        source: Sweep {
            experiment: "experiments/team-tracking.toml",
            quick_seeds: 2,
            table: Runs(tracking),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP, GENERATOR],
    },
    Measure {
        name: "team-heterogeneity",
        source: Sweep {
            experiment: "experiments/team-heterogeneity.toml",
            quick_seeds: 2,
            table: Runs(tracking),
            figures: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP, GENERATOR, TEAM_PRESETS],
    },
    Measure {
        name: "bench-team-flows",
        source: Bench {
            bench: "team_flows",
            ids: &[
                "trio_motion/pair-exact",
                "trio_motion/pair-adaptive",
                "trio_plan/pair-exact",
                "trio_plan/pair-adaptive",
            ],
            args: &[],
            quick_args: QUICK,
        },
        feature: None,
        depends: &[PLANT],
    },
    Measure {
        name: "adaptive-accuracy",
        source: Test {
            package: "magbench-env",
            target: Target::Test("adaptive_flow"),
            test: "adaptive_samples_match_a_fine_reference_within_the_tolerance",
            ignored: false,
            release: false,
        },
        feature: None,
        depends: &[PLANT],
    },
    Measure {
        name: "planner-figures",
        source: Bench {
            bench: "planner_figures",
            ids: &[],
            args: &[],
            quick_args: &["5"],
        },
        feature: None,
        depends: &[PLANT, PLANNING],
    },
    Measure {
        name: "bench-obc-tick",
        source: Bench {
            bench: "obc_tick",
            ids: &[
                "obc tick (micro-factory)",
                "lookahead tick (micro-factory)",
                "obc optimizer solve",
                "obc optimizer solve (three agents, planar)",
                "obc optimizer solve (three agents, elevated)",
                "formation tick (ten agents)",
                "obc tick (ten agents)",
                "lookahead tick (ten agents)",
                "mppi tick (micro-factory)",
                "mppi tick (ten agents)",
                "planning-model prediction (one frame)",
                "wall clearance (one agent)",
            ],
            args: &[],
            quick_args: QUICK,
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING],
    },
    Measure {
        name: "bench-ompl-abi",
        source: Bench {
            bench: "ompl_abi",
            ids: &["ompl_abi/direct", "ompl_abi/through_ompl"],
            args: &[],
            quick_args: QUICK,
        },
        feature: Some("ompl"),
        depends: &[PLANT, PLANNING],
    },
    Measure {
        name: "python-plugins",
        source: Python {
            script: "python/examples/run_bench.py",
            args: &["{work}"],
            quick_args: &[],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, SWEEP, PYTHON],
    },
    Measure {
        name: "scale",
        source: Python {
            script: "python/bench/scale.py",
            args: &["--runs", "10000", "100000", "1000000/100"],
            quick_args: &["--runs", "1000"],
        },
        feature: None,
        depends: &[CLI, REGRESS, FIGURES, DERIVED],
    },
    Measure {
        name: "scale-real",
        source: Python {
            script: "python/bench/scale.py",
            args: &["--real", "--runs", "10000", "--whole-up-to", "0"],
            quick_args: &["--real", "--runs", "400", "--whole-up-to", "0"],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, CLI, REGRESS, FIGURES, DERIVED],
    },
    Measure {
        name: "python-overhead",
        source: Python {
            script: "python/bench/overhead.py",
            args: &["--only", "calls"],
            quick_args: &["--quick"],
        },
        feature: None,
        depends: &[PLANT, PLANNING, PYTHON],
    },
    Measure {
        name: "python-rrt",
        source: Python {
            script: "python/bench/overhead.py",
            args: &["--only", "rrt"],
            quick_args: &["--quick"],
        },
        feature: None,
        depends: &[PLANT, PLANNING, PYTHON],
    },
    Measure {
        name: "sst-pruning",
        source: Test {
            package: "magbench-planners",
            target: Target::Lib,
            test: "ompl::tests::sst_node_counts",
            ignored: true,
            release: false,
        },
        feature: Some("ompl"),
        depends: &[PLANT],
    },
    Measure {
        name: "calibration-noise-bias",
        source: Test {
            package: "magbench-drivers",
            target: Target::Test("calibrate_noise_bias"),
            test: "free_start_states_remove_the_detection_noise_bias",
            ignored: true,
            release: false,
        },
        feature: None,
        depends: &[PLANT, RIG, FIT],
    },
    Measure {
        name: "calibration-draws",
        source: Test {
            package: "magbench-drivers",
            target: Target::Test("calibrate"),
            test: "calibrate_recovers_a_random_preset_from_an_excitation_run",
            ignored: true,
            release: false,
        },
        feature: None,
        depends: &[PLANT, RIG, FIT],
    },
    Measure {
        name: "calibration-emulator",
        source: Test {
            package: "magbench-drivers",
            target: Target::Test("calibrate_emulator"),
            test: "free_start_states_against_the_observed_starts_on_the_emulator",
            ignored: true,
            release: false,
        },
        feature: None,
        depends: &[PLANT, RIG, FIT],
    },
    Measure {
        name: "calibration-validation",
        source: Test {
            package: "magbench",
            target: Target::Test("calibrate"),
            test: "calibrate_recovers_presets_drawn_at_random_and_predicts_their_tracking_error",
            ignored: false,
            release: false,
        },
        feature: None,
        depends: &[PLANT, RIG, CLI, FIT],
    },
    Measure {
        name: "calibration-segments",
        source: Test {
            package: "magbench-drivers",
            target: Target::Test("calibrate_segments"),
            test: "segment_length_from_the_observed_starts_and_with_free_starts",
            ignored: true,
            release: false,
        },
        feature: None,
        depends: &[PLANT, RIG, FIT],
    },
    Measure {
        name: "calibration-bench",
        source: Transcript {
            files: &[],
            cwd: ".",
            steps: &[Step::Run("calibrate bench --out bench --threads 2")],
        },
        feature: None,
        depends: &[PLANT, RIG, PLANNING, TRACKING, CLI, CALIBRATION_BENCH, FIT],
    },
    Measure {
        name: "calibration-rig-7",
        source: Transcript {
            files: &[],
            cwd: ".",
            steps: &[
                // the first eight rigs of seed 0's draws (those of the default 20 as well)
                Step::Run("calibrate bench --rigs 8 --seed 0 --out bench --threads 2"),
                Step::Run(
                    "calibrate bench/rigs/rig-7/rig-log.csv --scenario open-field \
                     --base bench/rigs/rig-7/base.toml --out fit-80.toml",
                ),
                Step::Run(
                    "calibrate bench/rigs/rig-7/rig-log.csv --scenario open-field \
                     --base bench/rigs/rig-7/base.toml --out fit-60.toml --segment-frames 60",
                ),
                Step::Run(
                    "calibrate bench/rigs/rig-7/rig-log.csv --scenario open-field \
                     --base bench/rigs/rig-7/base.toml --out fit-60-6.toml --segment-frames 60 \
                     --max-latency 6",
                ),
            ],
        },
        feature: None,
        depends: &[PLANT, RIG, PLANNING, TRACKING, CLI, CALIBRATION_BENCH, FIT],
    },
    Measure {
        name: "calibration-bench-seed-1",
        source: Transcript {
            files: &[],
            cwd: ".",
            steps: &[Step::Run(
                "calibrate bench --out bench --threads 2 --seed 1",
            )],
        },
        feature: None,
        depends: &[PLANT, RIG, PLANNING, TRACKING, CLI, CALIBRATION_BENCH, FIT],
    },
    Measure {
        name: "calibration-bench-bulk-hydro",
        source: Transcript {
            files: &["docs/calibration/bench-bulk-hydro.toml"],
            cwd: "docs/calibration",
            steps: &[Step::Run(
                "calibrate bench --out bench --threads 2 --ranges bench-bulk-hydro.toml",
            )],
        },
        feature: None,
        depends: &[PLANT, RIG, PLANNING, TRACKING, CLI, CALIBRATION_BENCH, FIT],
    },
    Measure {
        name: "calibration-bench-segments",
        source: Test {
            package: "magbench",
            target: Target::Test("calibrate_bench_segments"),
            test: "segment_lengths_on_the_three_benchmarks",
            ignored: true,
            release: true,
        },
        feature: None,
        depends: &[
            PLANT,
            RIG,
            PLANNING,
            TRACKING,
            CLI,
            CALIBRATION_BENCH,
            FIT,
            BULK_HYDRO_RANGES,
        ],
    },
    Measure {
        name: "detector-accuracy",
        source: Test {
            package: "magbench-drivers",
            target: Target::Test("detector_accuracy"),
            test: "apart_nearly_touching_and_touching_within_a_quarter_pixel",
            ignored: false,
            release: false,
        },
        feature: None,
        depends: &[PLANT, RIG],
    },
    Measure {
        name: "detect-timing",
        source: Test {
            package: "magbench-drivers",
            target: Target::Example("detect_timing"),
            test: "",
            ignored: false,
            release: true,
        },
        feature: None,
        depends: &[PLANT, RIG],
    },
    Measure {
        name: "rig-redetect",
        source: Transcript {
            files: &["rigs"],
            cwd: ".",
            steps: &[
                Step::Background {
                    command: "rig emulate --rig rigs/emulator.toml micro-factory --lockstep \
                              --duration 10.1 --record rec --write-rig lockstep.toml",
                    ready: "lockstep.toml",
                },
                Step::Run("rig check --rig lockstep.toml micro-factory --duration 10"),
                Step::Run("rig redetect --rig rigs/emulator.toml rec --out detections.csv"),
            ],
        },
        feature: None,
        depends: &[PLANT, PLANNING, TRACKING, RIG, CLI],
    },
    Measure {
        name: "bench-plant-frame",
        source: Bench {
            bench: "plant_frame",
            ids: &[
                "plant frame/ideal",
                "plant frame/realistic",
                "plant frame/hardware",
            ],
            args: &[],
            quick_args: QUICK,
        },
        feature: None,
        depends: &[PLANT, TRACKING],
    },
    Measure {
        name: "pixel-quantisation",
        source: Test {
            package: "magbench-env",
            target: Target::Example("pixel_quantisation"),
            test: "",
            ignored: false,
            release: false,
        },
        feature: None,
        depends: &[PLANT],
    },
];

/// The measurement called `name`.
pub fn find(name: &str) -> Option<&'static Measure> {
    MEASURES.iter().find(|m| m.name == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn named_files_are_left_out_of_their_group_and_name_registered_components() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        for group in [PLANNING, TRACKING] {
            let excluded: Vec<&str> = group.iter().filter_map(|s| s.strip_prefix(":!")).collect();
            let files: Vec<&str> = NAMED_FILES
                .iter()
                .filter(|(g, _, _)| *g == group)
                .map(|(_, _, f)| *f)
                .collect();
            assert_eq!(excluded, files);
        }
        let planners = magbench_planners::planners::builtins();
        let trackers = magbench_trackers::trackers::builtins();
        for (group, name, file) in NAMED_FILES {
            assert!(root.join(file).exists(), "{file}");
            let known = if *group == PLANNING {
                planners.iter().any(|e| e.name() == *name)
            } else {
                trackers.iter().any(|e| e.name() == *name)
            };
            assert!(known, "{name}");
        }
    }

    #[test]
    fn a_sweep_depends_on_the_files_of_the_components_its_experiment_names() {
        let dir = tempfile::tempdir().unwrap();
        let sweep = |experiment: &'static str, depends| Measure {
            name: "m",
            source: Sweep {
                experiment,
                quick_seeds: 1,
                table: Runs(planning),
                figures: &[],
            },
            feature: None,
            depends,
        };
        std::fs::write(
            dir.path().join("a.toml"),
            "planners = [\"goal-zoom-rrt{trajopt=5}\", \"informed-rrt-star\"]",
        )
        .unwrap();
        let m = sweep("a.toml", &[PLANT, PLANNING]);
        assert_eq!(
            m.named_files(dir.path()),
            vec![
                "planners/src/planners/rrt_star",
                "planners/src/planners/trajopt.rs",
                "planners/src/trajopt"
            ]
        );
        // an experiment that cannot be read depends on all of its groups' files; a sweep that
        // declares neither group, on none
        assert_eq!(
            sweep("missing.toml", &[PLANNING, TRACKING]).named_files(dir.path()),
            NAMED_FILES.iter().map(|(_, _, f)| *f).collect::<Vec<_>>()
        );
        assert!(sweep("a.toml", &[PLANT]).named_files(dir.path()).is_empty());
        // a tracker named in a sweep that plans only
        std::fs::write(
            dir.path().join("b.toml"),
            "trackers = [\"mppi{horizon=8}\"]",
        )
        .unwrap();
        assert_eq!(
            sweep("b.toml", &[PLANNING, TRACKING]).named_files(dir.path()),
            vec!["trackers/src/trackers/mppi.rs"]
        );
        let team_sizes = MEASURES.iter().find(|m| m.name == "team-sizes").unwrap();
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        assert!(
            team_sizes
                .named_files(&root)
                .contains(&"planners/src/planners/formation_rrt.rs")
        );
    }

    #[test]
    fn a_transcript_test_or_script_depends_on_the_files_of_the_components_it_names() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path();
        std::fs::create_dir_all(root.join("x/tests/common")).unwrap();
        std::fs::create_dir_all(root.join("py")).unwrap();
        std::fs::write(root.join("e.toml"), "trackers = [\"formation\"]").unwrap();
        std::fs::write(root.join("x/tests/t.rs"), "create(\"goal-zoom-rrt\")").unwrap();
        std::fs::write(root.join("x/tests/common/mod.rs"), "create(\"sst\")").unwrap();
        std::fs::write(root.join("py/main.py"), "import helper").unwrap();
        std::fs::write(root.join("py/helper.py"), "mb.plan(sc, \"trajopt\")").unwrap();
        let measure = |source| Measure {
            name: "m",
            source,
            feature: None,
            depends: &[PLANNING, TRACKING],
        };
        let transcript = measure(Transcript {
            files: &["e.toml"],
            cwd: ".",
            steps: &[Step::Run("plan open-field --planner rrt-star")],
        });
        assert_eq!(
            transcript.named_files(root),
            vec![
                "planners/src/planners/rrt_star",
                "trackers/src/trackers/formation.rs"
            ]
        );
        // a test's common module counts, and a test that cannot be read may run anything
        let test = |target| {
            measure(Test {
                package: "x",
                target,
                test: "",
                release: false,
                ignored: false,
            })
        };
        assert_eq!(
            test(Target::Test("t")).named_files(root),
            vec!["planners/src/planners/sst.rs"]
        );
        let every: Vec<&str> = NAMED_FILES.iter().map(|(_, _, f)| *f).collect();
        assert_eq!(test(Target::Test("missing")).named_files(root), every);
        assert_eq!(test(Target::Lib).named_files(root), every);
        // a script's sibling modules count
        let script = measure(Python {
            script: "py/main.py",
            args: &[],
            quick_args: &[],
        });
        assert_eq!(
            script.named_files(root),
            vec!["planners/src/planners/trajopt.rs", "planners/src/trajopt"]
        );
    }

    #[test]
    fn no_measurement_takes_its_components_from_a_registry_listing() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        for m in MEASURES {
            let Some(text) = m.run_text(&root) else {
                continue;
            };
            for listing in [".list()", "list_registry", "builtins()", "--list"] {
                assert!(!text.contains(listing), "{}: {listing}", m.name);
            }
        }
        let calibration = find("calibration-bench").unwrap();
        assert!(calibration.named_files(&root).is_empty());
    }

    /// Whether `m` is a transcript with a step that runs `magbench COMMAND`.
    fn transcript_runs(m: &Measure, command: &str) -> bool {
        match &m.source {
            Transcript { steps, .. } => steps.iter().any(|step| {
                let (Step::Run(c) | Step::Background { command: c, .. }) = step;
                c.starts_with(command)
            }),
            _ => false,
        }
    }

    /// Whether `m` runs the magbench command `command` (its first words): in a transcript's
    /// step, or in an argument list of its script (`["results", "verify", …`).
    fn runs_command(m: &Measure, command: &str) -> bool {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let listed = format!("[\"{}\"", command.replace(' ', "\", \""));
        transcript_runs(m, command)
            || matches!(&m.source, Python { script, .. } if std::fs::read_to_string(root.join(script))
                .is_ok_and(|t| t.contains(&listed)))
    }

    #[test]
    fn no_transcript_runs_the_scenario_command_that_cli_leaves_out() {
        for m in MEASURES {
            assert!(!transcript_runs(m, "scenario"), "{}", m.name);
        }
    }

    /// CLI leaves `magbench regress` out: a transcript or a script that runs it depends on
    /// [`REGRESS`].
    #[test]
    fn every_measurement_that_runs_regress_depends_on_it() {
        let mut running = 0;
        for m in MEASURES {
            if runs_command(m, "regress") {
                running += 1;
                assert!(m.depends.contains(&REGRESS), "{} runs regress", m.name);
            }
        }
        assert_eq!(running, 2);
    }

    #[test]
    fn every_measurement_that_fits_depends_on_the_fit() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let mut fitting = 0;
        for m in MEASURES {
            let fits = match &m.source {
                Transcript { .. } => transcript_runs(m, "calibrate"),
                Test { .. } => m.own_files().iter().any(|f| {
                    std::fs::read_to_string(root.join(f)).is_ok_and(|t| {
                        ["fit::", "calibrate(", "\"calibrate\""]
                            .iter()
                            .any(|call| t.contains(call))
                    })
                }),
                _ => false,
            };
            if fits {
                fitting += 1;
                assert!(m.depends.contains(&FIT), "{} fits", m.name);
            }
        }
        assert_eq!(fitting, 13);
    }

    #[test]
    fn the_derived_files_are_left_out_of_the_sweep_and_the_command_line_and_no_table_reads_them() {
        // the results folder's own files of both groups (FIGURES also holds the plot crate)
        let results_files = FIGURES
            .iter()
            .filter(|f| f.starts_with("harness/src/results"));
        for file in DERIVED.iter().chain(results_files) {
            let excluded = format!(":!{file}");
            for (name, group) in [("SWEEP", SWEEP), ("CLI", CLI)] {
                assert!(group.contains(&excluded.as_str()), "{file} is in {name}");
            }
        }
        // what a table module would name to read a derived file (the figures' file names are
        // read by the measurements that show figures, which declare FIGURES)
        let modules = ["report", "ompl", "parquet", "progress_parquet", "traces"];
        let files = [
            "report.html",
            "ompl.log",
            "runs.parquet",
            "progress.parquet",
        ];
        let docs = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/docs");
        for e in std::fs::read_dir(&docs).unwrap() {
            let path = e.unwrap().path();
            let text = std::fs::read_to_string(&path).unwrap();
            let code = text.split("#[cfg(test)]").next().unwrap_or_default();
            for line in code.lines().filter(|l| !l.trim_start().starts_with("//")) {
                let module = modules.iter().find(|m| {
                    line.contains(&format!("results::{m}"))
                        || (line.contains("results::{") && line.contains(*m))
                });
                let file = files.iter().find(|f| line.contains(*f));
                assert!(
                    module.is_none() && file.is_none(),
                    "{}: {line}",
                    path.display()
                );
            }
        }
    }

    #[test]
    fn a_measurement_that_prints_what_finalizing_records_declares_the_derived_files() {
        // `merge`, `results verify` and `results plot` print the counts and hashes that
        // finalize.rs records
        let commands = ["merge", "results verify", "results plot"];
        let mut printing = vec![];
        for m in MEASURES {
            if commands.iter().any(|c| runs_command(m, c)) {
                assert!(m.depends.contains(&DERIVED), "{}", m.name);
                printing.push(m.name);
            }
        }
        assert_eq!(printing, ["scale", "scale-real"]);
    }

    #[test]
    fn the_lib_rs_files_left_out_hold_only_declarations() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        for file in [
            "env/src/lib.rs",
            "analysis/src/lib.rs",
            "plot/src/lib.rs",
            "store/src/lib.rs",
            "harness/src/lib.rs",
            "cli/src/lib.rs",
            "harness/src/results/mod.rs",
        ] {
            let excluded = format!(":!{file}");
            assert!(
                [PLANT, CLI].iter().any(|g| g.contains(&excluded.as_str())),
                "{file} is not left out"
            );
            if file.starts_with("harness/src/results") || file.starts_with("store/") {
                assert!(SWEEP.contains(&excluded.as_str()), "{file} is in SWEEP");
            }
            let text = std::fs::read_to_string(root.join(file)).unwrap();
            for line in text.lines().map(str::trim) {
                let declaration = ["//", "#![", "mod ", "pub mod ", "pub use "]
                    .iter()
                    .any(|p| line.starts_with(p));
                assert!(line.is_empty() || declaration, "{file}: {line}");
            }
        }
    }

    #[test]
    fn names_are_unique_and_sources_exist() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        for (i, m) in MEASURES.iter().enumerate() {
            match m.source {
                Sweep {
                    experiment,
                    quick_seeds,
                    ..
                } => {
                    assert!(root.join(experiment).is_file(), "{experiment}");
                    assert!(quick_seeds > 0, "{}", m.name);
                }
                Bench { bench, .. } => {
                    let file = root.join(format!("benches/benches/{bench}.rs"));
                    assert!(file.is_file(), "{}", file.display());
                }
                Test {
                    package,
                    target,
                    test,
                    ..
                } => {
                    let dir = match package {
                        "magbench" => "cli".to_string(),
                        p => p.trim_start_matches("magbench-").to_string(),
                    };
                    let file = match target {
                        Target::Lib => format!("{dir}/src/lib.rs"),
                        Target::Test(f) => format!("{dir}/tests/{f}.rs"),
                        Target::Example(e) => format!("{dir}/examples/{e}.rs"),
                    };
                    assert!(root.join(&file).is_file(), "{}: {file}", m.name);
                    assert_eq!(test.is_empty(), matches!(target, Target::Example(_)));
                }
                Python { script, .. } => {
                    assert!(root.join(script).is_file(), "{}: {script}", m.name);
                }
                Transcript { files, steps, .. } => {
                    for f in files {
                        assert!(root.join(f).exists(), "{}: {f}", m.name);
                    }
                    assert!(!steps.is_empty(), "{}", m.name);
                }
            }
            assert!(
                MEASURES[..i].iter().all(|o| o.name != m.name),
                "{} twice",
                m.name
            );
        }
        assert!(find("seed-metric").is_some() && find("nope").is_none());
        assert!(find("seed-metric").unwrap().available());
        assert_eq!(find("vs-ompl").unwrap().available(), cfg!(feature = "ompl"));
        assert_eq!(
            find("bench-ompl-abi").unwrap().available(),
            cfg!(feature = "ompl")
        );
        assert!(find("bench-ompl-abi").unwrap().runnable());
        assert!(!find("vs-ompl").unwrap().runnable() || cfg!(feature = "ompl"));
        assert_eq!(find("bench-ompl-abi").unwrap().experiment(), None);
    }
}
