//! Capillary (flotation) attraction between agents at a liquid–air interface.
//!
//! An agent at an interface deforms it: the meniscus around it carries the net vertical force
//! `F_i = g(ρ_l V_immersed − ρ_p V)` (buoyancy minus weight), which sets its capillary charge
//! `Q_i = F_i / (2πγ)`. Two such menisci overlap, and the agents attract (charges of one sign)
//! or repel with the lateral force of Chan, Henry & White (J. Colloid Interface Sci. 79, 410
//! (1981)) and Kralchevsky & Nagayama (Adv. Colloid Interface Sci. 85, 145 (2000)):
//!
//! ```text
//! F(L) = 2πγ q Q_i Q_j K₁(qL) = F_i F_j q K₁(qL) / (2πγ),      q = √(ρ_l g/γ),
//! ```
//!
//! `L` the centre distance and `K₁` the modified Bessel function of the second kind. It holds
//! for small menisci (`qR ≪ 1`: 0.1 here) and, by the superposition approximation, down to
//! contact. For the default physical preset and the `hardware` interface (γ = 66 mN/m,
//! ρ_l = 1190 kg/m³, ρ_p = 1210 kg/m³, θ = 90°): F_i = −0.39 µN, `1/q` = 2.4 mm = 4.8 BL and
//! F = 0.13 nN at 4 BL, 4% of the dipole force scale Ω/r⁴ there (10% at 6 BL, 0.2% at 1.25 BL).
//! The plant turns it into a velocity with the same drag as every other force (the medium's,
//! [`super::Medium::drag`]), so its ratio to the magnetic forces is the physical one.

use serde::{Deserialize, Serialize};

use super::term::Term;

use super::heterogeneity::AgentFactors;
use super::medium::Interface;
use crate::math::{MAX_AGENTS, Vec2};
use crate::physics::{DragFactors, PhysicalParams};

/// The capillary term of a preset: it acts only when the medium is an interface.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Capillary {
    /// Whether the term acts (at an interface).
    pub enabled: bool,
}

impl Term for Capillary {
    super::term::switch_is_enabled_field!();
}

/// The capillary force law of one run, in velocity units of a nominal agent.
#[derive(Debug, Clone, PartialEq)]
pub struct CapillaryLaw {
    /// `F_i · √(q/(2πγ)) / √(σ d)` per agent, so that the product of two is the pair's
    /// coefficient in BL/s.
    charge: [f64; MAX_AGENTS],
    /// q in 1/BL.
    q_bl: f64,
}

impl CapillaryLaw {
    /// The law for agents with the drawn contact angles of `f` at interface `iface`, whose
    /// nominal drag is `drag` times the bulk's.
    pub fn new(
        iface: &Interface,
        p: &PhysicalParams,
        drag: DragFactors,
        f: &AgentFactors,
        n: usize,
    ) -> Self {
        let q = iface.inverse_capillary_length();
        let gamma = iface.surface_tension_mn_per_m * 1e-3;
        let scale = (q / (2.0 * std::f64::consts::PI * gamma) / (p.drag_in(drag) * p.bl_m())).sqrt();
        let mut charge = [0.0; MAX_AGENTS];
        for (c, a) in charge.iter_mut().zip(&f.contact_angle[..n]) {
            *c = iface.net_vertical_force(p, *a) * scale;
        }
        Self {
            charge,
            q_bl: q * p.bl_m(),
        }
    }

    /// The velocity (BL/s, nominal mobility) the capillary force of agent `i` gives agent `j`,
    /// with `r = P_j − P_i` (BL): along `−r̂` when they attract.
    #[inline]
    pub fn pair(&self, i: usize, j: usize, r: Vec2) -> Vec2 {
        let d = r.norm();
        let k1 = puruspe::Kn(1, self.q_bl * d);
        -r / d * (self.charge[i] * self.charge[j] * k1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::heterogeneity::Heterogeneity;
    use crate::plant::medium::Medium;

    fn glycerol() -> Interface {
        Interface {
            surface_tension_mn_per_m: 66.0,
            liquid_density_kg_per_m3: 1190.0,
            agent_density_kg_per_m3: 1210.0,
            contact_angle_deg: 90.0,
            contact_angle_spread_deg: 0.0,
            contact_angle_hysteresis_deg: 0.0,
        }
    }

    #[test]
    fn equal_agents_attract_with_the_chan_force() {
        let p = PhysicalParams::default();
        let iface = glycerol();
        let medium = Medium::Interface(iface.clone());
        let f = Heterogeneity::default().draw(&medium, 2, 1);
        let drag = medium.drag();
        let law = CapillaryLaw::new(&iface, &p, drag, &f, 2);
        let r = Vec2::new(4.0, 0.0);
        let v = law.pair(0, 1, r);
        assert!(v.x < 0.0 && v.y == 0.0, "agent 1 pulled toward agent 0");
        // back to newtons: F = v σ d, σ the interface's drag (half the bulk's at 90°)
        assert!((p.drag_in(drag) - 0.5 * p.drag()).abs() < 1e-15 * p.drag());
        let force = -v.x * p.drag_in(drag) * p.bl_m();
        let fw = iface.net_vertical_force(&p, std::f64::consts::FRAC_PI_2);
        let q = iface.inverse_capillary_length();
        let l = 4.0 * p.bl_m();
        let chan = fw * fw * q * puruspe::Kn(1, q * l) / (2.0 * std::f64::consts::PI * 66e-3);
        assert!((force - chan).abs() < 1e-12 * chan, "{force} vs {chan}");
        assert!((force - 1.26e-10).abs() < 0.02e-10, "{force} N at 4 BL");
        // it falls off with distance
        assert!(law.pair(0, 1, Vec2::new(6.0, 0.0)).norm() < v.norm());
    }
}
