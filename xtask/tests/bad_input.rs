//! `cargo xtask` on bad input: exit 2 naming the option or file, the field and the reason.

use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_xtask");

/// Runs `xtask ARGS` and returns its exit code and stderr.
fn xtask(args: &[&str]) -> (Option<i32>, String) {
    let out = Command::new(BIN).args(args).output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Asserts that `xtask ARGS` exits 2 with every one of `parts` in its stderr, and no panic.
fn refused(args: &[&str], parts: &[&str]) {
    let (code, stderr) = xtask(args);
    assert_eq!(code, Some(2), "{args:?}: stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    for p in parts {
        assert!(stderr.contains(p), "{args:?}: {p:?} missing from: {stderr}");
    }
}

#[test]
fn stale_refuses_a_file_that_is_not_a_generated_file() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("guide.md");
    std::fs::write(&file, "a table typed by hand\n").unwrap();
    let d = dir.path().display().to_string();
    refused(
        &["stale", "--dir", &d],
        &[&format!(
            "{}: header: line 1: expected the mark",
            file.display()
        )],
    );
}

#[test]
fn unknown_measurements_are_refused_by_name() {
    refused(
        &["measure", "--only", "nope"],
        &[
            "<command line>",
            "--only: ",
            "no measurement \"nope\"",
            "seed-metric",
        ],
    );
    if !cfg!(feature = "ompl") {
        refused(
            &["measure", "--only", "vs-ompl"],
            &["--only: ", "vs-ompl needs a build with --features ompl"],
        );
    }
}
