//! Ablation of the simulated plant: which disturbance terms make the tracking error.
//!
//! From a base preset (`hardware`), [`variants`] makes `all` (the base), `none` (every term
//! off), and for every term the base has on, `no-TERM` (that term switched off, the rest on)
//! and `only-TERM` (that term alone). Every variant tracks the same plans with the same seeds:
//! each term draws from its own random stream, so switching one term leaves the others' draws
//! unchanged and runs pair by seed. [`contributions`] turns the runs into one row per term:
//!
//! - **off in turn**: the median over seeds of `e(all) − e(no-TERM)`, what the term adds on top
//!   of every other term;
//! - **alone**: the median over seeds of `e(only-TERM) − e(none)`, what the term does by itself;
//!
//! with `e` the run's `rms_error_bl` (the observed-position path error, what a rig measures).

use crate::metrics::Metric;
use std::collections::BTreeMap;

use magbench_env::plant::DisturbancePreset;

use crate::run::RunRecord;
use crate::stats::quantile::median;

/// One preset of the ablation.
#[derive(Debug, Clone, PartialEq)]
pub struct AblationVariant {
    /// `all`, `none`, `no-TERM` or `only-TERM` (a term's dots become dashes).
    pub name: String,
    /// The preset.
    pub preset: DisturbancePreset,
}

/// The file-name form of a term (`camera.noise` → `camera-noise`).
pub fn slug(term: &str) -> String {
    term.replace('.', "-")
}

/// The terms of `base` that are on, in [`DisturbancePreset::TERMS`] order.
pub fn terms_on(base: &DisturbancePreset) -> Vec<&'static str> {
    DisturbancePreset::TERMS
        .into_iter()
        .filter(|t| base.enabled(t) == Some(true))
        .collect()
}

/// The ablation's presets: `all`, `none`, then `no-TERM` and `only-TERM` for each term on.
pub fn variants(base: &DisturbancePreset) -> Vec<AblationVariant> {
    let terms = terms_on(base);
    let with = |name: String, on: &dyn Fn(&str) -> bool| {
        let mut p = base.clone();
        for t in &terms {
            p.set_enabled(t, on(t)).expect("a known term");
        }
        p.name = format!("{}:{name}", base.name);
        AblationVariant { name, preset: p }
    };
    let mut out = vec![
        with("all".into(), &|_| true),
        with("none".into(), &|_| false),
    ];
    for t in &terms {
        out.push(with(format!("no-{}", slug(t)), &|u| u != *t));
        out.push(with(format!("only-{}", slug(t)), &|u| u == *t));
    }
    out
}

/// One term's row of the ablation table.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TermRow {
    /// The term.
    pub term: String,
    /// Median of `e(all) − e(no-TERM)` over seeds (BL).
    pub off_in_turn_bl: f64,
    /// Median of `e(only-TERM) − e(none)` over seeds (BL).
    pub alone_bl: f64,
    /// Median `e(no-TERM)` (BL).
    pub without_median_bl: f64,
    /// Median `e(only-TERM)` (BL).
    pub only_median_bl: f64,
    /// Seeds paired.
    pub seeds: usize,
}

/// The error `e` of every run, by variant and seed; a variant's runs are found by their
/// preset label, `label(variant)`.
fn by_variant(runs: &[RunRecord]) -> BTreeMap<String, BTreeMap<u64, f64>> {
    let mut out: BTreeMap<String, BTreeMap<u64, f64>> = BTreeMap::new();
    for r in runs {
        if let Some(e) = r.get(Metric::RmsError).filter(|e| e.is_finite()) {
            out.entry(variant_of(&r.preset))
                .or_default()
                .insert(r.seed, e);
        }
    }
    out
}

/// The experiment label of a variant's preset file.
pub fn label(variant: &str) -> String {
    format!("presets/{variant}.toml")
}

/// The variant of an experiment label: of a preset file (`presets/no-flow.toml`, the inverse
/// of [`label`]) or of a variant label (`hardware:no-flow`, see [`variant`]).
pub fn variant_of(label: &str) -> String {
    let stem = label
        .trim_start_matches("presets/")
        .trim_end_matches(".toml");
    stem.rsplit_once(':').map_or(stem, |(_, v)| v).to_string()
}

/// The variant called `name` (`all`, `none`, `no-TERM`, `only-TERM`) of `base`, as
/// [`variants`] makes it; `None` if `base` has no such variant. An experiment names it
/// `BASE:NAME` (`hardware:no-camera-noise`).
pub fn variant(base: &DisturbancePreset, name: &str) -> Option<DisturbancePreset> {
    variants(base)
        .into_iter()
        .find(|v| v.name == name)
        .map(|v| v.preset)
}

/// The term whose [`slug`] is `s` (`camera-noise` → `camera.noise`).
pub fn term_of(s: &str) -> Option<&'static str> {
    DisturbancePreset::TERMS.into_iter().find(|t| slug(t) == s)
}

/// The median over seeds present in both of `a − b`.
fn paired(a: &BTreeMap<u64, f64>, b: &BTreeMap<u64, f64>) -> (f64, usize) {
    let d: Vec<f64> = a
        .iter()
        .filter_map(|(s, x)| b.get(s).map(|y| x - y))
        .collect();
    (median(&d).unwrap_or(f64::NAN), d.len())
}

fn med(m: Option<&BTreeMap<u64, f64>>) -> f64 {
    m.and_then(|m| median(&m.values().copied().collect::<Vec<_>>()))
        .unwrap_or(f64::NAN)
}

/// One row per term of `terms` from the ablation's runs, largest "off in turn" first.
pub fn contributions(runs: &[RunRecord], terms: &[&str]) -> Vec<TermRow> {
    let v = by_variant(runs);
    let empty = BTreeMap::new();
    let get = |name: &str| v.get(name).unwrap_or(&empty);
    let mut rows: Vec<TermRow> = terms
        .iter()
        .map(|t| {
            let (no, only) = (format!("no-{}", slug(t)), format!("only-{}", slug(t)));
            let (off, n1) = paired(get("all"), get(&no));
            let (alone, n2) = paired(get(&only), get("none"));
            TermRow {
                term: t.to_string(),
                off_in_turn_bl: off,
                alone_bl: alone,
                without_median_bl: med(v.get(&no)),
                only_median_bl: med(v.get(&only)),
                seeds: n1.min(n2),
            }
        })
        .collect();
    rows.sort_by(|a, b| b.off_in_turn_bl.total_cmp(&a.off_in_turn_bl));
    rows
}

/// Median `e` of every variant (`all`, `none` first).
pub fn variant_medians(runs: &[RunRecord]) -> Vec<(String, f64, usize)> {
    let v = by_variant(runs);
    let mut out: Vec<(String, f64, usize)> = v
        .iter()
        .map(|(k, m)| (k.clone(), med(Some(m)), m.len()))
        .collect();
    out.sort_by_key(|(k, _, _)| match k.as_str() {
        "all" => 0,
        "none" => 1,
        _ => 2,
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variants_switch_each_term_off_in_turn_and_alone() {
        let hw = DisturbancePreset::hardware();
        let terms = terms_on(&hw);
        assert_eq!(
            terms.len(),
            DisturbancePreset::TERMS.len() - 2,
            "all but drift and camera.pixels"
        );
        let v = variants(&hw);
        assert_eq!(v.len(), 2 + 2 * terms.len());
        assert_eq!(v[0].preset.name, "hardware:all");
        for t in &terms {
            let no = v
                .iter()
                .find(|x| x.name == format!("no-{}", slug(t)))
                .unwrap();
            let only = v
                .iter()
                .find(|x| x.name == format!("only-{}", slug(t)))
                .unwrap();
            for u in &terms {
                assert_eq!(no.preset.enabled(u), Some(u != t), "no-{t}: {u}");
                assert_eq!(only.preset.enabled(u), Some(u == t), "only-{t}: {u}");
            }
            // a variant is a valid preset file
            let text = no.preset.to_toml();
            assert_eq!(DisturbancePreset::parse(&text, "x").unwrap(), no.preset);
        }
        for x in &v {
            assert_eq!(
                variant(&hw, &x.name).as_ref(),
                Some(&x.preset),
                "{}",
                x.name
            );
            assert_eq!(variant_of(&format!("hardware:{}", x.name)), x.name);
            assert_eq!(variant_of(&label(&x.name)), x.name);
        }
        assert_eq!(variant(&hw, "no-drift"), None, "drift is off in hardware");
        assert_eq!(term_of("camera-noise"), Some("camera.noise"));
        assert_eq!(term_of("camera.noise"), None);
        let none = &v[1].preset;
        assert!(
            DisturbancePreset::TERMS
                .iter()
                .all(|t| none.enabled(t) == Some(false))
        );
    }

    fn run(variant: &str, seed: u64, e: f64) -> RunRecord {
        let mut r = RunRecord::example();
        r.preset = label(variant);
        r.seed = seed;
        r.set(Metric::RmsError, Some(e));
        r
    }

    #[test]
    fn contributions_pair_runs_by_seed() {
        let mut runs = vec![];
        for seed in 0..3 {
            let s = seed as f64 * 0.01;
            runs.push(run("all", seed, 0.30 + s));
            runs.push(run("none", seed, 0.01 + s));
            runs.push(run("no-flow", seed, 0.10 + s)); // flow adds 0.2 on top
            runs.push(run("only-flow", seed, 0.21 + s)); // and 0.2 alone
            runs.push(run("no-brownian", seed, 0.30 + s)); // brownian: nothing
            runs.push(run("only-brownian", seed, 0.01 + s));
        }
        let rows = contributions(&runs, &["brownian", "flow"]);
        assert_eq!(rows[0].term, "flow", "largest first");
        assert!((rows[0].off_in_turn_bl - 0.2).abs() < 1e-12);
        assert!((rows[0].alone_bl - 0.2).abs() < 1e-12);
        assert_eq!(rows[0].seeds, 3);
        assert!(rows[1].off_in_turn_bl.abs() < 1e-12 && rows[1].alone_bl.abs() < 1e-12);
        let m = variant_medians(&runs);
        assert_eq!((m[0].0.as_str(), m[1].0.as_str()), ("all", "none"));
        assert!((m[0].1 - 0.31).abs() < 1e-12);
    }
}
