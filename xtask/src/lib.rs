//! # xtask
//!
//! The project's own maintenance, kept out of the `magbench` library so that no plugin binary
//! or Python extension links it:
//!
//! - [`docs`]: the book's measured figures (`cargo xtask measure` regenerates
//!   `docs/measured/NAME.md`, `cargo xtask stale` names the files whose sources changed);
//! - [`fuzz`]: the input formats under fuzzing, for the `cargo fuzz` targets in `fuzz/` and the
//!   mutation tests of `cli/tests/`;
//! - [`lines`]: each crate's share of the project's non-test lines (`cargo xtask lines`).

#![warn(missing_docs)]

pub mod docs;
pub mod fuzz;
pub mod lines;
