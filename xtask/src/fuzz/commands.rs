//! The commands that use an accepted input: after [`Target::run`] accepts a mutant, the
//! mutation test writes it to a file and runs the command lines [`Target::commands`] gives,
//! as a child process under a time and memory cap.
//!
//! Each command line bounds its own work (iteration limits, a short emulation, one run of an
//! experiment), so that what remains unbounded is what the input itself asks for — exactly
//! what the caps are there to catch.

use std::path::Path;

use super::Target;
use magbench::experiment::Experiment;
use magbench::run::real::RealExecutor;

/// The most planner iterations of an experiment the test runs (more is a legitimately long
/// experiment, not a bug, and is skipped).
pub const MAX_EXPERIMENT_ITERATIONS: u64 = 20_000;

/// Numbers for `stlc`'s options: in range, at the edges, and beyond them.
const STLC_NUMBERS: &[&str] = &[
    "1.0001", "1.5", "2", "3", "12", "100", "1e308", "0.001", "0.01", "45", "90", "5e-324", "nan",
    "-1", "inf",
];

impl Target {
    /// The command lines (without the binary) that use the accepted input at `path`; `dir` is
    /// a scratch folder for their outputs. An empty list: the input is not run (see
    /// [`MAX_EXPERIMENT_ITERATIONS`]).
    pub fn commands(self, data: &[u8], path: &Path, dir: &Path) -> Vec<Vec<String>> {
        let p = path.display().to_string();
        let out = |name: &str| dir.join(name).display().to_string();
        let v = |a: &[&str]| a.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        match self {
            Target::Scenario => vec![
                v(&[
                    "plan",
                    &p,
                    "--planner",
                    "goal-zoom-rrt",
                    "--max-iters",
                    "2000",
                ]),
                v(&["track", &p, "--tracker", "obc", "--max-iters", "2000"]),
            ],
            Target::Experiment => {
                let text = String::from_utf8_lossy(data);
                let Ok(e) =
                    Experiment::parse(&text, &p, Path::new("."), "fuzz", &RealExecutor::default())
                else {
                    return vec![];
                };
                let small = e
                    .limits
                    .iterations
                    .is_some_and(|i| i <= MAX_EXPERIMENT_ITERATIONS)
                    && e.limits.time_s.is_none_or(|t| t <= 5.0);
                if !small {
                    return vec![];
                }
                // one run of the matrix: the last shard of as many as there are runs
                let n = e.runs().len().max(1);
                vec![v(&[
                    "bench",
                    &p,
                    "--out",
                    &out("results"),
                    "--quiet",
                    "--threads",
                    "1",
                    "--shard",
                    &format!("{n}/{n}"),
                ])]
            }
            Target::Rig => vec![v(&[
                "rig",
                "emulate",
                "--rig",
                &p,
                "open-field",
                "--duration",
                "0.3",
                "--speed",
                "20",
                "--log",
                &out("emulator-log.csv"),
            ])],
            Target::Plan => vec![v(&[
                "track",
                "open-field",
                "--tracker",
                "open-loop",
                "--plan",
                &p,
                "--preset",
                "ideal",
            ])],
            Target::Preset => vec![v(&[
                "track",
                "open-field",
                "--tracker",
                "obc",
                "--preset",
                &p,
                "--max-iters",
                "2000",
            ])],
        }
    }
}

/// `stlc` with its numbers drawn from [`STLC_NUMBERS`] by `index` (deterministic).
pub fn stlc_command(index: u64) -> Vec<String> {
    let n = STLC_NUMBERS.len() as u64;
    let pick = |k: u64| STLC_NUMBERS[((index / n.pow(k as u32)) % n) as usize].to_string();
    let agents = ["2", "3", "4", "5", "0", "1000"][(index % 6) as usize];
    vec![
        "stlc".into(),
        "--r".into(),
        pick(0),
        "--step".into(),
        pick(1),
        "--agents".into(),
        agents.into(),
    ]
}
