//! A scaling study over a results folder: per planner, the median time to a first solution
//! or the median iterations to it (unsolved runs = +∞) at each problem size, the power law
//! fitted to it ([`super::scaling`]), and a log–log plot of both.

use crate::metrics::Metric;
use std::path::{Path, PathBuf};

use super::instances::median_inf;
use super::scaling::{PowerFit, fit, label_param};
use crate::Error;
use crate::plot::charts::{BandPoint, LineBandChart, Series, W};
use crate::plot::save;
use crate::plot::style::{self, Dash, Family, Look};
use crate::run::RunRecord;

/// What grows with the size: a metric of the first solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// Time to the first solution (s; wall-clock).
    Time,
    /// Iterations to the first solution (machine-independent).
    Iterations,
}

impl Quantity {
    /// Both, in the order `results scaling` prints them.
    pub const ALL: [Quantity; 2] = [Quantity::Time, Quantity::Iterations];

    /// The metric of `runs.csv` it reads.
    pub fn metric(self) -> Metric {
        match self {
            Quantity::Time => Metric::FirstSolutionTime,
            Quantity::Iterations => Metric::FirstSolutionIteration,
        }
    }

    /// Its name in text and plot titles.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Time => "time to 1st solution",
            Quantity::Iterations => "iterations to 1st solution",
        }
    }

    /// Its unit (empty for a count).
    pub fn unit(self) -> &'static str {
        match self {
            Quantity::Time => "s",
            Quantity::Iterations => "",
        }
    }

    /// The suffix of its plot's file name (empty for time).
    fn suffix(self) -> &'static str {
        match self {
            Quantity::Time => "",
            Quantity::Iterations => "-iterations",
        }
    }
}

/// One planner's points and fit.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannerScaling {
    /// Planner label.
    pub planner: String,
    /// `(size, median of the quantity, runs solved, runs)` in increasing size.
    pub points: Vec<(f64, f64, u64, u64)>,
    /// The fit over the sizes with a finite median, if two or more have one.
    pub fit: Option<PowerFit>,
}

/// The size of a run: the `agents` column for `by = "agents"`, else parameter `by` of its
/// generated scenario's label; `None` when the run is not of `family` (a label prefix).
pub fn size_of(r: &RunRecord, family: Option<&str>, by: &str) -> Option<f64> {
    if let Some(f) = family
        && !r.scenario.starts_with(&format!("{f}-"))
    {
        return None;
    }
    if by == "agents" {
        Some(r.agents as f64)
    } else {
        label_param(&r.scenario, by)
    }
}

/// Per planner of the planning runs, the points and fit of quantity `q` against size.
pub fn study(
    runs: &[RunRecord],
    family: Option<&str>,
    by: &str,
    q: Quantity,
) -> Vec<PlannerScaling> {
    let mut out: Vec<PlannerScaling> = vec![];
    let mut sizes: Vec<(String, f64, f64)> = vec![];
    for r in runs.iter().filter(|r| r.tracker.is_empty()) {
        if let Some(s) = size_of(r, family, by) {
            let t = match (r.solved, r.get(q.metric())) {
                (true, Some(t)) => t,
                _ => f64::INFINITY,
            };
            sizes.push((r.planner.clone(), s, t));
        }
    }
    let mut planners: Vec<String> = vec![];
    for (p, _, _) in &sizes {
        if !planners.contains(p) {
            planners.push(p.clone());
        }
    }
    for p in planners {
        let mut ks: Vec<f64> = sizes.iter().filter(|s| s.0 == p).map(|s| s.1).collect();
        ks.sort_by(f64::total_cmp);
        ks.dedup();
        let points: Vec<(f64, f64, u64, u64)> = ks
            .iter()
            .map(|&k| {
                let t: Vec<f64> = sizes
                    .iter()
                    .filter(|s| s.0 == p && s.1 == k)
                    .map(|s| s.2)
                    .collect();
                let solved = t.iter().filter(|t| t.is_finite()).count() as u64;
                (k, median_inf(&t), solved, t.len() as u64)
            })
            .collect();
        let fit = fit(&points.iter().map(|p| (p.0, p.1)).collect::<Vec<_>>());
        out.push(PlannerScaling {
            planner: p,
            points,
            fit,
        });
    }
    out
}

/// The fit as text: `k^1.80 [1.52, 2.08]`.
pub fn fit_text(f: &Option<PowerFit>, by: &str) -> String {
    match f {
        Some(f) if f.ci.0.is_finite() => format!(
            "{by}^{:.2} [{:.2}, {:.2}] over {} sizes",
            f.exponent, f.ci.0, f.ci.1, f.n
        ),
        Some(f) => format!("{by}^{:.2} over {} sizes (no interval)", f.exponent, f.n),
        None => "no fit (fewer than two sizes with a median time)".into(),
    }
}

/// Plots `log₂` of the median of `q` against `log₂ size` per planner with its fitted line
/// into `dir/plots/scaling-[FAMILY-]BY[-iterations]`; returns the stem.
pub fn plot(
    dir: &Path,
    s: &[PlannerScaling],
    family: Option<&str>,
    by: &str,
    q: Quantity,
) -> Result<PathBuf, Error> {
    let mut series = vec![];
    let mut looks = vec![];
    for (i, p) in s.iter().enumerate() {
        let look = style::look(Family::Planner, i);
        looks.push(look);
        series.push(Series {
            label: format!("{}: {}", p.planner, fit_text(&p.fit, by)),
            data: p
                .points
                .iter()
                .map(|&(k, t, _, _)| BandPoint {
                    x: k.log2(),
                    y: if t.is_finite() { t.log2() } else { f64::NAN },
                    lo: f64::NAN,
                    hi: f64::NAN,
                })
                .collect(),
        });
        if let Some(f) = p.fit {
            // the line spans the sizes fitted (those with a finite median), not beyond
            let fitted: Vec<f64> = p
                .points
                .iter()
                .filter(|q| q.1.is_finite() && q.1 > 0.0)
                .map(|q| q.0)
                .collect();
            let (k0, k1) = (fitted[0], fitted[fitted.len() - 1]);
            looks.push(Look {
                dash: Dash::Dashed,
                ..look
            });
            series.push(Series {
                label: format!("{} fit", p.planner),
                data: [k0, k1]
                    .iter()
                    .map(|&k| BandPoint {
                        x: k.log2(),
                        y: (f.factor * k.powf(f.exponent)).log2(),
                        lo: f64::NAN,
                        hi: f64::NAN,
                    })
                    .collect(),
            });
        }
    }
    let what = family.map(|f| format!("{f}: ")).unwrap_or_default();
    let unit = match q.unit() {
        "" => String::new(),
        u => format!(" ({u})"),
    };
    let fig = LineBandChart {
        title: format!("{what}median {} vs {by}", q.name()),
        x_label: format!("log₂ {by}"),
        y_label: format!("log₂ median {}{unit}", q.name()),
        series,
        y_range: None,
        steps: false,
        band_label: String::new(),
        empty_note: "no size with half of its runs solved".into(),
        looks,
        x_log: false,
        width: W,
    };
    let name = match family {
        Some(f) => format!("scaling-{f}-{by}{}", q.suffix()),
        None => format!("scaling-{by}{}", q.suffix()),
    };
    let stem = dir.join("plots").join(name);
    save(&fig, &stem)?;
    Ok(stem)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_each_planner_over_the_family_sizes() {
        let run = |sc: &str, pl: &str, t: Option<f64>| {
            let mut r = RunRecord::example();
            r.scenario = sc.into();
            r.planner = pl.into();
            r.solved = t.is_some();
            r.set(Metric::FirstSolutionTime, t);
            // iterations grow as the time's cube root times 1000
            r.set(
                Metric::FirstSolutionIteration,
                t.map(|t| (1000.0 * t.cbrt()).round()),
            );
            r
        };
        let mut runs = vec![];
        for k in [1u32, 2, 4, 8] {
            let t = 0.01 * (k as f64).powi(2);
            runs.push(run(&format!("serpentine-walls={k}-s0"), "a", Some(t)));
            runs.push(run(&format!("serpentine-walls={k}-s1"), "a", Some(t)));
            runs.push(run(
                &format!("serpentine-walls={k}-s0"),
                "b",
                (k < 8).then_some(0.1),
            ));
        }
        runs.push(run("corridor-length=30-s0", "a", Some(5.0)));
        let s = study(&runs, Some("serpentine"), "walls", Quantity::Time);
        assert_eq!(s.len(), 2);
        assert_eq!(s[0].points.len(), 4);
        let f = s[0].fit.unwrap();
        assert!((f.exponent - 2.0).abs() < 1e-9);
        assert_eq!(s[1].points[3], (8.0, f64::INFINITY, 0, 1));
        assert!(s[1].fit.unwrap().exponent.abs() < 1e-9);
        // iterations: 1000·(0.01 k²)^(1/3) ∝ k^(2/3), up to the rounding to whole iterations
        let it = study(&runs, Some("serpentine"), "walls", Quantity::Iterations);
        let f = it[0].fit.unwrap();
        assert!((f.exponent - 2.0 / 3.0).abs() < 0.01, "{f:?}");
        assert_eq!(it[0].points[0].1, (1000.0f64 * 0.01f64.cbrt()).round());
        assert_eq!(it[1].points[3], (8.0, f64::INFINITY, 0, 1));
    }

    #[test]
    fn plots_time_and_iterations_into_their_own_files() {
        let dir = tempfile::tempdir().unwrap();
        let s = vec![PlannerScaling {
            planner: "a".into(),
            points: vec![(1.0, 10.0, 1, 1), (4.0, 160.0, 1, 1)],
            fit: fit(&[(1.0, 10.0), (4.0, 160.0)]),
        }];
        for q in Quantity::ALL {
            let stem = plot(dir.path(), &s, Some("corridor"), "length", q).unwrap();
            let svg = std::fs::read_to_string(stem.with_extension("svg")).unwrap();
            assert!(svg.contains(q.name()), "{q:?}");
        }
        let plots = dir.path().join("plots");
        assert!(plots.join("scaling-corridor-length.svg").exists());
        assert!(
            plots
                .join("scaling-corridor-length-iterations.svg")
                .exists()
        );
    }
}
