//! Halving the RK4 step changes an edge's end state by less than 1e-3 BL (RK4 still solves
//! teams of three or more, elevated fields and the plant), in the bulk and at the hardware
//! preset's liquid–air interface, where the agents move twice as fast and the medium's step
//! ([`magbench_env::plant::Medium::step`]) is half the bulk's.

use magbench_env::math::wrap_angle;
use magbench_env::model::Flow;
use magbench_env::plant::{DisturbancePreset, Medium};
use magbench_env::scenario::builtin_names;
use magbench_env::{Control, PlanningModel, Scenario, Vec2};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[test]
fn halving_the_step_moves_edge_ends_by_less_than_1e_3_bl() {
    halving_the_step_in(&Medium::Bulk);
}

#[test]
fn halving_the_step_at_the_interface_moves_edge_ends_by_less_than_1e_3_bl() {
    let medium = DisturbancePreset::hardware().medium;
    assert!(
        medium.interface().is_some(),
        "the hardware preset is at an interface"
    );
    halving_the_step_in(&medium);
}

fn halving_the_step_in(medium: &Medium) {
    let mut worst = 0.0f64;
    let mut checked = 0;
    for name in builtin_names() {
        let s = Scenario::load(name).unwrap();
        let fine_params = magbench_env::PhysicalParams {
            dt_s: s.physics.dt_s / 2.0,
            ..s.physics.clone()
        };
        let coarse = PlanningModel::new(&s.physics)
            .in_medium(&s.physics, medium)
            .with_flow(Flow::Rk4);
        let fine = PlanningModel::new(&fine_params)
            .in_medium(&fine_params, medium)
            .with_flow(Flow::Rk4);
        let checker = s.checker_for_leg(0);
        let g = s.physics.gradient_limit();
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        // edges from the start and from states reached along random valid edges
        let mut state = s.start.clone();
        for _ in 0..400 {
            let u = Control::planar(
                rng.random_range(-std::f64::consts::PI..std::f64::consts::PI),
                rng.random_range(-g..g),
                rng.random_range(-g..g),
            );
            let duration = (rng.random_range(6..=120) as f64) / 60.0;
            let mut a = vec![Vec2::zeros(); state.len()];
            if !checker.motion_valid(&coarse, &state, &u, duration, &mut a) {
                continue;
            }
            let mut b = vec![Vec2::zeros(); state.len()];
            fine.propagate(&state, &u, duration, &mut b);
            let d = a
                .iter()
                .zip(&b)
                .map(|(p, q)| (p - q).norm())
                .fold(0.0, f64::max);
            worst = worst.max(d);
            checked += 1;
            assert!(
                d < 1e-3,
                "{name}: θ = {:.3}, duration {duration}: end states differ by {d:e} BL",
                wrap_angle(u.theta)
            );
            state = a;
        }
    }
    assert!(checked > 200, "only {checked} valid edges were checked");
    eprintln!("{checked} edges, largest end-state change {worst:e} BL");
}
