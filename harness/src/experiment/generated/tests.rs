//! `[[generated]]` tables: expansion, labels, and errors naming the table's field.

use std::path::Path;

use super::*;
use crate::experiment::Experiment;
use crate::run::real::RealExecutor;

fn parse(text: &str) -> Result<Experiment, InputError> {
    Experiment::parse(
        text,
        "x.toml",
        Path::new("."),
        "x",
        &RealExecutor::default(),
    )
}

const HEAD: &str = "planners = [\"goal-zoom-rrt\"]\nseeds = 2\n[limits]\niterations = 1000\n";

#[test]
fn a_table_expands_into_the_grid_times_the_instance_seeds() {
    let e = parse(&format!(
        "scenarios = [\"open-field\"]\n{HEAD}\
         [[generated]]\nfamily = \"serpentine\"\nparams = {{ walls = [1, 2], gap = 4.0 }}\ninstances = [3, 7]\n\
         [[generated]]\nfamily = \"team\"\ninstances = 1\n"
    ))
    .unwrap();
    let labels: Vec<&str> = e.scenarios.iter().map(|(l, _)| l.as_str()).collect();
    assert_eq!(
        labels,
        [
            "open-field",
            "serpentine-gap=4-walls=1-s3",
            "serpentine-gap=4-walls=1-s7",
            "serpentine-gap=4-walls=2-s3",
            "serpentine-gap=4-walls=2-s7",
            "team-s0",
        ]
    );
    let (_, s) = &e.scenarios[3];
    assert_eq!(s.name, "serpentine-gap=4-walls=2-s3");
    assert_eq!(s.world.obstacles.len(), 2);
    assert_eq!(e.runs().len(), 6 * 2);
    // the same problem as `scenario generate` draws from that seed
    let direct = magbench_env::scenario::generate::generate(
        "t",
        "serpentine",
        &[("walls".into(), "2".into()), ("gap".into(), "4".into())],
        3,
        0,
    )
    .unwrap();
    assert_eq!(s.world, direct.scenario.world);
    assert_eq!(s.start, direct.scenario.start);
}

#[test]
fn the_files_are_kept_in_the_results_folder() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "{HEAD}[[generated]]\nfamily = \"rooms\"\nparams = {{ rooms = [2, 4] }}\ninstances = 2\n"
    );
    keep_files(&text, "x.toml", dir.path()).unwrap();
    let mut names: Vec<String> = std::fs::read_dir(dir.path().join("scenarios"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "rooms-rooms=2-s0.toml",
            "rooms-rooms=2-s1.toml",
            "rooms-rooms=4-s0.toml",
            "rooms-rooms=4-s1.toml"
        ]
    );
    let back = Scenario::load(
        &dir.path()
            .join("scenarios/rooms-rooms=4-s1.toml")
            .display()
            .to_string(),
    )
    .unwrap();
    assert_eq!(back.name, "rooms-rooms=4-s1");
}

#[test]
fn bad_tables_are_refused_naming_the_field() {
    for (table, field, reason) in [
        (
            "family = \"maze\"\ninstances = 1",
            "generated[0].family",
            "unknown family",
        ),
        (
            "family = \"serpentine\"\nparams = { gap = 2 }\ninstances = 1",
            "generated[0].params.gap",
            "turning width",
        ),
        (
            "family = \"serpentine\"\nparams = { gap = [] }\ninstances = 1",
            "generated[0].params.gap",
            "non-empty list",
        ),
        (
            "family = \"serpentine\"\ninstances = 0",
            "generated[0].instances",
            "a count in",
        ),
        (
            "family = \"serpentine\"\ninstances = [-1]",
            "generated[0].instances",
            "whole number",
        ),
        (
            "family = \"serpentine\"\nseeds = 1",
            "generated[0]",
            "seeds",
        ),
        (
            "family = \"serpentine\"\ninstances = 10000\nparams = { walls = [1, 2] }",
            "generated[0]",
            "more than",
        ),
    ] {
        let e = parse(&format!("{HEAD}[[generated]]\n{table}\n")).unwrap_err();
        assert_eq!(e.file, "x.toml");
        assert_eq!(e.field, field, "{table}: {e}");
        assert!(e.reason.contains(reason), "{table}: {e}");
    }
    let e = parse(HEAD).unwrap_err();
    assert!(
        e.field == "scenarios" && e.reason.contains("[[generated]]"),
        "{e}"
    );
}
