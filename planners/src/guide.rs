//! A guide path for the sampler: a geometric shortest path of the team's centroid from start
//! to goal, and how far along it the tree has come.
//!
//! Before the search, A* on a grid of [`SPACING`] BL over the map finds a shortest 8-connected
//! path between the start and goal centroids through grid nodes where an agent keeps at least
//! a margin of clearance (the largest of [`MARGINS`] that leaves a path). During the search
//! every new node that comes near the path a little ahead of the tree's progress advances it;
//! a guided sample puts the centroid in a disk about a path point just ahead of the progress.
//! The guide only chooses samples: every edge still comes from EXTEND and its checks.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use magbench_env::Vec2;
use magbench_env::math::centroid;
use rand::RngExt;

use crate::sampler::in_disk;
use crate::{Problem, Rng};

/// Grid spacing of the guide's search (BL).
pub const SPACING: f64 = 0.5;

/// Clearances (BL) an agent at a path node keeps, tried largest first.
pub const MARGINS: [f64; 3] = [1.0, 0.5, 0.0];

/// Largest number of grid nodes the guide searches; a larger map gets no guide.
pub const MAX_NODES: usize = 1 << 20;

/// How far ahead of the progress a guided sample's centroid is centred (path nodes).
pub const AHEAD: usize = 14;

/// Radius of the disk about the guide point a guided centroid is drawn in (BL).
pub const SPREAD: f64 = 2.0;

/// How far beyond the progress a new node may advance it (path nodes).
pub const WINDOW: usize = 12;

/// Distance within which a node's centroid counts as on the path (BL).
pub const NEAR: f64 = 1.5;

/// A centroid path from start to goal and the tree's progress along it.
#[derive(Debug, Clone)]
pub struct Guide {
    points: Vec<Vec2>,
    reach: usize,
}

impl Guide {
    /// The guide of `problem`: a shortest grid path of the centroid from start to goal, or
    /// `None` when no margin leaves one (or the map is too large for the grid).
    pub fn new(problem: &Problem) -> Option<Guide> {
        let grid = Grid::new(problem.world.width, problem.world.height)?;
        let start = centroid(&problem.start);
        let goal = centroid(&problem.goal.agents);
        // The goal centroid may lie in an obstacle (agents in chambers on either side of a
        // wall): the search ends at the first node within the goal agents' spread of it.
        let spread = problem
            .goal
            .agents
            .iter()
            .map(|g| (g - goal).norm())
            .fold(0.0, f64::max);
        let collision = &problem.checker.collision;
        let mut clearance = vec![f64::NAN; grid.len()];
        for margin in MARGINS {
            let free = |id: usize| {
                if clearance[id].is_nan() {
                    clearance[id] = collision.clearance_bound(grid.point(id));
                }
                clearance[id] >= margin
            };
            if let Some(mut points) = grid.search(start, goal, spread, free) {
                points[0] = start;
                points.push(goal);
                return Some(Guide { points, reach: 0 });
            }
        }
        None
    }

    /// The path points (BL), start centroid first, goal centroid last.
    pub fn points(&self) -> &[Vec2] {
        &self.points
    }

    /// The index of the farthest path point the tree has come near.
    pub fn reach(&self) -> usize {
        self.reach
    }

    /// Advances the progress to the path point nearest to `state`'s centroid when that point
    /// lies at most [`WINDOW`] points beyond the progress and within [`NEAR`] BL.
    pub fn observe(&mut self, state: &[Vec2]) {
        let c = centroid(state);
        let end = (self.reach + WINDOW).min(self.points.len() - 1);
        let mut best = (self.reach, f64::INFINITY);
        for (i, p) in self.points[self.reach..=end].iter().enumerate() {
            let d = (p - c).norm_squared();
            if d < best.1 {
                best = (self.reach + i, d);
            }
        }
        if best.1 <= NEAR * NEAR {
            self.reach = best.0;
        }
    }

    /// A centroid in the disk of radius [`SPREAD`] about a path point up to [`AHEAD`] points
    /// beyond the progress.
    pub fn centroid(&self, rng: &mut Rng) -> Vec2 {
        let last = self.points.len() - 1;
        let i = (self.reach + rng.random_range(1..=AHEAD)).min(last);
        in_disk(rng, self.points[i], SPREAD)
    }
}

/// The guide's grid of nodes `SPACING` apart over the world's rectangle.
struct Grid {
    columns: usize,
    rows: usize,
}

impl Grid {
    fn new(width: f64, height: f64) -> Option<Grid> {
        let count = |l: f64| (l.max(0.0) / SPACING).floor() as usize + 1;
        let (columns, rows) = (count(width), count(height));
        (columns.checked_mul(rows)? <= MAX_NODES).then_some(Grid { columns, rows })
    }

    fn len(&self) -> usize {
        self.columns * self.rows
    }

    fn point(&self, id: usize) -> Vec2 {
        Vec2::new(
            (id % self.columns) as f64 * SPACING,
            (id / self.columns) as f64 * SPACING,
        )
    }

    fn nearest(&self, p: Vec2) -> usize {
        let i = ((p.x / SPACING).round().max(0.0) as usize).min(self.columns - 1);
        let j = ((p.y / SPACING).round().max(0.0) as usize).min(self.rows - 1);
        j * self.columns + i
    }

    /// A* from the node nearest `from` (always accepted) to the first node within `radius` of
    /// `to` through nodes `free` accepts; the path's node positions.
    fn search(
        &self,
        from: Vec2,
        to: Vec2,
        radius: f64,
        mut free: impl FnMut(usize) -> bool,
    ) -> Option<Vec<Vec2>> {
        let s = self.nearest(from);
        let h = |id: usize| ((self.point(id) - to).norm() - radius).max(0.0);
        let mut cost = vec![f64::INFINITY; self.len()];
        let mut parent = vec![usize::MAX; self.len()];
        let mut open = BinaryHeap::new();
        cost[s] = 0.0;
        open.push((Reverse(Key(h(s))), s));
        while let Some((Reverse(Key(f)), id)) = open.pop() {
            if h(id) == 0.0 {
                let mut path = vec![self.point(id)];
                let mut at = id;
                while at != s {
                    at = parent[at];
                    path.push(self.point(at));
                }
                path.reverse();
                return Some(path);
            }
            if f > cost[id] + h(id) + 1e-9 {
                continue;
            }
            let (i, j) = ((id % self.columns) as isize, (id / self.columns) as isize);
            for (di, dj) in NEIGHBOURS {
                let (ni, nj) = (i + di, j + dj);
                if ni < 0 || nj < 0 || ni as usize >= self.columns || nj as usize >= self.rows {
                    continue;
                }
                let n = nj as usize * self.columns + ni as usize;
                let step = SPACING * if di != 0 && dj != 0 { 2f64.sqrt() } else { 1.0 };
                let c = cost[id] + step;
                if c < cost[n] && free(n) {
                    cost[n] = c;
                    parent[n] = id;
                    open.push((Reverse(Key(c + h(n))), n));
                }
            }
        }
        None
    }
}

/// The 8-connected neighbour offsets.
const NEIGHBOURS: [(isize, isize); 8] = [
    (1, 0),
    (-1, 0),
    (0, 1),
    (0, -1),
    (1, 1),
    (1, -1),
    (-1, 1),
    (-1, -1),
];

/// A finite f64 ordered for the open list.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Key(f64);

impl Eq for Key {}

impl PartialOrd for Key {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Key {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}
