use magbench_env::model::rk4_step;
use magbench_env::{Coil, Control, PhysicalParams, PlanningModel, Vec2};
fn main() {
    let m = PlanningModel::new(&PhysicalParams::default());
    let start = [Vec2::new(10.0, 10.0), Vec2::new(12.5, 10.3)];
    let mut out = [Vec2::zeros(); 2];
    let t = std::time::Instant::now();
    let mut acc = 0.0;
    let n = 200_000;
    for i in 0..n {
        let u = Control::planar(i as f64 * 0.001, 0.01, -0.02);
        m.propagate_with(&start, &u, 30.0 / 120.0, &mut out, |_| true);
        acc += out[0].x;
    }
    let dt = t.elapsed().as_secs_f64();
    println!(
        "{:.1} ns per RK4 step ({acc})",
        dt / (n as f64 * 30.0) * 1e9
    );
    // lockstep over 8 tries
    let t = std::time::Instant::now();
    let mut acc2 = 0.0;
    for i in 0..n / 8 {
        let acts: Vec<_> = (0..8)
            .map(|k| {
                m.coil
                    .actuation(&Control::planar((i * 8 + k) as f64 * 0.001, 0.01, -0.02))
            })
            .collect();
        let mut ps = [start; 8];
        for _ in 0..30 {
            for k in 0..8 {
                let act = acts[k];
                let f = |p: &[Vec2], v: &mut [Vec2]| m.kinematics.velocities(p, &act, v);
                rk4_step(&f, &mut ps[k], m.dt);
            }
        }
        for k in 0..8 {
            acc2 += ps[k][0].x;
        }
    }
    let dt = t.elapsed().as_secs_f64();
    println!(
        "{:.1} ns per RK4 step lockstep ({acc2})",
        dt / (n as f64 * 30.0) * 1e9
    );
}
