//! The coil command carried by plans and issued by trackers.

use serde::{Deserialize, Serialize};

/// A coil command: global field angle, elevation and pulling gradient.
///
/// This is what the coil applies, not the local angle ψ: ψ = θ_B − φ follows from the state.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Control {
    /// Global in-plane field angle θ_B (radians, from +x toward +y).
    pub theta: f64,
    /// Field elevation α out of the plane (radians); 0 for planar actuation.
    pub alpha: f64,
    /// Pulling-gradient command along x and y (T/m); see the coil for its meaning.
    pub grad: [f64; 2],
}

impl Control {
    /// A planar command (α = 0).
    pub fn planar(theta: f64, gx: f64, gy: f64) -> Self {
        Self {
            theta,
            alpha: 0.0,
            grad: [gx, gy],
        }
    }

    /// The same pair force with the opposite pull: θ_B + π.
    pub fn flipped(&self) -> Self {
        Self {
            theta: crate::math::wrap_angle(self.theta + std::f64::consts::PI),
            ..*self
        }
    }

    /// True when every number is finite.
    pub fn is_finite(&self) -> bool {
        self.theta.is_finite() && self.alpha.is_finite() && self.grad.iter().all(|g| g.is_finite())
    }
}
