//! One OBC tick: the tracker's command for one camera frame (nearest-sample search, the
//! brute-force field-angle grid with the closed-form pull, the refinement and the wall check),
//! on micro-factory, mid-path, with the team 0.05 BL off its reference.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use magbench_env::plant::Observation;
use magbench_env::{Control, PlanningModel, Scenario, Vec2};
use magbench_planners::Plan;
use magbench_trackers::{ObcOptimizer, ObcWeights, Reference, Tick, TrackerContext, TrackerSpec};

/// A reference through the open middle of micro-factory, made by propagating the planning
/// model.
fn reference(s: &Scenario, model: &PlanningModel) -> Reference {
    let start = magbench_env::LocalView {
        xc: 32.0,
        yc: 10.0,
        r: 2.5,
        phi: 0.0,
    }
    .to_pair()
    .to_vec();
    let mut plan = Plan::at(&start);
    let mut x = start;
    let g = model.coil.gradient_limit();
    for k in 0..40 {
        // near the magic angle either side of the pair heading: the pair turns to and fro
        // while the gradient pulls it along
        let phi = (x[1] - x[0]).y.atan2((x[1] - x[0]).x);
        let side = if k % 2 == 0 { 1.0 } else { -1.0 };
        let u = Control::planar(
            phi + side * (1.0f64 / 3.0).sqrt().acos(),
            0.6 * g,
            0.4 * g * (k as f64).cos(),
        );
        let mut out = vec![Vec2::zeros(); 2];
        model.propagate_with(&x, &u, 6.0 / 60.0, &mut out, |_| true);
        plan.push(u, 6.0 / 60.0, out.clone());
        x = out;
    }
    assert!(
        s.checker_for_leg(0).is_valid(plan.end()),
        "{:?}",
        plan.end()
    );
    Reference::from_plan(&plan, model)
}

fn bench(c: &mut Criterion) {
    let s = Scenario::load("micro-factory").unwrap();
    let model = PlanningModel::new(&s.physics);
    let checker = s.checker_for_leg(0);
    let r = reference(&s, &model);
    let k = r.len() / 2;
    let x: Vec<Vec2> = r
        .state(k)
        .iter()
        .map(|p| p + Vec2::new(0.03, -0.04))
        .collect();
    let obs = Observation {
        t: 0.0,
        agents: x.iter().map(|p| Some(*p)).collect(),
    };
    let period = 1.0 / 60.0;
    let ctx = TrackerContext {
        reference: &r,
        model: &model,
        checker: &checker,
        period,
    };
    for name in ["obc", "lookahead"] {
        let mut tracker = TrackerSpec::parse(name, &[], "bench").unwrap().build();
        tracker.reset(&ctx);
        // settle its progress near the middle
        tracker.command(
            &ctx,
            &Tick {
                t: r.time(k),
                estimate: &x,
                observation: &obs,
            },
        );
        c.bench_function(&format!("{name} tick (micro-factory)"), |b| {
            b.iter(|| {
                black_box(tracker.command(
                    &ctx,
                    &Tick {
                        t: r.time(k),
                        estimate: black_box(&x),
                        observation: &obs,
                    },
                ))
            })
        });
    }
    let opt = ObcOptimizer::new(
        model.clone(),
        checker.clone(),
        period,
        ObcWeights::default(),
    );
    let target = r.state(k + 2).to_vec();
    c.bench_function("obc optimizer solve", |b| {
        b.iter(|| {
            black_box(opt.solve(
                black_box(&x),
                &target,
                Some(&Control::planar(1.0, 0.0, 0.0)),
                None,
            ))
        })
    });
    c.bench_function("planning-model prediction (one frame)", |b| {
        let mut out = vec![Vec2::zeros(); 2];
        b.iter(|| {
            model.propagate_with(
                black_box(&x),
                &Control::planar(1.0, 0.0, 0.0),
                period,
                &mut out,
                |_| true,
            )
        })
    });
    c.bench_function("wall clearance (one agent)", |b| {
        b.iter(|| checker.collision.clearance(black_box(x[0])))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
