//! Trackers by name, with `key=value` parameters (from the command line or experiment files).
//!
//! The table of trackers is [`crate::trackers::TRACKERS`]; each tracker's parameters are
//! declared once in its own file. Every tracker also takes the loop's parameters
//! ([`LoopOptions`]: replanning, time limit, goal hold, estimator blend), with its own defaults.
//! Unknown trackers, unknown parameters and bad values are [`InputError`]s naming the source,
//! the field (`tracker`, `param.KEY`) and the reason.

use magbench_env::InputError;
use magbench_env::params::{Both, ParamInfo, ParamSet, apply, changed, lookup, names};

use crate::run::LoopOptions;
use crate::tracker::Tracker;
use crate::trackers::TRACKERS;

/// A registered tracker: its name, a one-line summary and a constructor with defaults.
pub type Entry = magbench_env::params::Entry<dyn Tracker>;

/// A fresh tracker and the loop's options, with their defaults.
fn fresh(entry: &Entry) -> (Box<dyn Tracker>, LoopOptions) {
    let t = entry.make();
    let opts = t.loop_options();
    (t, opts)
}

/// Every parameter tracker `entry` takes (its own, then the loop's) with its defaults.
pub fn params(entry: &Entry) -> Vec<ParamInfo> {
    let (mut t, mut opts) = fresh(entry);
    Both(&mut *t, &mut opts).params()
}

/// Names of the registered trackers.
pub fn tracker_names() -> Vec<&'static str> {
    names(TRACKERS)
}

/// The registry entry of `name`.
pub fn tracker_info(name: &str) -> Option<&'static Entry> {
    TRACKERS.iter().find(|t| t.name == name)
}

/// A tracker chosen by name, with its parameters checked.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackerSpec {
    /// Registry name.
    pub name: String,
    /// The parameters given (checked), in order.
    params: Vec<(String, String)>,
}

impl TrackerSpec {
    /// Checks `name` and `params` (`source` names the file or `<command line>` in errors).
    pub fn parse(
        name: &str,
        params: &[(String, String)],
        source: &str,
    ) -> Result<Self, InputError> {
        let (mut t, mut opts) = fresh(lookup(TRACKERS, source, "tracker", name)?);
        apply(source, name, &mut Both(&mut *t, &mut opts), params)?;
        Ok(TrackerSpec {
            name: name.to_string(),
            params: params.to_vec(),
        })
    }

    fn entry(&self) -> &'static Entry {
        tracker_info(&self.name).expect("a checked spec")
    }

    /// The tracker and the loop's options, with the parameters set.
    fn configured(&self) -> (Box<dyn Tracker>, LoopOptions) {
        let (mut t, mut opts) = fresh(self.entry());
        apply("", &self.name, &mut Both(&mut *t, &mut opts), &self.params)
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
        let changed = changed(&self.values(), &params(self.entry()));
        if changed.is_empty() {
            self.name.clone()
        } else {
            format!("{}{{{}}}", self.name, changed.join(","))
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

/// A tracker and its loop options from a name and `key=value` parameters.
pub fn build_tracker(
    name: &str,
    params: &[(String, String)],
    source: &str,
) -> Result<(Box<dyn Tracker>, LoopOptions), InputError> {
    let spec = TrackerSpec::parse(name, params, source)?;
    Ok(spec.configured())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kv(k: &str, v: &str) -> (String, String) {
        (k.to_string(), v.to_string())
    }

    #[test]
    fn builds_every_tracker_with_defaults() {
        for name in tracker_names() {
            let (t, _) = build_tracker(name, &[], "<command line>").unwrap();
            assert_eq!(t.name(), name);
            // every listed parameter accepts its own default
            let defaults: Vec<(String, String)> = params(tracker_info(name).unwrap())
                .iter()
                .map(|p| kv(p.name, &p.value.to_string()))
                .collect();
            let spec = TrackerSpec::parse(name, &defaults, "x").unwrap();
            assert_eq!(spec.label(), name);
        }
        let open = TrackerSpec::parse("open-loop", &[], "x").unwrap();
        assert_eq!(
            open.loop_options().replan_after,
            0.0,
            "open-loop does not replan on error by default"
        );
        let open = TrackerSpec::parse("open-loop", &[kv("replan_after", "2")], "x").unwrap();
        assert_eq!(open.label(), "open-loop{replan_after=2}");
        assert_eq!(
            TrackerSpec::parse("obc", &[kv("replan_after", "0")], "x")
                .unwrap()
                .label(),
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
        let s =
            TrackerSpec::parse("obc", &[kv("grid", "36.0"), kv("feedforward", "0")], "x").unwrap();
        assert_eq!(s.label(), "obc{feedforward=false,grid=36}");
    }

    #[test]
    fn labels_show_changed_params() {
        let s = TrackerSpec::parse("obc", &[kv("eps", "0.3")], "x").unwrap();
        assert_eq!(s.label(), "obc{eps=0.3}");
        let eps = s.values().into_iter().find(|p| p.name == "eps").unwrap();
        assert_eq!(eps.value.to_string(), "0.3");
    }
}
