//! Planners by name and `key=value` parameters, for the CLI and experiment files.
//!
//! The table of planners is [`crate::planners::PLANNERS`]; each planner's parameters are
//! declared once in its own file. Unknown planners, unknown parameters and bad values are
//! [`InputError`]s naming the source, the field (`planner`, `param.KEY`) and the reason.

use magbench_env::InputError;
use magbench_env::params::{ParamInfo, apply, lookup};

use crate::Planner;
use crate::planners::PLANNERS;

/// A registered planner: its name, a one-line summary and a constructor with defaults.
pub type Entry = magbench_env::params::Entry<dyn Planner>;

/// Names of the registered planners.
pub fn names() -> Vec<&'static str> {
    magbench_env::params::names(PLANNERS)
}

/// Every planner's name, summary and parameters with their defaults.
pub fn list() -> Vec<(&'static str, &'static str, Vec<ParamInfo>)> {
    PLANNERS
        .iter()
        .map(|e| (e.name, e.summary, e.make().params()))
        .collect()
}

/// Creates planner `name` with parameters `params` (key, value); errors name `<command line>`.
pub fn create(name: &str, params: &[(String, String)]) -> Result<Box<dyn Planner>, InputError> {
    create_in("<command line>", name, params)
}

/// Creates planner `name` with parameters `params`; errors name `source` (a file or
/// `<command line>`), the field (`planner` or `param.KEY`) and the reason.
pub fn create_in(
    source: &str,
    name: &str,
    params: &[(String, String)],
) -> Result<Box<dyn Planner>, InputError> {
    let mut planner = lookup(PLANNERS, source, "planner", name)?.make();
    apply(source, name, &mut *planner, params)?;
    Ok(planner)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kv(pairs: &[(&str, &str)]) -> Vec<(String, String)> {
        pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect()
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
        for (name, summary, params) in list() {
            assert!(!summary.is_empty() && !params.is_empty());
            let p = create(name, &[]).unwrap();
            assert_eq!(p.name(), name);
            // every magbench planner takes the shared sampling settings, EXTEND's timing
            // too (OMPL's planners take their own, under OMPL's names)
            for key in [
                "k",
                "min_duration",
                "max_duration",
                "goal_bias",
                "zoom_radius",
                "timing",
            ] {
                if name.starts_with("ompl:") {
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
        let p = create("goal-zoom-rrt", &kv(&[("k", "7"), ("goal_bias", "0.3")])).unwrap();
        assert_eq!(value(&*p, "k"), "7");
        assert_eq!(value(&*p, "goal_bias"), "0.3");
        assert_eq!(
            value(&*create("informed-rrt-star", &[]).unwrap(), "informed"),
            "true"
        );
        let p = create("sst", &kv(&[("timing", "closest")])).unwrap();
        assert_eq!(value(&*p, "timing"), "closest");
    }

    #[test]
    fn parameters_never_rename_a_planner() {
        let p = create("rrt-star", &kv(&[("informed", "true")])).unwrap();
        assert_eq!(
            (p.name(), value(&*p, "informed").as_str()),
            ("rrt-star", "true")
        );
        let p = create("informed-rrt-star", &kv(&[("informed", "false")])).unwrap();
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

        let e = create("sst", &kv(&[("radius", "1")])).err().unwrap();
        assert_eq!(e.field, "param.radius");
        assert!(e.reason.contains("pruning_radius"), "{e}");

        let e = create_in("exp.toml", "sst", &kv(&[("pruning_radius", "-1")]))
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
        ] {
            assert!(
                create("goal-zoom-rrt", &kv(&[(k, v)])).is_err(),
                "{k}={v} accepted"
            );
        }
        let e = create(
            "rrt-star",
            &kv(&[("min_duration", "3"), ("max_duration", "2")]),
        )
        .err()
        .unwrap();
        assert_eq!(e.field, "param");
        assert!(e.reason.contains("exceeds"), "{e}");
        assert!(
            create(
                "rrt-star",
                &kv(&[("min_duration", "3"), ("max_duration", "4")])
            )
            .is_ok()
        );
    }
}
