//! The one input checker: every input format (scenario, experiment, plan, rig and preset files)
//! and every command-line number goes through it, so that every message reads alike:
//! `FILE: FIELD: REASON (line N)`, with `FIELD` a full path such as `planners[0].k` or
//! `world.obstacles[2].polygon[5]`.
//!
//! - [`file`]: reading a file (regular files only, bounded in size) and parsing TOML or JSON
//!   into a serde type that denies unknown keys, with the field path of every failure;
//! - [`suggest`]: "did you mean" for an unknown key or name;
//! - [`fixed`]: arrays of exactly their size (`[x, y]`, never `[x, y, z]`);
//! - [`bounds`]: number checks, and the bounds chosen to keep every accepted input within a
//!   time and [`MEMORY_BUDGET_BYTES`];
//! - [`Rejection`] and [`InputChecks`]: a field and a reason, and the file they belong to.

pub mod bounds;
pub mod file;
pub mod fixed;
mod rejection;
pub mod suggest;

pub use bounds::{Bound, MEMORY_BUDGET_BYTES};
pub use file::{field_line, parse_json, parse_toml, read_text};
pub use fixed::Fixed;
pub use rejection::{InputChecks, Rejection};
