//! Presets as files from the outside: `preset show|check`, `track --preset FILE`, a preset file
//! in an experiment, a scenario's medium, and bad files (exit 2 naming file, field and line).

use crate::common;

use common::magbench;

fn shipped(name: &str) -> String {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("../presets/{name}.toml"))
        .display()
        .to_string()
}

#[test]
fn show_prints_a_preset_with_units_by_name_and_by_file() {
    let (code, by_name, stderr) = magbench(&["preset", "show", "hardware"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        by_name.contains("coil_lag") && by_name.contains("6 ms"),
        "{by_name}"
    );
    assert!(by_name.contains("19 µT"), "{by_name}");
    let (code, by_file, _) = magbench(&["preset", "show", &shipped("hardware")]);
    assert_eq!(code, 0);
    assert_eq!(by_file, by_name);
    let (code, list, _) = magbench(&["preset", "list"]);
    assert_eq!(code, 0);
    assert_eq!(list.lines().count(), 3, "{list}");
    let (code, ok, _) = magbench(&["preset", "check", &shipped("realistic")]);
    assert_eq!(code, 0);
    assert!(ok.contains(": ok (realistic"), "{ok}");
}

#[test]
fn bad_preset_files_exit_2_naming_file_field_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "range.toml",
            "name = \"lab\"\n\n[coil_lag]\nenabled = true\nfield_tau_ms = -3.0\ngradient_tau_ms = 1.0\nfield_slew_mt_per_s = 0.0\ngradient_slew_mt_per_m_per_s = 0.0\n",
            "coil_lag.field_tau_ms",
            "(line 5)",
        ),
        (
            "unknown.toml",
            "name = \"lab\"\n[hydrodynamics]\nenabled = true\nstrength = 2.0\n",
            "hydrodynamics",
            "(line 4)",
        ),
        (
            "type.toml",
            "name = \"lab\"\n[camera]\nfps = \"fast\"\n",
            "camera.fps",
            "(line 3)",
        ),
        ("syntax.toml", "name = \"lab\n", "", "invalid TOML"),
    ];
    for (file, text, field, reason) in cases {
        let path = dir.path().join(file);
        std::fs::write(&path, text).unwrap();
        let p = path.to_str().unwrap();
        for args in [
            vec!["preset", "show", p],
            vec!["preset", "check", p],
            vec!["track", "open-field", "--tracker", "obc", "--preset", p],
        ] {
            let (code, _, stderr) = magbench(&args);
            assert_eq!(code, 2, "{args:?}: {stderr}");
            assert!(
                stderr.contains(&format!("{p}: {field}")) && stderr.contains(reason),
                "{args:?}: {stderr}"
            );
        }
    }
    let (code, _, stderr) =
        magbench(&["track", "open-field", "--tracker", "obc", "--preset", "lab"]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("--preset") && stderr.contains("lab"),
        "{stderr}"
    );
}

#[test]
fn a_preset_file_drives_track_and_an_experiment() {
    let dir = tempfile::tempdir().unwrap();
    // the realistic preset as a lab's file, renamed
    let text = std::fs::read_to_string(shipped("realistic"))
        .unwrap()
        .replace("name = \"realistic\"", "name = \"lab\"");
    let preset = dir.path().join("lab.toml");
    std::fs::write(&preset, &text).unwrap();
    let p = preset.to_str().unwrap();
    let track = |preset: &str| {
        let (code, stdout, stderr) = magbench(&[
            "track",
            "open-field",
            "--tracker",
            "obc",
            "--seed",
            "2",
            "--max-iters",
            "3000",
            "--preset",
            preset,
            "--json",
        ]);
        assert_eq!(code, 0, "{stderr}");
        serde_json::from_str::<serde_json::Value>(&stdout).unwrap()
    };
    let (file, builtin) = (track(p), track("realistic"));
    assert_eq!(file["preset"], "lab");
    for k in [
        "rms_error_bl",
        "rms_error_true_bl",
        "rms_error_sync_bl",
        "rms_error_node_bl",
        "ticks",
    ] {
        assert_eq!(
            file[k], builtin[k],
            "{k}: the same preset gives the same run"
        );
    }
    // an experiment names the file relative to itself
    std::fs::write(
        dir.path().join("e.toml"),
        "name = \"e\"\nscenarios = [\"open-field\"]\nplanners = [\"goal-zoom-rrt\"]\ntrackers = [\"obc\"]\npresets = [\"lab.toml\", \"hardware\"]\nseeds = 1\n[limits]\niterations = 3000\n",
    )
    .unwrap();
    let out = dir.path().join("results");
    let (code, _, stderr) = magbench(&[
        "bench",
        dir.path().join("e.toml").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let runs = std::fs::read_to_string(out.join("runs.csv")).unwrap();
    assert!(
        runs.contains("lab.toml") && runs.contains("hardware"),
        "{runs}"
    );
    // the node error (the seed's) is a column of every tracked run, never below the
    // team-synchronous error of the same frames
    let mut rd = csv::Reader::from_reader(runs.as_bytes());
    let h = rd.headers().unwrap().clone();
    let col = |name: &str| h.iter().position(|c| c == name).expect(name);
    let (node, node_true, sync) = (
        col("rms_error_node_bl"),
        col("rms_error_node_true_bl"),
        col("rms_error_sync_bl"),
    );
    for row in rd.records() {
        let row = row.unwrap();
        let x = |c: usize| row[c].parse::<f64>().unwrap();
        assert!(x(node) >= x(sync) && x(node_true) > 0.0, "{row:?}");
    }
    // a bad preset in an experiment: exit 2 naming the experiment's field
    std::fs::write(dir.path().join("bad.toml"), "name = \"\"\n").unwrap();
    std::fs::write(
        dir.path().join("e2.toml"),
        "scenarios = [\"open-field\"]\nplanners = [\"goal-zoom-rrt\"]\ntrackers = [\"obc\"]\npresets = [\"bad.toml\"]\nseeds = 1\n[limits]\niterations = 100\n",
    )
    .unwrap();
    let (code, _, stderr) = magbench(&[
        "bench",
        dir.path().join("e2.toml").to_str().unwrap(),
        "--dry-run",
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("presets[0]") && stderr.contains("name: must not be empty"),
        "{stderr}"
    );
}

#[test]
fn a_scenario_medium_is_validated() {
    let dir = tempfile::tempdir().unwrap();
    let base = "name = \"s\"\n[world]\nwidth = 20.0\nheight = 20.0\n[start]\nagents = [[8.0, 10.0], [12.0, 10.0]]\n[goal]\nagents = [[8.0, 12.0], [12.0, 12.0]]\ntolerance = 0.5\n";
    let good = dir.path().join("good.toml");
    std::fs::write(&good, format!("{base}[medium]\nkind = \"bulk\"\n")).unwrap();
    let (code, _, stderr) = magbench(&["scenario", "check", good.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    let bad = dir.path().join("bad.toml");
    std::fs::write(
        &bad,
        format!(
            "{base}[medium]\nkind = \"interface\"\nsurface_tension_mn_per_m = 72.0\nliquid_density_kg_per_m3 = 1000.0\nagent_density_kg_per_m3 = 1200.0\ncontact_angle_deg = 180.0\ncontact_angle_spread_deg = 0.0\n"
        ),
    )
    .unwrap();
    let (code, _, stderr) = magbench(&["scenario", "check", bad.to_str().unwrap()]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("medium.contact_angle_deg") && stderr.contains("(line 15)"),
        "{stderr}"
    );
}
