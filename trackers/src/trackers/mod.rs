//! The trackers, one file each, and the list that names them.
//!
//! Adding a tracker to this crate is its own file here (its parameters declared with
//! [`magbench_env::declare_params!`]; `impl Tracker`) plus its `mod` line and one [`Entry`]
//! below. A tracker outside the workspace is added at run time instead
//! ([`magbench_env::registry::Registry::add`] on [`crate::registry::Trackers`]).

mod formation;
mod lookahead;
mod mppi;
mod obc;
mod obc_drive;
mod open_loop;

pub use formation::Formation;
pub use lookahead::Lookahead;
pub use mppi::Mppi;
pub use obc::Obc;
pub use obc_drive::ObcDrive;
pub use open_loop::OpenLoop;

use crate::registry::Entry;

/// The built-in trackers, in the order listings show them.
pub fn builtins() -> Vec<Entry> {
    vec![
        Entry::new(
            "open-loop",
            "replays the plan's controls on their schedule, ignoring observations",
            || Box::new(OpenLoop::default()),
        ),
        Entry::new(
            "obc",
            "optimization-based controller: follows the path forward, proximity control beyond eps",
            || Box::new(Obc::default()),
        ),
        Entry::new(
            "lookahead",
            "pure pursuit (eq. 6) with per-agent moving targets, turned into commands by the OBC optimizer",
            || Box::new(Lookahead::default()),
        ),
        Entry::new(
            "formation",
            "for teams: one period ahead, the field that keeps the shape closest to the plan's, gradients for the centroid, pairs kept apart",
            || Box::new(Formation::default()),
        ),
        Entry::new(
            "mppi",
            "model predictive path integral control: sampled control sequences over a horizon, rolled out with the planning model, exponentially averaged",
            || Box::new(Mppi::default()),
        ),
    ]
}
