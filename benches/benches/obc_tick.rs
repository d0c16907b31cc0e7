//! One OBC tick: the tracker's command for one camera frame (nearest-sample search, the
//! brute-force field-angle grid with the closed-form pull, the refinement and the wall check),
//! on micro-factory, mid-path, with the team 0.05 BL off its reference; the optimizer alone for
//! the pair and for three agents, planar and elevated; each tracker's tick on a team of ten. The
//! MPPI tracker's tick at its defaults is timed beside them (`mppi tick (micro-factory)`, `mppi
//! tick (ten agents)`).
//! After the criterion
//! groups, whole simulated runs give the median and 99th percentile of the per-tick time,
//! printed as a Markdown table (`cargo xtask measure --only bench-obc-tick` keeps it).
//!
//! Run: `cargo bench -p magbench-benches --bench obc_tick`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group};
use magbench_env::coil::Planar;
use magbench_env::plant::{DisturbancePreset, Observation};
use magbench_env::scenario::generate::generate;
use magbench_env::{Control, LocalView, PlanningModel, Scenario, Vec2};
use magbench_planners::registry::Planners;
use magbench_planners::{Limits, Plan, PlanningSetup};
use magbench_trackers::{
    Mission, ObcOptimizer, ObcWeights, Reference, Tick, TrackerContext, Trackers, simulate,
};

/// A plan through the open middle of micro-factory, made by propagating the planning model:
/// the field near the magic angle either side of the pair heading (the pair turns to and fro)
/// while the gradient pulls it along.
/// The estimate a tick sees: the reference's state `k` off by (0.03, −0.04) BL, and its
/// observation.
fn off_reference(r: &Reference, k: usize) -> (Vec<Vec2>, Observation) {
    let x: Vec<Vec2> = r
        .state(k)
        .iter()
        .map(|p| p + Vec2::new(0.03, -0.04))
        .collect();
    let obs = Observation {
        t: 0.0,
        agents: x.iter().map(|p| Some(*p)).collect(),
    };
    (x, obs)
}

fn plan(model: &PlanningModel) -> Plan {
    let start = LocalView {
        xc: 32.0,
        yc: 10.0,
        r: 2.5,
        phi: 0.0,
    }
    .to_pair()
    .to_vec();
    let magic = (1.0f64 / 3.0).sqrt().acos();
    let g = model.coil.gradient_limit();
    let mut plan = Plan::at(&start);
    let mut x = start;
    for k in 0..40 {
        let phi = (x[1] - x[0]).y.atan2((x[1] - x[0]).x);
        let side = if k % 2 == 0 { 1.0 } else { -1.0 };
        let u = Control::planar(phi + side * magic, 0.6 * g, 0.4 * g * (k as f64).cos());
        let mut out = vec![Vec2::zeros(); 2];
        model.propagate_with(&x, &u, 6.0 / 60.0, &mut out, |_| true);
        plan.push(u, 6.0 / 60.0, out.clone());
        x = out;
    }
    plan
}

fn bench(c: &mut Criterion) {
    let s = Scenario::load("micro-factory").unwrap();
    let model = PlanningModel::new(&s.physics);
    let checker = s.checker_for_leg(0);
    let p = plan(&model);
    assert!(checker.is_valid(p.end()), "{:?}", p.end());
    let r = Reference::from_plan(&p, &model);
    let k = r.len() / 2;
    let (x, obs) = off_reference(&r, k);
    let period = 1.0 / 60.0;
    let ctx = TrackerContext {
        reference: &r,
        model: &model,
        world: &s.world,
        checker: &checker,
        period,
        goal: s.final_goal(),
        seed: 0,
    };
    for name in ["obc", "lookahead", "mppi"] {
        let mut tracker = Trackers::builtin()
            .spec(name, &[], "bench")
            .unwrap()
            .build();
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
    ten_agents(c);
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
    // three agents mid-field: the elevated search (θ grid × α levels, alternating refinement)
    // against the planar one
    let x3 = [
        Vec2::new(31.0, 10.0),
        Vec2::new(33.5, 10.0),
        Vec2::new(32.25, 12.165),
    ];
    let target3: Vec<Vec2> = x3.iter().map(|p| p + Vec2::new(0.02, 0.01)).collect();
    for (label, planar) in [("planar", Planar::Yes), ("elevated", Planar::Auto)] {
        let weights = ObcWeights {
            planar,
            ..ObcWeights::default()
        };
        let opt3 = ObcOptimizer::new(model.clone(), checker.clone(), period, weights);
        c.bench_function(
            &format!("obc optimizer solve (three agents, {label})"),
            |b| {
                b.iter(|| {
                    black_box(opt3.solve(
                        black_box(&x3),
                        &target3,
                        Some(&Control::planar(1.0, 0.0, 0.0)),
                        None,
                    ))
                })
            },
        );
    }
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

/// One tick of each closed-loop tracker on a team of ten: a ring at 1.8 BL spacing (the `team`
/// family) moved 8 BL by formation-rrt's plan, mid-plan, with every agent 0.05 BL off its
/// reference.
fn ten_agents(c: &mut Criterion) {
    let params: Vec<(String, String)> = [("agents", "10"), ("spacing", "1.8")]
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    let s = generate("bench", "team", &params, 1, 0).unwrap().scenario;
    let setup = PlanningSetup {
        limits: Limits {
            max_iterations: Some(2_000),
            time_limit: None,
        },
        ..PlanningSetup::default()
    };
    let problem = setup.problem(&s, 0, None, 1);
    let solved = Planners::builtin()
        .create("formation-rrt", &[])
        .unwrap()
        .solve(&problem);
    assert!(solved.solved, "formation-rrt left the ring of ten unsolved");
    let model = &problem.model;
    let r = Reference::from_plan(&solved.plan, model);
    let k = r.len() / 2;
    let (x, obs) = off_reference(&r, k);
    let ctx = TrackerContext {
        reference: &r,
        model,
        world: &s.world,
        checker: &problem.checker,
        period: 1.0 / 60.0,
        goal: s.final_goal(),
        seed: 0,
    };
    let tick = Tick {
        t: r.time(k),
        estimate: &x,
        observation: &obs,
    };
    for name in ["formation", "obc", "lookahead", "mppi"] {
        let mut tracker = Trackers::builtin()
            .spec(name, &[], "bench")
            .unwrap()
            .build();
        tracker.reset(&ctx);
        tracker.command(&ctx, &tick);
        c.bench_function(&format!("{name} tick (ten agents)"), |b| {
            b.iter(|| black_box(tracker.command(&ctx, black_box(&tick))))
        });
    }
}

/// Per-tick times of whole simulated runs (realistic preset) of the same plan: median and 99th
/// percentile of the tracker's command time, which criterion's estimates of the mean do not
/// give.
fn tick_percentiles() {
    let mut s = Scenario::load("micro-factory").unwrap();
    let model = PlanningModel::new(&s.physics);
    let p = plan(&model);
    s.start = p.start().to_vec();
    println!("| tracker | simulated ticks (5 runs, realistic) | median | p99 |");
    println!("| --- | --- | --- | --- |");
    for name in ["obc", "lookahead", "mppi"] {
        let spec = Trackers::builtin()
            .spec(name, &[("time_slack".into(), "8".into())], "bench")
            .unwrap();
        let mut us: Vec<f64> = vec![];
        for seed in 0..5 {
            let mut m = Mission::with_plan(&s, p.clone());
            m.seed = seed;
            let out = simulate(
                m,
                spec.build().as_mut(),
                &DisturbancePreset::realistic(),
                &spec.loop_options(),
            );
            us.extend(
                out.ticks
                    .iter()
                    .filter(|t| t.mode != "end")
                    .map(|t| t.compute_us),
            );
        }
        us.sort_by(f64::total_cmp);
        let q = |f: f64| us[((us.len() - 1) as f64 * f).round() as usize];
        println!(
            "| {name} | {} | {:.1} µs | {:.1} µs |",
            us.len(),
            q(0.5),
            q(0.99)
        );
    }
}

criterion_group!(benches, bench);

fn main() {
    benches();
    tick_percentiles();
    Criterion::default().configure_from_args().final_summary();
}
