//! The elevation as a control: three agents plan with α free by default, `planar = true`
//! keeps them in the plane, and the validator enforces the setup's `alpha_max`.

mod common;

use common::*;
use magbench_planners::{PlanError, registry, validate_plan};

fn param(k: &str, v: &str) -> (String, String) {
    (k.to_string(), v.to_string())
}

#[test]
fn three_agents_plan_with_the_elevation_unless_told_planar() {
    let s = scenario(TRIO);
    let p = problem(&s, 1, 30_000);
    let r = registry::create("goal-zoom-rrt", &[]).unwrap().solve(&p);
    assert_solution(&p, &r);
    assert!(r.plan.controls.iter().any(|u| u.alpha > 0.0));
    assert!(
        r.plan
            .controls
            .iter()
            .all(|u| (0.0..=p.alpha_max).contains(&u.alpha))
    );

    let planar = registry::create("goal-zoom-rrt", &[param("planar", "true")])
        .unwrap()
        .solve(&p);
    assert!(planar.plan.controls.iter().all(|u| u.alpha == 0.0));
}

#[test]
fn the_validator_holds_plans_to_the_setups_largest_elevation() {
    let s = scenario(TRIO);
    let p = problem_with(&s, 1, 30_000, &[("alpha_max", "30")]);
    for name in ["goal-zoom-rrt", "sst"] {
        let r = registry::create(name, &[param("stop_on_solution", "true")])
            .or_else(|_| registry::create(name, &[]))
            .unwrap()
            .solve(&p);
        assert_solution(&p, &r);
        let limit = 30f64.to_radians();
        assert!(r.plan.controls.iter().all(|u| u.alpha <= limit), "{name}");
    }
    // a plan made with up to 90° fails a setup that allows 30°
    let wide = problem(&s, 1, 30_000);
    let r = registry::create("goal-zoom-rrt", &[]).unwrap().solve(&wide);
    if r.plan.controls.iter().any(|u| u.alpha > 30f64.to_radians()) {
        assert!(matches!(
            validate_plan(&p, &r.plan),
            Err(PlanError::BadControl { .. })
        ));
    }
}

#[test]
fn two_agents_stay_in_the_plane_by_default() {
    let s = scenario(SMALL);
    let p = problem(&s, 3, 20_000);
    let r = registry::create("goal-zoom-rrt", &[]).unwrap().solve(&p);
    assert!(r.plan.controls.iter().all(|u| u.alpha == 0.0));
    let elevated = registry::create("goal-zoom-rrt", &[param("planar", "false")])
        .unwrap()
        .solve(&p);
    assert!(elevated.plan.controls.iter().any(|u| u.alpha > 0.0));
    if elevated.solved {
        validate_plan(&p, &elevated.plan).unwrap();
    } else {
        magbench_planners::validate_path(&p, &elevated.plan).unwrap();
    }
}
