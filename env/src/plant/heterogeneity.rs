//! Agent heterogeneity: no two agents have quite the same moment or drag.
//!
//! Per run, each agent draws a moment factor and a drag factor (1 = the planning model's
//! agent), either uniformly in `[1 − s, 1 + s]` or lognormally, `exp(s·N(0, 1))` (median 1:
//! the spread of a product of many small independent factors, such as a size tolerance cubed
//! and a particle load). At an interface each agent also draws its contact angle, with the
//! medium's spread; its drag then scales with its drag fraction at that angle relative to the
//! mean angle's, and its capillary charge follows its own immersion.
//!
//! On top of the agent-to-agent factors come common-mode ones, shared by every agent of the
//! run: a moment factor (the batch's magnetisation off the model's, e.g. 0.9 for moments 10%
//! weaker than the model thinks) and a drag factor (the liquid's viscosity off the model's),
//! each a fixed factor times a factor drawn once per run with its own spread.

use rand::RngExt;
use serde::{Deserialize, Serialize};

use super::medium::{Interface, Medium};
use super::streams::{Stream, normal, stream};
use super::term::Term;
use crate::input::bounds::within;
use crate::input::{Bound, Rejection};
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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
    /// Fixed common-mode moment factor of every agent (1 = the planning model's moment).
    #[serde(default = "one")]
    pub common_moment_factor: f64,
    /// Spread `s` of a common-mode moment factor drawn once per run for all agents.
    #[serde(default)]
    pub common_moment_spread: f64,
    /// Fixed common-mode drag factor of every agent (1 = the planning model's drag).
    #[serde(default = "one")]
    pub common_drag_factor: f64,
    /// Spread `s` of a common-mode drag factor drawn once per run for all agents.
    #[serde(default)]
    pub common_drag_spread: f64,
}

fn one() -> f64 {
    1.0
}

impl Default for Heterogeneity {
    /// Off: identical agents, no common-mode factor.
    fn default() -> Self {
        Self {
            enabled: false,
            distribution: Spread::default(),
            moment_spread: 0.0,
            drag_spread: 0.0,
            common_moment_factor: 1.0,
            common_moment_spread: 0.0,
            common_drag_factor: 1.0,
            common_drag_spread: 0.0,
        }
    }
}

/// The fixed common-mode factors a preset accepts.
const COMMON_FACTOR: Bound = Bound::closed(
    0.1,
    10.0,
    "",
    "a batch or liquid ten times off the model is a different model, not a mismatch",
);

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
    super::term::switch_is_enabled_field!();

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
        within("drag_spread", self.drag_spread, 0.0, hi, "")?;
        COMMON_FACTOR.check("common_moment_factor", self.common_moment_factor)?;
        within("common_moment_spread", self.common_moment_spread, 0.0, hi, "")?;
        COMMON_FACTOR.check("common_drag_factor", self.common_drag_factor)?;
        within("common_drag_spread", self.common_drag_spread, 0.0, hi, "")
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
        let (moment, drag) = self.common(seed);
        if (moment, drag) != (1.0, 1.0) {
            for i in 0..n {
                f.moment[i] *= moment;
                f.mobility[i] /= drag;
            }
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

    /// The run's common-mode moment and drag factors: the fixed factors times factors drawn
    /// from their own stream (so the per-agent draws do not depend on them).
    fn common(&self, seed: u64) -> (f64, f64) {
        let rng = &mut stream(seed, Stream::CommonMode);
        let mut factor = |s: f64| match (s > 0.0, self.distribution) {
            (false, _) => 1.0,
            (true, Spread::Uniform) => rng.random_range(1.0 - s..=1.0 + s),
            (true, Spread::Lognormal) => (s * normal(rng)).exp(),
        };
        let moment = self.common_moment_factor * factor(self.common_moment_spread);
        let drag = self.common_drag_factor * factor(self.common_drag_spread);
        (moment, drag)
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
            ..Default::default()
        }
    }

    #[test]
    fn common_mode_scales_every_agent_alike_and_leaves_the_spread() {
        let base = lognormal(0.2);
        let common = Heterogeneity {
            common_moment_factor: 0.9,
            common_drag_factor: 1.05,
            ..base.clone()
        };
        for seed in 0..20 {
            let (a, b) = (
                base.draw(&Medium::Bulk, 3, seed),
                common.draw(&Medium::Bulk, 3, seed),
            );
            for i in 0..3 {
                assert!((b.moment[i] / a.moment[i] - 0.9).abs() < 1e-12);
                assert!((a.mobility[i] / b.mobility[i] - 1.05).abs() < 1e-12);
            }
        }
        let drawn = Heterogeneity {
            common_moment_spread: 0.1,
            ..base.clone()
        };
        let ratios: Vec<f64> = (0..400)
            .map(|seed| {
                let (a, b) = (
                    base.draw(&Medium::Bulk, 2, seed),
                    drawn.draw(&Medium::Bulk, 2, seed),
                );
                let r = b.moment[0] / a.moment[0];
                assert!((b.moment[1] / a.moment[1] - r).abs() < 1e-12, "common");
                r.ln()
            })
            .collect();
        let sd = (ratios.iter().map(|x| x * x).sum::<f64>() / ratios.len() as f64).sqrt();
        assert!((sd - 0.1).abs() < 0.015, "log-spread {sd}");
    }

    #[test]
    fn common_mode_values_are_bounded() {
        for (field, edit) in [
            ("common_moment_factor", Heterogeneity {
                common_moment_factor: 0.0,
                ..lognormal(0.1)
            }),
            ("common_moment_spread", Heterogeneity {
                common_moment_spread: -0.1,
                ..lognormal(0.1)
            }),
            ("common_drag_factor", Heterogeneity {
                common_drag_factor: f64::NAN,
                ..lognormal(0.1)
            }),
            ("common_drag_spread", Heterogeneity {
                common_drag_spread: 2.0,
                ..lognormal(0.1)
            }),
        ] {
            assert_eq!(Term::check(&edit).unwrap_err().field, field);
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
