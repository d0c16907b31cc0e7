//! A results folder of mixed team sizes: the per-agent columns of `runs.csv`, the worst-agent
//! and per-agent plots, and the per-agent table of `report.html`.

use crate::common;

use common::{opts, write};
use magbench::experiment::Experiment;
use magbench::run::fake::FakeExecutor;
use magbench::sweep::run_sweep;

#[test]
fn teams_of_three_and_four_get_per_agent_plots_and_tables_and_a_pair_does_not() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(
        dir.path(),
        "teams.toml",
        "name = \"teams\"\nscenarios = [\"open-field\", \"trio-triangle\", \"quad-square\"]\nplanners = [\"fake\"]\ntrackers = [\"fake\"]\npresets = [\"realistic\"]\nseeds = 4\n[limits]\niterations = 300\n",
    );
    let out = dir.path().join("out");
    let e = Experiment::load(&file, &FakeExecutor).unwrap();
    run_sweep(&e, &FakeExecutor, &opts(&out, 2)).unwrap();

    // runs.csv: columns for four agents, filled as far as each run's team goes
    let mut rd = csv::Reader::from_path(out.join("runs.csv")).unwrap();
    let header = rd.headers().unwrap().clone();
    let col = |c: &str| header.iter().position(|h| h == c);
    assert!(col("rms_error_agent3_bl").is_some() && col("rms_error_agent4_bl").is_none());
    for r in rd.records() {
        let r = r.unwrap();
        let n: usize = r[col("agents").unwrap()].parse().unwrap();
        for i in 0..4 {
            let cell = &r[col(&format!("rms_error_agent{i}_bl")).unwrap()];
            assert_eq!(
                cell.is_empty(),
                i >= n,
                "agent {i} of a team of {n}: {cell:?}"
            );
        }
        // the worst agent's RMS is the largest of the agents'
        let worst: f64 = r[col("rms_error_worst_agent_bl").unwrap()].parse().unwrap();
        let max = (0..n)
            .map(|i| {
                r[col(&format!("rms_error_agent{i}_bl")).unwrap()]
                    .parse::<f64>()
                    .unwrap()
            })
            .fold(0.0, f64::max);
        assert_eq!(worst, max);
    }

    let plots = out.join("plots");
    for sc in ["open-field", "trio-triangle", "quad-square"] {
        assert!(
            plots.join(sc).join("rms-error-worst-agent.svg").exists(),
            "{sc}"
        );
        assert!(
            plots
                .join(sc)
                .join("rms-error-true-worst-agent.png")
                .exists(),
            "{sc}"
        );
    }
    assert!(!plots.join("open-field/rms-error-per-agent.svg").exists());
    let per_agent =
        std::fs::read_to_string(plots.join("quad-square/rms-error-per-agent.svg")).unwrap();
    assert!(
        per_agent.contains("agent 4"),
        "the fourth agent's box is missing"
    );

    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("worst agent&#39;s RMS") || html.contains("worst agent's RMS"));
    // one per-agent table per team of three or more, none for the pair
    assert_eq!(html.matches("<h3>Per agent</h3>").count(), 2);
    let open_field = &html
        [html.find("<h2>open-field</h2>").unwrap()..html.find("<h2>trio-triangle</h2>").unwrap()];
    assert!(!open_field.contains("Per agent"));
    let quad = &html[html.find("<h2>quad-square</h2>").unwrap()..];
    assert!(
        quad.contains("agent 4</td>") && quad.contains("worst agent</td>"),
        "no per-agent rows"
    );
}
