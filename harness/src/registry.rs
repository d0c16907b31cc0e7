//! [`Registry`]: the planners and trackers known by name — the built-ins plus whatever a plugin
//! adds at run time. A registry is a value; every command that resolves a name is given the
//! registry to resolve it in (there is no global one).

use magbench_env::params::RegistryError;
use magbench_planners::{Planner, Planners};
use magbench_trackers::{Tracker, Trackers};

/// Planners and trackers by name: the built-ins plus whatever a plugin adds at run time.
#[derive(Clone, Debug, Default)]
pub struct Registry {
    planners: Planners,
    trackers: Trackers,
}

impl Registry {
    /// The built-in planners (and `ompl:*` with the feature `ompl`) and trackers.
    pub fn builtin() -> Registry {
        Registry {
            planners: Planners::builtin(),
            trackers: Trackers::builtin(),
        }
    }

    /// Adds planner `name` (`summary`: one line for `plan --list`), made with its defaults by
    /// `make`. A duplicate name, or one an experiment file cannot write, is an error. The
    /// planners it makes report `name` from [`Planner::name`].
    pub fn add_planner(
        &mut self,
        name: &str,
        summary: &str,
        make: impl Fn() -> Box<dyn Planner> + Send + Sync + 'static,
    ) -> Result<&mut Self, RegistryError> {
        self.planners.add(name, summary, make)?;
        Ok(self)
    }

    /// Adds tracker `name` (`summary`: one line on what it does), made with its defaults by
    /// `make`. A duplicate name, or one an experiment file cannot write, is an error. The
    /// trackers it makes report `name` from [`Tracker::name`].
    pub fn add_tracker(
        &mut self,
        name: &str,
        summary: &str,
        make: impl Fn() -> Box<dyn Tracker> + Send + Sync + 'static,
    ) -> Result<&mut Self, RegistryError> {
        self.trackers.add(name, summary, make)?;
        Ok(self)
    }

    /// The planners.
    pub fn planners(&self) -> &Planners {
        &self.planners
    }

    /// The trackers.
    pub fn trackers(&self) -> &Trackers {
        &self.trackers
    }
}
