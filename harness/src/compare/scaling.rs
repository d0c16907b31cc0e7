//! How time grows with a problem size: the least-squares line through
//! `(ln size, ln median time)`, whose slope is the exponent `b` of `time ≈ a·size^b`, with its
//! 95% t interval (regression standard error, n − 2 degrees of freedom).

use statrs::distribution::{ContinuousCDF, StudentsT};

/// A fitted power law `time ≈ a·size^b`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PowerFit {
    /// Points fitted.
    pub n: usize,
    /// The exponent `b`.
    pub exponent: f64,
    /// 95% interval of the exponent (NaN ends with fewer than three points).
    pub ci: (f64, f64),
    /// The factor `a` (time at size 1).
    pub factor: f64,
}

/// Fits `y ≈ a·x^b` to the points with `x > 0` and finite `y > 0`; `None` with fewer than two
/// distinct sizes.
pub fn fit(points: &[(f64, f64)]) -> Option<PowerFit> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && x.is_finite() && *y > 0.0 && y.is_finite())
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    let n = pts.len();
    if n < 2 {
        return None;
    }
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n as f64;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n as f64;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let b = sxy / sxx;
    let a = my - b * mx;
    let ci = if n > 2 {
        let sse: f64 = pts.iter().map(|p| (p.1 - a - b * p.0).powi(2)).sum();
        let se = (sse / (n - 2) as f64 / sxx).sqrt();
        let t = StudentsT::new(0.0, 1.0, (n - 2) as f64)
            .map(|d| d.inverse_cdf(0.975))
            .unwrap_or(f64::NAN);
        (b - t * se, b + t * se)
    } else {
        (f64::NAN, f64::NAN)
    };
    Some(PowerFit {
        n,
        exponent: b,
        ci,
        factor: a.exp(),
    })
}

/// The value of parameter `key` in a generated scenario's label
/// (`serpentine-gap=4-walls=8-s2` has `walls` = 8).
pub fn label_param(label: &str, key: &str) -> Option<f64> {
    let prefix = format!("{key}=");
    label
        .split('-')
        .find_map(|part| part.strip_prefix(&prefix))
        .and_then(|v| v.parse().ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_power_law_has_a_point_interval() {
        let pts: Vec<(f64, f64)> = [1.0, 2.0, 4.0, 8.0, 16.0]
            .iter()
            .map(|&k: &f64| (k, 3.0 * k.powf(1.8)))
            .collect();
        let f = fit(&pts).unwrap();
        assert!((f.exponent - 1.8).abs() < 1e-12);
        assert!((f.factor - 3.0).abs() < 1e-9);
        assert!((f.ci.0 - 1.8).abs() < 1e-9 && (f.ci.1 - 1.8).abs() < 1e-9);
    }

    #[test]
    fn hand_computed_slope_and_t_interval() {
        // ln x = 0, 1, 2 and ln y = 0, 1, 3: slope 3/2, SSE 1/6, se √(1/12), t(0.975, 1) = 12.706.
        let e = std::f64::consts::E;
        let f = fit(&[(1.0, 1.0), (e, e), (e * e, e.powi(3))]).unwrap();
        assert!((f.exponent - 1.5).abs() < 1e-12);
        let half = 12.706_204_736 * (1.0f64 / 12.0).sqrt();
        assert!((f.ci.0 - (1.5 - half)).abs() < 1e-6, "{:?}", f.ci);
        assert!((f.ci.1 - (1.5 + half)).abs() < 1e-6, "{:?}", f.ci);
    }

    #[test]
    fn unsolved_and_single_size_points_do_not_fit() {
        assert!(fit(&[(2.0, 1.0), (2.0, 3.0)]).is_none());
        assert!(fit(&[(1.0, 1.0), (2.0, f64::INFINITY)]).is_none());
        let f = fit(&[(1.0, 1.0), (2.0, 4.0)]).unwrap();
        assert!((f.exponent - 2.0).abs() < 1e-12 && f.ci.0.is_nan());
    }

    #[test]
    fn reads_parameters_from_generated_labels() {
        assert_eq!(
            label_param("serpentine-gap=4-walls=8-s2", "walls"),
            Some(8.0)
        );
        assert_eq!(label_param("corridor-length=30.5-s0", "length"), Some(30.5));
        assert_eq!(label_param("micro-factory", "walls"), None);
    }
}
