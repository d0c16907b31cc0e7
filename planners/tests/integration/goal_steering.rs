//! Goal-zoom RRT's goal steering: on the short moves (a turn in place and a swap, open field)
//! and a built-in maze, plans that end with a steer into the goal pass the validator, and the
//! steer ends on the goal centres.

use crate::common;

use common::assert_solution;
use magbench_env::{Scenario, Vec2};
use magbench_planners::goal_connect::GoalConnect;
use magbench_planners::search_settings::to_periods;
use magbench_planners::tree::Tree;
use magbench_planners::{Limits, Problem, registry::Planners, validate_plan, validate_result};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn solve(
    scenario: &Scenario,
    seed: u64,
    steer_radius: &str,
) -> (Problem, magbench_planners::PlannerResult) {
    let mut p = Problem::from_scenario(scenario, 0, None, seed);
    p.limits = Limits {
        max_iterations: Some(50_000),
        time_limit: None,
    };
    let params = vec![("steer_radius".to_string(), steer_radius.to_string())];
    let r = Planners::builtin()
        .create("goal-zoom-rrt", &params)
        .unwrap()
        .solve(&p);
    (p, r)
}

fn short(kind: &str) -> Scenario {
    let path = format!(
        "{}/../experiments/short-moves/{kind}.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    Scenario::load(&path).unwrap()
}

#[test]
fn steered_plans_pass_the_validator_and_end_on_the_goal_centres() {
    let mut exact = 0;
    for s in [
        short("turn"),
        short("swap"),
        Scenario::load("micro-factory").unwrap(),
    ] {
        for seed in 0..4 {
            let (p, r) = solve(&s, seed, "3");
            assert!(r.solved, "{}: seed {seed} not solved", s.name);
            validate_result(&p, &r).unwrap_or_else(|e| panic!("{}: {e:?}", s.name));
            assert_solution(&p, &r);
            if p.goal.distance(r.plan.end()) < 1e-6 {
                exact += 1;
            }
        }
    }
    // every short move ends with a steer (its goal is steered to from the start)
    assert!(exact >= 8, "{exact} of 12 plans end on the goal centres");
}

#[test]
fn without_steering_no_plan_ends_on_the_goal_centres() {
    let s = short("turn");
    let (p, r) = solve(&s, 0, "0");
    assert!(r.solved);
    validate_result(&p, &r).unwrap();
    assert!(p.goal.distance(r.plan.end()) > 1e-6);
}

#[test]
fn shortcut_plans_pass_the_validator_and_cost_no_more() {
    let s = Scenario::load("micro-factory").unwrap();
    let mut shorter = 0;
    for seed in 0..3 {
        let (_, before) = solve(&s, seed, "3");
        let mut p = Problem::from_scenario(&s, 0, None, seed);
        p.limits = Limits {
            max_iterations: Some(50_000),
            time_limit: None,
        };
        let params = vec![("shortcut".to_string(), "200".to_string())];
        let r = Planners::builtin()
            .create("goal-zoom-rrt", &params)
            .unwrap()
            .solve(&p);
        validate_result(&p, &r).unwrap();
        let (a, b) = (before.cost.unwrap(), r.cost.unwrap());
        eprintln!(
            "seed {seed}: cost {a:.1} -> {b:.1}, {} -> {} edges",
            before.plan.edges(),
            r.plan.edges()
        );
        assert!(b <= a + 1e-9);
        shorter += usize::from(b < a);
    }
    assert!(shorter >= 2, "{shorter} of 3 plans shortened");
}

/// micro-factory's goal (one agent per pocket) has one way out, upward: rungs at 2 and 4 BL.
/// An open goal has none.
#[test]
fn a_pocket_goal_has_approaches_and_an_open_goal_none() {
    let p = Problem::from_scenario(&Scenario::load("micro-factory").unwrap(), 0, None, 0);
    let c = GoalConnect::new(&p, 3.0, 5.0, to_periods(2.0, p.control_period));
    let up = |h: f64| [Vec2::new(40.0, 5.0 + h), Vec2::new(44.0, 5.0 + h)];
    assert_eq!(c.approaches(), vec![up(2.0), up(4.0)]);
    let open = Problem::from_scenario(&Scenario::load("open-field").unwrap(), 0, None, 0);
    let c = GoalConnect::new(&open, 3.0, 5.0, to_periods(2.0, p.control_period));
    assert!(c.approaches().is_empty());
}

/// From above the pockets in other shapes (2.5–4 BL apart, tilted up to 30°; the goal is
/// 4 BL apart, one agent per pocket), steers by way of the approaches reach the goal from
/// more states than steers straight in, and every plan passes the validator.
#[test]
fn a_pocket_goal_is_reached_more_often_by_way_of_its_approaches() {
    let p = Problem::from_scenario(&Scenario::load("micro-factory").unwrap(), 0, None, 0);
    let periods = to_periods(2.0, p.control_period);
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let (mut direct, mut via) = (0, 0);
    for _ in 0..30 {
        let centre = Vec2::new(rng.random_range(40.0..44.0), rng.random_range(9.0..11.0));
        let (r, phi): (f64, f64) = (rng.random_range(2.5..4.0), rng.random_range(-0.5..0.5));
        let half = Vec2::new(phi.cos(), phi.sin()) * (0.5 * r);
        let from = [centre - half, centre + half];
        let mut p = p.clone();
        p.start = from.to_vec();
        let distance = p.goal.distance(&from);
        let mut tree = Tree::new(&from);
        let straight = GoalConnect::new(&p, 10.0, 0.0, periods);
        if let Some(node) = straight.run(&p, &mut tree, None, 0) {
            validate_plan(&p, &tree.plan_to(node, &p)).unwrap();
            direct += 1;
        }
        let mut c = GoalConnect::new(&p, 3.0, 5.0, periods);
        let mut tree = Tree::new(&from);
        if let Some(node) = c.attempt(&p, &mut tree, None, 0, distance, true) {
            let plan = tree.plan_to(node, &p);
            validate_plan(&p, &plan).unwrap();
            assert!(p.goal.contains(plan.end()));
            via += 1;
        }
    }
    eprintln!("straight in: {direct}/30, by way of the approaches: {via}/30");
    assert!(
        via >= direct + 10,
        "straight in {direct}/30, by way of the approaches {via}/30"
    );
}
