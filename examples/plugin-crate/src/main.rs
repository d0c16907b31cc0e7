//! `my-magbench`: the whole `magbench` command line with this crate's planner and tracker beside
//! the built-ins (`my-magbench plan --list`, `my-magbench bench experiments/plugin.toml`).

mod com_p;
mod plain_rrt;

use std::process::ExitCode;

fn main() -> ExitCode {
    magbench::Cli::new()
        .planner::<plain_rrt::PlainRrt>("plain-rrt")
        .tracker::<com_p::ComP>("com-p")
        .run()
}
