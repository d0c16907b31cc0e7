//! Which directions a team can move in while its fields hold its shape, at first order, when its
//! agents' moments and drags differ (docs/physics.md, "A team whose agents differ").
//!
//! Averaged over fast switching, the fields move a shape by `F₀ + x₁₁F₁₁ + x₁₂F₁₂ + x₂₂F₂₂`
//! (their span is `{F₀, A, B}`, since `M' = −(3/2)F₀` per pair whatever the agents' factors),
//! and a pull `g` moves it by `g_x S_x + g_y S_y`, where `S` is the agents' spread of moment
//! times mobility. The shape holds while the team moves along `g` when `g·S` lies in the span of
//! the fields: the directions of such `g` are a space of dimension
//! `rank{F₀, A, B} + 2 − rank{F₀, A, B, S_x, S_y}`.

use magbench_env::math::MAX_AGENTS;
use magbench_env::model::Kinematics;
use magbench_env::team_controllability::{BasisFields, RANK_TOL, Shape, rank, shape_of};
use magbench_env::{Actuation, PhysicalParams, Vec2, Vec3};

/// A regular ring of `n` at neighbour spacing 1.8 BL (two agents: a pair 1.8 BL apart).
fn ring(n: usize) -> Vec<Vec2> {
    let r = 1.8 / (2.0 * (std::f64::consts::PI / n as f64).sin());
    (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64 + 0.1;
            Vec2::new(a.cos(), a.sin()) * r
        })
        .collect()
}

/// The default physics with moment and mobility factors spread within ±10% (fixed, uneven
/// values, as the `realistic` preset's draws are), or all 1.
fn kinematics(differ: bool) -> Kinematics {
    let mut k = Kinematics::nominal(&PhysicalParams::default());
    if differ {
        for i in 0..MAX_AGENTS {
            k.moment[i] = 1.0 + 0.1 * (1.7 * i as f64 + 0.3).sin();
            k.mobility[i] = 1.0 + 0.1 * (2.9 * i as f64 + 1.1).cos();
        }
    }
    k
}

/// The shape velocity of a unit pull along `axis`, the field's part taken away.
fn pull_direction(k: &Kinematics, positions: &[Vec2], axis: Vec3) -> Shape {
    let n = positions.len();
    let velocity = |pull: Vec3| {
        let act = Actuation {
            b_hat: Vec3::new(0.0, 0.0, 1.0),
            pull,
        };
        let mut v = [Vec2::zeros(); MAX_AGENTS];
        k.velocities(positions, &act, &mut v[..n]);
        // the shape is linear in the positions, so the shape of the velocities is its velocity
        shape_of(&v[..n])
    };
    velocity(axis) - velocity(Vec3::zeros())
}

/// The dimension of the pulls whose spread the fields can cancel at `positions`.
fn held_directions(k: &Kinematics, positions: &[Vec2]) -> usize {
    let fields = BasisFields::at(k, &shape_of(positions)).control_fields(true);
    let mut with_pull = fields.clone();
    with_pull.push(pull_direction(k, positions, Vec3::new(1.0, 0.0, 0.0)));
    with_pull.push(pull_direction(k, positions, Vec3::new(0.0, 1.0, 0.0)));
    rank(&fields, RANK_TOL) + 2 - rank(&with_pull, RANK_TOL)
}

/// Identical agents keep their shape under any pull; agents that differ do in every direction as
/// a pair, in one direction as a triangle, and in none from four agents on.
#[test]
fn agents_that_differ_hold_their_shape_while_moving_only_up_to_three() {
    for n in 2..=10 {
        let positions = ring(n);
        assert_eq!(
            held_directions(&kinematics(false), &positions),
            2,
            "{n} alike"
        );
        let want = match n {
            2 => 2,
            3 => 1,
            _ => 0,
        };
        assert_eq!(
            held_directions(&kinematics(true), &positions),
            want,
            "{n} differing"
        );
    }
}

/// The first-order span the count rests on: the elevation adds no field direction when the
/// agents differ, as when they are alike.
#[test]
fn the_fields_span_three_directions_when_the_agents_differ() {
    for n in 4..=10 {
        let fields = BasisFields::at(&kinematics(true), &shape_of(&ring(n))).control_fields(true);
        assert_eq!(rank(&fields, RANK_TOL), 3, "{n}");
    }
}
