//! The table of the tracker comparison (`trackers-mpc`): the seed's trackers beside MPPI.

use super::tables::{scenario, share, values};
use magbench::metrics::Metric;
use magbench::results::summary::groups;
use magbench::run::RunRecord;
use magbench::table::{Table, median, median_p90};

/// Per scenario, preset and tracker: runs that reached the goal and runs with agent contact (of
/// all), the RMS path error of the observed and of the true positions and the seed's node error
/// (median / p90, BL), and the whole loop's wall time per simulated second (median over runs of
/// tracking wall time ÷ tracking duration, ms; plant, camera, estimator, tracker and metrics).
pub fn comparison(runs: &[RunRecord]) -> Table {
    let mut t = Table::new(&[
        "scenario",
        "preset",
        "tracker",
        "goal reached",
        "agent contact",
        "path (observed)",
        "path (true)",
        "node (the seed's)",
        "loop wall time per simulated s, median (ms)",
    ]);
    let mut tracked: Vec<Vec<&RunRecord>> = groups(runs)
        .into_iter()
        .filter(|g| !g[0].tracker.is_empty())
        .collect();
    // a scenario's rows together, a preset's trackers together
    tracked.sort_by_key(|g| (g[0].scenario.clone(), g[0].preset.clone(), g[0].run));
    for g in tracked {
        let per_s: Vec<f64> = g
            .iter()
            .filter_map(|r| Some(1e3 * r.get(Metric::TrackTime)? / r.get(Metric::TrackDuration)?))
            .collect();
        t.row(vec![
            scenario(&g[0].scenario),
            g[0].preset.clone(),
            g[0].tracker.clone(),
            share(&g, |r| r.reached_goal == Some(true)),
            share(&g, |r| r.agent_contact == Some(true)),
            median_p90(&values(&g, Metric::RmsError)),
            median_p90(&values(&g, Metric::RmsErrorTrue)),
            median_p90(&values(&g, Metric::RmsErrorNode)),
            median(&per_s),
        ]);
    }
    t
}
