//! Distribution-free intervals of a shift between two samples (Hodges–Lehmann estimates with
//! the intervals that invert the rank tests):
//!
//! - unpaired: the median of all differences `yⱼ − xᵢ`, with Moses' interval from the
//!   Mann–Whitney distribution;
//! - paired: the median of the Walsh averages `(dᵢ + dⱼ)/2, i ≤ j` of the differences, with the
//!   interval from the Wilcoxon signed-rank distribution.
//!
//! Each end of an interval is a one-sided bound at level `alpha` (so the interval is a
//! two-sided `1 − 2·alpha` one, the pair TOST uses). The order statistics are found by
//! bisection over a counting function, in O((m + n)·log) time and O(m + n) memory: no sample
//! size makes this allocate the m·n differences.

use super::quantile::sorted_finite;
use super::rank_null::RankNull;

/// A shift estimate with its interval (each end infinite when too few values bound it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shift {
    /// The Hodges–Lehmann estimate.
    pub est: f64,
    /// Lower end.
    pub lo: f64,
    /// Upper end.
    pub hi: f64,
}

/// The smallest `t` with `count_le(t) ≥ k`, for `k` in `1..=count_le(hi)`, searched in
/// `[lo, hi]`.
fn kth(count_le: &dyn Fn(f64) -> usize, mut lo: f64, mut hi: f64, k: usize) -> f64 {
    if count_le(lo) >= k {
        return lo;
    }
    for _ in 0..4096 {
        let mid = lo + (hi - lo) / 2.0;
        if mid <= lo || mid >= hi {
            break;
        }
        if count_le(mid) >= k {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// The sample median of the values counted by `count_le` (`n` of them, in `[lo, hi]`).
fn median_of(count_le: &dyn Fn(f64) -> usize, lo: f64, hi: f64, n: usize) -> f64 {
    if n % 2 == 1 {
        kth(count_le, lo, hi, n.div_ceil(2))
    } else {
        0.5 * (kth(count_le, lo, hi, n / 2) + kth(count_le, lo, hi, n / 2 + 1))
    }
}

/// An estimate with the interval read at ranks `c` and `n + 1 − c` of `n` ordered values.
fn interval(
    count_le: &dyn Fn(f64) -> usize,
    lo: f64,
    hi: f64,
    n: usize,
    c: Option<usize>,
) -> Shift {
    let est = median_of(count_le, lo, hi, n);
    match c {
        Some(c) => Shift {
            est,
            lo: kth(count_le, lo, hi, c),
            hi: kth(count_le, lo, hi, n + 1 - c),
        },
        None => Shift {
            est,
            lo: f64::NEG_INFINITY,
            hi: f64::INFINITY,
        },
    }
}

/// Sorted finite samples and the number of differences `yⱼ − xᵢ ≤ t`.
struct Pairwise {
    x: Vec<f64>,
    y: Vec<f64>,
}

impl Pairwise {
    fn new(x: &[f64], y: &[f64]) -> Option<Pairwise> {
        let (x, y) = (sorted_finite(x), sorted_finite(y));
        (!x.is_empty() && !y.is_empty()).then_some(Pairwise { x, y })
    }

    fn count_le(&self, t: f64) -> usize {
        let m = self.x.len();
        let mut i = 0;
        let mut count = 0;
        for &yj in &self.y {
            while i < m && yj - self.x[i] > t {
                i += 1;
            }
            count += m - i;
        }
        count
    }

    fn range(&self) -> (f64, f64) {
        let (x, y) = (&self.x, &self.y);
        (y[0] - x[x.len() - 1], y[y.len() - 1] - x[0])
    }
}

/// The shift of `y` against `x` (Hodges–Lehmann) with Moses' interval, each end a one-sided
/// level-`alpha` bound. Non-finite values are dropped; `None` if a sample is then empty.
pub fn unpaired_shift(x: &[f64], y: &[f64], alpha: f64) -> Option<Shift> {
    let p = Pairwise::new(x, y)?;
    let null = RankNull::mann_whitney(p.x.len(), p.y.len());
    let (lo, hi) = p.range();
    let f = |t| p.count_le(t);
    Some(interval(&f, lo, hi, null.max(), null.lower_index(alpha)))
}

/// The one-sided p-value of "the shift of `y` against `x` is at most `margin`" (Mann–Whitney,
/// ties counted against the alternative); 1 if a sample is empty.
pub fn unpaired_p_above(x: &[f64], y: &[f64], margin: f64) -> f64 {
    match Pairwise::new(x, y) {
        Some(p) => RankNull::mann_whitney(p.x.len(), p.y.len()).cdf(p.count_le(margin)),
        None => 1.0,
    }
}

/// The number of Walsh averages `(dᵢ + dⱼ)/2, i ≤ j` of sorted `d` that are `≤ t`.
fn walsh_count_le(d: &[f64], t: f64) -> usize {
    let mut count = 0;
    let mut j = d.len();
    for (i, &di) in d.iter().enumerate() {
        while j > 0 && (di + d[j - 1]) / 2.0 > t {
            j -= 1;
        }
        if j <= i {
            break;
        }
        count += j - i;
    }
    count
}

/// The pseudo-median of the paired differences `d` (Hodges–Lehmann) with the signed-rank
/// interval, each end a one-sided level-`alpha` bound. Non-finite values are dropped; `None`
/// if none is left. When every difference is zero (the same value on both sides, seed by
/// seed) the interval is `[0, 0]` at any number of pairs, as with Tango's paired interval of
/// rates without a discordant pair.
pub fn paired_shift(d: &[f64], alpha: f64) -> Option<Shift> {
    let d = sorted_finite(d);
    if d.is_empty() {
        return None;
    }
    if d.iter().all(|&x| x == 0.0) {
        return Some(Shift {
            est: 0.0,
            lo: 0.0,
            hi: 0.0,
        });
    }
    let null = RankNull::signed_rank(d.len());
    let f = |t| walsh_count_le(&d, t);
    Some(interval(
        &f,
        d[0],
        d[d.len() - 1],
        null.max(),
        null.lower_index(alpha),
    ))
}

/// The one-sided p-value of "the pseudo-median of `d` is at most `margin`" (Wilcoxon signed
/// rank, ties counted against the alternative); 1 if `d` has no finite value.
pub fn paired_p_above(d: &[f64], margin: f64) -> f64 {
    let d = sorted_finite(d);
    if d.is_empty() {
        return 1.0;
    }
    RankNull::signed_rank(d.len()).cdf(walsh_count_le(&d, margin))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every pairwise difference, sorted (the reference the bisection must reproduce).
    fn all_diffs(x: &[f64], y: &[f64]) -> Vec<f64> {
        let mut v: Vec<f64> = y
            .iter()
            .flat_map(|b| x.iter().map(move |a| b - a))
            .collect();
        v.sort_by(f64::total_cmp);
        v
    }

    #[test]
    fn unpaired_matches_brute_force_order_statistics() {
        let x: Vec<f64> = (0..9).map(|i| ((i * 37) % 11) as f64 * 0.7).collect();
        let y: Vec<f64> = (0..7).map(|i| ((i * 53) % 13) as f64 * 0.5 + 1.0).collect();
        let d = all_diffs(&x, &y);
        let s = unpaired_shift(&x, &y, 0.05).unwrap();
        let c = RankNull::mann_whitney(9, 7).lower_index(0.05).unwrap();
        let close = |a: f64, b: f64| (a - b).abs() < 1e-9;
        assert!(
            close(s.lo, d[c - 1]) && close(s.hi, d[d.len() - c]),
            "{s:?}"
        );
        // 63 differences: the median is the 32nd.
        assert!(close(s.est, d[31]), "{s:?}");
    }

    #[test]
    fn paired_matches_brute_force_and_identical_is_zero_width() {
        let d = [0.3, -0.1, 0.5, 0.2, 0.8, 0.1, 0.4, -0.2, 0.6, 0.25];
        let mut w = vec![];
        for i in 0..d.len() {
            for j in i..d.len() {
                w.push((d[i] + d[j]) / 2.0);
            }
        }
        w.sort_by(f64::total_cmp);
        let s = paired_shift(&d, 0.05).unwrap();
        let c = RankNull::signed_rank(10).lower_index(0.05).unwrap();
        let close = |a: f64, b: f64| (a - b).abs() < 1e-9;
        assert!(
            close(s.lo, w[c - 1]) && close(s.hi, w[w.len() - c]),
            "{s:?}"
        );
        assert!(close(s.est, (w[27] + w[28]) / 2.0), "{s:?}");
        for n in [1, 3, 8] {
            let z = paired_shift(&vec![0.0; n], 0.05).unwrap();
            assert_eq!((z.est, z.lo, z.hi), (0.0, 0.0, 0.0));
        }
    }

    #[test]
    fn p_values_agree_with_the_intervals() {
        let x: Vec<f64> = (0..12).map(|i| i as f64).collect();
        let y: Vec<f64> = x.iter().map(|v| v + 9.0).collect();
        let s = unpaired_shift(&x, &y, 0.05).unwrap();
        // a margin below the lower end is rejected at 5%, one above it is not
        assert!(unpaired_p_above(&x, &y, s.lo - 0.01) <= 0.05);
        assert!(unpaired_p_above(&x, &y, s.lo + 0.01) > 0.05);
        let d: Vec<f64> = (0..15).map(|i| 1.0 + 0.1 * i as f64).collect();
        let s = paired_shift(&d, 0.05).unwrap();
        assert!(paired_p_above(&d, s.lo - 0.01) <= 0.05);
        assert!(paired_p_above(&d, s.lo + 0.01) > 0.05);
        // too few pairs: unbounded
        let s = paired_shift(&[1.0, 2.0, 3.0], 0.05).unwrap();
        assert!(s.lo.is_infinite() && s.hi.is_infinite());
    }
}
