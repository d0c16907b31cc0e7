//! A seeded percentile bootstrap of the difference of medians, `median(y) − median(x)`.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::quantile::{quantile_sorted, sorted_finite};

/// A bootstrap confidence interval of `median(y) − median(x)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MedianDiffCi {
    /// The observed difference.
    pub diff: f64,
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
    /// Confidence level, e.g. 0.95.
    pub level: f64,
}

fn resampled_median(v: &[f64], rng: &mut ChaCha8Rng, buf: &mut Vec<f64>) -> f64 {
    buf.clear();
    buf.extend((0..v.len()).map(|_| v[rng.random_range(0..v.len())]));
    buf.sort_by(f64::total_cmp);
    quantile_sorted(buf, 0.5)
}

/// The percentile bootstrap CI (at `level`, from `resamples` resamples of each sample drawn
/// with a ChaCha8 stream seeded by `seed`) of `median(y) − median(x)`. Non-finite values are
/// dropped; `None` if either sample is then empty. Same inputs, same seed: same interval.
pub fn median_diff_ci(
    x: &[f64],
    y: &[f64],
    level: f64,
    resamples: usize,
    seed: u64,
) -> Option<MedianDiffCi> {
    let (x, y) = (sorted_finite(x), sorted_finite(y));
    if x.is_empty() || y.is_empty() || resamples == 0 {
        return None;
    }
    let diff = quantile_sorted(&y, 0.5) - quantile_sorted(&x, 0.5);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut buf = Vec::with_capacity(x.len().max(y.len()));
    let mut d: Vec<f64> = (0..resamples)
        .map(|_| {
            let mx = resampled_median(&x, &mut rng, &mut buf);
            resampled_median(&y, &mut rng, &mut buf) - mx
        })
        .collect();
    d.sort_by(f64::total_cmp);
    let a = (1.0 - level) / 2.0;
    Some(MedianDiffCi {
        diff,
        lo: quantile_sorted(&d, a),
        hi: quantile_sorted(&d, 1.0 - a),
        level,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn covers_a_clear_shift_and_excludes_zero() {
        let x: Vec<f64> = (0..40).map(|i| (i % 10) as f64).collect();
        let y: Vec<f64> = x.iter().map(|v| v + 5.0).collect();
        let ci = median_diff_ci(&x, &y, 0.95, 2000, 7).unwrap();
        assert_eq!(ci.diff, 5.0);
        assert!(ci.lo > 0.0 && ci.lo <= 5.0 && ci.hi >= 5.0, "{ci:?}");
    }

    #[test]
    fn same_distribution_interval_contains_zero() {
        let x: Vec<f64> = (0..30).map(|i| ((i * 37) % 101) as f64).collect();
        let y: Vec<f64> = (0..30).map(|i| ((i * 53 + 11) % 101) as f64).collect();
        let ci = median_diff_ci(&x, &y, 0.95, 2000, 1).unwrap();
        assert!(ci.lo <= 0.0 && ci.hi >= 0.0, "{ci:?}");
    }

    #[test]
    fn seeded_and_degenerate_cases() {
        let x = [1.0, 2.0, 3.0, 4.0];
        let y = [2.0, 3.0, 5.0, 8.0];
        assert_eq!(
            median_diff_ci(&x, &y, 0.9, 500, 3),
            median_diff_ci(&x, &y, 0.9, 500, 3)
        );
        assert_ne!(
            median_diff_ci(&x, &y, 0.9, 500, 3),
            median_diff_ci(&x, &y, 0.9, 500, 4)
        );
        let c = median_diff_ci(&[2.0], &[2.0], 0.95, 100, 0).unwrap();
        assert_eq!((c.diff, c.lo, c.hi), (0.0, 0.0, 0.0));
        assert!(median_diff_ci(&[], &y, 0.95, 100, 0).is_none());
    }
}
