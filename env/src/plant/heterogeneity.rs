//! Agent heterogeneity: no two agents have quite the same moment or drag.
//!
//! Per run, each agent draws a moment factor and a drag factor (1 = the planning model's
//! agent), either uniformly in `[1 − s, 1 + s]` or lognormally, `exp(s·N(0, 1))` (median 1:
//! the spread of a product of many small independent factors, such as a size tolerance cubed
//! and a particle load). At an interface each agent also draws its contact angle, with the
//! medium's spread; its drag then scales with its drag fraction at that angle relative to the
//! mean angle's, and its capillary charge follows its own immersion.

use rand::RngExt;
use serde::{Deserialize, Serialize};

use super::medium::{Interface, Medium};
use super::streams::{Stream, normal, stream};
use super::term::Term;
use crate::check::Rejection;
use crate::check::bounds::within;
use crate::math::MAX_AGENTS;

/// How a per-agent factor is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Spread {
    /// Uniform in `[1 − s, 1 + s]`.
    #[default]
    Uniform,
    /// `exp(s·N(0, 1))`: lognormal with median 1 and log-standard-deviation `s`.
    Lognormal,
}

/// The heterogeneity term of a preset.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Heterogeneity {
    /// Whether the term acts.
    pub enabled: bool,
    /// How the moment and drag factors are drawn.
    pub distribution: Spread,
    /// Spread `s` of the moment factor.
    pub moment_spread: f64,
    /// Spread `s` of the drag factor (size and shape; immersion at an interface comes on top).
    pub drag_spread: f64,
}

/// The drawn factors of every agent.
#[derive(Debug, Clone, PartialEq)]
pub struct AgentFactors {
    /// Moment factor (1 = nominal).
    pub moment: [f64; MAX_AGENTS],
    /// Mobility factor, 1/drag factor (1 = nominal).
    pub mobility: [f64; MAX_AGENTS],
    /// Contact angle at an interface (radians); the medium's mean when not drawn.
    pub contact_angle: [f64; MAX_AGENTS],
}

impl Term for Heterogeneity {
    fn enabled(&self) -> bool {
        self.enabled
    }

    fn set_enabled(&mut self, on: bool) {
        self.enabled = on;
    }

    fn check(&self) -> Result<(), Rejection> {
        let hi = match self.distribution {
            Spread::Uniform => 0.9,
            Spread::Lognormal => 1.0,
        };
        within(
            "moment_spread",
            self.moment_spread,
            0.0,
            hi,
            "",
        )?;
        within("drag_spread", self.drag_spread, 0.0, hi, "")
    }
}

impl Heterogeneity {
    /// Draws the factors of `n` agents for the run seeded with `seed`.
    pub fn draw(&self, medium: &Medium, n: usize, seed: u64) -> AgentFactors {
        let mean_angle = medium
            .interface()
            .map(|i| i.contact_angle_deg.to_radians())
            .unwrap_or(std::f64::consts::FRAC_PI_2);
        let mut f = AgentFactors {
            moment: [1.0; MAX_AGENTS],
            mobility: [1.0; MAX_AGENTS],
            contact_angle: [mean_angle; MAX_AGENTS],
        };
        if !self.enabled {
            return f;
        }
        let rng = &mut stream(seed, Stream::Heterogeneity);
        let mut factor = |s: f64| match (s > 0.0, self.distribution) {
            (false, _) => 1.0,
            (true, Spread::Uniform) => rng.random_range(1.0 - s..=1.0 + s),
            (true, Spread::Lognormal) => (s * normal(rng)).exp(),
        };
        for i in 0..n {
            f.moment[i] = factor(self.moment_spread);
            f.mobility[i] = 1.0 / factor(self.drag_spread);
        }
        if let Some(iface) = medium.interface() {
            let rng = &mut stream(seed, Stream::ContactAngle);
            let sd = iface.contact_angle_spread_deg.to_radians();
            let mean_drag = Interface::drag_fraction(mean_angle);
            for i in 0..n {
                let a = Interface::clamp_angle(mean_angle + sd * normal(rng));
                f.contact_angle[i] = a;
                f.mobility[i] *= mean_drag / Interface::drag_fraction(a);
            }
        }
        f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lognormal(s: f64) -> Heterogeneity {
        Heterogeneity {
            enabled: true,
            distribution: Spread::Lognormal,
            moment_spread: s,
            drag_spread: s,
        }
    }

    #[test]
    fn lognormal_factors_have_the_set_log_spread() {
        let mut logs = vec![];
        for seed in 0..2000 {
            let f = lognormal(0.2).draw(&Medium::Bulk, 2, seed);
            logs.push(f.moment[0].ln());
            logs.push(f.moment[1].ln());
            assert!(f.moment[0] > 0.0 && f.mobility[0] > 0.0);
        }
        let n = logs.len() as f64;
        let mean = logs.iter().sum::<f64>() / n;
        let sd = (logs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n).sqrt();
        assert!(mean.abs() < 0.02 && (sd - 0.2).abs() < 0.01, "{mean} {sd}");
    }

    #[test]
    fn off_means_identical_agents() {
        let f = Heterogeneity::default().draw(&Medium::Bulk, 3, 1);
        assert_eq!(f.moment, [1.0; MAX_AGENTS]);
        assert_eq!(f.mobility, [1.0; MAX_AGENTS]);
    }
}
