//! Comparisons of planners across problems, over the plain data of a results folder:
//!
//! - [`instances`]: one value per planner and problem (the median time to a first solution
//!   over seeds, unsolved = +∞, and the success count) and each problem's difficulty measures
//!   (the difficulty columns of its runs in `runs.csv`);
//! - [`paired`]: two planners problem by problem: win rate (Wilson interval) and the median
//!   time ratio (Hodges–Lehmann with the signed-rank interval);
//! - [`profile`]: Dolan–Moré performance profiles;
//! - [`by_difficulty`]: success and time binned by a difficulty measure;
//! - [`scaling`]: the log–log fit of median time against a problem size;
//! - [`study`]: a scaling study over a results folder, its fits and plot;
//! - [`formations`]: the formation study (which formation a team reaches from which);
//! - [`section`]: the plots and the report's "Across problems" section.
//!
//! docs/suites.md, "Comparisons across problems".

pub mod by_difficulty;
pub mod formations;
pub mod instances;
pub mod paired;
pub mod profile;
pub mod scaling;
pub mod section;
pub mod study;
