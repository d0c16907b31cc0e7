//! The table of an ablation measurement: per scenario and tracker, what each plant term adds to
//! the tracking error, switched off in turn and alone ([`magbench::ablation`]).
//!
//! The experiment's presets are the variants of one base preset (`hardware:all`,
//! `hardware:none`, `hardware:no-TERM`, `hardware:only-TERM`, or files `presets/NAME.toml` as
//! `magbench ablate` writes them); the terms are those with a `no-TERM` variant.

use std::collections::BTreeMap;

use super::tables::scenario;
use magbench::ablation::{contributions, slug, term_of, variant_of};
use magbench::metrics::Metric;
use magbench::results::summary::group_by;
use magbench::run::RunRecord;
use magbench::table::{Table, median, num};

/// The error the ablation compares (the one [`contributions`] pairs).
const RMS: Metric = Metric::RmsError;

/// A difference in BL with its sign, "–" if not finite.
fn signed(x: f64) -> String {
    match num(x) {
        s if x > 0.0 && x.is_finite() => format!("+{s}"),
        s => s,
    }
}

/// Goals reached and agent contacts of one variant's runs: ("k/n", "k").
fn outcomes(runs: &[&RunRecord]) -> (String, String) {
    let goals = runs.iter().filter(|r| r.reached_goal == Some(true)).count();
    let contacts = runs
        .iter()
        .filter(|r| r.agent_contact == Some(true))
        .count();
    (format!("{goals}/{}", runs.len()), contacts.to_string())
}

/// One (scenario, tracker)'s runs by variant name.
fn by_variant<'a>(runs: &[&'a RunRecord]) -> BTreeMap<String, Vec<&'a RunRecord>> {
    let mut out: BTreeMap<String, Vec<&RunRecord>> = BTreeMap::new();
    for r in runs {
        out.entry(variant_of(&r.preset)).or_default().push(r);
    }
    out
}

/// Per scenario and tracker: a row for every term on (`all`) and for none, each with the
/// median RMS path error of the observed positions (`e`, BL), goals reached and agent
/// contacts; then one row per term, largest "off in turn" first: off in turn (median over
/// seeds of `e(all) − e(no-TERM)`), alone (median of `e(only-TERM) − e(none)`), the median `e`
/// of both variants and their goals and contacts.
pub fn ablation(runs: &[RunRecord]) -> Table {
    let mut t = Table::new(&[
        "scenario",
        "tracker",
        "term",
        "off in turn (BL)",
        "alone (BL)",
        "median e: all but the term / the term alone (BL)",
        "goal reached: all but / alone",
        "agent contact: all but / alone",
    ]);
    let tracked = runs.iter().filter(|r| !r.tracker.is_empty());
    for g in group_by(tracked, |r| (r.scenario.clone(), r.tracker.clone())) {
        let (sc, tracker) = (scenario(&g[0].scenario), g[0].tracker.clone());
        let v = by_variant(&g);
        let median_e = |name: &str| {
            let e: Vec<f64> = v
                .get(name)
                .map(|rs| rs.iter().filter_map(|r| r.get(RMS)).collect())
                .unwrap_or_default();
            median(&e)
        };
        let of = |name: &str| outcomes(v.get(name).map(Vec::as_slice).unwrap_or(&[]));
        for (name, label) in [("all", "every term on"), ("none", "no term on")] {
            let (goals, contacts) = of(name);
            t.row(vec![
                sc.clone(),
                tracker.clone(),
                format!("*{label}*"),
                "–".into(),
                "–".into(),
                median_e(name),
                goals,
                contacts,
            ]);
        }
        let terms: Vec<&str> = v
            .keys()
            .filter_map(|k| k.strip_prefix("no-").and_then(term_of))
            .collect();
        let owned: Vec<RunRecord> = g.iter().map(|r| (*r).clone()).collect();
        for row in contributions(&owned, &terms) {
            let s = slug(&row.term);
            let (no, only) = (format!("no-{s}"), format!("only-{s}"));
            let ((g_no, c_no), (g_only, c_only)) = (of(&no), of(&only));
            t.row(vec![
                sc.clone(),
                tracker.clone(),
                row.term.clone(),
                signed(row.off_in_turn_bl),
                signed(row.alone_bl),
                format!(
                    "{} / {}",
                    num(row.without_median_bl),
                    num(row.only_median_bl)
                ),
                format!("{g_no} / {g_only}"),
                format!("{c_no} / {c_only}"),
            ]);
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use magbench_env::plant::DisturbancePreset;

    fn run(variant: &str, seed: u64, e: f64, goal: bool) -> RunRecord {
        let mut r = RunRecord::example();
        r.tracker = "obc".into();
        r.preset = format!("hardware:{variant}");
        r.seed = seed;
        r.reached_goal = Some(goal);
        r.agent_contact = Some(!goal);
        r.set(Metric::RmsError, Some(e));
        r
    }

    #[test]
    fn each_term_gets_its_paired_differences_and_outcomes() {
        let mut runs = vec![];
        for seed in 0..3 {
            let s = seed as f64 * 0.01;
            runs.push(run("all", seed, 0.30 + s, seed > 0));
            runs.push(run("none", seed, 0.01 + s, true));
            runs.push(run("no-flow", seed, 0.10 + s, true));
            runs.push(run("only-flow", seed, 0.21 + s, seed == 0));
            runs.push(run("no-camera-noise", seed, 0.30 + s, true));
            runs.push(run("only-camera-noise", seed, 0.01 + s, true));
        }
        let t = ablation(&runs);
        assert_eq!(t.rows.len(), 4, "all, none and two terms");
        assert_eq!(t.rows[0][2], "*every term on*");
        assert_eq!(
            (t.rows[0][5].as_str(), t.rows[0][6].as_str()),
            ("0.310", "2/3")
        );
        assert_eq!(t.rows[0][7], "1");
        assert_eq!(t.rows[1][5], "0.0200");
        let flow = &t.rows[2];
        assert_eq!(flow[2], "flow", "largest off in turn first");
        assert_eq!((flow[3].as_str(), flow[4].as_str()), ("+0.200", "+0.200"));
        assert_eq!(flow[5], "0.110 / 0.220");
        assert_eq!((flow[6].as_str(), flow[7].as_str()), ("3/3 / 1/3", "0 / 2"));
        assert_eq!(t.rows[3][2], "camera.noise");
        assert_eq!(t.rows[3][3], "0");
        let text = t.markdown();
        assert!(text.contains("| flow |"), "{text}");
    }

    /// Every ablation measurement runs every variant of `hardware`, so a term added to the
    /// preset is measured (or this test fails until its experiment lists it).
    #[test]
    fn ablation_experiments_list_every_variant_of_hardware() {
        let want: Vec<String> = magbench::ablation::variants(&DisturbancePreset::hardware())
            .into_iter()
            .map(|v| format!("hardware:{}", v.name))
            .collect();
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let ms: Vec<_> = super::super::MEASURES
            .iter()
            .filter(|m| m.name.starts_with("ablation-"))
            .collect();
        assert_eq!(ms.len(), 3);
        for m in ms {
            let e = m.experiment().unwrap();
            let text = std::fs::read_to_string(root.join(e)).unwrap();
            let v: toml::Value = toml::from_str(&text).unwrap();
            let got: Vec<String> = v["presets"]
                .as_array()
                .unwrap()
                .iter()
                .map(|p| p.as_str().unwrap().to_string())
                .collect();
            assert_eq!(got, want, "{e}");
        }
    }

    #[test]
    fn signed_differences() {
        assert_eq!(signed(0.009), "+0.00900");
        assert_eq!(signed(-0.0001), "-1.00e-4");
        assert_eq!(signed(0.0), "0");
        assert_eq!(signed(f64::NAN), "–");
    }
}
