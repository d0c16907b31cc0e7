//! # magbench-env
//!
//! The physics and the world of magbench, in one place:
//!
//! - [`physics`]: the vector dipole–dipole force between aligned magnetic spheres, the local
//!   pair view `(x_c, y_c, r, φ)` and the physical preset that maps body lengths (BL) to SI;
//! - [`coil`]: what a coil can apply (field angle, elevation, pulling gradient) behind [`coil::Coil`];
//! - [`model`]: overdamped kinematics, the fixed-step integrator and the deterministic planning model;
//! - [`plant`]: the simulated plant: presets as data (`presets/`), one term per file (coil and
//!   magnet lag, field errors and non-uniformity, heterogeneity, hydrodynamic interaction,
//!   capillarity, flow, Brownian motion) and the camera;
//! - [`world`] and [`collision`]: maps, parry2d collision and the validity checker;
//! - [`input`]: the one input checker (regular files, bounded reads, TOML and JSON with field
//!   path and line, did-you-mean, exact-size arrays, bounds with their reasons);
//! - [`params`]: parameters declared once ([`declare_params!`]), for planners and trackers;
//! - [`registry`]: components by name (planners, trackers, rigs, scenario families), one
//!   [`registry::Registry`] shape for all;
//! - [`scenario`]: the TOML scenario format, its validation and the built-in scenarios;
//! - [`controllability`]: the numerical Lie-bracket (LARC) tool;
//! - [`team_symmetry`] and [`team_spin`]: the invariant set of every team, and the formations no
//!   field turns.
//!
//! Lengths are in body lengths (BL = one agent diameter) and times in seconds everywhere.

#![warn(missing_docs)]

pub mod coil;
pub mod collision;
pub mod controllability;
pub mod error;
pub mod input;
pub mod math;
pub mod model;
pub mod params;
pub mod physics;
pub mod plant;
pub mod registry;
pub mod scenario;
pub mod team_controllability;
pub mod team_spin;
pub mod team_symmetry;
pub mod world;

pub use coil::{Actuation, Coil, Control, TriaxialMaxwell};
pub use collision::{CollisionWorld, ValidityChecker};
pub use error::InputError;
pub use math::{MAX_AGENTS, Vec2, Vec3};
pub use model::{PlanningModel, Propagator};
pub use physics::{LocalView, PhysicalParams};
pub use scenario::{Goal, Leg, Scenario};
pub use world::{Obstacle, World};
