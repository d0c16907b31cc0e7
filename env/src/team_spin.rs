//! Spin: how fast a uniform field turns a team about its centroid, and the formations no field
//! turns.
//!
//! The team's spin under velocities `vᵢ` is their least-squares rigid rotation about the centroid
//! `c`: `ω = Σ (pᵢ − c) × vᵢ / Σ |pᵢ − c|²` ([`spin_rate`]). The pull is the same for every agent
//! and `Σ (pᵢ − c) = 0`, so only the forces between agents turn the team, and each pair turns it
//! by its separation crossed with its force. For identical agents the aligned-dipole force's part
//! across a separation of length `r` and heading `ψ` is `cos²α sin 2(θ − ψ) / r⁴` (the transverse
//! part of `2c b̂ + (1 − 5c²) r̂`, `c = b̂·r̂`), so with `κ` the pair's rate constant
//! ([`crate::PhysicalParams::kappa`]) and `I = Σ |pᵢ − c|²`:
//!
//! ```text
//! ω(θ, α) = (κ/2) cos²α Im(e^{2iθ} S̄) / I,        S = Σ_{i<j} e^{2iψᵢⱼ} / rᵢⱼ³
//! ```
//!
//! The plane's field (α = 0) turns the team fastest, at `(κ/2)|S| / I` ([`fastest_spin`]), and no
//! field turns it when the spin moment `S` ([`spin_moment`]) vanishes. `S` vanishes for every
//! formation with k-fold rotational symmetry, k ≥ 3 (its pairs fall into k-tuples whose headings
//! are 2π/k apart, and `Σₘ e^{2i·2πm/k} = 0`): every ring, the square and the triangles of
//! three, six and ten, the square grids of four, nine and sixteen. Such a formation cannot be
//! turned as it is: the team must first be deformed (a deformation of size ε turns at a rate of
//! order ε) and restored at the end. [`turn_note`] says so when a goal is its start turned.
//! Central forces (capillary attraction) add nothing to `S`; the plant's unequal agents and
//! hydrodynamic coupling do, by amounts of their own size.

use std::f64::consts::FRAC_PI_4;

use crate::math::{Vec2, centroid};
use crate::{Control, PlanningModel};

/// `|S|` relative to `Σ 1/rᵢⱼ³` at or under which a formation counts as one no field turns:
/// coordinates written to three decimals leave a relative `|S|` of about 1e-4, so a formation
/// within that is treated as the symmetric one it was written for.
pub const SPIN_FREE_EPS: f64 = 1e-3;

/// The spin moment `S = Σ_{i<j} e^{2iψᵢⱼ} / rᵢⱼ³` of `positions` as (real, imaginary), and
/// `Σ 1/rᵢⱼ³`, its largest possible size.
pub fn spin_moment(positions: &[Vec2]) -> (Vec2, f64) {
    let mut s = Vec2::zeros();
    let mut scale = 0.0;
    for (i, p) in positions.iter().enumerate() {
        for q in &positions[i + 1..] {
            let d = q - p;
            let r2 = d.norm_squared();
            let r3 = r2 * r2.sqrt();
            // e^{2iψ} = (dx² − dy² + 2i dx dy) / r²
            s += Vec2::new(d.x * d.x - d.y * d.y, 2.0 * d.x * d.y) / (r2 * r3);
            scale += 1.0 / r3;
        }
    }
    (s, scale)
}

/// True when no field turns `positions` (three or more agents whose spin moment is within
/// [`SPIN_FREE_EPS`] of zero, relative to its largest possible size).
pub fn spin_free(positions: &[Vec2]) -> bool {
    let (s, scale) = spin_moment(positions);
    positions.len() >= 3 && s.norm() <= SPIN_FREE_EPS * scale
}

/// The team's spin (rad/s, counter-clockwise positive) under `model` and `u` at `positions`: the
/// least-squares rigid rotation of the agents' velocities about their centroid.
pub fn spin_rate(model: &PlanningModel, positions: &[Vec2], u: &Control) -> f64 {
    let mut v = vec![Vec2::zeros(); positions.len()];
    model.velocities(positions, u, &mut v);
    let c = centroid(positions);
    let (mut turn, mut inertia) = (0.0, 0.0);
    for (p, v) in positions.iter().zip(&v) {
        let a = p - c;
        turn += a.x * v.y - a.y * v.x;
        inertia += a.norm_squared();
    }
    if inertia > 0.0 { turn / inertia } else { 0.0 }
}

/// The largest spin (rad/s) of `positions` under any field of `model`, and the field angle that
/// gives it: the spin is `A sin 2θ + B cos 2θ` in the plane, largest there, so two field angles
/// 45° apart give it.
pub fn fastest_spin(model: &PlanningModel, positions: &[Vec2]) -> (f64, f64) {
    let at = |theta: f64| spin_rate(model, positions, &Control::planar(theta, 0.0, 0.0));
    let (b, a) = (at(0.0), at(FRAC_PI_4));
    (a.hypot(b), 0.5 * a.atan2(b))
}

/// The rotation (rad, counter-clockwise) that best carries `from`'s formation onto `to`'s about
/// their centroids (least squares), and the largest agent distance left after it.
pub fn best_turn(from: &[Vec2], to: &[Vec2]) -> (f64, f64) {
    let (cf, ct) = (centroid(from), centroid(to));
    let (mut cross, mut dot) = (0.0, 0.0);
    for (p, q) in from.iter().zip(to) {
        let (a, b) = (p - cf, q - ct);
        cross += a.x * b.y - a.y * b.x;
        dot += a.dot(&b);
    }
    let angle = cross.atan2(dot);
    (angle, turned_gap(from, to, angle))
}

/// The largest agent distance between `from` turned by `angle` and `to`, about their centroids.
fn turned_gap(from: &[Vec2], to: &[Vec2], angle: f64) -> f64 {
    let (cf, ct) = (centroid(from), centroid(to));
    let (sin, cos) = angle.sin_cos();
    from.iter()
        .zip(to)
        .map(|(p, q)| {
            let a = p - cf;
            (Vec2::new(cos * a.x - sin * a.y, sin * a.x + cos * a.y) - (q - ct)).norm()
        })
        .fold(0.0, f64::max)
}

/// A note when `goal` is `start` turned (within `tolerance` after the best rotation, and farther
/// than `tolerance` without it) and `start` is a formation no field turns: the angle, and that
/// the team must be deformed to turn.
pub fn turn_note(start: &[Vec2], goal: &[Vec2], tolerance: f64) -> Option<String> {
    if !spin_free(start) {
        return None;
    }
    let (angle, left) = best_turn(start, goal);
    if left > tolerance || turned_gap(start, goal, 0.0) <= tolerance {
        return None;
    }
    Some(format!(
        "the goal is the start's formation turned by {:.1}°, and no field turns that formation \
         (its spin moment Σ e^(2iψ)/r³ over its pairs is zero, as for every formation with a \
         three-fold or higher rotational symmetry): the team must be deformed before it turns and \
         restored after, so plans are long and searches slow (docs/physics.md, \"Formations no \
         field turns\")",
        angle.to_degrees()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PhysicalParams;
    use std::f64::consts::{PI, TAU};

    fn ring(n: usize, side: f64, turn: f64) -> Vec<Vec2> {
        let radius = side / (2.0 * (PI / n as f64).sin());
        (0..n)
            .map(|k| {
                let a = turn + TAU * k as f64 / n as f64;
                Vec2::new(5.0 + radius * a.cos(), 4.0 + radius * a.sin())
            })
            .collect()
    }

    fn stretched(p: &[Vec2], sx: f64, sy: f64) -> Vec<Vec2> {
        let c = centroid(p);
        p.iter()
            .map(|q| c + Vec2::new((q.x - c.x) * sx, (q.y - c.y) * sy))
            .collect()
    }

    #[test]
    fn the_model_s_spin_is_the_spin_moment_s() {
        let p = PhysicalParams::default();
        let model = PlanningModel::new(&p);
        let team = stretched(&ring(7, 1.8, 0.3), 1.1, 0.9);
        let (s, _) = spin_moment(&team);
        let c = centroid(&team);
        let inertia: f64 = team.iter().map(|q| (q - c).norm_squared()).sum();
        for &(theta, alpha) in &[(0.0, 0.0), (0.7, 0.0), (-2.1, 0.4), (1.3, 0.9)] {
            let u = Control {
                theta,
                alpha,
                grad: [0.0, 0.0],
            };
            let e = Vec2::new((2.0 * theta).cos(), (2.0 * theta).sin());
            // Im(e^{2iθ} S̄)
            let im = e.y * s.x - e.x * s.y;
            let expect = 0.5 * p.kappa() * alpha.cos().powi(2) * im / inertia;
            let got = spin_rate(&model, &team, &u);
            assert!(
                (got - expect).abs() <= 1e-9 * expect.abs().max(1e-12),
                "θ {theta}, α {alpha}: {got} against {expect}"
            );
        }
    }

    #[test]
    fn no_field_turns_a_ring_and_a_stretched_ring_turns() {
        let model = PlanningModel::new(&PhysicalParams::default());
        for n in 3..=16 {
            let team = ring(n, 1.8, 0.2);
            assert!(spin_free(&team), "ring of {n}");
            let (fastest, _) = fastest_spin(&model, &team);
            let (stretched_fastest, _) = fastest_spin(&model, &stretched(&team, 1.08, 0.92));
            assert!(
                fastest <= 1e-9 * stretched_fastest,
                "ring of {n}: {fastest}"
            );
            assert!(!spin_free(&stretched(&team, 1.08, 0.92)));
        }
        // a pair and a row turn
        assert!(!spin_free(&ring(2, 2.0, 0.0)));
        let row: Vec<Vec2> = (0..4).map(|k| Vec2::new(2.0 * k as f64, 0.0)).collect();
        assert!(!spin_free(&row));
    }

    #[test]
    fn the_fastest_spin_is_the_largest_over_the_plane_s_fields() {
        let model = PlanningModel::new(&PhysicalParams::default());
        let team = stretched(&ring(5, 2.0, 0.1), 1.15, 0.95);
        let (fastest, theta) = fastest_spin(&model, &team);
        let sampled = (0..720)
            .map(|k| {
                let t = TAU * k as f64 / 720.0;
                spin_rate(&model, &team, &Control::planar(t, 0.0, 0.0)).abs()
            })
            .fold(0.0, f64::max);
        assert!(fastest >= sampled && fastest <= sampled * 1.0001);
        let at = spin_rate(&model, &team, &Control::planar(theta, 0.0, 0.0));
        assert!((at - fastest).abs() <= 1e-9 * fastest);
    }

    #[test]
    fn a_turned_ring_is_noted_and_a_moved_one_is_not() {
        let start = ring(10, 1.8, 0.0);
        let turned = ring(10, 1.8, 60f64.to_radians());
        let note = turn_note(&start, &turned, 0.75).expect("a turned ring");
        assert!(note.contains("turned by 60.0°"), "{note}");
        assert_eq!(turn_note(&start, &start, 0.75), None);
        // a small turn, within the tolerance as it is
        assert_eq!(turn_note(&start, &ring(10, 1.8, 0.05), 0.75), None);
        // a stretched start turns
        assert_eq!(turn_note(&stretched(&start, 1.1, 0.9), &turned, 0.75), None);
        // a goal that is another formation
        assert_eq!(turn_note(&start, &stretched(&turned, 1.3, 0.7), 0.75), None);
    }

    #[test]
    fn the_best_turn_undoes_a_rotation() {
        let start = ring(6, 2.0, 0.0);
        let (angle, left) = best_turn(&start, &ring(6, 2.0, -0.9));
        assert!((angle + 0.9).abs() < 1e-12 && left < 1e-12);
    }
}
