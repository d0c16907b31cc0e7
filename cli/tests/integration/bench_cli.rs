//! `magbench bench` and `magbench merge` on the command line: bad input exits 2 with
//! FILE: FIELD: REASON.

use crate::common;

use std::process::Command;

use common::{magbench, write};

const GOOD: &str =
    "scenarios = [\"open-field\"]\nplanners = [\"fake\"]\nseeds = 2\n[limits]\niterations = 100\n";

#[test]
fn bad_experiments_exit_2_naming_file_field_and_reason() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "unknown key",
            GOOD.replace("seeds = 2", "seeds = 2\ncolour = 1"),
            "colour",
        ),
        (
            "bad planner",
            GOOD.replace("[\"fake\"]", "[\"nope\"]"),
            "planners[0]",
        ),
        (
            "bad param",
            GOOD.replace("[\"fake\"]", "[\"fake{zz=1}\"]"),
            "planners[0]",
        ),
        (
            "bad label",
            GOOD.replace("[\"fake\"]", "[\"fake{k=}\"]"),
            "planners[0]",
        ),
        (
            "bad scenario",
            GOOD.replace("open-field", "no-such-maze"),
            "scenarios[0]",
        ),
        ("no limits", GOOD.replace("iterations = 100", ""), "limits"),
        (
            "zero seeds",
            GOOD.replace("seeds = 2", "seeds = 0"),
            "seeds",
        ),
        (
            "duplicate seed",
            GOOD.replace("seeds = 2", "seeds = [1, 1]"),
            "seeds[1]",
        ),
        (
            "presets without trackers",
            GOOD.replace("seeds = 2", "seeds = 2\npresets = [\"ideal\"]"),
            "presets",
        ),
        (
            "bad preset",
            GOOD.replace(
                "seeds = 2",
                "seeds = 2\ntrackers = [\"fake\"]\npresets = [\"windy\"]",
            ),
            "presets[0]",
        ),
        (
            "iterations beyond the memory budget",
            GOOD.replace("iterations = 100", "iterations = 100000000"),
            "limits.iterations: must be in [1, 2097152] iterations",
        ),
        (
            "negative time",
            GOOD.replace("iterations = 100", "time = -1.0"),
            "limits.time",
        ),
        (
            "bad toml",
            GOOD.replace("seeds = 2", "seeds = "),
            "invalid TOML",
        ),
    ];
    for (what, text, field) in cases {
        let p = write(dir.path(), "bad.toml", &text);
        let (code, _, err) = magbench(&[
            "bench",
            p.to_str().unwrap(),
            "--executor",
            "fake",
            "--out",
            dir.path().join("o").to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{what}: {err}");
        assert!(
            err.contains("bad.toml: ") && err.contains(field),
            "{what}: {err}"
        );
        assert!(
            !dir.path().join("o").exists(),
            "{what}: wrote results for bad input"
        );
    }
    let (code, _, err) = magbench(&["bench", "/no/such/file.toml"]);
    assert_eq!(code, 2, "{err}");
    let p = write(dir.path(), "good.toml", GOOD);
    for bad in ["0/2", "3/2", "x", "1/0"] {
        let (code, _, err) = magbench(&[
            "bench",
            p.to_str().unwrap(),
            "--executor",
            "fake",
            "--shard",
            bad,
        ]);
        assert_eq!(code, 2, "--shard {bad}: {err}");
        assert!(err.contains("--shard"), "{err}");
    }
}

#[test]
fn dry_run_counts_the_matrix_and_merge_rejects_mixed_experiments() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "good.toml", GOOD);
    let (code, out, _) = magbench(&[
        "bench",
        p.to_str().unwrap(),
        "--executor",
        "fake",
        "--dry-run",
    ]);
    assert_eq!(code, 0);
    assert!(out.contains("2 runs"), "{out}");
    let mixed = write(
        dir.path(),
        "mixed.toml",
        &(GOOD.to_string() + "[tracking]\ntrackers = [\"fake\", \"fake{gain=2}\"]\n"),
    );
    let (code, out, err) = magbench(&[
        "bench",
        mixed.to_str().unwrap(),
        "--executor",
        "fake",
        "--dry-run",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("6 runs (1 scenarios × (1 planners' planning runs + 1 tracked planners × 2 tracker/preset combinations) × 2 seeds)"),
        "{out}"
    );
    let q = write(
        dir.path(),
        "other.toml",
        &GOOD.replace("seeds = 2", "seeds = 3"),
    );
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    assert_eq!(
        magbench(&[
            "bench",
            p.to_str().unwrap(),
            "--executor",
            "fake",
            "--quiet",
            "--out",
            a.to_str().unwrap()
        ])
        .0,
        0
    );
    assert_eq!(
        magbench(&[
            "bench",
            q.to_str().unwrap(),
            "--executor",
            "fake",
            "--quiet",
            "--out",
            b.to_str().unwrap()
        ])
        .0,
        0
    );
    let (code, _, err) = magbench(&[
        "merge",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--out",
        dir.path().join("m").to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("differs"), "{err}");
    // a shard of another magbench version is refused, naming its manifest and the versions
    let c = dir.path().join("c");
    std::fs::create_dir(&c).unwrap();
    for f in std::fs::read_dir(&a).unwrap() {
        let f = f.unwrap().path();
        if f.is_file() {
            std::fs::copy(&f, c.join(f.file_name().unwrap())).unwrap();
        }
    }
    let manifest = c.join("manifest.json");
    let mut m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&manifest).unwrap()).unwrap();
    m["magbench_version"] = "0.0.1".into();
    std::fs::write(&manifest, m.to_string()).unwrap();
    let out = dir.path().join("m2");
    let (code, _, err) = magbench(&[
        "merge",
        a.to_str().unwrap(),
        c.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(&manifest.display().to_string()) && err.contains("magbench 0.0.1"),
        "{err}"
    );
    assert!(!out.join("runs.csv").exists(), "nothing merged");
}

/// On a terminal (a real PTY, from util-linux `script`) the progress bar ends its line, so the
/// summary starts a line of its own.
#[test]
fn on_a_terminal_the_summary_follows_the_progress_bar_on_its_own_line() {
    if Command::new("script").arg("--version").output().is_err() {
        let why = "util-linux `script` (a PTY) is not installed";
        assert!(
            std::env::var_os("MAGBENCH_REQUIRE_TOOLS").is_none(),
            "MAGBENCH_REQUIRE_TOOLS is set but {why}"
        );
        eprintln!("skipped: {why}");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let exp = write(
        dir.path(),
        "tty.toml",
        "name = \"tty\"\nscenarios = [\"open-field\"]\nplanners = [\"goal-zoom-rrt\"]\nseeds = 2\n[limits]\niterations = 2000\n",
    );
    let out = dir.path().join("out");
    let cmd = format!(
        "'{}' bench '{}' --out '{}'",
        env!("CARGO_BIN_EXE_magbench"),
        exp.display(),
        out.display()
    );
    let o = Command::new("script")
        .args(["-qec", &cmd, "/dev/null"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{o:?}");
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("runs, ETA"),
        "a progress bar is drawn: {text:?}"
    );
    let summary = text
        .split(['\n', '\r'])
        .find(|l| l.contains("tty: 2 runs in"))
        .unwrap_or_else(|| panic!("no summary: {text:?}"));
    assert!(
        summary.starts_with("tty: 2 runs in"),
        "the summary shares a line with the bar: {summary:?}"
    );
}

/// `results plot --units physical` shows lengths in µm from the scenario's agent diameter, in
/// the report's tables and the plots; `--units bl` (the default) in body lengths.
#[test]
fn results_plot_shows_lengths_in_micrometres_on_request() {
    let dir = tempfile::tempdir().unwrap();
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../results/baseline");
    let copy = dir.path().join("baseline");
    common::copy_dir(&src, &copy, &[]);
    let dir_arg = copy.display().to_string();
    let (code, _, err) = magbench(&["results", "plot", &dir_arg, "--units", "physical"]);
    assert_eq!(code, 0, "{err}");
    let html = std::fs::read_to_string(copy.join("report.html")).unwrap();
    assert!(html.contains("1 BL = 500 µm"), "the scale is stated");
    assert!(html.contains("RMS error, observed (µm)"));
    assert!(!html.contains("RMS error, observed (BL)"));
    let cdf = std::fs::read_to_string(copy.join("plots/open-field/rms-error-cdf.svg")).unwrap();
    assert!(cdf.contains("(µm)"), "the CDF's axis is in µm");
    let (code, _, err) = magbench(&["results", "plot", &dir_arg]);
    assert_eq!(code, 0, "{err}");
    let html = std::fs::read_to_string(copy.join("report.html")).unwrap();
    assert!(html.contains("RMS error, observed (BL)") && !html.contains("1 BL = "));
    let (code, _, err) = magbench(&["results", "plot", &dir_arg, "--units", "furlongs"]);
    assert_eq!(code, 2, "{err}");
}

/// `results plot --figure-size one-column --dpi 200 --pdf` (the `print` feature, which the tests
/// build) writes each figure's PDF and a PNG 3.5 in × 200 dpi = 700 px wide, and the SVG carries
/// the printed width.
#[test]
fn results_plot_writes_print_figures() {
    let dir = tempfile::tempdir().unwrap();
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../results/baseline");
    let copy = dir.path().join("baseline");
    common::copy_dir(&src, &copy, &[]);
    let dir_arg = copy.display().to_string();
    let args = ["results", "plot", &dir_arg, "--figure-size", "one-column"];
    let (code, _, err) = magbench(&[&args[..], &["--dpi", "200", "--pdf"]].concat());
    assert_eq!(code, 0, "{err}");
    let stem = copy.join("plots/open-field/rms-error-cdf");
    let pdf = std::fs::read(stem.with_extension("pdf")).unwrap();
    assert!(pdf.starts_with(b"%PDF-") && pdf.len() > 5_000, "a PDF");
    let png = std::fs::read(stem.with_extension("png")).unwrap();
    let width = u32::from_be_bytes(png[16..20].try_into().unwrap());
    assert_eq!(width, 700, "3.5 in at 200 dpi");
    let svg = std::fs::read_to_string(stem.with_extension("svg")).unwrap();
    assert!(svg.contains("width=\"3.500in\""), "the SVG's printed width");
}

/// `ablate` checks its options before it runs: a bad one exits 2 naming the option, and the
/// results folder it made for the run is removed again.
#[test]
fn ablate_refuses_bad_options_naming_them_and_leaves_no_folder() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("abl");
    let out_arg = out.display().to_string();
    for (args, option) in [
        (vec!["--planner", "nope"], "--planner: unknown planner"),
        (vec!["--tracker", "nope"], "--tracker: unknown tracker"),
        (
            vec!["--seeds", "100000000"],
            "--seeds: must be in [1, 100000] seeds",
        ),
    ] {
        let mut all = vec!["ablate", "--out", &out_arg];
        all.extend(args);
        let (code, _, err) = magbench(&all);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(option), "{err}");
        assert!(!out.exists(), "{} was left behind", out.display());
    }
}

/// The options of this round's commands refuse bad input with exit 2, naming the file or
/// option and the reason.
#[test]
fn suite_preview_and_results_plot_refuse_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing").display().to_string();
    let empty = dir.path().join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let empty = empty.display().to_string();
    let gif = dir.path().join("x.gif").display().to_string();
    for (args, parts) in [
        (
            vec!["bench", "--suite", "no-such-suite", "--dry-run"],
            vec!["suites/no-such-suite/suite.toml", "cannot read"],
        ),
        (
            vec!["scenario", "show", "open-field", "--out", &gif],
            vec!["--out", "must end in .svg or .png"],
        ),
        (
            vec!["results", "plot", &missing],
            vec!["DIR", "not a folder"],
        ),
        (
            vec!["results", "plot", &empty],
            vec!["manifest.json", "cannot read"],
        ),
    ] {
        let (code, _, err) = magbench(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        for p in parts {
            assert!(err.contains(p), "{args:?}: {err}");
        }
        assert!(!err.contains("note: no experiments"), "{err}");
    }
}
