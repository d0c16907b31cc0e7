//! One camera frame (1/60 s) of the simulated plant under each built-in preset, on
//! micro-factory mid-maze: the exact pair flow (ideal), RK4 of the legacy terms (realistic),
//! and every term with the magnet-lag sub-steps (hardware).
//!
//! Run: `cargo bench -p magbench-benches --bench plant_frame`.

use std::hint::black_box;
use std::sync::Arc;

use criterion::{Criterion, criterion_group, criterion_main};
use magbench_env::collision::CollisionWorld;
use magbench_env::plant::{DisturbancePreset, Plant};
use magbench_env::{Coil, Control, LocalView, Scenario, TriaxialMaxwell, Vec2};

fn bench(c: &mut Criterion) {
    let s = Scenario::load("micro-factory").unwrap();
    let p = &s.physics;
    let coil: Arc<dyn Coil> = Arc::new(TriaxialMaxwell::new(p.gradient_limit()));
    let collision = Arc::new(CollisionWorld::new(&s.world, 0.5));
    let start = LocalView {
        xc: 32.0,
        yc: 10.0,
        r: 2.5,
        phi: 0.0,
    }
    .to_pair();
    let magic = (1.0f64 / 3.0).sqrt().acos();
    let g = p.gradient_limit();
    for name in DisturbancePreset::NAMES {
        let preset = DisturbancePreset::by_name(name).unwrap();
        let mut plant = Plant::new(p, coil.clone(), collision.clone(), &preset, 1, &start);
        plant.set_coil_centre(Vec2::new(s.world.width, s.world.height) * 0.5);
        let mut k = 0u64;
        c.bench_function(&format!("plant frame/{name}"), |b| {
            b.iter(|| {
                // hold the field at the magic angle to the pair, on one side then the other
                // every half second, while the gradient pulls; start over every 10 s or when
                // the pair sticks (a stuck plant does no work)
                k += 1;
                if k.is_multiple_of(600) || plant.stuck() {
                    plant = Plant::new(p, coil.clone(), collision.clone(), &preset, k, &start);
                    plant.set_coil_centre(Vec2::new(s.world.width, s.world.height) * 0.5);
                }
                let side = if (k / 30).is_multiple_of(2) {
                    1.0
                } else {
                    -1.0
                };
                let d = plant.positions()[1] - plant.positions()[0];
                let u = Control::planar(d.y.atan2(d.x) + side * magic, 0.5 * g, -0.3 * g);
                plant.run(black_box(&u), 1.0 / 60.0);
                black_box(plant.positions()[0])
            })
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
