//! The `magbench` command. See `magbench --help`.

#![warn(missing_docs)]

use std::process::ExitCode;

fn main() -> ExitCode {
    magbench::Cli::new().run()
}
