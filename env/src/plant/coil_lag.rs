//! Coil dynamics: each field and gradient axis follows its command through a first-order lag
//! whose rate is bounded (a slew limit).
//!
//! A coil driven by a voltage-limited amplifier is an inductor: its current, and so its field,
//! relaxes to the commanded value with the time constant `τ = L/R`, and can change no faster
//! than the amplifier's spare voltage allows, `|di/dt| ≤ (V_max − iR)/L`. Per axis this is
//! `ẋ = clamp((u − x)/τ, −S, S)`, solved exactly here for a command `u` held constant: a ramp at
//! the slew limit while `|u − x| > S τ`, then the exponential.

use serde::{Deserialize, Serialize};

use super::term::Term;
use crate::input::Rejection;
use crate::input::bounds::{non_negative, within};

/// The coil-dynamics term of a preset.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoilLag {
    /// Whether the term acts.
    pub enabled: bool,
    /// Time constant of the uniform-field (Helmholtz) axes (ms); 0 = no lag.
    pub field_tau_ms: f64,
    /// Time constant of the gradient (Maxwell) axes (ms); 0 = no lag.
    pub gradient_tau_ms: f64,
    /// Largest rate of change of each field axis (mT/s); 0 = unlimited.
    pub field_slew_mt_per_s: f64,
    /// Largest rate of change of each gradient axis (mT/m per s); 0 = unlimited.
    pub gradient_slew_mt_per_m_per_s: f64,
}

impl Term for CoilLag {
    super::term::switch_is_enabled_field!();

    fn check(&self) -> Result<(), Rejection> {
        within(
            "field_tau_ms",
            self.field_tau_ms,
            0.0,
            1000.0,
            " ms",
        )?;
        within(
            "gradient_tau_ms",
            self.gradient_tau_ms,
            0.0,
            1000.0,
            " ms",
        )?;
        non_negative("field_slew_mt_per_s", self.field_slew_mt_per_s)?;
        non_negative(
            "gradient_slew_mt_per_m_per_s",
            self.gradient_slew_mt_per_m_per_s,
        )
    }
}

impl CoilLag {
    /// The response of a field axis (values in T).
    pub fn field_axis(&self) -> AxisResponse {
        AxisResponse::new(self.enabled, self.field_tau_ms, self.field_slew_mt_per_s)
    }

    /// The response of a gradient axis (values in T/m).
    pub fn gradient_axis(&self) -> AxisResponse {
        AxisResponse::new(
            self.enabled,
            self.gradient_tau_ms,
            self.gradient_slew_mt_per_m_per_s,
        )
    }
}

/// How one coil axis follows a constant command: time constant and slew limit, in SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisResponse {
    /// Time constant (s); 0 = none.
    pub tau: f64,
    /// Largest rate (units per s); infinite = unlimited.
    pub slew: f64,
}

impl AxisResponse {
    fn new(enabled: bool, tau_ms: f64, slew_milli_per_s: f64) -> Self {
        if !enabled {
            return Self::INSTANT;
        }
        Self {
            tau: tau_ms * 1e-3,
            slew: if slew_milli_per_s > 0.0 {
                slew_milli_per_s * 1e-3
            } else {
                f64::INFINITY
            },
        }
    }

    /// An axis that takes its command at once.
    pub const INSTANT: Self = Self {
        tau: 0.0,
        slew: f64::INFINITY,
    };

    /// True when the axis takes its command at once.
    pub fn is_instant(&self) -> bool {
        self.tau == 0.0 && self.slew == f64::INFINITY
    }

    /// The axis value `t` seconds after it was `x0`, under the constant command `u`.
    pub fn at(&self, x0: f64, u: f64, t: f64) -> f64 {
        let e = u - x0;
        if e == 0.0 || self.is_instant() {
            return u;
        }
        let s = e.signum();
        if self.tau == 0.0 {
            return if e.abs() <= self.slew * t {
                u
            } else {
                x0 + s * self.slew * t
            };
        }
        // the exponential's initial rate |e|/τ exceeds the slew limit: ramp first
        let knee = self.slew * self.tau;
        if e.abs() <= knee {
            return u - e * (-t / self.tau).exp();
        }
        let t1 = (e.abs() - knee) / self.slew;
        if t <= t1 {
            x0 + s * self.slew * t
        } else {
            u - s * knee * (-(t - t1) / self.tau).exp()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lag_reaches_63_percent_after_one_time_constant() {
        let a = AxisResponse {
            tau: 0.006,
            slew: f64::INFINITY,
        };
        let x = a.at(0.0, 1.0, 0.006);
        assert!((x - (1.0 - (-1.0f64).exp())).abs() < 1e-12);
        assert_eq!(AxisResponse::INSTANT.at(0.3, 1.0, 0.0), 1.0);
    }

    #[test]
    fn slew_limit_ramps_then_joins_the_exponential_smoothly() {
        let a = AxisResponse {
            tau: 0.01,
            slew: 20.0,
        };
        // |e|/τ = 100/s > 20/s: ramp for (1 − 0.2)/20 = 40 ms
        assert!((a.at(0.0, 1.0, 0.02) - 0.4).abs() < 1e-12);
        let (before, after) = (a.at(0.0, 1.0, 0.04 - 1e-9), a.at(0.0, 1.0, 0.04 + 1e-9));
        assert!((before - 0.8).abs() < 1e-6 && (after - 0.8).abs() < 1e-6);
        // the rate never exceeds the limit
        for k in 0..200 {
            let t = k as f64 * 1e-3;
            let rate = (a.at(0.0, 1.0, t + 1e-6) - a.at(0.0, 1.0, t)) / 1e-6;
            assert!(rate <= 20.0 + 1e-6, "rate {rate} at {t}");
        }
        // downward too
        assert!((a.at(1.0, 0.0, 0.02) - 0.6).abs() < 1e-12);
    }

    #[test]
    fn a_disabled_term_is_instant_and_zero_means_unlimited() {
        let c = CoilLag {
            enabled: false,
            field_tau_ms: 6.0,
            ..Default::default()
        };
        assert!(c.field_axis().is_instant());
        let on = CoilLag {
            enabled: true,
            field_tau_ms: 6.0,
            ..Default::default()
        };
        assert_eq!(on.field_axis().slew, f64::INFINITY);
        assert!((on.field_axis().tau - 0.006).abs() < 1e-15);
    }
}
