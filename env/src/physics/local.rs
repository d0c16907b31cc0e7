//! The local view of a two-agent team: centre of mass, separation and pair heading.

use crate::math::{Vec2, wrap_angle};

/// Two-agent configuration in the seed's coordinates `q = (x_c, y_c, r, φ)`.
///
/// `r` is the separation |P₂ − P₁| in BL and `φ` the heading of `P₂ − P₁` (radians, world
/// frame). The local field angle is `ψ = θ_B − φ` ([`LocalView::psi`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalView {
    /// Centre of mass, x (BL).
    pub xc: f64,
    /// Centre of mass, y (BL).
    pub yc: f64,
    /// Separation (BL).
    pub r: f64,
    /// Pair heading φ of `P₂ − P₁` (radians).
    pub phi: f64,
}

impl LocalView {
    /// The view of a pair centred at (`xc`, `yc`), `r` apart, heading `phi`.
    pub const fn new(xc: f64, yc: f64, r: f64, phi: f64) -> Self {
        Self { xc, yc, r, phi }
    }

    /// The local view of agents `p1` and `p2`.
    pub fn from_pair(p1: Vec2, p2: Vec2) -> Self {
        let c = (p1 + p2) * 0.5;
        let d = p2 - p1;
        Self {
            xc: c.x,
            yc: c.y,
            r: d.norm(),
            phi: d.y.atan2(d.x),
        }
    }

    /// The two agent positions of this view.
    pub fn to_pair(&self) -> [Vec2; 2] {
        let h = Vec2::new(self.phi.cos(), self.phi.sin()) * (0.5 * self.r);
        let c = Vec2::new(self.xc, self.yc);
        [c - h, c + h]
    }

    /// Local field angle `ψ = θ_B − φ`, wrapped to (−π, π].
    pub fn psi(&self, theta_b: f64) -> f64 {
        wrap_angle(theta_b - self.phi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip() {
        let (a, b) = (Vec2::new(1.0, 2.0), Vec2::new(3.5, 0.5));
        let v = LocalView::from_pair(a, b);
        let [a2, b2] = v.to_pair();
        assert!((a - a2).norm() < 1e-12 && (b - b2).norm() < 1e-12);
        assert!((v.r - (b - a).norm()).abs() < 1e-12);
        assert!((v.psi(v.phi + 0.3) - 0.3).abs() < 1e-12);
    }
}
