//! `magbench ablate`: a tracker under a preset with each term switched off in turn and each
//! term alone ([`crate::ablation`]); a table and a bar plot of each term's contribution.
//!
//! The command writes an ordinary experiment into its folder — `presets/*.toml` (one file per
//! variant) and `ablation.toml` over them — and runs it like `magbench bench` (runs.csv,
//! report.html, plots; `--resume` completes an interrupted ablation), then adds
//! `ablation.csv`, `variants.csv` and `ablation.svg`/`.png`.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args;
use magbench_drivers::rigs::preset_named;

use super::number::count;
use crate::Error;
use crate::ablation::{TermRow, contributions, label, terms_on, variant_medians, variants};
use crate::experiment::{Experiment, SEED_COUNT};
use crate::output::{outln, prepare_dir};
use crate::plot::bars::BarChart;
use crate::plot::charts::Series;
use crate::registry::Registry;
use crate::results::store::read_runs;
use crate::run::real::RealExecutor;
use crate::run::spec::ITERATIONS;
use crate::sweep::{ProgressMode, SweepOptions, run_sweep};

/// Arguments of `magbench ablate`.
#[derive(Debug, Args)]
pub struct AblateArgs {
    /// A built-in scenario name or a scenario file.
    #[arg(default_value = "micro-factory")]
    pub scenario: String,
    /// The base preset: a built-in name or a preset file.
    #[arg(long, default_value = "hardware")]
    pub preset: String,
    /// The planner that makes the plans.
    #[arg(long, default_value = "goal-zoom-rrt")]
    pub planner: String,
    /// The tracker, as an experiment names it (e.g. `obc`).
    #[arg(long, default_value = "obc")]
    pub tracker: String,
    /// Seeds per variant (0 … N−1).
    #[arg(long, default_value_t = 20)]
    pub seeds: u64,
    /// Planner iteration limit of every planning call.
    #[arg(long, default_value_t = 20_000)]
    pub max_iters: u64,
    /// Results folder (default results/ablate-<preset>-<tracker>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Worker threads (default: all CPUs).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Complete an interrupted ablation in --out.
    #[arg(long)]
    pub resume: bool,
    /// Which runs get a replay page: all, failed, sample:N, failed+sample:N or none (default
    /// failed+sample:30; docs/replay.md).
    #[arg(long, value_name = "POLICY")]
    pub replays: Option<String>,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
}

/// Runs `magbench ablate` with the planners and trackers of `registry`.
pub fn run(a: AblateArgs, registry: &Registry) -> Result<(), Error> {
    let base = preset_named(&a.preset, "--preset")?;
    let replays = a
        .replays
        .as_deref()
        .map(super::bench::replay_policy)
        .transpose()?;
    count("--seeds", &SEED_COUNT, a.seeds)?;
    count("--max-iters", &ITERATIONS, a.max_iters)?;
    let terms = terms_on(&base);
    if terms.is_empty() {
        return Err(Error::arg(
            "--preset",
            format!("{}: no term is on: nothing to ablate", a.preset),
        ));
    }
    let threads = super::number::threads(a.threads)?;
    let name = format!(
        "ablate-{}-{}",
        base.name.replace(|c: char| !c.is_ascii_alphanumeric(), "-"),
        a.tracker.replace(|c: char| !c.is_ascii_alphanumeric(), "-")
    );
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("results").join(&name));
    // a folder this command makes is removed again if its experiment is refused
    let fresh = !out.exists();
    prepare_dir(&out, "--out")?;
    let presets = out.join("presets");
    std::fs::create_dir_all(&presets)?;
    let vs = variants(&base);
    let mut labels = vec![];
    for v in &vs {
        std::fs::write(out.join(label(&v.name)), v.preset.to_toml())?;
        labels.push(format!("{:?}", label(&v.name)));
    }
    let scenario = std::path::Path::new(&a.scenario);
    let scenario = if scenario.exists() {
        std::fs::canonicalize(scenario)?.display().to_string()
    } else {
        a.scenario.clone()
    };
    let experiment = format!(
        "# Written by `magbench ablate`: {tracker} under {preset} with each term off in turn and alone.\n\
         name = {name:?}\n\
         description = \"Ablation of the {preset} preset: {tracker} tracking {planner}'s plans on {scenario_name}.\"\n\
         scenarios = [{scenario:?}]\n\
         planners = [{planner:?}]\n\
         trackers = [{tracker:?}]\n\
         presets = [{presets}]\n\
         seeds = {seeds}\n\n\
         [limits]\n\
         iterations = {iters}\n",
        tracker = a.tracker,
        preset = base.name,
        planner = a.planner,
        scenario_name = a.scenario,
        presets = labels.join(", "),
        seeds = a.seeds,
        iters = a.max_iters,
    );
    let file = out.join("ablation.toml");
    std::fs::write(&file, experiment)?;
    let executor = RealExecutor::new(registry.clone());
    let mut e = match Experiment::load(&file, &executor) {
        Ok(e) => e,
        Err(err) => {
            if fresh {
                let _ = std::fs::remove_dir_all(&out);
            }
            // the experiment is this command's: name the option its field came from
            let option = match err.field.split(['[', '.']).next() {
                Some("planners") => "--planner",
                Some("trackers") => "--tracker",
                Some("scenarios") => "SCENARIO",
                Some("seeds") => "--seeds",
                _ => return Err(err.into()),
            };
            return Err(Error::arg(option, err.reason));
        }
    };
    if let Some(p) = replays {
        e.replays = p;
    }
    let opts = SweepOptions {
        out: out.clone(),
        threads,
        shard: None,
        resume: a.resume,
        progress: if a.quiet {
            ProgressMode::Quiet
        } else {
            ProgressMode::Auto
        },
    };
    let s = run_sweep(&e, &executor, &opts)?;
    let runs = read_runs(&out)?;
    let rows = contributions(&runs, &terms);
    write_tables(&out, &rows, &variant_medians(&runs))?;
    crate::plot::save(&chart(&base.name, &a.tracker, &rows), &out.join("ablation"))?;
    outln!("{}", table(&rows));
    outln!(
        "{name}: {} runs in {} ({} crashed); ablation.csv, variants.csv, ablation.svg",
        s.total,
        out.display(),
        s.failed
    );
    Ok(())
}

fn write_tables(
    out: &std::path::Path,
    rows: &[TermRow],
    medians: &[(String, f64, usize)],
) -> Result<(), Error> {
    let mut w = csv::Writer::from_path(out.join("ablation.csv"))
        .map_err(|e| Error::Failed(e.to_string()))?;
    for r in rows {
        w.serialize(r).map_err(|e| Error::Failed(e.to_string()))?;
    }
    w.flush()?;
    let mut text = "variant,median_rms_error_bl,runs\n".to_string();
    for (v, m, n) in medians {
        let _ = writeln!(text, "{v},{m},{n}");
    }
    std::fs::write(out.join("variants.csv"), text)?;
    Ok(())
}

/// The ablation table as text.
pub fn table(rows: &[TermRow]) -> String {
    let mut s = format!(
        "{:<20} {:>14} {:>12} {:>14} {:>12} {:>6}\n",
        "term", "off in turn", "alone", "median w/o", "median only", "seeds"
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{:<20} {:>+14.4} {:>+12.4} {:>14.4} {:>12.4} {:>6}",
            r.term, r.off_in_turn_bl, r.alone_bl, r.without_median_bl, r.only_median_bl, r.seeds
        );
    }
    s + "(BL; off in turn = median over seeds of e(all) − e(without the term); alone = e(only the term) − e(no term); e = RMS observed-position path error)"
}

fn chart(preset: &str, tracker: &str, rows: &[TermRow]) -> BarChart {
    BarChart {
        title: format!("{tracker} under {preset}: each term's contribution to the RMS error"),
        value_label: "Δ RMS tracking error, observed positions (BL)".into(),
        categories: rows.iter().map(|r| r.term.clone()).collect(),
        series: vec![
            Series {
                label: "switched off in turn: e(all) − e(all but the term)".into(),
                data: rows.iter().map(|r| r.off_in_turn_bl).collect(),
            },
            Series {
                label: "alone: e(the term only) − e(no term)".into(),
                data: rows.iter().map(|r| r.alone_bl).collect(),
            },
        ],
    }
}
