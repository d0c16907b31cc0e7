//! The pixel ↔ world (BL) calibration: scale, origin, orientation.

use magbench_env::Vec2;

/// An image pixel position `(column, row)`, sub-pixel, with pixel centres at integers.
pub type Px = Vec2;

/// A similarity map between world coordinates (BL, y up) and image pixels.
///
/// `pixel = origin + s · R(θ) · F · world`, where `s` is pixels per BL, `R(θ)` a rotation and
/// `F = diag(1, −1)` when image rows grow downward (`flip_y`).
#[derive(Debug, Clone, PartialEq)]
pub struct PixelMap {
    /// Pixels per BL.
    pub px_per_bl: f64,
    /// Pixel position of the world origin.
    pub origin_px: [f64; 2],
    /// Angle of the world x axis in the image (radians).
    pub rotation: f64,
    /// True when image rows grow downward while world y grows upward.
    pub flip_y: bool,
}

impl PixelMap {
    /// A map from its four parameters.
    pub fn new(px_per_bl: f64, origin_px: [f64; 2], rotation: f64, flip_y: bool) -> Self {
        Self {
            px_per_bl,
            origin_px,
            rotation,
            flip_y,
        }
    }

    fn flip(&self) -> f64 {
        if self.flip_y { -1.0 } else { 1.0 }
    }

    /// World (BL) to pixel.
    pub fn to_px(&self, w: Vec2) -> Px {
        let (s, c) = self.rotation.sin_cos();
        let (x, y) = (w.x, self.flip() * w.y);
        Vec2::new(
            self.origin_px[0] + self.px_per_bl * (c * x - s * y),
            self.origin_px[1] + self.px_per_bl * (s * x + c * y),
        )
    }

    /// Pixel to world (BL).
    pub fn to_world(&self, p: Px) -> Vec2 {
        let (s, c) = self.rotation.sin_cos();
        let (dx, dy) = (
            (p.x - self.origin_px[0]) / self.px_per_bl,
            (p.y - self.origin_px[1]) / self.px_per_bl,
        );
        Vec2::new(c * dx + s * dy, self.flip() * (-s * dx + c * dy))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_orientation() {
        let m = PixelMap::new(10.0, [10.0, 330.0], 0.0, true);
        assert_eq!(m.to_px(Vec2::new(0.0, 0.0)), Vec2::new(10.0, 330.0));
        assert_eq!(m.to_px(Vec2::new(1.0, 1.0)), Vec2::new(20.0, 320.0));
        let r = PixelMap::new(12.5, [3.0, -7.0], 0.3, true);
        let w = Vec2::new(4.2, -1.7);
        assert!((r.to_world(r.to_px(w)) - w).norm() < 1e-12);
        let r = PixelMap::new(12.5, [3.0, -7.0], -2.0, false);
        assert!((r.to_world(r.to_px(w)) - w).norm() < 1e-12);
    }
}
