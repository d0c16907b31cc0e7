//! The replan-latency table: from the replan logs of tracked runs, how long each replan made
//! while tracking (for a persistent error, or a team's stall) took (wall and CPU time of the loop's thread), how it found
//! its plan and how much planner work it did.

use magbench_trackers::{PlanReason, ReplanHow, ReplanRecord};

use super::tables::scenario;
use magbench::metrics::Metric;
use magbench::results::summary::{group_by, key};
use magbench::run::RunOutput;
use magbench::table::{Table, int, num, quantile};

/// One 60 Hz camera frame (ms).
pub const FRAME_MS: f64 = 1000.0 / 60.0;

/// "p50 / p95 / max" of `v`, "–" if it is empty.
fn spread(v: &[f64]) -> String {
    match (quantile(v, 0.5), quantile(v, 0.95), quantile(v, 1.0)) {
        (Some(a), Some(b), Some(c)) => format!("{} / {} / {}", num(a), num(b), num(c)),
        _ => "–".into(),
    }
}

/// "mean / p95 / max" of `v`, "–" if it is empty.
fn work(v: &[f64]) -> String {
    match (quantile(v, 0.95), quantile(v, 1.0)) {
        (Some(p), Some(m)) => {
            let mean = v.iter().sum::<f64>() / v.len() as f64;
            format!("{} / {} / {}", num(mean), int(p), int(m))
        }
        _ => "–".into(),
    }
}

/// How the replans found their plans: `189 rejoin, 37 tree, 7 full, 1 failed` (kinds with none
/// left out).
fn hows(events: &[&ReplanRecord]) -> String {
    let kinds = [
        (ReplanHow::Rejoin, "rejoin"),
        (ReplanHow::Tree, "tree"),
        (ReplanHow::Full, "full"),
        (ReplanHow::Failed, "failed"),
    ];
    let parts: Vec<String> = kinds
        .iter()
        .map(|(h, name)| (events.iter().filter(|e| e.how == *h).count(), name))
        .filter(|(k, _)| *k > 0)
        .map(|(k, name)| format!("{k} {name}"))
        .collect();
    match parts.is_empty() {
        true => "–".into(),
        false => parts.join(", "),
    }
}

/// "rejoins / tree iterations / edges", each the mean per replan; "–" without replans.
fn repair_work(events: &[&ReplanRecord]) -> String {
    if events.is_empty() {
        return "–".into();
    }
    let n = events.len() as f64;
    let mean =
        |f: fn(&ReplanRecord) -> u64| num(events.iter().map(|e| f(e) as f64).sum::<f64>() / n);
    format!(
        "{} / {} / {}",
        mean(|e| e.rejoins),
        mean(|e| e.tree_iterations),
        mean(|e| e.repair_edges)
    )
}

/// The mean of the finite values, "–" if there are none.
fn mean(v: &[f64]) -> String {
    let v: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    match v.is_empty() {
        true => "–".into(),
        false => num(v.iter().sum::<f64>() / v.len() as f64),
    }
}

/// The outputs of tracked runs grouped by configuration (scenario, planner, tracker, preset),
/// in order of first appearance.
fn configurations(outs: &[RunOutput]) -> Vec<Vec<&RunOutput>> {
    let tracked = outs.iter().filter(|o| !o.record.tracker.is_empty());
    group_by(tracked, |o| key(&o.record))
}

/// Per tracked configuration, over every drift replan of its runs (made for a persistent error
/// or, for teams of three or more, a stall; not a run's first plan or a leg's): their
/// count, wall and CPU time (ms, p50 / p95 / max), how many took at most one 60 Hz frame of
/// wall time, how they found their plans, the planner iterations and repair work per replan
/// (load-independent), then the runs' mean tracking errors and goals reached.
pub fn replan_latency(outs: &[RunOutput]) -> Table {
    let mut t = Table::new(&[
        "scenario",
        "tracker",
        "preset",
        "drift replans",
        "wall ms, p50 / p95 / max",
        "CPU ms, p50 / p95 / max",
        "within one 60 Hz frame (16.7 ms), wall",
        "how",
        "planner iterations per replan, mean / p95 / max",
        "repair work per replan, mean: rejoins / tree iterations / edges",
        "RMS error, observed, mean of runs (BL)",
        "RMS error, true, mean of runs (BL)",
        "goal reached",
    ]);
    for g in configurations(outs) {
        let events: Vec<&ReplanRecord> = g
            .iter()
            .flat_map(|o| &o.replans)
            .filter(|e| matches!(e.reason, PlanReason::Error | PlanReason::Stall))
            .collect();
        let wall: Vec<f64> = events.iter().map(|e| 1e3 * e.wall_s).collect();
        let cpu: Vec<f64> = events
            .iter()
            .filter_map(|e| e.cpu_s)
            .map(|s| 1e3 * s)
            .collect();
        let planner: Vec<f64> = events.iter().map(|e| e.planner_iterations as f64).collect();
        let of = |m| {
            g.iter()
                .filter_map(|o| o.record.get(m))
                .collect::<Vec<f64>>()
        };
        let r = &g[0].record;
        t.row(vec![
            scenario(&r.scenario),
            r.tracker.clone(),
            r.preset.clone(),
            events.len().to_string(),
            spread(&wall),
            spread(&cpu),
            format!(
                "{}/{}",
                wall.iter().filter(|&&ms| ms <= FRAME_MS).count(),
                wall.len()
            ),
            hows(&events),
            work(&planner),
            repair_work(&events),
            mean(&of(Metric::RmsError)),
            mean(&of(Metric::RmsErrorTrue)),
            format!(
                "{}/{}",
                g.iter()
                    .filter(|o| o.record.reached_goal == Some(true))
                    .count(),
                g.len()
            ),
        ]);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use magbench::run::RunRecord;

    fn event(reason: PlanReason, how: ReplanHow, wall_ms: f64) -> ReplanRecord {
        ReplanRecord {
            t_s: 1.0,
            leg: 0,
            reason,
            how,
            wall_s: wall_ms / 1e3,
            cpu_s: Some(wall_ms / 2e3),
            rejoins: 1,
            tree_iterations: 0,
            repair_edges: 3,
            planner_iterations: if how == ReplanHow::Full { 100 } else { 0 },
        }
    }

    fn output(tracker: &str, replans: Vec<ReplanRecord>) -> RunOutput {
        let mut r = RunRecord::example();
        r.scenario = "micro-factory".into();
        r.tracker = tracker.into();
        r.preset = "hardware".into();
        r.reached_goal = Some(true);
        r.set(Metric::RmsError, Some(0.04));
        RunOutput {
            record: r,
            progress: vec![],
            replay: None,
            replans,
        }
    }

    #[test]
    fn only_drift_replans_count_per_configuration() {
        let outs = [
            output(
                "repair",
                vec![
                    event(PlanReason::Initial, ReplanHow::Full, 500.0),
                    event(PlanReason::Leg, ReplanHow::Full, 400.0),
                    event(PlanReason::Error, ReplanHow::Rejoin, 1.0),
                    event(PlanReason::Error, ReplanHow::Full, 30.0),
                ],
            ),
            output(
                "restart",
                vec![event(PlanReason::Error, ReplanHow::Full, 20.0)],
            ),
            output(
                "repair",
                vec![event(PlanReason::Stall, ReplanHow::Tree, 2.0)],
            ),
        ];
        let t = replan_latency(&outs);
        assert_eq!(t.rows.len(), 2);
        let repair = &t.rows[0];
        assert_eq!(repair[1], "repair");
        assert_eq!(repair[3], "3");
        assert_eq!(repair[4], "2.00 / 27.2 / 30.0");
        assert_eq!(repair[5], "1.00 / 13.6 / 15.0");
        assert_eq!(repair[6], "2/3");
        assert_eq!(repair[7], "1 rejoin, 1 tree, 1 full");
        assert_eq!(repair[8], "33.3 / 90 / 100");
        assert_eq!(repair[9], "1.00 / 0 / 3.00");
        assert_eq!(repair[10], "0.0400");
        assert_eq!(repair[12], "2/2");
        assert_eq!(t.rows[1][6], "0/1");
    }
}
