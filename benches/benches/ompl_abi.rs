//! The C ABI's overhead (feature `ompl`): one propagation step (one control period, the exact
//! flow with magbench's continuous edge check) on micro-factory's start,
//!
//! - `ompl_abi/direct`: `motion::propagate_valid` called from Rust;
//! - `ompl_abi/through_ompl`: OMPL's `SpaceInformation::propagate`, whose StatePropagator
//!   calls back into the same function over the C ABI (the loop runs in C++; its time only).
//!
//! ```sh
//! cargo bench -p magbench-benches --features ompl --bench ompl_abi
//! ```

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use magbench_env::{Control, Scenario, Vec2};
use magbench_planners::Problem;
use magbench_planners::motion::propagate_valid;
use magbench_planners::ompl::propagate_through_ompl;

fn bench(c: &mut Criterion) {
    let s = Scenario::load("micro-factory").unwrap();
    let p = Problem::from_scenario(&s, 0, None, 0);
    let u = Control::planar(0.7, 0.3 * p.model.coil.gradient_limit(), -0.1);
    let mut g = c.benchmark_group("ompl_abi");
    g.bench_function("direct", |b| {
        let mut out = vec![Vec2::zeros(); p.agents()];
        b.iter(|| {
            black_box(propagate_valid(
                &p,
                black_box(&p.start),
                &u,
                p.control_period,
                &mut out,
            ))
        })
    });
    g.bench_function("through_ompl", |b| {
        b.iter_custom(|iters| {
            let start = Instant::now();
            let (_, t) = propagate_through_ompl(&p, &p.start, &u, iters).expect("OMPL runs");
            // the loop's own time; the one-off setup of OMPL's SpaceInformation is excluded
            black_box(start.elapsed());
            t.max(Duration::from_nanos(1))
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
