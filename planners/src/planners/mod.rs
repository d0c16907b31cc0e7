//! The planners, one file each, and the list that names them.
//!
//! Adding a planner to this crate is its own file here (its parameters declared with
//! [`magbench_env::declare_params!`], embedding [`crate::search_settings::SearchSettings`]; `impl Planner`)
//! plus its `mod` line and one [`Entry`] below. A planner outside the workspace is added at run
//! time instead ([`magbench_env::registry::Registry::add`] on [`crate::registry::Planners`]).

mod formation_rrt;
mod goal_zoom_rrt;
mod rrt_star;
mod sst;
mod trajopt;

pub use formation_rrt::FormationRrt;
pub use goal_zoom_rrt::GoalZoomRrt;
pub use rrt_star::{LoggedSample, RrtStar, RrtStarStats};
pub use sst::{Sst, SstStats};
pub use trajopt::Trajopt;

use crate::registry::Entry;

/// The built-in planners, in the order `plan --list` shows them.
pub fn builtins() -> Vec<Entry> {
    Vec::from([
        Entry::new(
            "goal-zoom-rrt",
            "the seed's RRT (Algorithms 1–3): goal-zoom sampling, brute-force EXTEND, stops at the goal",
            || Box::new(GoalZoomRrt::default()),
        ),
        Entry::new(
            "formation-rrt",
            "for teams: shapes sampled apart from the centroid, the centroid carried along a line, HOLD at the goal shape",
            || Box::new(FormationRrt::default()),
        ),
        Entry::new(
            "rrt-star",
            "kinodynamic RRT*: shooting connections, parent by cost, rewiring; improves until the limits",
            || Box::new(RrtStar::default()),
        ),
        Entry::new(
            "informed-rrt-star",
            "RRT* that samples only states that can improve the best solution (per-agent ellipses)",
            || Box::new(RrtStar::informed()),
        ),
        Entry::new(
            "sst",
            "Stable Sparse RRT (Li, Littlefield & Bekris): selection and pruning radii, prunes dominated nodes",
            || Box::new(Sst::default()),
        ),
        Entry::new(
            "trajopt",
            "trajectory optimisation from a straight line: sequential convex programming (Clarabel) over fields and gradients",
            || Box::new(Trajopt::default()),
        ),
        #[cfg(feature = "ompl")]
        Entry::new(
            "ompl:rrt",
            "OMPL 1.5's control::RRT on magbench's model (feature ompl)",
            || {
                Box::new(crate::ompl::Ompl::<crate::ompl::Rrt>::new(
                    "ompl:rrt", "rrt",
                ))
            },
        ),
        #[cfg(feature = "ompl")]
        Entry::new(
            "ompl:sst",
            "OMPL 1.5's control::SST on magbench's model (feature ompl)",
            || {
                Box::new(crate::ompl::Ompl::<crate::ompl::Sst>::new(
                    "ompl:sst", "sst",
                ))
            },
        ),
        #[cfg(feature = "ompl")]
        Entry::new(
            "ompl:kpiece",
            "OMPL 1.5's control::KPIECE1 on magbench's model (feature ompl)",
            || {
                Box::new(crate::ompl::Ompl::<crate::ompl::Kpiece>::new(
                    "ompl:kpiece",
                    "kpiece",
                ))
            },
        ),
        #[cfg(feature = "ompl")]
        Entry::new(
            "ompl:est",
            "OMPL 1.5's control::EST on magbench's model (feature ompl)",
            || {
                Box::new(crate::ompl::Ompl::<crate::ompl::Est>::new(
                    "ompl:est", "est",
                ))
            },
        ),
        #[cfg(feature = "ompl")]
        Entry::new(
            "ompl:pdst",
            "OMPL 1.5's control::PDST on magbench's model (feature ompl)",
            || {
                Box::new(crate::ompl::Ompl::<crate::ompl::Pdst>::new(
                    "ompl:pdst",
                    "pdst",
                ))
            },
        ),
    ])
}
