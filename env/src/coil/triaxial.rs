//! The tri-axial Helmholtz–Maxwell coil.
//!
//! Three Helmholtz pairs set a uniform field `B b̂`; three Maxwell pairs superimpose a diagonal,
//! divergence-free gradient `∇B = diag(G_x, G_y, −G_x − G_y)`. The pull on an aligned moment is
//! `F = (m·∇)B = m (G_x b̂_x, G_y b̂_y, −(G_x+G_y) b̂_z)`, so the force along x scales with cos θ_B
//! and along y with sin θ_B: at θ_B = 90° nothing pulls along x, at θ_B = 0° nothing pulls along
//! y — the seed's pulling "singularities". Flipping b̂ keeps the pair force (quadratic in b̂) and
//! reverses the pull (linear in b̂).

use super::{Actuation, Coil, Control};
use crate::math::Vec3;
use crate::physics::field_direction;

/// Tri-axial Helmholtz–Maxwell coil with a per-axis gradient bound and an elevation range.
#[derive(Debug, Clone, PartialEq)]
pub struct TriaxialMaxwell {
    /// Largest |G_x|, |G_y| (T/m).
    pub gradient_limit: f64,
    /// Largest field elevation |α| it can set (rad): π/2 for a tri-axial coil
    /// ([`super::COIL_ALPHA_MAX_DEG`]), less when a rig file or preset says so.
    pub alpha_max: f64,
}

impl TriaxialMaxwell {
    /// A coil with gradient bound `gradient_limit` (T/m) and the whole elevation range.
    pub fn new(gradient_limit: f64) -> Self {
        Self {
            gradient_limit,
            alpha_max: super::COIL_ALPHA_MAX_DEG.to_radians(),
        }
    }

    /// The same coil with elevation range `alpha_max_deg` (degrees).
    pub fn with_alpha_max_deg(self, alpha_max_deg: f64) -> Self {
        Self {
            alpha_max: alpha_max_deg.to_radians(),
            ..self
        }
    }
}

impl Coil for TriaxialMaxwell {
    fn name(&self) -> &str {
        "triaxial-maxwell"
    }

    fn gradient_limit(&self) -> f64 {
        self.gradient_limit
    }

    fn alpha_max(&self) -> f64 {
        self.alpha_max
    }

    fn clamp(&self, u: &Control) -> (Control, bool) {
        let g = self.gradient_limit;
        let grad = u.grad.map(|x| x.clamp(-g, g));
        let alpha = u.alpha.clamp(-self.alpha_max, self.alpha_max);
        let clamped = grad != u.grad || alpha != u.alpha;
        (
            Control {
                theta: u.theta,
                alpha,
                grad,
            },
            clamped,
        )
    }

    fn actuation(&self, u: &Control) -> Actuation {
        let b = field_direction(u.theta, u.alpha);
        let [gx, gy] = u.grad;
        Actuation {
            b_hat: b,
            pull: Vec3::new(gx * b.x, gy * b.y, -(gx + gy) * b.z),
        }
    }

    fn pull_map(&self, u: &Control) -> (Actuation, [Vec3; 2]) {
        let b = field_direction(u.theta, u.alpha);
        let zero = Actuation {
            b_hat: b,
            pull: Vec3::zeros(),
        };
        (zero, [Vec3::new(b.x, 0.0, -b.z), Vec3::new(0.0, b.y, -b.z)])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    /// The closed-form pull map equals the trait's default, which probes the actuation.
    #[test]
    fn pull_map_equals_the_probed_one() {
        #[derive(Debug)]
        struct Probed(TriaxialMaxwell);
        impl Coil for Probed {
            fn name(&self) -> &str {
                "probed"
            }
            fn gradient_limit(&self) -> f64 {
                self.0.gradient_limit()
            }
            fn alpha_max(&self) -> f64 {
                self.0.alpha_max()
            }
            fn clamp(&self, u: &Control) -> (Control, bool) {
                self.0.clamp(u)
            }
            fn actuation(&self, u: &Control) -> Actuation {
                self.0.actuation(u)
            }
        }
        let c = TriaxialMaxwell::new(0.1);
        let probed = Probed(c.clone());
        for (theta, alpha) in [(0.3, 0.0), (-2.0, 0.4), (PI / 2.0, 0.1)] {
            let u = Control {
                theta,
                alpha,
                grad: [0.05, -0.02],
            };
            let (a, [x, y]) = c.pull_map(&u);
            let (b, [px, py]) = probed.pull_map(&u);
            assert_eq!(a.b_hat, b.b_hat);
            assert!((a.pull - b.pull).norm() < 1e-15);
            assert!(
                (x - px).norm() < 1e-12 && (y - py).norm() < 1e-12,
                "{x} {px} {y} {py}"
            );
            let full = c.actuation(&u).pull;
            assert!((a.pull + x * 0.05 - y * 0.02 - full).norm() < 1e-15);
        }
    }

    #[test]
    fn pull_along_x_vanishes_at_90_degrees() {
        let c = TriaxialMaxwell::new(0.1);
        let a = c.actuation(&Control::planar(FRAC_PI_2, 0.1, 0.0));
        assert!(a.pull.x.abs() < 1e-15);
        let a0 = c.actuation(&Control::planar(0.0, 0.0, 0.1));
        assert!(a0.pull.y.abs() < 1e-15);
    }

    #[test]
    fn flipping_reverses_pull_keeps_direction_axis() {
        let c = TriaxialMaxwell::new(0.1);
        let u = Control::planar(0.7, 0.05, -0.03);
        let (a, b) = (c.actuation(&u), c.actuation(&u.flipped()));
        assert!((a.pull + b.pull).norm() < 1e-15);
        assert!((a.b_hat + b.b_hat).norm() < 1e-15);
        assert!((Control::planar(PI, 0.0, 0.0).flipped().theta).abs() < 1e-15);
    }

    #[test]
    fn clamp_flags_out_of_range_gradients() {
        let c = TriaxialMaxwell::new(0.1);
        let (u, flagged) = c.clamp(&Control::planar(0.0, 0.5, -0.05));
        assert!(flagged && u.grad == [0.1, -0.05]);
        assert!(!c.clamp(&Control::planar(0.0, 0.05, -0.05)).1);
    }

    #[test]
    fn clamp_flags_elevations_beyond_the_coils_range() {
        let tilted = Control {
            alpha: 0.5,
            ..Control::planar(0.0, 0.0, 0.0)
        };
        assert!(!TriaxialMaxwell::new(0.1).clamp(&tilted).1);
        let planar_set = TriaxialMaxwell::new(0.1).with_alpha_max_deg(0.0);
        let (u, flagged) = planar_set.clamp(&tilted);
        assert!(flagged && u.alpha == 0.0);
        assert_eq!(planar_set.alpha_max(), 0.0);
    }
}
