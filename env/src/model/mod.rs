//! Overdamped kinematics, the fixed-step integrator, the exact pair flow and the deterministic
//! planning model.
//!
//! The planning model is the seed's eq. (3): agents move with (pair forces + pull)/σ. Two
//! identical agents under a planar command move by the exact flow ([`pair_flow`]); every other
//! motion is integrated by adaptive Dormand–Prince 5(4) ([`dp5_solve`]) or, by choice of
//! [`Flow`], by classic RK4 at the preset's fixed step `dt_s` (1/120 s by default).
//! A plan replays exactly only through this same arithmetic; see [`PlanningModel`].

mod dopri;
mod integrator;
mod kinematics;
pub mod pair_flow;
mod planning;
pub mod steer;
mod team_field;

pub use dopri::{
    Dp5Grid, Dp5Stats, ErrorBudget, REFERENCE_DURATION_S, TOLERANCE_BL, dp5_solve, dp5_solve_many,
};
pub use integrator::{rk4_step, step_schedule};
pub use kinematics::Kinematics;
pub use pair_flow::PairEdge;
pub use planning::{Flow, PlanningModel};
pub use steer::{OrbitSteer, SteerEdge, SteerLimits, orbit_steer, steer_pair};
pub use team_field::TeamField;

use crate::coil::Control;
use crate::math::Vec2;

/// Propagates a state under a constant control (OMPL's StatePropagator: it only propagates).
pub trait Propagator: Send + Sync {
    /// Integrates `start` under `u` for `duration` seconds into `out`, calling `visit` on every
    /// integration sample after the start (the last is the end state). Stops early and returns
    /// false as soon as `visit` returns false.
    fn propagate_visit(
        &self,
        start: &[Vec2],
        u: &Control,
        duration: f64,
        out: &mut [Vec2],
        visit: &mut dyn FnMut(&[Vec2]) -> bool,
    ) -> bool;

    /// Integrates `start` under `u` for `duration` seconds into `out`.
    fn propagate(&self, start: &[Vec2], u: &Control, duration: f64, out: &mut [Vec2]) {
        self.propagate_visit(start, u, duration, out, &mut |_| true);
    }

    /// The motion in closed form, when this propagator solves it exactly (a checker then
    /// checks the curve itself instead of the samples).
    fn closed_form(&self, start: &[Vec2], u: &Control) -> Option<PairEdge> {
        let _ = (start, u);
        None
    }

    /// The spacing of the visited samples (s): the fixed integration step.
    fn step(&self) -> f64;
}
