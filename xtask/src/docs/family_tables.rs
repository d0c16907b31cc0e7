//! Planners over a suite's families: a table that summarises a hundred generated problems in a
//! few rows ([`by_family`]).

use super::tables::{scenario, share, values};
use magbench::metrics::Metric;
use magbench::run::RunRecord;
use magbench::table::{Table, median};

/// A generated problem's family: its name's words before the first `key=value` word
/// (`clutter-density=0.03-s0`: `clutter`; `short-moves-move=swap-s1`: `short-moves`), or the
/// whole name.
pub fn family(scenario_name: &str) -> String {
    let words: Vec<&str> = scenario_name.split('-').collect();
    let end = words
        .iter()
        .position(|w| w.contains('='))
        .unwrap_or(words.len());
    words[..end.max(1)].join("-")
}

/// Per family and planner (in the order they first appear): runs solved, the plan's cost and
/// its ratio to the cost of the experiment's first planner on the same problem and seed
/// (medians over solved runs, the ratio over runs both solved), the time to the first solution
/// and the whole planning time (medians over solved runs, s).
pub fn by_family(runs: &[RunRecord]) -> Table {
    let mut t = Table::new(&[
        "family",
        "planner",
        "solved",
        "cost, median",
        "cost ÷ first planner's cost, same problem and seed, median",
        "time to 1st solution, median (s)",
        "planning time, median (s)",
    ]);
    let Some(first) = runs.first().map(|r| r.planner.clone()) else {
        return t;
    };
    let mut keys: Vec<(String, String)> = Vec::new();
    for r in runs {
        let key = (family(&scenario(&r.scenario)), r.planner.clone());
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    for (fam, planner) in keys {
        let g: Vec<&RunRecord> = runs
            .iter()
            .filter(|r| r.planner == planner && family(&scenario(&r.scenario)) == fam)
            .collect();
        let ok: Vec<&RunRecord> = g.iter().copied().filter(|r| r.solved).collect();
        let ratios: Vec<f64> = ok
            .iter()
            .filter_map(|r| {
                let base = runs.iter().find(|b| {
                    b.planner == first && b.scenario == r.scenario && b.seed == r.seed && b.solved
                })?;
                Some(r.get(Metric::Cost)? / base.get(Metric::Cost)?)
            })
            .collect();
        t.row(vec![
            fam,
            planner,
            share(&g, |r| r.solved),
            median(&values(&ok, Metric::Cost)),
            median(&ratios),
            median(&values(&ok, Metric::FirstSolutionTime)),
            median(&values(&ok, Metric::PlanTime)),
        ]);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::family;

    #[test]
    fn a_family_is_the_name_before_its_parameters() {
        assert_eq!(family("clutter-density=0.03-s0"), "clutter");
        assert_eq!(family("short-moves-move=swap-s1"), "short-moves");
        assert_eq!(family("serpentine-walls=1,gap=4-s2"), "serpentine");
        assert_eq!(family("open-field"), "open-field");
    }
}
