//! Tables of planning measurements that compare planner variants: a post-processing pass
//! against the plan it starts from ([`improvement`]) and a planner's speed against team size
//! ([`team_scaling`]).

use super::tables::{scenario, share, values};
use magbench::metrics::Metric;
use magbench::results::summary::{group_by, groups};
use magbench::run::RunRecord;
use magbench::table::{Table, median, num};

/// The solved runs of a configuration.
fn solved<'a>(g: &[&'a RunRecord]) -> Vec<&'a RunRecord> {
    g.iter().copied().filter(|r| r.solved).collect()
}

/// A planner variant against the first variant of its scenario: per scenario and planner, runs
/// solved, the plan's cost (median over solved runs), its ratio to the cost of the scenario's
/// first planner on the same seed (median over seeds both solved), the time to the first
/// solution and the whole planning time (medians over solved runs, s) and the time spent after
/// the first solution (planning time − time to the first solution: a post-processing pass such
/// as shortcutting; median over solved runs, s).
pub fn improvement(runs: &[RunRecord]) -> Table {
    let mut t = Table::new(&[
        "scenario",
        "planner",
        "solved",
        "cost, median",
        "cost ÷ first planner's cost, same seed, median",
        "time to 1st solution, median (s)",
        "planning time, median (s)",
        "after the 1st solution, median (s)",
    ]);
    for by_scenario in group_by(groups(runs), |g| g[0].scenario.clone()) {
        let base = solved(&by_scenario[0]);
        for g in &by_scenario {
            let ok = solved(g);
            let ratios: Vec<f64> = ok
                .iter()
                .filter_map(|r| {
                    let b = base.iter().find(|b| b.seed == r.seed)?;
                    Some(r.get(Metric::Cost)? / b.get(Metric::Cost)?)
                })
                .collect();
            let after: Vec<f64> = ok
                .iter()
                .filter_map(|r| Some(r.get(Metric::PlanTime)? - r.get(Metric::FirstSolutionTime)?))
                .collect();
            t.row(vec![
                scenario(&g[0].scenario),
                g[0].planner.clone(),
                share(g, |r| r.solved),
                median(&values(&ok, Metric::Cost)),
                median(&ratios),
                median(&values(&ok, Metric::FirstSolutionTime)),
                median(&values(&ok, Metric::PlanTime)),
                median(&after),
            ]);
        }
    }
    t
}

/// The value of parameter `key` in a run's planner overrides (`a=1,b="x"`), unquoted, or
/// "default".
fn param(r: &RunRecord, key: &str) -> String {
    r.planner_params
        .split(',')
        .filter_map(|kv| kv.split_once('='))
        .find(|(k, _)| k.trim() == key)
        .map(|(_, v)| v.trim().trim_matches('"').to_string())
        .unwrap_or_else(|| "default".into())
}

/// A planner's speed against team size: per configuration, the team size N, scenario, the
/// planning model's flow (the `flow` parameter), runs solved, the time to the first solution
/// and the iterations to it (medians over solved runs) and iterations per second over all runs
/// (Σ iterations ÷ Σ planning time).
pub fn team_scaling(runs: &[RunRecord]) -> Table {
    let mut t = Table::new(&[
        "N",
        "scenario",
        "flow",
        "solved",
        "time to 1st solution, median (s)",
        "iterations to 1st solution, median",
        "iterations/s (Σ iterations ÷ Σ time)",
    ]);
    for g in groups(runs) {
        let ok = solved(&g);
        let sum = |m| values(&g, m).iter().sum::<f64>();
        t.row(vec![
            g[0].agents.to_string(),
            scenario(&g[0].scenario),
            param(g[0], "flow"),
            share(&g, |r| r.solved),
            median(&values(&ok, Metric::FirstSolutionTime)),
            median(&values(&ok, Metric::FirstSolutionIteration)),
            num(sum(Metric::Iterations) / sum(Metric::PlanTime)),
        ]);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(scenario: &str, planner: &str, params: &str, seed: u64, fig: [f64; 4]) -> RunRecord {
        let mut r = RunRecord::example();
        r.run = seed as usize;
        r.scenario = scenario.into();
        r.agents = 2;
        r.planner = planner.into();
        r.planner_params = params.into();
        r.seed = seed;
        r.solved = fig[0].is_finite();
        let [cost, first, total, iterations] = fig;
        r.set(Metric::Cost, cost.is_finite().then_some(cost));
        r.set(
            Metric::FirstSolutionTime,
            first.is_finite().then_some(first),
        );
        r.set(Metric::FirstSolutionIteration, Some(iterations));
        r.set(Metric::PlanTime, Some(total));
        r.set(Metric::Iterations, Some(iterations));
        r
    }

    #[test]
    fn a_variant_is_paired_with_the_first_planner_by_seed() {
        let nan = f64::NAN;
        let runs = vec![
            run("a.toml", "p", "", 0, [10.0, 1.0, 1.0, 5.0]),
            run("a.toml", "p", "", 1, [20.0, 2.0, 2.0, 5.0]),
            run("a.toml", "p{s=1}", "s=1", 0, [5.0, 1.0, 4.0, 5.0]),
            run("a.toml", "p{s=1}", "s=1", 1, [nan, nan, 9.0, 5.0]),
            run("b", "p", "", 0, [8.0, 1.0, 1.0, 5.0]),
        ];
        let t = improvement(&runs);
        assert_eq!(t.rows.len(), 3);
        assert_eq!(t.rows[0][..5], ["a", "p", "2/2", "15.0", "1.00"]);
        assert_eq!(t.rows[1][..5], ["a", "p{s=1}", "1/2", "5.00", "0.500"]);
        assert_eq!(
            t.rows[1][7], "3.00",
            "planning time − time to the 1st solution"
        );
        assert_eq!(t.rows[2][0], "b");
    }

    #[test]
    fn team_scaling_sums_iterations_over_time_and_names_the_flow() {
        let nan = f64::NAN;
        let f = "flow=\"pair-exact\"";
        let runs = vec![
            run("trio", "q", f, 0, [1.0, 0.5, 0.5, 100.0]),
            run("trio", "q", f, 1, [nan, nan, 1.5, 300.0]),
        ];
        let t = team_scaling(&runs);
        assert_eq!(
            t.rows[0],
            ["2", "trio", "pair-exact", "1/2", "0.500", "100", "200"]
        );
        assert_eq!(param(&runs[0], "k"), "default");
    }
}
