//! `magbench results verify DIR`: check a results folder; `magbench results plot DIR`: draw
//! its figures again at a size preset, DPI and axis scale, and as PDF; `magbench results scaling
//! DIR`: fit how time and iterations to a first solution grow with a problem size; `magbench
//! results formations DIR`: which formation a team reaches from which; `magbench
//! results profile DIR`: the performance profile and paired comparisons as Markdown.

use std::path::PathBuf;

use clap::Subcommand;

use super::number::count;
use crate::Error;
use crate::output::{out, outln};
use crate::plot::export::{DPI, FigureOptions};
use crate::results::{lock, verify};

/// Results-folder subcommands.
#[derive(Debug, Subcommand)]
pub enum ResultsCmd {
    /// Check a results folder: its manifest, one row per run, one whole trace per run, and the
    /// files' hashes; print what is wrong. Exit 1 if anything is, 2 for bad input (no such
    /// folder, not a results folder, or a bench or merge writing it now).
    Verify {
        /// The results folder.
        dir: PathBuf,
    },
    /// Fit median time and median iterations to a first solution against a problem size, per
    /// planner: the exponent b of value ≈ a·size^b (log–log least squares) with its 95%
    /// interval; plot them into DIR/plots/scaling-[FAMILY-]BY.svg (time) and
    /// scaling-[FAMILY-]BY-iterations.svg.
    Scaling {
        /// The results folder.
        dir: PathBuf,
        /// The size: a parameter of the generated scenarios' labels (e.g. `walls`, `length`),
        /// or `agents`.
        #[arg(long)]
        by: String,
        /// Only scenarios of this generated family (label prefix `FAMILY-`).
        #[arg(long)]
        family: Option<String>,
    },
    /// The formation study: per team size, start and goal formation (the `team` family's labels)
    /// and planner, the runs solved, the median time to a first plan and cost over its lower
    /// bound, with the start's accessibility rank and central symmetry, as Markdown; one figure
    /// per planner into DIR/plots/formations-PLANNER.svg (docs/planners.md, "Which formation
    /// from which").
    Formations {
        /// The results folder.
        dir: PathBuf,
    },
    /// Print the comparison across problems of the report's "Across problems" section as
    /// Markdown: each planner's performance profile ρ(τ) at the given τ and the fraction of
    /// problems it solves, and the paired comparison (win rate, time ratio) of every pair of
    /// planners.
    Profile {
        /// The results folder.
        dir: PathBuf,
        /// The τ at which ρ(τ) is printed (comma-separated, each ≥ 1).
        #[arg(long, value_delimiter = ',', default_values_t = super::profile::DEFAULT_TAUS.to_vec())]
        tau: Vec<f64>,
    },
    /// Draw a finished results folder's figures and report again with figure options (for a
    /// paper: `--figure-size one-column --pdf`); docs/figures.md.
    Plot {
        /// The results folder.
        dir: PathBuf,
        /// Size, resolution, axes and formats.
        #[command(flatten)]
        figures: FigureOptions,
    },
}

/// Runs a results subcommand.
pub fn run(cmd: ResultsCmd) -> Result<(), Error> {
    match cmd {
        ResultsCmd::Scaling { dir, by, family } => scaling(&dir, &by, family.as_deref()),
        ResultsCmd::Formations { dir } => formations(&dir),
        ResultsCmd::Profile { dir, tau } => {
            let md = super::profile::run(&dir, &tau)?;
            out!("{md}");
            Ok(())
        }
        ResultsCmd::Plot { dir, figures } => {
            count("--dpi", &DPI, u64::from(figures.dpi))?;
            figures
                .check_build()
                .map_err(|(option, why)| Error::arg(option, why))?;
            if !dir.is_dir() {
                return Err(Error::arg(
                    "DIR",
                    format!("{}: not a folder", dir.display()),
                ));
            }
            let _lock = lock::exclusive(&dir, "results plot", "DIR")?;
            crate::results::Manifest::read(&dir)?;
            crate::results::finalize_with(&dir, &figures)?;
            outln!(
                "{}: figures written to {}",
                dir.display(),
                dir.join("plots").display()
            );
            Ok(())
        }
        ResultsCmd::Verify { dir } => {
            let _lock = lock::shared(&dir, "DIR")?;
            let v = verify::verify(&dir)?;
            for n in &v.notes {
                eprintln!("note: {}: {n}", dir.display());
            }
            let problems = v.all_problems();
            if problems.is_empty() {
                let hashes = match v.files_hashed {
                    0 => "no file hashes to check".to_string(),
                    n => format!("{n} files match the manifest's hashes"),
                };
                outln!(
                    "{}: ok: {} runs, {} trace points, {hashes}",
                    dir.display(),
                    v.runs,
                    v.trace_points,
                );
                return Ok(());
            }
            for p in &problems {
                outln!("{}: {p}", dir.display());
            }
            Err(Error::Failed(format!(
                "{}: {} problems found",
                dir.display(),
                problems.len()
            )))
        }
    }
}

fn formations(dir: &std::path::Path) -> Result<(), Error> {
    use crate::compare::formations::{figure, markdown, study};
    let _lock = lock::shared(dir, "DIR")?;
    let runs = crate::results::store::read_runs(dir)?;
    let pairs = study(&runs, &dir.join("scenarios"))?;
    out!("{}", markdown(&pairs));
    let mut planners: Vec<&str> = vec![];
    for o in pairs.iter().flat_map(|p| &p.planners) {
        if !planners.contains(&o.planner.as_str()) {
            planners.push(&o.planner);
        }
    }
    for p in planners {
        let stem = dir.join("plots").join(format!("formations-{p}"));
        crate::plot::save(&figure(&pairs, p), &stem)?;
        outln!("plot: {}", crate::plot::with_ext(&stem, "svg").display());
    }
    Ok(())
}

fn scaling(dir: &std::path::Path, by: &str, family: Option<&str>) -> Result<(), Error> {
    use crate::compare::study::{Quantity, fit_text, plot, study};
    let _lock = lock::shared(dir, "DIR")?;
    let runs = crate::results::store::read_runs(dir)?;
    for q in Quantity::ALL {
        let s = study(&runs, family, by, q);
        if s.is_empty() {
            return Err(Error::arg(
                "--by",
                format!(
                    "no planning run of {} has a size `{by}` (a label parameter or `agents`)",
                    dir.display()
                ),
            ));
        }
        let unit = match q.unit() {
            "" => String::new(),
            u => format!(" {u}"),
        };
        for p in &s {
            outln!("{}: {} ≈ {}", p.planner, q.name(), fit_text(&p.fit, by));
            for (k, t, solved, n) in &p.points {
                let v = match q {
                    Quantity::Time => format!("{t:.4}"),
                    Quantity::Iterations => format!("{t:.0}"),
                };
                outln!("  {by} = {k}: median {v}{unit}, {solved}/{n} solved");
            }
        }
        let stem = plot(dir, &s, family, by, q)?;
        outln!("plot: {}.svg", stem.display());
    }
    Ok(())
}
