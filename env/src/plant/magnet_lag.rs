//! Magnet rotation lag: an agent's moment turns toward the field it feels at a finite rate.
//!
//! A sphere of diameter `d` turning at rate ω in a liquid of viscosity η feels the Stokes
//! torque `8πη(d/2)³ω = πηd³ω`; the field `B` turns its moment `m` with the torque `mB sin Δ`,
//! `Δ` the angle from the moment to the field. Without inertia `πηd³ Δ̇ = −mB sin Δ`: the moment
//! relaxes toward the field with the time constant `τ = πηd³/(mB)` (`= 6η/(M_eff B)` for a
//! uniformly magnetised sphere, independent of its size). For the default physical preset
//! (η = 30 mPa·s, M_eff = 6.4 kA/m, B = 5 mT) τ = 5.6 ms in the bulk; at a clean interface at a
//! 90° contact angle the rotational drag about the vertical axis is exactly half (the bulk flow
//! is shear-free on the equatorial plane), τ = 2.8 ms. In vector form, for the unit moment
//! direction `m̂`: `dm̂/dt = (m/(πηd³)) (B − (B·m̂) m̂)`.

use serde::{Deserialize, Serialize};

use super::term::Term;

use crate::physics::PhysicalParams;

/// The magnet-rotation-lag term of a preset (its time constant follows from the physical
/// preset: τ = πηd³/(mB), scaled by each agent's moment and drag).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MagnetLag {
    /// Whether the term acts.
    pub enabled: bool,
}

impl Term for MagnetLag {
    super::term::switch_is_enabled_field!();
}

/// The rotation time constant `τ = πηd³ f/(m B)` of a nominal agent in the nominal field (s),
/// with `f` its rotational drag relative to full immersion.
pub fn rotation_time(p: &PhysicalParams, drag_fraction: f64) -> f64 {
    let d = p.bl_m();
    std::f64::consts::PI * p.viscosity_mpa_s * 1e-3 * d * d * d * drag_fraction
        / (p.moment() * p.field_mt * 1e-3)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_preset_rotates_in_under_six_milliseconds() {
        let p = PhysicalParams::default();
        let tau = rotation_time(&p, 1.0);
        // 6η/(M B) = 6 · 0.03 / (6400 · 0.005)
        assert!(
            (tau - 6.0 * 0.03 / (6400.0 * 0.005)).abs() < 1e-12,
            "τ = {tau}"
        );
        assert!((rotation_time(&p, 0.5) - 0.5 * tau).abs() < 1e-15);
    }
}
