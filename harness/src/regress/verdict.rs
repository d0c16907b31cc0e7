//! Verdicts: a one-sided test for a regression (Holm-adjusted over the gated metrics, and
//! apart over the ungated ones), an
//! interval inside the tolerance for "ok", and otherwise "inconclusive" with the number of
//! seeds that would likely resolve it.

use crate::stats::{holm, normal_quantile};

/// The verdict on one metric.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// The change is shown to be within the tolerance: the worse end of the interval lies
    /// inside it.
    Ok,
    /// Neither a regression nor "ok" is shown: too few runs for the observed spread.
    Inconclusive,
    /// A change beyond the tolerance is shown (one-sided test, Holm-adjusted).
    Regression,
    /// The configuration is missing from the candidate.
    Missing,
    /// A metric the baseline does not have (e.g. a column added after it was recorded).
    New,
}

impl Verdict {
    /// Table text.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Ok => "ok",
            Verdict::Inconclusive => "inconclusive",
            Verdict::Regression => "REGRESSION",
            Verdict::Missing => "MISSING",
            Verdict::New => "new (not in baseline)",
        }
    }
}

/// A metric's test on its analysis scale, where larger is worse: the success rate's drop
/// (baseline − candidate), the log of a median's ratio, or a difference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Test {
    /// The estimated change.
    pub est: f64,
    /// Lower end of the interval (a one-sided level-α bound; −∞ if unbounded).
    pub lo: f64,
    /// Upper end (+∞ if unbounded).
    pub hi: f64,
    /// The tolerance on this scale (≥ 0).
    pub tol: f64,
    /// The one-sided p-value of "the change is at most `tol`", before adjustment.
    pub p: f64,
    /// Seeds per folder behind the interval (pairs, or the harmonic mean of the two sizes).
    pub n: f64,
    /// The standard error from the sample spread, for when the interval is unbounded.
    pub se: Option<f64>,
}

/// The verdict of a tested metric from its (adjusted) p-value and interval, and whether the
/// interval lies wholly on the better side of the tolerance.
pub fn verdict_of(t: &Test, p_adjusted: f64, alpha: f64) -> (Verdict, bool) {
    let v = if p_adjusted < alpha {
        Verdict::Regression
    } else if t.hi <= t.tol {
        Verdict::Ok
    } else {
        Verdict::Inconclusive
    };
    (v, t.hi < -t.tol)
}

/// Holm-adjusted p-values in two families: the entries `gated` marks (those that can fail the
/// check), and the others (shown, not gated), so that neither family's verdicts show a
/// regression more often than at level α when nothing changed.
pub fn adjust(p: &[f64], gated: &[bool]) -> Vec<f64> {
    let mut out = p.to_vec();
    for in_family in [true, false] {
        let family: Vec<usize> = (0..p.len()).filter(|&i| gated[i] == in_family).collect();
        let adj = holm(&family.iter().map(|&i| p[i]).collect::<Vec<_>>());
        for (k, &i) in family.iter().enumerate() {
            out[i] = adj[k];
        }
    }
    out
}

/// Largest number of seeds [`seeds_needed`] reports: one more than an experiment runs
/// ([`crate::experiment::MAX_SEEDS`]), for a need that no experiment can meet.
pub const MAX_SEEDS: u64 = crate::experiment::MAX_SEEDS as u64 + 1;

/// Seeds per folder at which an inconclusive metric would likely (80% power) be resolved, if
/// the change and its spread stayed as observed: towards "ok" when the estimate is within the
/// tolerance, towards "regression" (at the unadjusted level) when beyond it. `None` when the
/// estimate sits on the tolerance or there is no spread to scale.
pub fn seeds_needed(t: &Test, alpha: f64) -> Option<u64> {
    let za = normal_quantile(1.0 - alpha);
    let zb = normal_quantile(0.8);
    let (d, w) = if t.est <= t.tol {
        (t.tol - t.est, t.hi - t.est)
    } else {
        (t.est - t.tol, t.est - t.lo)
    };
    if d.is_nan() || d <= 0.0 || za.is_nan() || za <= 0.0 {
        return None;
    }
    let se = if w.is_finite() && w > 0.0 {
        w / za
    } else {
        t.se.filter(|s| s.is_finite() && *s > 0.0)?
    };
    let n = t.n * ((za + zb) * se / d).powi(2);
    let now = t.n.ceil() as u64;
    Some((n.ceil().min(MAX_SEEDS as f64) as u64).max(now + 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn test(est: f64, lo: f64, hi: f64) -> Test {
        Test {
            est,
            lo,
            hi,
            tol: 0.1,
            p: 0.5,
            n: 8.0,
            se: None,
        }
    }

    #[test]
    fn not_significant_is_never_ok() {
        // an interval reaching past the tolerance without a significant test: inconclusive
        assert_eq!(
            verdict_of(&test(0.0, -0.3, 0.3), 0.4, 0.05).0,
            Verdict::Inconclusive
        );
        assert_eq!(
            verdict_of(&test(0.0, -0.05, 0.08), 0.9, 0.05).0,
            Verdict::Ok
        );
        assert_eq!(
            verdict_of(&test(0.5, 0.3, 0.7), 0.001, 0.05).0,
            Verdict::Regression
        );
        // shown beyond the tolerance but not after Holm's adjustment: inconclusive
        assert_eq!(
            verdict_of(&test(0.5, 0.3, 0.7), 0.2, 0.05).0,
            Verdict::Inconclusive
        );
        assert!(verdict_of(&test(-0.5, -0.7, -0.3), 1.0, 0.05).1);
    }

    #[test]
    fn seeds_needed_scales_with_the_square_of_the_spread() {
        // estimate 0, tolerance 0.1, upper end 0.2 at 8 seeds: se = 0.2/1.645; n = 8·((1.645
        // + 0.842)·se/0.1)² ≈ 73.
        let n = seeds_needed(&test(0.0, -0.2, 0.2), 0.05).unwrap();
        assert!((70..=76).contains(&n), "{n}");
        assert!(seeds_needed(&test(0.0, -0.4, 0.4), 0.05).unwrap() > 4 * n - 8);
        assert_eq!(seeds_needed(&test(0.1, 0.0, 0.2), 0.05), None);
        // an estimate a hair inside the tolerance needs more seeds than an experiment runs
        assert_eq!(
            seeds_needed(&test(0.0999, 0.0, 0.2), 0.05),
            Some(crate::experiment::MAX_SEEDS as u64 + 1)
        );
    }
}
