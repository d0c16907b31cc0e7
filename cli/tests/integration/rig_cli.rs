//! `magbench rig` command-line behaviour that needs no host loop: rig-file validation exit codes,
//! and `rig redetect` on frames the emulator recorded (with the truth).

use std::path::Path;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_magbench");

fn rig_file() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../rigs/emulator.toml")
}

#[test]
fn a_bad_rig_file_exits_2_naming_file_field_and_reason() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    let text = std::fs::read_to_string(rig_file())
        .unwrap()
        .replace("slew_a_per_s = 1000.0", "slew_a_per_s = -3.0");
    std::fs::write(&bad, text).unwrap();
    let out = Command::new(BIN)
        .args(["rig", "check", "--rig"])
        .arg(&bad)
        .arg("open-field")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(&format!(
            "{}: coil.limits.slew_a_per_s: must be in (0, 20000000] A/s",
            bad.display()
        )),
        "{stderr}"
    );
    let out = Command::new(BIN)
        .args(["rig", "emulate", "--rig"])
        .arg(rig_file())
        .args(["open-field", "--faults", "fire=1"])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn redetect_reruns_detection_on_recorded_frames() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    // one second of frames, no host: the emulator records and stops by itself
    let out = Command::new(BIN)
        .args(["rig", "emulate", "--rig"])
        .arg(rig_file())
        .args([
            "micro-factory",
            "--speed",
            "10",
            "--duration",
            "1",
            "--record",
        ])
        .arg(&frames)
        .arg("--log")
        .arg(dir.path().join("log.csv"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let det = dir.path().join("det.csv");
    let out = Command::new(BIN)
        .args(["rig", "redetect", "--rig"])
        .arg(rig_file())
        .arg(&frames)
        .arg("--out")
        .arg(&det)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("frames       60"), "{stdout}");
    assert!(stdout.contains("(0 missed)"), "{stdout}");
    let rms: f64 = stdout
        .split("RMS ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(rms < 0.25, "replay error {rms} px");
    assert_eq!(std::fs::read_to_string(&det).unwrap().lines().count(), 61);
}
