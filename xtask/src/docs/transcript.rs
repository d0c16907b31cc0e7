//! Running a transcript measurement: magbench command lines run one after another, as
//! subprocesses of this binary, in a fresh temporary directory that holds the repository files
//! the commands read; their stdout becomes a console block (each command as a `$ magbench …`
//! line followed by its output) and a table of each command's wall time.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use thiserror::Error;

use magbench::table::{Table, num};

/// One step of a transcript.
#[derive(Debug, Clone, Copy)]
pub enum Step {
    /// `magbench ARGS` run to its end; its stdout is kept.
    Run(&'static str),
    /// `magbench ARGS` started in the background (shown with a trailing `&`, its output not
    /// kept) and ended when the transcript ends; the next step starts once the file `ready`
    /// (relative to the working folder) exists.
    Background {
        /// The arguments.
        command: &'static str,
        /// A file the command writes when it is ready.
        ready: &'static str,
    },
}

/// Why a transcript failed.
#[derive(Debug, Error)]
pub enum TranscriptError {
    /// The temporary folder could not be set up.
    #[error("{path}: {source}")]
    Setup {
        /// The file or folder.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// A command could not be started or read.
    #[error("`magbench {command}`: {source}")]
    Spawn {
        /// The command's arguments.
        command: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// A command failed.
    #[error("`magbench {command}` failed ({status}): {stderr}")]
    Exit {
        /// The command's arguments.
        command: String,
        /// Its exit status.
        status: std::process::ExitStatus,
        /// The end of its stderr.
        stderr: String,
    },
    /// A background command did not write its ready file in time, or ended first.
    #[error("`magbench {command}` did not write {ready} within {secs} s")]
    NotReady {
        /// The command's arguments.
        command: String,
        /// The file awaited.
        ready: String,
        /// The time waited, s.
        secs: u64,
    },
}

/// How long a background step may take to write its ready file.
const READY_WITHIN: Duration = Duration::from_secs(120);

/// What one step printed.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// The command's arguments.
    pub command: String,
    /// Whether it ran in the background.
    pub background: bool,
    /// Its stdout (empty for a background step).
    pub output: String,
    /// Its wall time, s (`None` for a background step).
    pub secs: Option<f64>,
}

/// A transcript's body: a `console` block of `$ magbench …` lines, each followed by its
/// output, then a table of each command's wall time.
pub fn format_transcript(entries: &[Entry]) -> String {
    let mut out = String::from("```console\n");
    let mut t = Table::new(&["command", "wall time (s)"]);
    for e in entries {
        let amp = if e.background { " &" } else { "" };
        out.push_str(&format!("$ magbench {}{amp}\n", e.command));
        out.push_str(&e.output);
        if !e.output.is_empty() && !e.output.ends_with('\n') {
            out.push('\n');
        }
        if let Some(s) = e.secs {
            t.row(vec![format!("`magbench {}`", e.command), num(s)]);
        }
    }
    out.push_str("```\n\n");
    out.push_str(&t.markdown());
    out
}

/// `text` with the absolute paths of the working folder `cwd` and the temporary folder `tmp`
/// shown relative: `cwd/x` as `x`, `tmp/x` as `<tmp>/x`.
pub fn normalise(text: &str, cwd: &Path, tmp: &Path) -> String {
    let mut t = text.to_string();
    for (dir, by) in [(cwd, ""), (tmp, "<tmp>/")] {
        t = t.replace(&format!("{}/", dir.display()), by);
    }
    t
}

/// Ends the background steps when the transcript ends, however it ends.
struct Background(Vec<Child>);

impl Drop for Background {
    fn drop(&mut self) {
        for c in &mut self.0 {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

/// Makes `tmp` hold each of `files` (paths relative to `root`; a folder is linked, a file
/// copied) at the same relative path.
fn set_up(root: &Path, tmp: &Path, files: &[&str]) -> Result<(), TranscriptError> {
    let setup = |path: &Path| {
        let path = path.to_path_buf();
        move |source| TranscriptError::Setup { path, source }
    };
    for f in files {
        let from = std::fs::canonicalize(root.join(f)).map_err(setup(&root.join(f)))?;
        let to = tmp.join(f);
        if let Some(parent) = to.parent() {
            std::fs::create_dir_all(parent).map_err(setup(parent))?;
        }
        if from.is_dir() {
            std::os::unix::fs::symlink(&from, &to).map_err(setup(&to))?;
        } else {
            std::fs::copy(&from, &to).map_err(setup(&to))?;
        }
    }
    Ok(())
}

/// Runs `steps` with the `magbench` binary at `magbench` in folder `cwd` (relative to a fresh temporary folder that
/// holds `files` of the repository `root`) and returns what each printed, paths normalised.
pub fn run_transcript(
    root: &Path,
    magbench: &Path,
    files: &[&str],
    cwd: &str,
    steps: &[Step],
) -> Result<Vec<Entry>, TranscriptError> {
    let tmp_dir = tempfile::tempdir().map_err(|source| TranscriptError::Setup {
        path: std::env::temp_dir(),
        source,
    })?;
    let tmp = tmp_dir.path().to_path_buf();
    set_up(root, &tmp, files)?;
    let dir = tmp.join(cwd);
    std::fs::create_dir_all(&dir).map_err(|source| TranscriptError::Setup {
        path: dir.clone(),
        source,
    })?;
    let mut background = Background(vec![]);
    let mut entries = vec![];
    for step in steps {
        let (command, ready) = match *step {
            Step::Run(c) => (c, None),
            Step::Background { command, ready } => (command, Some(ready)),
        };
        let spawn = |source| TranscriptError::Spawn {
            command: command.to_string(),
            source,
        };
        let mut cmd = Command::new(magbench);
        cmd.args(command.split_whitespace())
            .current_dir(&dir)
            .stdin(Stdio::null());
        if let Some(ready) = ready {
            let child = cmd
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .map_err(spawn)?;
            background.0.push(child);
            let t0 = Instant::now();
            while !dir.join(ready).exists() {
                let ended = background
                    .0
                    .last_mut()
                    .and_then(|c| c.try_wait().ok().flatten())
                    .is_some();
                if ended || t0.elapsed() > READY_WITHIN {
                    return Err(TranscriptError::NotReady {
                        command: command.to_string(),
                        ready: ready.to_string(),
                        secs: READY_WITHIN.as_secs(),
                    });
                }
                std::thread::sleep(Duration::from_millis(50));
            }
            entries.push(Entry {
                command: command.to_string(),
                background: true,
                output: String::new(),
                secs: None,
            });
            continue;
        }
        let t0 = Instant::now();
        let mut child = cmd
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(spawn)?;
        // stderr on a thread, so that neither pipe fills while the other is read
        let mut err_pipe = child.stderr.take();
        let err_thread = std::thread::spawn(move || {
            let mut s = String::new();
            if let Some(p) = err_pipe.as_mut() {
                let _ = p.read_to_string(&mut s);
            }
            s
        });
        let mut stdout = String::new();
        if let Some(mut p) = child.stdout.take() {
            p.read_to_string(&mut stdout).map_err(spawn)?;
        }
        let status = child.wait().map_err(spawn)?;
        let stderr = err_thread.join().unwrap_or_default();
        if !status.success() {
            let tail: Vec<&str> = stderr.lines().rev().take(20).collect();
            return Err(TranscriptError::Exit {
                command: command.to_string(),
                status,
                stderr: tail.into_iter().rev().collect::<Vec<_>>().join("\n"),
            });
        }
        entries.push(Entry {
            command: command.to_string(),
            background: false,
            output: normalise(&stdout, &dir, &tmp),
            secs: Some(t0.elapsed().as_secs_f64()),
        });
    }
    drop(background);
    Ok(entries)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_transcript_shows_each_command_then_its_output_and_a_table_of_times() {
        let entries = [
            Entry {
                command: "rig emulate --write-rig live.toml".into(),
                background: true,
                output: String::new(),
                secs: None,
            },
            Entry {
                command: "calibrate exc --out fitted.toml".into(),
                background: false,
                output: "moment[0]  1.08\npreset  fitted.toml".into(),
                secs: Some(4.04),
            },
        ];
        assert_eq!(
            format_transcript(&entries),
            "```console\n\
             $ magbench rig emulate --write-rig live.toml &\n\
             $ magbench calibrate exc --out fitted.toml\n\
             moment[0]  1.08\npreset  fitted.toml\n\
             ```\n\n\
             | command | wall time (s) |\n| --- | --- |\n\
             | `magbench calibrate exc --out fitted.toml` | 4.04 |\n"
        );
    }

    #[test]
    fn temporary_paths_are_shown_relative() {
        let (cwd, tmp) = (Path::new("/tmp/x1/docs/c"), Path::new("/tmp/x1"));
        assert_eq!(
            normalise(
                "log /tmp/x1/docs/c/exc/log.csv, /tmp/x1/rigs/a.toml",
                cwd,
                tmp
            ),
            "log exc/log.csv, <tmp>/rigs/a.toml"
        );
    }

    #[test]
    fn a_failing_command_is_named() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        // the test binary is not magbench: it refuses the arguments and exits non-zero
        let exe = std::env::current_exe().unwrap();
        let steps = [Step::Run("--no-such-flag-x")];
        let err = run_transcript(&root, &exe, &[], ".", &steps).unwrap_err();
        assert!(err.to_string().contains("--no-such-flag-x"), "{err}");
    }
}
