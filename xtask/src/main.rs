//! `cargo xtask measure`: regenerate the measured figures of the book in `docs/measured/`;
//! `cargo xtask stale`: name the ones whose source changed since they were measured;
//! `cargo xtask lines`: each crate's share of the project's non-test lines.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};

use magbench::Error;
use magbench::output::prepare_dir;
use magbench::registry::Registry;
use magbench::run::real::RealExecutor;
use magbench::sweep::ProgressMode;
use magbench_env::InputError;
use xtask::docs::cargo::MagbenchBinary;
use xtask::docs::freshness::{FreshnessError, file_staleness, pathspecs};
use xtask::docs::measures::{MEASURES, Measure, find};
use xtask::docs::run::{RunOptions, measure};

/// `println!` that survives a closed pipe (`cargo xtask stale | head`), as magbench's commands do.
macro_rules! outln {
    ($($arg:tt)*) => {
        magbench::output::emit(&format!("{}\n", format_args!($($arg)*)))?
    };
}

/// `cargo xtask …`: the project's own maintenance.
#[derive(Debug, Parser)]
#[command(name = "cargo xtask", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// The maintenance commands.
#[derive(Debug, Subcommand)]
enum Command {
    /// Run the book's measurements and write each table to `docs/measured/NAME.md`, headed by
    /// the command, machine, load, date and version.
    Measure(MeasureArgs),
    /// Name each file of `docs/measured/` whose header names a dirty tree, or whose
    /// measurement's source paths changed in git after the revision it names; exit 1 when any
    /// is stale.
    Stale(StaleArgs),
    /// Print each crate's non-test lines and share of the project's, as a Markdown table.
    Lines,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let done = match cli.command {
        Command::Measure(a) => run_measure(a, &Registry::builtin()),
        Command::Stale(a) => run_stale(a),
        Command::Lines => run_lines(),
    };
    match done {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}

/// Arguments of `cargo xtask stale`.
#[derive(Debug, Args)]
pub struct StaleArgs {
    /// The folder of generated files (default: docs/measured of the repository).
    #[arg(long)]
    pub dir: Option<PathBuf>,
    /// Also print each measurement's source paths.
    #[arg(long)]
    pub verbose: bool,
}

/// Arguments of `cargo xtask measure`.
#[derive(Debug, Args)]
pub struct MeasureArgs {
    /// Keep a few seeds of each experiment and run benches with criterion's `--quick` (a check
    /// that the measurements run, not figures).
    #[arg(long)]
    pub quick: bool,
    /// Run only this measurement (repeatable); `--list` names them.
    #[arg(long, value_name = "NAME")]
    pub only: Vec<String>,
    /// Print the measurements and what each runs, and run nothing.
    #[arg(long)]
    pub list: bool,
    /// Where the files go (default: docs/measured of the repository).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Where the experiments' results and criterion's output go (default: target/docs-measure
    /// of the repository).
    #[arg(long)]
    pub work: Option<PathBuf>,
    /// Worker threads (default: all CPUs).
    #[arg(long)]
    pub threads: Option<usize>,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
}

/// The repository: the working directory if it holds `experiments/` and `docs/`, else the
/// source tree this binary was built from.
fn root() -> PathBuf {
    let here = PathBuf::from(".");
    if here.join("experiments").is_dir() && here.join("docs").is_dir() {
        return here;
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn run_lines() -> Result<(), Error> {
    let t =
        xtask::lines::table(&root()).map_err(|e| Error::Failed(format!("counting lines: {e}")))?;
    magbench::output::emit(&t.markdown())
}

fn run_stale(a: StaleArgs) -> Result<(), Error> {
    let root = root();
    let dir = a.dir.unwrap_or_else(|| root.join("docs/measured"));
    let mut stale = 0;
    for m in MEASURES {
        let path = dir.join(format!("{}.md", m.name));
        let text = match std::fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                outln!("{}: not measured yet", m.name);
                stale += 1;
                continue;
            }
            Err(e) => return Err(Error::Failed(format!("{}: {e}", path.display()))),
        };
        if a.verbose {
            outln!("{}: depends on {}", m.name, pathspecs(&root, m).join(" "));
        }
        let file = path.display().to_string();
        match file_staleness(&root, m, &text).map_err(|e| match e {
            FreshnessError::Header(e) => {
                Error::Input(InputError::new(file.clone(), "header", e.to_string()))
            }
            e => Error::Failed(format!("{file}: {e}")),
        })? {
            Some(why) => {
                outln!("{}: stale: {why}", m.name);
                stale += 1;
            }
            None if a.verbose => outln!("{}: fresh", m.name),
            None => {}
        }
    }
    match stale {
        0 => Ok(()),
        n => Err(Error::Failed(format!(
            "{n} of {} measured files are stale; regenerate each with `cargo xtask measure --only NAME` on an idle machine at a clean commit",
            MEASURES.len()
        ))),
    }
}

fn run_measure(a: MeasureArgs, registry: &Registry) -> Result<(), Error> {
    if a.list {
        for m in MEASURES {
            let needs = match m.feature {
                Some(f) if !m.runnable() => format!("\tneeds a build with --features {f}"),
                Some(f) if !m.available() => {
                    format!(
                        "\truns with --only (cargo builds it with --features {f}), else skipped"
                    )
                }
                _ => String::new(),
            };
            outln!("{}\t{}{needs}", m.name, m.describe());
        }
        return Ok(());
    }
    let chosen: Vec<&Measure> = match a.only.is_empty() {
        true => {
            for m in MEASURES.iter().filter(|m| !m.available()) {
                let or = match m.runnable() {
                    true => format!(" or `--only {}`", m.name),
                    false => String::new(),
                };
                eprintln!(
                    "{}: skipped; it needs a build with --features {}{or}",
                    m.name,
                    m.feature.unwrap_or_default()
                );
            }
            MEASURES.iter().filter(|m| m.available()).collect()
        }
        false => {
            let names: Vec<&str> = MEASURES.iter().map(|m| m.name).collect();
            a.only
                .iter()
                .map(|n| {
                    find(n).ok_or_else(|| {
                        let known = names.join(", ");
                        Error::arg("--only", format!("no measurement {n:?} (known: {known})"))
                    })
                })
                .collect::<Result<Vec<_>, _>>()?
        }
    };
    if let Some(m) = chosen.iter().find(|m| !m.runnable()) {
        return Err(Error::arg(
            "--only",
            format!(
                "{} needs a build with --features {} (`cargo run --release -p xtask --features {} -- measure --only {}`)",
                m.name,
                m.feature.unwrap_or_default(),
                m.feature.unwrap_or_default(),
                m.name
            ),
        ));
    }
    let threads = threads(a.threads)?;
    let root = root();
    let out = a.out.unwrap_or_else(|| root.join("docs/measured"));
    let work = a.work.unwrap_or_else(|| root.join("target/docs-measure"));
    prepare_dir(&out, "--out")?;
    prepare_dir(&work, "--work")?;
    let ex = RealExecutor::new(registry.clone());
    let magbench = MagbenchBinary::default();
    let opts = RunOptions {
        root: &root,
        work: &work,
        out: &out,
        quick: a.quick,
        threads,
        magbench: &magbench,
        progress: if a.quiet {
            ProgressMode::Quiet
        } else {
            ProgressMode::Auto
        },
    };
    for m in chosen {
        let text = measure(m, &ex, &opts)?;
        let file = out.join(format!("{}.md", m.name));
        std::fs::write(&file, text)?;
        outln!("{}: wrote {}", m.name, file.display());
    }
    Ok(())
}

/// The worker threads of `--threads`: the given number within the machine's bound, else one
/// per core.
fn threads(given: Option<usize>) -> Result<usize, Error> {
    match given {
        Some(n) => magbench_env::input::bounds::threads("--threads", n)
            .map_err(|r| Error::arg("--threads", r.reason)),
        None => Ok(std::thread::available_parallelism().map_or(1, |n| n.get())),
    }
}
