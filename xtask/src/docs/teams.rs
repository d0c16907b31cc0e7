//! Tables of the physics chapter: planners' work to a first solution with the distance their
//! plans end from the goal, and tracked runs of teams.

use super::tables::{scenario, share, values};
use magbench::metrics::Metric;
use magbench::results::summary::groups;
use magbench::run::RunRecord;
use magbench::table::{Table, int, median, median_p90};

/// Planning to a first solution: per scenario and planner, runs solved, iterations to the first
/// solution, its time (s) and the plan's cost (medians over solved runs), and how far the plan
/// ends from the goal (the largest agent distance from its goal centre, median over all runs,
/// BL: what an unsolved run came closest to at the end of its best plan).
pub fn first_solution_work(runs: &[RunRecord]) -> Table {
    let mut t = Table::new(&[
        "scenario",
        "planner",
        "solved",
        "iterations to 1st solution, median",
        "time to 1st solution, median (s)",
        "cost, median",
        "plan's end from the goal, median (BL)",
    ]);
    for g in groups(runs) {
        let solved: Vec<&RunRecord> = g.iter().copied().filter(|r| r.solved).collect();
        t.row(vec![
            scenario(&g[0].scenario),
            g[0].planner.clone(),
            share(&g, |r| r.solved),
            median(&values(&solved, Metric::FirstSolutionIteration)),
            median(&values(&solved, Metric::FirstSolutionTime)),
            median(&values(&solved, Metric::Cost)),
            median(&values(&g, Metric::GoalDistance)),
        ]);
    }
    t
}

/// Tracked runs of teams: per scenario, planner and tracker, runs that reached the goal, ended
/// in agent contact or at the time limit, the largest agent distance from its goal centre at the
/// end, the largest and the RMS observed path error (median / p90, BL), and the replans (median
/// per run, and of all runs).
pub fn team_runs(runs: &[RunRecord]) -> Table {
    let mut t = Table::new(&[
        "scenario",
        "planner",
        "tracker",
        "goal reached",
        "agent contact",
        "time limit",
        "final goal distance (BL)",
        "max path error, observed (BL)",
        "path RMS, observed (BL)",
        "replans, median (all runs)",
    ]);
    for g in groups(runs)
        .into_iter()
        .filter(|g| !g[0].tracker.is_empty())
    {
        let replans = values(&g, Metric::Replans);
        t.row(vec![
            scenario(&g[0].scenario),
            g[0].planner.clone(),
            g[0].tracker.clone(),
            share(&g, |r| r.reached_goal == Some(true)),
            share(&g, |r| r.agent_contact == Some(true)),
            share(&g, |r| r.track_status == "timeout"),
            median_p90(&values(&g, Metric::FinalDistance)),
            median_p90(&values(&g, Metric::MaxError)),
            median_p90(&values(&g, Metric::RmsError)),
            format!("{} ({})", median(&replans), int(replans.iter().sum())),
        ]);
    }
    t
}
