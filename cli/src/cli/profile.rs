//! `magbench results profile DIR`: the report's comparison across problems as Markdown: the
//! performance profile ρ(τ) at chosen τ with the fraction solved, and the paired comparison
//! of every pair of planners. The figures come from the computations the report's "Across
//! problems" section draws (`compare::profile`, `compare::paired`).

use std::path::Path;

use magbench_env::input::Bound;

use super::number::checked;
use crate::Error;
use crate::compare::instances::Instances;
use crate::compare::paired::paired;
use crate::compare::profile::profile;
use crate::results::{lock, store};
use crate::table::Table;

/// The τ of `--tau`.
pub const TAU: Bound = Bound::closed(
    1.0,
    1e9,
    "",
    "τ is a planner's time over the best planner's time on a problem",
);

/// The τ printed when `--tau` is not given.
pub const DEFAULT_TAUS: &[f64] = &[1.0, 2.0, 10.0];

/// Prints the Markdown of results folder `dir` at each τ of `taus` (`--tau`).
pub fn run(dir: &Path, taus: &[f64]) -> Result<String, Error> {
    for &tau in taus {
        checked("--tau", &TAU, tau)?;
    }
    if !dir.is_dir() {
        return Err(Error::arg(
            "DIR",
            format!("{}: not a folder", dir.display()),
        ));
    }
    let _lock = lock::shared(dir, "DIR")?;
    let runs = store::read_runs(dir)?;
    let t = Instances::of(&runs);
    if t.problems.len() < 2 || t.planners.is_empty() {
        return Err(Error::arg(
            "DIR",
            format!(
                "{}: runs.csv: planning runs of {} problems and {} planners; a profile needs \
                 two or more problems",
                dir.display(),
                t.problems.len(),
                t.planners.len()
            ),
        ));
    }
    Ok(markdown(&t, taus))
}

/// The profile table (one row per planner: ρ at each of `taus`, then the fraction solved)
/// and the paired table (one row per pair of planners) of `t`, as Markdown.
pub fn markdown(t: &Instances, taus: &[f64]) -> String {
    let mut at = taus.to_vec();
    // the largest finite number: ρ there is the fraction of problems solved
    at.push(f64::MAX);
    let rho = profile(&t.time, &at);
    let unsolved = (0..t.problems.len())
        .filter(|&i| t.time.iter().all(|row| !row[i].is_finite()))
        .count();
    let mut out = format!(
        "{} problems, {} planners; {unsolved} unsolved by every planner.\n\n",
        t.problems.len(),
        t.planners.len()
    );
    let mut head: Vec<String> = vec!["planner".into()];
    head.extend(taus.iter().map(|tau| format!("ρ({tau})")));
    head.push("solved".into());
    let head: Vec<&str> = head.iter().map(String::as_str).collect();
    let mut profile_table = Table::new(&head);
    for (name, r) in t.planners.iter().zip(&rho) {
        let mut row = vec![format!("`{name}`")];
        row.extend(r.iter().map(|v| format!("{v:.2}")));
        profile_table.row(row);
    }
    out.push_str(&profile_table.markdown());
    if t.planners.len() < 2 {
        return out;
    }
    let mut pairs = Table::new(&[
        "A vs B",
        "problems",
        "A faster / B faster / ties",
        "A's win rate (95% CI)",
        "time A / time B (95% CI)",
        "both solved",
    ]);
    let pct = |v: f64| {
        if v.is_nan() {
            "–".to_string()
        } else {
            format!("{:.0}%", 100.0 * v)
        }
    };
    for a in 0..t.planners.len() {
        for b in a + 1..t.planners.len() {
            let p = paired(&t.time[a], &t.time[b]);
            let ratio = match p.ratio {
                Some(r) => format!("{} [{}, {}]", two(r), two(p.ratio_ci.0), two(p.ratio_ci.1)),
                None => "–".into(),
            };
            pairs.row(vec![
                format!("`{}` vs `{}`", t.planners[a], t.planners[b]),
                p.problems.to_string(),
                format!("{} / {} / {}", p.wins, p.losses, p.ties),
                format!(
                    "{} [{}, {}]",
                    pct(p.win_rate),
                    pct(p.win_ci.0),
                    pct(p.win_ci.1)
                ),
                ratio,
                p.both_solved.to_string(),
            ]);
        }
    }
    out.push('\n');
    out.push_str(&pairs.markdown());
    out
}

/// `v` with two decimals, `∞` when infinite.
fn two(v: f64) -> String {
    if v.is_infinite() {
        "∞".into()
    } else {
        format!("{v:.2}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const INF: f64 = f64::INFINITY;

    fn instances(time: Vec<Vec<f64>>) -> Instances {
        let n = time[0].len();
        Instances {
            planners: (0..time.len()).map(|p| format!("p{p}")).collect(),
            problems: (0..n).map(|i| format!("s{i}")).collect(),
            solved: vec![vec![(0, 0); n]; time.len()],
            difficulty: vec![Default::default(); n],
            time,
        }
    }

    #[test]
    fn profile_rows_and_pairs_from_known_times() {
        // p0 fastest on problems 0 and 1, p1 on 2; problem 3 unsolved by both.
        let t = instances(vec![vec![1.0, 2.0, 8.0, INF], vec![3.0, 2.5, 2.0, INF]]);
        let md = markdown(&t, &[1.0, 2.0, 10.0]);
        assert!(
            md.starts_with("4 problems, 2 planners; 1 unsolved by every planner."),
            "{md}"
        );
        assert!(
            md.contains("| planner | ρ(1) | ρ(2) | ρ(10) | solved |"),
            "{md}"
        );
        // p0: ratios 1, 1, 4, ∞; p1: 3, 1.25, 1, ∞
        assert!(md.contains("| `p0` | 0.50 | 0.50 | 0.75 | 0.75 |"), "{md}");
        assert!(md.contains("| `p1` | 0.25 | 0.50 | 0.75 | 0.75 |"), "{md}");
        assert!(md.contains("| `p0` vs `p1` | 4 | 2 / 1 / 1 |"), "{md}");
        // three problems both solved: the signed-rank interval is open
        assert!(md.contains("[0.00, ∞] | 3 |"), "{md}");
    }

    #[test]
    fn bad_tau_and_a_folder_without_runs_exit_2_naming_the_option() {
        let dir = tempfile::tempdir().unwrap();
        let e = run(dir.path(), &[0.5]).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(
            e.to_string().contains("--tau") && e.to_string().contains("0.5"),
            "{e}"
        );
        let e = run(dir.path(), &[f64::NAN]).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        let e = run(dir.path(), DEFAULT_TAUS).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(
            e.to_string().contains("DIR") && e.to_string().contains("two or more problems"),
            "{e}"
        );
        let e = run(&dir.path().join("none"), DEFAULT_TAUS).unwrap_err();
        assert!(e.to_string().contains("not a folder"), "{e}");
    }
}
