//! The guide path (`guide=true`): it runs through free space from start to goal, guided plans
//! pass the validator, the option changes the search, and bad values are refused.

use crate::common;

use magbench_env::Scenario;
use magbench_env::math::centroid;
use magbench_planners::guide::{Guide, SPACING};
use magbench_planners::{
    Limits, PlannerResult, Problem, registry::Planners, validate_plan, validate_result,
};

fn problem(name: &str, seed: u64) -> Problem {
    let s = Scenario::load(name).unwrap();
    let mut p = Problem::from_scenario(&s, 0, None, seed);
    p.limits = Limits {
        max_iterations: Some(200_000),
        time_limit: None,
    };
    p
}

fn solve(p: &Problem, guide: &str) -> PlannerResult {
    let params = vec![("guide".to_string(), guide.to_string())];
    Planners::builtin()
        .create("goal-zoom-rrt", &params)
        .unwrap()
        .solve(p)
}

#[test]
fn the_guide_runs_through_free_space_from_start_to_goal() {
    for name in [
        "micro-factory",
        "narrow-passage",
        "cargo-delivery",
        "open-field",
    ] {
        let p = problem(name, 0);
        let g = Guide::new(&p).unwrap_or_else(|| panic!("{name}: no guide"));
        let pts = g.points();
        assert_eq!(pts[0], centroid(&p.start), "{name}");
        assert_eq!(*pts.last().unwrap(), centroid(&p.goal.agents), "{name}");
        assert_eq!(g.reach(), 0);
        // grid steps between the ends, every grid node clear of obstacles
        for w in pts[1..pts.len() - 1].windows(2) {
            assert!((w[1] - w[0]).norm() <= SPACING * 1.5, "{name}: {w:?}");
        }
        for q in &pts[1..pts.len() - 1] {
            let c = p.checker.collision.clearance(*q);
            assert!(c >= 0.0, "{name}: guide point {q:?} has clearance {c}");
        }
    }
}

#[test]
fn the_progress_advances_only_near_the_path_ahead() {
    let p = problem("micro-factory", 0);
    let mut g = Guide::new(&p).unwrap();
    let far = g.points()[g.points().len() / 2];
    g.observe(&[far, far]);
    assert_eq!(
        g.reach(),
        0,
        "a node far along the path is out of the window"
    );
    let next = g.points()[4];
    g.observe(&[next, next]);
    assert_eq!(g.reach(), 4);
}

#[test]
fn guided_plans_on_micro_factory_validate_and_change_the_search() {
    let mut differ = 0;
    for seed in 0..2 {
        let p = problem("micro-factory", seed);
        let guided = solve(&p, "true");
        assert!(guided.solved, "seed {seed}");
        validate_plan(&p, &guided.plan).unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        validate_result(&p, &guided).unwrap();
        let plain = solve(&p, "false");
        differ += usize::from(plain.iterations != guided.iterations);
    }
    assert_eq!(differ, 2, "guide=true left the search unchanged");
}

#[test]
fn bad_guide_values_are_refused() {
    common::assert_refused("guide", &["maybe", "2", "", "TRUE!"]);
}
