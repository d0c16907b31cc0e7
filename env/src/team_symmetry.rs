//! Central symmetry: the invariant set of a team of identical agents under one uniform field.
//!
//! Every force the planning model puts between two agents is odd in their separation
//! (`F(−r) = −F(r)`: the aligned-dipole force for any field), and the pull is the same for every
//! agent. A formation symmetric about its centroid — agents paired `i ↔ σ(i)` with
//! `P_i + P_σ(i) = 2c`, at most one agent at `c` — therefore stays symmetric, with the same
//! pairing, under every field and pull: the velocities of `i` and `σ(i)` about the centroid are
//! opposite. Its accessibility rank is the symmetric subspace's (`magbench stlc --agents 4`:
//! rank 4 of 6 for the square, the rhombus and the row), and in exact arithmetic a goal none of
//! whose formations within tolerance has that symmetry cannot be reached from it.
//!
//! The symmetric set is unstable, though: an asymmetry as small as round-off (1e-15 BL) grows
//! under the team's chaotic dynamics until the team has left it, so in floating point a planner
//! does reach such goals, through that growth, as a rig does through its noise
//! (planners/tests/integration/formation.rs shows a plan that does). [`symmetry_note`] says so.
//!
//! The least distance from a goal `G` to the symmetric set is exact: with `m_i = (G_i + G_σ(i))/2`,
//! `|S_i − G_i| + |S_σ(i) − G_σ(i)| ≥ |S_i + S_σ(i) − 2m_i| = 2|c − m_i|`, and
//! `S_i = G_i + c − m_i` attains it, so the least largest agent distance is the radius of the
//! smallest circle holding every `m_i` ([`symmetric_gap`]).

use crate::math::{Vec2, centroid};

/// Largest |P_i + P_σ(i) − 2c| (BL) at which a formation counts as symmetric: written
/// coordinates that are symmetric in decimal are symmetric to rounding (~1e-15 BL), and a
/// formation asymmetric by more is left to the planners.
pub const SYMMETRY_EPS: f64 = 1e-9;

/// The pairing `σ` (an involution, `σ(i) = i` for an agent at the centroid) under which
/// `positions` is symmetric about its centroid within `eps`, if there is one.
pub fn central_pairing(positions: &[Vec2], eps: f64) -> Option<Vec<usize>> {
    let c = centroid(positions);
    let mut pairing = Vec::with_capacity(positions.len());
    for p in positions {
        // agents stand over a body length apart, so a partner within eps is unique
        let partner = positions
            .iter()
            .position(|q| (p + q - 2.0 * c).norm() <= eps)?;
        pairing.push(partner);
    }
    let involution = pairing.iter().enumerate().all(|(i, &j)| pairing[j] == i);
    let fixed = pairing.iter().enumerate().filter(|(i, j)| i == *j).count();
    (involution && fixed <= 1).then_some(pairing)
}

/// The least largest agent distance (BL) from `goal` to a formation symmetric under `pairing`:
/// the radius of the smallest circle holding the midpoints of the paired goal positions.
pub fn symmetric_gap(goal: &[Vec2], pairing: &[usize]) -> f64 {
    let mids: Vec<Vec2> = pairing
        .iter()
        .enumerate()
        .filter(|(i, j)| i <= *j)
        .map(|(i, &j)| (goal[i] + goal[j]) / 2.0)
        .collect();
    smallest_circle_radius(&mids)
}

/// Radius of the smallest circle holding `points` (exhaustive over the circles through two or
/// three of them: a team has at most nine midpoints).
fn smallest_circle_radius(points: &[Vec2]) -> f64 {
    let holds = |c: Vec2, r: f64| {
        points
            .iter()
            .all(|p| (p - c).norm() <= r * (1.0 + 1e-12) + 1e-12)
    };
    let mut best = f64::INFINITY;
    let n = points.len();
    if n <= 1 {
        return 0.0;
    }
    for i in 0..n {
        for j in (i + 1)..n {
            let c = (points[i] + points[j]) / 2.0;
            let r = (points[i] - c).norm();
            if r < best && holds(c, r) {
                best = r;
            }
            for k in (j + 1)..n {
                if let Some((c, r)) = circumcircle(points[i], points[j], points[k])
                    && r < best
                    && holds(c, r)
                {
                    best = r;
                }
            }
        }
    }
    best
}

/// The circle through `a`, `b` and `c`, unless they are collinear.
fn circumcircle(a: Vec2, b: Vec2, c: Vec2) -> Option<(Vec2, f64)> {
    let (b, c) = (b - a, c - a);
    let d = 2.0 * (b.x * c.y - b.y * c.x);
    if d.abs() < 1e-15 {
        return None;
    }
    let (bb, cc) = (b.norm_squared(), c.norm_squared());
    let center = Vec2::new(c.y * bb - b.y * cc, b.x * cc - c.x * bb) / d;
    Some((a + center, center.norm()))
}

/// A note when `start` is symmetric about its centroid and `goal` is farther than `tolerance`
/// from every formation with its symmetry: the pairing, the distance, and that the goal is
/// reached only through the growth of an asymmetry the exact dynamics would never create.
pub fn symmetry_note(start: &[Vec2], goal: &[Vec2], tolerance: f64) -> Option<String> {
    let pairing = central_pairing(start, SYMMETRY_EPS)?;
    let gap = symmetric_gap(goal, &pairing);
    if gap <= tolerance {
        return None;
    }
    let pairs: Vec<String> = pairing
        .iter()
        .enumerate()
        .filter(|(i, j)| i < *j)
        .map(|(i, j)| format!("{i}↔{j}"))
        .collect();
    let centre = pairing
        .iter()
        .enumerate()
        .find(|(i, j)| i == *j)
        .map(|(i, _)| format!(", agent {i} at the centroid"))
        .unwrap_or_default();
    Some(format!(
        "the start is symmetric about its centroid (agents paired {}{centre}), and in exact \
         arithmetic every field keeps it so (the forces between agents are odd in their \
         separation, the pull is the same for all); the nearest formation with that symmetry is \
         {gap:.3} BL from this goal, beyond its tolerance {tolerance} BL. The symmetric \
         formations are unstable, so the goal is reached only through the growth of an asymmetry: \
         round-off in the planning model, noise on a rig (docs/physics.md, \"Central symmetry\")",
        pairs.join(", ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(p: &[[f64; 2]]) -> Vec<Vec2> {
        p.iter().map(|q| Vec2::new(q[0], q[1])).collect()
    }

    #[test]
    fn a_parallelogram_is_paired_across_its_diagonals() {
        let p = v(&[[0.0, 0.0], [2.0, 0.0], [3.0, 1.5], [1.0, 1.5]]);
        assert_eq!(central_pairing(&p, SYMMETRY_EPS), Some(vec![2, 3, 0, 1]));
    }

    #[test]
    fn a_kite_and_a_triangle_are_not_symmetric() {
        let kite = v(&[[0.0, 0.0], [2.0, 1.0], [4.0, 0.0], [2.0, -2.5]]);
        assert_eq!(central_pairing(&kite, SYMMETRY_EPS), None);
        let tri = v(&[[0.0, 0.0], [2.0, 0.0], [1.0, 1.7]]);
        assert_eq!(central_pairing(&tri, SYMMETRY_EPS), None);
    }

    #[test]
    fn a_row_of_three_has_its_middle_agent_at_the_centroid() {
        let row = v(&[[0.0, 0.0], [2.0, 0.0], [4.0, 0.0]]);
        assert_eq!(central_pairing(&row, SYMMETRY_EPS), Some(vec![2, 1, 0]));
        // a triangle's midpoints (0↔2) and agent 1 are 1.7/2 apart: the gap is half that
        let tri = v(&[[0.0, 0.0], [2.0, 1.7], [4.0, 0.0]]);
        let gap = symmetric_gap(&tri, &[2, 1, 0]);
        assert!((gap - 0.85).abs() < 1e-12, "{gap}");
        assert!(symmetry_note(&row, &tri, 0.5).is_some());
        assert!(symmetry_note(&row, &tri, 0.9).is_none());
    }

    #[test]
    fn a_pair_reaches_every_goal() {
        let pair = v(&[[0.0, 0.0], [2.0, 0.0]]);
        let goal = v(&[[5.0, 3.0], [6.0, 7.0]]);
        assert_eq!(symmetric_gap(&goal, &[1, 0]), 0.0);
        assert!(symmetry_note(&pair, &goal, 0.1).is_none());
    }

    #[test]
    fn the_gap_is_attained_by_the_symmetric_formation_it_names() {
        let square = v(&[[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]);
        let pairing = central_pairing(&square, SYMMETRY_EPS).unwrap();
        let kite = v(&[[10.0, 10.0], [12.0, 11.0], [14.0, 10.0], [12.0, 7.5]]);
        let gap = symmetric_gap(&kite, &pairing);
        // midpoints (0↔2) = (12, 10) and (1↔3) = (12, 9.25): the circle on them has radius 0.375
        assert!((gap - 0.375).abs() < 1e-12, "{gap}");
        let reason = symmetry_note(&square, &kite, 0.3).unwrap();
        assert!(
            reason.contains("0↔2, 1↔3") && reason.contains("0.375"),
            "{reason}"
        );
    }
}
