//! The exact flow of a nominal pair: against a 30-digit ODE solution and fine RK4, its
//! symmetries, finite-time contact, the singular orbits, and the RK4 path it leaves alone.

use std::f64::consts::{FRAC_PI_2, PI};

use magbench_env::model::Flow;
use magbench_env::{Control, LocalView, PhysicalParams, PlanningModel, Vec2};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn model() -> PlanningModel {
    PlanningModel::new(&PhysicalParams::default())
}

fn pair(r: f64, phi: f64) -> [Vec2; 2] {
    LocalView::new(20.0, 15.0, r, phi).to_pair()
}

fn end(m: &PlanningModel, s: &[Vec2], u: &Control, t: f64) -> Vec<Vec2> {
    let mut out = vec![Vec2::zeros(); s.len()];
    m.propagate(s, u, t, &mut out);
    out
}

fn deviation(a: &[Vec2], b: &[Vec2]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max)
}

/// (r₀, ψ₀, t, r(t), ψ(t)) from mpmath's Taylor ODE solver at 30 digits with
/// κ = 23.829562066868142 (the default preset's), ṙ = κ(1 − 3cos²ψ)/r⁴, ψ̇ = −κ sin2ψ/r⁵.
const ODE_30_DIGITS: [(f64, f64, f64, f64, f64); 5] = [
    (3.0, 1.2, 2.0, 3.2368606819491443, 1.0805949757674294),
    (5.5, 0.3, 2.0, 5.406086828520738, 0.2944651220321059),
    (2.5, 2.0, 0.4, 2.589882778267708, 2.0709261740231213),
    (4.0, -0.9, 1.5, 3.9702536435295634, -0.8651681178902596),
    (1.6, FRAC_PI_2, 1.0, 2.6457176616053095, FRAC_PI_2),
];

#[test]
fn agrees_with_a_30_digit_ode_solution() {
    let m = model();
    assert!((PhysicalParams::default().kappa() - 23.829562066868142).abs() < 1e-12);
    for &(r0, psi0, t, r1, psi1) in &ODE_30_DIGITS {
        let phi0 = 0.7;
        let u = Control::planar(phi0 + psi0, 0.0, 0.0);
        let e = end(&m, &pair(r0, phi0), &u, t);
        let v = LocalView::from_pair(e[0], e[1]);
        let psi = u.theta - v.phi;
        assert!(
            (v.r - r1).abs() < 1e-12,
            "r₀ {r0} ψ₀ {psi0}: r {} vs {r1}",
            v.r
        );
        assert!(
            (psi.sin() - psi1.sin()).abs() < 1e-12 && (psi.cos() - psi1.cos()).abs() < 1e-12,
            "r₀ {r0} ψ₀ {psi0}: ψ {psi} vs {psi1}"
        );
    }
}

#[test]
fn agrees_with_rk4_at_a_sixteenth_of_the_step_on_10k_random_edges() {
    let p = PhysicalParams::default();
    let exact = model();
    let mut fine = exact.with_flow(Flow::Rk4);
    fine.dt = p.dt_s / 16.0;
    let g = p.gradient_limit();
    let mut rng = ChaCha8Rng::seed_from_u64(10);
    let (mut worst, mut checked) = (0.0f64, 0);
    while checked < 10_000 {
        let s = pair(rng.random_range(1.25..6.0), rng.random_range(-PI..PI));
        let u = Control::planar(
            rng.random_range(-PI..PI),
            rng.random_range(-g..g),
            rng.random_range(-g..g),
        );
        let t = rng.random_range(0.0..2.0);
        let (lo, hi) = exact.pair_edge(&s, &u).unwrap().separation_range(t);
        if lo <= p.r_min || hi >= p.r_max {
            continue;
        }
        worst = worst.max(deviation(&end(&exact, &s, &u, t), &end(&fine, &s, &u, t)));
        checked += 1;
    }
    eprintln!("{checked} edges of up to 2 s: largest deviation from RK4 at dt/16 {worst:e} BL");
    assert!(worst <= 1e-6, "{worst:e}");
}

#[test]
fn symmetries_of_the_plane_the_agents_and_the_field() {
    let m = model();
    let g = PhysicalParams::default().gradient_limit();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for _ in 0..500 {
        let (r, phi) = (rng.random_range(1.3..5.9), rng.random_range(-PI..PI));
        let s = pair(r, phi);
        let theta = rng.random_range(-PI..PI);
        let (gx, gy) = (rng.random_range(-g..g), rng.random_range(-g..g));
        let t = rng.random_range(0.0..1.5);
        let u = Control::planar(theta, gx, gy);
        let e = end(&m, &s, &u, t);
        if !e.iter().all(|p| p.x.is_finite()) || (e[1] - e[0]).norm() < 0.5 {
            continue; // collapsed: nothing to compare
        }
        let tol = 1e-11;
        // translation
        let shift = Vec2::new(3.25, -1.5);
        let moved: Vec<Vec2> = s.iter().map(|p| p + shift).collect();
        let e2 = end(&m, &moved, &u, t);
        assert!(deviation(&e2, &e.iter().map(|p| p + shift).collect::<Vec<_>>()) < tol);
        // swapping the agents
        let e2 = end(&m, &[s[1], s[0]], &u, t);
        assert!(deviation(&e2, &[e[1], e[0]]) < tol);
        // mirror in the x axis: y → −y, θ → −θ (the tri-axial pull mirrors with it)
        let mirror = |p: &Vec2| Vec2::new(p.x, -p.y);
        let e2 = end(
            &m,
            &s.iter().map(mirror).collect::<Vec<_>>(),
            &Control::planar(-theta, gx, gy),
            t,
        );
        assert!(deviation(&e2, &e.iter().map(mirror).collect::<Vec<_>>()) < tol);
        // rotation of the plane and the field together (no gradient: the coil's pull axes are
        // fixed in the lab frame)
        let u0 = Control::planar(theta, 0.0, 0.0);
        let e0 = end(&m, &s, &u0, t);
        let beta = rng.random_range(-PI..PI);
        let (sb, cb) = beta.sin_cos();
        let c = Vec2::new(20.0, 15.0);
        let rot = |p: &Vec2| {
            let d = p - c;
            c + Vec2::new(cb * d.x - sb * d.y, sb * d.x + cb * d.y)
        };
        let e2 = end(
            &m,
            &s.iter().map(rot).collect::<Vec<_>>(),
            &Control::planar(theta + beta, 0.0, 0.0),
            t,
        );
        assert!(deviation(&e2, &e0.iter().map(rot).collect::<Vec<_>>()) < tol);
        // flipping the field keeps the pair's motion and reverses the pull
        let e2 = end(&m, &s, &u.flipped(), t);
        let (d1, d2) = (e[1] - e[0], e2[1] - e2[0]);
        assert!((d1 - d2).norm() < tol);
        let c0 = (s[0] + s[1]) * 0.5;
        let (m1, m2) = ((e[0] + e[1]) * 0.5 - c0, (e2[0] + e2[1]) * 0.5 - c0);
        assert!((m1 + m2).norm() < tol);
        // a motion in two parts ends where the whole does
        let half = end(&m, &end(&m, &s, &u, 0.4 * t), &u, 0.6 * t);
        assert!(deviation(&half, &e) < 1e-10, "{}", deviation(&half, &e));
    }
}

#[test]
fn an_aligned_pair_collapses_in_finite_time() {
    let m = model();
    let kappa = PhysicalParams::default().kappa();
    for &r0 in &[1.3, 2.0, 3.7] {
        // ψ = 0: r⁵ = r₀⁵ − 10κt; the agents touch (r = 1) at t* = (r₀⁵ − 1)/(10κ)
        let s = pair(r0, 0.3);
        let u = Control::planar(0.3, 0.0, 0.0);
        let edge = m.pair_edge(&s, &u).unwrap();
        let touch = (r0.powi(5) - 1.0) / (10.0 * kappa);
        let t = edge.exit_time(10.0 * touch, 1.0, f64::INFINITY).unwrap();
        assert!((t - touch).abs() < 1e-12 * touch, "r₀ {r0}: {t} vs {touch}");
        let at = |t: f64| (r0.powi(5) - 10.0 * kappa * t).powf(0.2);
        for f in [0.1, 0.5, 0.99] {
            assert!((edge.separation_at(f * touch) - at(f * touch)).abs() < 1e-12);
        }
        // and it has collapsed (r = 0) by r₀⁵/(10κ)
        assert_eq!(edge.separation_at(1.01 * r0.powi(5) / (10.0 * kappa)), 0.0);
        // a pair a hair off the axis does the same
        let e2 = m
            .pair_edge(&s, &Control::planar(0.3 + 1e-9, 0.0, 0.0))
            .unwrap();
        let t2 = e2.exit_time(10.0 * touch, 1.0, f64::INFINITY).unwrap();
        assert!((t2 - touch).abs() < 1e-9 * touch);
    }
}

#[test]
fn the_first_exit_from_the_proximity_range_is_exact() {
    let m = model();
    let p = PhysicalParams::default();
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let mut found = 0;
    for _ in 0..2000 {
        let s = pair(rng.random_range(1.3..5.9), rng.random_range(-PI..PI));
        let u = Control::planar(rng.random_range(-PI..PI), 0.0, 0.0);
        let edge = m.pair_edge(&s, &u).unwrap();
        let Some(t) = edge.exit_time(2.0, p.r_min, p.r_max) else {
            let (lo, hi) = edge.separation_range(2.0);
            assert!(lo > p.r_min && hi < p.r_max);
            continue;
        };
        found += 1;
        // at the exit the separation is on the boundary, and just before it is inside
        let r = edge.separation_at(t);
        assert!(
            (r - p.r_min).abs() < 1e-9 || (r - p.r_max).abs() < 1e-9,
            "r = {r} at the exit"
        );
        let before = edge.separation_at(t * (1.0 - 1e-9));
        assert!(before > p.r_min && before < p.r_max);
        // a dense scan finds no earlier exit
        for k in 0..1000 {
            let r = edge.separation_at(t * k as f64 / 1000.0);
            assert!(
                r > p.r_min && r < p.r_max,
                "earlier exit at {k}/1000 of {t}"
            );
        }
    }
    assert!(found > 200, "{found}");
}

#[test]
fn the_singular_orbits_and_their_neighbours() {
    let m = model();
    let kappa = PhysicalParams::default().kappa();
    for &r0 in &[1.5, 2.5, 4.0] {
        for &t in &[0.01, 0.3, 1.7] {
            // ψ = π/2: r⁵ = r₀⁵ + 5κt, no turning
            let s = pair(r0, 0.2);
            let e = end(&m, &s, &Control::planar(0.2 + FRAC_PI_2, 0.0, 0.0), t);
            let v = LocalView::from_pair(e[0], e[1]);
            let want = (r0.powi(5) + 5.0 * kappa * t).powf(0.2);
            assert!((v.r - want).abs() < 1e-12 * want, "{} vs {want}", v.r);
            assert!((v.phi - 0.2).abs() < 1e-12);
            // next to ψ = π/2 and to ψ = 0 the flow is continuous: a 1e-12 rad change of the
            // field moves the ends by about that much, not more
            for psi in [FRAC_PI_2, 0.0] {
                let a = end(&m, &s, &Control::planar(0.2 + psi, 0.0, 0.0), t);
                let b = end(&m, &s, &Control::planar(0.2 + psi + 1e-12, 0.0, 0.0), t);
                if (a[1] - a[0]).norm() > 1.0 {
                    assert!(deviation(&a, &b) < 1e-9, "ψ {psi}: {}", deviation(&a, &b));
                }
            }
        }
    }
}

#[test]
fn rk4_still_solves_teams_of_three_and_elevated_fields_bit_for_bit() {
    // the fixed-step flow with the exact pair: RK4 wherever the closed form does not apply
    let exact = model().with_flow(Flow::PairExact);
    let rk4 = exact.with_flow(Flow::Rk4);
    let trio = [
        Vec2::new(4.0, 5.0),
        Vec2::new(6.5, 5.2),
        Vec2::new(5.1, 7.3),
    ];
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    for _ in 0..50 {
        let u = Control::planar(rng.random_range(-PI..PI), 0.02, -0.03);
        let t = rng.random_range(0.0..1.0);
        assert_eq!(end(&exact, &trio, &u, t), end(&rk4, &trio, &u, t));
        assert!(exact.pair_edge(&trio, &u).is_none());
        let pair = pair(2.2, 0.4);
        let tilted = Control {
            alpha: rng.random_range(0.01..1.5),
            ..u
        };
        assert_eq!(end(&exact, &pair, &tilted, t), end(&rk4, &pair, &tilted, t));
        assert!(exact.pair_edge(&pair, &tilted).is_none());
        // unequal agents have no closed form either
        let mut unequal = exact.clone();
        unequal.kinematics.moment[1] = 1.05;
        assert!(unequal.pair_edge(&pair, &u).is_none());
    }
    // and the exact flow applies to the planar pair
    assert!(
        exact
            .pair_edge(&pair(2.0, 0.0), &Control::planar(0.5, 0.0, 0.0))
            .is_some()
    );
}
