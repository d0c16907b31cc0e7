use super::*;
use crate::search_settings::SearchSettings;
use crate::{Planners, validate_result};
use magbench_env::Scenario;

/// A solved plan of micro-factory (seed 2) and its problem.
fn planned() -> (Scenario, Problem, Plan) {
    let s = Scenario::load("micro-factory").unwrap();
    let problem = Problem::from_scenario(&s, 0, None, 2);
    let mut planner = Planners::builtin().create("goal-zoom-rrt", &[]).unwrap();
    let result = planner.solve(&problem);
    assert!(result.solved && validate_result(&problem, &result).is_ok());
    (s, problem, result.plan)
}

fn repair(problem: &Problem, iterations: u64) -> Repair {
    Repair {
        extend: SearchSettings::default().extend(problem),
        iterations,
        ahead: 8,
    }
}

/// The problem of `s` from `start` with seed `seed`.
fn from(s: &Scenario, start: &[Vec2], seed: u64) -> Problem {
    Problem::from_scenario(s, 0, Some(start), seed)
}

/// A state `offset` BL off waypoint `k` of `plan` (each agent moved the same way).
fn off(plan: &Plan, k: usize, offset: Vec2) -> Vec<Vec2> {
    plan.states[k].iter().map(|p| p + offset).collect()
}

#[test]
fn a_state_near_the_plan_is_repaired_into_a_valid_plan_to_the_goal() {
    let (s, _, plan) = planned();
    let mut repaired = 0;
    for (k, offset) in [
        (plan.edges() / 4, Vec2::new(0.15, -0.1)),
        (plan.edges() / 2, Vec2::new(-0.2, 0.05)),
        (3 * plan.edges() / 4, Vec2::new(0.1, 0.2)),
    ] {
        let start = off(&plan, k, offset);
        let problem = from(&s, &start, 11);
        if !problem.checker.is_valid(&start) {
            continue;
        }
        let r = repair(&problem, 200).run(&problem, &plan);
        let (result, _) = r.found.expect("a state near the plan is repaired");
        assert_eq!(validate_result(&problem, &result), Ok(()));
        assert!(result.solved && problem.goal.contains(result.plan.end()));
        assert_eq!(result.plan.start(), &start[..]);
        assert!(result.iterations >= 1);
        repaired += 1;
    }
    assert!(repaired >= 2, "only {repaired} of the states were valid");
}

/// The rejoin's steer carries a pair turned off its plan's shape back onto it.
#[test]
fn a_pair_turned_off_its_plan_rejoins_by_steering() {
    let (s, _, plan) = planned();
    let mut steered = 0;
    for k in (1..plan.edges()).step_by(3) {
        let w = &plan.states[k];
        let c = (w[0] + w[1]) * 0.5;
        let h = (w[1] - w[0]) * 0.5;
        // the separation turned by 0.3 rad about the centre
        let (sn, cs) = 0.3f64.sin_cos();
        let t = Vec2::new(cs * h.x - sn * h.y, sn * h.x + cs * h.y);
        let start = vec![c - t, c + t];
        let problem = from(&s, &start, 4);
        if !problem.checker.is_valid(&start) {
            continue;
        }
        let r = repair(&problem, 0).run(&problem, &plan);
        if let Some((result, how)) = r.found {
            assert_eq!(how, RepairHow::Rejoin);
            assert_eq!(validate_result(&problem, &result), Ok(()));
            steered += usize::from(r.rejoins >= 2);
        }
    }
    assert!(steered >= 3, "{steered} rejoins by a steer");
}

/// A valid state more than `distance` BL (the metric's) from every waypoint of `plan`.
pub(super) fn far_from(problem: &Problem, plan: &Plan, distance: f64) -> Vec<Vec2> {
    let sampler = crate::sampler::StateSampler::new(problem);
    let mut rng = Rng::seed_from_u64(0);
    let mut s = vec![Vec2::zeros(); problem.agents()];
    loop {
        sampler.uniform(&mut rng, &mut s);
        let near = plan
            .states
            .iter()
            .map(|w| problem.metric.distance(&s, w))
            .fold(f64::INFINITY, f64::min);
        if near > distance && problem.checker.is_valid(&s) {
            return s;
        }
    }
}

#[test]
fn a_state_far_off_the_plan_is_not_repaired() {
    let (s, problem, plan) = planned();
    let far = far_from(&problem, &plan, 15.0);
    let problem = from(&s, &far, 1);
    let r = repair(&problem, 10).run(&problem, &plan);
    assert!(r.found.is_none(), "repaired from {far:?}");
    assert_eq!(r.iterations, 10, "the tree ran its whole budget");
}

#[test]
fn repair_is_deterministic_per_seed() {
    let (s, _, plan) = planned();
    let start = off(&plan, plan.edges() / 3, Vec2::new(0.6, -0.4));
    for seed in [3, 9] {
        let problem = from(&s, &start, seed);
        let a = repair(&problem, 300).run(&problem, &plan);
        let b = repair(&problem, 300).run(&problem, &plan);
        assert_eq!(
            (a.rejoins, a.iterations, a.edges),
            (b.rejoins, b.iterations, b.edges)
        );
        assert_eq!(
            a.found.map(|(r, h)| (r.plan, h)),
            b.found.map(|(r, h)| (r.plan, h))
        );
    }
}

/// A plan of another flow cannot be spliced: nothing is tried.
#[test]
fn a_plan_of_another_flow_is_not_repaired() {
    let (s, _, mut plan) = planned();
    plan.flow = magbench_env::model::Flow::Rk4;
    let start = off(&plan, 1, Vec2::new(0.05, 0.0));
    let problem = from(&s, &start, 0);
    let r = repair(&problem, 100).run(&problem, &plan);
    assert!(r.found.is_none() && r.rejoins == 0 && r.iterations == 0);
}
