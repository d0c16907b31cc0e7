//! The data one replay page shows: frames (time, leg, plan, true and observed positions,
//! commanded field), the plans, the planner's trees, the marked events and a few metrics.
//!
//! Positions are stored as integers in hundredths of a BL ([`SCALE`]), tree edges in
//! twentieths ([`TREE_SCALE`]), and long runs are thinned to [`MAX_FRAMES`] frames, so that a
//! page's packed data ([`super::pack`]) stays within a few tens of kB; contacts and replans
//! keep their exact times.

use magbench_env::{Control, PlanningModel, Scenario, Vec2};
use magbench_planners::{Plan, PlannerResult};
use magbench_trackers::{PlanReason, Reference, TrackOutcome};
use serde::Serialize;

use super::events::{self, Event};
use super::scene::{Scene, r3, xy};
use super::tree::LegTree;

/// Units of a stored position per BL.
pub const SCALE: f64 = 100.0;
/// Most frames one replay keeps (longer runs are thinned evenly; the last frame is kept):
/// 50 s of a 30 fps camera, and a pair's page under 30 kB.
pub const MAX_FRAMES: usize = 1500;
/// Most points of one agent's path in one plan.
pub const MAX_PLAN_POINTS: usize = 300;
/// Units of a stored tree edge per BL (the tree is drawn in light grey behind the run).
pub const TREE_SCALE: f64 = 20.0;
/// Most tree edges drawn per leg.
pub const MAX_TREE_EDGES: usize = 1000;

fn q(x: f64) -> i32 {
    (x * SCALE).round() as i32
}

/// The commanded field of one frame: in-plane angle and elevation in degrees, gradient in mT/m.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FieldFrame(pub f64, pub f64, pub f64, pub f64);

impl FieldFrame {
    fn of(u: Option<&Control>) -> FieldFrame {
        match u {
            Some(u) => FieldFrame(
                (u.theta.to_degrees() * 10.0).round() / 10.0,
                (u.alpha.to_degrees() * 10.0).round() / 10.0,
                (u.grad[0] * 1e4).round() / 10.0,
                (u.grad[1] * 1e4).round() / 10.0,
            ),
            None => FieldFrame(0.0, 0.0, 0.0, 0.0),
        }
    }
}

/// One plan the run made or followed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReplayPlan {
    /// Its leg (0-based).
    pub leg: usize,
    /// When it took over (s).
    pub t0: f64,
    /// Why it was made: `initial`, `leg`, `error`, `stall` (or `plan` for a planning run).
    pub reason: String,
    /// Whether the planner solved its problem exactly.
    pub solved: bool,
    /// Each agent's path, `x, y, x, y, …` in hundredths of a BL.
    pub paths: Vec<Vec<i32>>,
}

/// One leg's tree, projected on the team's centroid.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReplayTree {
    /// Its leg (0-based).
    pub leg: usize,
    /// Nodes in the whole tree.
    pub nodes: usize,
    /// The edges drawn, `x1, y1, x2, y2, …` in [`TREE_SCALE`] units per BL, sorted by their
    /// first point (the order they are drawn in does not matter, and sorted they pack smaller).
    pub edges: Vec<i32>,
}

/// Everything a replay page shows.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReplayData {
    /// The page's title.
    pub title: String,
    /// `tracked` (positions from the rig) or `planned` (positions along the plan).
    pub kind: &'static str,
    /// Whether `truth` holds true positions (false: the rig's estimates).
    pub truth_known: bool,
    /// The scenario drawing.
    pub scene: Scene,
    /// Units of a stored position per BL.
    pub scale: f64,
    /// Units of a stored tree edge per BL.
    pub tree_scale: f64,
    /// Each frame's time (s since the first tick).
    pub t: Vec<f64>,
    /// Each frame's leg (0-based).
    pub leg: Vec<usize>,
    /// Each frame's plan (an index into `plans`).
    pub plan: Vec<usize>,
    /// Each agent's positions, `x, y` per frame, in hundredths of a BL.
    pub truth: Vec<Vec<i32>>,
    /// Each agent's observed positions per frame (`null` for a missed detection; empty for a
    /// planning run).
    pub obs: Vec<Vec<Option<i32>>>,
    /// The commanded field per frame.
    pub field: Vec<FieldFrame>,
    /// The plans.
    pub plans: Vec<ReplayPlan>,
    /// The planner's trees.
    pub trees: Vec<ReplayTree>,
    /// Contacts, replans and new legs.
    pub events: Vec<Event>,
    /// A few metrics of the run, `(name, value)`.
    pub info: Vec<(String, String)>,
}

/// Indices `0, stride, 2·stride, …` below `n`, and always `n - 1`.
fn thinned(n: usize) -> Vec<usize> {
    let stride = n.div_ceil(MAX_FRAMES).max(1);
    let mut idx: Vec<usize> = (0..n).step_by(stride).collect();
    if n > 0 && idx.last() != Some(&(n - 1)) {
        idx.push(n - 1);
    }
    idx
}

fn plan_paths(plan: &Plan, model: &PlanningModel) -> Vec<Vec<i32>> {
    let r = Reference::from_plan(plan, model);
    let n = plan.start().len();
    let stride = r.len().div_ceil(MAX_PLAN_POINTS).max(1);
    let mut ks: Vec<usize> = (0..r.len()).step_by(stride).collect();
    if ks.last() != Some(&r.last()) {
        ks.push(r.last());
    }
    (0..n)
        .map(|i| {
            ks.iter()
                .flat_map(|&k| {
                    let p = r.point(k, i);
                    [q(p.x), q(p.y)]
                })
                .collect()
        })
        .collect()
}

fn replay_tree(t: &LegTree) -> ReplayTree {
    let tq = |x: f64| (x * TREE_SCALE).round() as i32;
    let mut edges: Vec<[i32; 4]> = t
        .centroid_edges(MAX_TREE_EDGES)
        .iter()
        .map(|(a, b)| [tq(a[0]), tq(a[1]), tq(b[0]), tq(b[1])])
        .collect();
    edges.sort_unstable();
    ReplayTree {
        leg: t.leg - 1,
        nodes: t.nodes(),
        edges: edges.concat(),
    }
}

fn fmt(x: f64) -> String {
    format!("{x:.3}")
}

impl ReplayData {
    fn empty(s: &Scenario, title: String, kind: &'static str) -> ReplayData {
        ReplayData {
            title,
            kind,
            truth_known: true,
            scene: Scene::of(s),
            scale: SCALE,
            tree_scale: TREE_SCALE,
            t: vec![],
            leg: vec![],
            plan: vec![],
            truth: vec![vec![]; s.agents()],
            obs: vec![],
            field: vec![],
            plans: vec![],
            trees: vec![],
            events: vec![],
            info: vec![],
        }
    }

    /// The replay of a tracked run: its ticks, plans and the trees of its plans (`trees`, as
    /// many as were kept).
    /// `model` is the planning model the plans were made with (its medium sets their time
    /// scale).
    pub fn tracked(
        s: &Scenario,
        title: String,
        out: &TrackOutcome,
        trees: &[LegTree],
        model: &PlanningModel,
    ) -> Self {
        let mut d = ReplayData::empty(s, title, "tracked");
        let n = s.agents();
        d.truth_known = out.ticks.iter().all(|t| t.truth.is_some());
        d.obs = vec![vec![]; n];
        for k in thinned(out.ticks.len()) {
            let tk = &out.ticks[k];
            d.t.push(r3(tk.t));
            d.leg.push(tk.leg);
            d.plan.push(tk.plan);
            for i in 0..n {
                let p = tk.position(i);
                d.truth[i].extend([q(p.x), q(p.y)]);
                let o = tk.observed.get(i).copied().flatten();
                d.obs[i].extend([o.map(|p| q(p.x)), o.map(|p| q(p.y))]);
            }
            d.field.push(FieldFrame::of(Some(&tk.command)));
        }
        d.plans = out
            .plans
            .iter()
            .map(|p| ReplayPlan {
                leg: p.leg,
                t0: r3(p.start_t),
                reason: serde_json::to_value(p.reason)
                    .ok()
                    .and_then(|v| v.as_str().map(String::from))
                    .unwrap_or_default(),
                solved: p.solved,
                paths: plan_paths(&p.plan, model),
            })
            .collect();
        d.trees = trees.iter().map(replay_tree).collect();
        let positions: Vec<Vec<Vec2>> = out
            .ticks
            .iter()
            .map(|t| (0..n).map(|i| t.position(i)).collect())
            .collect();
        d.events = events::contacts(
            s,
            out.ticks
                .iter()
                .zip(&positions)
                .map(|(t, p)| (t.t, t.leg, p.as_slice())),
        );
        for p in out.plans.iter().skip(1) {
            let at = out
                .ticks
                .iter()
                .find(|t| t.t >= p.start_t)
                .map(|t| {
                    let c = (0..n).map(|i| t.position(i)).sum::<Vec2>() / n as f64;
                    xy(c)
                })
                .unwrap_or([0.0, 0.0]);
            let (kind, note) = match p.reason {
                PlanReason::Leg => ("leg", format!("leg {} planned", p.leg + 1)),
                PlanReason::Error => ("replan", "replan: persistent tracking error".into()),
                PlanReason::Stall => ("replan", "replan: no progress".into()),
                PlanReason::Initial => ("replan", "plan".into()),
            };
            d.events.push(Event {
                t: r3(p.start_t),
                kind,
                agent: None,
                at,
                note,
            });
        }
        d.events.sort_by(|a, b| a.t.total_cmp(&b.t));
        let m = &out.metrics;
        d.info = vec![
            ("status".into(), m.status.as_str().into()),
            ("reached goal".into(), m.reached_goal.to_string()),
            ("legs".into(), format!("{}/{}", m.legs_completed, m.legs)),
            (
                "time to goal (s)".into(),
                m.time_to_goal_s.map_or("–".into(), fmt),
            ),
            ("RMS error, observed (BL)".into(), fmt(m.rms_error_bl)),
            (
                "RMS error, true (BL)".into(),
                m.rms_error_true_bl.map_or("–".into(), fmt),
            ),
            ("agent contact".into(), m.agent_contact.to_string()),
            ("wall contacts".into(), m.wall_contacts.to_string()),
            ("replans".into(), m.replans.to_string()),
        ];
        d
    }

    /// The replay of a planning run: the team moving along the plans of `legs` (leg after
    /// leg), with the legs' trees; `model` is the planning model the plans were made with.
    pub fn planned(
        s: &Scenario,
        title: String,
        legs: &[&PlannerResult],
        trees: &[LegTree],
        model: &PlanningModel,
    ) -> Self {
        let mut d = ReplayData::empty(s, title, "planned");
        let n = s.agents();
        let refs: Vec<Reference> = legs
            .iter()
            .map(|r| Reference::from_plan(&r.plan, model))
            .collect();
        let total: usize = refs.iter().map(Reference::len).sum();
        let stride = total.div_ceil(MAX_FRAMES).max(1);
        let mut t0 = 0.0;
        for (leg, (r, res)) in refs.iter().zip(legs).enumerate() {
            let mut ks: Vec<usize> = (0..r.len()).step_by(stride).collect();
            if ks.last() != Some(&r.last()) {
                ks.push(r.last());
            }
            for k in ks {
                d.t.push(r3(t0 + r.time(k)));
                d.leg.push(leg);
                d.plan.push(leg);
                for i in 0..n {
                    let p = r.point(k, i);
                    d.truth[i].extend([q(p.x), q(p.y)]);
                }
                d.field.push(FieldFrame::of(r.control(k)));
            }
            d.plans.push(ReplayPlan {
                leg,
                t0: r3(t0),
                reason: "plan".into(),
                solved: res.solved,
                paths: plan_paths(&res.plan, model),
            });
            if leg > 0 {
                d.events.push(Event {
                    t: r3(t0),
                    kind: "leg",
                    agent: None,
                    at: xy(r.state(0).iter().sum::<Vec2>() / n as f64),
                    note: format!("leg {}", leg + 1),
                });
            }
            t0 += r.duration();
        }
        d.trees = trees.iter().map(replay_tree).collect();
        let solved = legs.len() == s.legs.len() && legs.iter().all(|r| r.solved);
        d.info = vec![
            ("solved".into(), solved.to_string()),
            (
                "iterations".into(),
                legs.iter().map(|r| r.iterations).sum::<u64>().to_string(),
            ),
            (
                "nodes".into(),
                legs.iter().map(|r| r.nodes).sum::<usize>().to_string(),
            ),
            ("plan duration (s)".into(), fmt(t0)),
            (
                "goal distance (BL)".into(),
                legs.last().map_or("–".into(), |r| fmt(r.goal_distance)),
            ),
        ];
        d
    }
}

#[cfg(test)]
mod tests {
    use magbench_planners::{Limits, Planner, PlanningSetup, planners::GoalZoomRrt};

    use super::*;

    #[test]
    fn a_planned_replay_follows_the_plan_within_the_frame_budget() {
        let s = Scenario::load("cargo-delivery").unwrap();
        let setup = PlanningSetup {
            limits: Limits {
                max_iterations: Some(5000),
                time_limit: None,
            },
            ..PlanningSetup::default()
        };
        let mut legs = vec![];
        let mut trees = vec![];
        let mut start = s.start.clone();
        for leg in 0..s.legs.len() {
            let p = setup.problem(&s, leg, Some(&start), leg as u64);
            let mut planner = GoalZoomRrt::default();
            let r = planner.solve(&p);
            trees.extend(LegTree::of_planner(&planner, &p, leg));
            start = r.plan.end().to_vec();
            legs.push(r);
        }
        let shown: Vec<&PlannerResult> = legs.iter().collect();
        let d = ReplayData::planned(
            &s,
            "x".into(),
            &shown,
            &trees,
            &PlanningModel::new(&s.physics),
        );
        assert!(d.t.len() <= MAX_FRAMES + s.legs.len());
        assert!(d.t.windows(2).all(|w| w[0] <= w[1]), "time runs forward");
        let total: f64 = legs.iter().map(|r| r.plan.duration()).sum();
        assert!((d.t.last().unwrap() - total).abs() < 2e-3);
        // the last frame is where the last plan ends
        let end = legs.last().unwrap().plan.end();
        let k = d.t.len() - 1;
        for (i, p) in end.iter().enumerate() {
            assert_eq!(d.truth[i][2 * k], q(p.x));
            assert_eq!(d.truth[i][2 * k + 1], q(p.y));
        }
        assert_eq!(d.plans.len(), legs.len());
        assert_eq!(d.trees.len(), legs.len());
        assert_eq!(*d.leg.last().unwrap(), legs.len() - 1);
        assert!(d.trees[0].edges.len() <= 4 * MAX_TREE_EDGES);
    }

    #[test]
    fn thinning_keeps_the_last_frame() {
        assert_eq!(thinned(0), Vec::<usize>::new());
        assert_eq!(thinned(3), [0, 1, 2]);
        let t = thinned(3 * MAX_FRAMES + 1);
        assert!(t.len() <= MAX_FRAMES + 1);
        assert_eq!(*t.last().unwrap(), 3 * MAX_FRAMES);
    }
}
