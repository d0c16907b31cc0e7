//! # magbench-store
//!
//! The results store of magbench: what a results folder holds of its runs and how it is kept
//! whole. Each finished run is one row of `runs.csv` and its progress trace rows of
//! `progress.csv` ([`record`], [`store`]); a finished folder also holds them typed in Parquet
//! ([`parquet`], [`progress_parquet`]). The manifest ([`manifest`]) says what made the folder;
//! a lock ([`lock`]) keeps a second writer out; [`repair`] cuts what a killed writer left
//! half-written, [`sort`] puts the rows in run order, and [`verify`] checks a finished folder.
//! The harness (`magbench-harness`) runs the sweeps that fill a folder and writes its replays,
//! figures and report; docs/results.md describes the files.

#![warn(missing_docs)]

pub mod error;
pub mod lock;
pub mod manifest;
pub mod merge;
pub mod parquet;
pub mod progress_parquet;
pub mod record;
pub mod repair;
pub mod sort;
pub mod store;
pub mod temporary;
pub mod traces;
pub mod verify;
mod verify_rows;

pub use error::Error;
pub use manifest::{MANIFEST, Manifest};
pub use record::{ProgressRow, RunRecord, Status};
