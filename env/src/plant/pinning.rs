//! Contact-line pinning: how far a field tilted out of the plane tilts a magnet at an interface.
//!
//! A sphere at a liquid–air interface that turns about a horizontal axis rolls its surface out
//! of the liquid on one side and into it on the other: the contact line recedes on one side and
//! advances on the other, and contact-angle hysteresis resists with the capillary torque of
//! Naga, Vollmer & Butt (*Langmuir* 37, 7457 (2021), eq. for a sphere):
//!
//! ```text
//! M_pin = γ R L k (cos θ_r − cos θ_a),     L = 2R sin θ,  k = 24/π³,
//! ```
//!
//! with `L` the contact line's diameter and `θ_r = θ − H/2`, `θ_a = θ + H/2` the receding and
//! advancing angles of a hysteresis window `H` about the mean angle θ. A field `B` tilted by α
//! out of the plane turns an in-plane moment `m` with the torque `mB sin(α − e)`, `e` the
//! moment's elevation; the magnet turns until that torque falls to `M_pin`. So it lags the
//! field's elevation by `δ = asin(M_pin/(mB))` and takes `e = sign(α) max(0, |α| − δ)`; when
//! `M_pin ≥ mB` it does not tilt at all. The tilt reached after a larger |α| (the magnet stays
//! tilted while α comes back within δ) is not kept: the elevation depends on the present
//! field only. Rotation about the vertical does not move the contact line across the solid and
//! meets no pinning.
//!
//! For the `hardware` preset (γ = 66 mN/m, R = 250 µm, θ = 90°, H = 20°): `M_pin` = 2.2 nN·m
//! against `mB` = 2.1 nN·m (M_eff = 6.4 kA/m, 5 mT): the nominal magnet is pinned and a
//! commanded α does not tilt it.

use super::heterogeneity::AgentFactors;
use super::medium::{Interface, Medium};
use crate::math::{MAX_AGENTS, Vec3};
use crate::physics::PhysicalParams;

/// Geometric constant `k = 24/π³` of the capillary torque (Naga, Vollmer & Butt 2021).
pub const TORQUE_SHAPE: f64 =
    24.0 / (std::f64::consts::PI * std::f64::consts::PI * std::f64::consts::PI);

/// The pinning torque `γ R L k (cos θ_r − cos θ_a)` of an agent with contact angle `theta`
/// (radians) at `iface` (N·m).
pub fn pinning_torque(iface: &Interface, p: &PhysicalParams, theta: f64) -> f64 {
    let r = 0.5 * p.bl_m();
    let half = 0.5 * iface.contact_angle_hysteresis_deg.to_radians();
    let pi = std::f64::consts::PI;
    let (receding, advancing) = ((theta - half).clamp(0.0, pi), (theta + half).clamp(0.0, pi));
    let gamma = iface.surface_tension_mn_per_m * 1e-3;
    let line = 2.0 * r * theta.sin();
    gamma * r * line * TORQUE_SHAPE * (receding.cos() - advancing.cos())
}

/// The lag `δ = asin(M_pin/(mB))` of a moment's elevation behind its field's (radians): π/2
/// when the pinning torque `pin` is at least the magnetic torque `magnetic`.
pub fn tilt_lag(pin: f64, magnetic: f64) -> f64 {
    if pin >= magnetic {
        std::f64::consts::FRAC_PI_2
    } else {
        (pin / magnetic).asin()
    }
}

/// The elevation a moment takes under a field of elevation `alpha`, with lag `lag` (radians).
pub fn achieved_elevation(alpha: f64, lag: f64) -> f64 {
    alpha.signum() * (alpha.abs() - lag).max(0.0)
}

/// How far a nominal agent in the nominal field tilts in a medium.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tilt {
    /// The contact line's pinning torque (N·m).
    pub pinning_torque: f64,
    /// The largest magnetic torque `mB` (N·m).
    pub magnetic_torque: f64,
    /// The lag of the moment's elevation behind the field's (radians).
    pub lag: f64,
}

impl Tilt {
    /// The tilt of a nominal agent of `p` in `medium`; `None` where nothing pins it (bulk, or an
    /// interface without hysteresis).
    pub fn of(medium: &Medium, p: &PhysicalParams) -> Option<Self> {
        let iface = medium.interface()?;
        if iface.contact_angle_hysteresis_deg <= 0.0 {
            return None;
        }
        let pin = pinning_torque(iface, p, iface.contact_angle_deg.to_radians());
        let magnetic = p.moment() * p.field_mt * 1e-3;
        Some(Self {
            pinning_torque: pin,
            magnetic_torque: magnetic,
            lag: tilt_lag(pin, magnetic),
        })
    }

    /// The elevation the agent takes under a field of elevation `alpha` (radians).
    pub fn achieved(&self, alpha: f64) -> f64 {
        achieved_elevation(alpha, self.lag)
    }
}

/// The pinning of each agent of one run: the field `M_pin,i/(s_i m)` (T) below which its
/// moment does not tilt.
#[derive(Debug, Clone, PartialEq)]
pub struct PinningLaw {
    holding_field: [f64; MAX_AGENTS],
}

impl PinningLaw {
    /// The law for the agents drawn in `f` at `medium`; `None` where nothing pins them.
    pub fn new(medium: &Medium, p: &PhysicalParams, f: &AgentFactors, n: usize) -> Option<Self> {
        let iface = medium.interface()?;
        if iface.contact_angle_hysteresis_deg <= 0.0 {
            return None;
        }
        let mut holding_field = [0.0; MAX_AGENTS];
        for (i, h) in holding_field.iter_mut().enumerate().take(n) {
            *h = pinning_torque(iface, p, f.contact_angle[i]) / (f.moment[i] * p.moment());
        }
        Some(Self { holding_field })
    }

    /// The field `b` (T) as agent `i` follows it: its elevation reduced by the agent's lag,
    /// its magnitude and in-plane direction kept (the direction of `fallback` when `b` is
    /// vertical).
    pub fn limit(&self, i: usize, b: Vec3, fallback: Vec3) -> Vec3 {
        let magnitude = b.norm();
        if magnitude == 0.0 || b.z == 0.0 {
            return b;
        }
        let horizontal = b.x.hypot(b.y);
        let alpha = b.z.atan2(horizontal);
        let lag = tilt_lag(self.holding_field[i], magnitude);
        let e = achieved_elevation(alpha, lag);
        let (dx, dy) = if horizontal > 0.0 {
            (b.x / horizontal, b.y / horizontal)
        } else {
            let h = fallback.x.hypot(fallback.y);
            if h > 0.0 {
                (fallback.x / h, fallback.y / h)
            } else {
                (1.0, 0.0)
            }
        };
        let (s, c) = e.sin_cos();
        Vec3::new(c * dx, c * dy, s) * magnitude
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hardware_like(hysteresis: f64) -> Medium {
        Medium::Interface(Interface {
            surface_tension_mn_per_m: 66.0,
            liquid_density_kg_per_m3: 1190.0,
            agent_density_kg_per_m3: 1210.0,
            contact_angle_deg: 90.0,
            contact_angle_spread_deg: 6.0,
            contact_angle_hysteresis_deg: hysteresis,
        })
    }

    #[test]
    fn pinning_torque_follows_the_capillary_torque_formula() {
        let p = PhysicalParams::default();
        let t = Tilt::of(&hardware_like(20.0), &p).unwrap();
        // γ R (2R) (24/π³) · 2 sin 10°, R = 250 µm
        let r: f64 = 250e-6;
        let expect = 0.066 * r * 2.0 * r * TORQUE_SHAPE * 2.0 * 10f64.to_radians().sin();
        assert!((t.pinning_torque - expect).abs() < 1e-18, "{t:?}");
        assert!((t.pinning_torque - 2.22e-9).abs() < 0.01e-9, "{t:?}");
        assert!((t.magnetic_torque - 2.094e-9).abs() < 0.001e-9, "{t:?}");
        // the nominal magnet is pinned: no tilt at any α
        assert_eq!(t.lag, std::f64::consts::FRAC_PI_2);
        assert_eq!(t.achieved(1.2), 0.0);
        assert!(Tilt::of(&Medium::Bulk, &p).is_none());
        assert!(Tilt::of(&hardware_like(0.0), &p).is_none());
    }

    #[test]
    fn a_weak_pin_lags_the_field_elevation() {
        let p = PhysicalParams::default();
        let t = Tilt::of(&hardware_like(5.0), &p).unwrap();
        assert!(t.pinning_torque < t.magnetic_torque);
        let lag = (t.pinning_torque / t.magnetic_torque).asin();
        assert!((t.lag - lag).abs() < 1e-15);
        assert_eq!(t.achieved(0.5 * lag), 0.0);
        assert!((t.achieved(0.8) - (0.8 - lag)).abs() < 1e-15);
        assert!((t.achieved(-0.8) + (0.8 - lag)).abs() < 1e-15);
    }

    #[test]
    fn the_law_limits_each_agents_elevation_and_keeps_planar_fields() {
        let p = PhysicalParams::default();
        let f = AgentFactors {
            moment: [1.0; MAX_AGENTS],
            mobility: [1.0; MAX_AGENTS],
            contact_angle: [std::f64::consts::FRAC_PI_2; MAX_AGENTS],
        };
        let law = PinningLaw::new(&hardware_like(20.0), &p, &f, 2).unwrap();
        let b0 = 5e-3;
        let planar = Vec3::new(0.6, 0.8, 0.0) * b0;
        assert_eq!(law.limit(0, planar, Vec3::x()), planar);
        let tilted = Vec3::new(0.6 * 0.8, 0.8 * 0.8, 0.6) * b0;
        let held = law.limit(1, tilted, Vec3::x());
        assert!(held.z.abs() < 1e-18 && (held.norm() - b0).abs() < 1e-15);
        assert!((held.x / held.y - 0.75).abs() < 1e-12);
        // a field twice as strong overcomes the pin, lagging by asin(B_pin/|B|)
        let strong = law.limit(1, tilted * 2.0, Vec3::x());
        let lag = (law.holding_field[1] / (2.0 * b0)).asin();
        let e = strong.z.atan2(strong.x.hypot(strong.y));
        assert!((e - (0.6f64.asin() - lag)).abs() < 1e-12, "e = {e}");
        assert!(PinningLaw::new(&Medium::Bulk, &p, &f, 2).is_none());
    }
}
