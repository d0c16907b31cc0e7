//! Success rates: Wilson and Clopper–Pearson intervals.

use statrs::distribution::{Beta, ContinuousCDF};

use super::normal_quantile;

/// The Wilson score interval of a success rate `s/n` at `level` (e.g. 0.95); `(0, 1)` if n = 0.
pub fn wilson(s: u64, n: u64, level: f64) -> (f64, f64) {
    wilson_z(s, n, normal_quantile(1.0 - (1.0 - level) / 2.0))
}

/// The Wilson score interval of `s/n` at the normal quantile `z`; `(0, 1)` if n = 0.
pub fn wilson_z(s: u64, n: u64, z: f64) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let (nf, p) = (n as f64, s as f64 / n as f64);
    let d = 1.0 + z * z / nf;
    let c = (p + z * z / (2.0 * nf)) / d;
    let h = z * (p * (1.0 - p) / nf + z * z / (4.0 * nf * nf)).sqrt() / d;
    let lo = if s == 0 { 0.0 } else { (c - h).max(0.0) };
    let hi = if s >= n { 1.0 } else { (c + h).min(1.0) };
    (lo, hi)
}

/// The exact (Clopper–Pearson) interval of `s/n` at `level`; `(0, 1)` if n = 0.
pub fn clopper_pearson(s: u64, n: u64, level: f64) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let a = 1.0 - level;
    let (sf, nf) = (s as f64, n as f64);
    let lo = if s == 0 {
        0.0
    } else {
        Beta::new(sf, nf - sf + 1.0)
            .map(|b| b.inverse_cdf(a / 2.0))
            .unwrap_or(0.0)
    };
    let hi = if s >= n {
        1.0
    } else {
        Beta::new(sf + 1.0, nf - sf)
            .map(|b| b.inverse_cdf(1.0 - a / 2.0))
            .unwrap_or(1.0)
    };
    (lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    // Reference values computed with SciPy 1.10 (norm, beta.ppf).

    #[test]
    fn wilson_matches_reference() {
        let (lo, hi) = wilson(8, 10, 0.95);
        assert!((lo - 0.49016247153664183).abs() < 1e-9 && (hi - 0.9433178485456247).abs() < 1e-9);
        let (lo, hi) = wilson(0, 20, 0.95);
        assert!(lo == 0.0 && (hi - 0.16112515805281938).abs() < 1e-9);
        let (lo, hi) = wilson(20, 20, 0.95);
        assert!((lo - 0.8388748419471806).abs() < 1e-9 && hi == 1.0);
    }

    #[test]
    fn clopper_pearson_matches_reference() {
        let (lo, hi) = clopper_pearson(8, 10, 0.95);
        assert!(
            (lo - 0.4439045376923585).abs() < 1e-8 && (hi - 0.9747892736731666).abs() < 1e-8,
            "{lo} {hi}"
        );
        let (lo, hi) = clopper_pearson(0, 20, 0.95);
        assert!(lo == 0.0 && (hi - 0.1684334709830853).abs() < 1e-8);
        let (lo, hi) = clopper_pearson(7, 25, 0.95);
        assert!((lo - 0.12071668850406661).abs() < 1e-8 && (hi - 0.49387682180625553).abs() < 1e-8);
        assert_eq!(clopper_pearson(0, 0, 0.95), (0.0, 1.0));
    }
}
