//! The experiment file format (serde) and its validation.

use std::collections::BTreeSet;
use std::path::Path;
use std::sync::Arc;

use magbench_env::InputError;
use magbench_env::input::{Bound, Rejection, parse_toml};
use magbench_env::plant::DisturbancePreset;
use serde::Deserialize;

use super::{Experiment, LabelledPreset, Tracking, resolve_preset, resolve_scenario};
use crate::replay::ReplayPolicy;
use crate::run::spec::{ITERATIONS, time_limit};
use crate::run::{Executor, ParamValue, RunLimits, Variant};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ExperimentFile {
    name: Option<String>,
    #[serde(default)]
    description: String,
    #[serde(default)]
    scenarios: Vec<String>,
    #[serde(default)]
    generated: Vec<toml::Value>,
    planners: Vec<toml::Value>,
    #[serde(default)]
    trackers: Vec<toml::Value>,
    presets: Option<Vec<String>>,
    seeds: toml::Value,
    limits: LimitsFile,
    tracking: Option<TrackingFile>,
    replays: Option<String>,
}

/// `[tracking]`: track only some planners' plans, besides every planner's planning runs.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TrackingFile {
    plans: Option<Vec<String>>,
    trackers: Vec<toml::Value>,
    presets: Option<Vec<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LimitsFile {
    iterations: Option<i64>,
    time: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ComponentTable {
    name: String,
    #[serde(default)]
    params: toml::Table,
}

fn component(v: &toml::Value, file: &str, field: &str) -> Result<Variant, InputError> {
    let err = |r: String| InputError::new(file, field, r);
    let refused = |r: Rejection| r.under(field).in_file(file);
    match v {
        toml::Value::String(s) => Variant::parse(s).map_err(refused),
        toml::Value::Table(t) => {
            let c: ComponentTable =
                toml::Value::Table(t.clone())
                    .try_into()
                    .map_err(|e: toml::de::Error| {
                        err(format!(
                            "{} (expected {{ name = \"...\", params = {{ ... }} }})",
                            e.message().trim()
                        ))
                    })?;
            let mut v = Variant::parse(&c.name).map_err(refused)?;
            if !v.params.is_empty() {
                return Err(err(
                    "give parameters either in the name or in `params`, not both".into(),
                ));
            }
            for (k, p) in &c.params {
                let pv = ParamValue::from_toml(p)
                    .map_err(|r| r.under(&format!("{field}.params.{k}")).in_file(file))?;
                v.params.insert(k.clone(), pv);
            }
            Ok(v)
        }
        other => Err(err(format!(
            "expected a label such as \"goal-zoom-rrt{{k=5}}\" or a table, got a {}",
            other.type_str()
        ))),
    }
}

fn components(
    list: &[toml::Value],
    file: &str,
    key: &str,
    check: &dyn Fn(&Variant) -> Result<(), magbench_env::input::Rejection>,
) -> Result<Vec<Variant>, InputError> {
    let mut out: Vec<Variant> = vec![];
    for (i, v) in list.iter().enumerate() {
        let field = format!("{key}[{i}]");
        let c = component(v, file, &field)?;
        check(&c).map_err(|r| r.under(&field).in_file(file))?;
        if out.iter().any(|o| o.label() == c.label()) {
            return Err(InputError::new(
                file,
                &field,
                format!("{} is listed twice", c.label()),
            ));
        }
        out.push(c);
    }
    Ok(out)
}

/// Most seeds of an experiment.
pub const MAX_SEEDS: usize = 100_000;

/// A seed count (`seeds = N`, `ablate --seeds`): 1 to [`MAX_SEEDS`].
pub const SEED_COUNT: Bound = Bound::closed(
    1.0,
    MAX_SEEDS as f64,
    " seeds",
    "each seed is a run of every variant, and a sweep holds its whole run matrix in memory",
);

/// Most runs in an experiment's run matrix.
pub const MAX_RUNS: usize = 1_000_000;

/// Longest experiment name (it names a folder, with `-shard-I-of-N` added).
pub const MAX_NAME_CHARS: usize = 64;

fn seeds(v: &toml::Value, file: &str) -> Result<Vec<u64>, InputError> {
    let err = |r: String| InputError::new(file, "seeds", r);
    match v {
        toml::Value::Integer(n) => {
            SEED_COUNT
                .check("seeds", *n as f64)
                .map_err(|r| err(format!("a seed count {}", r.reason)))?;
            Ok((0..*n as u64).collect())
        }
        toml::Value::Array(a) if a.len() > MAX_SEEDS => {
            Err(err(format!("at most {MAX_SEEDS} seeds, got {}", a.len())))
        }
        toml::Value::Array(a) if !a.is_empty() => {
            let mut seen = BTreeSet::new();
            let mut out = vec![];
            for (i, s) in a.iter().enumerate() {
                let s = s.as_integer().filter(|s| *s >= 0).ok_or_else(|| {
                    InputError::new(file, format!("seeds[{i}]"), "a seed is an integer ≥ 0")
                })?;
                if !seen.insert(s) {
                    return Err(InputError::new(
                        file,
                        format!("seeds[{i}]"),
                        format!("seed {s} is listed twice"),
                    ));
                }
                out.push(s as u64);
            }
            Ok(out)
        }
        toml::Value::Array(_) => Err(err("the seed list is empty".into())),
        other => Err(err(format!(
            "expected a count or a list of integers, got a {}",
            other.type_str()
        ))),
    }
}

/// Checks an experiment name: it names the results folder.
fn check_name(name: &str) -> Result<(), Rejection> {
    let refuse = |reason: String| Rejection::new("name", format!("{name:?}: {reason}"));
    let chars_ok = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c));
    if !chars_ok {
        return Err(refuse(
            "use letters, digits, '-', '_' and '.' (it names the results folder)".into(),
        ));
    }
    if name.starts_with('.') {
        return Err(refuse(
            "must not start with '.' (`.` and `..` would put results in the parent folder; a dot-folder is hidden)".into(),
        ));
    }
    if name.chars().count() > MAX_NAME_CHARS {
        return Err(refuse(format!(
            "at most {MAX_NAME_CHARS} characters (it names the results folder), got {}",
            name.chars().count()
        )));
    }
    Ok(())
}

/// The presets of `list` (default `["ideal"]`): built-in names or preset files (relative to
/// `base_dir` or the working directory), loaded and validated; errors name `field`.
fn presets(
    list: Option<Vec<String>>,
    file: &str,
    field: &str,
    base_dir: &Path,
) -> Result<Vec<LabelledPreset>, InputError> {
    let Some(p) = list else {
        return Ok(vec![(
            "ideal".to_string(),
            Arc::new(DisturbancePreset::ideal()),
        )]);
    };
    if p.is_empty() {
        return Err(InputError::new(
            file,
            field,
            format!("list at least one preset, or leave `{field}` out for [\"ideal\"]"),
        ));
    }
    let mut out = vec![];
    for (i, name) in p.iter().enumerate() {
        let preset = resolve_preset(name, base_dir)
            .map_err(|e| InputError::new(file, format!("{field}[{i}]"), e.to_string()))?;
        if p[..i].contains(name) {
            return Err(InputError::new(
                file,
                format!("{field}[{i}]"),
                format!("{name} is listed twice"),
            ));
        }
        out.push((name.clone(), Arc::new(preset)));
    }
    Ok(out)
}

/// The labels of the planners whose plans are tracked (`[tracking] plans`; default every
/// planner): each must be one of `planners`, as written there (compared canonically).
fn tracked_plans(
    plans: Option<Vec<String>>,
    planners: &[Variant],
    file: &str,
) -> Result<Vec<String>, InputError> {
    let labels: Vec<String> = planners.iter().map(Variant::label).collect();
    let Some(plans) = plans else {
        return Ok(labels);
    };
    if plans.is_empty() {
        return Err(InputError::new(
            file,
            "tracking.plans",
            "list at least one planner, or leave `plans` out to track every planner's plans",
        ));
    }
    let mut out: Vec<String> = vec![];
    for (i, text) in plans.iter().enumerate() {
        let field = format!("tracking.plans[{i}]");
        let label = Variant::parse(text)
            .map_err(|r| r.under(&field).in_file(file))?
            .label();
        if !labels.contains(&label) {
            return Err(InputError::new(
                file,
                &field,
                format!(
                    "{text:?} is not one of the planners ({})",
                    labels.join(", ")
                ),
            ));
        }
        if out.contains(&label) {
            return Err(InputError::new(
                file,
                &field,
                format!("{label} is listed twice"),
            ));
        }
        out.push(label);
    }
    Ok(out)
}

/// Parses and validates an experiment.
pub fn parse(
    text: &str,
    file: &str,
    base_dir: &Path,
    default_name: &str,
    ex: &dyn Executor,
) -> Result<Experiment, InputError> {
    let raw: ExperimentFile = parse_toml(text, file)?;
    let name = raw.name.unwrap_or_else(|| default_name.to_string());
    check_name(&name).map_err(|r| r.in_file(file))?;
    if raw.scenarios.is_empty() && raw.generated.is_empty() {
        return Err(InputError::new(
            file,
            "scenarios",
            "list at least one scenario (or give a [[generated]] table)",
        ));
    }
    let mut scenarios = vec![];
    for (i, label) in raw.scenarios.iter().enumerate() {
        let field = format!("scenarios[{i}]");
        if scenarios.iter().any(|(l, _): &(String, _)| l == label) {
            return Err(InputError::new(
                file,
                &field,
                format!("{label} is listed twice"),
            ));
        }
        let s = resolve_scenario(label, base_dir)
            .map_err(|e| InputError::new(file, &field, e.to_string()))?;
        scenarios.push((label.clone(), Arc::new(s)));
    }
    scenarios.extend(super::generated::scenarios(&raw.generated, file)?);
    if raw.planners.is_empty() {
        return Err(InputError::new(
            file,
            "planners",
            "list at least one planner",
        ));
    }
    let planners = components(&raw.planners, file, "planners", &|v| ex.check_planner(v))?;
    let (trackers, presets, tracking) = match raw.tracking {
        None => {
            let trackers = components(&raw.trackers, file, "trackers", &|v| ex.check_tracker(v))?;
            if trackers.is_empty() {
                if raw.presets.as_ref().is_some_and(|p| !p.is_empty()) {
                    return Err(InputError::new(
                        file,
                        "presets",
                        "presets apply to tracking: list `trackers` too",
                    ));
                }
                (trackers, vec![], Tracking::None)
            } else {
                let presets = presets(raw.presets, file, "presets", base_dir)?;
                (trackers, presets, Tracking::Every)
            }
        }
        Some(t) => {
            if !raw.trackers.is_empty() || raw.presets.is_some() {
                let field = if raw.trackers.is_empty() {
                    "presets"
                } else {
                    "trackers"
                };
                return Err(InputError::new(
                    file,
                    field,
                    "give trackers and presets either at the top level (every run tracked) or in [tracking] (some planners' plans tracked), not both",
                ));
            }
            let trackers = components(&t.trackers, file, "tracking.trackers", &|v| {
                ex.check_tracker(v)
            })?;
            if trackers.is_empty() {
                return Err(InputError::new(
                    file,
                    "tracking.trackers",
                    "list at least one tracker",
                ));
            }
            let presets = presets(t.presets, file, "tracking.presets", base_dir)?;
            let plans = tracked_plans(t.plans, &planners, file)?;
            (trackers, presets, Tracking::Plans(plans))
        }
    };
    let seeds = seeds(&raw.seeds, file)?;
    let iterations = match raw.limits.iterations {
        Some(n) => Some(
            ITERATIONS
                .check("limits.iterations", n as f64)
                .map(|_| n as u64)
                .map_err(|r| InputError::new(file, "limits.iterations", r.reason))?,
        ),
        None => None,
    };
    let time_s = match raw.limits.time {
        Some(t) => {
            time_limit(t).map_err(|r| r.under("limits.time").in_file(file))?;
            Some(t)
        }
        None => None,
    };
    if iterations.is_none() && time_s.is_none() {
        return Err(InputError::new(
            file,
            "limits",
            "give `iterations` and/or `time`",
        ));
    }
    let replays = match &raw.replays {
        Some(p) => p
            .parse::<ReplayPolicy>()
            .map_err(|why| InputError::new(file, "replays", why))?,
        None => ReplayPolicy::default(),
    };
    let combos = trackers.len() * presets.len();
    let per_seed = match &tracking {
        Tracking::None => Some(planners.len()),
        Tracking::Every => planners.len().checked_mul(combos),
        Tracking::Plans(p) => p
            .len()
            .checked_mul(combos)
            .and_then(|t| t.checked_add(planners.len())),
    };
    let runs = per_seed
        .and_then(|n| n.checked_mul(scenarios.len()))
        .and_then(|n| n.checked_mul(seeds.len()))
        .filter(|n| *n <= MAX_RUNS);
    if runs.is_none() {
        return Err(InputError::new(
            file,
            "seeds",
            format!(
                "the run matrix ({} scenarios × {} planner runs (planning and tracking) per seed × {} seeds) has more than {MAX_RUNS} runs",
                scenarios.len(),
                per_seed.map_or("too many".to_string(), |n| n.to_string()),
                seeds.len()
            ),
        ));
    }
    let experiment = Experiment {
        name,
        description: raw.description,
        source: file.to_string(),
        text: text.to_string(),
        scenarios,
        planners,
        trackers,
        presets,
        tracking,
        seeds,
        limits: RunLimits { iterations, time_s },
        replays,
    };
    // what only a whole run can tell (a planner's `planar` against a scenario's medium): one
    // seed of each combination
    let first_seed = experiment.seeds[0];
    for spec in &experiment.runs_where(|_, seed| seed == first_seed) {
        ex.check_run(spec)
            .map_err(|(field, reason)| InputError::new(file, field, reason))?;
    }
    Ok(experiment)
}
