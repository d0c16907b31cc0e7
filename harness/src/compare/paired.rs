//! Two planners compared problem by problem on their per-problem times ([`super::instances`]):
//! how often the first is faster (win rate with its Wilson interval) and by what factor
//! (the Hodges–Lehmann estimate of the median ratio of times, with the Wilcoxon signed-rank
//! interval, over the problems both solved).

use crate::stats::shift::paired_shift;
use crate::stats::wilson;

/// The paired comparison of planner A against planner B.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Paired {
    /// Problems where both planners have a value.
    pub problems: usize,
    /// Problems where A is faster (an unsolved problem is slower than any time).
    pub wins: usize,
    /// Problems where B is faster.
    pub losses: usize,
    /// Equal times, or both unsolved.
    pub ties: usize,
    /// `wins / (wins + losses)`: NaN without a decided problem.
    pub win_rate: f64,
    /// 95% Wilson interval of the win rate.
    pub win_ci: (f64, f64),
    /// Problems both solved: the ratio is computed over them.
    pub both_solved: usize,
    /// Hodges–Lehmann estimate of A's time over B's (below 1: A is faster), `None` without a
    /// problem both solved.
    pub ratio: Option<f64>,
    /// 95% interval of the ratio (each end a one-sided 2.5% bound).
    pub ratio_ci: (f64, f64),
}

/// Compares times `a` and `b` (one value per problem, the same order; +∞ = unsolved, NaN = no
/// value).
pub fn paired(a: &[f64], b: &[f64]) -> Paired {
    let (mut wins, mut losses, mut ties, mut problems) = (0, 0, 0, 0);
    let mut log_ratios = vec![];
    for (&x, &y) in a.iter().zip(b) {
        if x.is_nan() || y.is_nan() {
            continue;
        }
        problems += 1;
        if x < y {
            wins += 1;
        } else if y < x {
            losses += 1;
        } else {
            ties += 1;
        }
        if x.is_finite() && y.is_finite() && x > 0.0 && y > 0.0 {
            log_ratios.push(x.ln() - y.ln());
        }
    }
    let decided = (wins + losses) as u64;
    let win_rate = if decided == 0 {
        f64::NAN
    } else {
        wins as f64 / decided as f64
    };
    let shift = paired_shift(&log_ratios, 0.025);
    Paired {
        problems,
        wins,
        losses,
        ties,
        win_rate,
        win_ci: wilson(wins as u64, decided, 0.95),
        both_solved: log_ratios.len(),
        ratio: shift.map(|s| s.est.exp()),
        ratio_ci: shift.map_or((f64::NAN, f64::NAN), |s| (s.lo.exp(), s.hi.exp())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const INF: f64 = f64::INFINITY;

    #[test]
    fn twice_as_fast_everywhere() {
        let p = paired(&[1.0, 2.0, 4.0, 8.0], &[2.0, 4.0, 8.0, 16.0]);
        assert_eq!((p.problems, p.wins, p.losses, p.ties), (4, 4, 0, 0));
        assert_eq!(p.win_rate, 1.0);
        assert_eq!(p.win_ci, wilson(4, 4, 0.95));
        assert_eq!(p.both_solved, 4);
        assert!((p.ratio.unwrap() - 0.5).abs() < 1e-12);
        // Four pairs cannot reach a one-sided 2.5% signed-rank bound: the interval is open.
        assert_eq!(p.ratio_ci, (0.0, f64::INFINITY));
        let b: Vec<f64> = (1..=8).map(|i| i as f64).collect();
        let a: Vec<f64> = b.iter().map(|x| x / 2.0).collect();
        let p = paired(&a, &b);
        assert!((p.ratio_ci.0 - 0.5).abs() < 1e-12 && (p.ratio_ci.1 - 0.5).abs() < 1e-12);
    }

    #[test]
    fn unsolved_loses_and_ratio_uses_problems_both_solved() {
        let p = paired(&[1.0, INF, INF, 2.0, 3.0], &[2.0, 1.0, INF, 1.0, f64::NAN]);
        assert_eq!((p.problems, p.wins, p.losses, p.ties), (4, 1, 2, 1));
        assert!((p.win_rate - 1.0 / 3.0).abs() < 1e-12);
        assert_eq!(p.both_solved, 2);
        // log ratios −ln 2 and ln 2: Walsh averages −ln 2, 0, ln 2, median 0.
        assert!((p.ratio.unwrap() - 1.0).abs() < 1e-12);
        assert!(p.ratio_ci.0 <= 0.5 + 1e-12 && p.ratio_ci.1 >= 2.0 - 1e-12);
    }

    #[test]
    fn nothing_solved_has_no_ratio() {
        let p = paired(&[INF, INF], &[INF, INF]);
        assert_eq!((p.wins, p.losses, p.ties), (0, 0, 2));
        assert!(p.win_rate.is_nan() && p.ratio.is_none());
        assert_eq!(p.win_ci, (0.0, 1.0));
    }

    #[test]
    fn ratio_interval_covers_a_noisy_factor_of_three() {
        let b: Vec<f64> = (1..=30).map(|i| i as f64).collect();
        let a: Vec<f64> = b
            .iter()
            .enumerate()
            .map(|(i, x)| 3.0 * x * if i % 2 == 0 { 1.1 } else { 1.0 / 1.1 })
            .collect();
        let p = paired(&a, &b);
        assert_eq!(p.losses, 30);
        let r = p.ratio.unwrap();
        assert!((r - 3.0).abs() < 0.2, "{r}");
        assert!(p.ratio_ci.0 < 3.0 && 3.0 < p.ratio_ci.1, "{:?}", p.ratio_ci);
        assert!(p.ratio_ci.0 > 2.7 && p.ratio_ci.1 < 3.3, "{:?}", p.ratio_ci);
    }
}
