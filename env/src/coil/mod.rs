//! What the coil applies, behind the [`Coil`] trait.
//!
//! A [`Control`] is the command a plan or a tracker sends: the global in-plane field angle θ_B,
//! its elevation α and a pulling-gradient command. A coil turns it into an [`Actuation`]: the
//! unit field direction (which all moments follow) and the pulling force per unit moment.

mod control;
mod elevation;
mod triaxial;

pub use control::Control;
pub use elevation::{
    COIL_ALPHA_MAX_DEG, DEFAULT_ALPHA_MAX_DEG, NEEDS_INTERFACE, Planar, elevation_params,
};
pub use triaxial::TriaxialMaxwell;

use crate::math::Vec3;

/// What the coil produces for a command: the field direction and the pull per unit moment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Actuation {
    /// Unit field direction `b̂`; every moment is aligned with it.
    pub b_hat: Vec3,
    /// Pulling force per unit moment `(b̂·∇)B` (T/m); the force on a moment `m` is `m × pull`.
    pub pull: Vec3,
}

/// A coil geometry: maps a [`Control`] to the field and gradient it realises.
///
/// A tri-axial Helmholtz–Maxwell set ([`TriaxialMaxwell`]) is the default; an 8-coil actuation
/// matrix would implement the same trait.
pub trait Coil: Send + Sync + std::fmt::Debug {
    /// Short name of the geometry.
    fn name(&self) -> &str;
    /// Largest gradient command per axis (T/m).
    fn gradient_limit(&self) -> f64;
    /// Largest field elevation |α| it can set (rad).
    fn alpha_max(&self) -> f64;
    /// The command brought within the coil's limits, and whether anything had to be clamped.
    fn clamp(&self, u: &Control) -> (Control, bool);
    /// The field direction and pull a (within-limits) command produces.
    fn actuation(&self, u: &Control) -> Actuation;

    /// The actuation of `u`'s field with zero gradient commands, and the pull's change per unit
    /// gradient command along x and along y: the pull is linear in the gradient commands for a
    /// given field. The default probes [`Coil::actuation`] three times.
    fn pull_map(&self, u: &Control) -> (Actuation, [Vec3; 2]) {
        let at = |gx: f64, gy: f64| {
            self.actuation(&Control {
                grad: [gx, gy],
                ..*u
            })
        };
        let zero = at(0.0, 0.0);
        let (x, y) = (at(1.0, 0.0), at(0.0, 1.0));
        (zero, [x.pull - zero.pull, y.pull - zero.pull])
    }
}
