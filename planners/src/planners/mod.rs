//! The planners, one file each.

mod goal_zoom_rrt;
mod rrt_star;
mod sst;

pub use goal_zoom_rrt::GoalZoomRrt;
pub use rrt_star::RrtStar;
pub use sst::Sst;
