//! Medians, quantiles and five-number summaries (linear interpolation, R's type 7 / NumPy's
//! default).

/// The `p`-quantile of an ascending, non-empty slice without NaN, interpolating linearly
/// between order statistics.
pub fn quantile_sorted(sorted: &[f64], p: f64) -> f64 {
    assert!(!sorted.is_empty(), "quantile of an empty sample");
    let h = (sorted.len() - 1) as f64 * p.clamp(0.0, 1.0);
    let lo = h.floor() as usize;
    let hi = h.ceil() as usize;
    sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
}

/// Sorts the finite values of `v` (NaN and infinities dropped).
pub fn sorted_finite(v: &[f64]) -> Vec<f64> {
    let mut s: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    s.sort_by(f64::total_cmp);
    s
}

/// The median of the finite values of `v`, or `None` if there are none.
pub fn median(v: &[f64]) -> Option<f64> {
    let s = sorted_finite(v);
    (!s.is_empty()).then(|| quantile_sorted(&s, 0.5))
}

/// A five-number summary plus count and mean.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Summary {
    /// Number of finite values.
    pub n: usize,
    /// Smallest value.
    pub min: f64,
    /// First quartile.
    pub q1: f64,
    /// Median.
    pub median: f64,
    /// Third quartile.
    pub q3: f64,
    /// Largest value.
    pub max: f64,
    /// Arithmetic mean.
    pub mean: f64,
}

impl Summary {
    /// The summary of the finite values of `v`, or `None` if there are none.
    pub fn of(v: &[f64]) -> Option<Summary> {
        let s = sorted_finite(v);
        if s.is_empty() {
            return None;
        }
        Some(Summary {
            n: s.len(),
            min: s[0],
            q1: quantile_sorted(&s, 0.25),
            median: quantile_sorted(&s, 0.5),
            q3: quantile_sorted(&s, 0.75),
            max: s[s.len() - 1],
            mean: s.iter().sum::<f64>() / s.len() as f64,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_numpy_type7() {
        // numpy.quantile([3,1,4,1,5,9,2,6,5,3,5], [0, .25, .5, .75, 1]) = [1, 2.5, 4, 5, 9]
        let s = Summary::of(&[3.0, 1.0, 4.0, 1.0, 5.0, 9.0, 2.0, 6.0, 5.0, 3.0, 5.0]).unwrap();
        assert_eq!(
            (s.min, s.q1, s.median, s.q3, s.max),
            (1.0, 2.5, 4.0, 5.0, 9.0)
        );
        assert_eq!(s.n, 11);
        assert!((s.mean - 44.0 / 11.0).abs() < 1e-12);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), Some(2.5));
        assert_eq!(median(&[f64::NAN, 7.0]), Some(7.0));
        assert_eq!(median(&[]), None);
        assert_eq!(quantile_sorted(&[1.0, 2.0], 0.1), 1.1);
    }
}
