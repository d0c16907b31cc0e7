//! `magbench scenario list|show|check|generate`.

use std::path::PathBuf;

use clap::{Args, Subcommand};
use magbench_env::input::Bound;
use magbench_env::params::split_all;
use magbench_env::scenario::difficulty::measure;
use magbench_env::scenario::{builtin_names, generate};
use magbench_env::team_spin::{fastest_spin, spin_free, turn_note};
use magbench_env::team_symmetry::symmetry_note;
use magbench_env::{Obstacle, PlanningModel, Scenario};
use sha2::{Digest, Sha256};

use super::number::count;
use crate::Error;
use crate::output::{out, outln};

/// Scenario subcommands.
#[derive(Debug, Subcommand)]
pub enum ScenarioCmd {
    /// List the built-in scenarios.
    List,
    /// Summarise a scenario: world, obstacles, start, goals, physics and difficulty measures;
    /// with --out, draw it instead.
    Show {
        /// A built-in name or a scenario file.
        scenario: String,
        /// Draw every leg's map, start (agents to scale), goal regions and the pair's
        /// proximity range into this file (.svg or .png).
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
    },
    /// Validate a scenario file; exits 2 with FILE: FIELD: REASON when it is invalid, and
    /// notes on stderr a goal off the symmetric set of a start symmetric about its centroid
    /// (reached only through the growth of an asymmetry).
    Check {
        /// The scenario file (or built-in name) to validate.
        file: String,
    },
    /// Write generated scenario files of a family (deterministic per seed); --list lists the
    /// families and their parameters.
    Generate(GenerateArgs),
}

/// Arguments of `magbench scenario generate`.
#[derive(Debug, Args)]
pub struct GenerateArgs {
    /// The family: serpentine, corridor, clutter, rooms, short-moves or team (see --list).
    #[arg(required_unless_present = "list")]
    pub family: Option<String>,
    /// A family parameter, key=value (repeatable; see --list).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// The seed; file i of the count is drawn from stream i of this seed.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// How many files to write.
    #[arg(long, default_value_t = 1)]
    pub count: u64,
    /// The folder to write FAMILY-sSEED-INDEX.toml into (created if missing).
    #[arg(long, value_name = "DIR", required_unless_present = "list")]
    pub out: Option<PathBuf>,
    /// List the families and their parameters with ranges and defaults, and exit.
    #[arg(long)]
    pub list: bool,
}

/// How many files one `scenario generate` writes: as many as an experiment's most seeds.
const COUNT: Bound = Bound::closed(
    1.0,
    crate::experiment::MAX_SEEDS as f64,
    " files",
    "as many as an experiment has seeds at most; each file is generated, checked and written in turn",
);

/// Runs a scenario subcommand.
pub fn run(cmd: ScenarioCmd) -> Result<(), Error> {
    match cmd {
        ScenarioCmd::List => {
            for name in builtin_names() {
                let s = Scenario::load(name)?;
                outln!("{name:<16} {}", s.description);
            }
        }
        ScenarioCmd::Show { scenario, out } => {
            let s = Scenario::load(&scenario)?;
            match out {
                Some(path) => {
                    crate::replay::preview::write(&s, &path, "--out")?;
                    outln!("wrote {}", path.display());
                }
                None => out!("{}", summary(&s)),
            }
        }
        ScenarioCmd::Generate(a) => generate_files(a)?,
        ScenarioCmd::Check { file } => {
            let s = Scenario::load(&file)?;
            for (i, leg) in s.legs.iter().enumerate() {
                let field = if s.legs.len() == 1 {
                    "goal.agents".to_string()
                } else {
                    format!("legs[{i}].goal.agents")
                };
                let (start, goal) = (&s.start, &leg.goal);
                for note in [symmetry_note, turn_note] {
                    if let Some(note) = note(start, &goal.agents, goal.tolerance) {
                        eprintln!("note: {}: {field}: {note}", s.source);
                    }
                }
            }
            outln!(
                "{file}: ok ({} agents, {} leg(s), {} obstacles)",
                s.agents(),
                s.legs.len(),
                s.world.obstacles.len()
            );
        }
    }
    Ok(())
}

/// Runs `magbench scenario generate`: checks every parameter before writing anything, then
/// writes the files and prints one line per file (name, SHA-256, a difficulty summary).
fn generate_files(a: GenerateArgs) -> Result<(), Error> {
    if a.list {
        out!("{}", generate::list());
        return Ok(());
    }
    let (Some(family), Some(dir)) = (a.family.as_deref(), a.out.as_ref()) else {
        return Err(Error::arg("FAMILY", "a family and --out are required"));
    };
    count("--count", &COUNT, a.count)?;
    let params = split_all("<command line>", &a.set).map_err(|e| Error::arg("--set", e.reason))?;
    generate::family("<command line>", family, &params)?;
    crate::output::prepare_dir(dir, "--out")?;
    for index in 0..a.count {
        let g = generate::generate("<command line>", family, &params, a.seed, index)?;
        let path = dir.join(&g.file_name);
        std::fs::write(&path, &g.text)
            .map_err(|e| Error::Failed(format!("{}: {e}", path.display())))?;
        let d = measure(&g.scenario);
        let hash = Sha256::digest(g.text.as_bytes());
        outln!(
            "{}  sha256 {:x}  path {} BL, {} turn(s), passage {:.2} BL",
            path.display(),
            hash,
            d.path_length_bl
                .map(|l| format!("{l:.1}"))
                .unwrap_or_else(|| "none".into()),
            d.path_turns.map(|t| t.to_string()).unwrap_or_default(),
            d.narrowest_passage_bl
        );
    }
    Ok(())
}

fn pts(v: &[magbench_env::Vec2]) -> String {
    v.iter()
        .map(|p| format!("({:.2}, {:.2})", p.x, p.y))
        .collect::<Vec<_>>()
        .join(" ")
}

/// A human-readable summary of a scenario.
pub fn summary(s: &Scenario) -> String {
    let mut out = String::new();
    let p = &s.physics;
    out += &format!("scenario    {}\n", s.name);
    if !s.description.is_empty() {
        out += &format!("            {}\n", s.description);
    }
    out += &format!("source      {}\n", s.source);
    out += &format!(
        "world       {} x {} BL, {} obstacles\n",
        s.world.width,
        s.world.height,
        s.world.obstacles.len()
    );
    for o in &s.world.obstacles {
        out += &match o {
            Obstacle::Polygon(v) => format!("  polygon   {} vertices: {}\n", v.len(), pts(v)),
            Obstacle::Circle { center, radius } => format!(
                "  circle    centre ({:.2}, {:.2}), radius {radius}\n",
                center.x, center.y
            ),
        };
    }
    out += &format!("start       {}\n", pts(&s.start));
    for (i, l) in s.legs.iter().enumerate() {
        let switch = l
            .obstacles
            .as_ref()
            .map(|o| format!(", map switch to {} obstacles", o.len()))
            .unwrap_or_default();
        out += &format!(
            "goal {}      {} within {} BL{switch}\n",
            i + 1,
            pts(&l.goal.agents),
            l.goal.tolerance
        );
    }
    out += &format!(
        "physics     d = {} µm, η = {} mPa·s, M = {} kA/m, G_max = {} mT/m, dt = {:.5} s\n",
        p.diameter_um,
        p.viscosity_mpa_s,
        p.magnetization_ka_per_m,
        p.gradient_limit_mt_per_m,
        p.dt_s
    );
    out += &format!(
        "            κ = {:.3} BL⁵/s (ṙ at r = 2, ψ = 0: {:.2} BL/s), max pull {:.3} BL/s, proximity range ({}, {}) BL\n",
        p.kappa(),
        2.0 * p.kappa() / 16.0,
        p.max_pull_speed(),
        p.r_min,
        p.r_max
    );
    if let Some(m) = &s.medium {
        let drag = m.drag().translation;
        out += &format!(
            "medium      {}: {drag:.3} of the bulk's drag, so κ = {:.3} BL⁵/s and every pair and \
             pull moves {:.3}× as fast\n",
            m.kind(),
            p.kappa() / drag,
            1.0 / drag
        );
    }
    if s.agents() >= 3 {
        out += &spin_line(s);
    }
    out += &measure(s).summary();
    out
}

/// How fast the fastest field turns the start about its centroid, in the planning model at the
/// scenario's medium, and whether no field turns it ([`magbench_env::team_spin`]).
fn spin_line(s: &Scenario) -> String {
    let mut model = PlanningModel::new(&s.physics);
    if let Some(m) = &s.medium {
        model = model.in_medium(&s.physics, m);
    }
    let (fastest, theta) = fastest_spin(&model, &s.start);
    let free = if spin_free(&s.start) {
        " (no field turns this formation: docs/physics.md, \"Formations no field turns\")"
    } else {
        ""
    };
    format!(
        "spin        the start turns at most {:.3}°/s about its centroid (field at {:.1}°){free}\n",
        fastest.to_degrees(),
        theta.to_degrees()
    )
}
