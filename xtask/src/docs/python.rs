//! Running a Python measurement: a script of the repository run from the repository root by
//! the interpreter that `$MAGBENCH_PYTHON` names (default `python3`), which must import the
//! magbench package (`pip install ./python`); the Markdown table lines (`| … |`) it prints on
//! stdout are kept, as a test measurement keeps them.

use std::path::Path;
use std::process::{Command, Output, Stdio};

use magbench_env::InputError;
use thiserror::Error;

use super::cargo::table_text;

/// The environment variable naming the Python interpreter.
pub const PYTHON_VAR: &str = "MAGBENCH_PYTHON";

/// The interpreter used when `$MAGBENCH_PYTHON` is unset or empty.
pub const DEFAULT_PYTHON: &str = "python3";

/// What the interpreter prints about itself: its executable, its version, magbench's
/// distribution version and the imported module's file, one per line.
const PROBE: &str = "import sys\nimport magbench\ntry:\n    from importlib.metadata import version\n    v = version('magbench')\nexcept Exception:\n    v = 'unknown'\nprint(sys.executable)\nprint(sys.version.split()[0])\nprint(v)\nprint(magbench.__file__)\n";

/// Why a Python measurement failed.
#[derive(Debug, Error)]
pub enum PythonError {
    /// The interpreter cannot be started or cannot import magbench (bad input: the variable).
    #[error("{0}")]
    Interpreter(InputError),
    /// The script could not be started.
    #[error("python script {script}: could not run `{command}`: {source}")]
    Spawn {
        /// The script.
        script: String,
        /// The command line.
        command: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The script failed (an exception, a crashed run).
    #[error("python script {script}: `{command}` failed ({status}); its output is above")]
    Exit {
        /// The script.
        script: String,
        /// The command line.
        command: String,
        /// Its exit status.
        status: std::process::ExitStatus,
    },
    /// The script printed no Markdown table line.
    #[error(
        "python script {script}: `{command}` printed no Markdown table (`| … |` lines on stdout)"
    )]
    NoTable {
        /// The script.
        script: String,
        /// The command line.
        command: String,
    },
}

impl From<PythonError> for magbench::Error {
    fn from(e: PythonError) -> Self {
        match e {
            PythonError::Interpreter(e) => magbench::Error::Input(e),
            e => magbench::Error::Failed(e.to_string()),
        }
    }
}

/// The interpreter `$MAGBENCH_PYTHON` names, or [`DEFAULT_PYTHON`].
pub fn interpreter_program() -> String {
    std::env::var(PYTHON_VAR)
        .ok()
        .filter(|p| !p.trim().is_empty())
        .unwrap_or_else(|| DEFAULT_PYTHON.into())
}

/// A Python interpreter that imports magbench.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Interpreter {
    /// The program as `$MAGBENCH_PYTHON` names it.
    pub program: String,
    /// Its absolute path (`sys.executable`).
    pub executable: String,
    /// Its version (`3.11.2`).
    pub version: String,
    /// The installed magbench distribution's version.
    pub magbench: String,
    /// The file of the imported magbench module.
    pub module: String,
}

impl Interpreter {
    /// The interpreter and its magbench, as a header names them.
    pub fn describe(&self) -> String {
        format!(
            "Python {} (`{}`) with magbench {} from `{}`",
            self.version, self.executable, self.magbench, self.module
        )
    }
}

/// A bad `$MAGBENCH_PYTHON`: `<environment>: MAGBENCH_PYTHON: REASON` and how to fix it.
fn bad_interpreter(program: &str, why: &str) -> PythonError {
    PythonError::Interpreter(InputError::new(
        "<environment>",
        PYTHON_VAR,
        format!(
            "{program:?} {why}; install the package into that interpreter's environment \
             (`pip install ./python`) or set {PYTHON_VAR} to an interpreter that has it"
        ),
    ))
}

/// Runs `program` in `root` and asks it for its version and magbench's; an interpreter that
/// cannot start or cannot import magbench is an [`PythonError::Interpreter`] error.
pub fn probe(program: &str, root: &Path) -> Result<Interpreter, PythonError> {
    let out = Command::new(program)
        .args(["-c", PROBE])
        .current_dir(root)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| bad_interpreter(program, &format!("cannot be started ({e})")))?;
    if !out.status.success() {
        let stderr = String::from_utf8_lossy(&out.stderr);
        let last = stderr.lines().rev().find(|l| !l.trim().is_empty());
        let why = match last {
            Some(l) => format!("cannot import magbench ({}: {})", out.status, l.trim()),
            None => format!("cannot import magbench ({})", out.status),
        };
        return Err(bad_interpreter(program, &why));
    }
    let stdout = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<&str> = stdout.lines().map(str::trim).collect();
    match lines[..] {
        [executable, version, magbench, module] => Ok(Interpreter {
            program: program.into(),
            executable: executable.into(),
            version: version.into(),
            magbench: magbench.into(),
            module: module.into(),
        }),
        _ => Err(bad_interpreter(
            program,
            &format!("is not a Python interpreter (it printed {stdout:?} for a probe of magbench)"),
        )),
    }
}

/// One run of a Python script of a measurement.
#[derive(Debug, Clone)]
pub struct PythonRun<'a> {
    /// The script, relative to the repository root.
    pub script: &'a str,
    /// Its arguments.
    pub args: Vec<String>,
    /// The repository root (the working directory).
    pub root: &'a Path,
    /// Echo the script's stdout to stderr once it ends.
    pub echo: bool,
    /// The `magbench` binary the script may run, named to it by `$MAGBENCH_BIN` (none: the
    /// variable is not set).
    pub magbench: Option<&'a Path>,
}

impl PythonRun<'_> {
    /// The command line as a header names it: `$MAGBENCH_PYTHON SCRIPT ARGS`.
    pub fn command_line(&self) -> String {
        let mut c = format!("${PYTHON_VAR} {}", self.script);
        for a in &self.args {
            c.push(' ');
            c.push_str(a);
        }
        c
    }
}

/// The environment variable a script finds this magbench binary in (the one running `docs
/// measure`), for scripts that time its commands.
pub const BIN_VAR: &str = "MAGBENCH_BIN";

/// Runs `r` with interpreter `i` (its stderr inherited) and returns the Markdown table lines
/// it printed, one per line.
pub fn run_python(i: &Interpreter, r: &PythonRun) -> Result<String, PythonError> {
    let command = r.command_line();
    let mut cmd = Command::new(&i.executable);
    if let Some(exe) = r.magbench {
        cmd.env(BIN_VAR, exe);
    }
    let out: Output = cmd
        .arg(r.script)
        .args(&r.args)
        .current_dir(r.root)
        .stdin(Stdio::null())
        .stderr(Stdio::inherit())
        .output()
        .map_err(|source| PythonError::Spawn {
            script: r.script.into(),
            command: command.clone(),
            source,
        })?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    if r.echo {
        eprint!("{stdout}");
    }
    if !out.status.success() {
        return Err(PythonError::Exit {
            script: r.script.into(),
            command,
            status: out.status,
        });
    }
    table_text(&stdout).ok_or_else(|| PythonError::NoTable {
        script: r.script.into(),
        command,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An executable shell script `name` in `dir` with body `body`, written by a shell of its
    /// own: a file this process held open for writing could be inherited by a child that
    /// another test's thread forks meanwhile, and running it would then fail with "Text file
    /// busy" until that child execs.
    fn script(dir: &Path, name: &str, body: &str) -> String {
        let p = dir.join(name);
        let written = Command::new("/bin/sh")
            .args([
                "-c",
                "printf '%s' \"$1\" > \"$2\" && chmod 755 \"$2\"",
                "sh",
            ])
            .arg(format!("#!/bin/sh\n{body}\n"))
            .arg(&p)
            .status()
            .unwrap();
        assert!(written.success(), "{}: not written", p.display());
        p.display().to_string()
    }

    #[test]
    fn an_interpreter_without_magbench_is_bad_input_naming_the_variable() {
        let dir = tempfile::tempdir().unwrap();
        let lacking = script(
            dir.path(),
            "python",
            "echo 'Traceback (most recent call last):' >&2\n\
             echo \"ModuleNotFoundError: No module named 'magbench'\" >&2\nexit 1",
        );
        let e = magbench::Error::from(probe(&lacking, dir.path()).unwrap_err());
        assert_eq!(e.exit_code(), 2);
        let text = e.to_string();
        assert!(
            text.starts_with("<environment>: MAGBENCH_PYTHON: "),
            "{text}"
        );
        assert!(text.contains("cannot import magbench"), "{text}");
        assert!(text.contains("No module named 'magbench'"), "{text}");
        assert!(text.contains("pip install ./python"), "{text}");

        let missing = dir.path().join("no-such-python").display().to_string();
        let e = magbench::Error::from(probe(&missing, dir.path()).unwrap_err());
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains("cannot be started"), "{e}");

        let not_python = script(dir.path(), "echo", "echo hello");
        let e = magbench::Error::from(probe(&not_python, dir.path()).unwrap_err());
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains("is not a Python interpreter"), "{e}");
    }

    #[test]
    fn a_probe_reads_the_interpreter_and_its_magbench() {
        let dir = tempfile::tempdir().unwrap();
        let fake = script(
            dir.path(),
            "python",
            "printf '/venv/bin/python\\n3.11.2\\n0.1.0\\n/venv/magbench/__init__.py\\n'",
        );
        let i = probe(&fake, dir.path()).unwrap();
        assert_eq!(i.executable, "/venv/bin/python");
        assert_eq!(
            i.describe(),
            "Python 3.11.2 (`/venv/bin/python`) with magbench 0.1.0 from \
             `/venv/magbench/__init__.py`"
        );
    }

    #[test]
    fn only_the_table_lines_of_a_script_are_kept_and_a_failure_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("table.sh"),
            "echo '16 runs in out'\necho\necho '| a | b |'\necho '| --- | --- |'\necho '| 1 | 2 |'\n",
        )
        .unwrap();
        std::fs::write(dir.path().join("none.sh"), "echo 'no table'\n").unwrap();
        std::fs::write(dir.path().join("fails.sh"), "echo '| a |'\nexit 3\n").unwrap();
        let sh = Interpreter {
            program: "sh".into(),
            executable: "sh".into(),
            version: "-".into(),
            magbench: "-".into(),
            module: "-".into(),
        };
        let run = |s: &'static str| PythonRun {
            script: s,
            args: vec!["x".into()],
            root: dir.path(),
            echo: false,
            magbench: None,
        };
        assert_eq!(
            run_python(&sh, &run("table.sh")).unwrap(),
            "| a | b |\n| --- | --- |\n| 1 | 2 |\n"
        );
        assert_eq!(
            run("table.sh").command_line(),
            "$MAGBENCH_PYTHON table.sh x"
        );
        let none = run_python(&sh, &run("none.sh")).unwrap_err();
        assert!(matches!(none, PythonError::NoTable { .. }), "{none}");
        let fails = magbench::Error::from(run_python(&sh, &run("fails.sh")).unwrap_err());
        assert_eq!(fails.exit_code(), 1);
        assert!(fails.to_string().contains("failed"), "{fails}");
    }
}
