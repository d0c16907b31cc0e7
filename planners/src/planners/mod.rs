//! The planners, one file each.

mod goal_zoom_rrt;
mod rrt_star;
mod sst;

pub use goal_zoom_rrt::GoalZoomRrt;
pub use rrt_star::{LoggedSample, RrtStar, RrtStarStats};
pub use sst::{Sst, SstStats};
