//! examples/plugin-crate, built outside the checkout as a user builds a plugin: copied to a
//! temporary folder, its `magbench` dependency pointed at this checkout, built with cargo, and
//! its experiment run by its own binary. The plugin's planner and tracker must be in the rows,
//! the plots and the report beside the built-ins.
//!
//! Skipped (with the reason printed) only when cargo cannot be run. The build goes to a
//! target folder under `target/tmp/` that is kept between runs, so a second run is incremental,
//! or to the folder `MAGBENCH_PLUGIN_TARGET_DIR` names. CI names the workspace's own `target/`
//! and runs this test binary directly after `cargo test`, so the plugin's build reuses the
//! dependencies the tests compiled (under `cargo test` that folder is locked, and a build in it
//! would wait forever); magbench's own crates are compiled again, from outside their workspace.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

/// The plugin's planner and tracker names, as its main.rs registers them.
const PLANNER: &str = "plain-rrt";
const TRACKER: &str = "com-p";

/// Build outputs and results, left out of the copy.
const NOT_COPIED: [&str; 3] = ["target", "results", "Cargo.lock"];

/// The features and profile with which `cargo test --workspace` compiles magbench's crates and
/// their dependencies, given to the copied manifest so that a build into the workspace's target
/// folder (`MAGBENCH_PLUGIN_TARGET_DIR`, as CI runs this test) reuses them and compiles only the
/// plugin: the command line's tests turn on `print`, the benches crate's criterion serde's
/// `alloc`; the workspace's members keep line tables and `moxcms`/`pxfm` are not optimised
/// (../../Cargo.toml). Neither changes what the plugin does.
const SERDE_AS_THE_TESTS: &str = r#"serde = { version = "1", features = ["alloc"] }"#;

/// magbench's crates, the workspace's members: they keep line tables in its dev profile.
const OWN_CRATES: [&str; 9] = [
    "magbench",
    "magbench-env",
    "magbench-planners",
    "magbench-trackers",
    "magbench-drivers",
    "magbench-analysis",
    "magbench-plot",
    "magbench-store",
    "magbench-harness",
];

/// The profile lines of [`SERDE_AS_THE_TESTS`], for the end of the manifest.
fn profile_as_the_tests() -> String {
    let own = OWN_CRATES
        .iter()
        .map(|c| format!("[profile.dev.package.{c}]\ndebug = \"line-tables-only\"\n"));
    let unoptimised = ["moxcms", "pxfm"]
        .iter()
        .map(|c| format!("[profile.dev.package.{c}]\nopt-level = 0\n"));
    std::iter::once("\n".to_string())
        .chain(own)
        .chain(unoptimised)
        .collect()
}

/// The text of every SVG under `dir`.
fn svg_text(dir: &Path) -> String {
    let mut text = String::new();
    for entry in std::fs::read_dir(dir).into_iter().flatten() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            text += &svg_text(&path);
        } else if path.extension().is_some_and(|e| e == "svg") {
            text += &std::fs::read_to_string(&path).unwrap();
        }
    }
    text
}

/// The cargo that runs this test, if it can be run.
fn cargo() -> Option<PathBuf> {
    let cargo = PathBuf::from(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()));
    let ok = Command::new(&cargo)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    ok.then_some(cargo)
}

/// Runs `cmd`; panics with its output unless it succeeds; returns its stdout.
fn run(cmd: &mut Command, what: &str) -> String {
    let o = cmd.output().unwrap_or_else(|e| panic!("{what}: {e}"));
    assert!(
        o.status.success(),
        "{what} failed ({}):\n{}\n{}",
        o.status,
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8(o.stdout).unwrap()
}

#[test]
fn a_plugin_crate_outside_the_workspace_is_benchmarked_beside_the_built_ins() {
    let Some(cargo) = cargo() else {
        let why = "cargo cannot be run here (set CARGO or put cargo on PATH)";
        assert!(
            std::env::var_os("MAGBENCH_REQUIRE_TOOLS").is_none(),
            "MAGBENCH_REQUIRE_TOOLS is set but {why}"
        );
        eprintln!("skipped: {why}");
        return;
    };
    let cli = Path::new(env!("CARGO_MANIFEST_DIR"));
    let root = cli.parent().unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let crate_dir = tmp.path().join("my-plugin");
    common::copy_dir(&root.join("examples/plugin-crate"), &crate_dir, &NOT_COPIED);

    // point the dependency at this checkout, by absolute path
    let manifest = crate_dir.join("Cargo.toml");
    let text = std::fs::read_to_string(&manifest).unwrap();
    let relative = r#"magbench = { path = "../../cli" }"#;
    assert!(
        text.contains(relative),
        "examples/plugin-crate/Cargo.toml must depend on {relative}"
    );
    let absolute = format!(
        "magbench = {{ path = {:?}, features = [\"print\"] }}\n{SERDE_AS_THE_TESTS}",
        cli.display().to_string()
    );
    let text = text.replace(relative, &absolute) + &profile_as_the_tests();
    std::fs::write(&manifest, text).unwrap();
    // the workspace's lock file: the same dependency versions, no registry look-ups
    std::fs::copy(root.join("Cargo.lock"), crate_dir.join("Cargo.lock")).unwrap();

    let target = match std::env::var_os("MAGBENCH_PLUGIN_TARGET_DIR") {
        Some(dir) => PathBuf::from(dir),
        None => Path::new(env!("CARGO_TARGET_TMPDIR")).join("plugin-crate-target"),
    };
    run(
        Command::new(&cargo)
            .arg("build")
            .current_dir(&crate_dir)
            .env("CARGO_TARGET_DIR", &target),
        "cargo build of the plugin crate",
    );
    let bin = target
        .join("debug")
        .join(format!("my-magbench{}", std::env::consts::EXE_SUFFIX));

    // every subcommand, the plugin's planner listed beside the built-ins
    let list = run(
        Command::new(&bin).args(["plan", "--list"]),
        "my-magbench plan --list",
    );
    for name in [PLANNER, "goal-zoom-rrt", "sst"] {
        assert!(
            list.lines().any(|l| l == name),
            "{name} not listed:\n{list}"
        );
    }

    // its experiment, by its own binary
    let out = tmp.path().join("results");
    run(
        Command::new(&bin)
            .args(["bench", "experiments/plugin.toml", "--quiet", "--out"])
            .arg(&out)
            .current_dir(&crate_dir),
        "my-magbench bench experiments/plugin.toml",
    );

    let mut rd = csv::Reader::from_path(out.join("runs.csv")).unwrap();
    let header = rd.headers().unwrap().clone();
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let (planner, tracker, status, error) = (
        col("planner_name"),
        col("tracker"),
        col("status"),
        col("error"),
    );
    let rows: Vec<csv::StringRecord> = rd.records().map(Result::unwrap).collect();
    let count = |f: &dyn Fn(&csv::StringRecord) -> bool| rows.iter().filter(|r| f(r)).count();
    assert_eq!(rows.len(), 9 + 2 * 2 * 3, "planning runs and tracked runs");
    assert_eq!(
        count(&|r| &r[planner] == PLANNER && r[tracker].is_empty()),
        6
    );
    assert_eq!(count(&|r| &r[tracker] == TRACKER), 6);
    assert_eq!(
        count(&|r| &r[planner] == PLANNER && &r[tracker] == TRACKER),
        3
    );
    for r in &rows {
        assert!(
            &r[status] != "crash" && r[error].is_empty(),
            "a run failed: {r:?}"
        );
    }
    // the plugin's planner solves open-field within the limits at least once
    assert!(count(&|r| &r[planner] == PLANNER && &r[status] == "exact") > 0);

    // its series in the plots and the report
    let svgs = svg_text(&out.join("plots"));
    assert!(!svgs.is_empty(), "no plots in {}", out.display());
    for name in [PLANNER, TRACKER, "goal-zoom-rrt", "obc"] {
        assert!(svgs.contains(name), "no plot mentions {name}");
    }
    let report = std::fs::read_to_string(out.join("report.html")).unwrap();
    for name in [PLANNER, TRACKER] {
        assert!(report.contains(name), "report.html does not mention {name}");
    }
}
