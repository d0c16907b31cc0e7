//! [`Rigs`]: the rig kinds known by name, the built-ins and whatever was added at run time.

use std::sync::Arc;

use magbench_env::registry::{Registry, RegistryError};

use super::{CoilRig, OpenError, RigDescription, RigKind, SimulatedRig};

/// Loads a rig's description from its argument and the option it came from.
pub type LoadRig = dyn Fn(&str, &str) -> Result<Box<dyn RigDescription>, OpenError> + Send + Sync;

/// The rig kinds known by name: a name, a one-line summary and a loader each.
#[derive(Clone, Debug)]
pub struct Rigs {
    table: Registry<LoadRig>,
}

impl Default for Rigs {
    /// The built-in rigs.
    fn default() -> Self {
        Rigs::builtin()
    }
}

impl Rigs {
    /// No rigs.
    pub fn empty() -> Self {
        Rigs {
            table: Registry::new("rig"),
        }
    }

    /// `simulated` (env's plant and camera under a disturbance preset) and `coil` (a
    /// coil-and-camera rig, or its emulator, described by a rig file).
    pub fn builtin() -> Self {
        let mut r = Rigs::empty();
        r.add_kind::<SimulatedRig>(
            "simulated",
            "env's simulated plant and camera under a disturbance preset (ideal, realistic, hardware or a preset file)",
        )
        .expect("the built-in rigs have distinct, valid names");
        r.add_kind::<CoilRig>(
            "coil",
            "a coil-and-camera rig, or the emulator standing in for one, described by a rig file",
        )
        .expect("the built-in rigs have distinct, valid names");
        r
    }

    /// Adds rig `name`, whose description `load` reads from its argument (and the option
    /// that gave it, for messages); refuses a name already taken or a malformed one.
    pub fn add(
        &mut self,
        name: &str,
        summary: &str,
        load: impl Fn(&str, &str) -> Result<Box<dyn RigDescription>, OpenError> + Send + Sync + 'static,
    ) -> Result<&mut Self, RegistryError> {
        let load = Arc::new(load);
        self.table.add(name, summary, move || {
            let load = load.clone();
            Box::new(move |arg: &str, option: &str| load(arg, option)) as Box<LoadRig>
        })?;
        Ok(self)
    }

    /// Adds rig kind `R` as `name` ([`RigKind::load`] reads its argument).
    pub fn add_kind<R: RigKind>(
        &mut self,
        name: &str,
        summary: &str,
    ) -> Result<&mut Self, RegistryError> {
        self.add(name, summary, |arg, option| {
            Ok(Box::new(R::load(arg, option)?) as Box<dyn RigDescription>)
        })
    }

    /// Names of the registered rigs, in the order they were added.
    pub fn names(&self) -> Vec<&str> {
        self.table.names()
    }

    /// Every rig's name and summary.
    pub fn list(&self) -> Vec<(&str, &str)> {
        self.table.iter().map(|e| (e.name(), e.summary())).collect()
    }

    /// The description of rig `name` loaded from `arg`. An unknown name is an input error on
    /// the field `rig` that lists the known names; `option` names where `arg` came from.
    pub fn load(
        &self,
        name: &str,
        arg: &str,
        option: &str,
    ) -> Result<Box<dyn RigDescription>, OpenError> {
        let entry = self.table.lookup("<command line>", name)?;
        (entry.make())(arg, option)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn built_in_rigs_load_by_name_and_unknown_names_list_them() {
        let rigs = Rigs::builtin();
        assert_eq!(rigs.names(), ["simulated", "coil"]);
        let sim = rigs.load("simulated", "hardware", "--preset").unwrap();
        assert!(sim.frame_period() > 0.0);
        let e = rigs
            .load("simulated", "no-such-preset", "--preset")
            .err()
            .unwrap();
        assert!(e.to_string().contains("--preset"), "{e}");
        let e = rigs.load("simulted", "ideal", "--preset").err().unwrap();
        assert!(
            matches!(&e, OpenError::Input(i) if i.field == "rig")
                && e.to_string().contains("unknown rig \"simulted\"")
                && e.to_string().contains("coil"),
            "{e}"
        );
    }

    #[test]
    fn takes_rigs_at_run_time() {
        let mut rigs = Rigs::builtin();
        rigs.add_kind::<SimulatedRig>("sim2", "the simulated rig again")
            .unwrap();
        assert!(rigs.load("sim2", "ideal", "--preset").is_ok());
        assert!(Rigs::builtin().load("sim2", "ideal", "--preset").is_err());
        let e = rigs
            .add_kind::<SimulatedRig>("coil", "again")
            .err()
            .unwrap();
        assert!(matches!(e, RegistryError::Duplicate { .. }), "{e}");
    }
}
