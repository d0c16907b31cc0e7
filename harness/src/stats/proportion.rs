//! Success rates: the pooled two-proportion z test and Wilson and Clopper–Pearson intervals.

use statrs::distribution::{Beta, ContinuousCDF};

use super::{Alternative, normal_quantile, normal_sf};

/// The pooled two-proportion z test of `s1/n1` against `s2/n2`: returns `(z, p)` with
/// `z = (p̂₁ − p̂₂)/√(p̄(1 − p̄)(1/n₁ + 1/n₂))`. `Less` means the first rate is smaller.
/// With no variance (both rates 0 or both 1) or an empty sample, `z = 0` and `p = 1`.
pub fn two_proportion_z(s1: u64, n1: u64, s2: u64, n2: u64, alt: Alternative) -> (f64, f64) {
    if n1 == 0 || n2 == 0 {
        return (0.0, 1.0);
    }
    let (p1, p2) = (s1 as f64 / n1 as f64, s2 as f64 / n2 as f64);
    let pool = (s1 + s2) as f64 / (n1 + n2) as f64;
    let se = (pool * (1.0 - pool) * (1.0 / n1 as f64 + 1.0 / n2 as f64)).sqrt();
    if se == 0.0 {
        return (0.0, 1.0);
    }
    let z = (p1 - p2) / se;
    let p = match alt {
        Alternative::TwoSided => (2.0 * normal_sf(z.abs())).min(1.0),
        Alternative::Greater => normal_sf(z),
        Alternative::Less => normal_sf(-z),
    };
    (z, p)
}

/// The Wilson score interval of a success rate `s/n` at `level` (e.g. 0.95); `(0, 1)` if n = 0.
pub fn wilson(s: u64, n: u64, level: f64) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let z = normal_quantile(1.0 - (1.0 - level) / 2.0);
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
    fn two_proportion_z_textbook() {
        // 45/50 vs 30/50: pooled p̄ = 0.75, z = 0.3/√(0.75·0.25·0.04) = 3.4641.
        let (z, p) = two_proportion_z(45, 50, 30, 50, Alternative::TwoSided);
        assert!((z - 3.4641016151377553).abs() < 1e-12);
        assert!((p - 0.0005320055051392477).abs() < 1e-9, "{p}");
        let (_, pg) = two_proportion_z(45, 50, 30, 50, Alternative::Greater);
        assert!((pg - 0.00026600275256962385).abs() < 1e-9);
        let (_, pl) = two_proportion_z(45, 50, 30, 50, Alternative::Less);
        assert!((pl - (1.0 - 0.00026600275256962385)).abs() < 1e-9);
        assert_eq!(
            two_proportion_z(10, 10, 20, 20, Alternative::TwoSided),
            (0.0, 1.0)
        );
    }

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
