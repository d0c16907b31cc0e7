//! The exact flow of a nominal pair under a constant planar command (docs/physics.md
//! "Physics → The exact flow of a pair").
//!
//! For two identical agents (equal moment and mobility) under a constant field angle θ_B,
//! elevation 0 and gradient, the centre of mass moves at the constant pull velocity and the
//! separation follows a closed-form orbit ([`Orbit`]). One evaluation costs the same for any
//! duration: a polynomial and a few Newton steps, no integration. [`PairEdge`] packages an
//! edge: positions at any time, the separation's range and first exit from the proximity
//! range, a speed bound for conservative advancement, and the path length.

mod coeffs;
mod edge;
mod orbit;
mod quadrature;
mod special;

pub use edge::{PATH_TOLERANCE, PairEdge, PairStart, SpeedSummary};
pub use orbit::{Orbit, OrbitPoint};
pub use special::{g, g_complement};

/// `G(π/2) = ½ B(5/2, 5/4)`: the orbit-time function over a quarter turn.
pub const G_QUARTER: f64 = special::G_TOTAL;
