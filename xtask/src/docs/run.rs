//! Running one measurement: its experiment's sweep, its bench, its cargo test, its Python
//! script or its transcript, then its table under a [`Header`].

use std::path::Path;
use std::time::Instant;

use super::bench::{BenchRun, cargo_args, run_bench};
use super::cargo::MagbenchBinary;
use super::cargo_test::{TestRun, run_test};
use super::header::{Header, parse};
use super::measures::{Kind, Measure, Source};
use super::python::{PythonRun, interpreter_program, probe, run_python};
use super::transcript::{format_transcript, run_transcript};
use magbench::Error;
use magbench::experiment::Experiment;
use magbench::results::manifest::{git_revision_outside, host, now};
use magbench::results::plots::slug;
use magbench::results::store::read_runs;
use magbench::run::{Executor, RunOutput, Status, execute_caught};
use magbench::sweep::{ProgressMode, SweepOptions, run_sweep};

/// How a measurement runs.
#[derive(Debug, Clone)]
pub struct RunOptions<'a> {
    /// The repository root (experiments are read relative to it).
    pub root: &'a Path,
    /// Folder for the sweeps' results (`NAME/` in it is replaced).
    pub work: &'a Path,
    /// Folder the measured files are written to: a sweep's figures go to `NAME/` in it
    /// (replaced).
    pub out: &'a Path,
    /// Keep only the measurement's `quick_seeds` seeds.
    pub quick: bool,
    /// Worker threads.
    pub threads: usize,
    /// Progress display of the sweep.
    pub progress: ProgressMode,
    /// The `magbench` binary that transcripts and Python scripts run.
    pub magbench: &'a MagbenchBinary,
}

/// The load average over 1, 5 and 15 minutes from `/proc/loadavg` ("unknown" elsewhere).
pub fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .map(|t| t.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "unknown".into())
}

/// This binary's build, as the header names it.
fn build() -> &'static str {
    if cfg!(debug_assertions) {
        "dev (debug assertions on)"
    } else {
        "release"
    }
}

/// Runs measurement `m` with executor `ex` and returns the text of `docs/measured/NAME.md`.
pub fn measure(m: &Measure, ex: &dyn Executor, o: &RunOptions) -> Result<String, Error> {
    let load = load_average();
    let (runs, body) = match m.source {
        Source::Sweep {
            experiment,
            quick_seeds,
            table,
            figures,
        } => run_sweep_measure(m, experiment, (quick_seeds, table, figures), ex, o)?,
        Source::Bench {
            bench,
            ids,
            args,
            quick_args,
        } => {
            let args = if o.quick { quick_args } else { args };
            run_bench_measure(m, bench, ids, args, o)?
        }
        Source::Test {
            package,
            target,
            test,
            ignored,
            release,
        } => {
            let r = TestRun {
                package,
                target,
                test,
                ignored,
                release,
                feature: m.feature,
                root: o.root,
                echo: !matches!(o.progress, ProgressMode::Quiet),
            };
            run_test_measure(&r)?
        }
        Source::Python {
            script,
            args,
            quick_args,
        } => run_python_measure(m, script, args, quick_args, o)?,
        Source::Transcript { files, cwd, steps } => {
            let echo = !matches!(o.progress, ProgressMode::Quiet);
            let magbench = o
                .magbench
                .path(o.root, echo)
                .map_err(|e| Error::Failed(format!("{}: {e}", m.name)))?;
            let t0 = Instant::now();
            let entries = run_transcript(o.root, magbench, files, cwd, steps)
                .map_err(|e| Error::Failed(format!("{}: {e}", m.name)))?;
            let runs = format!(
                "{} magbench commands in a temporary folder, in {:.0} s, release build",
                steps.len(),
                t0.elapsed().as_secs_f64(),
            );
            (runs, format_transcript(&entries))
        }
    };
    let h = host();
    let header = Header {
        command: format!(
            "cargo xtask measure --only {}{}{}",
            m.name,
            if o.quick { " --quick" } else { "" },
            match (m.source, m.feature) {
                // the sources this binary runs itself; cargo is given the feature
                (Source::Sweep { .. } | Source::Transcript { .. }, Some(f)) => {
                    format!(" (a build with --features {f})")
                }
                _ => String::new(),
            }
        ),
        runs,
        machine: format!("{}, {} logical cores", h.cpu_model, h.cpus),
        load: format!("{load} (1, 5, 15 min) at the start; the machine may be shared"),
        date: now(),
        version: format!(
            "{} (git {})",
            env!("CARGO_PKG_VERSION"),
            git_revision_outside(&["docs/measured"])
        ),
    };
    let text = format!("{}\n{}", header.render(), body);
    parse(&text).map_err(|err| Error::Failed(format!("{}: generated file: {err}", m.name)))?;
    Ok(text)
}

/// Runs the bench of bench measurement `m` with `args`; returns the header's `runs` line and
/// the file's body.
fn run_bench_measure(
    m: &Measure,
    bench: &str,
    ids: &[&str],
    args: &[&str],
    o: &RunOptions,
) -> Result<(String, String), Error> {
    let t0 = Instant::now();
    let r = BenchRun {
        bench,
        feature: m.feature,
        args,
        ids,
        root: o.root,
        criterion_home: o.work.join(m.name).join("criterion"),
        echo: !matches!(o.progress, ProgressMode::Quiet),
    };
    let body = run_bench(&r)?;
    let runs = format!(
        "`cargo {}` from the repository root, in {:.0} s (bench profile: release){}",
        cargo_args(&r).join(" "),
        t0.elapsed().as_secs_f64(),
        if o.quick {
            "; `--quick`: a check that it runs, not figures"
        } else {
            ""
        }
    );
    Ok((runs, body))
}

/// Runs the cargo test or example `r`; returns the header's `runs` line and the file's body.
fn run_test_measure(r: &TestRun) -> Result<(String, String), Error> {
    let t0 = Instant::now();
    let body = run_test(r)?;
    let build = match r.release {
        true => "release build: figures of time",
        false => "debug build (the dev profile): its figures do not depend on speed",
    };
    let runs = format!(
        "`cargo {}` from the repository root, in {:.0} s ({build}); `--quick` runs it in full",
        super::cargo_test::cargo_args(r).join(" "),
        t0.elapsed().as_secs_f64(),
    );
    Ok((runs, body))
}

/// Runs the Python script of measurement `m` with `args` (and `quick_args` under `--quick`),
/// `{work}` in them replaced by its emptied folder in `--work`; returns the header's `runs`
/// line and the file's body.
fn run_python_measure(
    m: &Measure,
    script: &str,
    args: &[&str],
    quick_args: &[&str],
    o: &RunOptions,
) -> Result<(String, String), Error> {
    let interpreter = probe(&interpreter_program(), o.root)?;
    let dir = o.work.join(m.name);
    if args.iter().any(|a| a.contains("{work}")) {
        if dir.exists() {
            std::fs::remove_dir_all(&dir)?;
        }
        magbench::output::prepare_dir(&dir, "--work")?;
    }
    let shown = dir
        .strip_prefix(o.root)
        .unwrap_or(&dir)
        .display()
        .to_string();
    let extra = if o.quick { quick_args } else { &[] };
    let with = |work: &str| -> Vec<String> {
        args.iter()
            .chain(extra)
            .map(|a| a.replace("{work}", work))
            .collect()
    };
    let echo = !matches!(o.progress, ProgressMode::Quiet);
    let magbench = o
        .magbench
        .path(o.root, echo)
        .map_err(|e| Error::Failed(format!("{}: {e}", m.name)))?;
    let mut r = PythonRun {
        script,
        args: with(&dir.display().to_string()),
        root: o.root,
        echo,
        magbench: Some(magbench),
    };
    let t0 = Instant::now();
    let body = run_python(&interpreter, &r)?;
    let secs = t0.elapsed().as_secs_f64();
    r.args = with(&shown);
    let quick = match (o.quick, quick_args) {
        (false, _) => String::new(),
        (true, []) => "; `--quick` runs it in full".into(),
        (true, _) => "; `--quick`: a check that it runs, not figures".into(),
    };
    let runs = format!(
        "`{}` from the repository root, in {secs:.0} s; {}{quick}",
        r.command_line(),
        interpreter.describe()
    );
    Ok((runs, body))
}

/// Runs the experiment of sweep measurement `m`; returns the header's `runs` line and the
/// table, followed by its figures (copied by [`copy_figures`]).
fn run_sweep_measure(
    m: &Measure,
    experiment: &str,
    (quick_seeds, kind, figures): (usize, Kind, &[&str]),
    ex: &dyn Executor,
    o: &RunOptions,
) -> Result<(String, String), Error> {
    let mut e = Experiment::load(&o.root.join(experiment), ex)?;
    let all = e.seeds.len();
    if o.quick {
        e.seeds.truncate(quick_seeds);
    }
    let dir = o.work.join(m.name);
    if dir.exists() {
        std::fs::remove_dir_all(&dir)?;
    }
    magbench::output::prepare_dir(&dir, "--work")?;
    let t0 = Instant::now();
    let (count, table, scenarios) = match kind {
        Kind::Runs(f) => {
            let runs = sweep(m, &e, ex, o, &dir)?;
            (runs.len(), f(&runs), scenarios_of(&runs))
        }
        Kind::Folder(f) => {
            let runs = sweep(m, &e, ex, o, &dir)?;
            (runs.len(), f(&dir, &runs)?, scenarios_of(&runs))
        }
        Kind::Outputs(f) => {
            let outs = run_each(m, &e, ex, o.threads)?;
            (outs.len(), f(&outs), vec![])
        }
    };
    let shown = copy_figures(m.name, &dir, &scenarios, figures, o.out)?;
    let secs = t0.elapsed().as_secs_f64();
    let seeds = match o.quick {
        true => format!("the first {} of its {all} seeds (`--quick`)", e.seeds.len()),
        false => format!("{all} seeds"),
    };
    let runs = format!(
        "`{experiment}`, {seeds}: {count} runs in {secs:.0} s on {} threads, {} build",
        o.threads,
        build()
    );
    Ok((runs, format!("{}{shown}", table.markdown())))
}

/// The scenarios of `runs` as their plot folders are named, in the order they first appear.
fn scenarios_of(runs: &[magbench::run::RunRecord]) -> Vec<String> {
    let mut v: Vec<String> = Vec::new();
    for r in runs {
        let s = slug(&r.scenario);
        if !v.contains(&s) {
            v.push(s);
        }
    }
    v
}

/// Copies figure `STEM` of every scenario of the results folder `dir`
/// (`plots/SCENARIO/STEM.svg`) to `out/NAME/SCENARIO-STEM.svg` (that folder replaced) and
/// returns the Markdown that shows them, one image per line (paths relative to `docs/`, where
/// the chapters that include the file are); nothing without `figures`. A figure missing from
/// the folder is an error.
fn copy_figures(
    name: &str,
    dir: &Path,
    scenarios: &[String],
    figures: &[&str],
    out: &Path,
) -> Result<String, Error> {
    if figures.is_empty() {
        return Ok(String::new());
    }
    let to = out.join(name);
    if to.exists() {
        std::fs::remove_dir_all(&to)?;
    }
    std::fs::create_dir_all(&to)?;
    let mut md = String::from("\n");
    for sc in scenarios {
        for stem in figures {
            let from = dir.join("plots").join(sc).join(format!("{stem}.svg"));
            if !from.is_file() {
                return Err(Error::Failed(format!(
                    "{name}: figure {} was not drawn",
                    from.display()
                )));
            }
            let file = format!("{sc}-{stem}.svg");
            std::fs::copy(&from, to.join(&file))?;
            md.push_str(&format!("\n![{sc}: {stem}](measured/{name}/{file})\n"));
        }
    }
    Ok(md)
}

/// Sweeps experiment `e` of `m` into `dir` and returns its runs; a crashed run is an error.
fn sweep(
    m: &Measure,
    e: &Experiment,
    ex: &dyn Executor,
    o: &RunOptions,
    dir: &Path,
) -> Result<Vec<magbench::run::RunRecord>, Error> {
    let opts = SweepOptions {
        out: dir.to_path_buf(),
        threads: o.threads,
        shard: None,
        resume: false,
        progress: o.progress,
    };
    let s = run_sweep(e, ex, &opts)?;
    if s.failed > 0 {
        return Err(Error::Failed(format!(
            "{}: {} runs crashed: see the `error` column of {}",
            m.name,
            s.failed,
            dir.join("runs.csv").display()
        )));
    }
    Ok(read_runs(dir)?)
}

/// Runs every run of experiment `e` of `m` on `threads` threads and keeps each whole output,
/// in run order; a crashed run is an error naming it.
fn run_each(
    m: &Measure,
    e: &Experiment,
    ex: &dyn Executor,
    threads: usize,
) -> Result<Vec<RunOutput>, Error> {
    use rayon::prelude::*;
    let specs = e.runs();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|err| Error::Failed(format!("{}: thread pool: {err}", m.name)))?;
    let outs: Vec<RunOutput> = pool.install(|| {
        specs
            .par_iter()
            .map(|spec| execute_caught(ex, spec))
            .collect()
    });
    if let Some(c) = outs.iter().find(|o| o.record.status == Status::Crash) {
        return Err(Error::Failed(format!(
            "{}: run {} crashed: {}",
            m.name, c.record.run_id, c.record.error
        )));
    }
    Ok(outs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sweeps_figures_are_copied_beside_its_file_and_shown_under_the_table() {
        let tmp = tempfile::tempdir().unwrap();
        let (dir, out) = (tmp.path().join("sweep"), tmp.path().join("measured"));
        for sc in ["open-field", "micro-factory"] {
            let plots = dir.join("plots").join(sc);
            std::fs::create_dir_all(&plots).unwrap();
            std::fs::write(plots.join("cost-vs-time.svg"), format!("<svg>{sc}</svg>")).unwrap();
        }
        let scenarios = ["micro-factory".to_string(), "open-field".to_string()];
        std::fs::create_dir_all(out.join("m")).unwrap();
        std::fs::write(out.join("m/old.svg"), "stale").unwrap();
        let md = copy_figures("m", &dir, &scenarios, &["cost-vs-time"], &out).unwrap();
        assert_eq!(
            md,
            "\n\n![micro-factory: cost-vs-time](measured/m/micro-factory-cost-vs-time.svg)\n\
             \n![open-field: cost-vs-time](measured/m/open-field-cost-vs-time.svg)\n"
        );
        let copied = std::fs::read_to_string(out.join("m/open-field-cost-vs-time.svg")).unwrap();
        assert_eq!(copied, "<svg>open-field</svg>");
        assert!(!out.join("m/old.svg").exists(), "the folder is replaced");
        // none asked: nothing copied, nothing shown
        assert_eq!(copy_figures("n", &dir, &scenarios, &[], &out).unwrap(), "");
        assert!(!out.join("n").exists());
        // a figure the sweep did not draw is an error naming it
        let err = copy_figures("m", &dir, &scenarios, &["cost-vs-nothing"], &out).unwrap_err();
        assert!(err.to_string().contains("cost-vs-nothing.svg"), "{err}");
    }
}
