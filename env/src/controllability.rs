//! Numerical Lie-bracket (LARC) analysis of the local two-agent model.
//!
//! Local model `x = (r, φ, ψ)`, `ẋ = f(x) + g u` with `g = ∂/∂ψ` and the drift
//! `f = (ṙ, φ̇, 0)` evaluated from the full vector physics ([`Kinematics`]) of two agents at
//! separation `r`, heading `φ` and field angle `θ_B = φ + ψ`. With the bracket
//! `[X, Y] = (DY) X − (DX) Y`, the closed form (derived in docs/physics.md, "Controllability") is
//!
//! ```text
//! f          = ( κ(1 − 3cos²ψ)/r⁴,  κ sin2ψ/r⁵,  0 )
//! [f, g]     = −κ ( 3 sin2ψ/r⁴,  2 cos2ψ/r⁵,  0 )
//! [f, [f,g]] = ( 0,  −10 κ² (1 + cos²ψ)/r¹⁰,  0 )
//! det Δ      = 15 κ³ sin2ψ (3 + cos2ψ) / r¹⁴
//! ```
//!
//! so `Δ = [g, [f,g], [f,[f,g]]]` has rank 3 unless sin 2ψ = 0, i.e. ψ ∈ {0°, 90°} mod 90°,
//! where it drops to 2. [`larc`] computes Δ by central finite differences of the physics,
//! independently of the closed form, and [`closed_form`] gives the formula to compare with.

use nalgebra::{Matrix3, Vector3};

use crate::coil::Actuation;
use crate::math::Vec2;
use crate::model::Kinematics;
use crate::physics::{LocalView, field_direction};

/// The LARC test at one `(r, ψ)`.
#[derive(Debug, Clone)]
pub struct LarcReport {
    /// Separation (BL).
    pub r: f64,
    /// Local field angle (radians).
    pub psi: f64,
    /// Δ = [g, [f,g], [f,[f,g]]] by finite differences of the physics (columns).
    pub delta: Matrix3<f64>,
    /// Numerical rank of Δ (singular values relative to the largest, after column scaling).
    pub rank: usize,
    /// Smallest singular value of Δ with unit-length columns: the LARC margin in [0, 1].
    pub margin: f64,
    /// Determinant of Δ.
    pub det: f64,
}

/// The drift `f(r, φ, ψ) = (ṙ, φ̇, 0)` from the vector physics of two agents (no pull).
pub fn drift(kin: &Kinematics, x: Vector3<f64>) -> Vector3<f64> {
    let (r, phi, psi) = (x[0], x[1], x[2]);
    let p = LocalView::new(0.0, 0.0, r, phi).to_pair();
    let act = Actuation {
        b_hat: field_direction(phi + psi, 0.0),
        pull: nalgebra::Vector3::zeros(),
    };
    let mut v = [Vec2::zeros(); 2];
    kin.velocities(&p, &act, &mut v);
    let rel = v[1] - v[0];
    let rh = Vec2::new(phi.cos(), phi.sin());
    let eph = Vec2::new(-phi.sin(), phi.cos());
    Vector3::new(rel.dot(&rh), rel.dot(&eph) / r, 0.0)
}

/// Jacobian of a vector field by central differences with step `h`.
fn jacobian(field: &dyn Fn(Vector3<f64>) -> Vector3<f64>, x: Vector3<f64>, h: f64) -> Matrix3<f64> {
    let mut j = Matrix3::zeros();
    for k in 0..3 {
        let mut e = Vector3::zeros();
        e[k] = h;
        j.set_column(k, &((field(x + e) - field(x - e)) / (2.0 * h)));
    }
    j
}

/// Lie bracket `[X, Y](x) = DY·X − DX·Y` by central differences.
fn bracket(
    xf: &dyn Fn(Vector3<f64>) -> Vector3<f64>,
    yf: &dyn Fn(Vector3<f64>) -> Vector3<f64>,
    x: Vector3<f64>,
    h: f64,
) -> Vector3<f64> {
    jacobian(yf, x, h) * xf(x) - jacobian(xf, x, h) * yf(x)
}

/// Δ = [g, [f,g], [f,[f,g]]] at `(r, ψ)` by finite differences, with its rank and margin.
pub fn larc(kin: &Kinematics, r: f64, psi: f64) -> LarcReport {
    let x = Vector3::new(r, 0.3, psi);
    let f = |x: Vector3<f64>| drift(kin, x);
    let g = |_: Vector3<f64>| Vector3::new(0.0, 0.0, 1.0);
    let fg = |x: Vector3<f64>| bracket(&f, &g, x, 1e-5);
    let ffg = bracket(&f, &fg, x, 1e-4);
    let delta = Matrix3::from_columns(&[g(x), fg(x), ffg]);
    let (rank, margin) = rank_and_margin(&delta);
    LarcReport {
        r,
        psi,
        delta,
        rank,
        margin,
        det: delta.determinant(),
    }
}

/// Numerical rank and smallest singular value of `m` after scaling its columns to unit length.
pub fn rank_and_margin(m: &Matrix3<f64>) -> (usize, f64) {
    let mut unit = *m;
    for k in 0..3 {
        let n = unit.column(k).norm();
        if n > 0.0 {
            unit.set_column(k, &(unit.column(k) / n));
        }
    }
    let sv = unit.singular_values();
    let max = sv.max();
    let rank = sv.iter().filter(|s| **s > 1e-6 * max).count();
    (rank, sv.min())
}

/// The closed-form Δ for relative-motion constant κ (see the module documentation).
pub fn closed_form(kappa: f64, r: f64, psi: f64) -> Matrix3<f64> {
    let (s2, c2, c) = ((2.0 * psi).sin(), (2.0 * psi).cos(), psi.cos());
    Matrix3::from_columns(&[
        Vector3::new(0.0, 0.0, 1.0),
        Vector3::new(
            -3.0 * kappa * s2 / r.powi(4),
            -2.0 * kappa * c2 / r.powi(5),
            0.0,
        ),
        Vector3::new(0.0, -10.0 * kappa * kappa * (1.0 + c * c) / r.powi(10), 0.0),
    ])
}

/// The achievable relative velocity `(ṙ, r φ̇)` in units of κ/r⁴ at local angle ψ:
/// `(1 − 3cos²ψ, sin 2ψ)`, an ellipse centred at (−½, 0) with semi-axes 3/2 and 1.
pub fn velocity_ellipse(psi: f64) -> (f64, f64) {
    (1.0 - 3.0 * psi.cos().powi(2), (2.0 * psi).sin())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::physics::PhysicalParams;

    /// The nominal kinematics and κ of the default parameters.
    pub(crate) fn kin() -> (Kinematics, f64) {
        let p = PhysicalParams::default();
        (Kinematics::nominal(&p), p.kappa())
    }

    #[test]
    fn numerical_brackets_match_closed_form() {
        let (k, kappa) = kin();
        for &r in &[1.5, 2.0, 3.5] {
            for d in [-80.0, -54.7356, -30.0, -5.0, 10.0, 45.0, 60.0, 85.0f64] {
                let psi = d.to_radians();
                let rep = larc(&k, r, psi);
                let cf = closed_form(kappa, r, psi);
                for c in 0..3 {
                    let scale = cf.column(c).norm().max(1e-300);
                    let err = (rep.delta.column(c) - cf.column(c)).norm() / scale;
                    assert!(err < 1e-5, "r={r} ψ={d}° column {c}: relative error {err}");
                }
            }
        }
    }

    #[test]
    fn rank_three_except_at_multiples_of_90_degrees() {
        let (k, _) = kin();
        for step in -24..=24 {
            let d = step as f64 * 7.5;
            let rep = larc(&k, 2.0, d.to_radians());
            let singular = (d / 90.0).fract().abs() < 1e-12;
            if singular {
                assert_eq!(rep.rank, 2, "ψ = {d}°: rank {}", rep.rank);
                assert!(rep.margin < 1e-6);
            } else {
                assert_eq!(rep.rank, 3, "ψ = {d}°: rank {}", rep.rank);
            }
        }
    }

    #[test]
    fn velocity_set_is_an_ellipse_around_the_origin() {
        for k in 0..360 {
            let (x, y) = velocity_ellipse((k as f64).to_radians());
            let e = ((x + 0.5) / 1.5).powi(2) + y * y;
            assert!((e - 1.0).abs() < 1e-12);
        }
        // the origin is strictly inside
        let e0 = (0.5f64 / 1.5).powi(2);
        assert!(e0 < 1.0);
        // and the physics traces that ellipse: (ṙ, r φ̇) r⁴/κ
        let (k, kappa) = kin();
        for d in [0.0, 33.0, 54.7356, 90.0, 140.0f64] {
            let psi = d.to_radians();
            let f = drift(&k, Vector3::new(2.0, 0.0, psi));
            let (x, y) = velocity_ellipse(psi);
            assert!((f[0] * 16.0 / kappa - x).abs() < 1e-12);
            assert!((f[1] * 2.0 * 16.0 / kappa - y).abs() < 1e-12);
        }
    }
}
