//! Trackers by name, with `key=value` parameters (from the command line or experiment files).
//!
//! [`Trackers`] is a value: [`Trackers::builtin`] holds the trackers of this crate
//! ([`crate::trackers::builtins`]) and [`Registry::add`] takes more at run time (a plugin's).
//! Each tracker's parameters are declared once in its own file. Every tracker also takes the
//! loop's parameters ([`LoopOptions`]: replanning, time limit, goal hold, estimator blend), with
//! its own defaults. Unknown trackers, unknown parameters and bad values are [`InputError`]s
//! naming the source, the field (`tracker`, `param.KEY`) and the reason.

use std::fmt;
use std::ops::{Deref, DerefMut};

use magbench_env::params::{Both, ParamInfo, ParamSet, apply, changed};
use magbench_env::registry::{Registry, Renamed};
use magbench_env::{Control, InputError};

use crate::closed_loop::LoopOptions;
use crate::tracker::{Tick, Tracker, TrackerContext, TrackerStatus};

/// A registered tracker: its name, a one-line summary and a constructor with defaults.
pub type Entry = magbench_env::registry::Entry<dyn Tracker>;

/// The trackers known by name: the built-ins and whatever was added at run time. The
/// registry's own operations (`add`, `add_entry`, `get`, `names`, `lookup`, `iter`) are those
/// of [`Registry`], reached through `Deref`.
#[derive(Clone, Debug)]
pub struct Trackers(Registry<dyn Tracker>);

impl Deref for Trackers {
    type Target = Registry<dyn Tracker>;
    fn deref(&self) -> &Self::Target {
        &self.0
    }
}

impl DerefMut for Trackers {
    fn deref_mut(&mut self) -> &mut Self::Target {
        &mut self.0
    }
}

impl Default for Trackers {
    /// The built-in trackers.
    fn default() -> Self {
        Trackers::builtin()
    }
}

impl Trackers {
    /// No trackers.
    pub fn empty() -> Self {
        Trackers(Registry::new("tracker"))
    }

    /// The trackers of this crate.
    pub fn builtin() -> Self {
        Trackers(
            Registry::of("tracker", crate::trackers::builtins())
                .expect("the built-in trackers have distinct, valid names"),
        )
    }

    /// Every tracker's name, summary and parameters (its own, then the loop's) with their
    /// defaults.
    pub fn list(&self) -> Vec<(&str, &str, Vec<ParamInfo>)> {
        self.iter()
            .map(|e| (e.name(), e.summary(), params(e)))
            .collect()
    }

    /// Checks `name` and `params` (`source` names the file or `<command line>` in errors).
    pub fn spec(
        &self,
        name: &str,
        params: &[(String, String)],
        source: &str,
    ) -> Result<TrackerSpec, InputError> {
        let entry = self.lookup(source, name)?;
        let (mut t, mut opts) = fresh(entry);
        apply(source, name, &mut Both(&mut *t, &mut opts), params)?;
        Ok(TrackerSpec {
            entry: entry.clone(),
            params: params.to_vec(),
        })
    }

    /// A tracker and its loop options from a name and `key=value` parameters.
    pub fn build(
        &self,
        name: &str,
        params: &[(String, String)],
        source: &str,
    ) -> Result<(Box<dyn Tracker>, LoopOptions), InputError> {
        Ok(self.spec(name, params, source)?.configured())
    }
}

/// A fresh tracker under its registry name and the loop's options, with their defaults.
fn fresh(entry: &Entry) -> (Box<dyn Tracker>, LoopOptions) {
    let t = named(entry.make(), entry.name());
    let opts = t.loop_options();
    (t, opts)
}

/// Every parameter tracker `entry` takes (its own, then the loop's) with its defaults.
pub fn params(entry: &Entry) -> Vec<ParamInfo> {
    let (mut t, mut opts) = fresh(entry);
    Both(&mut *t, &mut opts).params()
}

/// A tracker chosen by name from a registry, with its parameters checked
/// ([`Trackers::spec`]).
#[derive(Clone)]
pub struct TrackerSpec {
    /// The registry entry.
    entry: Entry,
    /// The parameters given (checked), in order.
    params: Vec<(String, String)>,
}

impl fmt::Debug for TrackerSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("TrackerSpec")
            .field("name", &self.name())
            .field("params", &self.params)
            .finish()
    }
}

impl PartialEq for TrackerSpec {
    fn eq(&self, other: &Self) -> bool {
        self.name() == other.name() && self.params == other.params
    }
}

impl TrackerSpec {
    /// The registry name.
    pub fn name(&self) -> &str {
        self.entry.name()
    }

    /// The tracker and the loop's options, with the parameters set.
    fn configured(&self) -> (Box<dyn Tracker>, LoopOptions) {
        let (mut t, mut opts) = fresh(&self.entry);
        apply("", self.name(), &mut Both(&mut *t, &mut opts), &self.params)
            .expect("parameters checked when parsed");
        (t, opts)
    }

    /// Every parameter's value (the tracker's, then the loop's).
    pub fn values(&self) -> Vec<ParamInfo> {
        let (mut t, mut opts) = self.configured();
        Both(&mut *t, &mut opts).params()
    }

    /// The parameters that differ from their defaults, as `name{key=value,...}` (for labels).
    pub fn label(&self) -> String {
        let changed = changed(&self.values(), &params(&self.entry));
        if changed.is_empty() {
            self.name().to_string()
        } else {
            format!("{}{{{}}}", self.name(), changed.join(","))
        }
    }

    /// A fresh tracker.
    pub fn build(&self) -> Box<dyn Tracker> {
        self.configured().0
    }

    /// The loop's options.
    pub fn loop_options(&self) -> LoopOptions {
        self.configured().1
    }
}

/// `tracker`, reporting `name` from [`Tracker::name`] (wrapped when it reports another).
fn named(tracker: Box<dyn Tracker>, name: &str) -> Box<dyn Tracker> {
    if tracker.name() == name {
        tracker
    } else {
        Box::new(Renamed {
            name: name.to_string(),
            inner: tracker,
        })
    }
}

impl Tracker for Renamed<dyn Tracker> {
    fn name(&self) -> &str {
        &self.name
    }
    fn loop_options(&self) -> LoopOptions {
        self.inner.loop_options()
    }
    fn reset(&mut self, ctx: &TrackerContext) {
        self.inner.reset(ctx)
    }
    fn command(&mut self, ctx: &TrackerContext, tick: &Tick) -> Control {
        self.inner.command(ctx, tick)
    }
    fn status(&self) -> TrackerStatus {
        self.inner.status()
    }
    fn finished(&self) -> bool {
        self.inner.finished()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trackers::Obc;
    use magbench_env::registry::RegistryError;

    fn build_tracker(
        name: &str,
        params: &[(String, String)],
        source: &str,
    ) -> Result<(Box<dyn Tracker>, LoopOptions), InputError> {
        Trackers::builtin().build(name, params, source)
    }

    fn parse(name: &str, params: &[(String, String)], source: &str) -> TrackerSpec {
        Trackers::builtin().spec(name, params, source).unwrap()
    }

    fn kv(k: &str, v: &str) -> (String, String) {
        (k.to_string(), v.to_string())
    }

    #[test]
    fn builds_every_tracker_with_defaults() {
        let builtin = Trackers::builtin();
        for name in builtin.names() {
            let (t, _) = build_tracker(name, &[], "<command line>").unwrap();
            assert_eq!(t.name(), name);
            // every listed parameter accepts its own default
            let defaults: Vec<(String, String)> = params(builtin.get(name).unwrap())
                .iter()
                .map(|p| kv(&p.name, &p.value.to_string()))
                .collect();
            let spec = parse(name, &defaults, "x");
            assert_eq!(spec.label(), name);
        }
        let open = parse("open-loop", &[], "x");
        assert_eq!(
            open.loop_options().replan_after,
            0.0,
            "open-loop does not replan on error by default"
        );
        let open = parse("open-loop", &[kv("replan_after", "2")], "x");
        assert_eq!(open.label(), "open-loop{replan_after=2}");
        assert_eq!(
            parse("obc", &[kv("replan_after", "0")], "x").label(),
            "obc{replan_after=0}"
        );
    }

    #[test]
    fn rejects_unknown_names_params_and_bad_values() {
        let e = build_tracker("pid", &[], "<command line>").err().unwrap();
        assert_eq!(e.field, "tracker");
        assert!(e.to_string().contains("unknown tracker \"pid\""), "{e}");
        let e = build_tracker("obc", &[kv("gain", "0.5")], "exp.toml")
            .err()
            .unwrap();
        assert_eq!(
            (e.file.as_str(), e.field.as_str()),
            ("exp.toml", "param.gain")
        );
        assert!(
            e.reason.contains("no parameter") && e.reason.contains("w_com"),
            "{e}"
        );
        let e = build_tracker("obc", &[kv("eps", "abc")], "x")
            .err()
            .unwrap();
        assert!(e.reason.contains("not a number"));
        let e = build_tracker("lookahead", &[kv("gain", "1.5")], "x")
            .err()
            .unwrap();
        assert!(e.reason.contains("must be in"));
        let e = build_tracker("obc", &[kv("grid", "10.5")], "x")
            .err()
            .unwrap();
        assert!(e.reason.contains("whole number"));
        // a whole number written as a real (a TOML float) and a 0/1 flag still parse
        let s = parse("obc", &[kv("grid", "36.0"), kv("feedforward", "0")], "x");
        assert_eq!(s.label(), "obc{feedforward=false,grid=36}");
    }

    #[test]
    fn labels_show_changed_params() {
        let s = parse("obc", &[kv("eps", "0.3")], "x");
        assert_eq!(s.label(), "obc{eps=0.3}");
        let eps = s.values().into_iter().find(|p| p.name == "eps").unwrap();
        assert_eq!(eps.value.to_string(), "0.3");
    }

    #[test]
    fn takes_trackers_at_run_time_under_their_registry_name() {
        let mut reg = Trackers::builtin();
        reg.add("my-obc", "an OBC under another name", || {
            Box::new(Obc::default())
        })
        .unwrap();
        assert_eq!(reg.names().last(), Some(&"my-obc"));
        let spec = reg.spec("my-obc", &[kv("eps", "0.3")], "x").unwrap();
        assert_eq!(spec.label(), "my-obc{eps=0.3}");
        assert_eq!(spec.build().name(), "my-obc");
        assert!(Trackers::builtin().get("my-obc").is_none());
        let e = reg
            .add("obc", "again", || Box::new(Obc::default()))
            .err()
            .unwrap();
        assert!(matches!(e, RegistryError::Duplicate { .. }), "{e}");
        let e = reg.spec("my-ocb", &[], "exp.toml").err().unwrap();
        assert_eq!((e.file.as_str(), e.field.as_str()), ("exp.toml", "tracker"));
        assert!(
            e.reason.contains("my-obc") && e.reason.contains("lookahead"),
            "{e}"
        );
    }
}
