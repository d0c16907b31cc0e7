//! The world's obstacles and walls as one parry [`Compound`] with its BVH.

use std::sync::Arc;

use parry2d_f64::math::Pose;
use parry2d_f64::query::{self, PointQuery};
use parry2d_f64::shape::{Ball, Capsule, Compound, SharedShape, TriMesh};

use super::grid::ClearanceGrid;
use super::{from_parry, to_parry};
use crate::math::Vec2;
use crate::world::{Obstacle, World, signed_area};

/// Wall slab thickness outside the rectangle (BL).
const WALL: f64 = 50.0;

/// Below this grid bound (BL), [`CollisionWorld::clearance_bound`] measures exactly.
pub const NEAR: f64 = 0.25;

/// The obstacles and walls of a [`World`] for disks of radius `agent_radius`.
///
/// Non-convex polygons are triangulated (parry's ear clipping); walls are slabs just outside
/// the rectangle. All queries go through parry and the compound's bounding-volume hierarchy.
#[derive(Clone)]
pub struct CollisionWorld {
    compound: Compound,
    ball: Ball,
    agent_radius: f64,
    grid: Arc<ClearanceGrid>,
}

impl std::fmt::Debug for CollisionWorld {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "CollisionWorld({} parts, agent radius {})",
            self.compound.shapes().len(),
            self.agent_radius
        )
    }
}

impl CollisionWorld {
    /// Builds the collision shapes of `world` (polygons must already be valid).
    pub fn new(world: &World, agent_radius: f64) -> Self {
        let (w, h) = (world.width, world.height);
        let mut parts: Vec<(Pose, SharedShape)> = vec![
            (
                Pose::translation(w * 0.5, -WALL),
                SharedShape::cuboid(w * 0.5 + 2.0 * WALL, WALL),
            ),
            (
                Pose::translation(w * 0.5, h + WALL),
                SharedShape::cuboid(w * 0.5 + 2.0 * WALL, WALL),
            ),
            (
                Pose::translation(-WALL, h * 0.5),
                SharedShape::cuboid(WALL, h * 0.5 + 2.0 * WALL),
            ),
            (
                Pose::translation(w + WALL, h * 0.5),
                SharedShape::cuboid(WALL, h * 0.5 + 2.0 * WALL),
            ),
        ];
        for o in &world.obstacles {
            match o {
                Obstacle::Circle { center, radius } => {
                    parts.push((
                        Pose::translation(center.x, center.y),
                        SharedShape::ball(*radius),
                    ));
                }
                Obstacle::Polygon(v) => {
                    let mut v: Vec<_> = v.iter().map(|p| to_parry(*p)).collect();
                    let ccw: Vec<Vec2> = v.iter().map(|p| from_parry(*p)).collect();
                    if signed_area(&ccw) < 0.0 {
                        v.reverse();
                    }
                    let mesh =
                        TriMesh::from_polygon(v).expect("a validated simple polygon triangulates");
                    for t in mesh.triangles() {
                        parts.push((Pose::IDENTITY, SharedShape::triangle(t.a, t.b, t.c)));
                    }
                }
            }
        }
        Self {
            compound: Compound::new(parts),
            ball: Ball::new(agent_radius),
            agent_radius,
            grid: ClearanceGrid::shared(geometry_key(world, agent_radius), w, h),
        }
    }

    /// Agent radius (BL).
    pub fn agent_radius(&self) -> f64 {
        self.agent_radius
    }

    /// True when an agent disk centred at `p` touches no obstacle and no wall: at once when the
    /// clearance grid shows it [`NEAR`] BL clear or [`NEAR`] BL deep, by parry's intersection
    /// test otherwise.
    #[inline]
    pub fn agent_clear(&self, p: Vec2) -> bool {
        match self.grid.bounds(p, |q| self.clearance(q)) {
            Some((lo, _)) if lo >= NEAR => true,
            Some((_, hi)) if hi <= -NEAR => false,
            _ => !intersects(&Pose::translation(p.x, p.y), &self.ball, &self.compound),
        }
    }

    /// True when an agent disk swept in a straight line from `a` to `b` touches nothing.
    pub fn sweep_clear(&self, a: Vec2, b: Vec2) -> bool {
        if a == b {
            return self.agent_clear(a);
        }
        let capsule = Capsule::new(to_parry(a), to_parry(b), self.agent_radius);
        !intersects(&Pose::IDENTITY, &capsule, &self.compound)
    }

    /// Distance from the agent disk at `p` to the nearest obstacle or wall (BL); 0 or less when
    /// touching (−radius when the centre is inside an obstacle).
    pub fn clearance(&self, p: Vec2) -> f64 {
        self.compound
            .distance_to_point(&Pose::IDENTITY, to_parry(p), true)
            - self.agent_radius
    }

    /// A lower bound on [`CollisionWorld::clearance`] at `p`: the exact clearance near
    /// obstacles (below [`NEAR`] BL), a cheaper bound from the clearance grid farther out.
    #[inline]
    pub fn clearance_bound(&self, p: Vec2) -> f64 {
        match self.grid.lower_bound(p, |q| self.clearance(q)) {
            Some(b) if b >= NEAR => b,
            _ => self.clearance(p),
        }
    }

    /// Where an agent at `p` that overlaps obstacles slides to: a nearby position in contact
    /// with the surfaces (projected out repeatedly, for corners). `None` when the agent is clear.
    pub fn push_out(&self, p: Vec2) -> Option<Vec2> {
        let mut q = self.push_out_once(p)?;
        for _ in 0..4 {
            match self.push_out_once(q) {
                Some(next) => q = next,
                None => break,
            }
        }
        Some(q)
    }

    fn push_out_once(&self, p: Vec2) -> Option<Vec2> {
        let proj = self
            .compound
            .project_point(&Pose::IDENTITY, to_parry(p), false);
        let q = from_parry(proj.point);
        let d = p - q;
        let dist = d.norm();
        if proj.is_inside {
            // centre inside an obstacle: leave through the nearest boundary point
            let n = if dist > 0.0 {
                -d / dist
            } else {
                Vec2::new(0.0, 1.0)
            };
            return Some(q + n * self.agent_radius);
        }
        if dist >= self.agent_radius - 1e-12 {
            return None;
        }
        let n = if dist > 0.0 {
            d / dist
        } else {
            Vec2::new(0.0, 1.0)
        };
        Some(q + n * self.agent_radius)
    }
}

/// Every number that defines the clearance field of `world` for disks of `agent_radius`, as
/// bits (with a tag per obstacle kind and count), the key of its shared grid.
fn geometry_key(world: &World, agent_radius: f64) -> Vec<u64> {
    let mut key = vec![
        world.width.to_bits(),
        world.height.to_bits(),
        agent_radius.to_bits(),
    ];
    for o in &world.obstacles {
        match o {
            Obstacle::Circle { center, radius } => {
                key.extend([0, center.x.to_bits(), center.y.to_bits(), radius.to_bits()]);
            }
            Obstacle::Polygon(v) => {
                key.extend([1, v.len() as u64]);
                key.extend(v.iter().flat_map(|p| [p.x.to_bits(), p.y.to_bits()]));
            }
        }
    }
    key
}

/// parry's intersection test of `shape` at `pose` against the compound; an unsupported pair
/// counts as a collision.
fn intersects(pose: &Pose, shape: &dyn parry2d_f64::shape::Shape, compound: &Compound) -> bool {
    query::intersection_test(pose, shape, &Pose::IDENTITY, compound)
        .map(|i| i.intersecting)
        .unwrap_or(true)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn world() -> World {
        World {
            width: 20.0,
            height: 10.0,
            obstacles: vec![
                // an L-shaped (non-convex) polygon, clockwise on purpose
                Obstacle::Polygon(vec![
                    Vec2::new(8.0, 2.0),
                    Vec2::new(8.0, 6.0),
                    Vec2::new(9.0, 6.0),
                    Vec2::new(9.0, 3.0),
                    Vec2::new(12.0, 3.0),
                    Vec2::new(12.0, 2.0),
                ]),
                Obstacle::Circle {
                    center: Vec2::new(15.0, 7.0),
                    radius: 1.0,
                },
            ],
        }
    }

    #[test]
    fn walls_and_obstacles_block() {
        let c = CollisionWorld::new(&world(), 0.5);
        assert!(c.agent_clear(Vec2::new(3.0, 5.0)));
        assert!(!c.agent_clear(Vec2::new(0.4, 5.0)), "left wall");
        assert!(!c.agent_clear(Vec2::new(3.0, 9.7)), "top wall");
        assert!(
            !c.agent_clear(Vec2::new(10.0, 3.3)),
            "inside the L's foot margin"
        );
        assert!(c.agent_clear(Vec2::new(10.5, 4.5)), "in the L's notch");
        assert!(!c.agent_clear(Vec2::new(15.0, 5.6)), "circle");
        assert!((c.clearance(Vec2::new(3.0, 5.0)) - 2.5).abs() < 1e-9);
    }

    #[test]
    fn sweep_catches_graze_between_samples() {
        let c = CollisionWorld::new(&world(), 0.5);
        // both ends clear of the circle, the straight sweep between them grazes it
        let (a, b) = (Vec2::new(13.0, 5.6), Vec2::new(17.0, 5.6));
        assert!(c.agent_clear(a) && c.agent_clear(b));
        assert!(!c.sweep_clear(a, b));
        assert!(c.sweep_clear(Vec2::new(13.0, 4.0), Vec2::new(17.0, 4.0)));
    }

    #[test]
    fn push_out_leaves_a_corner_clear_of_both_walls() {
        let c = CollisionWorld::new(&world(), 0.5);
        let q = c.push_out(Vec2::new(0.2, 0.3)).unwrap();
        assert!(q.x >= 0.5 - 1e-9 && q.y >= 0.5 - 1e-9, "{q:?}");
    }

    /// On every built-in map, at random points (inside and outside obstacles), the clearance
    /// bound never exceeds the exact clearance, and the grid's quick answers of
    /// [`CollisionWorld::agent_clear`] agree with parry's intersection test; a second world of
    /// the same geometry shares the (partly filled) grid and answers the same.
    #[test]
    fn bounds_never_exceed_the_exact_clearance_on_every_map() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        for name in crate::scenario::builtin_names() {
            let s = crate::Scenario::load(name).unwrap();
            let (a, b) = (
                CollisionWorld::new(&s.world, 0.5),
                CollisionWorld::new(&s.world, 0.5),
            );
            assert!(
                Arc::ptr_eq(&a.grid, &b.grid),
                "{name}: one grid per geometry"
            );
            let other = CollisionWorld::new(&s.world, 0.25);
            assert!(
                !Arc::ptr_eq(&a.grid, &other.grid),
                "{name}: radius is geometry"
            );
            let mut near = 0;
            for k in 0..4000 {
                let p = Vec2::new(
                    rng.random_range(-1.0..s.world.width + 1.0),
                    rng.random_range(-1.0..s.world.height + 1.0),
                );
                let w = if k % 2 == 0 { &a } else { &b };
                let exact = w.clearance(p);
                let bound = w.clearance_bound(p);
                assert!(
                    bound <= exact,
                    "{name} {p:?}: bound {bound} > exact {exact}"
                );
                let touching = !intersects(&Pose::translation(p.x, p.y), &w.ball, &w.compound);
                assert_eq!(w.agent_clear(p), touching, "{name} {p:?}");
                near += usize::from(exact.abs() < NEAR);
            }
            assert!(near > 0, "{name}: no point near an obstacle");
        }
    }

    #[test]
    fn push_out_slides_to_contact() {
        let c = CollisionWorld::new(&world(), 0.5);
        let q = c.push_out(Vec2::new(0.3, 5.0)).unwrap();
        assert!((q - Vec2::new(0.5, 5.0)).norm() < 1e-9);
        assert!(c.push_out(Vec2::new(3.0, 5.0)).is_none());
    }
}
