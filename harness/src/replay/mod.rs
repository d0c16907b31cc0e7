//! Replays and previews: a self-contained HTML page per run that plays it back (the maze,
//! the plans, the planner's tree, true and observed positions, the commanded field, contacts
//! and replans), a picture of a scenario before it is run, and the planner's tree as data.
//!
//! - [`scene`]: the scenario as the page draws it;
//! - [`data`]: what one page shows, from a tracked or a planning run;
//! - [`events`]: contacts found in the positions, replans and legs;
//! - [`tree`]: a search tree as data (`plan --tree`), [`tree_svg`]: its picture;
//! - [`page`]: the HTML page with its player script, [`pack`]: the page's compact data;
//! - [`policy`]: which runs of a sweep get a page (`bench --replays`);
//! - [`preview`]: the scenario preview (`scenario show --out`);
//! - [`files`]: where a results folder keeps them.
//!
//! docs/replay.md describes the page and the tree file.

pub mod data;
pub mod events;
pub mod files;
pub mod pack;
pub mod page;
pub mod policy;
pub mod preview;
pub mod scene;
pub mod tree;
pub mod tree_svg;

pub use data::ReplayData;
pub use policy::ReplayPolicy;
pub use tree::{LegTree, TreeFile};
