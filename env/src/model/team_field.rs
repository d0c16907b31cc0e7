//! The planning model's velocity field for one actuation, with every per-motion constant folded
//! in: what the adaptive integrator evaluates six times a step.
//!
//! [`TeamField::velocities`] computes the same field as [`Kinematics::velocities`] (to rounding:
//! the test below holds them within 1e-12 relative), with one square root and one division per
//! pair instead of one square root and three divisions: with `d = p_j − p_i`, `c' = b̂·d` and
//! `r = |d|`, the aligned dipole force `(2 c b̂ + (1 − 5c²) r̂) / r⁴` (`c = c'/r`, `r̂ = d/r`)
//! is `(2 c' b̂ + (1 − 5 c'²/r²) d) / r⁵`. Each pair's force is added to one agent and taken
//! from the other with the same coefficient when their factors are equal, so the pair forces of
//! identical agents cancel in the sum, as in [`Kinematics::velocities`]: the centre of mass moves
//! at the constant drift.
//!
//! The fixed-step flows keep [`Kinematics::velocities`], so their motions keep their bits.

use super::Kinematics;
use crate::coil::Actuation;
use crate::math::{MAX_AGENTS, Vec2};

/// The velocity field of a team of `n` agents under one actuation (BL/s).
#[derive(Debug, Clone, Copy)]
pub struct TeamField {
    n: usize,
    /// In-plane part of the unit field direction.
    b: Vec2,
    /// Each agent's velocity without pair forces: pull and background flow.
    drift: [Vec2; MAX_AGENTS],
    /// Per pair `(i, j)`, `i < j`, in the order of [`TeamField::velocities`]: the factor of the
    /// unit-coefficient force added to agent `j` and the one taken from agent `i`.
    coeff: [(f64, f64); PAIRS],
}

/// The most pairs a team has.
const PAIRS: usize = MAX_AGENTS * (MAX_AGENTS - 1) / 2;

impl TeamField {
    /// The field of `kinematics` under `act` for a team of `n` agents.
    pub fn new(kinematics: &Kinematics, act: &Actuation, n: usize) -> Self {
        assert!(n <= MAX_AGENTS, "at most {MAX_AGENTS} agents");
        let k = kinematics;
        let pull = Vec2::new(act.pull.x, act.pull.y) * k.pull_coeff;
        let mut drift = [Vec2::zeros(); MAX_AGENTS];
        for (j, d) in drift.iter_mut().enumerate().take(n) {
            *d = pull * (k.moment[j] * k.mobility[j]) + k.flow;
        }
        let mut coeff = [(0.0, 0.0); PAIRS];
        let mut q = 0;
        for i in 0..n {
            for j in (i + 1)..n {
                let c = k.force_coeff * k.moment[i] * k.moment[j];
                coeff[q] = (c * k.mobility[j], c * k.mobility[i]);
                q += 1;
            }
        }
        Self {
            n,
            b: Vec2::new(act.b_hat.x, act.b_hat.y),
            drift,
            coeff,
        }
    }

    /// Writes the velocity of every agent of the team at positions `p` into `v` (`p` holds
    /// the team's `n`; a caller whose `p` has a length known at compile time gets unrolled
    /// loops).
    #[inline]
    pub fn velocities(&self, p: &[Vec2], v: &mut [Vec2]) {
        let n = p.len();
        assert!(n == self.n, "the team has {} agents", self.n);
        let v = &mut v[..n];
        v.copy_from_slice(&self.drift[..n]);
        let b = self.b;
        let mut q = 0;
        for i in 0..n {
            for j in (i + 1)..n {
                let d = p[j] - p[i];
                let r2 = d.x * d.x + d.y * d.y;
                // the division and the square root are independent: their latencies overlap
                let inv_r2 = 1.0 / r2;
                let inv_r = r2.sqrt() * inv_r2;
                let c = b.x * d.x + b.y * d.y;
                let radial = 1.0 - 5.0 * c * c * inv_r2;
                let s = inv_r2 * inv_r2 * inv_r;
                let two_c = 2.0 * c;
                let f = Vec2::new(
                    (two_c * b.x + radial * d.x) * s,
                    (two_c * b.y + radial * d.y) * s,
                );
                let (to_j, from_i) = self.coeff[q];
                v[j] += f * to_j;
                v[i] -= f * from_i;
                q += 1;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coil::{Coil, Control, TriaxialMaxwell};
    use crate::physics::PhysicalParams;

    /// The folded field equals [`Kinematics::velocities`] to rounding, for unequal agents, a
    /// background flow and elevated fields, teams of one to six.
    #[test]
    fn team_field_matches_the_kinematics() {
        let p = PhysicalParams::default();
        let mut k = Kinematics::nominal(&p);
        k.moment[..6].copy_from_slice(&[1.0, 0.9, 1.2, 1.05, 0.8, 1.1]);
        k.mobility[..6].copy_from_slice(&[1.0, 1.1, 0.95, 0.85, 1.2, 1.0]);
        k.flow = Vec2::new(0.3, -0.2);
        let coil = TriaxialMaxwell::new(p.gradient_limit());
        let g = p.gradient_limit();
        let pos = [
            Vec2::new(0.0, 0.0),
            Vec2::new(2.1, 0.4),
            Vec2::new(0.7, -1.8),
            Vec2::new(-1.9, 1.3),
            Vec2::new(3.5, -2.2),
            Vec2::new(-0.4, 3.1),
        ];
        let mut worst: f64 = 0.0;
        for n in 1..=6 {
            for (theta, alpha, gx, gy) in [
                (0.3, 0.0, 0.0, 0.0),
                (-2.1, 0.4, g, -0.5 * g),
                (1.2, 1.1, -g, g),
            ] {
                let act = coil.actuation(&Control {
                    theta,
                    alpha,
                    grad: [gx, gy],
                });
                let (mut a, mut b) = ([Vec2::zeros(); 6], [Vec2::zeros(); 6]);
                k.velocities(&pos[..n], &act, &mut a[..n]);
                TeamField::new(&k, &act, n).velocities(&pos[..n], &mut b[..n]);
                for i in 0..n {
                    let scale = a[i].norm().max(1.0);
                    worst = worst.max((a[i] - b[i]).norm() / scale);
                }
            }
        }
        assert!(worst < 1e-12, "relative difference {worst:e}");
    }
}
