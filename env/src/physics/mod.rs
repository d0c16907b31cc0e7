//! Magnetic physics of aligned spheres: the dipole–dipole force, the local pair view and the
//! physical preset that turns SI quantities into the normalised BL-and-seconds model.

pub mod dipole;
pub mod drag;
pub mod local;
pub mod params;

pub use dipole::{
    aligned_pair_force, dipole_force, field_direction, radial_transverse,
    sweep_cancelling_elevation,
};
pub use drag::DragFactors;
pub use local::LocalView;
pub use params::{MAX_FIELD_MT, PhysicalOverrides, PhysicalParams};
