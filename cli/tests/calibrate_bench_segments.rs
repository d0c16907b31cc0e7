//! The segment length of `magbench calibrate`, chosen on the calibration benchmark: the
//! book's three benchmarks (seed 0, seed 1 and bulk liquid with hydrodynamic interaction, 20
//! rigs of 90 s each) run with segments of 40, 60 and 80 frames, each row counting the values
//! within tolerance, the gradient gains within theirs, the values the fit would not pin
//! (not identified or imprecise), and the written values whose error is within two of the
//! fit's own standard errors.
//!
//! `cargo test --release -p magbench --test calibrate_bench_segments -- --ignored --nocapture`
//! (about 20 minutes on 2 cores); `cargo xtask measure --only calibration-bench-segments` keeps
//! the table (docs/calibration.md, "The fit").

use std::path::Path;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_magbench");

/// The segment lengths compared (frames).
const FRAMES: [usize; 3] = [40, 60, 80];

/// The benchmarks: a name and the options that select it.
const BENCHMARKS: [(&str, &[&str]); 3] = [
    ("seed 0", &[]),
    ("seed 1", &["--seed", "1"]),
    (
        "bulk with hydrodynamic interaction",
        &["--ranges", "docs/calibration/bench-bulk-hydro.toml"],
    ),
];

/// One benchmark's counts.
struct Counts {
    values: usize,
    within: usize,
    gains: usize,
    gains_within: usize,
    not_pinned: usize,
    written: usize,
    covered: usize,
}

/// Counts the rows of a benchmark's CSV.
fn counts(csv: &Path) -> Counts {
    let mut rd = csv::Reader::from_path(csv).unwrap();
    let head = rd.headers().unwrap().clone();
    let col = |c: &str| head.iter().position(|h| h == c).unwrap();
    let (param, status, within, in_se) = (
        col("parameter"),
        col("status"),
        col("within_tolerance"),
        col("error_in_se"),
    );
    let mut c = Counts {
        values: 0,
        within: 0,
        gains: 0,
        gains_within: 0,
        not_pinned: 0,
        written: 0,
        covered: 0,
    };
    for row in rd.records().map(Result::unwrap) {
        let ok = &row[within] == "true";
        c.values += 1;
        c.within += usize::from(ok);
        if row[param].starts_with("gradient_gain") {
            c.gains += 1;
            c.gains_within += usize::from(ok);
        }
        c.not_pinned += usize::from(matches!(&row[status], "not identified" | "imprecise"));
        if let Ok(e) = row[in_se].parse::<f64>() {
            c.written += 1;
            c.covered += usize::from(e.abs() <= 2.0);
        }
    }
    c
}

#[test]
#[ignore = "twenty minutes of release-build fits; run by `cargo xtask measure`"]
fn segment_lengths_on_the_three_benchmarks() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let dir = tempfile::tempdir().unwrap();
    println!(
        "| benchmark | segment frames | values within tolerance | gradient gains within 5% | not identified or imprecise | errors within 2 SE |"
    );
    println!("| --- | --- | --- | --- | --- | --- |");
    for (name, opts) in BENCHMARKS {
        for frames in FRAMES {
            let out = dir
                .path()
                .join(format!("{}-{frames}", name.replace(' ', "-")));
            let frames_arg = frames.to_string();
            let mut args = vec![
                "calibrate",
                "bench",
                "--out",
                out.to_str().unwrap(),
                "--threads",
                "2",
                "--segment-frames",
                &frames_arg,
            ];
            args.extend_from_slice(opts);
            let run = Command::new(BIN)
                .args(&args)
                .current_dir(root)
                .output()
                .unwrap();
            assert!(
                run.status.success(),
                "{args:?}: {}",
                String::from_utf8_lossy(&run.stderr)
            );
            let c = counts(&out.join("calibration-bench.csv"));
            println!(
                "| {name} | {frames} | {} of {} | {} of {} | {} | {} of {} |",
                c.within, c.values, c.gains_within, c.gains, c.not_pinned, c.covered, c.written
            );
        }
    }
}
