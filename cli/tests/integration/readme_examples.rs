//! The documentation's examples, run: so that none can go stale.
//!
//! Which commands run (the convention, also in docs/commands.md):
//! - README.md: every line of a ```` ```sh ```` block that starts with `magbench ` — the
//!   set-up-free commands; `cargo`, `pip`, `python` and `cd` lines are set-up and skipped;
//! - docs/*.md: the `magbench ` lines of blocks marked ```` ```sh runnable ````.
//!
//! `magbench` is the built binary; the commands run in order in a scratch folder that links
//! the repository's `experiments`, `scenarios`, `rigs` and `presets`, so what one command
//! writes the next can read. Each runs under a deadline and must exit 0. Some are bounded or
//! skipped, each for a reason that [`adapt`] states and the test prints.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

const BIN: &str = env!("CARGO_BIN_EXE_magbench");

/// Longest one example may take (a debug build on a shared machine).
const DEADLINE: Duration = Duration::from_secs(600);

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The `magbench` command lines of `text` in blocks whose info string `runnable` accepts.
fn commands(text: &str, runnable: impl Fn(&str) -> bool) -> Vec<String> {
    let mut out = vec![];
    let mut inside: Option<bool> = None;
    for line in text.lines() {
        let t = line.trim_start();
        if let Some(info) = t.strip_prefix("```") {
            inside = match inside {
                None => Some(runnable(info.trim())),
                Some(_) => None,
            };
            continue;
        }
        if inside == Some(true) {
            // the command, without its trailing comment
            let cmd = t.split(" #").next().unwrap_or(t).trim();
            if cmd.starts_with("magbench ") {
                out.push(cmd.to_string());
            }
        }
    }
    out
}

/// What the test runs for an example: its arguments (bounded where it would run for long), or
/// the reason it is skipped.
fn adapt(cmd: &str) -> Result<Vec<String>, String> {
    let mut args: Vec<String> = cmd.split_whitespace().skip(1).map(String::from).collect();
    if args
        .iter()
        .any(|a| a.contains('<') || a.contains('$') || a == "|" || a == "&&")
    {
        return Err("a template or a pipeline, not a command".into());
    }
    match args.first().map(String::as_str) {
        Some("bench") if !args.iter().any(|a| a == "--dry-run") => {
            args.push("--dry-run".into());
            Ok(args)
        }
        Some("regress") => Err("compares folders of earlier full bench runs".into()),
        Some("figures") => Err("renders every paper figure: minutes of planning".into()),
        Some("rig") if args.get(1).is_some_and(|a| a == "emulate") => {
            if !args.iter().any(|a| a == "--duration") {
                args.extend(["--duration".into(), "1".into()]);
            }
            Ok(args)
        }
        Some("rig") => Err("needs a running rig or emulator".into()),
        _ => Ok(args),
    }
}

/// Runs `magbench ARGS` in `dir` under the deadline; (exit code, stderr).
fn run(dir: &Path, args: &[String]) -> (Option<i32>, String) {
    let child = Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run magbench");
    match common::wait_with_deadline(child, DEADLINE) {
        Some((status, stderr)) => (status.code(), stderr),
        None => (None, format!("still running after {DEADLINE:?}")),
    }
}

#[test]
fn the_readme_and_runnable_doc_examples_run() {
    let root = repo();
    let mut examples = vec![];
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    for c in commands(&readme, |info| info == "sh" || info.starts_with("sh ")) {
        examples.push(("README.md".to_string(), c));
    }
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    docs.sort();
    for d in docs {
        let text = std::fs::read_to_string(&d).unwrap();
        let name = format!("docs/{}", d.file_name().unwrap().to_string_lossy());
        for c in commands(&text, |info| info.split_whitespace().eq(["sh", "runnable"])) {
            examples.push((name.clone(), c));
        }
    }
    assert!(!examples.is_empty(), "no examples found");
    let dir = tempfile::tempdir().unwrap();
    for link in ["experiments", "scenarios", "rigs", "presets"] {
        std::os::unix::fs::symlink(root.join(link), dir.path().join(link)).unwrap();
    }
    let (mut ran, mut skipped) = (0, 0);
    let mut failures = vec![];
    for (file, cmd) in &examples {
        match adapt(cmd) {
            Err(why) => {
                skipped += 1;
                println!("skipped  {file}: {cmd}  ({why})");
            }
            Ok(args) => {
                ran += 1;
                let (code, stderr) = run(dir.path(), &args);
                println!("exit {code:?}  {file}: magbench {}", args.join(" "));
                if code != Some(0) {
                    failures.push(format!(
                        "{file}: `{cmd}` exited {code:?}: {}",
                        &stderr[stderr.len().saturating_sub(2000)..]
                    ));
                }
            }
        }
    }
    println!("{ran} examples ran, {skipped} skipped");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_convention_picks_commands_and_drops_comments() {
    let text = "```sh\nmagbench plan x   # a comment\ncargo test\n```\n```toml\nmagbench no\n```\n";
    assert_eq!(commands(text, |i| i == "sh"), vec!["magbench plan x"]);
    assert_eq!(
        adapt("magbench bench experiments/x.toml").unwrap(),
        vec!["bench", "experiments/x.toml", "--dry-run"]
    );
    assert!(adapt("magbench regress a b").is_err());
}
