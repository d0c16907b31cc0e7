//! Plans for the tracker tests, made without a planner: valid controls propagated through the
//! planning model (random ones, or ones the OBC optimizer picks to steer the team along
//! hand-drawn waypoints), and a tiny waypoint-steering `Planner` for the replanning tests.
#![allow(dead_code)]

use std::time::Instant;

use magbench_env::{Control, PlanningModel, Scenario, ValidityChecker, Vec2};
use magbench_planners::{Plan, Planner, PlannerResult, Problem};
use magbench_trackers::{ObcOptimizer, ObcWeights};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

pub const FRAME: f64 = 1.0 / 60.0;

/// A plan of `edges` random valid edges from `start`: random field angle and gradient, held for
/// 6 to 60 frames, each checked by the validity checker along its whole motion.
pub fn random_plan(
    model: &PlanningModel,
    checker: &ValidityChecker,
    start: &[Vec2],
    edges: usize,
    seed: u64,
) -> Plan {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let g = model.coil.gradient_limit();
    let mut plan = Plan::at(start);
    let mut s = start.to_vec();
    let mut out = vec![Vec2::zeros(); s.len()];
    let mut tries = 0;
    while plan.edges() < edges {
        tries += 1;
        assert!(tries < 100_000, "could not extend the random plan");
        let u = Control::planar(
            rng.random_range(-std::f64::consts::PI..std::f64::consts::PI),
            rng.random_range(-g..g),
            rng.random_range(-g..g),
        );
        let d = rng.random_range(6..=60) as f64 * FRAME;
        if checker.motion_valid(model, &s, &u, d, &mut out) {
            // keep clear of the proximity limits so the plan is a fair one to track
            let r = (out[1] - out[0]).norm();
            if r < checker.r_min + 0.3 || r > checker.r_max - 0.5 {
                continue;
            }
            plan.push(u, d, out.clone());
            s.copy_from_slice(&out);
        }
    }
    plan
}

/// Steers the planning model from `start` through `waypoints` (team states) with the OBC
/// optimizer, one frame per edge, the target moving at `speed` BL/s; every edge is checked.
/// Ends when the last waypoint is within `tol` (largest agent distance) or after `max_s`.
pub fn steer_plan(
    model: &PlanningModel,
    checker: &ValidityChecker,
    start: &[Vec2],
    waypoints: &[Vec<Vec2>],
    speed: f64,
    tol: f64,
    max_s: f64,
) -> Option<Plan> {
    let opt = ObcOptimizer::new(
        model.clone(),
        checker.clone(),
        FRAME,
        ObcWeights {
            w_smooth: 1e-4,
            ..Default::default()
        },
    );
    let n = start.len();
    let mut plan = Plan::at(start);
    let mut s = start.to_vec();
    let mut out = vec![Vec2::zeros(); n];
    let mut last: Option<Control> = None;
    // the moving target: a point that travels the waypoint polyline at `speed`
    let mut target = start.to_vec();
    let mut w = 0;
    let mut t = 0.0;
    while t < max_s {
        let goal = waypoints.last().unwrap();
        let dist = s
            .iter()
            .zip(goal)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        if dist <= tol {
            return Some(plan);
        }
        // advance the target along the waypoints, not too far ahead of the team
        let lag = s
            .iter()
            .zip(&target)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        if lag < 0.5 {
            let mut step = speed * FRAME;
            while step > 0.0 && w < waypoints.len() {
                let seg: Vec<Vec2> = waypoints[w]
                    .iter()
                    .zip(&target)
                    .map(|(a, b)| a - b)
                    .collect();
                let len = seg.iter().map(|v| v.norm()).fold(0.0, f64::max);
                if len <= step {
                    target = waypoints[w].clone();
                    w += 1;
                    step -= len;
                } else {
                    for (tg, v) in target.iter_mut().zip(&seg) {
                        *tg += v * (step / len);
                    }
                    step = 0.0;
                }
            }
        }
        let sol = opt.solve(&s, &target, last.as_ref(), None);
        if !checker.motion_valid(model, &s, &sol.control, FRAME, &mut out) {
            if std::env::var("STEER_DEBUG").is_ok() {
                eprintln!(
                    "steer: invalid motion at t = {t:.2} s, waypoint {w}, state {s:?}, target {target:?}"
                );
            }
            return None;
        }
        plan.push(sol.control, FRAME, out.clone());
        s.copy_from_slice(&out);
        last = Some(sol.control);
        t += FRAME;
    }
    if std::env::var("STEER_DEBUG").is_ok() {
        eprintln!("steer: out of time at waypoint {w}, state {s:?}");
    }
    None
}

/// A team state: the pair centred at `c`, separation `r`, heading `phi_deg`.
pub fn pair(c: [f64; 2], r: f64, phi_deg: f64) -> Vec<Vec2> {
    magbench_env::LocalView::new(c[0], c[1], r, phi_deg.to_radians())
        .to_pair()
        .to_vec()
}

/// A "planner" for tests: steers through fixed waypoints per leg (from the first waypoint
/// ahead of the start), with the OBC optimizer on the planning model.
pub struct WaypointPlanner {
    pub legs: Vec<Vec<Vec<Vec2>>>,
    pub calls: usize,
}

impl magbench_env::params::ParamSet for WaypointPlanner {}

impl Planner for WaypointPlanner {
    fn name(&self) -> &str {
        "waypoints"
    }

    fn solve(&mut self, problem: &Problem) -> PlannerResult {
        self.calls += 1;
        let started = Instant::now();
        // the leg whose final waypoint is the problem's goal
        let leg = self
            .legs
            .iter()
            .position(|l| {
                let last = l.last().unwrap();
                last.iter()
                    .zip(&problem.goal.agents)
                    .all(|(a, b)| (a - b).norm() < 1e-9)
            })
            .expect("a known leg");
        let wps = &self.legs[leg];
        // start from the waypoint nearest the start (so a replan does not go back)
        let com = |s: &[Vec2]| s.iter().sum::<Vec2>() / s.len() as f64;
        let c0 = com(&problem.start);
        let first = (0..wps.len())
            .min_by(|&a, &b| {
                (com(&wps[a]) - c0)
                    .norm()
                    .total_cmp(&(com(&wps[b]) - c0).norm())
            })
            .unwrap();
        let rest = wps[first..].to_vec();
        let plan = steer_plan(
            &problem.model,
            &problem.checker,
            &problem.start,
            &rest,
            0.4,
            problem.goal.tolerance * 0.4,
            600.0,
        );
        let solved = plan
            .as_ref()
            .is_some_and(|p| problem.goal.contains(p.end()));
        let plan = plan.unwrap_or_else(|| Plan::at(&problem.start));
        PlannerResult {
            solved,
            approximate: !solved,
            goal_distance: problem.goal.distance(plan.end()),
            plan,
            iterations: 1,
            nodes: 1,
            time_s: started.elapsed().as_secs_f64(),
            cost: None,
            first_solution: None,
            progress: vec![],
        }
    }
}

/// Waypoints through cargo-delivery: leg 1 over the wall to the cargo, leg 2 under the new
/// wall to the drop-off.
pub fn cargo_waypoints(s: &Scenario) -> Vec<Vec<Vec<Vec2>>> {
    let g1 = s.legs[0].goal.agents.clone();
    let g2 = s.legs[1].goal.agents.clone();
    vec![
        vec![
            pair([9.0, 12.0], 2.5, 0.0),
            pair([17.0, 22.5], 2.5, 0.0),
            pair([28.0, 21.0], 2.8, 0.0),
            g1,
        ],
        vec![
            pair([36.0, 14.0], 2.5, 0.0),
            pair([37.0, 6.0], 2.5, 0.0),
            g2,
        ],
    ]
}

/// Scenario by name.
pub fn scenario(name: &str) -> Scenario {
    Scenario::load(name).unwrap()
}

/// Waypoints through micro-factory: up channel 1 (the pair upright past the circle), over the
/// first wall, down channel 2, under the second wall, and into the two pockets.
pub fn micro_factory_waypoints(s: &Scenario) -> Vec<Vec<Vec2>> {
    vec![
        pair([8.0, 6.0], 2.5, 60.0),
        pair([9.75, 10.0], 2.5, 90.0),
        pair([9.75, 19.0], 2.5, 90.0),
        pair([11.0, 24.5], 2.5, 30.0),
        pair([18.0, 25.0], 2.5, 0.0),
        pair([21.0, 17.0], 2.5, 90.0),
        pair([22.5, 12.0], 2.5, 45.0),
        pair([24.0, 9.5], 2.5, 0.0),
        pair([30.0, 9.5], 2.5, 0.0),
        pair([38.0, 10.0], 3.5, 0.0),
        pair([42.0, 8.5], 4.0, 0.0),
        s.legs[0].goal.agents.clone(),
    ]
}
