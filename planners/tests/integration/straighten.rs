//! Straightening the centroid (`straighten=true`), the pass after shortcutting: its plans pass
//! the validator, cost no more than the same run's plan without it and keep the relative
//! motion; the centroid runs at one velocity where the coil's limits allow; bad values are
//! refused.

use crate::common;

use magbench_env::math::centroid;
use magbench_env::{Scenario, Vec2};
use magbench_planners::straighten::{line_commands, straighten, straighten_with_stats};
use magbench_planners::{PlannerResult, Problem, plan_cost, validate_plan, validate_result};

use common::{BUILTIN_PLANNERS as PLANNERS, first_solution};

fn solve(planner: &str, p: &Problem, straighten: &str) -> PlannerResult {
    first_solution(planner, p, "straighten", straighten)
}

fn problem(name: &str, seed: u64) -> Problem {
    common::problem(&Scenario::load(name).unwrap(), seed, 200_000)
}

#[test]
fn every_planners_straightened_plans_validate_and_cost_no_more() {
    for planner in PLANNERS {
        for name in ["open-field", "narrow-passage"] {
            let mut shorter = 0;
            for seed in 0..2 {
                let p = problem(name, seed);
                let before = solve(planner, &p, "false");
                let after = solve(planner, &p, "true");
                assert!(
                    before.solved && after.solved,
                    "{planner}, {name}, seed {seed}"
                );
                validate_plan(&p, &after.plan).unwrap_or_else(|e| panic!("{planner}: {e}"));
                validate_result(&p, &after).unwrap();
                let (a, b) = (before.cost.unwrap(), after.cost.unwrap());
                eprintln!("{planner}, {name}, seed {seed}: cost {a:.1} -> {b:.1}");
                assert!(b <= a + 1e-9, "{planner}, {name}, seed {seed}: {a} -> {b}");
                assert_eq!(after.progress.last().unwrap().best_cost, Some(b));
                shorter += usize::from(b < 0.95 * a);
            }
            // open-field has no obstacle in the centroid's way: every plan gets shorter
            if name == "open-field" {
                assert_eq!(
                    shorter, 2,
                    "{planner}: {shorter} of 2 plans shortened by 5%"
                );
            }
        }
    }
}

/// The relative state at every waypoint, each agent's offset from the centroid.
fn shapes(plan: &magbench_planners::Plan) -> Vec<Vec<Vec2>> {
    plan.states
        .iter()
        .map(|s| {
            let c = centroid(s);
            s.iter().map(|a| a - c).collect()
        })
        .collect()
}

#[test]
fn the_pass_keeps_the_relative_motion_and_runs_the_centroid_straight() {
    let p = problem("open-field", 1);
    let r = solve("goal-zoom-rrt", &p, "false");
    let (out, stats) = straighten_with_stats(&p, &r.plan);
    // open-field's whole plan is one run: the same fields and durations, new gradients
    assert_eq!(stats.accepted, 1, "{stats:?}");
    assert_eq!(out.durations, r.plan.durations);
    for (u, v) in out.controls.iter().zip(&r.plan.controls) {
        assert_eq!((u.theta, u.alpha), (v.theta, v.alpha));
    }
    // (up to the rounding of the new positions, which the relative dynamics amplify: the pass
    // accepts a run ending within 1e-3 BL of the old waypoint)
    for (a, b) in shapes(&out).iter().zip(shapes(&r.plan)) {
        for (x, y) in a.iter().zip(&b) {
            assert!(
                (x - y).norm() < 1e-3,
                "relative state moved by {}",
                (x - y).norm()
            );
        }
    }
    // per axis, every edge whose command is within the coil's limit moves the centroid at one
    // common velocity, and no edge moves it against the shift (open-field has no drift)
    let limit = p.model.coil.gradient_limit();
    let (c0, c1) = (centroid(&out.states[0]), centroid(out.end()));
    for axis in 0..2 {
        let mut common: Option<f64> = None;
        for (k, u) in out.controls.iter().enumerate() {
            let step = centroid(&out.states[k + 1]) - centroid(&out.states[k]);
            let v = step[axis] / out.durations[k];
            assert!(
                v * (c1 - c0)[axis] >= -1e-12,
                "edge {k} runs backwards along {axis}"
            );
            if u.grad[axis].abs() < limit * (1.0 - 1e-9) {
                let mu = *common.get_or_insert(v);
                assert!(
                    (v - mu).abs() < 1e-9,
                    "edge {k}: {v} against {mu} along {axis}"
                );
            }
        }
        assert!(common.is_some(), "every edge clipped along {axis}");
    }
    // the centroid's share of the path length is the line's: each agent travels at least the
    // centroid's shift, and the pass leaves little beyond it
    let shift = (c1 - c0).norm();
    let before = plan_cost(&p, &r.plan);
    let after = plan_cost(&p, &out);
    eprintln!("centroid shift {shift:.1}: cost {before:.1} -> {after:.1}");
    assert!(after < 0.9 * before);
    assert!(after >= 2.0 * shift - 1e-9);
}

#[test]
fn line_commands_carry_the_centroid_by_the_shift_or_say_none() {
    let p = problem("open-field", 2);
    let r = solve("goal-zoom-rrt", &p, "false");
    let plan = &r.plan;
    let m = plan.edges().min(6);
    let (controls, durations) = (&plan.controls[..m], &plan.durations[..m]);
    let from = &plan.states[0];
    let mut out = vec![Vec2::zeros(); 2];
    for shift in [Vec2::new(0.5, -0.25), Vec2::zeros(), Vec2::new(-1.0, 2.0)] {
        let Some(commands) = line_commands(&p, 2, controls, durations, shift) else {
            panic!("shift {shift:?} out of reach over {m} edges");
        };
        let mut at = from.clone();
        for (u, &d) in commands.iter().zip(durations) {
            assert!(
                u.grad
                    .iter()
                    .all(|g| g.abs() <= p.model.coil.gradient_limit())
            );
            p.model.propagate(&at, u, d, &mut out);
            at.clone_from(&out);
        }
        let moved = centroid(&at) - centroid(from);
        assert!((moved - shift).norm() < 1e-9, "{shift:?}: moved {moved:?}");
    }
    // a shift beyond the coil's fastest pull over the edges' time has no commands
    let time: f64 = durations.iter().sum();
    assert!(line_commands(&p, 2, controls, durations, Vec2::new(10.0 * time, 0.0)).is_none());
}

#[test]
fn the_pass_is_reproducible_and_straightens_a_trio_too() {
    let p = problem("open-field", 3);
    let r = solve("goal-zoom-rrt", &p, "false");
    assert_eq!(straighten(&p, &r.plan), straighten(&p, &r.plan));
    // the work is a count bounded by the plan's length: 100 propagations an edge, and the last
    // run tried and the rest replayed after it. A plan of a thousand quarter-second edges
    // through micro-factory's walls would take many times that.
    let p = problem("micro-factory", 0);
    let long = first_solution("goal-zoom-rrt", &p, "max_duration", "0.25");
    let (_, stats) = straighten_with_stats(&p, &long.plan);
    let m = long.plan.edges();
    assert!(m > 500, "{m} edges");
    assert!(stats.propagations <= 102 * m, "{stats:?} over {m} edges");
    let (p, r) = common::solved_trio();
    let out = straighten(&p, &r.plan);
    let (before, after) = (plan_cost(&p, &r.plan), plan_cost(&p, &out));
    eprintln!("trio: cost {before:.2} -> {after:.2}");
    validate_plan(&p, &out).unwrap();
    // three agents share one pull too: their centroid straightens under RK4 as well
    assert!(after < before);
}

#[test]
fn bad_straighten_values_are_refused() {
    common::assert_refused("straighten", &["2", "maybe", "on", ""]);
}
