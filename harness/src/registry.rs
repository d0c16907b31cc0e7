//! [`Registry`]: the planners, trackers and rigs known by name — the built-ins plus whatever a plugin
//! adds at run time. A registry is a value; every command that resolves a name is given the
//! registry to resolve it in (there is no global one).

use magbench_drivers::rigs::{OpenError, RigDescription, Rigs};
use magbench_env::registry::RegistryError;
use magbench_planners::{Planner, Planners};
use magbench_trackers::{Tracker, Trackers};

/// Planners, trackers and rigs by name: the built-ins plus whatever a plugin adds at run time.
#[derive(Clone, Debug, Default)]
pub struct Registry {
    planners: Planners,
    trackers: Trackers,
    rigs: Rigs,
}

impl Registry {
    /// The built-in planners (and `ompl:*` with the feature `ompl`), trackers and rigs.
    pub fn builtin() -> Registry {
        Registry {
            planners: Planners::builtin(),
            trackers: Trackers::builtin(),
            rigs: Rigs::builtin(),
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

    /// Adds planner `entry` (with [`magbench_env::registry::Entry::serial`] when its runs must
    /// go one at a time). A duplicate name, or a malformed one, is an error.
    pub fn add_planner_entry(
        &mut self,
        entry: magbench_planners::registry::Entry,
    ) -> Result<&mut Self, RegistryError> {
        self.planners.add_entry(entry)?;
        Ok(self)
    }

    /// Adds tracker `entry` (with [`magbench_env::registry::Entry::serial`] when its runs must
    /// go one at a time). A duplicate name, or a malformed one, is an error.
    pub fn add_tracker_entry(
        &mut self,
        entry: magbench_trackers::registry::Entry,
    ) -> Result<&mut Self, RegistryError> {
        self.trackers.add_entry(entry)?;
        Ok(self)
    }

    /// Of planner `planner` and tracker `tracker`, the names whose runs go one at a time
    /// ([`magbench_env::registry::Entry::serial`]: a Python plugin holds the GIL).
    pub fn one_at_a_time(&self, planner: &str, tracker: Option<&str>) -> Vec<String> {
        let p = self.planners.get(planner).filter(|e| e.is_serial());
        let t = tracker
            .and_then(|t| self.trackers.get(t))
            .filter(|e| e.is_serial());
        p.map(|e| e.name())
            .into_iter()
            .chain(t.map(|e| e.name()))
            .map(str::to_string)
            .collect()
    }

    /// Adds rig `name` (`summary`: one line on what it is), whose description `load` reads
    /// from its argument (`--rig` of `rig run`, `--preset` of `track`) and the option that gave
    /// it. A duplicate name, or a malformed one, is an error.
    pub fn add_rig(
        &mut self,
        name: &str,
        summary: &str,
        load: impl Fn(&str, &str) -> Result<Box<dyn RigDescription>, OpenError> + Send + Sync + 'static,
    ) -> Result<&mut Self, RegistryError> {
        self.rigs.add(name, summary, load)?;
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

    /// The rigs.
    pub fn rigs(&self) -> &Rigs {
        &self.rigs
    }
}
