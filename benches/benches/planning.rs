//! Planning building blocks and one whole plan, on micro-factory:
//!
//! - `propagate/rk4/step`: one RK4 step of the planning model (two agents);
//! - `propagate/rk4/period`, `propagate/rk4/1s`: one control period (2 steps), one second of a
//!   motion that stays inside the proximity range;
//! - `propagate/exact/period`, `…/1s`: the exact flow over the same motions;
//! - `propagate/exact/any`: the exact flow over 1024 random states, controls and durations in
//!   (0, 2] s inside the proximity range, in turn (so no branch predictor learns one motion);
//! - `path_length/exact/1s`: the path length of that 1 s motion (quadrature on the curve);
//! - `extend/default`: one EXTEND call with goal-zoom-rrt's defaults (5 tries of 0.25–2 s);
//! - `extend/k12/{batch,scalar}`: one EXTEND call with 12 tries (the search settings' default
//!   k), through the batch that `Extend::run` takes for a pair and through `Extend::run_scalar`;
//! - `nearest/10k`: a nearest-neighbour query among 10 000 team states (k-d tree);
//! - `motion_valid/{rk4,exact}/1s`: checking a 1 s edge (RK4: propagation + capsule sweeps +
//!   proximity at samples; exact: separation range + conservative advancement);
//! - `goal_zoom_rrt/micro_factory`: a whole plan to the first solution, seeds 0, 1, 2, … in turn.
//!
//! ```sh
//! cargo bench -p magbench-benches --bench planning
//! ```

// −3.14 here is a round bound of the sampled angles, not π (π would change the inputs)
#![allow(clippy::approx_constant)]

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use magbench_env::model::Flow;
use magbench_env::{Control, LocalView, Scenario, Vec2};
use magbench_planners::extend::{Extend, Timing};
use magbench_planners::nn::NearestNeighbors;
use magbench_planners::{Distance, Limits, Planner, Planners, Problem, Rng};
use rand::{RngExt, SeedableRng};

fn problem() -> Problem {
    let s = Scenario::load("micro-factory").unwrap();
    Problem::from_scenario(&s, 0, None, 0)
}

fn mid_state() -> Vec<Vec2> {
    LocalView {
        xc: 20.0,
        yc: 14.0,
        r: 2.5,
        phi: 0.4,
    }
    .to_pair()
    .to_vec()
}

fn bench(c: &mut Criterion) {
    let p = problem();
    let x = mid_state();
    let g = p.model.coil.gradient_limit();
    let u = Control::planar(0.7, 0.5 * g, -0.3 * g);
    let mut out = vec![Vec2::zeros(); 2];

    let rk4 = p.model.with_flow(Flow::Rk4);
    // the first field angle (in 0.05 rad steps) whose 1 s edge is valid under both flows: the
    // checks run to the end, and the 1 s motions below stay inside the proximity range
    let soft = (0..126)
        .map(|k| Control::planar(-3.14 + 0.05 * k as f64, 0.3 * g, 0.2 * g))
        .find(|u| {
            p.checker.motion_valid(&p.model, &x, u, 1.0, &mut out)
                && p.checker.motion_valid(&rk4, &x, u, 1.0, &mut out)
        })
        .expect("some 1 s edge from the benchmark state is valid");
    let mut group = c.benchmark_group("propagate");
    group.bench_function("rk4/step", |b| {
        b.iter(|| rk4.propagate(black_box(&x), &u, rk4.dt, &mut out))
    });
    group.bench_function("rk4/period", |b| {
        b.iter(|| rk4.propagate(black_box(&x), &u, p.control_period, &mut out))
    });
    group.bench_function("rk4/1s", |b| {
        b.iter(|| rk4.propagate(black_box(&x), &soft, 1.0, &mut out))
    });
    group.bench_function("exact/period", |b| {
        b.iter(|| {
            p.model
                .propagate(black_box(&x), &u, p.control_period, &mut out)
        })
    });
    group.bench_function("exact/1s", |b| {
        b.iter(|| p.model.propagate(black_box(&x), &soft, 1.0, &mut out))
    });
    let mut rng = Rng::seed_from_u64(3);
    let mut motions = Vec::new();
    while motions.len() < 1024 {
        let s = LocalView {
            xc: 20.0,
            yc: 14.0,
            r: rng.random_range(1.3..5.9),
            phi: rng.random_range(-3.14..3.14),
        }
        .to_pair();
        let v = Control::planar(
            rng.random_range(-3.14..3.14),
            rng.random_range(-g..g),
            rng.random_range(-g..g),
        );
        let d: f64 = rng.random_range(0.001..2.0);
        let (lo, hi) = p.model.pair_edge(&s, &v).unwrap().separation_range(d);
        if lo > p.checker.r_min && hi < p.checker.r_max {
            motions.push((s, v, d));
        }
    }
    let mut k = 0;
    group.bench_function("exact/any", |b| {
        b.iter(|| {
            k = (k + 1) % motions.len();
            let (s, v, d) = &motions[k];
            p.model.propagate(black_box(s), v, *d, &mut out)
        })
    });
    group.finish();
    c.bench_function("path_length/exact/1s", |b| {
        b.iter(|| p.model.path_length(black_box(&x), &soft, 1.0))
    });

    let extend = Extend {
        tries: 5,
        min_periods: 15,
        max_periods: 120,
        timing: Timing::Random,
        alpha_max: None,
        aim: false,
    };
    let target = LocalView {
        xc: 20.5,
        yc: 14.3,
        r: 3.0,
        phi: 1.0,
    }
    .to_pair()
    .to_vec();
    let mut rng = Rng::seed_from_u64(1);
    c.bench_function("extend/default", |b| {
        b.iter(|| extend.run(&p, &mut rng, black_box(&x), &target))
    });

    let k12 = Extend {
        tries: 12,
        ..extend
    };
    let mut rng = Rng::seed_from_u64(1);
    c.bench_function("extend/k12/batch", |b| {
        b.iter(|| k12.run(&p, &mut rng, black_box(&x), &target))
    });
    let mut rng = Rng::seed_from_u64(1);
    c.bench_function("extend/k12/scalar", |b| {
        b.iter(|| k12.run_scalar(&p, &mut rng, black_box(&x), &target))
    });

    let mut nn = NearestNeighbors::new(Distance::Positions, 2);
    let mut rng = Rng::seed_from_u64(2);
    let team = |rng: &mut Rng| {
        LocalView {
            xc: rng.random_range(0.0..48.0),
            yc: rng.random_range(0.0..32.0),
            r: rng.random_range(1.25..6.0),
            phi: rng.random_range(-3.14..3.14),
        }
        .to_pair()
    };
    for i in 0..10_000u32 {
        nn.add(&team(&mut rng), i);
    }
    let queries: Vec<[Vec2; 2]> = (0..1024).map(|_| team(&mut rng)).collect();
    let mut k = 0;
    c.bench_function("nearest/10k", |b| {
        b.iter(|| {
            k = (k + 1) % queries.len();
            nn.nearest(black_box(&queries[k]))
        })
    });

    c.bench_function("motion_valid/rk4/1s", |b| {
        b.iter(|| {
            p.checker
                .motion_valid(&rk4, black_box(&x), &soft, 1.0, &mut out)
        })
    });
    c.bench_function("motion_valid/exact/1s", |b| {
        b.iter(|| {
            p.checker
                .motion_valid(&p.model, black_box(&x), &soft, 1.0, &mut out)
        })
    });

    let mut group = c.benchmark_group("goal_zoom_rrt");
    group.sample_size(20);
    let mut seed = 0;
    group.bench_function("micro_factory", |b| {
        b.iter(|| {
            let mut q = p.clone();
            q.seed = seed;
            q.limits = Limits {
                max_iterations: Some(200_000),
                time_limit: None,
            };
            seed += 1;
            let mut planner: Box<dyn Planner> =
                Planners::builtin().create("goal-zoom-rrt", &[]).unwrap();
            planner.solve(&q).solved
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
