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

/// Sets the problem's distance metric by name (`positions`, `centroid-shape:W_C:W_S`).
pub fn set_metric(source: &str, problem: &mut Problem, name: &str) -> Result<(), InputError> {
    problem.metric = Metric::parse(name).map_err(|r| InputError::new(source, "metric", r))?;
    Ok(())
}
