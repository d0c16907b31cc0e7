//! Collision: parry2d shapes and queries behind [`CollisionWorld`], the configuration and
//! motion checks behind [`ValidityChecker`], and conservative advancement ([`advance`]) for
//! motions known in closed form.
//!
//! parry2d-f64 0.31 works in glam vectors; the conversion from the workspace's nalgebra
//! [`Vec2`](crate::math::Vec2) lives here only ([`to_parry`]).

pub mod advance;
pub mod grid;
mod shapes;
mod validity;

pub use shapes::CollisionWorld;
pub use validity::ValidityChecker;

use crate::math::Vec2;

/// The one conversion into parry's vector type.
#[inline]
pub(crate) fn to_parry(v: Vec2) -> parry2d_f64::math::Vector {
    parry2d_f64::math::Vector::new(v.x, v.y)
}

/// The one conversion out of parry's vector type.
#[inline]
pub(crate) fn from_parry(v: parry2d_f64::math::Vector) -> Vec2 {
    Vec2::new(v.x, v.y)
}
