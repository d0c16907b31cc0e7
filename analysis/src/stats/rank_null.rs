//! Null distributions of the two rank statistics behind distribution-free shift intervals:
//! the Mann–Whitney U of two independent samples and the Wilcoxon signed-rank T of paired
//! differences. Exact (counted) for small samples, the normal approximation with a continuity
//! correction of ½ beyond.

use super::{normal_quantile, normal_sf};

/// Largest `m·n` (Mann–Whitney) whose distribution is counted exactly.
const EXACT_MN: usize = 2500;
/// Largest `n` (signed rank) whose distribution is counted exactly.
const EXACT_N: usize = 60;

/// The null distribution of a rank statistic taking the values `0..=max`.
#[derive(Debug, Clone, PartialEq)]
pub struct RankNull {
    /// `cdf[k] = P(S ≤ k)`, when counted exactly.
    cdf: Option<Vec<f64>>,
    /// Largest value of the statistic.
    max: usize,
    /// Mean under the null hypothesis.
    mean: f64,
    /// Standard deviation under the null hypothesis.
    sd: f64,
}

/// Cumulative sums of `counts`, divided by their total.
fn cdf_of(counts: &[f64]) -> Vec<f64> {
    let total: f64 = counts.iter().sum();
    let mut acc = 0.0;
    counts
        .iter()
        .map(|c| {
            acc += c;
            (acc / total).min(1.0)
        })
        .collect()
}

impl RankNull {
    /// U of samples of sizes `m` and `n` (the number of pairs with the second value larger).
    pub fn mann_whitney(m: usize, n: usize) -> RankNull {
        let max = m * n;
        let (mf, nf) = (m as f64, n as f64);
        let sd = (mf * nf * (mf + nf + 1.0) / 12.0).sqrt();
        let cdf = (max <= EXACT_MN && m > 0 && n > 0).then(|| {
            // f[i][k]: arrangements of i first-sample values among the values seen so far
            // (nn second-sample values) with U = k; the largest value is either kind.
            let mut f = vec![vec![0.0f64; max + 1]; m + 1];
            for row in f.iter_mut() {
                row[0] = 1.0;
            }
            for nn in 1..=n {
                let mut g = vec![vec![0.0f64; max + 1]; m + 1];
                g[0][0] = 1.0;
                for i in 1..=m {
                    for k in 0..=max {
                        let mut c = f[i][k];
                        if k >= nn {
                            c += g[i - 1][k - nn];
                        }
                        g[i][k] = c;
                    }
                }
                f = g;
            }
            cdf_of(&f[m])
        });
        RankNull {
            cdf,
            max,
            mean: mf * nf / 2.0,
            sd,
        }
    }

    /// T⁺ of `n` paired differences (the sum of the ranks of the positive ones).
    pub fn signed_rank(n: usize) -> RankNull {
        let max = n * (n + 1) / 2;
        let nf = n as f64;
        let sd = (nf * (nf + 1.0) * (2.0 * nf + 1.0) / 24.0).sqrt();
        let cdf = (n <= EXACT_N && n > 0).then(|| {
            let mut c = vec![0.0f64; max + 1];
            c[0] = 1.0;
            for r in 1..=n {
                for k in (r..=max).rev() {
                    c[k] += c[k - r];
                }
            }
            cdf_of(&c)
        });
        RankNull {
            cdf,
            max,
            mean: max as f64 / 2.0,
            sd,
        }
    }

    /// The largest value of the statistic (the number of pairwise differences or Walsh
    /// averages the interval is read from).
    pub fn max(&self) -> usize {
        self.max
    }

    /// `P(S ≤ k)`.
    pub fn cdf(&self, k: usize) -> f64 {
        if k >= self.max {
            return 1.0;
        }
        match &self.cdf {
            Some(c) => c[k],
            None if self.sd > 0.0 => normal_sf((self.mean - k as f64 - 0.5) / self.sd),
            None => 1.0,
        }
    }

    /// The largest `c ≥ 1` with `P(S ≤ c − 1) ≤ alpha`: the 1-based rank of the lower end of
    /// a one-sided level-`alpha` interval; `None` if even the most extreme value has a larger
    /// probability (too few values to bound the shift at this level).
    pub fn lower_index(&self, alpha: f64) -> Option<usize> {
        if self.max == 0 {
            return None;
        }
        let c = match &self.cdf {
            Some(c) => c.iter().take_while(|&&p| p <= alpha).count(),
            None => {
                let z = normal_quantile(1.0 - alpha);
                (self.mean + 0.5 - z * self.sd).floor().max(0.0) as usize
            }
        };
        (c >= 1).then_some(c.min(self.max.div_ceil(2)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_tables_match_known_values() {
        // Signed rank, n = 8: P(T ≤ 0) = 1/256, P(T ≤ 5) = 10/256 (counts 1,1,1,2,2,3).
        let t = RankNull::signed_rank(8);
        assert!((t.cdf(0) - 1.0 / 256.0).abs() < 1e-15);
        assert!((t.cdf(5) - 10.0 / 256.0).abs() < 1e-15);
        assert_eq!(t.lower_index(0.05), Some(6));
        // Mann–Whitney 8 × 8: P(U ≤ 0) = 1/C(16, 8) = 1/12870.
        let u = RankNull::mann_whitney(8, 8);
        assert!((u.cdf(0) - 1.0 / 12870.0).abs() < 1e-15);
        // Too few pairs for a 5% bound: 2⁻⁴ = 0.0625.
        assert_eq!(RankNull::signed_rank(4).lower_index(0.05), None);
    }

    #[test]
    fn normal_approximation_is_close_to_the_exact_count_where_they_meet() {
        let exact = RankNull::mann_whitney(50, 50);
        let mut approx = exact.clone();
        approx.cdf = None;
        for k in [900, 1000, 1100, 1250] {
            assert!((exact.cdf(k) - approx.cdf(k)).abs() < 2e-3, "{k}");
        }
        let exact = RankNull::signed_rank(60);
        let mut approx = exact.clone();
        approx.cdf = None;
        let (e, a) = (exact.lower_index(0.05), approx.lower_index(0.05));
        assert!(e.unwrap().abs_diff(a.unwrap()) <= 1, "{e:?} {a:?}");
    }
}
