//! Maps: a walled rectangle with polygon (convex or not) and circle obstacles, in BL.

mod polygon;

pub use polygon::{MAX_POLYGON_VERTICES, PolygonError, check_polygon, signed_area};

use crate::math::Vec2;

/// An obstacle in the world frame (BL).
#[derive(Debug, Clone, PartialEq)]
pub enum Obstacle {
    /// A simple polygon, convex or not, given by its vertices in order (either orientation).
    Polygon(Vec<Vec2>),
    /// A disk.
    Circle {
        /// Centre (BL).
        center: Vec2,
        /// Radius (BL).
        radius: f64,
    },
}

/// A world: the rectangle `[0, width] × [0, height]` whose edges are walls, plus obstacles.
#[derive(Debug, Clone, PartialEq)]
pub struct World {
    /// Width along x (BL).
    pub width: f64,
    /// Height along y (BL).
    pub height: f64,
    /// Obstacles inside the rectangle.
    pub obstacles: Vec<Obstacle>,
}

impl World {
    /// True when `p` lies in the rectangle `[0, width] × [0, height]`.
    pub fn contains(&self, p: Vec2) -> bool {
        (0.0..=self.width).contains(&p.x) && (0.0..=self.height).contains(&p.y)
    }

    /// The same rectangle with another set of obstacles (a map switch).
    pub fn with_obstacles(&self, obstacles: Vec<Obstacle>) -> World {
        World {
            width: self.width,
            height: self.height,
            obstacles,
        }
    }
}
