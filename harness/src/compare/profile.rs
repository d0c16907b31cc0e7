//! Dolan–Moré performance profiles: for each planner, the fraction of problems it solves
//! within τ times the best planner's time on that problem, for τ ≥ 1 (E. D. Dolan and
//! J. J. Moré, "Benchmarking optimization software with performance profiles", 2002).
//! A problem no planner solves counts for every planner as unsolved at every τ.

/// Performance ratios `r[p][i] = t[p][i] / min_q t[q][i]`: +∞ where planner `p` did not solve
/// problem `i` (an infinite or NaN time) or no planner did.
pub fn ratios(times: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let problems = times.iter().map(Vec::len).max().unwrap_or(0);
    let best: Vec<f64> = (0..problems)
        .map(|i| {
            times
                .iter()
                .filter_map(|row| row.get(i).copied())
                .filter(|t| t.is_finite())
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    times
        .iter()
        .map(|row| {
            (0..problems)
                .map(|i| match row.get(i) {
                    Some(&t) if t.is_finite() && best[i].is_finite() => {
                        if best[i] > 0.0 {
                            t / best[i]
                        } else if t > 0.0 {
                            f64::INFINITY
                        } else {
                            1.0
                        }
                    }
                    _ => f64::INFINITY,
                })
                .collect()
        })
        .collect()
}

/// `ρ_p(τ)` for each planner (rows of `times`) at each `τ` of `taus`: the fraction of problems
/// with a ratio at most `τ`.
pub fn profile(times: &[Vec<f64>], taus: &[f64]) -> Vec<Vec<f64>> {
    let r = ratios(times);
    r.iter()
        .map(|row| {
            let n = row.len().max(1) as f64;
            taus.iter()
                .map(|&tau| row.iter().filter(|&&x| x <= tau).count() as f64 / n)
                .collect()
        })
        .collect()
}

/// `n` values of τ from 1 to a bit past the largest finite ratio (at least 2), evenly spaced
/// on a log axis.
pub fn tau_grid(times: &[Vec<f64>], n: usize) -> Vec<f64> {
    let max = ratios(times)
        .iter()
        .flatten()
        .copied()
        .filter(|x| x.is_finite())
        .fold(2.0, f64::max)
        * 1.05;
    let n = n.max(2);
    (0..n)
        .map(|k| max.powf(k as f64 / (n - 1) as f64))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const INF: f64 = f64::INFINITY;

    #[test]
    fn ratios_against_the_best_planner() {
        let t = vec![vec![1.0, 4.0, INF, INF], vec![2.0, 2.0, 3.0, INF]];
        let r = ratios(&t);
        assert_eq!(r[0], [1.0, 2.0, INF, INF]);
        assert_eq!(r[1], [2.0, 1.0, 1.0, INF]);
    }

    #[test]
    fn profile_is_the_fraction_within_tau() {
        let t = vec![vec![1.0, 4.0, INF, INF], vec![2.0, 2.0, 3.0, INF]];
        let p = profile(&t, &[1.0, 1.5, 2.0, 100.0]);
        assert_eq!(p[0], [0.25, 0.25, 0.5, 0.5]);
        assert_eq!(p[1], [0.5, 0.5, 0.75, 0.75]);
    }

    #[test]
    fn at_tau_one_the_winners_share_each_problem() {
        // Ties count for both; ρ(1) summed over planners is at least the problems solved.
        let t = vec![
            vec![1.0, 1.0, 5.0],
            vec![1.0, 2.0, 4.0],
            vec![3.0, 2.0, 6.0],
        ];
        let p = profile(&t, &[1.0]);
        let (a, b, c) = (p[0][0], p[1][0], p[2][0]);
        assert_eq!((a * 3.0, b * 3.0, c * 3.0), (2.0, 2.0, 0.0));
    }

    #[test]
    fn tau_grid_spans_the_largest_ratio_on_a_log_scale() {
        let g = tau_grid(&[vec![1.0, 10.0], vec![8.0, 1.0]], 5);
        assert_eq!(g[0], 1.0);
        assert!((g[4] - 10.5).abs() < 1e-9);
        assert!((g[2] - 10.5f64.sqrt()).abs() < 1e-9);
    }
}
