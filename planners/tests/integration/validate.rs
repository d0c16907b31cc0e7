//! The validator accepts what the planners make and rejects every kind of broken plan.

use crate::common;

use common::*;
use magbench_env::model::Flow;
use magbench_env::{Control, Vec2};
use magbench_planners::{Plan, PlanError, registry::Planners, validate_path, validate_plan};

fn solved() -> (magbench_planners::Problem, Plan) {
    let s = scenario(SMALL);
    let p = problem(&s, 1, 20_000);
    let r = Planners::builtin()
        .create("goal-zoom-rrt", &[])
        .unwrap()
        .solve(&p);
    assert!(r.solved);
    (p, r.plan)
}

#[test]
fn accepts_a_planned_plan() {
    let (p, plan) = solved();
    validate_plan(&p, &plan).unwrap();
    assert!(plan.edges() > 1);
}

#[test]
fn rejects_tampered_plans() {
    let (p, plan) = solved();
    let k = plan.edges() / 2;

    let mut bad = plan.clone();
    bad.controls[k].theta += 1e-4;
    assert!(
        matches!(validate_plan(&p, &bad), Err(PlanError::ReplayMismatch { edge, .. }) if edge == k)
    );

    let mut bad = plan.clone();
    bad.states[k + 1][0].x += 2e-9;
    assert!(
        matches!(validate_plan(&p, &bad), Err(PlanError::ReplayMismatch { edge, .. }) if edge == k)
    );

    let mut bad = plan.clone();
    bad.durations[k] += 0.004;
    assert!(
        matches!(validate_plan(&p, &bad), Err(PlanError::BadDuration { edge, .. }) if edge == k)
    );

    let mut bad = plan.clone();
    bad.durations[k] = 0.0;
    assert!(matches!(
        validate_plan(&p, &bad),
        Err(PlanError::BadDuration { .. })
    ));

    let mut bad = plan.clone();
    bad.controls[k].grad[1] = 1.01 * p.model.coil.gradient_limit();
    assert!(
        matches!(validate_plan(&p, &bad), Err(PlanError::BadControl { edge, .. }) if edge == k)
    );

    let mut bad = plan.clone();
    bad.controls[k].theta = f64::NAN;
    assert!(matches!(
        validate_plan(&p, &bad),
        Err(PlanError::BadControl { .. })
    ));

    let mut bad = plan.clone();
    bad.states[0][1].y += 0.1;
    assert!(matches!(
        validate_plan(&p, &bad),
        Err(PlanError::WrongStart { .. })
    ));

    let mut bad = plan.clone();
    bad.states.pop();
    assert!(matches!(
        validate_plan(&p, &bad),
        Err(PlanError::Malformed(_))
    ));

    let mut bad = plan.clone();
    bad.states[1].pop();
    assert!(matches!(
        validate_plan(&p, &bad),
        Err(PlanError::Malformed(_))
    ));

    // a prefix is a valid path but does not end in the goal
    let mut prefix = plan.clone();
    prefix.states.truncate(k + 1);
    prefix.controls.truncate(k);
    prefix.durations.truncate(k);
    validate_path(&p, &prefix).unwrap();
    assert!(matches!(
        validate_plan(&p, &prefix),
        Err(PlanError::NotInGoal { .. })
    ));
}

/// A plan whose stored states are exactly what the model replays, but which runs into the
/// block: only the motion check catches it.
#[test]
fn rejects_a_motion_through_an_obstacle() {
    let s = scenario(SMALL);
    let p = problem(&s, 1, 1);
    let g = p.model.coil.gradient_limit();
    // pull the pair along +x (θ = 0): it drifts into the block at x = 7
    let u = Control::planar(0.0, g, 0.0);
    let mut plan = Plan::at(&p.start);
    let mut state = p.start.clone();
    for _ in 0..20 {
        let mut next = vec![Vec2::zeros(); 2];
        p.model.propagate_with(&state, &u, 0.5, &mut next, |_| true);
        plan.push(u, 0.5, next.clone());
        state = next;
    }
    match validate_path(&p, &plan) {
        Err(PlanError::InvalidMotion { .. }) => {}
        other => panic!("expected an invalid motion, got {other:?}"),
    }
}

#[test]
fn a_plan_made_with_other_arithmetic_fails_replay() {
    // the same controls solved by RK4 end slightly elsewhere than by the exact flow: a plan
    // that claims the other flow than the one that made it does not replay
    let (p, plan) = solved();
    assert_eq!(plan.flow, Flow::PairAdaptive);
    let rk4 = p.model.with_flow(Flow::Rk4);
    let mut other = Plan::at(&plan.states[0]);
    let mut state = plan.states[0].clone();
    for (u, &d) in plan.controls.iter().zip(&plan.durations) {
        let mut next = vec![Vec2::zeros(); 2];
        rk4.propagate(&state, u, d, &mut next);
        other.push(*u, d, next.clone());
        state = next;
    }
    assert!(matches!(
        validate_path(&p, &other),
        Err(PlanError::ReplayMismatch { .. })
    ));
    // labelled with the flow that made it, the RK4 plan replays (it may collide or miss the
    // goal: the controls were chosen for the exact motion)
    other.flow = Flow::Rk4;
    assert!(!matches!(
        validate_path(&p, &other),
        Err(PlanError::ReplayMismatch { .. })
    ));
    let mut relabelled = plan.clone();
    relabelled.flow = Flow::Rk4;
    assert!(matches!(
        validate_path(&p, &relabelled),
        Err(PlanError::ReplayMismatch { .. })
    ));
}

#[test]
fn rejects_nan_states() {
    let (p, plan) = solved();
    let mut bad = plan.clone();
    bad.states[1][0].x = f64::NAN;
    assert!(matches!(
        validate_plan(&p, &bad),
        Err(PlanError::ReplayMismatch { edge: 0, .. })
    ));
    let mut bad = plan;
    bad.states[0][0].y = f64::NAN;
    assert!(matches!(
        validate_plan(&p, &bad),
        Err(PlanError::WrongStart { .. })
    ));
}
