use super::*;
use crate::planners::GoalZoomRrt;
use crate::{Limits, Planner, validate_plan};
use magbench_env::math::max_agent_distance;
use magbench_env::{Scenario, Vec2};

fn problem(name: &str, seed: u64) -> Problem {
    let sc = Scenario::load(name).expect("a built-in scenario");
    let mut p = Problem::from_scenario(&sc, 0, None, seed);
    p.limits = Limits {
        max_iterations: Some(50_000),
        time_limit: None,
    };
    p
}

/// The optimiser refines goal-zoom RRT's plan into a valid plan of the same timing that costs
/// less, and never returns a plan that fails the validator.
#[test]
fn refining_a_plan_keeps_it_valid_and_lowers_its_cost() {
    let p = problem("open-field", 1);
    let r = GoalZoomRrt::default().solve(&p);
    assert!(r.solved);
    let before = crate::plan_cost(&p, &r.plan);
    let better = refine(&p, &r.plan, &Settings::default(), 30).expect("a cheaper plan");
    validate_plan(&p, &better).expect("the refined plan replays valid into the goal");
    assert!(crate::plan_cost(&p, &better) < before);
    assert!((better.duration() - r.plan.duration()).abs() < 1e-9);
}

/// The receding horizon leaves the plan between horizons: goal-zoom RRT's straightened plan of
/// narrow-passage (seed 1) refined with 20 subproblems a horizon costs less than 0.8 of it, and
/// most of its every-8th waypoints, where horizons landing on the plan's own states would end,
/// are more than 1e-3 BL from the plan's.
#[test]
fn the_receding_horizon_refines_a_plan_away_from_its_states() {
    let p = problem("narrow-passage", 1);
    let r = GoalZoomRrt::default().solve(&p);
    assert!(r.solved);
    let straight = crate::straighten::straighten(&p, &r.plan);
    let before = crate::plan_cost(&p, &straight);
    let better = refine(&p, &straight, &Settings::default(), 20).expect("a cheaper plan");
    validate_plan(&p, &better).expect("the refined plan replays valid into the goal");
    let ratio = crate::plan_cost(&p, &better) / before;
    assert!(ratio < 0.8, "{ratio}");
    // the plan's edges as the refinement cut them, replayed: the states it started from
    let periods = |d: &f64| (d / p.control_period).round() as usize;
    let edges = straight.controls.iter().zip(&straight.durations);
    let (controls, durations) = cut(&p, edges.map(|(u, d)| (*u, periods(d))), 15);
    let guide = Rollout::run(&p, &p.start, controls, durations, End::Goal, 0.02);
    assert_eq!(guide.edges(), better.edges());
    // every 8th waypoint, where a horizon that had to land on the plan would end
    let ends: Vec<usize> = (8..better.edges()).step_by(8).collect();
    let parted = ends
        .iter()
        .filter(|&&k| max_agent_distance(&better.states[k], &guide.states[k]) > 1e-3)
        .count();
    assert!(parted > ends.len() / 2, "{parted} of {}", ends.len());
}

/// An empty field where the pair moves 6 BL and keeps its shape.
const SLIDE: &str = r#"
name = "slide"
description = "An empty field: carry the pair 6 BL to the right."
[world]
width = 20.0
height = 12.0
[start]
agents = [[4.0, 6.0], [7.0, 6.0]]
[goal]
agents = [[10.0, 6.0], [13.0, 6.0]]
tolerance = 0.5
"#;

/// From its straight line, the planner solves an open field, and its plan passes the
/// validator.
#[test]
fn the_planner_solves_an_open_field_from_a_straight_line() {
    let sc = magbench_env::scenario::parse_scenario(SLIDE, "slide").expect("a scenario");
    let p = Problem::from_scenario(&sc, 0, None, 2);
    let r = crate::planners::Trajopt::default().solve(&p);
    assert!(r.solved, "ends {} BL from the goal", r.goal_distance);
    validate_plan(&p, &r.plan).expect("valid");
}

/// A run whose steps are all refused stops within four subproblems: each refusal shrinks the
/// trust region tenfold, from its first size to below the smallest; a step taken grows it by
/// half, up to the largest.
#[test]
fn a_run_whose_steps_are_refused_stops_within_four_subproblems() {
    let mut trust = Settings::default().trust;
    let mut refused = 0;
    while trust >= SMALLEST_TRUST {
        trust = resized(trust, false);
        refused += 1;
    }
    assert_eq!(refused, 4);
    assert_eq!(resized(0.1, true), 0.1 * EXPAND);
    assert_eq!(resized(LARGEST_TRUST, true), LARGEST_TRUST);
}

/// In a maze whose straight line crosses walls, the planner stops within its subproblems and
/// reports an approximate plan.
#[test]
fn the_planner_stops_and_reports_a_maze_it_cannot_solve() {
    let p = problem("micro-factory", 4);
    let mut planner = crate::planners::Trajopt {
        max_subproblems: 20,
        ..Default::default()
    };
    let r = planner.solve(&p);
    assert!(r.iterations <= 20);
    assert!(!r.solved && r.approximate && r.goal_distance > p.goal.tolerance);
    let why = planner.stop_reason().expect("an unsolved run says why");
    assert!(why.starts_with("trajopt: no feasible plan; "), "{why}");
    assert!(
        why.contains(&format!("after {} subproblems", r.iterations)),
        "{why}"
    );
}

/// A solved run has no stop reason, and a later unsolved one does not inherit it.
#[test]
fn only_an_unsolved_run_gives_a_stop_reason() {
    let sc = magbench_env::scenario::parse_scenario(SLIDE, "slide").expect("a scenario");
    let mut planner = crate::planners::Trajopt {
        max_subproblems: 5,
        ..Default::default()
    };
    planner.solve(&problem("micro-factory", 4));
    assert!(planner.stop_reason().is_some());
    let r = planner.solve(&Problem::from_scenario(&sc, 0, None, 2));
    assert!(r.solved);
    assert_eq!(planner.stop_reason(), None);
}

/// A rollout whose state is not finite has diverged: it stops solving the flow, is invalid,
/// and its violation is infinite, so that no step to it is taken.
#[test]
fn a_diverged_rollout_is_invalid_with_an_infinite_violation() {
    let p = problem("open-field", 5);
    let (controls, durations) = straight_line(&p, &Settings::default());
    let edges = controls.len();
    let start = vec![Vec2::new(f64::NAN, 0.0); p.agents()];
    let r = Rollout::run(&p, &start, controls, durations, End::Goal, 0.02);
    assert_eq!(r.states.len(), edges + 1);
    assert!(!r.valid && !r.feasible && r.valid_edges == 0);
    assert_eq!(r.violation, f64::INFINITY);
    assert!(r.merit(PENALTY).is_nan() || r.merit(PENALTY) == f64::INFINITY);
}

/// A subproblem's linearisation predicts a small step: the rollout after the step lands where
/// the linear model says, to second order.
#[test]
fn the_linearisation_predicts_a_small_step() {
    let p = problem("open-field", 3);
    let (mut controls, mut durations) = straight_line(&p, &Settings::default());
    controls.truncate(8);
    durations.truncate(8);
    let r = Rollout::run(&p, &p.start, controls, durations, End::Goal, 0.0);
    let jac = linearise::jacobians(&p, &r);
    let n = p.agents();
    let dim = 2 * n;
    let h = 1e-6;
    let delta: Vec<[f64; 3]> = (0..r.edges())
        .map(|k| [h * ((k % 3) as f64 - 1.0), 0.0, 0.0])
        .collect();
    let moved = r.rerun(&p, r.stepped(&delta, 1e9), 0.0);
    let mut dx = vec![0.0; dim];
    for (k, jk) in jac.iter().enumerate() {
        dx = (0..dim)
            .map(|row| {
                (0..dim).map(|c| jk.a[row * dim + c] * dx[c]).sum::<f64>()
                    + jk.b[row * 3] * delta[k][0]
            })
            .collect();
    }
    let end = moved.states.last().unwrap();
    let was = r.states.last().unwrap();
    for c in 0..dim {
        let actual = end[c / 2][c % 2] - was[c / 2][c % 2];
        assert!(
            (actual - dx[c]).abs() <= 1e-3 * actual.abs() + 1e-12,
            "{c}: {actual} vs {}",
            dx[c]
        );
    }
}

/// A rollout resumed from a waypoint with its own controls is the rollout itself, and with
/// other controls it is the replay from the start under them.
#[test]
fn a_resumed_rollout_is_the_replay_from_the_start() {
    let p = problem("open-field", 5);
    let (controls, durations) = straight_line(&p, &Settings::default());
    let r = Rollout::run(&p, &p.start, controls, durations, End::Goal, 0.02);
    let k = r.edges() / 2;
    let same = r.resumed(&p, k, r.controls[k..].to_vec(), 0.02);
    assert_eq!(same.states, r.states);
    assert_eq!(same.cost, r.cost);
    let mut other = r.controls.clone();
    for u in &mut other[k..] {
        u.theta += 1e-3;
    }
    let resumed = r.resumed(&p, k, other[k..].to_vec(), 0.02);
    let replayed = r.rerun(&p, other, 0.02);
    assert_eq!(resumed.states, replayed.states);
    assert_eq!(resumed.edge_costs, replayed.edge_costs);
    assert_eq!(resumed.waypoint_violations, replayed.waypoint_violations);
    assert_eq!(
        (resumed.valid, resumed.valid_edges, resumed.feasible),
        (replayed.valid, replayed.valid_edges, replayed.feasible)
    );
    assert!((resumed.cost - replayed.cost).abs() <= 1e-9 * replayed.cost);
}

/// A team of three under the RK4 flow: the held line is a guess whose every edge the flow
/// solves, the optimiser stops within its subproblems, and an unsolved run returns a valid
/// closest approach.
#[test]
fn a_team_of_three_is_optimised_within_its_subproblems() {
    let p = problem("trio-row", 1);
    assert_eq!(p.agents(), 3);
    let mut planner = crate::planners::Trajopt {
        max_subproblems: 10,
        ..Default::default()
    };
    let r = planner.solve(&p);
    assert!(r.iterations <= 10);
    if r.solved {
        validate_plan(&p, &r.plan).expect("valid");
    } else {
        crate::validate_path(&p, &r.plan).expect("a valid closest approach");
    }
}

/// A rollout does not solve the flow from a pair at one point (the end of a collapse the
/// unchecked flow let happen, where the pair force is infinite): it has diverged there, is not
/// valid, and repeats the state.
#[test]
fn a_rollout_from_agents_at_one_point_has_diverged() {
    let sc = magbench_env::scenario::parse_scenario(SLIDE, "slide").expect("a scenario");
    let p = Problem::from_scenario(&sc, 0, None, 2);
    let at = vec![Vec2::new(5.0, 6.0); 2];
    let u = Control::planar(0.3, 0.0, 0.0);
    let r = Rollout::run(&p, &at, vec![u], vec![p.periods(6)], End::Goal, 0.02);
    assert!(!r.valid && !r.feasible);
    assert_eq!(r.violation, f64::INFINITY);
    assert_eq!(r.states[1], at);
}
