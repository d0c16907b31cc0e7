//! Planners by name and `key=value` parameters, for the CLI and experiment files.
//!
//! [`Planners`] is a value: [`Planners::builtin`] holds the planners of this crate
//! ([`crate::planners::builtins`]) and [`Registry::add`] takes more at run time (a plugin's).
//! Each planner's parameters are declared once in its own file; every planner made here is a
//! [`PostProcessed`] one, so it also takes the run's post-processing passes (`shortcut`,
//! `straighten`, crate::post_process) and its solutions go through them. Unknown planners, unknown
//! parameters and bad values are [`InputError`]s naming the source, the field (`planner`,
//! `param.KEY`) and the reason.

use std::ops::{Deref, DerefMut};

use magbench_env::InputError;
use magbench_env::params::{ParamInfo, ParamSet, apply};
use magbench_env::registry::{Registry, Renamed};

use crate::tree::Tree;
use crate::{Planner, PlannerResult, PostProcessed, Problem};

/// A registered planner: its name, a one-line summary and a constructor with defaults.
pub type Entry = magbench_env::registry::Entry<dyn Planner>;

/// The planners known by name: the built-ins and whatever was added at run time. The
/// registry's own operations (`add`, `add_entry`, `get`, `names`, `lookup`, `iter`) are those
/// of [`Registry`], reached through `Deref`.
#[derive(Clone, Debug)]
pub struct Planners(Registry<dyn Planner>);

impl Deref for Planners {
    type Target = Registry<dyn Planner>;
    fn deref(&self) -> &Self::Target {
        &self.0
    }
}

impl DerefMut for Planners {
    fn deref_mut(&mut self) -> &mut Self::Target {
        &mut self.0
    }
}

impl Default for Planners {
    /// The built-in planners.
    fn default() -> Self {
        Planners::builtin()
    }
}

impl Planners {
    /// No planners.
    pub fn empty() -> Self {
        Planners(Registry::new("planner"))
    }

    /// The planners of this crate (and `ompl:*` with the feature `ompl`).
    pub fn builtin() -> Self {
        Planners(
            Registry::of("planner", crate::planners::builtins())
                .expect("the built-in planners have distinct, valid names"),
        )
    }

    /// Every planner's name, summary and parameters (the post-processing passes' included)
    /// with their defaults.
    pub fn list(&self) -> Vec<(&str, &str, Vec<ParamInfo>)> {
        self.iter()
            .map(|e| (e.name(), e.summary(), PostProcessed::new(e.make()).params()))
            .collect()
    }

    /// Creates planner `name` with parameters `params` (key, value); errors name
    /// `<command line>`.
    pub fn create(
        &self,
        name: &str,
        params: &[(String, String)],
    ) -> Result<Box<dyn Planner>, InputError> {
        self.create_in("<command line>", name, params)
    }

    /// Creates planner `name` with parameters `params`, followed by the post-processing passes
    /// they set ([`PostProcessed`]); errors name `source` (a file or `<command line>`), the
    /// field (`planner` or `param.KEY`) and the reason.
    pub fn create_in(
        &self,
        source: &str,
        name: &str,
        params: &[(String, String)],
    ) -> Result<Box<dyn Planner>, InputError> {
        let entry = self.lookup(source, name)?;
        let mut planner: Box<dyn Planner> =
            Box::new(PostProcessed::new(named(entry.make(), entry.name())));
        apply(source, name, &mut *planner, params)?;
        Ok(planner)
    }
}

/// `planner`, reporting `name` from [`Planner::name`] (wrapped when it reports another).
fn named(planner: Box<dyn Planner>, name: &str) -> Box<dyn Planner> {
    if planner.name() == name {
        planner
    } else {
        Box::new(Renamed {
            name: name.to_string(),
            inner: planner,
        })
    }
}

impl Planner for Renamed<dyn Planner> {
    fn name(&self) -> &str {
        &self.name
    }
    fn solve(&mut self, problem: &Problem) -> PlannerResult {
        self.inner.solve(problem)
    }
    fn tree(&self) -> Option<&Tree> {
        self.inner.tree()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planners::GoalZoomRrt;
    use magbench_env::params::owned;
    use magbench_env::registry::RegistryError;

    fn create(name: &str, params: &[(String, String)]) -> Result<Box<dyn Planner>, InputError> {
        Planners::builtin().create(name, params)
    }

    fn create_in(
        source: &str,
        name: &str,
        params: &[(String, String)],
    ) -> Result<Box<dyn Planner>, InputError> {
        Planners::builtin().create_in(source, name, params)
    }

    fn value(p: &dyn Planner, key: &str) -> String {
        let params = p.params();
        params
            .iter()
            .find(|p| p.name == key)
            .unwrap()
            .value
            .to_string()
    }

    #[test]
    fn creates_every_planner_with_defaults_and_parameters() {
        let builtin = Planners::builtin();
        for (name, summary, params) in builtin.list() {
            assert!(!summary.is_empty() && !params.is_empty());
            let p = create(name, &[]).unwrap();
            assert_eq!(p.name(), name);
            // every planner takes the post-processing passes
            for key in ["shortcut", "straighten", "trajopt"] {
                assert!(params.iter().any(|p| p.name == key), "{name} lacks {key}");
            }
            // every magbench sampling planner takes the shared sampling settings, EXTEND's
            // timing too (OMPL's planners take their own, under OMPL's names; trajopt samples
            // nothing)
            for key in [
                "k",
                "min_duration",
                "max_duration",
                "goal_bias",
                "zoom_radius",
                "timing",
                "guide",
                "aim",
            ] {
                if name.starts_with("ompl:") || name == "trajopt" {
                    break;
                }
                assert!(params.iter().any(|p| p.name == key), "{name} lacks {key}");
            }
            // every listed parameter accepts its own default
            let defaults: Vec<(String, String)> = params
                .iter()
                .map(|p| (p.name.to_string(), p.value.to_string()))
                .collect();
            let again = create(name, &defaults).unwrap();
            assert_eq!(again.params(), params, "{name}");
        }
        let p = create("goal-zoom-rrt", &owned(&[("k", "7"), ("goal_bias", "0.3")])).unwrap();
        assert_eq!(value(&*p, "k"), "7");
        assert_eq!(value(&*p, "goal_bias"), "0.3");
        assert_eq!(
            value(&*create("informed-rrt-star", &[]).unwrap(), "informed"),
            "true"
        );
        let p = create("sst", &owned(&[("timing", "closest")])).unwrap();
        assert_eq!(value(&*p, "timing"), "closest");
    }

    #[test]
    fn parameters_never_rename_a_planner() {
        let p = create("rrt-star", &owned(&[("informed", "true")])).unwrap();
        assert_eq!(
            (p.name(), value(&*p, "informed").as_str()),
            ("rrt-star", "true")
        );
        let p = create("informed-rrt-star", &owned(&[("informed", "false")])).unwrap();
        assert_eq!(p.name(), "informed-rrt-star");
    }

    #[test]
    fn bad_input_is_an_input_error_naming_the_field() {
        let e = create("rrt", &[]).err().unwrap();
        assert_eq!(
            (e.file.as_str(), e.field.as_str()),
            ("<command line>", "planner")
        );
        assert!(
            e.reason.contains("goal-zoom-rrt") && e.reason.contains("sst"),
            "{e}"
        );

        let e = create("sst", &owned(&[("radius", "1")])).err().unwrap();
        assert_eq!(e.field, "param.radius");
        assert!(e.reason.contains("pruning_radius"), "{e}");

        let e = create_in("exp.toml", "sst", &owned(&[("pruning_radius", "-1")]))
            .err()
            .unwrap();
        assert_eq!(
            (e.file.as_str(), e.field.as_str()),
            ("exp.toml", "param.pruning_radius")
        );

        for (k, v) in [
            ("k", "0"),
            ("k", "many"),
            ("goal_bias", "1.5"),
            ("max_duration", "nan"),
            ("zoom_radius", "inf"),
            ("timing", "soon"),
            ("shortcut", "-1"),
        ] {
            assert!(
                create("goal-zoom-rrt", &owned(&[(k, v)])).is_err(),
                "{k}={v} accepted"
            );
        }
        let e = create(
            "rrt-star",
            &owned(&[("min_duration", "3"), ("max_duration", "2")]),
        )
        .err()
        .unwrap();
        assert_eq!(e.field, "param");
        assert!(e.reason.contains("exceeds"), "{e}");
        assert!(
            create(
                "rrt-star",
                &owned(&[("min_duration", "3"), ("max_duration", "4")])
            )
            .is_ok()
        );
    }

    #[test]
    fn takes_planners_at_run_time_under_their_registry_name() {
        let mut reg = Planners::builtin();
        let before = reg.names().len();
        reg.add("my-rrt", "a plugin's RRT", || {
            Box::new(GoalZoomRrt::default())
        })
        .unwrap()
        .add("lab:rrt.v2", "another", || Box::new(GoalZoomRrt::default()))
        .unwrap();
        assert_eq!(reg.names().len(), before + 2);
        assert_eq!(reg.names()[before], "my-rrt");
        // the planner made reports the registry name and keeps its parameters
        let p = reg.create("my-rrt", &owned(&[("k", "7")])).unwrap();
        assert_eq!(p.name(), "my-rrt");
        assert_eq!(value(&*p, "k"), "7");
        assert!(
            reg.list()
                .iter()
                .any(|(n, s, _)| *n == "my-rrt" && *s == "a plugin's RRT")
        );
        // a copy is independent: the built-ins stay as they are
        assert!(Planners::builtin().get("my-rrt").is_none());
    }

    #[test]
    fn refuses_duplicate_and_malformed_names() {
        let mut reg = Planners::builtin();
        let e = reg
            .add(
                "goal-zoom-rrt",
                "again",
                || Box::new(GoalZoomRrt::default()),
            )
            .err()
            .unwrap();
        assert!(matches!(e, RegistryError::Duplicate { .. }), "{e}");
        assert!(
            e.to_string()
                .contains("\"goal-zoom-rrt\" is already registered"),
            "{e}"
        );
        for bad in ["", "my rrt", "a{b}", "x:", ":x", "a:b:c", "é"] {
            let e = reg.add(bad, "", || Box::new(GoalZoomRrt::default())).err();
            assert!(
                matches!(e, Some(RegistryError::BadName { .. })),
                "{bad:?}: {e:?}"
            );
        }
    }

    #[test]
    fn unknown_names_list_the_registered_ones() {
        let mut reg = Planners::builtin();
        reg.add("my-rrt", "", || Box::new(GoalZoomRrt::default()))
            .unwrap();
        let e = reg.create_in("exp.toml", "my-rtt", &[]).err().unwrap();
        assert_eq!((e.file.as_str(), e.field.as_str()), ("exp.toml", "planner"));
        assert!(
            e.reason.contains("unknown planner \"my-rtt\"")
                && e.reason.contains("my-rrt")
                && e.reason.contains("goal-zoom-rrt"),
            "{e}"
        );
    }
}
