//! `magbench scenario` and `magbench stlc` from the outside: output and exit codes.

use crate::common;

use common::magbench;

#[test]
fn scenario_list_names_every_builtin() {
    let (code, out, _) = magbench(&["scenario", "list"]);
    assert_eq!(code, 0);
    for name in [
        "micro-factory",
        "cargo-delivery",
        "open-field",
        "narrow-passage",
    ] {
        assert!(out.contains(name), "{name} missing from:\n{out}");
    }
}

#[test]
fn scenario_check_notes_a_goal_off_the_starts_symmetric_set() {
    // team-30 v1's grid of four (a square, paired 0↔3 and 1↔2 across its centre) to a ring
    // paired otherwise: valid, and reached only through the growth of an asymmetry
    let f = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../suites/team-30/scenarios/team-agents=4-goal=ring-start=grid-s0.toml");
    let f = f.to_str().unwrap();
    let (code, out, err) = magbench(&["scenario", "check", f]);
    assert_eq!(code, 0, "stderr: {err}");
    assert!(out.contains("ok (4 agents"), "{out}");
    assert!(
        err.starts_with("note: ")
            && err.contains("goal.agents")
            && err.contains("0↔3, 1↔2")
            && err.contains("unstable"),
        "{err}"
    );
}

#[test]
fn scenario_check_rejects_a_bad_file_with_exit_2_and_names_file_field_reason() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.toml");
    std::fs::write(
        &path,
        "name = \"bad\"\n[world]\nwidth = 20.0\nheight = 10.0\n[start]\nagents = [[3.0, 5.0], [5.0, 5.0]]\n\
         [goal]\nagents = [[15.0, 5.0], [17.0, 5.0]]\ntolerance = -0.5\n",
    )
    .unwrap();
    let p = path.to_str().unwrap();
    let (code, _, err) = magbench(&["scenario", "check", p]);
    assert_eq!(code, 2, "stderr: {err}");
    assert!(
        err.contains(p) && err.contains("goal.tolerance") && err.contains("> 0"),
        "{err}"
    );
}

#[test]
fn scenario_check_accepts_the_builtin_files() {
    for f in [
        "micro-factory",
        "cargo-delivery",
        "open-field",
        "narrow-passage",
    ] {
        let path = format!("{}/../scenarios/{f}.toml", env!("CARGO_MANIFEST_DIR"));
        let (code, out, err) = magbench(&["scenario", "check", &path]);
        assert_eq!(code, 0, "{f}: {err}");
        assert!(out.contains("ok"));
    }
}

#[test]
fn stlc_table_shows_rank_drop_only_at_multiples_of_90_degrees() {
    let (code, out, _) = magbench(&["stlc", "--r", "2", "--step", "15"]);
    assert_eq!(code, 0);
    let mut rows = 0;
    for line in out.lines() {
        let cols: Vec<&str> = line.split_whitespace().collect();
        let (Some(psi), Some(rank)) = (
            cols.first().and_then(|c| c.parse::<f64>().ok()),
            cols.get(1),
        ) else {
            continue;
        };
        rows += 1;
        let expected = if (psi / 90.0).fract().abs() < 1e-9 {
            "2"
        } else {
            "3"
        };
        assert_eq!(*rank, expected, "ψ = {psi}: {line}");
    }
    assert!(rows >= 13, "{out}");
    let (code, _, err) = magbench(&["stlc", "--r", "0.5"]);
    assert_eq!(code, 2, "{err}");
}
