//! Planted regressions, identical folders and an A/A check of the verdicts, on synthetic runs
//! drawn from seeded generators (deterministic).

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::report::{inconclusive, regressions};
use super::*;
use crate::metrics::Metric;
use crate::run::RunRecord;
use crate::run::Status;

/// One configuration's runs: seed `seeds[i]` has RMS error `rms[i]` and succeeds if `ok[i]`.
fn runs(seeds: &[u64], rms: &[f64], ok: &[bool]) -> Vec<RunRecord> {
    seeds
        .iter()
        .enumerate()
        .map(|(i, &seed)| {
            let mut r = RunRecord::example();
            (r.run, r.seed, r.scenario, r.planner, r.tracker, r.preset) =
                (i, seed, "s".into(), "p".into(), "t".into(), "ideal".into());
            r.solved = true;
            r.status = Status::Exact;
            r.reached_goal = Some(ok[i]);
            r.agent_contact = Some(false);
            r.set(Metric::RmsError, Some(rms[i]));
            r.set(Metric::PlanTime, Some(0.0));
            r
        })
        .collect()
}

fn row<'a>(rows: &'a [Comparison], metric: &str) -> &'a Comparison {
    rows.iter().find(|r| r.metric == metric).unwrap()
}

fn verdict(rows: &[Comparison], metric: &str) -> Verdict {
    row(rows, metric).verdict
}

fn seeds(from: u64, n: usize) -> Vec<u64> {
    (from..from + n as u64).collect()
}

/// `n` log-normal values with median `median` and log-sd `sd`.
fn lognormal(rng: &mut ChaCha8Rng, n: usize, median: f64, sd: f64) -> Vec<f64> {
    (0..n)
        .map(|_| {
            let (u, v): (f64, f64) = (rng.random_range(1e-12..1.0), rng.random_range(0.0..1.0));
            let z = (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos();
            median * (sd * z).exp()
        })
        .collect()
}

fn bernoulli(rng: &mut ChaCha8Rng, n: usize, p: f64) -> Vec<bool> {
    (0..n).map(|_| rng.random_range(0.0..1.0) < p).collect()
}

const TOL: Tolerances = Tolerances {
    alpha: 0.05,
    success: 0.10,
    relative: 0.10,
    time: 1.0,
    wall_clock: true,
    gate_time: false,
};

#[test]
fn identical_folders_are_ok_with_zero_width_intervals_at_any_size() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for n in [3, 8, 40] {
        let e = lognormal(&mut rng, n, 0.1, 0.5);
        let ok = bernoulli(&mut rng, n, 0.6);
        let a = runs(&seeds(0, n), &e, &ok);
        let rows = compare(&a, &a, &TOL);
        assert!(rows.len() >= 3);
        for r in &rows {
            assert_eq!(r.verdict, Verdict::Ok, "{n} seeds: {r:?}");
            assert_eq!(r.design, Design::Paired(n));
            match r.change {
                Change::Points { diff, lo, hi }
                | Change::Relative { rel: diff, lo, hi }
                | Change::Absolute { diff, lo, hi } => {
                    assert_eq!((diff, lo, hi), (0.0, 0.0, 0.0), "{r:?}")
                }
                Change::None => panic!("{r:?}"),
            }
        }
        assert_eq!(failures(&rows, OnInconclusive::Fail), 0);
    }
}

#[test]
fn a_success_drop_from_8_of_8_to_4_of_8_is_never_ok() {
    let e = vec![0.1; 8];
    let all = vec![true; 8];
    let half: Vec<bool> = (0..8).map(|i| i % 2 == 0).collect();
    let base = runs(&seeds(0, 8), &e, &all);
    // paired (same seeds) and unpaired (other seeds)
    for cand in [
        runs(&seeds(0, 8), &e, &half),
        runs(&seeds(100, 8), &e, &half),
    ] {
        let rows = compare(&base, &cand, &TOL);
        let v = verdict(&rows, "success_rate");
        assert!(
            matches!(v, Verdict::Regression | Verdict::Inconclusive),
            "{v:?}: {}",
            table(&rows, &TOL)
        );
        assert!(failures(&rows, OnInconclusive::Fail) > 0);
    }
}

#[test]
fn a_success_drop_from_40_of_40_to_20_of_40_is_a_regression() {
    let e = vec![0.1; 40];
    let all = vec![true; 40];
    let half: Vec<bool> = (0..40).map(|i| i % 2 == 0).collect();
    let base = runs(&seeds(0, 40), &e, &all);
    for cand in [
        runs(&seeds(0, 40), &e, &half),
        runs(&seeds(100, 40), &e, &half),
    ] {
        let rows = compare(&base, &cand, &TOL);
        assert_eq!(
            verdict(&rows, "success_rate"),
            Verdict::Regression,
            "{}",
            table(&rows, &TOL)
        );
        assert_eq!(regressions(&rows), 1);
        let Change::Points { diff, lo, hi } = row(&rows, "success_rate").change else {
            panic!()
        };
        assert!(
            diff == -0.5 && lo < -0.5 && hi < -0.1 && lo >= -1.0,
            "{lo} {hi}"
        );
    }
}

#[test]
fn a_median_30_percent_higher_over_many_seeds_is_a_regression() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let n = 60;
    let ok = vec![true; n];
    let b = lognormal(&mut rng, n, 0.1, 0.3);
    // unpaired: other seeds, the same spread, the median 30% higher
    let c = lognormal(&mut rng, n, 0.13, 0.3);
    let rows = compare(
        &runs(&seeds(0, n), &b, &ok),
        &runs(&seeds(1000, n), &c, &ok),
        &TOL,
    );
    assert_eq!(
        verdict(&rows, "rms_error_bl"),
        Verdict::Regression,
        "{}",
        table(&rows, &TOL)
    );
    // paired: each seed 30% higher, with 5% per-seed noise
    let noise = lognormal(&mut rng, n, 1.3, 0.05);
    let c: Vec<f64> = b.iter().zip(&noise).map(|(x, k)| x * k).collect();
    let rows = compare(
        &runs(&seeds(0, n), &b, &ok),
        &runs(&seeds(0, n), &c, &ok),
        &TOL,
    );
    assert_eq!(verdict(&rows, "rms_error_bl"), Verdict::Regression);
    let Change::Relative { rel, lo, hi } = row(&rows, "rms_error_bl").change else {
        panic!()
    };
    assert!(
        lo > 0.1 && lo < rel && rel < hi && (rel - 0.3).abs() < 0.05,
        "{rel} {lo} {hi}"
    );
}

#[test]
fn a_doubled_tracking_error_is_a_regression_and_intervals_stay_above_minus_100_percent() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let n = 20;
    let ok = vec![true; n];
    let b = lognormal(&mut rng, n, 0.1, 0.4);
    let doubled: Vec<f64> = b.iter().map(|x| 2.0 * x).collect();
    let base = runs(&seeds(0, n), &b, &ok);
    let rows = compare(&base, &runs(&seeds(0, n), &doubled, &ok), &TOL);
    assert_eq!(verdict(&rows, "rms_error_bl"), Verdict::Regression);
    let Change::Relative { rel, .. } = row(&rows, "rms_error_bl").change else {
        panic!()
    };
    assert!((rel - 1.0).abs() < 1e-9, "{rel}");
    // unpaired, other seeds: still shown
    let c = lognormal(&mut rng, n, 0.2, 0.4);
    let rows = compare(&base, &runs(&seeds(500, n), &c, &ok), &TOL);
    assert_eq!(verdict(&rows, "rms_error_bl"), Verdict::Regression);
    // the reverse (the error halved) is ok, shown better
    let rows = compare(&runs(&seeds(0, n), &doubled, &ok), &base, &TOL);
    let r = row(&rows, "rms_error_bl");
    assert!(r.verdict == Verdict::Ok && r.better, "{r:?}");
    // a wide spread over few seeds: the interval is wide but never below −100%
    let wide_b = lognormal(&mut rng, 6, 0.1, 2.0);
    let wide_c = lognormal(&mut rng, 6, 0.1, 2.0);
    let rows = compare(
        &runs(&seeds(0, 6), &wide_b, &[true; 6]),
        &runs(&seeds(9, 6), &wide_c, &[true; 6]),
        &TOL,
    );
    let Change::Relative { lo, .. } = row(&rows, "rms_error_bl").change else {
        panic!()
    };
    assert!(lo > -1.0, "{lo}");
}

#[test]
fn not_significant_is_inconclusive_with_the_seeds_that_would_resolve_it() {
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let ok = vec![true; 8];
    let b = lognormal(&mut rng, 8, 0.1, 0.5);
    let c = lognormal(&mut rng, 8, 0.1, 0.5);
    let rows = compare(
        &runs(&seeds(0, 8), &b, &ok),
        &runs(&seeds(100, 8), &c, &ok),
        &TOL,
    );
    let r = row(&rows, "rms_error_bl");
    assert_eq!(r.verdict, Verdict::Inconclusive, "{}", table(&rows, &TOL));
    assert!(r.seeds_needed.is_some_and(|n| n > 8), "{r:?}");
    assert!(table(&rows, &TOL).contains("inconclusive (~"));
    assert_eq!(
        inconclusive(&rows),
        2,
        "success 8/8 against 8/8 unpaired too"
    );
    assert_eq!(failures(&rows, OnInconclusive::Fail), 2);
    assert_eq!(failures(&rows, OnInconclusive::Pass), 0);
    let text = footer(&rows, &TOL, OnInconclusive::Fail);
    assert!(
        text.contains("result: FAIL") && text.contains("2 inconclusive"),
        "{text}"
    );
    let text = footer(&rows, &TOL, OnInconclusive::Pass);
    assert!(text.contains("result: pass"), "{text}");
}

/// Over 100 comparisons of two samples of the same distribution on different seeds, the
/// share with one or more regression verdicts stays at most α.
#[test]
fn a_a_comparisons_raise_false_alarms_at_most_at_rate_alpha() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let (mut alarms, mut ok, mut total) = (0, 0, 0);
    for k in 0..100u64 {
        let n = [8, 20, 40][k as usize % 3];
        let side = |rng: &mut ChaCha8Rng, from: u64| {
            let e = lognormal(rng, n, 0.1, 0.3);
            let s = bernoulli(rng, n, 0.8);
            let cost = lognormal(rng, n, 50.0, 0.2);
            let mut r = runs(&seeds(from, n), &e, &s);
            for (r, c) in r.iter_mut().zip(cost) {
                r.set(Metric::Cost, Some(c));
            }
            r
        };
        let (b, c) = (side(&mut rng, 0), side(&mut rng, 1000));
        let rows = compare(&b, &c, &TOL);
        alarms += usize::from(regressions(&rows) > 0);
        ok += rows.iter().filter(|r| r.verdict == Verdict::Ok).count();
        total += rows.len();
    }
    eprintln!(
        "A/A: {alarms} of 100 comparisons with a regression verdict; {ok} of {total} verdicts ok"
    );
    assert!(
        alarms <= 5,
        "{alarms} of 100 A/A comparisons flagged a regression"
    );
    // the check is not vacuous: with 40 seeds most metrics resolve to ok
    assert!(ok > total / 4, "{ok} of {total} ok");
}

/// Over 100 comparisons of two samples of the same distribution on different seeds, with every
/// ungated metric (the shown ones and, by default, the wall-clock ones) filled, the share of
/// tables that show a "REGRESSION" anywhere stays at most α: ungated verdicts are corrected for
/// their multiplicity as the gated ones are.
#[test]
fn a_a_comparisons_of_many_ungated_metrics_show_no_regression_beyond_rate_alpha() {
    use crate::metrics::Regress;
    let ungated: Vec<Metric> = Metric::ALL
        .iter()
        .copied()
        .filter(|m| matches!(m.def().regress, Regress::Shown | Regress::WallClock))
        .collect();
    assert!(ungated.len() >= 10, "{ungated:?}");
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut shown = 0;
    for k in 0..100u64 {
        let n = [8, 12, 20][k as usize % 3];
        let side = |rng: &mut ChaCha8Rng, from: u64| {
            let e = lognormal(rng, n, 0.1, 0.3);
            let mut r = runs(&seeds(from, n), &e, &vec![true; n]);
            for &m in &ungated {
                for (r, v) in r.iter_mut().zip(lognormal(rng, n, 5.0, 1.0)) {
                    r.set(m, Some(v));
                }
            }
            r
        };
        let (b, c) = (side(&mut rng, 0), side(&mut rng, 1000));
        let rows = compare(&b, &c, &TOL);
        if table(&rows, &TOL).contains("REGRESSION") {
            shown += 1;
        }
    }
    assert!(
        shown <= 5,
        "{shown} of 100 A/A comparisons showed a REGRESSION"
    );
}

#[test]
fn slower_times_are_reported_but_not_gated_by_default() {
    let e = vec![0.1; 20];
    let ok = vec![true; 20];
    let mut slow = runs(&seeds(0, 20), &e, &ok);
    slow.iter_mut()
        .enumerate()
        .for_each(|(i, r)| r.set(Metric::PlanTime, Some(3.0 + 0.01 * i as f64)));
    let mut fast = runs(&seeds(0, 20), &e, &ok);
    fast.iter_mut()
        .enumerate()
        .for_each(|(i, r)| r.set(Metric::PlanTime, Some(1.0 + 0.01 * i as f64)));
    let rows = compare(&fast, &slow, &TOL);
    let r = row(&rows, "plan_time_s");
    assert!(r.verdict == Verdict::Regression && !r.gated, "{r:?}");
    assert_eq!(failures(&rows, OnInconclusive::Fail), 0);
    assert!(table(&rows, &TOL).contains("REGRESSION (not gated)"));
    let gated = Tolerances {
        gate_time: true,
        ..TOL
    };
    assert_eq!(regressions(&compare(&fast, &slow, &gated)), 1);
    let off = Tolerances {
        wall_clock: false,
        ..TOL
    };
    assert!(
        compare(&fast, &slow, &off)
            .iter()
            .all(|r| r.metric != "plan_time_s")
    );
}

#[test]
fn a_missing_configuration_fails() {
    let e = vec![0.1; 10];
    let ok = vec![true; 10];
    let mut other = runs(&seeds(0, 10), &e, &ok);
    other.iter_mut().for_each(|r| r.preset = "realistic".into());
    let rows = compare(&runs(&seeds(0, 10), &e, &ok), &other, &TOL);
    assert_eq!(verdict(&rows, "runs"), Verdict::Missing);
    assert_eq!(failures(&rows, OnInconclusive::Pass), 1);
    assert!(table(&rows, &TOL).contains("MISSING"));
}

/// Three-agent runs whose agent 2 has RMS error `e2` (agents 0 and 1: 0.1), true errors
/// 80% of those.
fn trio(e2: &[f64]) -> Vec<RunRecord> {
    let n = e2.len();
    let mut rs = runs(&seeds(0, n), &vec![0.1; n], &vec![true; n]);
    for (r, &e) in rs.iter_mut().zip(e2) {
        r.agents = 3;
        r.per_agent = [0.1, 0.1, e]
            .iter()
            .map(|&x| crate::run::record::AgentErrors {
                rms_bl: Some(x),
                max_bl: Some(3.0 * x),
                rms_true_bl: Some(0.8 * x),
                max_true_bl: Some(2.4 * x),
            })
            .collect();
        r.set(Metric::RmsErrorWorstAgent, Some(e.max(0.1)));
    }
    rs
}

#[test]
fn per_agent_errors_are_compared_and_a_drifting_agent_is_flagged() {
    let base: Vec<f64> = (0..20).map(|i| 0.2 + 0.003 * i as f64).collect();
    let worse: Vec<f64> = base.iter().map(|v| 2.0 * v).collect();
    let rows = compare(&trio(&base), &trio(&worse), &TOL);
    assert_eq!(verdict(&rows, "rms_error_agent2_bl"), Verdict::Regression);
    assert_eq!(
        verdict(&rows, "rms_error_true_agent2_bl"),
        Verdict::Regression
    );
    assert_eq!(
        verdict(&rows, "rms_error_worst_agent_bl"),
        Verdict::Regression
    );
    assert_eq!(verdict(&rows, "rms_error_agent0_bl"), Verdict::Ok);
    // the team's RMS did not move: only the per-agent view sees the drift
    assert_eq!(verdict(&rows, "rms_error_bl"), Verdict::Ok);
    assert!(new_metrics(&rows).is_empty());
}

#[test]
fn a_baseline_without_per_agent_columns_compares_cleanly() {
    let e: Vec<f64> = (0..20).map(|i| 0.2 + 0.003 * i as f64).collect();
    // an old baseline: no per-agent, worst-true or true-max values
    let mut old = trio(&e);
    for r in &mut old {
        r.per_agent.clear();
        r.set(Metric::RmsErrorTrueWorstAgent, None);
    }
    let mut cur = trio(&e);
    for r in &mut cur {
        r.set(Metric::RmsErrorTrueWorstAgent, Some(0.16));
    }
    let rows = compare(&old, &cur, &TOL);
    assert_eq!(failures(&rows, OnInconclusive::Fail), 0);
    assert_eq!(verdict(&rows, "rms_error_agent1_bl"), Verdict::New);
    assert_eq!(verdict(&rows, "rms_error_bl"), Verdict::Ok);
    assert_eq!(
        new_metrics(&rows),
        [
            "rms_error_true_worst_agent_bl",
            "rms_error_agent0_bl",
            "rms_error_true_agent0_bl",
            "rms_error_agent1_bl",
            "rms_error_true_agent1_bl",
            "rms_error_agent2_bl",
            "rms_error_true_agent2_bl",
        ]
    );
    let text = footer(&rows, &TOL, OnInconclusive::Fail);
    assert!(
        text.starts_with("new since the baseline (not compared): rms_error_true_worst_agent_bl, rms_error_agent0_bl,"),
        "{text}"
    );
    assert!(text.contains("result: pass"), "{text}");
    assert!(table(&rows, &TOL).contains("new (not in baseline)"));
}

#[test]
fn a_metric_where_higher_is_better_regresses_when_it_falls() {
    let e = vec![0.1; 20];
    let ok = vec![true; 20];
    let with = |v: f64| {
        let mut rs = runs(&seeds(0, 20), &e, &ok);
        for (i, r) in rs.iter_mut().enumerate() {
            r.set(Metric::ClearanceMin, Some(v + 0.001 * i as f64));
        }
        rs
    };
    // clearance halved: a regression, shown as a drop of about 50%, not gated by the table
    let rows = compare(&with(2.0), &with(1.0), &TOL);
    let r = row(&rows, "clearance_min_bl");
    assert_eq!(r.verdict, Verdict::Regression);
    assert!(!r.gated);
    let Change::Relative { rel, lo, hi } = r.change else {
        panic!("{:?}", r.change)
    };
    assert!(
        lo <= rel && rel <= hi && (rel + 0.5).abs() < 0.01,
        "{rel} [{lo}, {hi}]"
    );
    // clearance doubled: better, not a regression
    let rows = compare(&with(1.0), &with(2.0), &TOL);
    let r = row(&rows, "clearance_min_bl");
    assert!(r.verdict == Verdict::Ok && r.better, "{r:?}");
}

/// A configuration of more runs than a side keeps is compared on a sample of its seeds, the
/// same on both sides, so that it stays paired; a planted regression is still found in it,
/// and a configuration of fewer runs keeps every run.
#[test]
fn large_configurations_are_compared_on_the_same_sample_of_seeds() {
    let n = 3 * runs::SEEDS;
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let s = seeds(1000, n);
    let rms = lognormal(&mut rng, n, 1.0, 0.5);
    let ok = vec![true; n];
    let worse: Vec<f64> = rms.iter().map(|v| v * 1.3).collect();
    let (base, cand) = (
        Runs::of(&runs(&s, &rms, &ok)),
        Runs::of(&runs(&s, &worse, &ok)),
    );
    let kept = base.configs[0].len();
    assert!(
        (runs::SEEDS / 2..=runs::SEEDS).contains(&kept),
        "{kept} runs kept"
    );
    assert_eq!(base.configs[0].seeds, cand.configs[0].seeds);
    let rows = compare_runs(&base, &cand, &TOL);
    let r = row(&rows, "rms_error_bl");
    assert_eq!(r.design, Design::Paired(kept));
    assert_eq!(r.sampled_from, Some((n, n)));
    assert_eq!(r.verdict, Verdict::Regression);
    // missing from the candidate, the configuration shows every run the baseline has
    let rows = compare_runs(&base, &Runs::of(&[]), &TOL);
    assert_eq!(row(&rows, "runs").baseline, Value::Runs(n));
    // a folder of half the seeds keeps more of them; brought down to the larger folder's
    // level, its sample is part of that folder's
    let half = n / 2;
    let small = Runs::of(&runs(&s[..half], &rms[..half], &ok[..half]));
    assert!(small.configs[0].len() > kept / 2 && small.configs[0].sampled());
    let thinned = small.configs[0].thinned(base.configs[0].level);
    assert!(
        thinned
            .seeds
            .iter()
            .all(|x| base.configs[0].seeds.contains(x))
    );
    // below the limit, every run
    let few = Runs::of(&runs(&s[..100], &rms[..100], &ok[..100]));
    let rows = compare_runs(&few, &few, &TOL);
    assert_eq!(row(&rows, "rms_error_bl").sampled_from, None);
    assert_eq!(row(&rows, "rms_error_bl").design, Design::Paired(100));
}
