//! Goal connection by exact steering: from a tree node near the goal, env's `steer_pair`
//! solves constant commands (whole control periods) that carry a nominal pair onto the goal
//! centres; every edge is checked by the same checked propagation as EXTEND's
//! ([`propagate_valid`]), and the steer is added to the tree only if all of it is valid and it
//! ends in the goal region. Teams other than a pair under the exact flow are never connected.
//!
//! A goal in a pocket (agents in chambers, a dock) is rarely reached by one steer: the pair's
//! centre moves on a straight line while its shape changes, and the agents cut across the
//! pocket's walls. So such a goal, one whose agents are not both [`APPROACH_CLEARANCE`] clear,
//! also has *approaches*: in each of [`APPROACH_DIRECTIONS`] directions, rungs of the goal's
//! shape translated straight out of it by each of [`APPROACH_DISTANCES`] in turn, for as long
//! as both agents sweep clear from the goal, up to the first rung where both are
//! [`APPROACH_CLEARANCE`] clear. Each rung steers into the one below it (the first into the
//! goal), solved once, from the rung, the first time it is needed. A node near a rung, closer
//! to it than any node before, is steered onto the rung and then along the rung's steer into
//! the goal; the whole is added only if every edge is valid and it ends in the goal region.

use std::f64::consts::TAU;

use magbench_env::math::max_agent_distance;
use magbench_env::model::{SteerEdge, steer_pair};
use magbench_env::{MAX_AGENTS, Vec2};

use crate::Problem;
use crate::motion::propagate_valid;
use crate::nn::NearestNeighbors;
use crate::tree::Tree;

/// Directions, evenly spaced from +x, in which approaches are looked for.
pub const APPROACH_DIRECTIONS: usize = 8;

/// Distances (BL) of an approach's rungs from the goal, nearest first.
pub const APPROACH_DISTANCES: [f64; 3] = [2.0, 4.0, 6.0];

/// The clearance (BL) at which both agents are out of the pocket: the last rung has it, and a
/// goal that has it needs no approaches; room for the tree to arrive in a different shape.
pub const APPROACH_CLEARANCE: f64 = 1.5;

/// Goal connection settings and state.
#[derive(Debug, Clone)]
pub struct GoalConnect {
    /// Try straight into the goal from nodes within this distance of it (the goal's
    /// distance, BL); 0: never.
    pub radius: f64,
    /// Try by way of an approach from nodes within this distance of it (BL); 0: never.
    pub approach_radius: f64,
    /// The longest steered edge, in control periods.
    pub max_periods: u32,
    approaches: Vec<Approach>,
}

/// A rung: the goal's shape translated out of the goal, and how to steer from it into the
/// goal.
#[derive(Debug, Clone)]
struct Approach {
    state: [Vec2; 2],
    /// The approach it steers into, or the goal.
    next: Option<usize>,
    /// The closest distance of a node tried so far.
    closest: f64,
    /// The steer from `state` into the goal through the approaches it steers into: not yet
    /// solved, or solved (`None`: none valid).
    tail: Option<Option<Vec<SteerEdge>>>,
}

impl GoalConnect {
    /// Goal connection for `problem`, with the goal's approaches when it is a pair's.
    pub fn new(problem: &Problem, radius: f64, approach_radius: f64, max_periods: u32) -> Self {
        let approaches = if problem.agents() == 2 && approach_radius > 0.0 {
            approaches(problem)
        } else {
            Vec::new()
        };
        GoalConnect {
            radius,
            approach_radius,
            max_periods,
            approaches,
        }
    }

    /// The goal's approach states, nearest the goal first in each direction.
    pub fn approaches(&self) -> Vec<[Vec2; 2]> {
        self.approaches.iter().map(|a| a.state).collect()
    }

    /// Whether a node at `distance` from the goal is worth a direct try.
    pub fn near(&self, problem: &Problem, distance: f64) -> bool {
        problem.agents() == 2 && distance <= self.radius
    }

    /// Tries node `from`, at `distance` from the goal and `closer` to it than any node
    /// before: straight into the goal if near it, then by way of each approach it is near and
    /// closer to than any node before. On success the steer's nodes are in the tree (and
    /// `nn`, if given) with zero cost, and the last, which is in the goal region, is returned.
    pub fn attempt(
        &mut self,
        problem: &Problem,
        tree: &mut Tree,
        mut nn: Option<&mut NearestNeighbors>,
        from: u32,
        distance: f64,
        closer: bool,
    ) -> Option<u32> {
        if closer
            && self.near(problem, distance)
            && let Some(node) = self.run(problem, tree, nn.as_deref_mut(), from)
        {
            return Some(node);
        }
        for a in 0..self.approaches.len() {
            let d = max_agent_distance(tree.state(from), &self.approaches[a].state);
            if d > self.approach_radius || d >= self.approaches[a].closest {
                continue;
            }
            self.approaches[a].closest = d;
            if let Some(node) = self.via(problem, tree, nn.as_deref_mut(), from, a) {
                return Some(node);
            }
        }
        None
    }

    /// Steers from node `from` onto the goal centres. On success the steer's nodes are in the
    /// tree (and `nn`, if given) with zero cost, and the last, which is in the goal region, is
    /// returned.
    pub fn run(
        &self,
        problem: &Problem,
        tree: &mut Tree,
        nn: Option<&mut NearestNeighbors>,
        from: u32,
    ) -> Option<u32> {
        let start = pair(tree.state(from));
        let states = self.steer_into_goal(problem, &start, &problem.goal.agents, &[])?;
        Some(add(tree, nn, from, &states))
    }

    /// Steers from node `from` onto approach `a`, then along the approach's steer into the
    /// goal.
    fn via(
        &mut self,
        problem: &Problem,
        tree: &mut Tree,
        nn: Option<&mut NearestNeighbors>,
        from: u32,
        a: usize,
    ) -> Option<u32> {
        let tail = self.tail(problem, a)?;
        let start = pair(tree.state(from));
        let states = self.steer_into_goal(problem, &start, &self.approaches[a].state, &tail)?;
        Some(add(tree, nn, from, &states))
    }

    /// The steer from approach `a` into the goal, solved the first time it is asked for: a
    /// steer onto the approach it steers into followed by that one's, or straight into the
    /// goal.
    fn tail(&mut self, problem: &Problem, a: usize) -> Option<Vec<SteerEdge>> {
        if let Some(known) = &self.approaches[a].tail {
            return known.clone();
        }
        let (from, next) = (self.approaches[a].state, self.approaches[a].next);
        let tail = match next {
            Some(b) => self.tail(problem, b).and_then(|after| {
                self.steer_into_goal(problem, &from, &self.approaches[b].state, &after)
            }),
            None => self.steer_into_goal(problem, &from, &problem.goal.agents, &[]),
        }
        .map(|states| states.into_iter().map(|(e, _)| e).collect());
        self.approaches[a].tail = Some(tail.clone());
        tail
    }

    /// A steer from `from` onto `to` whose edges, followed by `after`, all pass the checked
    /// propagation and end in the goal region: every edge of both with its end.
    fn steer_into_goal(
        &self,
        problem: &Problem,
        from: &[Vec2; 2],
        to: &[Vec2],
        after: &[SteerEdge],
    ) -> Option<Vec<(SteerEdge, [Vec2; MAX_AGENTS])>> {
        let mut states = Vec::new();
        steer_pair(
            &problem.model,
            from,
            to,
            &problem.steer_limits(self.max_periods),
            |edges| {
                states.clear();
                replay(problem, from, edges, &mut states)
                    .and_then(|there| replay(problem, &there, after, &mut states))
                    .is_some_and(|end| problem.goal.contains(&end))
            },
        )?;
        Some(states)
    }
}

/// The first two agents of `s`.
fn pair(s: &[Vec2]) -> [Vec2; 2] {
    [s[0], s[1]]
}

/// Propagates `edges` from `start` with the checked propagation, pushing each edge's command,
/// periods and end onto `states`: the end, or `None` at the first invalid edge.
fn replay(
    problem: &Problem,
    start: &[Vec2],
    edges: &[SteerEdge],
    states: &mut Vec<(SteerEdge, [Vec2; MAX_AGENTS])>,
) -> Option<[Vec2; 2]> {
    let mut at = [start[0], start[1]];
    for e in edges {
        let mut out = [Vec2::zeros(); MAX_AGENTS];
        let d = problem.periods(e.periods);
        if !propagate_valid(problem, &at, &e.control, d, &mut out[..2]) {
            return None;
        }
        states.push((*e, out));
        at = [out[0], out[1]];
    }
    Some(at)
}

/// Adds the replayed edges `states` below node `from`: the last node.
fn add(
    tree: &mut Tree,
    mut nn: Option<&mut NearestNeighbors>,
    from: u32,
    states: &[(SteerEdge, [Vec2; MAX_AGENTS])],
) -> u32 {
    let mut node = from;
    for (e, s) in states {
        node = tree.add(node, &s[..2], e.control, e.periods, 0.0);
        if let Some(nn) = nn.as_deref_mut() {
            nn.add(&s[..2], node);
        }
    }
    node
}

/// The goal's approaches, none when both goal agents are [`APPROACH_CLEARANCE`] clear: in each
/// direction, the goal's shape translated by each of [`APPROACH_DISTANCES`] in turn while both
/// agents sweep clear from the goal, up to the first where both are [`APPROACH_CLEARANCE`]
/// clear. Each steers into the one before it (the first into the goal).
fn approaches(problem: &Problem) -> Vec<Approach> {
    let goal = &problem.goal.agents;
    let collision = &problem.checker.collision;
    let clear = |s: &[Vec2]| {
        s.iter()
            .all(|p| collision.clearance(*p) >= APPROACH_CLEARANCE)
    };
    if clear(goal) {
        return Vec::new();
    }
    let mut out: Vec<Approach> = Vec::new();
    for k in 0..APPROACH_DIRECTIONS {
        let angle = TAU * k as f64 / APPROACH_DIRECTIONS as f64;
        let dir = Vec2::new(angle.cos(), angle.sin());
        let mut next = None;
        for h in APPROACH_DISTANCES {
            let state = [goal[0] + dir * h, goal[1] + dir * h];
            if !state
                .iter()
                .zip(goal)
                .all(|(p, g)| collision.sweep_clear(*g, *p))
            {
                break;
            }
            out.push(Approach {
                state,
                next,
                closest: f64::INFINITY,
                tail: None,
            });
            next = Some(out.len() - 1);
            if clear(&state) {
                break;
            }
        }
    }
    out
}
