//! Goal connection by exact steering: from a tree node near the goal, env's `steer_pair`
//! solves constant commands (whole control periods) that carry a nominal pair onto the goal
//! centres; every edge is checked by the same checked propagation as EXTEND's
//! ([`propagate_valid`]), and the steer is added to the tree only if all of it is valid and it
//! ends in the goal region. Teams other than a pair under the exact flow are never connected.

use magbench_env::model::steer_pair;
use magbench_env::{MAX_AGENTS, Vec2};

use crate::Problem;
use crate::motion::propagate_valid;
use crate::nn::NearestNeighbors;
use crate::tree::Tree;

/// Goal connection settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GoalConnect {
    /// Try from nodes within this distance of the goal (the goal's distance, BL); 0: never.
    pub radius: f64,
    /// The longest steered edge, in control periods.
    pub max_periods: u32,
}

impl GoalConnect {
    /// Whether a node at `distance` from the goal is worth a try.
    pub fn near(&self, problem: &Problem, distance: f64) -> bool {
        problem.agents() == 2 && distance <= self.radius
    }

    /// Steers from node `from` onto the goal centres. On success the steer's nodes are in the
    /// tree (and `nn`, if given) with zero cost, and the last, which is in the goal region, is
    /// returned.
    pub fn run(
        &self,
        problem: &Problem,
        tree: &mut Tree,
        mut nn: Option<&mut NearestNeighbors>,
        from: u32,
    ) -> Option<u32> {
        let limits = problem.steer_limits(self.max_periods);
        let start: Vec<Vec2> = tree.state(from).to_vec();
        let mut states: Vec<[Vec2; MAX_AGENTS]> = Vec::new();
        let steer = steer_pair(
            &problem.model,
            &start,
            &problem.goal.agents,
            &limits,
            |edges| {
                states.clear();
                let mut at = [Vec2::zeros(); MAX_AGENTS];
                at[..2].copy_from_slice(&start);
                for e in edges {
                    let mut out = [Vec2::zeros(); MAX_AGENTS];
                    let d = problem.periods(e.periods);
                    if !propagate_valid(problem, &at[..2], &e.control, d, &mut out[..2]) {
                        return false;
                    }
                    states.push(out);
                    at = out;
                }
                problem.goal.contains(&at[..2])
            },
        )?;
        let mut node = from;
        for (e, s) in steer.iter().zip(&states) {
            node = tree.add(node, &s[..2], e.control, e.periods, 0.0);
            if let Some(nn) = nn.as_deref_mut() {
                nn.add(&s[..2], node);
            }
        }
        Some(node)
    }
}
