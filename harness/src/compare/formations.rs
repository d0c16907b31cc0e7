//! The formation study over a results folder: which formation a team of N reaches from which.
//!
//! Runs of the `team` family carry their team size, start formation and goal formation in their
//! labels (`team-agents=6-goal=ring-…-start=grid-s0`). Per (N, start, goal, planner) the study
//! gives the success rate, the median time to a first plan (unsolved = +∞) and the median of
//! each solved plan's cost over its lower bound; per (N, start, goal), from the generated
//! scenario files the bench keeps in `DIR/scenarios/`, what the physics says of the pair:
//!
//! - **symmetry**: a start symmetric about its centroid stays so under every field in exact
//!   arithmetic, so a goal farther than its tolerance from every such formation is reached only
//!   through the growth of an asymmetry (round-off in the planning model, noise on a rig:
//!   [`magbench_env::team_symmetry`]); the study gives the goal's distance from that set;
//! - **rank**: the accessibility rank at the start ([`magbench_env::team_controllability`]):
//!   the span of the control fields, their brackets and brackets of brackets, out of the shape
//!   space's 2(N − 1) dimensions. Three control fields give at most 14 independent brackets of
//!   depth two, so for N ≥ 9 the test is a lower bound: a rank below 2(N − 1) there does not
//!   mean a direction is lost.
//!
//! The lower bound on cost is the one docs/planners.md states: `Σᵢ max(0, |gᵢ − pᵢ| − tol)`.

use std::collections::BTreeMap;
use std::path::Path;

use magbench_env::model::Kinematics;
use magbench_env::team_controllability::{FieldSet, Ranks, accessibility};
use magbench_env::team_symmetry::{SYMMETRY_EPS, central_pairing, symmetric_gap};
use magbench_env::{Scenario, Vec2};

use super::instances::median_inf;
use crate::Error;
use crate::metrics::Metric;
use crate::plot::grid::{Cell, CellGrid, Panel};
use crate::run::RunRecord;

/// The generated family the study reads.
pub const FAMILY: &str = "team";

/// Elevation of the rank test's field set (rad): the planners' default `alpha_max`, 45°.
const ALPHA_MAX: f64 = std::f64::consts::FRAC_PI_4;

/// One (N, start, goal) pair of formations, as the physics sees it.
#[derive(Debug, Clone, PartialEq)]
pub struct Pair {
    /// Team size N.
    pub agents: usize,
    /// Start formation.
    pub start: String,
    /// Goal formation.
    pub goal: String,
    /// Scenarios (instances) of the pair.
    pub instances: usize,
    /// Instances whose start is symmetric about its centroid and whose goal lies farther than
    /// its tolerance from every formation with that symmetry, and the largest such distance (BL).
    pub off_symmetric: (usize, f64),
    /// The least and largest accessibility rank at the instances' starts, and 2(N − 1).
    pub rank: Option<(usize, usize, usize)>,
    /// Per planner, what its runs did.
    pub planners: Vec<Outcome>,
}

/// One planner's runs on one pair of formations.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// Planner label.
    pub planner: String,
    /// Planning runs.
    pub runs: u64,
    /// Solved runs.
    pub solved: u64,
    /// Median time to a first plan (s; +∞ when most runs are unsolved).
    pub time: f64,
    /// Median cost over the lower bound of the solved runs (NaN when none is solved).
    pub cost_ratio: f64,
}

/// The value of label parameter `key` (`…-key=value-…`).
pub fn label_value<'a>(label: &'a str, key: &str) -> Option<&'a str> {
    let prefix = format!("{key}=");
    label.split('-').find_map(|part| part.strip_prefix(&prefix))
}

/// The lower bound on a plan's summed path length (BL): each agent at least its straight
/// distance to the edge of its goal disk.
pub fn cost_lower_bound(start: &[Vec2], goal: &[Vec2], tolerance: f64) -> f64 {
    start
        .iter()
        .zip(goal)
        .map(|(p, g)| ((g - p).norm() - tolerance).max(0.0))
        .sum()
}

/// What the physics says of one scenario: the distance of its goal from the symmetric set of a
/// start symmetric about its centroid, when beyond the goal's tolerance, and the accessibility
/// ranks at its start.
fn physics_of(s: &Scenario) -> (Option<f64>, Ranks) {
    let goal = s.final_goal();
    let gap = central_pairing(&s.start, SYMMETRY_EPS)
        .map(|pairing| symmetric_gap(&goal.agents, &pairing))
        .filter(|gap| *gap > goal.tolerance);
    let kin = Kinematics::nominal(&s.physics);
    let fields = match &s.medium {
        Some(m) if m.carries_fz() => FieldSet::Elevated {
            alpha_max: ALPHA_MAX,
        },
        _ => FieldSet::Planar,
    };
    (gap, accessibility(&kin, &s.start, fields))
}

/// The study of the planning runs of `runs` whose scenarios are of the `team` family, with the
/// scenario files in `scenarios` (a results folder's `scenarios/`); pairs in increasing N, then
/// start and goal by name. Refused when no run is of the family or a scenario file is missing.
pub fn study(runs: &[RunRecord], scenarios: &Path) -> Result<Vec<Pair>, Error> {
    type Key = (usize, String, String);
    let mut groups: BTreeMap<Key, Vec<&RunRecord>> = BTreeMap::new();
    for r in runs.iter().filter(|r| r.tracker.is_empty()) {
        if !r.scenario.starts_with(&format!("{FAMILY}-")) {
            continue;
        }
        let (Some(start), Some(goal)) = (
            label_value(&r.scenario, "start"),
            label_value(&r.scenario, "goal"),
        ) else {
            continue;
        };
        groups
            .entry((r.agents, start.to_string(), goal.to_string()))
            .or_default()
            .push(r);
    }
    if groups.is_empty() {
        return Err(Error::arg(
            "DIR",
            format!(
                "no planning run of a `{FAMILY}` scenario with `start` and `goal` in its label \
                 (an experiment's [[generated]] table of family `{FAMILY}` that lists both)"
            ),
        ));
    }
    let mut cache: BTreeMap<String, (Option<f64>, Ranks, f64)> = BTreeMap::new();
    let mut out = Vec::new();
    for ((agents, start, goal), rs) in groups {
        let mut names: Vec<&str> = rs.iter().map(|r| r.scenario.as_str()).collect();
        names.sort();
        names.dedup();
        let mut off_symmetric = (0, 0.0f64);
        let mut rank: Option<(usize, usize, usize)> = None;
        for name in &names {
            if !cache.contains_key(*name) {
                let path = scenarios.join(format!("{name}.toml"));
                let s = Scenario::load(&path.to_string_lossy()).map_err(|e| {
                    Error::arg(
                        "DIR",
                        format!(
                            "{}: the generated scenario of runs on {name}: {e}",
                            path.display()
                        ),
                    )
                })?;
                let (gap, ranks) = physics_of(&s);
                let goal = s.final_goal();
                let bound = cost_lower_bound(&s.start, &goal.agents, goal.tolerance);
                cache.insert(name.to_string(), (gap, ranks, bound));
            }
            let (gap, ranks, _) = &cache[*name];
            if let Some(gap) = gap {
                off_symmetric = (off_symmetric.0 + 1, off_symmetric.1.max(*gap));
            }
            rank = Some(match rank {
                None => (ranks.depth2, ranks.depth2, ranks.dim),
                Some((lo, hi, d)) => (lo.min(ranks.depth2), hi.max(ranks.depth2), d),
            });
        }
        let mut planners: Vec<String> = vec![];
        for r in &rs {
            if !planners.contains(&r.planner) {
                planners.push(r.planner.clone());
            }
        }
        let outcomes = planners
            .into_iter()
            .map(|p| {
                let mine: Vec<&&RunRecord> = rs.iter().filter(|r| r.planner == p).collect();
                let times: Vec<f64> = mine
                    .iter()
                    .map(|r| match (r.solved, r.get(Metric::FirstSolutionTime)) {
                        (true, Some(t)) => t,
                        _ => f64::INFINITY,
                    })
                    .collect();
                let mut ratios: Vec<f64> = mine
                    .iter()
                    .filter(|r| r.solved)
                    .filter_map(|r| {
                        let bound = cache[&r.scenario].2;
                        r.get(Metric::Cost)
                            .filter(|_| bound > 0.0)
                            .map(|c| c / bound)
                    })
                    .collect();
                ratios.sort_by(f64::total_cmp);
                Outcome {
                    planner: p,
                    runs: mine.len() as u64,
                    solved: mine.iter().filter(|r| r.solved).count() as u64,
                    time: median_inf(&times),
                    cost_ratio: median_sorted(&ratios),
                }
            })
            .collect();
        out.push(Pair {
            agents,
            start,
            goal,
            instances: names.len(),
            off_symmetric,
            rank,
            planners: outcomes,
        });
    }
    Ok(out)
}

/// The median of sorted finite values (NaN when there are none).
fn median_sorted(v: &[f64]) -> f64 {
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// The study as a Markdown table: one row per pair and planner.
pub fn markdown(pairs: &[Pair]) -> String {
    let mut s = String::from(
        "| N | start | goal | planner | solved | time to 1st plan, median (s) | cost / bound, median | rank at start (of 2(N−1)) | goal off a symmetric start's set (instances: largest distance) |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n",
    );
    for p in pairs {
        let rank = match p.rank {
            Some((lo, hi, d)) if lo == hi => format!("{lo} / {d}"),
            Some((lo, hi, d)) => format!("{lo}–{hi} / {d}"),
            None => "–".into(),
        };
        let symmetry = match p.off_symmetric {
            (0, _) => "–".to_string(),
            (k, gap) => format!("{k}/{}: {gap:.2} BL", p.instances),
        };
        for o in &p.planners {
            let time = if o.time.is_finite() {
                format!("{:.3}", o.time)
            } else {
                "–".into()
            };
            let ratio = if o.cost_ratio.is_finite() {
                format!("{:.1}", o.cost_ratio)
            } else {
                "–".into()
            };
            s += &format!(
                "| {} | {} | {} | {} | {}/{} | {time} | {ratio} | {rank} | {symmetry} |\n",
                p.agents, p.start, p.goal, o.planner, o.solved, o.runs
            );
        }
    }
    s
}

/// Formations in the order the generator lists them; others follow by name.
const ORDER: [&str; 5] = ["row", "ring", "grid", "triangle", "random"];

/// The formations among `names`, in [`ORDER`] and then by name.
fn ordered<'a>(names: impl Iterator<Item = &'a str>) -> Vec<String> {
    let mut v: Vec<String> = names.map(str::to_string).collect();
    v.sort_by_key(|n| {
        (
            ORDER.iter().position(|o| o == n).unwrap_or(ORDER.len()),
            n.clone(),
        )
    });
    v.dedup();
    v
}

/// The study's figure for `planner`: one panel per team size, start formations down and goal
/// formations across, each cell shaded by the fraction of runs solved and labelled `solved/runs`;
/// a pair with an instance whose goal lies off its symmetric start's set is marked `*`.
pub fn figure(pairs: &[Pair], planner: &str) -> CellGrid {
    let mut sizes: Vec<usize> = pairs.iter().map(|p| p.agents).collect();
    sizes.dedup();
    let panels = sizes
        .into_iter()
        .map(|n| {
            let mine: Vec<&Pair> = pairs.iter().filter(|p| p.agents == n).collect();
            let rows = ordered(mine.iter().map(|p| p.start.as_str()));
            let columns = ordered(mine.iter().map(|p| p.goal.as_str()));
            let cells = rows
                .iter()
                .map(|r| {
                    columns
                        .iter()
                        .map(|c| {
                            let p = mine.iter().find(|p| &p.start == r && &p.goal == c)?;
                            let o = p.planners.iter().find(|o| o.planner == planner)?;
                            let mark = if p.off_symmetric.0 > 0 { "*" } else { "" };
                            Some(Cell {
                                fraction: o.solved as f64 / o.runs.max(1) as f64,
                                text: format!("{}/{}{mark}", o.solved, o.runs),
                            })
                        })
                        .collect()
                })
                .collect();
            Panel {
                title: format!("N = {n}"),
                rows,
                columns,
                cells,
            }
        })
        .collect();
    CellGrid {
        title: format!("Which formation a team reaches from which: {planner}"),
        corner: "start \\ goal".into(),
        panels,
        note: "shade and text: runs solved; *: the goal lies off its symmetric start's set (reached only through round-off); blank: not run".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn label_values_and_the_bound() {
        let l = "team-agents=6-goal=ring-spacing=1.5-start=grid-s0";
        assert_eq!(label_value(l, "start"), Some("grid"));
        assert_eq!(label_value(l, "goal"), Some("ring"));
        assert_eq!(label_value(l, "rotation"), None);
        let a = [Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0)];
        let b = [Vec2::new(3.0, 4.0), Vec2::new(1.5, 0.0)];
        // 5 − 1 and max(0, 0.5 − 1)
        assert_eq!(cost_lower_bound(&a, &b, 1.0), 4.0);
        assert!(median_sorted(&[]).is_nan());
        assert_eq!(median_sorted(&[1.0, 2.0, 4.0, 9.0]), 3.0);
    }
}
