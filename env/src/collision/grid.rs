//! A lazily filled grid of clearances: cheap lower bounds on an agent's clearance.
//!
//! Clearance is 1-Lipschitz in the agent's position, so the clearance at a grid node less the
//! distance to it bounds the clearance at any point from below. Nodes are computed (by the
//! exact query) the first time a point near them is asked about, and kept; a node's value
//! depends only on the geometry, so the order in which threads fill the grid never changes an
//! answer. For the same reason every collision world of one geometry shares one grid
//! ([`ClearanceGrid::shared`]): problems built from one map (many seeds, many planners) fill
//! it together, as if the map's clearance field were computed once.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use crate::math::Vec2;

/// Grid spacing (BL) for worlds up to [`MAX_NODES`] nodes; larger worlds get a coarser grid.
pub const SPACING: f64 = 0.25;

/// Largest number of grid nodes of one world.
pub const MAX_NODES: usize = 1 << 20;

/// Geometries whose grids [`ClearanceGrid::shared`] keeps.
pub const SHARED_MAPS: usize = 8;

/// The kept grids, with the geometry each belongs to; the latest used last.
static SHARED: Mutex<Vec<(Vec<u64>, Arc<ClearanceGrid>)>> = Mutex::new(Vec::new());

/// A node not yet computed (a NaN no query returns).
const UNSET: u64 = u64::MAX;

/// Clearances at the nodes of a regular grid over the world's rectangle, computed on demand.
#[derive(Debug)]
pub struct ClearanceGrid {
    spacing: f64,
    columns: usize,
    rows: usize,
    nodes: Vec<AtomicU64>,
}

impl Clone for ClearanceGrid {
    fn clone(&self) -> Self {
        ClearanceGrid {
            spacing: self.spacing,
            columns: self.columns,
            rows: self.rows,
            nodes: self
                .nodes
                .iter()
                .map(|n| AtomicU64::new(n.load(Ordering::Relaxed)))
                .collect(),
        }
    }
}

impl ClearanceGrid {
    /// An empty grid over `[0, width] × [0, height]`.
    pub fn new(width: f64, height: f64) -> Self {
        let area = (width.max(0.0) + SPACING) * (height.max(0.0) + SPACING);
        let spacing = SPACING.max((area / MAX_NODES as f64).sqrt() * 1.01);
        let count = |l: f64| ((l.max(0.0) / spacing).ceil() as usize).saturating_add(1);
        let (columns, rows) = (count(width), count(height));
        let total = columns.saturating_mul(rows);
        if !spacing.is_finite() || total > 2 * MAX_NODES {
            return ClearanceGrid {
                spacing: f64::INFINITY,
                columns: 0,
                rows: 0,
                nodes: Vec::new(),
            };
        }
        ClearanceGrid {
            spacing,
            columns,
            rows,
            nodes: (0..total).map(|_| AtomicU64::new(UNSET)).collect(),
        }
    }

    /// The grid over `[0, width] × [0, height]` of the geometry `key` (every number that
    /// defines the clearance, as bits): the one kept for that key if any, else a new empty one,
    /// kept from then on. At most [`SHARED_MAPS`] geometries are kept; the one used longest ago
    /// gives way.
    pub fn shared(key: Vec<u64>, width: f64, height: f64) -> Arc<Self> {
        let mut kept = SHARED.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(i) = kept.iter().position(|(k, _)| *k == key) {
            let entry = kept.remove(i);
            let grid = entry.1.clone();
            kept.push(entry);
            return grid;
        }
        let grid = Arc::new(ClearanceGrid::new(width, height));
        if kept.len() >= SHARED_MAPS {
            kept.remove(0);
        }
        kept.push((key, grid.clone()));
        grid
    }

    /// A lower bound on the clearance at `p`, from the nearest node (computed by `exact` on
    /// first use); `None` outside the grid.
    #[inline]
    pub fn lower_bound(&self, p: Vec2, exact: impl Fn(Vec2) -> f64) -> Option<f64> {
        self.bounds(p, exact).map(|(lo, _)| lo)
    }

    /// Lower and upper bounds on the clearance at `p`: the nearest node's clearance (computed
    /// by `exact` on first use) less and plus the distance to it; `None` outside the grid.
    #[inline]
    pub fn bounds(&self, p: Vec2, exact: impl Fn(Vec2) -> f64) -> Option<(f64, f64)> {
        let (i, j) = ((p.x / self.spacing).round(), (p.y / self.spacing).round());
        if !(i >= 0.0 && j >= 0.0 && (i as usize) < self.columns && (j as usize) < self.rows) {
            return None;
        }
        let node = Vec2::new(i * self.spacing, j * self.spacing);
        let cell = &self.nodes[j as usize * self.columns + i as usize];
        let bits = cell.load(Ordering::Relaxed);
        let value = if bits == UNSET {
            let v = exact(node);
            cell.store(v.to_bits(), Ordering::Relaxed);
            v
        } else {
            f64::from_bits(bits)
        };
        let gap = (p - node).norm();
        Some((value - gap, value + gap))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_from_below_and_fills_once() {
        let g = ClearanceGrid::new(10.0, 5.0);
        // clearance of the disk of radius 1 about (5, 2.5)
        let exact = |q: Vec2| (q - Vec2::new(5.0, 2.5)).norm() - 1.0;
        let calls = std::cell::Cell::new(0);
        let counted = |q: Vec2| {
            calls.set(calls.get() + 1);
            exact(q)
        };
        for k in 0..400 {
            let p = Vec2::new(0.03 * k as f64 % 10.0, 0.017 * k as f64 % 5.0);
            let b = g.lower_bound(p, counted).unwrap();
            assert!(b <= exact(p) + 1e-12, "{p:?}: {b} > {}", exact(p));
            assert!(
                b >= exact(p) - SPACING * 2f64.sqrt(),
                "{p:?}: {b} too loose"
            );
        }
        let first = calls.get();
        for k in 0..400 {
            let p = Vec2::new(0.03 * k as f64 % 10.0, 0.017 * k as f64 % 5.0);
            g.lower_bound(p, counted).unwrap();
        }
        assert_eq!(calls.get(), first, "nodes are computed once");
        assert!(g.lower_bound(Vec2::new(-1.0, 1.0), exact).is_none());
        assert!(g.lower_bound(Vec2::new(1.0, 9.0), exact).is_none());
        // a huge world gets a coarser grid, not a huge allocation
        let big = ClearanceGrid::new(1e6, 1e6);
        assert!(big.nodes.len() <= 2 * MAX_NODES);
        let absurd = ClearanceGrid::new(1e300, 1e300);
        assert!(absurd.nodes.is_empty());
    }

    #[test]
    fn one_grid_per_geometry() {
        let key = |x: f64| vec![x.to_bits(), 7];
        let a = ClearanceGrid::shared(key(-1.5), 10.0, 5.0);
        let b = ClearanceGrid::shared(key(-1.5), 10.0, 5.0);
        let c = ClearanceGrid::shared(key(-2.5), 10.0, 5.0);
        assert!(Arc::ptr_eq(&a, &b));
        assert!(!Arc::ptr_eq(&a, &c));
        // the kept grids are bounded: after many other geometries, the first is new again
        for i in 0..SHARED_MAPS {
            ClearanceGrid::shared(key(-10.0 - i as f64), 10.0, 5.0);
        }
        assert!(!Arc::ptr_eq(
            &a,
            &ClearanceGrid::shared(key(-1.5), 10.0, 5.0)
        ));
    }
}
