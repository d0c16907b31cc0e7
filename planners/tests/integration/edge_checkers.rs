//! The exact-flow edge check (exact separation range + conservative advancement) and the RK4
//! sampled check (proximity at samples + capsule sweeps between them) give the same verdict on
//! random edges of every built-in scenario, except on edges that pass within a hair of a wall
//! or of the proximity range, where the two motions (exact, and RK4 at 1/120 s with chords)
//! legitimately differ by ~1e-5 BL.

use magbench_env::model::Flow;
use magbench_env::scenario::builtin_names;
use magbench_env::{Control, Scenario, Vec2};
use magbench_planners::motion::random_control;
use magbench_planners::sampler::{StateSampler, valid_sample};
use magbench_planners::{Problem, Rng};
use rand::{RngExt, SeedableRng};

/// Margin (BL) within which a disagreement counts as a graze of a wall or of the range.
const HAIR: f64 = 1e-3;

/// The smallest wall clearance and proximity-range margin along the exact motion, sampled
/// densely (2000 points per second).
fn margins(p: &Problem, x: &[Vec2], u: &Control, d: f64) -> (f64, f64) {
    let edge = p.model.pair_edge(x, u).expect("two agents, planar field");
    let samples = (d * 2000.0).ceil() as usize;
    let (mut wall, mut range) = (f64::INFINITY, f64::INFINITY);
    let mut s = [Vec2::zeros(); 2];
    for k in 0..=samples {
        edge.at(d * k as f64 / samples as f64, &mut s);
        wall = wall.min(p.checker.clearance(&s));
        let r = (s[1] - s[0]).norm();
        range = range.min(r - p.checker.r_min).min(p.checker.r_max - r);
    }
    (wall, range)
}

#[test]
fn exact_and_sampled_checks_agree_on_random_edges() {
    let (mut total, mut valid, mut grazes) = (0usize, 0usize, 0usize);
    for name in builtin_names() {
        let s = Scenario::load(name).unwrap();
        if s.start.len() != 2 {
            continue;
        }
        let p = Problem::from_scenario(&s, 0, None, 0);
        let rk4 = p.model.with_flow(Flow::Rk4);
        let sampler = StateSampler::new(&p);
        let mut rng = Rng::seed_from_u64(23);
        let g = p.model.coil.gradient_limit();
        let mut x = vec![Vec2::zeros(); 2];
        let (mut a, mut b) = (vec![Vec2::zeros(); 2], vec![Vec2::zeros(); 2]);
        for _ in 0..3000 {
            assert!(valid_sample(&p, 1000, &mut x, |st| sampler.uniform(&mut rng, st)));
            let u = random_control(&mut rng, g);
            let d = p.periods(rng.random_range(1..=120));
            let exact = p.checker.motion_valid(&p.model, &x, &u, d, &mut a);
            let sampled = p.checker.motion_valid(&rk4, &x, &u, d, &mut b);
            total += 1;
            valid += usize::from(exact);
            if exact != sampled {
                let (wall, range) = margins(&p, &x, &u, d);
                assert!(
                    wall.abs() < HAIR || range.abs() < HAIR,
                    "{name}: exact {exact}, sampled {sampled}, but the motion keeps {wall} BL \
                     from walls and {range} BL inside the range: x {x:?} u {u:?} d {d}"
                );
                grazes += 1;
            }
        }
    }
    eprintln!(
        "{total} edges, {valid} valid; {grazes} verdicts differ, each a graze within {HAIR} BL"
    );
    assert!(total >= 10_000 && valid > total / 10 && valid < total * 9 / 10);
}
