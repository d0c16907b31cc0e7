//! Planners by name and `key=value` parameters, for the CLI and experiment files.

use magbench_env::InputError;

use crate::metric::Metric;
use crate::objective::{OBJECTIVES, objective_by_name};
use crate::planner::{Param, ParamError};
use crate::planners::{GoalZoomRrt, RrtStar, Sst};
use crate::{Planner, Problem};

/// A registered planner: its name, a one-line summary and a constructor with defaults.
pub struct Entry {
    /// The registry name.
    pub name: &'static str,
    /// One line on what it is.
    pub summary: &'static str,
    make: fn() -> Box<dyn Planner>,
}

/// Every registered planner.
pub const PLANNERS: [Entry; 4] = [
    Entry {
        name: "goal-zoom-rrt",
        summary: "the seed's RRT (Algorithms 1–3): goal-zoom sampling, brute-force EXTEND, stops at the goal",
        make: || Box::new(GoalZoomRrt::default()),
    },
    Entry {
        name: "rrt-star",
        summary: "kinodynamic RRT*: shooting connections, parent by cost, rewiring; improves until the limits",
        make: || Box::new(RrtStar::default()),
    },
    Entry {
        name: "informed-rrt-star",
        summary: "RRT* that samples only states that can improve the best solution (per-agent ellipses)",
        make: || Box::new(RrtStar::informed()),
    },
    Entry {
        name: "sst",
        summary: "Stable Sparse RRT (Li, Littlefield & Bekris): selection and pruning radii, prunes dominated nodes",
        make: || Box::new(Sst::default()),
    },
];

/// Names of the registered planners.
pub fn names() -> Vec<&'static str> {
    PLANNERS.iter().map(|e| e.name).collect()
}

/// Every planner's name, summary and parameters with their defaults.
pub fn list() -> Vec<(&'static str, &'static str, Vec<Param>)> {
    PLANNERS
        .iter()
        .map(|e| (e.name, e.summary, (e.make)().params()))
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
    let entry = PLANNERS.iter().find(|e| e.name == name).ok_or_else(|| {
        InputError::new(
            source,
            "planner",
            format!("unknown planner {name:?} (known: {})", names().join(", ")),
        )
    })?;
    let mut planner = (entry.make)();
    for (key, value) in params {
        planner
            .set_param(key, value)
            .map_err(|e| param_error(source, name, &*planner, key, e))?;
    }
    planner
        .check_params()
        .map_err(|e| InputError::new(source, "param", format!("{name}: {e}")))?;
    Ok(planner)
}

fn param_error(
    source: &str,
    name: &str,
    planner: &dyn Planner,
    key: &str,
    e: ParamError,
) -> InputError {
    let reason = match e {
        ParamError::Unknown(_) => {
            let known: Vec<&str> = planner.params().iter().map(|p| p.name).collect();
            format!(
                "{name} has no parameter {key:?} (known: {})",
                known.join(", ")
            )
        }
        ParamError::BadValue(r) => r,
    };
    InputError::new(source, format!("param.{key}"), reason)
}

/// Splits `key=value` text; an error names `source` and the text.
pub fn parse_assignment(source: &str, text: &str) -> Result<(String, String), InputError> {
    match text.split_once('=') {
        Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().to_string(), v.trim().to_string())),
        _ => Err(InputError::new(
            source,
            "param",
            format!("{text:?} is not key=value"),
        )),
    }
}

/// Sets the problem's objective by name (`path-length`, `duration`, `control-effort`).
pub fn set_objective(source: &str, problem: &mut Problem, name: &str) -> Result<(), InputError> {
    problem.objective = objective_by_name(name, &problem.model).ok_or_else(|| {
        InputError::new(
            source,
            "objective",
            format!(
                "unknown objective {name:?} (known: {})",
                OBJECTIVES.join(", ")
            ),
        )
    })?;
    Ok(())
}

/// Sets how the problem's planning model solves motions, by name (`pair-exact`, `rk4`).
pub fn set_flow(source: &str, problem: &mut Problem, name: &str) -> Result<(), InputError> {
    let flow = magbench_env::model::Flow::from_name(name).ok_or_else(|| {
        InputError::new(
            source,
            "flow",
            format!("unknown flow {name:?} (known: pair-exact, rk4)"),
        )
    })?;
    problem.model.flow = flow;
    Ok(())
}

/// Sets the problem's distance metric by name (`positions`, `centroid-shape:W_C:W_S`).
pub fn set_metric(source: &str, problem: &mut Problem, name: &str) -> Result<(), InputError> {
    problem.metric = Metric::parse(name).map_err(|r| InputError::new(source, "metric", r))?;
    Ok(())
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

    #[test]
    fn creates_every_planner_with_defaults_and_parameters() {
        for (name, summary, params) in list() {
            assert!(!summary.is_empty() && !params.is_empty());
            let p = create(name, &[]).unwrap();
            assert_eq!(p.name(), name);
            // every listed parameter accepts its own default
            let defaults: Vec<(String, String)> = params
                .iter()
                .map(|p| (p.name.to_string(), p.value.clone()))
                .collect();
            let again = create(name, &defaults).unwrap();
            assert_eq!(again.params(), params, "{name}");
        }
        let p = create("goal-zoom-rrt", &kv(&[("k", "7"), ("goal_bias", "0.3")])).unwrap();
        let params = p.params();
        assert_eq!(params.iter().find(|p| p.name == "k").unwrap().value, "7");
        assert_eq!(
            params.iter().find(|p| p.name == "goal_bias").unwrap().value,
            "0.3"
        );
        assert_eq!(
            create("informed-rrt-star", &[])
                .unwrap()
                .params()
                .iter()
                .find(|p| p.name == "informed")
                .unwrap()
                .value,
            "true"
        );
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
        assert!(e.reason.contains("exceeds"), "{e}");
        assert!(
            create(
                "rrt-star",
                &kv(&[("min_duration", "3"), ("max_duration", "4")])
            )
            .is_ok()
        );
        assert!(parse_assignment("<command line>", "k7").is_err());
        assert_eq!(
            parse_assignment("x", " k = 7 ").unwrap(),
            ("k".to_string(), "7".to_string())
        );
    }

    #[test]
    fn objectives_and_metrics_by_name() {
        let s = magbench_env::Scenario::load("open-field").unwrap();
        let mut p = Problem::from_scenario(&s, 0, None, 0);
        for name in OBJECTIVES {
            set_objective("<command line>", &mut p, name).unwrap();
            assert_eq!(p.objective.name(), name);
        }
        assert_eq!(
            set_objective("<command line>", &mut p, "energy")
                .unwrap_err()
                .field,
            "objective"
        );
        set_metric("<command line>", &mut p, "centroid-shape:1:2").unwrap();
        assert_eq!(
            p.metric,
            Metric::CentroidShape {
                centroid: 1.0,
                shape: 2.0
            }
        );
        assert_eq!(
            set_metric("<command line>", &mut p, "l1")
                .unwrap_err()
                .field,
            "metric"
        );
    }
}
