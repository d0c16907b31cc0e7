//! `magbench results formations` on the command line: the formation study's table and figure
//! from a results folder's runs and its generated scenario files, and its refusals.

use std::path::Path;
use std::process::Command;

use magbench::compare::formations::cost_lower_bound;
use magbench::metrics::Metric;
use magbench::results::store::write_runs_atomic;
use magbench::run::RunRecord;
use magbench_env::scenario::generate::generate_named;

/// A square moved 4 BL to a triangle of four: its start is symmetric about its centroid and
/// the goal lies off that set.
const SQUARE_TO_TRIANGLE: &str = "team-agents=4-distance=4-goal=triangle-spacing=1.5-start=ring-s0";
/// A triangle of three moved 4 BL to a ring of three.
const TRIANGLE_TO_RING: &str = "team-agents=3-distance=4-goal=ring-spacing=1.5-start=triangle-s0";

/// Writes the generated scenario of `label` (as a bench keeps it) into `dir/scenarios/` and
/// returns its lower bound on cost.
fn keep(dir: &Path, label: &str) -> f64 {
    let params: Vec<(String, String)> = label
        .split('-')
        .filter_map(|kv| kv.split_once('='))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    let g = generate_named("x.toml", "team", &params, 0, 0, label).unwrap();
    std::fs::create_dir_all(dir.join("scenarios")).unwrap();
    std::fs::write(dir.join("scenarios").join(&g.file_name), &g.text).unwrap();
    let goal = g.scenario.final_goal();
    cost_lower_bound(&g.scenario.start, &goal.agents, goal.tolerance)
}

/// A planning run of `planner` on `label` with `agents`; solved runs take `time` s and cost
/// `cost`.
fn run(label: &str, agents: usize, planner: &str, solved: Option<(f64, f64)>) -> RunRecord {
    let mut r = RunRecord::example();
    r.scenario = label.into();
    r.agents = agents;
    r.planner = planner.into();
    r.solved = solved.is_some();
    if let Some((time, cost)) = solved {
        r.set(Metric::FirstSolutionTime, Some(time));
        r.set(Metric::Cost, Some(cost));
    }
    r
}

fn formations(dir: &Path) -> (i32, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_magbench"))
        .args(["results", "formations"])
        .arg(dir)
        .output()
        .unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn write(dir: &Path, runs: Vec<RunRecord>) {
    let runs: Vec<RunRecord> = runs
        .into_iter()
        .enumerate()
        .map(|(i, mut r)| {
            r.run = i;
            r
        })
        .collect();
    write_runs_atomic(&dir.join("runs.csv"), 0, &runs).unwrap();
}

#[test]
fn tabulates_success_time_cost_rank_and_symmetry_and_draws_a_panel_per_size() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let square = keep(d, SQUARE_TO_TRIANGLE);
    let triangle = keep(d, TRIANGLE_TO_RING);
    write(
        d,
        vec![
            run(SQUARE_TO_TRIANGLE, 4, "a", Some((0.5, 3.0 * square))),
            run(SQUARE_TO_TRIANGLE, 4, "a", Some((1.5, 3.0 * square))),
            run(SQUARE_TO_TRIANGLE, 4, "b", None),
            run(TRIANGLE_TO_RING, 3, "a", Some((0.2, 2.0 * triangle))),
            run(TRIANGLE_TO_RING, 3, "a", None),
        ],
    );
    let (code, out, err) = formations(d);
    assert_eq!(code, 0, "{out}{err}");
    // N = 3 first; the triangle of three has the full rank 4 and no symmetry; one of two runs
    // solved leaves the median time unsolved
    assert!(
        out.contains("| 3 | triangle | ring | a | 1/2 | – | 2.0 | 4 / 4 | – |"),
        "{out}"
    );
    // the square keeps rank 4 of 6 (its symmetric set) and its goal lies off that set
    let square_row = out
        .lines()
        .find(|l| l.starts_with("| 4 | ring | triangle | a |"))
        .unwrap_or_else(|| panic!("{out}"));
    assert!(
        square_row.starts_with("| 4 | ring | triangle | a | 2/2 | 1.000 | 3.0 | 4 / 6 | 1/1: "),
        "{square_row}"
    );
    assert!(
        out.contains("| 4 | ring | triangle | b | 0/1 | – | – | 4 / 6 |"),
        "{out}"
    );
    let first = |s: &str| out.find(s).unwrap();
    assert!(first("| 3 |") < first("| 4 |"), "{out}");
    for p in ["a", "b"] {
        let svg = d.join("plots").join(format!("formations-{p}.svg"));
        let svg = std::fs::read_to_string(&svg).unwrap_or_else(|e| panic!("{p}: {e}"));
        assert!(svg.contains("N = 3") && svg.contains("N = 4"), "{p}");
    }
    let a = std::fs::read_to_string(d.join("plots/formations-a.svg")).unwrap();
    assert!(a.contains("2/2*") && a.contains("1/2"), "the cells");
}

#[test]
fn refuses_a_folder_without_team_runs_and_a_missing_scenario_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, vec![run("serpentine-walls=2-s0", 2, "a", None)]);
    let (code, _, err) = formations(d);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("DIR") && err.contains("`team`"), "{err}");
    write(d, vec![run(TRIANGLE_TO_RING, 3, "a", None)]);
    let (code, _, err) = formations(d);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("DIR") && err.contains(&format!("{TRIANGLE_TO_RING}.toml")),
        "{err}"
    );
}
