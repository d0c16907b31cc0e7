//! The physical preset: SI quantities and the normalised constants the BL model uses.
//!
//! Every length in the model is in body lengths (1 BL = one sphere diameter `d`) and every time
//! in seconds. From the preset:
//!
//! - drag `σ = 3πηd` (Stokes, sphere of diameter `d`);
//! - moment `m = M_eff · πd³/6`, force constant `Ω = 3μ0 m²/(4π)`;
//! - pair-velocity coefficient `c_F = Ω / (σ d⁵)` in BL⁵/s: one agent moves at
//!   `c_F · [2(b̂·r̂)b̂ + (1 − 5(b̂·r̂)²) r̂] / r⁴` (r in BL) because of one neighbour; the pair's
//!   relative motion carries the factor 2: `κ = 2 c_F`, `ṙ = κ (1 − 3cos²ψ)/r⁴`, `φ̇ = κ sin 2ψ / r⁵`;
//! - pull coefficient `m / (σ d)` in BL/s per T/m of gradient;
//! - diffusion `D = k_B T / σ`, in BL²/s.

use serde::{Deserialize, Serialize};

use super::DragFactors;

/// Permeability of free space (T·m/A).
pub const MU0: f64 = 1.256_637_062_12e-6;
/// Boltzmann constant (J/K).
pub const K_B: f64 = 1.380_649e-23;

/// A physical preset. Field names are also the keys of a scenario's `[physics]` overrides.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhysicalParams {
    /// Sphere diameter (µm); this is 1 BL.
    pub diameter_um: f64,
    /// Fluid dynamic viscosity (mPa·s).
    pub viscosity_mpa_s: f64,
    /// Effective magnetisation of the sphere (kA/m), moment = magnetisation × volume.
    pub magnetization_ka_per_m: f64,
    /// Uniform field magnitude (mT); moments align with it.
    pub field_mt: f64,
    /// Largest pulling gradient per coil axis (mT/m).
    pub gradient_limit_mt_per_m: f64,
    /// Fluid temperature (K), for Brownian motion.
    pub temperature_k: f64,
    /// Smallest separation allowed by the proximity constraint (BL, exclusive).
    pub r_min: f64,
    /// Largest separation allowed by the proximity constraint (BL, exclusive).
    pub r_max: f64,
    /// Fixed integration step in the bulk (s); a medium of lower drag divides it
    /// ([`crate::plant::Medium::step`]).
    pub dt_s: f64,
}

/// Partial overrides of [`PhysicalParams`], as written in a scenario's `[physics]` table.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct PhysicalOverrides {
    pub diameter_um: Option<f64>,
    pub viscosity_mpa_s: Option<f64>,
    pub magnetization_ka_per_m: Option<f64>,
    pub field_mt: Option<f64>,
    pub gradient_limit_mt_per_m: Option<f64>,
    pub temperature_k: Option<f64>,
    pub r_min: Option<f64>,
    pub r_max: Option<f64>,
    pub dt_s: Option<f64>,
}

/// Smallest integration step accepted (s): a tenth of a millisecond, 83 times finer than the
/// default; below it every motion is so many steps that planning all but stops.
pub const MIN_DT_S: f64 = 1e-4;

/// Strongest field accepted (mT).
pub const MAX_FIELD_MT: f64 = 1000.0;

/// Most magnet-rotation sub-steps per integration step of a nominal agent in the bulk.
pub const MAX_ROTATION_SUBSTEPS: f64 = 1000.0;

impl Default for PhysicalParams {
    /// The default preset: 500 µm spheres in 30 mPa·s glycerol–water (see docs/physics.md).
    fn default() -> Self {
        Self {
            diameter_um: 500.0,
            viscosity_mpa_s: 30.0,
            magnetization_ka_per_m: 6.4,
            field_mt: 5.0,
            gradient_limit_mt_per_m: 85.0,
            temperature_k: 298.15,
            r_min: 1.25,
            r_max: 6.0,
            dt_s: 1.0 / 120.0,
        }
    }
}

impl PhysicalParams {
    /// Diameter in metres (1 BL).
    pub fn bl_m(&self) -> f64 {
        self.diameter_um * 1e-6
    }

    /// Stokes drag coefficient σ = 3πηd (N·s/m).
    pub fn drag(&self) -> f64 {
        3.0 * std::f64::consts::PI * self.viscosity_mpa_s * 1e-3 * self.bl_m()
    }

    /// Magnetic moment of one sphere (A·m²).
    pub fn moment(&self) -> f64 {
        let d = self.bl_m();
        self.magnetization_ka_per_m * 1e3 * std::f64::consts::PI * d.powi(3) / 6.0
    }

    /// Force constant Ω = 3μ0 m²/(4π) (N·m⁴).
    pub fn omega(&self) -> f64 {
        3.0 * MU0 * self.moment().powi(2) / (4.0 * std::f64::consts::PI)
    }

    /// Single-agent pair-velocity coefficient c_F = Ω/(σ d⁵) (BL⁵/s).
    pub fn force_coeff(&self) -> f64 {
        self.omega() / (self.drag() * self.bl_m().powi(5))
    }

    /// Translational drag in a medium with drag factors `f`: `f.translation · 3πηd` (N·s/m).
    pub fn drag_in(&self, f: DragFactors) -> f64 {
        self.drag() * f.translation
    }

    /// [`PhysicalParams::force_coeff`] with the drag of a medium with factors `f`; equal bit
    /// for bit to it in the bulk.
    pub fn force_coeff_in(&self, f: DragFactors) -> f64 {
        self.omega() / (self.drag_in(f) * self.bl_m().powi(5))
    }

    /// [`PhysicalParams::pull_coeff`] with the drag of a medium with factors `f`.
    pub fn pull_coeff_in(&self, f: DragFactors) -> f64 {
        self.moment() / (self.drag_in(f) * self.bl_m())
    }

    /// [`PhysicalParams::diffusion`] with the drag of a medium with factors `f`.
    pub fn diffusion_in(&self, f: DragFactors) -> f64 {
        K_B * self.temperature_k / self.drag_in(f) / self.bl_m().powi(2)
    }

    /// Relative-motion constant κ = 2 c_F (BL⁵/s): `ṙ = κ(1 − 3cos²ψ)/r⁴`, `φ̇ = κ sin2ψ/r⁵`.
    pub fn kappa(&self) -> f64 {
        2.0 * self.force_coeff()
    }

    /// Pull speed per unit gradient, m/(σ d) (BL/s per T/m).
    pub fn pull_coeff(&self) -> f64 {
        self.moment() / (self.drag() * self.bl_m())
    }

    /// Gradient limit in T/m.
    pub fn gradient_limit(&self) -> f64 {
        self.gradient_limit_mt_per_m * 1e-3
    }

    /// Largest centre-of-mass pull speed along one axis (BL/s).
    pub fn max_pull_speed(&self) -> f64 {
        self.pull_coeff() * self.gradient_limit()
    }

    /// Translational diffusion constant D = k_B T/σ (BL²/s).
    pub fn diffusion(&self) -> f64 {
        K_B * self.temperature_k / self.drag() / self.bl_m().powi(2)
    }

    /// Applies scenario overrides.
    pub fn with_overrides(&self, o: &PhysicalOverrides) -> Self {
        let mut p = self.clone();
        macro_rules! set {
            ($($f:ident),*) => { $( if let Some(v) = o.$f { p.$f = v; } )* };
        }
        set!(
            diameter_um,
            viscosity_mpa_s,
            magnetization_ka_per_m,
            field_mt,
            gradient_limit_mt_per_m,
            temperature_k,
            r_min,
            r_max,
            dt_s
        );
        p
    }

    /// Checks that every value is finite and physically meaningful; returns (field, reason).
    pub fn check(&self) -> Result<(), crate::input::Rejection> {
        let positive = [
            ("diameter_um", self.diameter_um),
            ("viscosity_mpa_s", self.viscosity_mpa_s),
            ("magnetization_ka_per_m", self.magnetization_ka_per_m),
            ("field_mt", self.field_mt),
            ("gradient_limit_mt_per_m", self.gradient_limit_mt_per_m),
            ("temperature_k", self.temperature_k),
            ("dt_s", self.dt_s),
        ];
        for (name, v) in positive {
            if !v.is_finite() || v <= 0.0 {
                return Err(crate::input::Rejection::new(
                    name,
                    format!("must be a finite number > 0, got {v}"),
                ));
            }
        }
        if !self.r_min.is_finite() || self.r_min <= 1.0 {
            return Err(crate::input::Rejection::new(
                "r_min",
                format!("must be > 1 BL (agents touch at 1 BL), got {}", self.r_min),
            ));
        }
        if !self.r_max.is_finite() || self.r_max <= self.r_min {
            return Err(crate::input::Rejection::new(
                "r_max",
                format!("must be > r_min = {}, got {}", self.r_min, self.r_max),
            ));
        }
        if self.field_mt > MAX_FIELD_MT {
            return Err(crate::input::Rejection::new(
                "field_mt",
                format!(
                    "must be at most {MAX_FIELD_MT} mT (1 T: beyond what coil systems for microrobots make), got {}",
                    self.field_mt
                ),
            ));
        }
        // the magnet-lag term integrates each moment in sub-steps of its rotation time
        let tau = std::f64::consts::PI * self.viscosity_mpa_s * 1e-3 * self.bl_m().powi(3)
            / (self.moment() * self.field_mt * 1e-3);
        let substeps = 1.5 * self.dt_s / tau;
        if substeps.is_nan() || substeps > MAX_ROTATION_SUBSTEPS {
            return Err(crate::input::Rejection::new(
                "field_mt",
                format!(
                    "with these values a moment turns to the field in τ = {tau:.3e} s; the plant integrates that in {substeps:.3e} sub-steps per step of dt_s = {} s, at most {MAX_ROTATION_SUBSTEPS} are allowed (so that a simulated second stays under a minute): lower field_mt or magnetization_ka_per_m, or raise viscosity_mpa_s",
                    self.dt_s
                ),
            ));
        }
        if !(MIN_DT_S..=0.05).contains(&self.dt_s) {
            return Err(crate::input::Rejection::new(
                "dt_s",
                format!(
                    "must be in [{MIN_DT_S}, 0.05] s (≤ 0.05 s for an accurate integration, ≥ {MIN_DT_S} s so that a plan is not millions of steps), got {}",
                    self.dt_s
                ),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_preset_gives_realistic_speeds() {
        let p = PhysicalParams::default();
        // relative attraction speed at r = 2 BL, ψ = 0: 2κ/r⁴
        let rel = 2.0 * p.kappa() / 16.0;
        assert!(
            (2.0..=5.0).contains(&rel),
            "relative speed {rel} BL/s at r = 2"
        );
        let pull = p.max_pull_speed();
        assert!((0.4..=0.6).contains(&pull), "pull {pull} BL/s");
        assert!(p.r_min < 1.5 && p.r_max > 5.0);
        assert!(p.check().is_ok());
    }

    #[test]
    fn overrides_apply_by_name() {
        let o = PhysicalOverrides {
            r_max: Some(7.0),
            ..Default::default()
        };
        assert_eq!(PhysicalParams::default().with_overrides(&o).r_max, 7.0);
    }
}
