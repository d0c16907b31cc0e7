//! `magbench calibrate bench`: a tiny run writes a row per rig × parameter and the summary; the
//! same seed gives the same CSV on 1 and 2 threads; a bad ranges file or option exits 2 naming
//! the file or option, the field and the reason.

use std::path::Path;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_magbench");

/// Parameters scored for open-field's two agents: moment and drag each, two gradient gains,
/// the bias, two drifts, two coil τ, the latency and the noise.
const PARAMS: usize = 2 * 2 + 2 + 1 + 2 + 2 + 1 + 1;

/// Runs magbench; (exit code, stdout, stderr).
fn magbench(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(BIN).args(args).output().expect("run magbench");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `calibrate bench` of 2 rigs, 20 s each, seed 7, on `threads` threads into `out`.
fn tiny(out: &Path, threads: &str) -> String {
    let (code, stdout, err) = magbench(&[
        "calibrate",
        "bench",
        "--out",
        &out.display().to_string(),
        "--rigs",
        "2",
        "--duration",
        "20",
        "--seed",
        "7",
        "--threads",
        threads,
    ]);
    assert_eq!(code, 0, "{err}");
    stdout
}

#[test]
fn a_tiny_run_writes_a_row_per_rig_and_parameter_and_the_summary() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bench");
    let stdout = tiny(&out, "2");
    let mut rd = csv::Reader::from_path(out.join("calibration-bench.csv")).unwrap();
    let head = rd.headers().unwrap().clone();
    let col = |c: &str| head.iter().position(|h| h == c).unwrap();
    let (rig, param, status) = (col("rig"), col("parameter"), col("status"));
    let rows: Vec<csv::StringRecord> = rd.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), 2 * PARAMS);
    for r in 0..2 {
        let mine: Vec<_> = rows.iter().filter(|x| x[rig] == r.to_string()).collect();
        assert_eq!(mine.len(), PARAMS, "rig {r}");
        for name in [
            "moment[1]",
            "coil_lag.field_tau_ms",
            "camera.latency.frames",
        ] {
            assert!(mine.iter().any(|x| &x[param] == name), "rig {r}: {name}");
        }
    }
    for x in &rows {
        assert!(
            ["fitted", "not identified", "rig failed"].contains(&&x[status]),
            "{x:?}"
        );
        if &x[status] != "fitted" {
            assert!(!x[col("reason")].is_empty(), "a reason: {x:?}");
        }
    }
    let md = std::fs::read_to_string(out.join("calibration-bench.md")).unwrap();
    assert!(
        md.starts_with("| parameter | tolerance | within tolerance |"),
        "{md}"
    );
    let tables: Vec<Vec<&str>> = md
        .split("\n\n")
        .map(|b| {
            b.lines()
                .filter(|l| l.starts_with("| "))
                .collect::<Vec<_>>()
        })
        .filter(|t| !t.is_empty())
        .collect();
    assert_eq!(tables[0].len(), 2 + PARAMS, "a row per parameter: {md}");
    assert!(tables[1][0].contains("tracking RMS"), "{md}");
    assert_eq!(tables[1].len(), 2 + 2, "a row per rig: {md}");
    // each rig's held-out check as the CSV's prediction errors say, and the fits calibrate
    // warns not to use counted
    let (fitted_rms, base_rms) = (col("held_out_fitted_rms_bl"), col("held_out_base_rms_bl"));
    let mut warned = 0;
    let mut fitted = 0;
    for r in 0..2 {
        let x = rows.iter().find(|x| x[rig] == r.to_string()).unwrap();
        let expected = if &x[status] == "rig failed" {
            "–"
        } else if x[fitted_rms].is_empty() {
            "cannot tell"
        } else if x[fitted_rms].parse::<f64>().unwrap() < x[base_rms].parse::<f64>().unwrap() {
            "better"
        } else {
            "no better"
        };
        if expected != "–" {
            fitted += 1;
        }
        if expected == "cannot tell" || expected == "no better" {
            warned += 1;
        }
        let cells: Vec<&str> = tables[1][2 + r].split(" | ").collect();
        assert!(cells[3].starts_with(expected), "rig {r}: {expected}: {md}");
    }
    assert!(
        md.contains(&format!("warns not to use (held-out predictions no better than the base's, or a check that cannot tell): {warned} of {fitted} rigs fitted")),
        "{md}"
    );
    // the errors within two of their own standard errors, as the CSV's error_in_se says
    let z = col("error_in_se");
    let with_se: Vec<f64> = rows
        .iter()
        .filter(|x| !x[z].is_empty())
        .map(|x| x[z].parse::<f64>().unwrap())
        .collect();
    let covered = with_se.iter().filter(|z| z.abs() <= 2.0).count();
    assert!(
        md.contains(&format!(
            "within 2 of the fit's own standard errors: {covered} of {} values",
            with_se.len()
        )),
        "{md}"
    );
    assert!(stdout.contains(md.lines().nth(2).unwrap()), "{stdout}");
    assert!(out.join("calibration-bench.svg").is_file());
    assert!(out.join("calibration-bench.png").is_file());
}

#[test]
fn the_same_seed_gives_the_same_csv_at_1_and_2_threads() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("t1"), dir.path().join("t2"));
    tiny(&a, "1");
    tiny(&b, "2");
    let read = |d: &Path| std::fs::read(d.join("calibration-bench.csv")).unwrap();
    assert!(read(&a) == read(&b), "the CSVs differ");
}

#[test]
fn a_bad_ranges_file_exits_2_naming_the_file_the_field_and_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out").display().to_string();
    for (text, field, reason) in [
        ("noise_bl = [0.08, 0.005]\n", "noise_bl", "[low, high]"),
        ("moment = [0.0, 1.3]\n", "moment", "must be in [0.1, 10]"),
        (
            "interface_share = 1.5\n",
            "interface_share",
            "must be in [0, 1]",
        ),
        (
            "latncy_frames = [0.0, 4.0]\n",
            "latncy_frames",
            "did you mean `latency_frames`",
        ),
        (
            "field_tau_ms = [0.0, 40.0]\n",
            "field_tau_ms",
            "must be in (0, 1000]",
        ),
        (
            "field_bias_deg = [-60.0, 2.0]\n",
            "field_bias_deg",
            "must be in [-45, 45]",
        ),
    ] {
        let file = dir.path().join("ranges.toml");
        std::fs::write(&file, text).unwrap();
        let name = file.display().to_string();
        let (code, _, err) = magbench(&["calibrate", "bench", "--out", &out, "--ranges", &name]);
        assert_eq!(code, 2, "{text}: {err}");
        assert!(
            err.contains(&format!("{name}: {field}: ")) && err.contains(reason),
            "{text}: {err}"
        );
    }
    assert!(!dir.path().join("out").exists(), "nothing written");
}

#[test]
fn a_bad_option_exits_2_naming_the_option_and_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out").display().to_string();
    for (opt, value, reason) in [
        ("--rigs", "0", "must be in [1, 1000]"),
        ("--duration", "nan", "must be in (0, 3600]"),
        ("--duration", "0", "must be in (0, 3600]"),
        ("--threads", "0", "must be in [1,"),
        ("--segment-frames", "0", "must be in [1, 600]"),
    ] {
        let (code, _, err) = magbench(&["calibrate", "bench", "--out", &out, opt, value]);
        assert_eq!(code, 2, "{opt} {value}: {err}");
        assert!(
            err.contains(&format!("<command line>: {opt}: ")) && err.contains(reason),
            "{opt} {value}: {err}"
        );
    }
}
