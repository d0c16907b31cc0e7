//! Where the agents move: in the bulk of the liquid, or at its surface (a liquid–air
//! interface).
//!
//! At an interface each agent sits with its contact line where the liquid meets it at the
//! contact angle θ (measured through the liquid). The Bond number of a 500 µm sphere is
//! `(R/ℓ_c)² ≈ 0.01`, so gravity barely moves it and its centre lies `z = R cos θ` below the
//! flat interface. From that position:
//!
//! - the immersed fraction of its volume is `(2 + 3 cos θ − cos³θ)/4` (a spherical cap);
//! - its drag, relative to full immersion, is taken as `(1 + cos θ)/2`, for translation in the
//!   plane and for rotation about the vertical alike. At θ = 90° this is exact: the flow of a
//!   sphere translating in unbounded liquid, or turning about an axis through its centre, has
//!   no normal velocity and no shear stress on its own equatorial plane, so it is also the flow
//!   of a half-immersed sphere under a clean, flat, shear-free surface, and carries half the
//!   force or torque (the 90° limit of Dörr, Hardt, Masoud & Stone, *J. Fluid Mech.* 790, 607
//!   (2016), for a gas of negligible viscosity and no surface viscosity). Away from 90° the line
//!   through 1 (deep in the liquid) and 0 (out of it) is an approximation; Dörr et al. give the
//!   perturbation in θ − 90°. [`Medium::drag`] is the one source of these factors for the
//!   planning model and every plant term;
//! - the net vertical force that its meniscus carries, `g (ρ_l V_immersed − ρ_p V)`, sets its
//!   capillary charge (see the capillary term).

use serde::{Deserialize, Serialize};

use crate::input::Rejection;
use crate::input::bounds::{positive, within};
use crate::physics::{DragFactors, PhysicalParams};

/// Standard gravity (m/s²).
pub const GRAVITY: f64 = 9.806_65;

/// The medium of a preset: `kind = "bulk"` or `kind = "interface"` with its properties.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Medium {
    /// Agents fully immersed in the liquid (no interface terms).
    #[default]
    Bulk,
    /// Agents at a liquid–air interface.
    Interface(Interface),
}

/// A liquid–air interface and how the agents sit in it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Interface {
    /// Liquid–air surface tension γ (mN/m).
    pub surface_tension_mn_per_m: f64,
    /// Liquid density ρ_l (kg/m³).
    pub liquid_density_kg_per_m3: f64,
    /// Agent density ρ_p (kg/m³).
    pub agent_density_kg_per_m3: f64,
    /// Mean contact angle θ of the liquid on the agents, through the liquid (degrees).
    pub contact_angle_deg: f64,
    /// Standard deviation of the contact angle from agent to agent (degrees); acts through
    /// the heterogeneity term.
    pub contact_angle_spread_deg: f64,
    /// Contact-angle hysteresis θ_a − θ_r about the mean angle (degrees): it pins the contact
    /// line against a field that tilts the agents out of the plane (see
    /// [`super::pinning`]). 0 (the default): no pinning.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub contact_angle_hysteresis_deg: f64,
}

/// Whether `v` is 0 (a medium table leaves a zero hysteresis out).
fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

impl Medium {
    /// The interface, if the agents are at one.
    pub fn interface(&self) -> Option<&Interface> {
        match self {
            Medium::Bulk => None,
            Medium::Interface(i) => Some(i),
        }
    }

    /// Whether the medium carries the out-of-plane force f_z: at an interface the meniscus
    /// holds each agent in the surface (the seed, Sec. II-A: "the liquid–air interface ...
    /// restrains the elevation force f_z = 0"); in bulk nothing does, and a field tilted out of
    /// the plane lifts or sinks the agents.
    pub fn carries_fz(&self) -> bool {
        self.interface().is_some()
    }

    /// The drag of a nominal agent in this medium relative to the bulk: 1 in the bulk,
    /// [`Interface::drag_fraction`] of the mean contact angle (for translation and rotation
    /// about the vertical) at an interface. The planning model and the plant take every drag
    /// from here.
    pub fn drag(&self) -> DragFactors {
        match self {
            Medium::Bulk => DragFactors::BULK,
            Medium::Interface(i) => {
                let f = Interface::drag_fraction(i.contact_angle_deg.to_radians());
                DragFactors {
                    translation: f,
                    rotation: f,
                }
            }
        }
    }

    /// The integration step in this medium for the preset's bulk step `dt_s`: `dt_s` divided
    /// by `⌈1 / drag⌉` (the smaller of the translation and rotation factors of
    /// [`Medium::drag`]). Lower drag makes every motion faster by `1 / drag`; dividing the step
    /// by at least that keeps an agent's displacement per step, and so RK4's error against the
    /// r⁻⁴ force, no larger than in the bulk, where `dt_s` holds. The bulk's step is `dt_s`
    /// itself, and a whole number of steps still fills every multiple of `dt_s` (a control
    /// period, a camera frame).
    pub fn step(&self, dt_s: f64) -> f64 {
        let d = self.drag();
        let slowest = d.translation.min(d.rotation);
        if slowest >= 1.0 {
            return dt_s;
        }
        dt_s / (1.0 / slowest).ceil()
    }

    /// `bulk` or `interface`, as the `kind` field says.
    pub fn kind(&self) -> &'static str {
        match self {
            Medium::Bulk => "bulk",
            Medium::Interface(_) => "interface",
        }
    }

    /// Checks every value; returns (field, reason).
    pub fn check(&self) -> Result<(), Rejection> {
        let Some(i) = self.interface() else {
            return Ok(());
        };
        positive(
            "medium.surface_tension_mn_per_m",
            i.surface_tension_mn_per_m,
        )?;
        positive(
            "medium.liquid_density_kg_per_m3",
            i.liquid_density_kg_per_m3,
        )?;
        positive("medium.agent_density_kg_per_m3", i.agent_density_kg_per_m3)?;
        within(
            "medium.contact_angle_deg",
            i.contact_angle_deg,
            10.0,
            170.0,
            "°",
        )?;
        within(
            "medium.contact_angle_spread_deg",
            i.contact_angle_spread_deg,
            0.0,
            30.0,
            "°",
        )?;
        within(
            "medium.contact_angle_hysteresis_deg",
            i.contact_angle_hysteresis_deg,
            0.0,
            90.0,
            "°",
        )
    }
}

impl Interface {
    /// Drag of an agent with contact angle `theta` (radians), relative to full immersion.
    pub fn drag_fraction(theta: f64) -> f64 {
        0.5 * (1.0 + theta.cos())
    }

    /// Immersed fraction of an agent's volume at contact angle `theta` (radians).
    pub fn immersed_fraction(theta: f64) -> f64 {
        let z = theta.cos();
        (2.0 + 3.0 * z - z * z * z) / 4.0
    }

    /// The contact angle clamped to where an agent still touches the liquid (radians).
    pub fn clamp_angle(theta: f64) -> f64 {
        theta.clamp(5f64.to_radians(), 175f64.to_radians())
    }

    /// Net upward force on an agent at contact angle `theta`: buoyancy of its immersed part
    /// minus its weight (N). Negative for an agent that the meniscus holds up.
    pub fn net_vertical_force(&self, p: &PhysicalParams, theta: f64) -> f64 {
        let d = p.bl_m();
        let volume = std::f64::consts::PI * d * d * d / 6.0;
        GRAVITY
            * volume
            * (self.liquid_density_kg_per_m3 * Self::immersed_fraction(theta)
                - self.agent_density_kg_per_m3)
    }

    /// Inverse capillary length `q = √(ρ_l g / γ)` (1/m).
    pub fn inverse_capillary_length(&self) -> f64 {
        (self.liquid_density_kg_per_m3 * GRAVITY / (self.surface_tension_mn_per_m * 1e-3)).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn half_immersed_at_ninety_degrees() {
        assert!((Interface::drag_fraction(FRAC_PI_2) - 0.5).abs() < 1e-15);
        assert!((Interface::immersed_fraction(FRAC_PI_2) - 0.5).abs() < 1e-15);
        assert!((Interface::immersed_fraction(0.0) - 1.0).abs() < 1e-15);
        assert!(Interface::immersed_fraction(std::f64::consts::PI).abs() < 1e-15);
        // a more wetting agent sinks deeper and drags more
        assert!(Interface::drag_fraction(1.2) > Interface::drag_fraction(1.7));
    }

    #[test]
    fn the_medium_gives_bulk_or_half_drag() {
        assert_eq!(Medium::Bulk.drag(), DragFactors::BULK);
        let half = Medium::Interface(Interface {
            surface_tension_mn_per_m: 66.0,
            liquid_density_kg_per_m3: 1190.0,
            agent_density_kg_per_m3: 1210.0,
            contact_angle_deg: 90.0,
            contact_angle_spread_deg: 6.0,
            contact_angle_hysteresis_deg: 20.0,
        })
        .drag();
        assert!((half.translation - 0.5).abs() < 1e-15);
        assert!((half.rotation - 0.5).abs() < 1e-15);
    }

    #[test]
    fn the_step_divides_the_bulk_step_by_the_drag() {
        let dt = 1.0 / 120.0;
        assert_eq!(Medium::Bulk.step(dt), dt);
        let at = |deg: f64| {
            Medium::Interface(Interface {
                surface_tension_mn_per_m: 66.0,
                liquid_density_kg_per_m3: 1190.0,
                agent_density_kg_per_m3: 1210.0,
                contact_angle_deg: deg,
                contact_angle_spread_deg: 6.0,
                contact_angle_hysteresis_deg: 20.0,
            })
            .step(dt)
        };
        // half drag: half the step; a quarter (θ = 120°): a quarter; 0.41 (θ = 100°): a third
        assert_eq!(at(90.0), dt / 2.0);
        assert!((at(120.0) - dt / 4.0).abs() < 1e-15);
        assert!((at(100.0) - dt / 3.0).abs() < 1e-15);
        // a wetting agent drags more than half: still a whole number of steps per dt_s
        assert_eq!(at(60.0), dt / 2.0);
    }

    #[test]
    fn medium_table_reads_and_writes() {
        let text = "kind = \"interface\"\nsurface_tension_mn_per_m = 66.0\n\
                    liquid_density_kg_per_m3 = 1190.0\nagent_density_kg_per_m3 = 1210.0\n\
                    contact_angle_deg = 90.0\ncontact_angle_spread_deg = 6.0\n";
        let m: Medium = toml::from_str(text).unwrap();
        assert!(m.interface().is_some());
        let back: Medium = toml::from_str(&toml::to_string(&m).unwrap()).unwrap();
        assert_eq!(back, m);
        let bulk: Medium = toml::from_str("kind = \"bulk\"").unwrap();
        assert_eq!(bulk, Medium::Bulk);
        assert!(toml::from_str::<Medium>(&format!("{text}colour = 3\n")).is_err());
    }
}
