//! Aimed gradients (`aim=true`): each try keeps its random field and duration and takes the
//! gradients that carry the centroid closest to the target's. They are the best gradients for
//! the try, they leave the relative motion alone, aimed plans pass the validator, and bad
//! values are refused.

use crate::common;

use magbench_env::math::centroid;
use magbench_env::{Control, MAX_AGENTS, Scenario, Vec2};
use magbench_planners::motion::{aimed, propagate_valid, random_control};
use magbench_planners::sampler::{StateSampler, valid_sample};
use magbench_planners::{Problem, Rng, registry::Planners, validate_plan, validate_result};
use rand::{RngExt, SeedableRng};

use common::BUILTIN_PLANNERS as PLANNERS;

fn problem(name: &str, seed: u64) -> Problem {
    common::problem(&Scenario::load(name).unwrap(), seed, 200_000)
}

fn params(pairs: &[(&str, &str)]) -> Vec<(String, String)> {
    pairs
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

/// From random states toward random targets, the aimed control ends no farther from the target
/// under the problem's metric than the same field and duration with any of 20 random
/// gradients (motions that run their whole duration valid: one that meets an obstacle or
/// leaves the proximity range stops early), within the coil's limits, with the same relative motion: exactly for the pair's
/// closed-form flow, within the adaptive integrator's error for the trio.
#[test]
fn aimed_gradients_are_the_best_for_the_try_and_keep_the_shape() {
    for name in ["micro-factory", "trio-triangle"] {
        let p = problem(name, 0);
        let n = p.agents();
        let sampler = StateSampler::new(&p);
        let mut rng = Rng::seed_from_u64(3);
        let limit = p.model.coil.gradient_limit();
        let (mut near, mut target) = (vec![Vec2::zeros(); n], vec![Vec2::zeros(); n]);
        let (mut a, mut b) = ([Vec2::zeros(); MAX_AGENTS], [Vec2::zeros(); MAX_AGENTS]);
        let (mut compared, mut strictly) = (0, 0);
        let tol = if n == 2 { 1e-9 } else { 1e-4 };
        for _ in 0..200 {
            assert!(valid_sample(&p, 1000, &mut near, |x| sampler.uniform(&mut rng, x)));
            assert!(valid_sample(&p, 1000, &mut target, |x| sampler.uniform(&mut rng, x)));
            let d = rng.random_range(15..=120) as f64 * p.control_period;
            let u = random_control(&mut rng, limit);
            let aim = aimed(&p, u, n, centroid(&near), centroid(&target), d);
            assert_eq!((aim.theta, aim.alpha), (u.theta, u.alpha));
            assert!(aim.grad.iter().all(|g| g.abs() <= limit), "{aim:?}");
            if !propagate_valid(&p, &near, &aim, d, &mut a[..n]) {
                continue;
            }
            let best = p.metric.distance_squared(&a[..n], &target);
            for _ in 0..20 {
                let other = Control {
                    grad: random_control(&mut rng, limit).grad,
                    ..u
                };
                if !propagate_valid(&p, &near, &other, d, &mut b[..n]) {
                    continue;
                }
                let d2 = p.metric.distance_squared(&b[..n], &target);
                assert!(best <= d2 * (1.0 + 1e-9) + tol, "{name}: {best} > {d2}");
                compared += 1;
                strictly += usize::from(best < d2);
                // the shape is the same whatever the gradients
                let (ca, cb) = (centroid(&a[..n]), centroid(&b[..n]));
                for j in 0..n {
                    let gap = ((a[j] - ca) - (b[j] - cb)).norm();
                    assert!(gap < tol, "{name}: shapes differ by {gap}");
                }
            }
        }
        assert!(
            compared >= 300,
            "{name}: only {compared} valid pairs of motions"
        );
        assert!(
            strictly * 10 >= compared * 9,
            "{name}: aimed was strictly better in only {strictly} of {compared}"
        );
    }
}

#[test]
fn aimed_plans_validate_and_change_the_search() {
    for (name, planners) in [
        ("micro-factory", &PLANNERS[..]),
        ("trio-triangle", &["goal-zoom-rrt"][..]),
    ] {
        for planner in planners {
            let p = problem(name, 0);
            let create = |aim: &str| {
                let stop = if *planner == "goal-zoom-rrt" {
                    ""
                } else {
                    "true"
                };
                let mut ps = params(&[("aim", aim)]);
                if !stop.is_empty() {
                    ps.extend(params(&[("stop_on_solution", stop)]));
                }
                Planners::builtin().create(planner, &ps).unwrap()
            };
            let aimed = create("true").solve(&p);
            assert!(aimed.solved, "{planner} on {name}");
            validate_plan(&p, &aimed.plan).unwrap_or_else(|e| panic!("{planner} on {name}: {e}"));
            validate_result(&p, &aimed).unwrap();
            let plain = create("false").solve(&p);
            assert_ne!(
                (plain.iterations, plain.cost),
                (aimed.iterations, aimed.cost),
                "{planner} on {name}: aim=true left the search unchanged"
            );
        }
    }
}

#[test]
fn bad_aim_values_are_refused() {
    common::assert_refused("aim", &["maybe", "2", "", "TRUE!"]);
    for planner in PLANNERS {
        let both = params(&[("aim", "true"), ("timing", "closest")]);
        let e = match Planners::builtin().create(planner, &both) {
            Ok(_) => panic!("{planner}: aim=true with timing=closest accepted"),
            Err(e) => e,
        };
        assert_eq!(e.field, "param.aim", "{planner}: {e}");
        assert!(e.reason.contains("timing=random"), "{e}");
    }
}
