//! Intervals and one-sided tests of a difference of two success rates `p₁ − p₂`:
//!
//! - independent samples: Newcombe's hybrid score interval (method 10 of Newcombe 1998, built
//!   from the two Wilson intervals), which keeps its coverage near 0 and 1 where the Wald
//!   interval collapses;
//! - paired samples (the same seeds on both sides): Tango's score interval (Tango 1998), the
//!   inversion of the McNemar-type score test, from the discordant pairs. With no discordant
//!   pair the observed per-seed differences are all zero and the interval is `[0, 0]`.
//!
//! Each end is a one-sided bound at the normal quantile `z` (z = 1.645: one-sided 5% ends, a
//! two-sided 90% interval).

use super::normal_sf;
use super::proportion::wilson_z;

/// A difference of rates with its interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RateDiff {
    /// The observed difference.
    pub est: f64,
    /// Lower end.
    pub lo: f64,
    /// Upper end.
    pub hi: f64,
}

/// Newcombe's hybrid score interval of `s1/n1 − s2/n2` (independent samples).
pub fn newcombe(s1: u64, n1: u64, s2: u64, n2: u64, z: f64) -> RateDiff {
    let rate = |s: u64, n: u64| if n == 0 { 0.0 } else { s as f64 / n as f64 };
    let (p1, p2) = (rate(s1, n1), rate(s2, n2));
    let (l1, u1) = wilson_z(s1, n1, z);
    let (l2, u2) = wilson_z(s2, n2, z);
    let est = p1 - p2;
    RateDiff {
        est,
        lo: est - ((p1 - l1).powi(2) + (u2 - p2).powi(2)).sqrt(),
        hi: est + ((u1 - p1).powi(2) + (p2 - l2).powi(2)).sqrt(),
    }
}

/// The one-sided p-value of "`p₁ − p₂ ≤ margin`" from Newcombe's interval: the level at
/// which its lower end reaches `margin` (1 when the estimate itself is at most `margin`).
pub fn newcombe_p_above(s1: u64, n1: u64, s2: u64, n2: u64, margin: f64) -> f64 {
    let lo = |z: f64| newcombe(s1, n1, s2, n2, z).lo;
    if lo(0.0) <= margin {
        return 1.0;
    }
    let (mut a, mut b) = (0.0, 40.0);
    if lo(b) > margin {
        return normal_sf(b);
    }
    for _ in 0..100 {
        let m = 0.5 * (a + b);
        if lo(m) > margin { a = m } else { b = m }
    }
    normal_sf(a)
}

/// Tango's score statistic for `Δ = p₁ − p₂ = delta` from `n12` pairs (first success, second
/// failure), `n21` pairs (first failure, second success) of `n`; decreasing in `delta`.
fn tango_t(n12: u64, n21: u64, n: u64, delta: f64) -> f64 {
    let (b, c, nf) = (n12 as f64, n21 as f64, n as f64);
    // the restricted maximum-likelihood estimate of p₂₁ given Δ
    let w = -b - c + (2.0 * nf - b + c) * delta;
    let q = ((w * w + 8.0 * nf * c * delta * (1.0 - delta))
        .max(0.0)
        .sqrt()
        - w)
        / (4.0 * nf);
    let num = b - c - nf * delta;
    let var = nf * (2.0 * q + delta * (1.0 - delta));
    if num == 0.0 {
        0.0
    } else if var <= 0.0 {
        num.signum() * f64::INFINITY
    } else {
        num / var.sqrt()
    }
}

/// The root in `(-1, 1)` of `tango_t(..) = target` (the statistic decreases in Δ).
fn tango_root(n12: u64, n21: u64, n: u64, target: f64) -> f64 {
    let (mut a, mut b) = (-1.0, 1.0);
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if tango_t(n12, n21, n, m) > target {
            a = m
        } else {
            b = m
        }
    }
    0.5 * (a + b)
}

/// Tango's score interval of `p₁ − p₂` from paired outcomes: `n12` pairs where only the first
/// succeeded, `n21` where only the second did, `n` pairs in all.
pub fn tango(n12: u64, n21: u64, n: u64, z: f64) -> RateDiff {
    if n == 0 {
        return RateDiff {
            est: 0.0,
            lo: -1.0,
            hi: 1.0,
        };
    }
    let est = (n12 as f64 - n21 as f64) / n as f64;
    if n12 == 0 && n21 == 0 {
        return RateDiff {
            est,
            lo: 0.0,
            hi: 0.0,
        };
    }
    RateDiff {
        est,
        lo: tango_root(n12, n21, n, z),
        hi: tango_root(n12, n21, n, -z),
    }
}

/// The one-sided p-value of "`p₁ − p₂ ≤ margin`" by Tango's score test (1 with no discordant
/// pair: every seed gave the same outcome on both sides).
pub fn tango_p_above(n12: u64, n21: u64, n: u64, margin: f64) -> f64 {
    if n == 0 || n12 + n21 == 0 {
        return 1.0;
    }
    normal_sf(tango_t(n12, n21, n, margin))
}

#[cfg(test)]
mod tests {
    use super::*;

    const Z95: f64 = 1.959963984540054;

    #[test]
    fn newcombe_matches_the_published_example() {
        // Newcombe (1998), Statistics in Medicine 17:873, table II, example (a): 56/70 − 48/80,
        // method 10: 0.0524 to 0.3339.
        let d = newcombe(56, 70, 48, 80, Z95);
        assert!((d.est - 0.2).abs() < 1e-12);
        assert!(
            (d.lo - 0.0524).abs() < 5e-5 && (d.hi - 0.3339).abs() < 5e-5,
            "{d:?}"
        );
        // example (d): 0/10 − 0/20: −0.1611 to 0.2775
        let d = newcombe(0, 10, 0, 20, Z95);
        assert!(
            (d.lo + 0.1611).abs() < 5e-5 && (d.hi - 0.2775).abs() < 5e-5,
            "{d:?}"
        );
    }

    #[test]
    fn tango_matches_the_published_example() {
        // Fagerland, Lydersen & Laake (2013), Statistics in Medicine 32:1810, the airway
        // hyper-responsiveness example (n12 = 1, n21 = 7 of 21): Tango's interval −0.517 to
        // −0.026; and 1, 2 of 44 against a numeric maximisation of the restricted likelihood
        // (independent of the closed form): −0.13299 to 0.08010.
        let d = tango(1, 7, 21, Z95);
        assert!((d.est + 6.0 / 21.0).abs() < 1e-12);
        assert!(
            (d.lo + 0.5172).abs() < 1e-4 && (d.hi + 0.0260).abs() < 1e-4,
            "{d:?}"
        );
        let d = tango(1, 2, 44, Z95);
        assert!(
            (d.lo + 0.13299).abs() < 1e-5 && (d.hi - 0.08010).abs() < 1e-5,
            "{d:?}"
        );
        let zero = tango(0, 0, 8, Z95);
        assert_eq!((zero.lo, zero.hi), (0.0, 0.0));
    }

    #[test]
    fn p_values_agree_with_the_intervals() {
        let z = 1.6448536269514722;
        let d = newcombe(40, 40, 20, 40, z);
        assert!(newcombe_p_above(40, 40, 20, 40, d.lo - 1e-6) < 0.05);
        assert!(newcombe_p_above(40, 40, 20, 40, d.lo + 1e-6) > 0.05);
        let t = tango(20, 0, 40, z);
        assert!(tango_p_above(20, 0, 40, t.lo - 1e-6) < 0.05);
        assert!(tango_p_above(20, 0, 40, t.lo + 1e-6) > 0.05);
    }
}
