//! `[[generated]]` tables of an experiment file: a scenario family, a grid of parameter values
//! and instance seeds, expanded into generated scenarios beside the listed ones.
//!
//! ```toml
//! [[generated]]
//! family = "serpentine"
//! params = { walls = [1, 2, 4], gap = 4.0 }   # a value or a list of values per parameter
//! instances = 3                               # instance seeds 0..2, or a list [3, 7]
//! ```
//!
//! Each combination of parameter values and each instance seed is one scenario, labelled
//! `FAMILY-KEY=VALUE-...-sSEED` (keys in name order) and drawn as file 0 of that seed
//! (`magbench scenario generate FAMILY --set KEY=VALUE ... --seed SEED` writes the same
//! problem). `bench` keeps the files in `<results>/scenarios/`.

use std::path::Path;
use std::sync::Arc;

use magbench_env::scenario::generate::{Generated, generate_named};
use magbench_env::{InputError, Scenario};
use serde::Deserialize;

/// Most scenarios the `[[generated]]` tables of one experiment expand into.
pub const MAX_GENERATED: usize = 10_000;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct GeneratedTable {
    family: String,
    #[serde(default)]
    params: toml::Table,
    instances: toml::Value,
}

/// A parameter value as `key=value` text takes it; `None` for a table or a date.
fn scalar(v: &toml::Value) -> Option<String> {
    match v {
        toml::Value::String(s) => Some(s.clone()),
        toml::Value::Integer(i) => Some(i.to_string()),
        toml::Value::Float(x) => Some(x.to_string()),
        toml::Value::Boolean(b) => Some(b.to_string()),
        _ => None,
    }
}

/// The instance seeds: a count n (0..n) or a list.
fn instances(v: &toml::Value, field: &str, file: &str) -> Result<Vec<u64>, InputError> {
    let err = |r: String| InputError::new(file, field, r);
    match v {
        toml::Value::Integer(n) if (1..=MAX_GENERATED as i64).contains(n) => {
            Ok((0..*n as u64).collect())
        }
        toml::Value::Array(a) if !a.is_empty() && a.len() <= MAX_GENERATED => a
            .iter()
            .map(|s| match s {
                toml::Value::Integer(i) if *i >= 0 => Ok(*i as u64),
                other => Err(err(format!("a seed is a whole number ≥ 0, got {other}"))),
            })
            .collect(),
        other => Err(err(format!(
            "a count in [1, {MAX_GENERATED}] or a non-empty list of seeds, got {other}"
        ))),
    }
}

/// Expands the `[[generated]]` tables (raw TOML values) of experiment `file` into labelled
/// generated problems, in table order, then parameter combination, then seed.
pub fn expand(tables: &[toml::Value], file: &str) -> Result<Vec<(String, Generated)>, InputError> {
    let mut out: Vec<(String, Generated)> = Vec::new();
    for (i, v) in tables.iter().enumerate() {
        let field = format!("generated[{i}]");
        let t: GeneratedTable = v
            .clone()
            .try_into()
            .map_err(|e: toml::de::Error| InputError::new(file, &field, e.message().to_string()))?;
        // every key's values, in name order
        let mut axes: Vec<(String, Vec<String>)> = Vec::new();
        let mut keys: Vec<&String> = t.params.keys().collect();
        keys.sort();
        for k in keys {
            let f = format!("{field}.params.{k}");
            let bad = || InputError::new(file, &f, "a value or a non-empty list of values");
            let values = match &t.params[k] {
                toml::Value::Array(a) if !a.is_empty() => a
                    .iter()
                    .map(scalar)
                    .collect::<Option<Vec<_>>>()
                    .ok_or_else(bad)?,
                v => vec![scalar(v).ok_or_else(bad)?],
            };
            axes.push((k.clone(), values));
        }
        let seeds = instances(&t.instances, &format!("{field}.instances"), file)?;
        let combos = axes
            .iter()
            .try_fold(seeds.len(), |n, (_, v)| n.checked_mul(v.len()))
            .filter(|n| out.len() + n <= MAX_GENERATED);
        let Some(combos) = combos else {
            return Err(InputError::new(
                file,
                &field,
                format!("the tables expand into more than {MAX_GENERATED} scenarios"),
            ));
        };
        for c in 0..combos {
            // combination c: seed fastest, then the last key's values, ...
            let seed = seeds[c % seeds.len()];
            let mut rest = c / seeds.len();
            let mut params: Vec<(String, String)> = Vec::new();
            for (k, values) in axes.iter().rev() {
                params.push((k.clone(), values[rest % values.len()].clone()));
                rest /= values.len();
            }
            params.reverse();
            let mut label = t.family.clone();
            for (k, v) in &params {
                label += &format!("-{k}={v}");
            }
            label += &format!("-s{seed}");
            let g = generate_named(file, &t.family, &params, seed, 0, &label).map_err(|e| {
                let f = match e.field.strip_prefix("param.") {
                    Some(k) => format!("{field}.params.{k}"),
                    None if e.field == "param" => format!("{field}.params"),
                    None => format!("{field}.{}", e.field),
                };
                InputError::new(file, f, e.reason)
            })?;
            if out.iter().any(|(l, _)| *l == label) {
                return Err(InputError::new(
                    file,
                    &field,
                    format!("{label} is generated twice"),
                ));
            }
            out.push((label, g));
        }
    }
    Ok(out)
}

/// The scenarios of [`expand`], as an experiment holds them.
pub fn scenarios(
    tables: &[toml::Value],
    file: &str,
) -> Result<Vec<(String, Arc<Scenario>)>, InputError> {
    Ok(expand(tables, file)?
        .into_iter()
        .map(|(label, g)| (label, Arc::new(g.scenario)))
        .collect())
}

/// Writes the generated scenario files of experiment text `text` (read from `file`) into
/// `dir/scenarios/`; nothing when it has no `[[generated]]` table.
pub fn keep_files(text: &str, file: &str, dir: &Path) -> Result<(), crate::Error> {
    let tables = match toml::from_str::<toml::Table>(text) {
        Ok(mut t) => match t.remove("generated") {
            Some(toml::Value::Array(a)) => a,
            _ => return Ok(()),
        },
        Err(_) => return Ok(()),
    };
    let folder = dir.join("scenarios");
    std::fs::create_dir_all(&folder)?;
    for (_, g) in expand(&tables, file)? {
        let path = folder.join(&g.file_name);
        std::fs::write(&path, &g.text)
            .map_err(|e| crate::Error::Failed(format!("{}: {e}", path.display())))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests;
