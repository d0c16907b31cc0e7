//! `magbench scenario list|show|check`.

use clap::Subcommand;
use magbench_env::scenario::builtin_names;
use magbench_env::{Obstacle, Scenario};

use super::output::{out, outln};
use crate::CliError;

/// Scenario subcommands.
#[derive(Debug, Subcommand)]
pub enum ScenarioCmd {
    /// List the built-in scenarios.
    List,
    /// Summarise a scenario: world, obstacles, start, goals and physics.
    Show {
        /// A built-in name or a scenario file.
        scenario: String,
    },
    /// Validate a scenario file; exits 2 with FILE: FIELD: REASON when it is invalid.
    Check {
        /// The scenario file (or built-in name) to validate.
        file: String,
    },
}

/// Runs a scenario subcommand.
pub fn run(cmd: ScenarioCmd) -> Result<(), CliError> {
    match cmd {
        ScenarioCmd::List => {
            for name in builtin_names() {
                let s = Scenario::load(name)?;
                outln!("{name:<16} {}", s.description);
            }
        }
        ScenarioCmd::Show { scenario } => out!("{}", summary(&Scenario::load(&scenario)?)),
        ScenarioCmd::Check { file } => {
            let s = Scenario::load(&file)?;
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
    out
}
