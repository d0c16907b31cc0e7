//! The free space of a map on a regular grid: each cell centre's distance to the nearest wall
//! or obstacle, shortest paths of a point kept a given clearance away from them, and the
//! widest path (the narrowest passage between two points).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::collision::CollisionWorld;
use crate::math::Vec2;
use crate::world::World;

/// The finest grid spacing (BL).
pub const FINEST: f64 = 0.1;

/// Most grid cells; larger worlds get a coarser grid.
pub const MAX_CELLS: usize = 250_000;

/// Passes of the corner refinement of [`FreeGrid::shortest_path`].
const REFINE_PASSES: usize = 3;

/// A world's free space sampled at the centres of square cells.
pub struct FreeGrid {
    /// Cell side (BL).
    pub spacing: f64,
    columns: usize,
    rows: usize,
    /// Distance of each cell centre to the nearest wall or obstacle (0 inside one), row-major.
    distance: Vec<f64>,
    world: World,
}

/// The 8 neighbours of a cell and the length of each step, in cells.
const STEPS: [(isize, isize, f64); 8] = [
    (1, 0, 1.0),
    (-1, 0, 1.0),
    (0, 1, 1.0),
    (0, -1, 1.0),
    (1, 1, std::f64::consts::SQRT_2),
    (1, -1, std::f64::consts::SQRT_2),
    (-1, 1, std::f64::consts::SQRT_2),
    (-1, -1, std::f64::consts::SQRT_2),
];

/// A non-negative f64 as a key that orders like the number.
fn key(x: f64) -> u64 {
    x.max(0.0).to_bits()
}

impl FreeGrid {
    /// The grid of `world`: cells of [`FINEST`] BL, or coarser so that there are at most
    /// [`MAX_CELLS`].
    pub fn new(world: &World) -> FreeGrid {
        let area = world.width * world.height;
        let spacing = FINEST.max((area / MAX_CELLS as f64).sqrt() * 1.001);
        let columns = ((world.width / spacing).ceil() as usize).max(1);
        let rows = ((world.height / spacing).ceil() as usize).max(1);
        let cw = CollisionWorld::new(world, 0.0);
        let mut distance = Vec::with_capacity(columns * rows);
        for j in 0..rows {
            for i in 0..columns {
                distance.push(cw.clearance(Self::centre_of(spacing, world, i, j)).max(0.0));
            }
        }
        FreeGrid {
            spacing,
            columns,
            rows,
            distance,
            world: world.clone(),
        }
    }

    /// The centre of cell (i, j), kept inside the world (the last cells may be cut by it).
    fn centre_of(spacing: f64, world: &World, i: usize, j: usize) -> Vec2 {
        Vec2::new(
            ((i as f64 + 0.5) * spacing).min(world.width),
            ((j as f64 + 0.5) * spacing).min(world.height),
        )
    }

    fn centre(&self, c: usize) -> Vec2 {
        Self::centre_of(
            self.spacing,
            &self.world,
            c % self.columns,
            c / self.columns,
        )
    }

    /// The cell that holds `p` (clamped to the grid).
    fn cell(&self, p: Vec2) -> usize {
        let i = ((p.x / self.spacing).floor().max(0.0) as usize).min(self.columns - 1);
        let j = ((p.y / self.spacing).floor().max(0.0) as usize).min(self.rows - 1);
        j * self.columns + i
    }

    fn neighbours(&self, c: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let (i, j) = ((c % self.columns) as isize, (c / self.columns) as isize);
        STEPS.iter().filter_map(move |&(di, dj, len)| {
            let (a, b) = (i + di, j + dj);
            (a >= 0 && b >= 0 && (a as usize) < self.columns && (b as usize) < self.rows)
                .then(|| (b as usize * self.columns + a as usize, len * self.spacing))
        })
    }

    /// Fraction of the cell centres outside every obstacle.
    pub fn free_fraction(&self) -> f64 {
        let free = self.distance.iter().filter(|d| **d > 0.0).count();
        free as f64 / self.distance.len() as f64
    }

    /// The free cell (distance ≥ `clearance`) nearest `p`, within `reach` BL; `None` if there
    /// is none.
    fn free_cell_near(&self, p: Vec2, clearance: f64, reach: f64) -> Option<usize> {
        let c = self.cell(p);
        if self.distance[c] >= clearance {
            return Some(c);
        }
        let r = (reach / self.spacing).ceil() as isize + 1;
        let (ci, cj) = ((c % self.columns) as isize, (c / self.columns) as isize);
        let mut best: Option<(f64, usize)> = None;
        for dj in -r..=r {
            for di in -r..=r {
                let (a, b) = (ci + di, cj + dj);
                if a < 0 || b < 0 || a as usize >= self.columns || b as usize >= self.rows {
                    continue;
                }
                let k = b as usize * self.columns + a as usize;
                let d = (self.centre(k) - p).norm();
                if self.distance[k] >= clearance
                    && d <= reach
                    && best.is_none_or(|(bd, bk)| (d, k) < (bd, bk))
                {
                    best = Some((d, k));
                }
            }
        }
        best.map(|(_, k)| k)
    }

    /// A shortest 8-connected path of grid cells from `from` to `to` whose every cell centre
    /// is at least `clearance` from walls and obstacles (A*), as points: `from`, the cell
    /// centres, `to`. An end whose own cell is too close starts from the nearest cell that is
    /// not, within `clearance` + 2 cells. `None` when no such path exists.
    pub fn grid_path(&self, from: Vec2, to: Vec2, clearance: f64) -> Option<Vec<Vec2>> {
        let reach = clearance + 2.0 * self.spacing;
        let s = self.free_cell_near(from, clearance, reach)?;
        let g = self.free_cell_near(to, clearance, reach)?;
        let goal = self.centre(g);
        let n = self.distance.len();
        let mut cost = vec![f64::INFINITY; n];
        let mut parent = vec![usize::MAX; n];
        let mut heap = BinaryHeap::new();
        cost[s] = 0.0;
        heap.push(Reverse((key((self.centre(s) - goal).norm()), s)));
        while let Some(Reverse((_, c))) = heap.pop() {
            if c == g {
                break;
            }
            for (k, len) in self.neighbours(c) {
                if self.distance[k] < clearance {
                    continue;
                }
                let nc = cost[c] + len;
                if nc < cost[k] {
                    cost[k] = nc;
                    parent[k] = c;
                    heap.push(Reverse((key(nc + (self.centre(k) - goal).norm()), k)));
                }
            }
        }
        if !cost[g].is_finite() {
            return None;
        }
        let mut cells = vec![g];
        while *cells.last().expect("non-empty") != s {
            cells.push(parent[*cells.last().expect("non-empty")]);
        }
        let mut path = vec![from];
        path.extend(cells.iter().rev().map(|c| self.centre(*c)));
        path.push(to);
        Some(path)
    }

    /// The grid path shortened by line of sight: from each kept point, the farthest later
    /// point reachable in a straight line by a disk of radius `clearance` less one cell (so
    /// that neighbouring cells always see each other), then each corner moved to the grid
    /// point between its neighbours that shortens the path most. Close to the shortest path
    /// in the plane at that clearance.
    pub fn shortest_path(&self, from: Vec2, to: Vec2, clearance: f64) -> Option<Vec<Vec2>> {
        let grid = self.grid_path(from, to, clearance)?;
        let cw = CollisionWorld::new(&self.world, (clearance - self.spacing).max(0.0));
        let mut kept = vec![0];
        let mut i = 0;
        while i + 1 < grid.len() {
            let mut j = i + 1;
            while j + 1 < grid.len() && cw.sweep_clear(grid[i], grid[j + 1]) {
                j += 1;
            }
            kept.push(j);
            i = j;
        }
        // move each kept corner to the grid point between its neighbours that shortens the
        // path most while both neighbours still see it
        for _ in 0..REFINE_PASSES {
            for k in 1..kept.len().saturating_sub(1) {
                let (a, b) = (grid[kept[k - 1]], grid[kept[k + 1]]);
                let len = |p: Vec2| (p - a).norm() + (p - b).norm();
                let mut best = kept[k];
                for (m, &p) in grid
                    .iter()
                    .enumerate()
                    .take(kept[k + 1])
                    .skip(kept[k - 1] + 1)
                {
                    if len(p) < len(grid[best]) - 1e-12
                        && cw.sweep_clear(a, p)
                        && cw.sweep_clear(p, b)
                    {
                        best = m;
                    }
                }
                kept[k] = best;
            }
        }
        Some(kept.iter().map(|&k| grid[k]).collect())
    }

    /// The clearance of the widest path from `from` to `to`: the largest d such that some
    /// 8-connected path of cells keeps every cell centre at least d from walls and obstacles
    /// (the cells of `from` and `to` included). Twice it is the narrowest passage the path
    /// must go through.
    pub fn widest_clearance(&self, from: Vec2, to: Vec2) -> f64 {
        let (s, g) = (self.cell(from), self.cell(to));
        let mut best = vec![-1.0f64; self.distance.len()];
        let mut heap = BinaryHeap::new();
        best[s] = self.distance[s];
        heap.push((key(best[s]), s));
        while let Some((b, c)) = heap.pop() {
            let b = f64::from_bits(b);
            if c == g {
                return b;
            }
            if b < best[c] {
                continue;
            }
            for (k, _) in self.neighbours(c) {
                let nb = b.min(self.distance[k]);
                if nb > best[k] {
                    best[k] = nb;
                    heap.push((key(nb), k));
                }
            }
        }
        best[g].max(0.0)
    }
}
