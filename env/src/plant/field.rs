//! The field each agent feels, from the coil's (lagging) output, the coil's calibration
//! errors, the ambient field and the gradient's non-uniformity.
//!
//! The coil is the tri-axial Helmholtz–Maxwell set of [`crate::coil::TriaxialMaxwell`]: the
//! command sets the uniform field `B₀ b̂(θ_B, α)` and the diagonal gradient
//! `diag(G_x, G_y, −G_x − G_y)`. The five coil outputs (three field axes, two gradient axes)
//! are what the coil-dynamics term delays.

use nalgebra::{Matrix3, Vector2};
use rand_chacha::ChaCha8Rng;

use super::DisturbancePreset;
use super::streams::{Stream, normal, stream};
use crate::coil::Control;
use crate::math::{Vec2, Vec3};
use crate::physics::{PhysicalParams, field_direction};

/// The five coil outputs: field x, y, z (T), gradient x, y (T/m).
pub type CoilOutput = [f64; 5];

/// The field model of one run: its drawn calibration, ambient field and coil centre.
#[derive(Debug, Clone)]
pub struct FieldModel {
    /// Nominal field magnitude B₀ (T).
    pub b0: f64,
    /// Per-run rotation of the coil frame (radians).
    pub bias: f64,
    /// Standard deviation of the per-step jitter (radians).
    pub jitter: f64,
    field_gain: Matrix3<f64>,
    gradient_gain: [f64; 2],
    crosstalk: [f64; 2],
    ambient: Vec3,
    nonuniform: bool,
    centre_offset: Vec2,
    bl_m: f64,
}

impl FieldModel {
    /// Draws the field model of the run seeded with `seed`.
    pub fn draw(preset: &DisturbancePreset, p: &PhysicalParams, seed: u64) -> Self {
        let b0 = p.field_mt * 1e-3;
        let drawn_bias =
            preset.field_error.bias_sd() * normal(&mut stream(seed, Stream::FieldBias));
        let bias = preset.fitted.field_bias().unwrap_or(drawn_bias);
        let cal = &preset.coil_calibration;
        let (mut field_gain, mut gradient_gain, mut crosstalk) =
            (Matrix3::identity(), [1.0; 2], [0.0; 2]);
        if cal.enabled {
            let rng = &mut stream(seed, Stream::Calibration);
            let mut n = |sd: f64| sd * normal(rng);
            let (gx, gy, gz) = (
                1.0 + n(cal.axis_gain_error),
                1.0 + n(cal.axis_gain_error),
                1.0 + n(cal.axis_gain_error),
            );
            let skew = n(cal.axis_skew_deg.to_radians());
            // columns: the real directions of the x, y, z coil axes, scaled by their gains
            field_gain = Matrix3::new(
                gx,
                -gy * skew.sin(),
                0.0,
                0.0,
                gy * skew.cos(),
                0.0,
                0.0,
                0.0,
                gz,
            );
            let off = cal.gradient_gain_offset;
            gradient_gain = [
                1.0 + off[0] + n(cal.gradient_gain_error),
                1.0 + off[1] + n(cal.gradient_gain_error),
            ];
            crosstalk = [n(cal.gradient_crosstalk), n(cal.gradient_crosstalk)];
        }
        if let Some(g) = preset.fitted.gradient_gain() {
            gradient_gain = g;
        }
        let ambient = if preset.ambient_field.enabled {
            let a = rand::RngExt::random_range(
                &mut stream(seed, Stream::Ambient),
                0.0..std::f64::consts::TAU,
            );
            Vec3::new(a.cos(), a.sin(), 0.0) * (preset.ambient_field.field_ut * 1e-6)
        } else {
            Vec3::zeros()
        };
        let nu = &preset.nonuniform_field;
        let centre_offset = if nu.enabled {
            let rng = &mut stream(seed, Stream::Nonuniform);
            let s = nu.centre_offset_mm * 1e-3 / p.bl_m();
            Vec2::new(normal(rng), normal(rng)) * s
        } else {
            Vec2::zeros()
        };
        Self {
            b0,
            bias,
            jitter: preset.field_error.jitter_sd(),
            field_gain,
            gradient_gain,
            crosstalk,
            ambient,
            nonuniform: nu.enabled,
            centre_offset,
            bl_m: p.bl_m(),
        }
    }

    /// The coil outputs a (clamped) command asks for, with the run's bias and a jitter `j`
    /// (radians) added to its angle.
    pub fn target(&self, u: &Control, j: f64) -> CoilOutput {
        let b = field_direction(u.theta + self.bias + j, u.alpha) * self.b0;
        [b.x, b.y, b.z, u.grad[0], u.grad[1]]
    }

    /// The uniform part of the realised field (T) and the realised gradient tensor (T/m) of
    /// the coil outputs `c`.
    pub fn realise(&self, c: &CoilOutput) -> (Vec3, Matrix3<f64>) {
        let b = self.field_gain * Vec3::new(c[0], c[1], c[2]) + self.ambient;
        let gxx = self.gradient_gain[0] * c[3];
        let gyy = self.gradient_gain[1] * c[4];
        let gxy = self.crosstalk[0] * c[3] + self.crosstalk[1] * c[4];
        let g = Matrix3::new(gxx, gxy, 0.0, gxy, gyy, 0.0, 0.0, 0.0, -(gxx + gyy));
        (b, g)
    }

    /// The field (T) at `p` (BL) of a realised uniform field `b` and gradient `g`, with the
    /// coil centred on `centre` (BL) before the run's placement offset.
    pub fn at(&self, b: &Vec3, g: &Matrix3<f64>, centre: Vec2, p: Vec2) -> Vec3 {
        if !self.nonuniform {
            return *b;
        }
        let d = (p - centre - self.centre_offset) * self.bl_m;
        let gd = g.fixed_view::<2, 2>(0, 0) * Vector2::new(d.x, d.y);
        b + Vec3::new(gd.x, gd.y, 0.0)
    }

    /// True when the field is the same everywhere and exactly the command.
    pub fn is_exact(&self) -> bool {
        !self.nonuniform
            && self.field_gain == Matrix3::identity()
            && self.gradient_gain == [1.0; 2]
            && self.crosstalk == [0.0; 2]
            && self.ambient == Vec3::zeros()
    }

    /// A jitter sample (radians) from the jitter stream.
    pub fn jitter_sample(&self, rng: &mut ChaCha8Rng) -> f64 {
        if self.jitter > 0.0 {
            self.jitter * normal(rng)
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::CoilCalibration;

    #[test]
    fn a_fixed_gradient_offset_scales_each_axis() {
        let preset = DisturbancePreset {
            coil_calibration: CoilCalibration {
                enabled: true,
                gradient_gain_offset: [0.05, -0.1],
                ..Default::default()
            },
            ..DisturbancePreset::ideal()
        };
        let f = FieldModel::draw(&preset, &PhysicalParams::default(), 3);
        let (_, g) = f.realise(&[0.0, 0.0, 0.0, 1.0, 1.0]);
        assert!((g[(0, 0)] - 1.05).abs() < 1e-12, "{g}");
        assert!((g[(1, 1)] - 0.9).abs() < 1e-12, "{g}");
        assert!(!f.is_exact());
    }
}
