//! The elevation as a control: three agents at an interface plan with α free by default,
//! `planar = true` keeps them in the plane, in bulk `auto` keeps them in the plane, and the
//! validator enforces the setup's `alpha_max`, the coil's range and α = 0 in bulk.

use crate::common;

use common::*;
use magbench_planners::{PlanError, registry::Planners, validate_plan};

fn param(k: &str, v: &str) -> (String, String) {
    (k.to_string(), v.to_string())
}

#[test]
fn three_agents_plan_with_the_elevation_unless_told_planar() {
    let (p, r) = solved_trio();
    assert!(r.plan.controls.iter().any(|u| u.alpha > 0.0));
    assert!(
        r.plan
            .controls
            .iter()
            .all(|u| (0.0..=p.alpha_max).contains(&u.alpha))
    );

    assert_eq!(r.plan.alpha_max, Some(p.alpha_max));
    // the plan file says so, and reads back the same
    let back: magbench_planners::Plan =
        serde_json::from_str(&serde_json::to_string(&r.plan).unwrap()).unwrap();
    assert_eq!(
        (back.alpha_max, back.edges()),
        (r.plan.alpha_max, r.plan.edges())
    );

    let planar = Planners::builtin()
        .create("goal-zoom-rrt", &[param("planar", "true")])
        .unwrap()
        .solve(&p);
    assert!(planar.plan.controls.iter().all(|u| u.alpha == 0.0));
    assert_eq!(planar.plan.alpha_max, None);
    assert!(
        !serde_json::to_string(&planar.plan)
            .unwrap()
            .contains("alpha_max")
    );

    // in bulk nothing carries f_z: `auto` keeps the field in the plane, and the validator
    // refuses the elevated plan
    let bulk = scenario(&in_bulk(TRIO));
    let pb = problem(&bulk, 1, 2_000);
    assert!(!pb.model.carries_fz);
    let flat = Planners::builtin()
        .create("goal-zoom-rrt", &[])
        .unwrap()
        .solve(&pb);
    assert!(flat.plan.controls.iter().all(|u| u.alpha == 0.0));
    assert!(matches!(
        validate_plan(&pb, &r.plan),
        Err(PlanError::BadControl { .. })
    ));
}

#[test]
fn the_validator_holds_plans_to_the_coils_range() {
    let (_, r) = solved_trio();
    let s = scenario(TRIO);
    // the same problem on a planar coil set (range 0°) refuses every elevated control
    let planar_coil = magbench_planners::PlanningSetup {
        limits: magbench_planners::Limits {
            max_iterations: Some(30_000),
            time_limit: None,
        },
        ..Default::default()
    }
    .on_plant(&magbench_env::plant::Medium::Bulk, 0.0)
    .problem(&s, 0, None, 1);
    assert!(planar_coil.model.carries_fz);
    assert!(matches!(
        validate_plan(&planar_coil, &r.plan),
        Err(PlanError::BadControl { .. })
    ));
}

#[test]
fn the_validator_holds_plans_to_the_setups_largest_elevation() {
    let s = scenario(TRIO);
    let p = problem_with(&s, 1, 30_000, &[("alpha_max", "30")]);
    for name in ["goal-zoom-rrt", "sst"] {
        let r = Planners::builtin()
            .create(name, &[param("stop_on_solution", "true")])
            .or_else(|_| Planners::builtin().create(name, &[]))
            .unwrap()
            .solve(&p);
        assert_solution(&p, &r);
        let limit = 30f64.to_radians();
        assert!(r.plan.controls.iter().all(|u| u.alpha <= limit), "{name}");
    }
    // a plan made with up to 90° fails a setup that allows 30°
    let wide = problem(&s, 1, 30_000);
    let r = Planners::builtin()
        .create("goal-zoom-rrt", &[])
        .unwrap()
        .solve(&wide);
    if r.plan.controls.iter().any(|u| u.alpha > 30f64.to_radians()) {
        assert!(matches!(
            validate_plan(&p, &r.plan),
            Err(PlanError::BadControl { .. })
        ));
    }
}

#[test]
fn two_agents_stay_in_the_plane_by_default() {
    let s = scenario(&at_interface(SMALL));
    let p = problem(&s, 3, 20_000);
    let r = Planners::builtin()
        .create("goal-zoom-rrt", &[])
        .unwrap()
        .solve(&p);
    assert!(r.plan.controls.iter().all(|u| u.alpha == 0.0));
    let elevated = Planners::builtin()
        .create("goal-zoom-rrt", &[param("planar", "false")])
        .unwrap()
        .solve(&p);
    assert!(elevated.plan.controls.iter().any(|u| u.alpha > 0.0));
    if elevated.solved {
        validate_plan(&p, &elevated.plan).unwrap();
    } else {
        magbench_planners::validate_path(&p, &elevated.plan).unwrap();
    }
}
