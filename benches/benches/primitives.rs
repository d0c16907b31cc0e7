//! The planning primitives on micro-factory: one propagation step, one EXTEND (the seed's
//! k = 10 tries), a nearest-neighbour query among 10k tree nodes, a motion validity check, and
//! a goal-zoom-rrt plan capped at 2000 iterations (throughput; time to a first solution is the
//! planners' own bench).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use magbench_env::{Control, LocalView, Scenario, Vec2};
use magbench_planners::extend::Extend;
use magbench_planners::nn::NearestNeighbors;
use magbench_planners::{Limits, Metric, Problem, Rng, registry};
use rand_chacha::rand_core::SeedableRng;

fn pair(xc: f64, yc: f64, r: f64, phi: f64) -> Vec<Vec2> {
    LocalView { xc, yc, r, phi }.to_pair().to_vec()
}

fn problem() -> Problem {
    let s = Scenario::load("micro-factory").expect("built-in");
    Problem::from_scenario(&s, 0, None, 7)
}

fn primitives(c: &mut Criterion) {
    let p = problem();
    let g = p.model.coil.gradient_limit();
    let start = pair(32.0, 10.0, 2.2, 0.4);
    let u = Control::planar(1.1, 0.5 * g, -0.3 * g);
    let mut out = vec![Vec2::zeros(); 2];

    c.bench_function("propagate one RK4 step (1/120 s)", |b| {
        b.iter(|| {
            p.model.propagate_with(
                black_box(&start),
                black_box(&u),
                1.0 / 120.0,
                &mut out,
                |_| true,
            )
        })
    });

    let ext = Extend {
        tries: 10,
        min_periods: 1,
        max_periods: 30,
    };
    let target = pair(34.0, 12.0, 2.0, 1.0);
    let mut rng = Rng::seed_from_u64(1);
    c.bench_function("EXTEND (k = 10 tries, up to 0.5 s each)", |b| {
        b.iter(|| black_box(ext.run(&p, &mut rng, black_box(&start), black_box(&target))))
    });

    let mut nn = NearestNeighbors::new(Metric::Positions, 2);
    let mut rng = Rng::seed_from_u64(2);
    use rand::RngExt;
    for id in 0..10_000u32 {
        let s = pair(
            rng.random_range(1.0..47.0),
            rng.random_range(1.0..31.0),
            rng.random_range(1.3..5.9),
            rng.random_range(-3.1..3.1),
        );
        nn.add(&s, id);
    }
    let q = pair(20.0, 15.0, 2.5, 0.3);
    c.bench_function("nearest neighbour among 10k nodes", |b| {
        b.iter(|| black_box(nn.nearest(black_box(&q))))
    });

    c.bench_function(
        "motion validity check (0.25 s motion, swept capsules)",
        |b| {
            b.iter(|| {
                p.checker
                    .motion_valid(&p.model, black_box(&start), black_box(&u), 0.25, &mut out)
            })
        },
    );

    let mut group = c.benchmark_group("plan");
    group.sample_size(10);
    group.bench_function("goal-zoom-rrt on micro-factory, 2000 iterations", |b| {
        b.iter(|| {
            let mut planner = registry::create("goal-zoom-rrt", &[]).expect("registered");
            let mut q = problem();
            q.limits = Limits {
                max_iterations: Some(2000),
                time_limit: None,
            };
            black_box(planner.solve(&q))
        })
    });
    group.finish();
}

criterion_group!(benches, primitives);
criterion_main!(benches);
