//! `formation-rrt`: a planner for teams that plans the shape and the centroid apart.
//!
//! Every agent feels the same pull, so a team's shape (its positions about the centroid) moves
//! under the field's angle θ and elevation α alone, and its centroid moves at a velocity affine
//! in the gradient commands (crate::motion::centroid_map). The search therefore samples shapes
//! only, in 2N − 2 dimensions instead of 2N, and every edge's gradients carry the centroid
//! along the straight line from the start's centroid to the goal's at one speed the coil can
//! hold under any field the search draws ([`crate::motion::aimed`]); the centroid arrives on
//! its own schedule and waits there. Once a node's shape fits the goal, HOLD keeps it: one
//! control period at a time, the field among a fixed set that keeps the shape closest to the
//! goal's, until the centroid has arrived.
//!
//! ```text
//! FORMATION-RRT(q_start, q_goal)
//!   T ⇐ q_start
//!   while i ≤ k:
//!     s_sample ← goal shape ⊕ zoom noise (bias), else a random shape within the proximity range
//!     q_near   ← nearest(T, s_sample)                   shape distance
//!     (u, δt)  ← argmin over k tries (θ, α, δt) of ‖shape(f(q_near, u_aimed, δt)) − s_sample‖
//!                                                       tries propagated in parallel (rayon)
//!     if collisionFree(q_near, u, δt): add q_new
//!     if shape(q_new) fits the goal: τ ← HOLD(q_new); if τ ends in the goal: break
//!   return computePlan(T) ⊕ τ
//!
//! HOLD(q)
//!   until the centroid is at the goal's (or after `hold` seconds, or the search's time):
//!     u ← argmin over the hold set (θ, α) of ‖shape(f(q, u_aimed, one period)) − s_goal‖
//!     q ← f(q, u_aimed, one period)                     checked like any edge
//! ```
//!
//! The hold set draws on the time average that cancels every pair's force: at the elevation
//! α_h with cos²α_h = 2/3 (35.26°), a field turned through three in-plane angles 120° apart
//! cancels the radial and the transverse force of every pair, whatever its heading
//! (Σₖ cos²(ψₖ) = 3/2 and Σₖ sin 2ψₖ = 0 for ψₖ 120° apart); HOLD picks among those angles, and
//! among the plane's and a steeper elevation, whichever leaves the shape closest.
//!
//! Teams of three or more need the elevation (a medium that carries the out-of-plane force);
//! in the plane, or for a pair, the planner searches the same way with α = 0. The centroid's
//! straight line is checked like every edge, so a wall across it leaves the problem unsolved.

use std::f64::consts::{PI, TAU};

use magbench_env::math::{centroid, shape_distance};
use magbench_env::params::Reals;
use magbench_env::physics::sweep_cancelling_elevation;
use magbench_env::{Control, MAX_AGENTS, Vec2, declare_params};
use rand::{RngExt, SeedableRng};
use rayon::prelude::*;

use crate::distance::Distance;
use crate::extend::Extend;
use crate::motion::{aimed, centroid_map, propagate, propagate_valid};
use crate::nn::NearestNeighbors;
use crate::objective::plan_cost;
use crate::progress::Progress;
use crate::result::{Best, finish};
use crate::search_settings::SearchSettings;
use crate::tree::Tree;
use crate::{Plan, Planner, PlannerResult, Problem, Rng};

declare_params! {
    /// Formation RRT: shapes sampled, the centroid carried along a line, HOLD at the goal shape.
    #[derive(Debug, Clone)]
    pub struct FormationRrt {
        /// EXTEND's tries and durations, the goal-zoom sampler (its zoom radius is about each
        /// agent's goal position in the shape). Edges last one to four frames at 60 fps: at a
        /// team's spacings (under 2 BL) a pair's separation changes by several BL/s, so a longer
        /// edge mostly ends invalid. On rings of five to eight agents, longest edges of 2, 4 and
        /// 6 frames find first plans in about the same time, and faster than a quarter second
        /// (`experiments/team-edge.toml`, docs/planners.md). Half the samples are the goal's
        /// shape (each then CONNECTs).
        #[params]
        pub search: SearchSettings = SearchSettings {
            min_duration: 1.0 / 60.0,
            max_duration: 4.0 / 60.0,
            goal_bias: 0.5,
            ..SearchSettings::default()
        },
        /// Fraction of the speed along the line that the coil gives the centroid under each
        /// edge's field at which the centroid is carried to the goal.
        #[param("speed", Reals::closed(0.01, 1.0))]
        pub speed: f64 = 0.8,
        /// Fraction of the goal tolerance a shape must fit within before HOLD starts.
        #[param("fit", Reals::closed(0.05, 1.0))]
        pub fit: f64 = 0.9,
        /// Weight of the shape's own change in HOLD's choice (0: the field that ends closest to
        /// the goal's shape; larger: fields that move the agents less).
        #[param("stay", Reals::closed(0.0, 1.0e6))]
        pub stay: f64 = 1.0,
        /// Longest HOLD (s).
        #[param("hold", Reals::closed(0.0, 3600.0))]
        pub hold: f64 = 120.0,
        /// Tries from which EXTEND's are propagated in parallel (on rayon's threads).
        #[param("parallel_from", 1..=100_000)]
        pub parallel_from: usize = 48,
        /// The tree of the last solve.
        pub last_tree: Option<Tree> = None,
    }
}

/// In-plane angles of the hold set.
const HOLD_ANGLES: usize = 12;

/// HOLD's best-ranked fields checked each period before it gives up.
const HOLD_CHECKS: usize = 4;

/// EXTEND's best-ranked tries checked before the extension is given up.
const EXTEND_CHECKS: usize = 4;

/// Most extensions of one CONNECT toward the goal's shape.
const CONNECT_STEPS: usize = 50;

/// One edge of HOLD: its control, duration in periods and end.
type HoldEdge = (Control, u32, Vec<Vec2>);

/// One try of EXTEND or HOLD: its control, duration in periods and its end's shape distance
/// to the target.
#[derive(Clone, Copy)]
struct Try {
    control: Control,
    periods: u32,
    distance: f64,
}

/// Where the centroid is carried: toward the goal's centroid along the straight line, each edge
/// at `fraction` of the speed along the line that the coil reaches under the edge's field (the
/// tri-axial coil pulls along x in proportion to the field's x component, and so along y).
#[derive(Clone, Copy)]
struct Carry {
    goal: Vec2,
    fraction: f64,
}

impl Carry {
    /// `u` with the gradients that move the centroid of a team of `n` from `from` toward the
    /// goal's for `duration` seconds.
    fn aim(&self, problem: &Problem, u: Control, n: usize, from: Vec2, duration: f64) -> Control {
        let left = self.goal - from;
        let dist = left.norm();
        let Some((_, ax, ay)) = centroid_map(problem, &u, n) else {
            return u;
        };
        let to = if dist <= 1e-12 {
            self.goal
        } else {
            let d = left / dist;
            let along = |reach: f64, part: f64| {
                if part.abs() < 1e-12 {
                    f64::INFINITY
                } else {
                    reach.abs() / part.abs()
                }
            };
            let speed = along(ax.x, d.x).min(along(ay.y, d.y)) * self.fraction;
            from + d * (speed * duration).min(dist)
        };
        aimed(problem, u, n, from, to, duration)
    }
}

/// Nearest neighbours by the shape alone: each node's positions about its centroid, under the
/// positions metric. Two such shapes are as far apart as their shape distance, and a query
/// about another centroid shifts every squared distance by the same amount. Indexing the
/// centroid itself, even with a small weight, gives the k-d tree a coordinate that is constant,
/// or nearly so, whenever the centroid's line runs along an axis, and kiddo's rebuild of such a
/// tree grew its stems without bound (33 GB asked for while planning a ring of nine for 60 s).
struct ShapeIndex {
    nn: NearestNeighbors,
    about: Vec<Vec2>,
}

impl ShapeIndex {
    /// An empty index for teams of `n`.
    fn new(n: usize) -> Self {
        ShapeIndex {
            nn: NearestNeighbors::new(Distance::Positions, n),
            about: vec![Vec2::zeros(); n],
        }
    }

    /// Indexes the shape of state `s` of node `id`.
    fn add(&mut self, s: &[Vec2], id: u32) {
        let c = centroid(s);
        for (a, p) in self.about.iter_mut().zip(s) {
            *a = p - c;
        }
        self.nn.add(&self.about, id);
    }

    /// The node whose shape is nearest to `shape` (positions about the origin).
    fn nearest(&self, shape: &[Vec2]) -> Option<u32> {
        self.nn.nearest(shape).map(|(id, _)| id)
    }
}

/// The largest agent distance between the shapes of `a` and `b`.
fn shape_max_distance(a: &[Vec2], b: &[Vec2]) -> f64 {
    let (ca, cb) = (centroid(a), centroid(b));
    a.iter()
        .zip(b)
        .map(|(p, q)| ((p - ca) - (q - cb)).norm())
        .fold(0.0, f64::max)
}

impl FormationRrt {
    /// Propagates `tries` from `from` (the centroid carried) and returns them with their
    /// scores, best first: the squared shape distance of each end to `target`'s plus `stay`
    /// times its squared shape distance to `from`'s; in parallel when there are at least
    /// `parallel_from`.
    fn ranked_tries(
        &self,
        problem: &Problem,
        from: &[Vec2],
        carry: Carry,
        target: &[Vec2],
        stay: f64,
        tries: &[(Control, u32)],
    ) -> Vec<Try> {
        let n = from.len();
        let c = centroid(from);
        let one = |&(u, periods): &(Control, u32)| {
            let d = problem.periods(periods);
            let u = carry.aim(problem, u, n, c, d);
            let mut end = [Vec2::zeros(); MAX_AGENTS];
            propagate(problem, from, &u, d, &mut end[..n]);
            let distance =
                shape_distance(&end[..n], target) + stay * shape_distance(&end[..n], from);
            Try {
                control: u,
                periods,
                distance: if distance.is_finite() {
                    distance
                } else {
                    f64::INFINITY
                },
            }
        };
        let mut all: Vec<Try> = if tries.len() >= self.parallel_from {
            tries.par_iter().map(one).collect()
        } else {
            tries.iter().map(one).collect()
        };
        // stable: ties keep the order of the draws
        all.sort_by(|a, b| a.distance.total_cmp(&b.distance));
        all
    }

    /// EXTEND: `extend.tries` random fields and durations from `from` (the centroid carried
    /// along the line), ranked by how close each ends to `target`'s shape; the best of the first
    /// [`EXTEND_CHECKS`] whose motion is valid, its end in `out`.
    #[allow(clippy::too_many_arguments)]
    fn extend(
        &self,
        problem: &Problem,
        rng: &mut Rng,
        extend: &Extend,
        from: &[Vec2],
        carry: Carry,
        target: &[Vec2],
        out: &mut [Vec2],
    ) -> Option<Try> {
        let alpha_max = extend.alpha_max.unwrap_or(0.0);
        let tries: Vec<(Control, u32)> = (0..extend.tries)
            .map(|_| {
                let theta = rng.random_range(-PI..PI);
                let alpha = if alpha_max > 0.0 {
                    rng.random_range(0.0..=alpha_max)
                } else {
                    0.0
                };
                let periods = rng.random_range(extend.min_periods..=extend.max_periods);
                let u = Control {
                    theta,
                    alpha,
                    grad: [0.0, 0.0],
                };
                (u, periods)
            })
            .collect();
        self.ranked_tries(problem, from, carry, target, 0.0, &tries)
            .into_iter()
            .take(EXTEND_CHECKS)
            .find(|t| propagate_valid(problem, from, &t.control, problem.periods(t.periods), out))
    }

    /// HOLD from `q`: one period at a time, the hold-set field that keeps the shape closest to
    /// `goal`'s, until the centroid is at the goal's; the edges, or `None` if an edge is
    /// invalid, the shape strays beyond `tolerance` of the goal's, the hold runs out of time
    /// (`hold` seconds of motion) or the search does (`stopped`, asked every period).
    #[allow(clippy::too_many_arguments)]
    fn hold_from(
        &self,
        problem: &Problem,
        q: &[Vec2],
        carry: Carry,
        goal: &[Vec2],
        tolerance: f64,
        alpha_max: f64,
        stopped: impl Fn() -> bool,
    ) -> Option<Vec<HoldEdge>> {
        let n = q.len();
        let set = hold_set(alpha_max, carry.goal - centroid(q));
        let max_steps = (self.hold / problem.control_period).ceil() as usize;
        let mut at = q.to_vec();
        let mut edges = Vec::new();
        let mut next = vec![Vec2::zeros(); n];
        for _ in 0..max_steps {
            if (centroid(&at) - carry.goal).norm() <= 1e-9 {
                return Some(edges);
            }
            if stopped() {
                return None;
            }
            let ranked = self.ranked_tries(problem, &at, carry, goal, self.stay, &set);
            let best = ranked.into_iter().take(HOLD_CHECKS).find(|t| {
                propagate_valid(problem, &at, &t.control, problem.periods(1), &mut next)
            })?;
            at.copy_from_slice(&next);
            if shape_max_distance(&at, goal) > tolerance {
                return None;
            }
            edges.push((best.control, 1, at.clone()));
        }
        None
    }
}

/// The hold set for a centroid still `left` from the goal's: twelve in-plane angles at the
/// plane, at α_h and, where allowed, at twice α_h's tilt toward the vertical (each for one
/// period), less the fields under which the coil pulls the centroid along `left` at under half
/// the speed of the best (the tri-axial coil pulls along an axis in proportion to the field's
/// component on it).
fn hold_set(alpha_max: f64, left: Vec2) -> Vec<(Control, u32)> {
    let mut alphas = vec![0.0];
    let h = sweep_cancelling_elevation();
    if alpha_max >= h {
        alphas.push(h);
    }
    let steep = (2.0 * h).min(alpha_max);
    if steep > 0.0 && !alphas.contains(&steep) {
        alphas.push(steep);
    }
    let d = left.try_normalize(1e-12).unwrap_or_else(Vec2::zeros);
    // the speed along d, in units of the full gradient's, under an in-plane field b
    let along = |b: Vec2| {
        let axis = |b: f64, d: f64| {
            if d.abs() < 1e-12 {
                f64::INFINITY
            } else {
                b.abs() / d.abs()
            }
        };
        axis(b.x, d.x).min(axis(b.y, d.y))
    };
    let mut set = Vec::new();
    for &alpha in &alphas {
        for i in 0..HOLD_ANGLES {
            let theta = -PI + TAU * i as f64 / HOLD_ANGLES as f64;
            let b = Vec2::new(theta.cos(), theta.sin()) * alpha.cos();
            let u = Control {
                theta,
                alpha,
                grad: [0.0, 0.0],
            };
            set.push((along(b), u));
        }
    }
    let best = set.iter().map(|s| s.0).fold(0.0, f64::max);
    set.into_iter()
        .filter(|(speed, _)| *speed >= 0.5 * best)
        .map(|(_, u)| (u, 1))
        .collect()
}

impl Planner for FormationRrt {
    fn name(&self) -> &str {
        "formation-rrt"
    }

    fn solve(&mut self, problem: &Problem) -> PlannerResult {
        let n = problem.agents();
        let mut rng = Rng::seed_from_u64(problem.seed);
        let extend = self.search.extend(problem);
        let alpha_max = extend.alpha_max.unwrap_or(0.0);
        let mut progress = Progress::start(problem);
        let goal = &problem.goal;
        let goal_c = centroid(&goal.agents);
        let carry = Carry {
            goal: goal_c,
            fraction: self.speed,
        };
        let fit = self.fit * goal.tolerance;
        // the radius within which a random shape's agents lie about its centroid
        let spread = 0.5 * problem.checker.r_max;

        let mut tree = Tree::new(&problem.start);
        let mut nn = ShapeIndex::new(n);
        nn.add(&problem.start, 0);
        let mut closest = (0u32, shape_max_distance(&problem.start, &goal.agents));
        let mut found: Option<(u32, Vec<HoldEdge>)> = None;
        // HOLD from a node whose shape fits, while the search's time allows (a HOLD is part of
        // the iteration that added the node, so the iteration limit does not cut it)
        let time_limit = problem.limits.time_limit.map(|t| t.as_secs_f64());
        let tried_hold = |node: u32, state: &[Vec2], found: &mut Option<_>, progress: &Progress| {
            if shape_max_distance(state, &goal.agents) <= fit
                && let Some(edges) = self.hold_from(
                    problem,
                    state,
                    carry,
                    &goal.agents,
                    goal.tolerance,
                    alpha_max,
                    || time_limit.is_some_and(|t| progress.elapsed() >= t),
                )
                && goal.contains(edges.last().map_or(state, |e| &e.2))
            {
                *found = Some((node, edges));
            }
        };
        tried_hold(0, &problem.start, &mut found, &progress);

        let mut sample = vec![Vec2::zeros(); n];
        let mut q_new = vec![Vec2::zeros(); n];
        let mut i = 0u64;
        while found.is_none() && !progress.done(i) {
            i += 1;
            // a shape: the goal's with zoom noise, or a random one within the proximity range
            let toward_goal = rng.random_bool(self.search.goal_bias);
            if toward_goal {
                for (s, g) in sample.iter_mut().zip(&goal.agents) {
                    let r = self.search.zoom_radius * rng.random_range(0.0f64..1.0).sqrt();
                    let a = rng.random_range(-PI..PI);
                    *s = g - goal_c + Vec2::new(a.cos(), a.sin()) * r;
                }
            } else {
                for s in sample.iter_mut() {
                    let r = spread * rng.random_range(0.0f64..1.0).sqrt();
                    let a = rng.random_range(-PI..PI);
                    *s = Vec2::new(a.cos(), a.sin()) * r;
                }
            }
            let mut near = nn.nearest(&sample).expect("the tree has its root");
            // EXTEND toward the sample; toward the goal's shape, CONNECT: again from each new
            // node while the shape comes closer, each extension an iteration (a tree gains at
            // most one node per iteration)
            let mut last = f64::INFINITY;
            for step in 0..if toward_goal { CONNECT_STEPS } else { 1 } {
                if step > 0 {
                    i += 1;
                    if progress.done(i) {
                        break;
                    }
                }
                let from = tree.state(near).to_vec();
                let Some(best) = self.extend(
                    problem, &mut rng, &extend, &from, carry, &sample, &mut q_new,
                ) else {
                    break;
                };
                let id = tree.add(near, &q_new, best.control, best.periods, 0.0);
                nn.add(&q_new, id);
                let dist = shape_max_distance(&q_new, &goal.agents);
                if dist < closest.1 {
                    closest = (id, dist);
                }
                tried_hold(id, &q_new, &mut found, &progress);
                if found.is_some() || dist >= last {
                    break;
                }
                (near, last) = (id, dist);
            }
            if found.is_none() {
                progress.record(i, None);
            }
        }

        let first = found.as_ref().map(|_| (i, progress.elapsed()));
        let (node, hold) = found.unwrap_or((closest.0, Vec::new()));
        let mut plan: Plan = tree.plan_to(node, problem);
        for (u, periods, state) in hold {
            plan.push(u, problem.periods(periods), state);
        }
        let solved = goal.contains(plan.end());
        let cost = plan_cost(problem, &plan);
        if solved {
            progress.record(i, Some(cost));
        }
        let best = Best { plan, solved, cost };
        let nodes = tree.len();
        self.last_tree = Some(tree);
        finish(problem, best, i, nodes, progress, first, extend.alpha_max)
    }

    fn tree(&self) -> Option<&Tree> {
        self.last_tree.as_ref()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shape_index_keys_a_state_by_its_shape_whatever_its_centroid() {
        // a ring of nine carried along x, its shape jittered
        let n = 9;
        let mut rng = Rng::seed_from_u64(3);
        let mut index = ShapeIndex::new(n);
        let mut states = vec![];
        let mut keys = vec![];
        for k in 0..200u32 {
            let s: Vec<Vec2> = (0..n)
                .map(|i| {
                    let a = TAU * i as f64 / n as f64;
                    let jitter =
                        Vec2::new(rng.random_range(-0.2..0.2), rng.random_range(-0.2..0.2));
                    Vec2::new(10.0 + 0.05 * k as f64, 6.0)
                        + Vec2::new(a.cos(), a.sin()) * 2.9
                        + jitter
                })
                .collect();
            index.add(&s, k);
            keys.push(index.about.clone());
            states.push(s);
        }
        // a key does not move with the centroid: translated, a state gives the same key
        let mut other = ShapeIndex::new(n);
        for (s, key) in states.iter().zip(&keys) {
            let moved: Vec<Vec2> = s.iter().map(|p| p + Vec2::new(13.0, -7.0)).collect();
            other.add(&moved, 0);
            for (a, b) in other.about.iter().zip(key) {
                assert!((a - b).norm() < 1e-12, "{a} vs {b}");
            }
        }
        // a node is found by its shape, wherever the query's centroid lies
        for k in [0usize, 57, 199] {
            let far: Vec<Vec2> = states[k]
                .iter()
                .map(|p| p + Vec2::new(-40.0, 25.0))
                .collect();
            assert_eq!(index.nearest(&far), Some(k as u32));
        }
    }
}
