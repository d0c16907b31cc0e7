//! Running cargo as a subprocess from the repository root for a measurement, and keeping the
//! Markdown table lines (`| … |`) of what it prints.

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::OnceLock;

use thiserror::Error;

/// Why a cargo subprocess failed.
#[derive(Debug, Error)]
pub enum CargoError {
    /// `cargo` could not be started or its output read.
    #[error("could not run `{command}`: {source}")]
    Spawn {
        /// The command line.
        command: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The command failed (build error, a panic, a failed test, missing library).
    #[error("`{command}` failed ({status}); its output is above")]
    Exit {
        /// The command line.
        command: String,
        /// Its exit status.
        status: std::process::ExitStatus,
    },
    /// The build succeeded but named no executable of the binary asked for.
    #[error("`{command}` built no `{binary}` executable")]
    NoExecutable {
        /// The command line.
        command: String,
        /// The binary asked for.
        binary: String,
    },
}

/// The cargo program: `$CARGO` (set when run by cargo) or `cargo`.
pub fn cargo_program() -> String {
    std::env::var("CARGO").unwrap_or_else(|_| "cargo".into())
}

/// The command line of cargo arguments `args`, as a header or an error names it.
pub fn command_line(args: &[String]) -> String {
    format!("cargo {}", args.join(" "))
}

/// Runs cargo with `args` and environment `envs` in `root`, its stderr inherited, and returns
/// its stdout (echoed to stderr line by line while it runs if `echo`).
pub fn run_cargo(
    root: &Path,
    args: &[String],
    envs: &[(&str, &Path)],
    echo: bool,
) -> Result<String, CargoError> {
    let command = command_line(args);
    let spawn = |source| CargoError::Spawn {
        command: command.clone(),
        source,
    };
    let mut child = Command::new(cargo_program())
        .args(args)
        .current_dir(root)
        .envs(envs.iter().copied())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .map_err(spawn)?;
    let mut stdout = String::new();
    if let Some(out) = child.stdout.take() {
        for line in BufReader::new(out).lines() {
            let line = line.map_err(spawn)?;
            if echo {
                eprintln!("{line}");
            }
            stdout.push_str(&line);
            stdout.push('\n');
        }
    }
    let status = child.wait().map_err(spawn)?;
    if !status.success() {
        return Err(CargoError::Exit { command, status });
    }
    Ok(stdout)
}

/// The `magbench` binary that transcripts and Python scripts run: built once, on first use, by
/// `cargo build --release -p magbench` (with OMPL's planners when this crate has its `ompl`
/// feature), wherever cargo puts its target folder.
#[derive(Debug, Default)]
pub struct MagbenchBinary {
    path: OnceLock<PathBuf>,
}

impl MagbenchBinary {
    /// The binary's path, built from the repository at `root` the first time it is asked for
    /// (cargo's build output echoed to stderr when `echo`).
    pub fn path(&self, root: &Path, echo: bool) -> Result<&Path, CargoError> {
        if let Some(p) = self.path.get() {
            return Ok(p);
        }
        let mut args: Vec<String> = ["build", "--release", "-p", "magbench", "--bin", "magbench"]
            .map(String::from)
            .to_vec();
        if cfg!(feature = "ompl") {
            args.extend(["--features".into(), "ompl".into()]);
        }
        args.push("--message-format=json-render-diagnostics".into());
        let stdout = run_cargo(root, &args, &[], false)?;
        let path = executable(&stdout, "magbench").ok_or_else(|| CargoError::NoExecutable {
            command: command_line(&args),
            binary: "magbench".into(),
        })?;
        if echo {
            eprintln!("magbench: {}", path.display());
        }
        Ok(self.path.get_or_init(|| path))
    }
}

/// The executable of binary `name` among the messages of `cargo build
/// --message-format=json` (one JSON object a line), if it was built.
pub fn executable(messages: &str, name: &str) -> Option<PathBuf> {
    messages
        .lines()
        .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
        .filter(|m| m["reason"] == "compiler-artifact" && m["target"]["name"] == name)
        .find_map(|m| m["executable"].as_str().map(PathBuf::from))
}

/// The lines of `stdout` that are Markdown table lines (`| … |`), trimmed.
pub fn own_table(stdout: &str) -> Vec<&str> {
    stdout
        .lines()
        .map(str::trim)
        .filter(|l| l.len() >= 2 && l.starts_with('|') && l.ends_with('|'))
        .collect()
}

/// The Markdown table lines of `stdout`, each ending in a newline: the file a test, example or
/// script measurement keeps; `None` when it printed none.
pub fn table_text(stdout: &str) -> Option<String> {
    let lines = own_table(stdout);
    (!lines.is_empty()).then(|| lines.iter().map(|l| format!("{l}\n")).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_executable_is_read_from_cargos_messages() {
        let messages = concat!(
            r#"{"reason":"compiler-artifact","target":{"name":"magbench","kind":["lib"]},"executable":null}"#,
            "\n",
            "a line that is not JSON\n",
            r#"{"reason":"compiler-artifact","target":{"name":"other"},"executable":"/t/other"}"#,
            "\n",
            r#"{"reason":"compiler-artifact","target":{"name":"magbench","kind":["bin"]},"executable":"/t/release/magbench"}"#,
            "\n",
            r#"{"reason":"build-finished","success":true}"#,
            "\n",
        );
        assert_eq!(
            executable(messages, "magbench"),
            Some(PathBuf::from("/t/release/magbench"))
        );
        assert_eq!(executable(messages, "absent"), None);
        assert_eq!(executable("", "magbench"), None);
    }

    #[test]
    fn only_table_lines_of_the_stdout_are_kept() {
        let out = "obc tick (micro-factory)\n                        time:   [8.7 µs 8.8 µs 8.9 µs]\n\
                   | tracker | median |\n| --- | --- |\n  | obc | 13.4 µs |\nFound 3 outliers\n\
                   running 1 test\n|\ntest sst_node_counts ... ok\n";
        assert_eq!(
            own_table(out),
            vec!["| tracker | median |", "| --- | --- |", "| obc | 13.4 µs |"]
        );
    }

    #[test]
    fn a_failing_command_is_an_error_naming_it() {
        let args = vec!["no-such-cargo-subcommand-xyz".to_string()];
        let e = run_cargo(Path::new("."), &args, &[], false).unwrap_err();
        assert!(
            e.to_string()
                .contains("`cargo no-such-cargo-subcommand-xyz` failed"),
            "{e}"
        );
    }
}
