//! Small statistics for reports: percentiles of latencies and errors.

/// The `q`-quantile (0 ≤ q ≤ 1) of `v` by linear interpolation; `None` when `v` is empty.
pub fn percentile(v: &[f64], q: f64) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let x = q.clamp(0.0, 1.0) * (s.len() - 1) as f64;
    let (i, f) = (x.floor() as usize, x.fract());
    Some(if i + 1 < s.len() {
        s[i] * (1.0 - f) + s[i + 1] * f
    } else {
        s[i]
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn percentiles_interpolate() {
        let v = [4.0, 1.0, 3.0, 2.0];
        assert_eq!(super::percentile(&v, 0.5), Some(2.5));
        assert_eq!(super::percentile(&v, 1.0), Some(4.0));
        assert_eq!(super::percentile(&[], 0.5), None);
    }
}
