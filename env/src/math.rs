//! Vector types and small angle helpers shared by the whole workspace.

/// A 2D vector in body lengths (BL), world frame: x right, y up.
pub type Vec2 = nalgebra::Vector2<f64>;

/// A 3D vector (used for field directions and the full 3D dipole force).
pub type Vec3 = nalgebra::Vector3<f64>;

/// The largest team the fixed-size integrator buffers accept.
pub const MAX_AGENTS: usize = 8;

/// Wraps an angle to the interval (−π, π].
pub fn wrap_angle(a: f64) -> f64 {
    let two_pi = std::f64::consts::TAU;
    let mut w = a.rem_euclid(two_pi);
    if w > std::f64::consts::PI {
        w -= two_pi;
    }
    w
}

/// Lifts a planar vector into 3D with z = 0.
pub fn lift(v: Vec2) -> Vec3 {
    Vec3::new(v.x, v.y, 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn wrap_angle_lands_in_half_open_interval() {
        assert!((wrap_angle(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(-PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(0.5) - 0.5).abs() < 1e-15);
        assert!((wrap_angle(-0.5 - 4.0 * PI) + 0.5).abs() < 1e-12);
    }
}
