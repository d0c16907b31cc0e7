//! One metric of one configuration, tested: the success rate by a score interval of the
//! difference of rates, the other metrics by a rank interval of the ratio of the candidate's
//! values to the baseline's (on log values, so no interval reaches below −100%). Paired by
//! seed where both folders hold the same seeds, unpaired otherwise.

use super::verdict::Test;
use crate::metrics::Direction;
use crate::stats::normal_quantile;
use crate::stats::rate_diff::{newcombe, newcombe_p_above, tango, tango_p_above};
use crate::stats::shift::{paired_p_above, paired_shift, unpaired_p_above, unpaired_shift};

/// The runs of one configuration on both sides, by their indices in each side.
#[derive(Debug, Clone)]
pub enum Sides {
    /// The same seeds on both sides: (baseline, candidate) runs of each seed.
    Paired(Vec<(usize, usize)>),
    /// Different seeds: every run of each side, (baseline runs, candidate runs).
    Unpaired(usize, usize),
}

/// The change from the baseline to the candidate, with its interval (each end a one-sided
/// level-α bound; infinite ends when too few runs bound it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Change {
    /// Not computed.
    None,
    /// A difference of success rates, candidate − baseline (fractions; 0.05 is 5 points).
    Points {
        /// The change.
        diff: f64,
        /// Lower end.
        lo: f64,
        /// Upper end.
        hi: f64,
    },
    /// A relative change (ratio − 1) of the candidate's values to the baseline's.
    Relative {
        /// The change.
        rel: f64,
        /// Lower end.
        lo: f64,
        /// Upper end.
        hi: f64,
    },
    /// A difference of values, candidate − baseline (where a value is zero or negative and
    /// a ratio has no meaning).
    Absolute {
        /// The change.
        diff: f64,
        /// Lower end.
        lo: f64,
        /// Upper end.
        hi: f64,
    },
}

/// The success rate's test: the drop (baseline − candidate) against the tolerance `tol`
/// (points, as a fraction) by Tango's paired or Newcombe's unpaired score interval.
pub fn success(s: &Sides, b: &[bool], c: &[bool], tol: f64, alpha: f64) -> (Test, Change) {
    let z = normal_quantile(1.0 - alpha);
    let (d, p, n) = match s {
        Sides::Paired(pairs) => {
            let drop = pairs.iter().filter(|&&(i, j)| b[i] && !c[j]);
            let gain = pairs.iter().filter(|&&(i, j)| !b[i] && c[j]);
            let (n12, n21, n) = (drop.count() as u64, gain.count() as u64, pairs.len() as u64);
            (
                tango(n12, n21, n, z),
                tango_p_above(n12, n21, n, tol),
                n as f64,
            )
        }
        Sides::Unpaired(..) => {
            let sb = b.iter().filter(|&&x| x).count() as u64;
            let sc = c.iter().filter(|&&x| x).count() as u64;
            let (nb, nc) = (b.len() as u64, c.len() as u64);
            (
                newcombe(sb, nb, sc, nc, z),
                newcombe_p_above(sb, nb, sc, nc, tol),
                harmonic(b.len(), c.len()),
            )
        }
    };
    let test = Test {
        est: d.est,
        lo: d.lo,
        hi: d.hi,
        tol,
        p,
        n,
        se: None,
    };
    // 0 − x, not −x: an unchanged rate shows as +0.0, not −0.0
    let change = Change::Points {
        diff: 0.0 - d.est,
        lo: 0.0 - d.hi,
        hi: 0.0 - d.lo,
    };
    (test, change)
}

/// The harmonic mean of two sample sizes (the equal size with the same standard error).
fn harmonic(m: usize, n: usize) -> f64 {
    2.0 / (1.0 / m as f64 + 1.0 / n as f64)
}

/// The standard error of a mean of `v` (None below two values).
fn se_of(v: &[f64]) -> Option<(f64, usize)> {
    let n = v.len();
    if n < 2 {
        return None;
    }
    let mean = v.iter().sum::<f64>() / n as f64;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    Some((var, n))
}

/// A metric's test: the shift of the candidate's values against the baseline's on log values
/// (a ratio; the tolerance `rel` is relative) when every value is positive, else on the values
/// (the tolerance is `rel` times the baseline median `base_median`). The test's scale has larger
/// as worse: for a metric where higher is better it is the negated scale, and the change is
/// reported on the metric's own. `None` when a side has no value (or no seed has a value on
/// both sides).
pub fn shift(
    s: &Sides,
    fb: &dyn Fn(usize) -> Option<f64>,
    fc: &dyn Fn(usize) -> Option<f64>,
    direction: Direction,
    rel: f64,
    base_median: f64,
    alpha: f64,
) -> Option<(Test, Change)> {
    let finite = |v: Option<f64>| v.filter(|v| v.is_finite());
    let (b, c): (Vec<f64>, Vec<f64>) = match s {
        Sides::Paired(pairs) => pairs
            .iter()
            .filter_map(|&(i, j)| Some((finite(fb(i))?, finite(fc(j))?)))
            .unzip(),
        Sides::Unpaired(nb, nc) => (
            (0..*nb).filter_map(|i| finite(fb(i))).collect(),
            (0..*nc).filter_map(|j| finite(fc(j))).collect(),
        ),
    };
    if b.is_empty() || c.is_empty() {
        return None;
    }
    let log = b.iter().chain(&c).all(|&v| v > 0.0);
    let sign = match direction {
        Direction::Lower => 1.0,
        Direction::Higher => -1.0,
    };
    let scale = |v: &[f64]| -> Vec<f64> {
        v.iter()
            .map(|x| sign * if log { x.ln() } else { *x })
            .collect()
    };
    let (b, c) = (scale(&b), scale(&c));
    let tol = if log {
        rel.ln_1p()
    } else {
        rel * base_median.abs()
    };
    let (sh, p, n, se) = match s {
        Sides::Paired(_) => {
            let d: Vec<f64> = b.iter().zip(&c).map(|(x, y)| y - x).collect();
            let se = se_of(&d).map(|(v, n)| (v / n as f64).sqrt());
            (
                paired_shift(&d, alpha)?,
                paired_p_above(&d, tol),
                d.len() as f64,
                se,
            )
        }
        Sides::Unpaired(..) => {
            let se = match (se_of(&b), se_of(&c)) {
                (Some((vb, nb)), Some((vc, nc))) => Some((vb / nb as f64 + vc / nc as f64).sqrt()),
                _ => None,
            };
            (
                unpaired_shift(&b, &c, alpha)?,
                unpaired_p_above(&b, &c, tol),
                harmonic(b.len(), c.len()),
                se,
            )
        }
    };
    let test = Test {
        est: sh.est,
        lo: sh.lo,
        hi: sh.hi,
        tol,
        p,
        n,
        se,
    };
    // the change on the metric's own scale: its ends swap when the test's scale is negated
    let (est, lo, hi) = if sign > 0.0 {
        (sh.est, sh.lo, sh.hi)
    } else {
        (-sh.est, -sh.hi, -sh.lo)
    };
    let change = if log {
        Change::Relative {
            rel: est.exp_m1(),
            lo: lo.exp_m1(),
            hi: hi.exp_m1(),
        }
    } else {
        Change::Absolute { diff: est, lo, hi }
    };
    Some((test, change))
}
