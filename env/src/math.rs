//! Vector types and small angle helpers shared by the whole workspace.

/// A 2D vector in body lengths (BL), world frame: x right, y up.
pub type Vec2 = nalgebra::Vector2<f64>;

/// A 3D vector (used for field directions and the full 3D dipole force).
pub type Vec3 = nalgebra::Vector3<f64>;

/// The largest team the fixed-size integrator buffers accept.
pub const MAX_AGENTS: usize = 16;

/// Wraps an angle to the interval (−π, π].
pub fn wrap_angle(a: f64) -> f64 {
    let two_pi = std::f64::consts::TAU;
    let mut w = a.rem_euclid(two_pi);
    if w > std::f64::consts::PI {
        w -= two_pi;
    }
    w
}

/// The centroid (mean position) of a team's state; zero for an empty one.
pub fn centroid(state: &[Vec2]) -> Vec2 {
    state.iter().sum::<Vec2>() / state.len().max(1) as f64
}

/// Sum of squared distances between the shapes (positions about the centroid) of `a` and `b`.
pub fn shape_distance(a: &[Vec2], b: &[Vec2]) -> f64 {
    let (ca, cb) = (centroid(a), centroid(b));
    a.iter()
        .zip(b)
        .map(|(p, q)| ((p - ca) - (q - cb)).norm_squared())
        .sum()
}

/// The largest distance between matched agents of two states (BL); NaN when a position is not
/// a number.
pub fn max_agent_distance(a: &[Vec2], b: &[Vec2]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, |m: f64, d| {
            if m.is_nan() || d.is_nan() {
                f64::NAN
            } else {
                m.max(d)
            }
        })
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

    #[test]
    fn centroid_is_the_mean_and_zero_for_no_agents() {
        let s = [
            Vec2::new(0.0, 0.0),
            Vec2::new(2.0, 4.0),
            Vec2::new(1.0, -1.0),
        ];
        assert_eq!(centroid(&s), Vec2::new(1.0, 1.0));
        assert_eq!(centroid(&[]), Vec2::zeros());
    }
}
