//! The planning model's two integrators for a team of three, on trio-triangle:
//!
//! - `trio_motion/{pair-exact,pair-adaptive}`: one motion of 0.25–2 s from the scenario's start
//!   under 1024 random commands (elevation up to 45°) in turn, by fixed-step RK4 and by adaptive
//!   Dormand–Prince 5(4);
//! - `trio_plan/{pair-exact,pair-adaptive}`: goal-zoom-rrt to its first solution, seeds 0, 1,
//!   2, … in turn (iterations/s: the plans' summed iterations over their summed time, printed
//!   as a Markdown table after the group).
//!
//! ```sh
//! cargo bench -p magbench-benches --bench team_flows
//! ```

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use magbench_benches::first_plan;
use magbench_env::model::Flow;
use magbench_env::{Control, Scenario, Vec2};
use magbench_planners::Problem;
use rand::{RngExt, SeedableRng};

const FLOWS: [Flow; 2] = [Flow::PairExact, Flow::PairAdaptive];

fn bench(c: &mut Criterion) {
    let s = Scenario::load("trio-triangle").unwrap();
    let p = Problem::from_scenario(&s, 0, None, 0);
    let g = p.model.coil.gradient_limit();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    let motions: Vec<(Control, f64)> = (0..1024)
        .map(|_| {
            let u = Control {
                theta: rng.random_range(-std::f64::consts::PI..std::f64::consts::PI),
                alpha: rng.random_range(0.0..std::f64::consts::FRAC_PI_4),
                grad: [rng.random_range(-g..=g), rng.random_range(-g..=g)],
            };
            (u, p.periods(rng.random_range(15..=120)))
        })
        .collect();
    let mut out = vec![Vec2::zeros(); 3];
    let mut group = c.benchmark_group("trio_motion");
    for flow in FLOWS {
        let m = p.model.with_flow(flow);
        let mut k = 0;
        group.bench_function(flow.name(), |b| {
            b.iter(|| {
                k = (k + 1) % motions.len();
                let (u, d) = &motions[k];
                m.propagate(black_box(&p.start), u, *d, &mut out)
            })
        });
    }
    group.finish();

    let mut group = c.benchmark_group("trio_plan");
    group.sample_size(20);
    let mut rates = Vec::new();
    for flow in FLOWS {
        let (mut seed, mut iterations, mut seconds) = (0, 0u64, 0.0);
        group.bench_function(flow.name(), |b| {
            b.iter(|| {
                let (r, s) = first_plan(&p, flow, seed);
                seed += 1;
                seconds += s;
                iterations += r.iterations;
                r.solved
            })
        });
        rates.push((flow, seed, iterations as f64 / seconds));
    }
    group.finish();
    println!(
        "| trio_plan flow | plans run (warm-up included) | iterations/s (Σ iterations ÷ Σ time) |"
    );
    println!("| --- | --- | --- |");
    for (flow, plans, rate) in rates {
        println!("| {} | {plans} | {rate:.0} |", flow.name());
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
