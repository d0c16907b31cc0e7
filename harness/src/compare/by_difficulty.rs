//! Success and time against a difficulty measure: the problems binned by the measure's value
//! (one bin per value when there are at most [`MAX_BINS`] distinct values, else bins of about
//! equal counts), one series per planner.

use super::instances::{Instances, median_inf};
use crate::plot::charts::BandPoint;
use crate::stats::quantile::{quantile_sorted, sorted_finite};
use crate::stats::wilson;

/// Most bins of a measure.
pub const MAX_BINS: usize = 6;

/// Problem indices by bin, ascending in `x` (problems without a value are left out).
pub fn bins(x: &[Option<f64>]) -> Vec<Vec<usize>> {
    let mut idx: Vec<(usize, f64)> = x
        .iter()
        .enumerate()
        .filter_map(|(i, v)| v.filter(|v| v.is_finite()).map(|v| (i, v)))
        .collect();
    idx.sort_by(|a, b| a.1.total_cmp(&b.1));
    let mut distinct: Vec<f64> = idx.iter().map(|p| p.1).collect();
    distinct.dedup();
    if distinct.len() <= MAX_BINS {
        return distinct
            .iter()
            .map(|d| idx.iter().filter(|p| p.1 == *d).map(|p| p.0).collect())
            .collect();
    }
    // equal-count bins that never split equal values
    let target = idx.len().div_ceil(MAX_BINS);
    let mut out: Vec<Vec<usize>> = vec![];
    let mut cur: Vec<usize> = vec![];
    for (k, &(i, v)) in idx.iter().enumerate() {
        cur.push(i);
        let next_differs = idx.get(k + 1).is_none_or(|n| n.1 != v);
        if cur.len() >= target && next_differs {
            out.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

fn bin_x(x: &[Option<f64>], bin: &[usize]) -> f64 {
    let v: Vec<f64> = bin.iter().filter_map(|&i| x[i]).collect();
    quantile_sorted(&sorted_finite(&v), 0.5)
}

/// Planner `p`'s success rate per bin (all its runs of the bin's problems) with the 95%
/// Wilson interval; x is the bin's median value.
pub fn success(t: &Instances, p: usize, x: &[Option<f64>], bins: &[Vec<usize>]) -> Vec<BandPoint> {
    bins.iter()
        .map(|b| {
            let (s, n) = b
                .iter()
                .map(|&i| t.solved[p][i])
                .fold((0, 0), |a, v| (a.0 + v.0, a.1 + v.1));
            let (lo, hi) = wilson(s, n, 0.95);
            BandPoint {
                x: bin_x(x, b),
                y: if n == 0 {
                    f64::NAN
                } else {
                    s as f64 / n as f64
                },
                lo,
                hi,
            }
        })
        .collect()
}

/// Planner `p`'s median over the bin's problems of its per-problem median time, as log10 of
/// seconds (NaN when half or more of the problems are unsolved), with the quartiles as band
/// where finite.
pub fn time(t: &Instances, p: usize, x: &[Option<f64>], bins: &[Vec<usize>]) -> Vec<BandPoint> {
    bins.iter()
        .map(|b| {
            let v: Vec<f64> = b.iter().map(|&i| t.time[p][i]).collect();
            let m = median_inf(&v);
            let mut s: Vec<f64> = v.iter().copied().filter(|t| !t.is_nan()).collect();
            s.sort_by(f64::total_cmp);
            let q = |f: f64| {
                if s.is_empty() {
                    return f64::NAN;
                }
                let v = s[((s.len() - 1) as f64 * f).round() as usize];
                if v.is_finite() && v > 0.0 {
                    v.log10()
                } else {
                    f64::NAN
                }
            };
            BandPoint {
                x: bin_x(x, b),
                y: if m.is_finite() && m > 0.0 {
                    m.log10()
                } else {
                    f64::NAN
                },
                lo: q(0.25),
                hi: q(0.75),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn few_values_get_one_bin_each() {
        let x = [Some(2.0), Some(1.0), None, Some(2.0), Some(4.0)];
        assert_eq!(bins(&x), vec![vec![1], vec![0, 3], vec![4]]);
    }

    #[test]
    fn many_values_get_equal_count_bins() {
        let x: Vec<Option<f64>> = (0..12).map(|i| Some(i as f64)).collect();
        let b = bins(&x);
        assert_eq!(b.len(), MAX_BINS);
        assert!(b.iter().all(|b| b.len() == 2));
    }

    #[test]
    fn success_and_time_per_bin() {
        let t = Instances {
            planners: vec!["a".into()],
            problems: vec!["p0".into(), "p1".into(), "p2".into()],
            time: vec![vec![0.1, 10.0, f64::INFINITY]],
            solved: vec![vec![(2, 2), (1, 2), (0, 2)]],
            difficulty: vec![],
        };
        let x = [Some(1.0), Some(5.0), Some(5.0)];
        let b = bins(&x);
        let s = success(&t, 0, &x, &b);
        assert_eq!((s[0].x, s[0].y), (1.0, 1.0));
        assert_eq!((s[1].x, s[1].y), (5.0, 0.25));
        let tm = time(&t, 0, &x, &b);
        assert!((tm[0].y + 1.0).abs() < 1e-12);
        assert!(tm[1].y.is_nan());
    }
}
