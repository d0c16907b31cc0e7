//! # magbench-plot
//!
//! magbench's charts, drawn from plain data: the palette, styles and legends, bar and grid
//! charts, the world view of a scenario with its paths, animations, and export to PNG, SVG and
//! (with the `print` feature) PDF. What the charts show is the caller's: the harness draws a
//! results folder's figures and the paper figures with it.

#![warn(missing_docs)]

pub mod plot;
pub use magbench_analysis::{stats, units};
