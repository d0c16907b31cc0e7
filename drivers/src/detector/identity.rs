//! Keeping agent identity from frame to frame: nearest assignment within a gate.

use magbench_env::Vec2;

/// Assigns candidates to agents: the closest (agent, candidate) pairs first, each used once,
/// no pair farther than its agent's gate. Returns, per agent, the index of its candidate.
pub fn assign(previous: &[Vec2], gates: &[f64], candidates: &[Vec2]) -> Vec<Option<usize>> {
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (i, p) in previous.iter().enumerate() {
        for (j, c) in candidates.iter().enumerate() {
            let d = (c - p).norm();
            if d <= gates[i] {
                pairs.push((d, i, j));
            }
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out = vec![None; previous.len()];
    let mut used = vec![false; candidates.len()];
    for (_, i, j) in pairs {
        if out[i].is_none() && !used[j] {
            out[i] = Some(j);
            used[j] = true;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_wins_and_gates_hold() {
        let prev = [Vec2::new(0.0, 0.0), Vec2::new(2.0, 0.0)];
        let cand = [Vec2::new(2.1, 0.0), Vec2::new(0.1, 0.0)];
        assert_eq!(assign(&prev, &[1.0, 1.0], &cand), vec![Some(1), Some(0)]);
        let far = [Vec2::new(5.0, 0.0), Vec2::new(0.1, 0.0)];
        assert_eq!(assign(&prev, &[1.0, 1.0], &far), vec![Some(1), None]);
    }
}
