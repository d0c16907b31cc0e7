//! The vector dipole–dipole force.
//!
//! For point dipoles `m_i` at `P_i` and `m_j` at `P_j`, with `r = P_j − P_i`, `r̂ = r/|r|`,
//! the force on `j` from `i` is
//!
//! ```text
//! F_ij = 3μ0/(4π|r|⁴) · [ (m_i·r̂) m_j + (m_j·r̂) m_i + (m_i·m_j) r̂ − 5 (m_i·r̂)(m_j·r̂) r̂ ].
//! ```
//!
//! When both moments are aligned with the unit field direction `b̂` (`m_i = m_j = m b̂`), this is
//! `Ω/|r|⁴ · [ 2 (b̂·r̂) b̂ + (1 − 5 (b̂·r̂)²) r̂ ]` with `Ω = 3μ0 m²/(4π)`. Projected on `r̂` and on
//! the in-plane normal `ê_φ` it gives the seed's eq. (1):
//! `f_r = Ω/r⁴ (1 − 3 cos²α cos²ψ)`, `f_φ = Ω/r⁴ cos²α sin 2ψ`. A positive `f_r` pushes `j`
//! away from `i` (repulsion). The out-of-plane part is carried by the liquid–air interface.

use crate::math::{Vec2, Vec3};

/// The general 3D dipole–dipole force on `m_j` from `m_i`, in units of `3μ0/(4π)`
/// (moments in A·m², `r_ij = P_j − P_i` in any length unit `L`; the result is per `L⁴`).
pub fn dipole_force(m_i: Vec3, m_j: Vec3, r_ij: Vec3) -> Vec3 {
    let r2 = r_ij.norm_squared();
    let r = r2.sqrt();
    let rh = r_ij / r;
    let a = m_i.dot(&rh);
    let b = m_j.dot(&rh);
    (m_j * a + m_i * b + rh * (m_i.dot(&m_j) - 5.0 * a * b)) / (r2 * r2)
}

/// The force on agent `j` from agent `i` when both moments are aligned with the unit field
/// direction `b`, in units of `Ω = 3μ0 m²/(4π)`; `r_ij = P_j − P_i` is in BL.
///
/// This is [`dipole_force`] with `m_i = m_j = b`, written out for speed.
#[inline]
pub fn aligned_pair_force(r_ij: Vec3, b: Vec3) -> Vec3 {
    let r2 = r_ij.norm_squared();
    let r = r2.sqrt();
    let rh = r_ij / r;
    let c = b.dot(&rh);
    (b * (2.0 * c) + rh * (1.0 - 5.0 * c * c)) / (r2 * r2)
}

/// The in-plane version of [`aligned_pair_force`]: the (x, y) force on agent `j` from agent `i`
/// for a planar separation `r_ij`; the z component is dropped (carried by the interface).
#[inline]
pub fn aligned_pair_force_planar(r_ij: Vec2, b: Vec3) -> Vec2 {
    let r2 = r_ij.norm_squared();
    let r = r2.sqrt();
    let (rx, ry) = (r_ij.x / r, r_ij.y / r);
    let c = b.x * rx + b.y * ry;
    let k = 1.0 - 5.0 * c * c;
    let inv = 1.0 / (r2 * r2);
    Vec2::new(
        (2.0 * c * b.x + k * rx) * inv,
        (2.0 * c * b.y + k * ry) * inv,
    )
}

/// The elevation α_h (cos²α_h = 2/3, 35.26°) at which a field swept through in-plane angles
/// evenly cancels every aligned pair's force on average (docs/physics.md, "Teams of three and
/// more").
pub fn sweep_cancelling_elevation() -> f64 {
    (2.0f64 / 3.0).sqrt().acos()
}

/// Unit field direction for global in-plane angle `theta` and elevation `alpha` (radians).
/// An in-plane field (`alpha = ±0`) skips the elevation's sine and cosine, which are then
/// `(alpha, 1)` exactly.
#[inline]
pub fn field_direction(theta: f64, alpha: f64) -> Vec3 {
    let (st, ct) = theta.sin_cos();
    let (sa, ca) = if alpha == 0.0 {
        (alpha, 1.0)
    } else {
        alpha.sin_cos()
    };
    Vec3::new(ca * ct, ca * st, sa)
}

/// Closed-form radial and transverse force (seed's eq. 1) in units of `Ω/r⁴`, for local field
/// angle `psi` (between the field's in-plane projection and `r̂`) and elevation `alpha`.
pub fn radial_transverse(psi: f64, alpha: f64) -> (f64, f64) {
    let ca2 = alpha.cos().powi(2);
    (1.0 - 3.0 * ca2 * psi.cos().powi(2), ca2 * (2.0 * psi).sin())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::lift;

    /// Radial and transverse components of the vector force for a pair separated along `phi`.
    fn components(r: f64, phi: f64, psi: f64, alpha: f64) -> (f64, f64, f64) {
        let rh = Vec3::new(phi.cos(), phi.sin(), 0.0);
        let eph = Vec3::new(-phi.sin(), phi.cos(), 0.0);
        let f = aligned_pair_force(rh * r, field_direction(phi + psi, alpha));
        let s = r.powi(4);
        (f.dot(&rh) * s, f.dot(&eph) * s, f.z * s)
    }

    #[test]
    fn in_plane_direction_equals_the_general_formula() {
        for theta in [-3.0, -0.7, 0.0, 0.4, 2.9] {
            for alpha in [0.0, -0.0] {
                let b = field_direction(theta, alpha);
                let (sa, ca) = f64::sin_cos(alpha);
                let (st, ct) = f64::sin_cos(theta);
                let general = Vec3::new(ca * ct, ca * st, sa);
                assert_eq!(b.map(f64::to_bits), general.map(f64::to_bits));
            }
        }
    }

    #[test]
    fn radial_force_vanishes_at_magic_angle() {
        let magic = (1.0f64 / 3.0).sqrt().acos(); // 54.7356°
        assert!((magic.to_degrees() - 54.7356).abs() < 1e-4);
        for phi in [0.0, 0.7, -2.1] {
            let (fr, _, _) = components(2.0, phi, magic, 0.0);
            assert!(fr.abs() < 1e-12, "f_r = {fr}");
        }
    }

    #[test]
    fn radial_force_is_minus_two_and_plus_one_at_0_and_90() {
        let (fr0, ft0, _) = components(1.7, 0.3, 0.0, 0.0);
        let (fr90, ft90, _) = components(1.7, 0.3, std::f64::consts::FRAC_PI_2, 0.0);
        assert!((fr0 + 2.0).abs() < 1e-12 && ft0.abs() < 1e-12);
        assert!((fr90 - 1.0).abs() < 1e-12 && ft90.abs() < 1e-12);
    }

    #[test]
    fn max_transverse_is_half_max_radial() {
        let n = 20000;
        let (mut max_r, mut max_t) = (0.0f64, 0.0f64);
        for k in 0..n {
            let psi = std::f64::consts::PI * k as f64 / n as f64;
            let (fr, ft, _) = components(2.5, 1.1, psi, 0.0);
            max_r = max_r.max(fr.abs());
            max_t = max_t.max(ft.abs());
        }
        assert!((max_r - 2.0).abs() < 1e-9);
        assert!(
            (max_t / max_r - 0.5).abs() < 1e-6,
            "ratio {}",
            max_t / max_r
        );
    }

    #[test]
    fn general_3d_formula_equals_planar_closed_form() {
        for &alpha in &[0.0, 0.3, -0.9] {
            for k in 0..36 {
                let psi = -3.0 + k as f64 * 0.17;
                let (fr, ft, _) = components(1.9, 0.4, psi, alpha);
                let (cr, ct) = radial_transverse(psi, alpha);
                assert!((fr - cr).abs() < 1e-12 && (ft - ct).abs() < 1e-12);
                // the general formula with equal moments agrees with the aligned one
                let b = field_direction(0.4 + psi, alpha);
                let r = Vec3::new(1.9 * 0.4f64.cos(), 1.9 * 0.4f64.sin(), 0.0);
                assert!((dipole_force(b, b, r) - aligned_pair_force(r, b)).norm() < 1e-13);
                let planar = aligned_pair_force_planar(Vec2::new(r.x, r.y), b);
                let full = aligned_pair_force(r, b);
                assert!((lift(planar) - Vec3::new(full.x, full.y, 0.0)).norm() < 1e-13);
            }
        }
    }

    #[test]
    fn forces_are_equal_and_opposite_for_three_agents() {
        let p = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.1, 0.4, 0.0),
            Vec3::new(0.7, -1.8, 0.0),
        ];
        let m = [
            Vec3::new(0.3, 0.9, 0.1),
            Vec3::new(-0.5, 0.2, 0.0),
            Vec3::new(0.8, -0.1, 0.4),
        ];
        for i in 0..3 {
            for j in 0..3 {
                if i != j {
                    let fij = dipole_force(m[i], m[j], p[j] - p[i]);
                    let fji = dipole_force(m[j], m[i], p[i] - p[j]);
                    assert!((fij + fji).norm() < 1e-14, "pair ({i},{j})");
                }
            }
        }
    }
}
