//! Background flow of the liquid: a flow that varies smoothly in space and time, and the run's
//! flow field (that flow plus the uniform drift of [`super::drift`]).
//!
//! The varying flow is divergence-free, from a stream function of `N = 8` random modes:
//! `ψ(x, t) = Σ A_n sin(k_n·x + φ_n) cos(ω_n t + χ_n)` and `u = (∂ψ/∂y, −∂ψ/∂x)`. Each mode's
//! wavelength is the preset's length times a factor drawn in [0.75, 1.25], its period the
//! preset's period times a factor in [0.75, 1.25], its direction and phases uniform; the
//! amplitudes `A_n = 2 u_rms / (|k_n| √N)` give the set RMS speed over space and time.

use rand::RngExt;
use serde::{Deserialize, Serialize};

use super::drift::Drift;
use super::streams::{Stream, stream};
use super::term::Term;
use crate::input::Rejection;
use crate::input::bounds::{positive, within};
use crate::math::Vec2;

/// The varying-flow term of a preset.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Flow {
    /// Whether the term acts.
    pub enabled: bool,
    /// RMS speed over space and time (BL/s).
    pub rms_speed_bl_s: f64,
    /// Typical wavelength of its spatial variation (BL).
    pub length_bl: f64,
    /// Typical period of its variation in time (s).
    pub period_s: f64,
}

impl Term for Flow {
    super::term::switch_is_enabled_field!();

    fn check(&self) -> Result<(), Rejection> {
        if !self.enabled {
            return Ok(());
        }
        within(
            "rms_speed_bl_s",
            self.rms_speed_bl_s,
            0.0,
            100.0,
            " BL/s",
        )?;
        positive("length_bl", self.length_bl)?;
        positive("period_s", self.period_s)
    }
}

/// Number of modes of the varying flow.
const MODES: usize = 8;

#[derive(Debug, Clone, PartialEq)]
struct Mode {
    k: Vec2,
    amplitude: f64,
    phase: f64,
    omega: f64,
    time_phase: f64,
}

/// The background flow of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct FlowField {
    /// The uniform drift (BL/s).
    pub drift: Vec2,
    modes: Vec<Mode>,
}

impl FlowField {
    /// Draws the flow of the run seeded with `seed`.
    pub fn draw(drift: &Drift, flow: &Flow, seed: u64) -> Self {
        let mut uniform = Vec2::zeros();
        if drift.enabled && drift.max_speed_bl_s > 0.0 {
            let rng = &mut stream(seed, Stream::Drift);
            let speed = rng.random_range(0.0..=drift.max_speed_bl_s);
            let dir = rng.random_range(0.0..std::f64::consts::TAU);
            uniform = Vec2::new(dir.cos(), dir.sin()) * speed;
        }
        let mut modes = vec![];
        if flow.enabled && flow.rms_speed_bl_s > 0.0 {
            let rng = &mut stream(seed, Stream::Flow);
            let tau = std::f64::consts::TAU;
            for _ in 0..MODES {
                let kn = tau / (flow.length_bl * rng.random_range(0.75..=1.25));
                let dir = rng.random_range(0.0..tau);
                modes.push(Mode {
                    k: Vec2::new(dir.cos(), dir.sin()) * kn,
                    amplitude: 2.0 * flow.rms_speed_bl_s / (kn * (MODES as f64).sqrt()),
                    phase: rng.random_range(0.0..tau),
                    omega: tau / (flow.period_s * rng.random_range(0.75..=1.25)),
                    time_phase: rng.random_range(0.0..tau),
                });
            }
        }
        Self {
            drift: uniform,
            modes,
        }
    }

    /// The flow with its uniform drift replaced by `drift` (BL/s), when given.
    pub fn with_drift(mut self, drift: Option<[f64; 2]>) -> Self {
        if let Some([x, y]) = drift {
            self.drift = Vec2::new(x, y);
        }
        self
    }

    /// True when the flow is uniform and steady (the drift alone).
    pub fn is_uniform(&self) -> bool {
        self.modes.is_empty()
    }

    /// The flow velocity at `p` (BL) and time `t` (s), in BL/s.
    #[inline]
    pub fn at(&self, p: Vec2, t: f64) -> Vec2 {
        let mut v = self.drift;
        for m in &self.modes {
            let s =
                m.amplitude * (m.k.dot(&p) + m.phase).cos() * (m.omega * t + m.time_phase).cos();
            v += Vec2::new(m.k.y, -m.k.x) * s;
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flow() -> Flow {
        Flow {
            enabled: true,
            rms_speed_bl_s: 0.02,
            length_bl: 10.0,
            period_s: 30.0,
        }
    }

    #[test]
    fn varying_flow_has_the_set_rms_and_no_divergence() {
        let mut sum2 = 0.0;
        let mut n = 0.0;
        for seed in 0..40 {
            let f = FlowField::draw(&Drift::default(), &flow(), seed);
            for k in 0..50 {
                let p = Vec2::new(k as f64 * 1.7 % 40.0, k as f64 * 3.1 % 30.0);
                sum2 += f.at(p, k as f64 * 7.3).norm_squared();
                n += 1.0;
            }
            // divergence by central differences
            let (p, h) = (Vec2::new(3.0, 4.0), 1e-4);
            let div = (f.at(p + Vec2::new(h, 0.0), 1.0).x - f.at(p - Vec2::new(h, 0.0), 1.0).x
                + f.at(p + Vec2::new(0.0, h), 1.0).y
                - f.at(p - Vec2::new(0.0, h), 1.0).y)
                / (2.0 * h);
            assert!(div.abs() < 1e-9, "divergence {div}");
        }
        let rms = (sum2 / n).sqrt();
        assert!((rms - 0.02).abs() < 0.003, "rms {rms}");
    }

    #[test]
    fn flow_is_smooth_on_its_scales() {
        let f = FlowField::draw(&Drift::default(), &flow(), 3);
        let p = Vec2::new(10.0, 10.0);
        let (v, near, later) = (
            f.at(p, 0.0),
            f.at(p + Vec2::new(0.5, 0.0), 0.0),
            f.at(p, 1.0),
        );
        assert!((v - near).norm() < 0.3 * 0.02 * 2.0 && (v - later).norm() < 0.3 * 0.02 * 2.0);
        assert!(
            FlowField::draw(&Drift::default(), &Flow::default(), 3).at(p, 5.0) == Vec2::zeros()
        );
    }
}
