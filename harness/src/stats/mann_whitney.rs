//! The Mann–Whitney U (Wilcoxon rank-sum) test, with mid-ranks for ties.
//!
//! Exact p-values (the permutation distribution of U) when there are no ties and the samples
//! are small (m·n ≤ 2500, e.g. 50 × 50); otherwise the normal approximation with the
//! tie-corrected variance and a continuity correction of ½. (SciPy's `method="auto"` switches
//! to the approximation already at 8 values per sample, where it can overstate p several-fold
//! in the tails — which matters after a multiple-comparison adjustment.)

use super::{Alternative, normal_sf};

/// The outcome of a Mann–Whitney U test of `x` against `y`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MannWhitney {
    /// U of `x`: the number of pairs (xᵢ, yⱼ) with xᵢ > yⱼ, ties counting ½.
    pub u: f64,
    /// Sample sizes.
    pub n_x: usize,
    /// Sample sizes.
    pub n_y: usize,
    /// The p-value under the chosen alternative.
    pub p: f64,
    /// The standardised statistic (normal approximation, without continuity correction).
    pub z: f64,
    /// True if `p` comes from the exact distribution.
    pub exact: bool,
}

/// Mid-ranks (1-based) of `v` and the tie term Σ(t³ − t) over groups of equal values.
fn ranks(v: &[f64]) -> (Vec<f64>, f64) {
    let mut idx: Vec<usize> = (0..v.len()).collect();
    idx.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
    let mut r = vec![0.0; v.len()];
    let mut ties = 0.0;
    let mut i = 0;
    while i < idx.len() {
        let mut j = i;
        while j + 1 < idx.len() && v[idx[j + 1]] == v[idx[i]] {
            j += 1;
        }
        let mid = (i + j) as f64 / 2.0 + 1.0;
        for &k in &idx[i..=j] {
            r[k] = mid;
        }
        let t = (j - i + 1) as f64;
        ties += t * t * t - t;
        i = j + 1;
    }
    (r, ties)
}

/// `P(U ≥ u)` under the null hypothesis, exactly, for sample sizes `m` and `n` without ties.
fn exact_sf(u: f64, m: usize, n: usize) -> f64 {
    // c[j][k]: number of arrangements of j x's among the first values with U = k, built by the
    // recurrence f(m, n, k) = f(m − 1, n, k − n) + f(m, n − 1, k).
    let max = m * n;
    // f[i][k] for fixed n' = 0..=n, iterating over n'.
    let mut f = vec![vec![0.0f64; max + 1]; m + 1]; // f[i][k] at current n'
    for row in f.iter_mut() {
        row[0] = 1.0; // n' = 0: U = 0 only
    }
    for nn in 1..=n {
        let mut g = vec![vec![0.0f64; max + 1]; m + 1];
        g[0][0] = 1.0;
        for i in 1..=m {
            for k in 0..=max {
                let mut c = f[i][k]; // the largest value is a y
                if k >= nn {
                    c += g[i - 1][k - nn]; // the largest value is an x: it beats all nn y's
                }
                g[i][k] = c;
            }
        }
        f = g;
    }
    let total: f64 = f[m].iter().sum();
    let start = u.ceil().max(0.0) as usize;
    f[m][start.min(max + 1)..].iter().sum::<f64>() / total
}

/// Tests whether `x` and `y` come from the same distribution. NaNs are dropped first.
/// Returns `None` if either sample is empty.
pub fn mann_whitney_u(x: &[f64], y: &[f64], alt: Alternative) -> Option<MannWhitney> {
    let x: Vec<f64> = x.iter().copied().filter(|v| !v.is_nan()).collect();
    let y: Vec<f64> = y.iter().copied().filter(|v| !v.is_nan()).collect();
    let (m, n) = (x.len(), y.len());
    if m == 0 || n == 0 {
        return None;
    }
    let all: Vec<f64> = x.iter().chain(&y).copied().collect();
    let (r, ties) = ranks(&all);
    let r1: f64 = r[..m].iter().sum();
    let u1 = r1 - (m * (m + 1)) as f64 / 2.0;
    let (mf, nf) = (m as f64, n as f64);
    let u2 = mf * nf - u1;
    let mu = mf * nf / 2.0;
    let nt = mf + nf;
    let var = mf * nf / 12.0 * ((nt + 1.0) - ties / (nt * (nt - 1.0)));
    let sd = var.max(0.0).sqrt();
    let z = if sd > 0.0 { (u1 - mu) / sd } else { 0.0 };
    let exact = ties == 0.0 && m * n <= 2500;
    // The statistic in the direction of the alternative; large values are evidence for it.
    let (u_alt, factor) = match alt {
        Alternative::Greater => (u1, 1.0),
        Alternative::Less => (u2, 1.0),
        Alternative::TwoSided => (u1.max(u2), 2.0),
    };
    let p_one = if exact {
        exact_sf(u_alt, m, n)
    } else if sd > 0.0 {
        normal_sf((u_alt - mu - 0.5) / sd)
    } else {
        1.0
    };
    Some(MannWhitney {
        u: u1,
        n_x: m,
        n_y: n,
        p: (factor * p_one).min(1.0),
        z,
        exact,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    // Reference values from SciPy 1.10 `scipy.stats.mannwhitneyu`.

    #[test]
    fn exact_small_samples_match_scipy() {
        let x = [1.1, 2.3, 3.0, 4.8, 5.2];
        let y = [6.1, 2.9, 7.4, 8.0, 9.9, 10.5];
        let t = mann_whitney_u(&x, &y, Alternative::TwoSided).unwrap();
        assert!(t.exact);
        assert_eq!(t.u, 3.0);
        assert!((t.p - 0.030303030303030304).abs() < 1e-12, "{}", t.p);
        let l = mann_whitney_u(&x, &y, Alternative::Less).unwrap();
        assert!((l.p - 0.015151515151515152).abs() < 1e-12, "{}", l.p);
    }

    #[test]
    fn normal_approximation_with_ties_matches_scipy() {
        let a = [1.0, 2.0, 2.0, 3.0, 3.0, 3.0, 4.0, 5.0, 7.0, 8.0];
        let b = [3.0, 4.0, 4.0, 5.0, 6.0, 6.0, 7.0, 8.0, 9.0, 9.0, 10.0];
        let two = mann_whitney_u(&a, &b, Alternative::TwoSided).unwrap();
        assert!(!two.exact);
        assert_eq!(two.u, 21.0);
        assert!((two.p - 0.017574261452286636).abs() < 1e-9, "{}", two.p);
        let less = mann_whitney_u(&a, &b, Alternative::Less).unwrap();
        assert!((less.p - 0.008787130726143318).abs() < 1e-9, "{}", less.p);
        let greater = mann_whitney_u(&a, &b, Alternative::Greater).unwrap();
        assert!(
            (greater.p - 0.9927643702848582).abs() < 1e-9,
            "{}",
            greater.p
        );
    }

    #[test]
    fn exact_distribution_at_eight_and_nine() {
        // SciPy's exact method: 0.059234882764294526 two-sided, 0.9767996709173179 "greater".
        let x = [0.8, 1.9, 2.2, 3.7, 4.1, 5.5, 6.0, 7.3];
        let y = [2.5, 3.1, 4.4, 5.8, 6.6, 7.9, 8.2, 9.0, 9.5];
        let t = mann_whitney_u(&x, &y, Alternative::TwoSided).unwrap();
        assert!(t.exact);
        assert_eq!(t.u, 16.0);
        assert!((t.p - 0.059234882764294526).abs() < 1e-12, "{}", t.p);
        let g = mann_whitney_u(&x, &y, Alternative::Greater).unwrap();
        assert!((g.p - 0.9767996709173179).abs() < 1e-12, "{}", g.p);
        // Complete separation of 8 and 8: p = 1 / C(16, 8) = 1/12870.
        let lo: Vec<f64> = (0..8).map(|i| i as f64).collect();
        let hi: Vec<f64> = (0..8).map(|i| 10.0 + i as f64).collect();
        let s = mann_whitney_u(&hi, &lo, Alternative::Greater).unwrap();
        assert!((s.p - 1.0 / 12870.0).abs() < 1e-15, "{}", s.p);
        // Large samples use the normal approximation.
        let big: Vec<f64> = (0..60).map(|i| i as f64).collect();
        assert!(
            !mann_whitney_u(
                &big,
                &big.iter().map(|v| v + 0.5).collect::<Vec<_>>(),
                Alternative::Less
            )
            .unwrap()
            .exact
        );
    }

    #[test]
    fn identical_samples_are_not_significant_and_empty_is_none() {
        let x = [1.0, 1.0, 1.0];
        let t = mann_whitney_u(&x, &x, Alternative::TwoSided).unwrap();
        assert_eq!(t.p, 1.0);
        assert!(mann_whitney_u(&[], &x, Alternative::TwoSided).is_none());
    }

    #[test]
    fn mid_ranks_and_tie_term() {
        let (r, t) = ranks(&[10.0, 20.0, 20.0, 30.0, 20.0]);
        assert_eq!(r, vec![1.0, 3.0, 3.0, 5.0, 3.0]);
        assert_eq!(t, 24.0);
    }
}
