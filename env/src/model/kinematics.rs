//! Overdamped (Stokes) kinematics of N aligned magnetic spheres.
//!
//! Each agent moves with its summed pair forces plus its pulling force, divided by its drag:
//! `Ṗ_j = c_F Σ_i s_i s_j μ_j F̂(P_j − P_i) + k_pull s_j μ_j pull_xy + flow`, with `F̂` the
//! aligned dipole force in units of Ω (BL), `s` the per-agent moment factors and `μ` the
//! per-agent mobility (inverse drag) factors, both 1 in the planning model.

use super::pair_flow::{PairEdge, PairStart};
use crate::coil::Actuation;
use crate::math::{MAX_AGENTS, Vec2};
use crate::physics::dipole::aligned_pair_force_planar;
use crate::physics::{DragFactors, PhysicalParams};

/// The velocity field of the team, in BL/s.
#[derive(Debug, Clone, PartialEq)]
pub struct Kinematics {
    /// Single-agent pair-velocity coefficient c_F (BL⁵/s).
    pub force_coeff: f64,
    /// Pull speed per unit gradient (BL/s per T/m).
    pub pull_coeff: f64,
    /// Per-agent moment factors (1 = nominal).
    pub moment: [f64; MAX_AGENTS],
    /// Per-agent mobility factors, 1/drag factor (1 = nominal).
    pub mobility: [f64; MAX_AGENTS],
    /// Uniform background flow (BL/s).
    pub flow: Vec2,
}

impl Kinematics {
    /// The nominal kinematics of a preset: identical agents, no flow.
    pub fn nominal(p: &PhysicalParams) -> Self {
        Self {
            force_coeff: p.force_coeff(),
            pull_coeff: p.pull_coeff(),
            moment: [1.0; MAX_AGENTS],
            mobility: [1.0; MAX_AGENTS],
            flow: Vec2::zeros(),
        }
    }

    /// The nominal kinematics of a preset in a medium whose drag is `drag` times the bulk's
    /// ([`crate::plant::Medium::drag`]); [`Kinematics::nominal`] bit for bit in the bulk.
    pub fn in_medium(p: &PhysicalParams, drag: DragFactors) -> Self {
        Self {
            force_coeff: p.force_coeff_in(drag),
            pull_coeff: p.pull_coeff_in(drag),
            ..Self::nominal(p)
        }
    }

    /// The exact motion of two agents from `start` under `act`, when the closed form applies:
    /// equal moment and mobility factors and an in-plane field. The pull and the uniform flow
    /// then only move the centre of mass; the pair moves with `κ = 2 c_F m² μ`.
    #[inline]
    pub fn pair_edge(&self, start: &[Vec2], act: &Actuation) -> Option<PairEdge> {
        if start.len() != 2 {
            return None;
        }
        self.pair_edge_from(&PairStart::new(start)?, act)
    }

    /// [`Kinematics::pair_edge`] from a start already prepared (for many commands from one
    /// state).
    #[inline]
    pub fn pair_edge_from(&self, start: &PairStart, act: &Actuation) -> Option<PairEdge> {
        let velocity = self.pair_velocity(act)?;
        let (m, mu) = (self.moment[0], self.mobility[0]);
        let kappa = 2.0 * self.force_coeff * m * m * mu;
        start.edge(kappa, velocity, Vec2::new(act.b_hat.x, act.b_hat.y))
    }

    /// The centre-of-mass velocity of the exact pair motion under `act` (that of
    /// [`Kinematics::pair_edge_from`]'s edge, bit for bit), without solving the orbit; `None`
    /// when the closed form does not apply.
    #[inline]
    pub fn pair_velocity(&self, act: &Actuation) -> Option<Vec2> {
        if self.moment[0] != self.moment[1]
            || self.mobility[0] != self.mobility[1]
            || act.b_hat.z != 0.0
        {
            return None;
        }
        let (m, mu) = (self.moment[0], self.mobility[0]);
        Some(Vec2::new(act.pull.x, act.pull.y) * (self.pull_coeff * m * mu) + self.flow)
    }

    /// The velocity of the centroid of a team of `n` under `act`, constant whatever the team's
    /// shape when all `n` agents share one mobility: each pair force then moves its two agents
    /// by opposite velocities, which cancel in the mean, and the centroid moves at the mean of
    /// the agents' pull and flow velocities. `None` when the mobilities differ.
    #[inline]
    pub fn centroid_velocity(&self, act: &Actuation, n: usize) -> Option<Vec2> {
        let mu = self.mobility[0];
        if n == 0 || self.mobility[..n].iter().any(|&m| m != mu) {
            return None;
        }
        let moment = self.moment[..n].iter().sum::<f64>() / n as f64;
        Some(Vec2::new(act.pull.x, act.pull.y) * (self.pull_coeff * moment * mu) + self.flow)
    }

    /// Writes the velocity of every agent at positions `p` under `act` into `v`.
    #[inline]
    pub fn velocities(&self, p: &[Vec2], act: &Actuation, v: &mut [Vec2]) {
        let n = p.len();
        let pull = Vec2::new(act.pull.x, act.pull.y) * self.pull_coeff;
        for (j, vj) in v.iter_mut().enumerate().take(n) {
            *vj = pull * (self.moment[j] * self.mobility[j]) + self.flow;
        }
        for i in 0..n {
            for j in (i + 1)..n {
                let f = aligned_pair_force_planar(p[j] - p[i], act.b_hat)
                    * (self.force_coeff * self.moment[i] * self.moment[j]);
                v[j] += f * self.mobility[j];
                v[i] -= f * self.mobility[i];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coil::{Coil, Control, TriaxialMaxwell};
    use crate::physics::LocalView;

    fn setup() -> (Kinematics, TriaxialMaxwell, PhysicalParams) {
        let p = PhysicalParams::default();
        (
            Kinematics::nominal(&p),
            TriaxialMaxwell::new(p.gradient_limit()),
            p,
        )
    }

    /// Two agents centred at (5, 4), `r` apart, at angle `phi`.
    fn pair_at(r: f64, phi: f64) -> [Vec2; 2] {
        LocalView::new(5.0, 4.0, r, phi).to_pair()
    }

    #[test]
    fn two_agent_rates_match_closed_form_with_factor_two() {
        let (k, coil, p) = setup();
        let kappa = p.kappa();
        for &(r, phi, psi) in &[(2.0, 0.3, 0.2), (1.6, -1.2, 1.0), (3.3, 2.5, -0.7)] {
            let pos = pair_at(r, phi);
            let act = coil.actuation(&Control::planar(phi + psi, 0.0, 0.0));
            let mut vel = [Vec2::zeros(); 2];
            k.velocities(&pos, &act, &mut vel);
            let rh = Vec2::new(phi.cos(), phi.sin());
            let eph = Vec2::new(-phi.sin(), phi.cos());
            let rel = vel[1] - vel[0];
            let r_dot = rel.dot(&rh);
            let phi_dot = rel.dot(&eph) / r;
            let psi_c = psi.cos();
            assert!((r_dot - kappa * (1.0 - 3.0 * psi_c * psi_c) / r.powi(4)).abs() < 1e-12);
            assert!((phi_dot - kappa * (2.0 * psi).sin() / r.powi(5)).abs() < 1e-12);
            // equal and opposite: the centre of mass does not move without a gradient
            assert!((vel[0] + vel[1]).norm() < 1e-12);
        }
    }

    #[test]
    fn gradient_pull_moves_only_the_centre_of_mass() {
        let (k, coil, p) = setup();
        let pos = pair_at(2.2, 0.4);
        let g = p.gradient_limit();
        let u0 = Control::planar(0.9, 0.0, 0.0);
        let u1 = Control::planar(0.9, g, -0.5 * g);
        let (mut v0, mut v1) = ([Vec2::zeros(); 2], [Vec2::zeros(); 2]);
        k.velocities(&pos, &coil.actuation(&u0), &mut v0);
        k.velocities(&pos, &coil.actuation(&u1), &mut v1);
        let d0 = v1[0] - v0[0];
        let d1 = v1[1] - v0[1];
        assert!(
            (d0 - d1).norm() < 1e-15,
            "relative velocity changed by the pull"
        );
        assert!(d0.norm() > 0.1);
    }

    #[test]
    fn flipping_field_keeps_pair_force_and_reverses_pull() {
        let (k, coil, p) = setup();
        let pos = pair_at(2.2, 0.4);
        let g = p.gradient_limit();
        let u = Control::planar(0.9, g, g);
        let (mut va, mut vb) = ([Vec2::zeros(); 2], [Vec2::zeros(); 2]);
        k.velocities(&pos, &coil.actuation(&u), &mut va);
        k.velocities(&pos, &coil.actuation(&u.flipped()), &mut vb);
        // relative motion identical, centre-of-mass motion reversed
        assert!(((va[1] - va[0]) - (vb[1] - vb[0])).norm() < 1e-12);
        assert!(((va[0] + va[1]) + (vb[0] + vb[1])).norm() < 1e-12);
    }

    #[test]
    fn three_agents_conserve_zero_net_pair_force() {
        let (k, coil, _) = setup();
        let pos = [
            Vec2::new(0.0, 0.0),
            Vec2::new(2.1, 0.4),
            Vec2::new(0.7, -1.8),
        ];
        let mut v = [Vec2::zeros(); 3];
        k.velocities(
            &pos,
            &coil.actuation(&Control::planar(0.3, 0.0, 0.0)),
            &mut v,
        );
        assert!((v[0] + v[1] + v[2]).norm() < 1e-12);
        assert!(v[0].norm() > 1e-3);
    }
}
