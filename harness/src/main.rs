//! The `magbench` command. See `magbench --help`.

#![warn(missing_docs)]

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = magbench::cli::Cli::parse();
    match magbench::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
