//! Nearest neighbours over team states: a kiddo k-d tree on the metric's embedding.
//!
//! kiddo's mutable tree needs its dimension at compile time and splits leaves on the dimensions
//! in turn, so a constant padding coordinate would make leaves unsplittable. Instead a team of
//! N agents (embedding dimension D = 2N) is stored in a tree of K ∈ {4, 8, 16, 32} dimensions whose
//! extra coordinates repeat the embedding's first ones, each copy scaled by `1/√multiplicity`:
//! squared distances stay exactly those of the metric. Two agents use K = 4 with no copies.

use std::num::NonZero;

use kiddo::leaf_strategies::VecOfArrays;
use kiddo::stem_strategies::eytzinger::Eytzinger;
use kiddo::{KdTree, SquaredEuclidean};

/// Points per leaf bucket: 128 keeps the index near 70 B per two-agent node (32: ~90 B) at
/// about a microsecond per nearest query among 10 000 nodes.
const BUCKET: usize = 128;

/// kiddo's mutable k-d tree (Eytzinger stems, array leaves) with `BUCKET`-point leaves.
type Kd<const K: usize> = KdTree<f64, u32, Eytzinger, VecOfArrays<f64, u32, K, BUCKET>, K, BUCKET>;
use magbench_env::{MAX_AGENTS, Vec2};

use crate::distance::{Distance, MAX_DIMS};

/// A k-d tree of the states of one tree's nodes, keyed by node id.
#[derive(Debug)]
pub struct NearestNeighbors {
    metric: Distance,
    dims: usize,
    weights: [f64; MAX_DIMS],
    index: Index,
}

#[derive(Debug)]
enum Index {
    K4(Kd<4>),
    K8(Kd<8>),
    K16(Kd<16>),
    K32(Kd<32>),
}

/// Runs `$body` with `$t` bound to the tree inside `$index` (`&self.index` or
/// `&mut self.index`) and `$k` to its dimension.
macro_rules! with_index {
    ($index:expr, $t:ident, $k:ident, $body:expr) => {
        match $index {
            Index::K4($t) => {
                #[allow(dead_code)]
                const $k: usize = 4;
                $body
            }
            Index::K8($t) => {
                #[allow(dead_code)]
                const $k: usize = 8;
                $body
            }
            Index::K16($t) => {
                #[allow(dead_code)]
                const $k: usize = 16;
                $body
            }
            Index::K32($t) => {
                #[allow(dead_code)]
                const $k: usize = 32;
                $body
            }
        }
    };
}

impl NearestNeighbors {
    /// An empty structure for teams of `agents` agents under `metric`.
    pub fn new(metric: Distance, agents: usize) -> Self {
        let dims = 2 * agents;
        assert!((4..=MAX_DIMS).contains(&dims), "2 to {MAX_AGENTS} agents");
        let (index, k) = match dims {
            4 => (Index::K4(Kd::default()), 4),
            5..=8 => (Index::K8(Kd::default()), 8),
            9..=16 => (Index::K16(Kd::default()), 16),
            _ => (Index::K32(Kd::default()), 32),
        };
        let mut weights = [0.0; MAX_DIMS];
        for (j, w) in weights.iter_mut().enumerate().take(k) {
            // how many tree coordinates repeat embedding coordinate j mod D
            let copies = (0..k).filter(|i| i % dims == j % dims).count();
            *w = 1.0 / (copies as f64).sqrt();
        }
        NearestNeighbors {
            metric,
            dims,
            weights,
            index,
        }
    }

    /// The metric.
    pub fn metric(&self) -> Distance {
        self.metric
    }

    /// Number of indexed states.
    pub fn len(&self) -> usize {
        with_index!(&self.index, t, K, t.size())
    }

    /// True when nothing is indexed.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    #[inline]
    fn point<const K: usize>(&self, s: &[Vec2]) -> [f64; K] {
        point_of::<K>(self.metric, self.dims, &self.weights, s)
    }

    /// Indexes state `s` of node `id`. Returns false if the k-d tree refused it (a leaf full of
    /// identical coordinates); the node then cannot be found by queries.
    pub fn add(&mut self, s: &[Vec2], id: u32) -> bool {
        let (metric, dims, weights) = (self.metric, self.dims, self.weights);
        with_index!(&mut self.index, t, K, {
            let p = point_of::<K>(metric, dims, &weights, s);
            t.add(&p, id).is_ok()
        })
    }

    /// Removes node `id`, indexed at state `s` (the state it was added with).
    pub fn remove(&mut self, s: &[Vec2], id: u32) {
        let (metric, dims, weights) = (self.metric, self.dims, self.weights);
        with_index!(&mut self.index, t, K, {
            let p = point_of::<K>(metric, dims, &weights, s);
            t.remove(&p, id)
        })
    }

    /// The node nearest to `s` and its distance, if any node is indexed.
    pub fn nearest(&self, s: &[Vec2]) -> Option<(u32, f64)> {
        if self.is_empty() {
            return None;
        }
        with_index!(&self.index, t, K, {
            let p = self.point::<K>(s);
            let r = t.query(&p).nearest_one::<SquaredEuclidean<f64>>().execute();
            Some((r.item, r.distance.sqrt()))
        })
    }

    /// The nodes within distance `radius` of `s` (inclusive), nearest first, into `out`.
    pub fn within(&self, s: &[Vec2], radius: f64, out: &mut Vec<(u32, f64)>) {
        out.clear();
        if self.is_empty() {
            return;
        }
        with_index!(&self.index, t, K, {
            let p = self.point::<K>(s);
            let r = t
                .query(&p)
                .within::<SquaredEuclidean<f64>>(radius * radius)
                .execute();
            out.extend(r.into_iter().map(|q| (q.item, q.distance.sqrt())));
        })
    }

    /// The `k` nodes nearest to `s`, nearest first, into `out`.
    pub fn nearest_k(&self, s: &[Vec2], k: usize, out: &mut Vec<(u32, f64)>) {
        out.clear();
        let Some(k) = NonZero::new(k) else { return };
        if self.is_empty() {
            return;
        }
        with_index!(&self.index, t, K, {
            let p = self.point::<K>(s);
            let r = t.query(&p).nearest_n::<SquaredEuclidean<f64>>(k).execute();
            out.extend(r.into_iter().map(|q| (q.item, q.distance.sqrt())));
        })
    }
}

/// The tree point of state `s`: the embedding, its first coordinates repeated up to K.
#[inline]
fn point_of<const K: usize>(
    metric: Distance,
    dims: usize,
    weights: &[f64; MAX_DIMS],
    s: &[Vec2],
) -> [f64; K] {
    let mut e = [0.0; MAX_DIMS];
    metric.embed(s, &mut e);
    let mut p = [0.0; K];
    if K == dims {
        p.copy_from_slice(&e[..K]);
    } else {
        for (j, x) in p.iter_mut().enumerate() {
            *x = e[j % dims] * weights[j];
        }
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Rng;
    use rand::{RngExt, SeedableRng};

    fn random_team(rng: &mut Rng, n: usize) -> Vec<Vec2> {
        (0..n)
            .map(|_| Vec2::new(rng.random_range(0.0..30.0), rng.random_range(0.0..20.0)))
            .collect()
    }

    /// The k-d tree answers exactly what a linear scan answers, for every team size (the padded
    /// trees included) and both metrics, before and after removals.
    #[test]
    fn queries_match_a_linear_scan() {
        let mut rng = Rng::seed_from_u64(3);
        for n in 2..=MAX_AGENTS {
            for metric in [
                Distance::Positions,
                Distance::CentroidShape {
                    centroid: 1.0,
                    shape: 2.5,
                },
            ] {
                let states: Vec<Vec<Vec2>> = (0..2000).map(|_| random_team(&mut rng, n)).collect();
                let mut nn = NearestNeighbors::new(metric, n);
                for (i, s) in states.iter().enumerate() {
                    assert!(nn.add(s, i as u32));
                }
                for i in (0..2000).step_by(3) {
                    nn.remove(&states[i], i as u32);
                }
                let alive: Vec<usize> = (0..2000).filter(|i| i % 3 != 0).collect();
                assert_eq!(nn.len(), alive.len());
                let mut out = Vec::new();
                for _ in 0..30 {
                    let q = random_team(&mut rng, n);
                    let mut scan: Vec<(f64, u32)> = alive
                        .iter()
                        .map(|&i| (metric.distance(&q, &states[i]), i as u32))
                        .collect();
                    scan.sort_by(|a, b| a.0.total_cmp(&b.0));
                    let (id, d) = nn.nearest(&q).unwrap();
                    assert_eq!(id, scan[0].1, "n = {n}");
                    assert!((d - scan[0].0).abs() < 1e-9 * (1.0 + d));
                    nn.nearest_k(&q, 5, &mut out);
                    let ids: Vec<u32> = out.iter().map(|x| x.0).collect();
                    let want: Vec<u32> = scan[..5].iter().map(|x| x.1).collect();
                    assert_eq!(ids, want, "n = {n}");
                    let r = scan[7].0 + 1e-9;
                    nn.within(&q, r, &mut out);
                    assert_eq!(out.len(), 8, "n = {n}");
                }
            }
        }
    }
}
