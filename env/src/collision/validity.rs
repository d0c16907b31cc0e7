//! Configuration and motion validity: walls, obstacles and the proximity range.

use std::sync::Arc;

use super::{CollisionWorld, advance};
use crate::coil::Control;
use crate::math::Vec2;
use crate::model::pair_flow::SpeedSummary;
use crate::model::{PairEdge, Propagator};

/// Answers "is this configuration valid?" and "is this motion valid?" (it only checks).
///
/// A configuration is valid when every agent disk is clear of every wall and obstacle and every
/// pair's separation lies strictly inside the proximity range `(r_min, r_max)`; agents that touch
/// (r ≤ 1 BL) stick, and `r_min > 1` keeps that out. A motion is checked along the integrated
/// trajectory: each agent's straight sweep between consecutive integration samples is tested
/// with a parry capsule, and the proximity range at every sample. At the default step (1/120 s)
/// an agent moves at most ~0.09 BL between samples (10.5 BL/s at r_min), under a quarter of its
/// radius, and the capsules make the check continuous along each chord.
#[derive(Debug, Clone)]
pub struct ValidityChecker {
    /// The collision shapes.
    pub collision: Arc<CollisionWorld>,
    /// Smallest separation (exclusive, BL).
    pub r_min: f64,
    /// Largest separation (exclusive, BL).
    pub r_max: f64,
}

impl ValidityChecker {
    /// A checker over `collision` with proximity range `(r_min, r_max)`.
    pub fn new(collision: Arc<CollisionWorld>, r_min: f64, r_max: f64) -> Self {
        Self {
            collision,
            r_min,
            r_max,
        }
    }

    /// True when every pair's separation is inside `(r_min, r_max)`; a separation that is not
    /// a number (a position NaN) is outside.
    pub fn proximity_ok(&self, s: &[Vec2]) -> bool {
        let (lo, hi) = (self.r_min * self.r_min, self.r_max * self.r_max);
        for i in 0..s.len() {
            for j in (i + 1)..s.len() {
                let d2 = (s[j] - s[i]).norm_squared();
                if !(d2 > lo && d2 < hi) {
                    return false;
                }
            }
        }
        true
    }

    /// True when the configuration is valid (see the type's documentation).
    pub fn is_valid(&self, s: &[Vec2]) -> bool {
        self.proximity_ok(s) && s.iter().all(|p| self.collision.agent_clear(*p))
    }

    /// True when moving from `a` to `b` (consecutive integration samples) is valid.
    pub fn segment_valid(&self, a: &[Vec2], b: &[Vec2]) -> bool {
        self.proximity_ok(b)
            && a.iter()
                .zip(b)
                .all(|(p, q)| self.collision.sweep_clear(*p, *q))
    }

    /// Integrates `start` under `u` for `duration` with `model` into `out` and reports whether
    /// the whole motion is valid. A sampled motion stops at the first invalid sample (`out`
    /// then holds it); a closed-form motion leaves its end in `out`.
    pub fn motion_valid(
        &self,
        model: &dyn Propagator,
        start: &[Vec2],
        u: &Control,
        duration: f64,
        out: &mut [Vec2],
    ) -> bool {
        if let Some(edge) = model.closed_form(start, u) {
            return self.edge_end_valid(&edge, duration, out);
        }
        let mut prev = [Vec2::zeros(); crate::MAX_AGENTS];
        let n = start.len();
        prev[..n].copy_from_slice(start);
        model.propagate_visit(start, u, duration, out, &mut |s| {
            let ok = self.segment_valid(&prev[..n], s);
            prev[..n].copy_from_slice(s);
            ok
        })
    }

    /// True when the exact motion `edge` is valid over `[0, duration]`: its separation stays
    /// strictly inside the proximity range (checked exactly, not at samples) and both agents
    /// keep clear of every obstacle ([`advance::clear_along`] with the edge's speed bound).
    pub fn edge_valid(&self, edge: &PairEdge, duration: f64) -> bool {
        let (lo, hi) = edge.separation_range(duration);
        if !(lo > self.r_min && hi < self.r_max) {
            return false;
        }
        advance::clear_along(&self.collision, &PairMotion(edge), duration)
    }

    /// [`PairEdge::at`] `duration` into `out` and [`ValidityChecker::edge_valid`], with the end,
    /// the separation range and the end's speed bound from one evaluation of the orbit.
    pub fn edge_end_valid(&self, edge: &PairEdge, duration: f64, out: &mut [Vec2]) -> bool {
        let ((lo, hi), summary) = edge.end_range_and_speed(duration, out);
        if !(lo > self.r_min && hi < self.r_max) {
            return false;
        }
        let motion = PairMotion(edge);
        advance::clear_along_from(&self.collision, &motion, duration, &out[..2], summary)
    }

    /// Smallest agent clearance to walls and obstacles (BL).
    pub fn clearance(&self, s: &[Vec2]) -> f64 {
        s.iter()
            .map(|p| self.collision.clearance(*p))
            .fold(f64::INFINITY, f64::min)
    }
}

/// A [`PairEdge`] as conservative advancement follows it.
struct PairMotion<'a>(&'a PairEdge);

impl advance::Motion for PairMotion<'_> {
    type Summary = SpeedSummary;

    fn agents(&self) -> usize {
        2
    }

    fn at(&self, t: f64, out: &mut [Vec2]) -> SpeedSummary {
        self.0.at_with_speed(t, out)
    }

    fn bound(&self, a: &SpeedSummary, b: &SpeedSummary) -> f64 {
        self.0.speed_bound(a, b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pair_is_inside_the_range_only_strictly_and_never_with_a_nan_position() {
        let world = crate::world::World {
            width: 20.0,
            height: 20.0,
            obstacles: vec![],
        };
        let world = Arc::new(CollisionWorld::new(&world, 0.5));
        let checker = ValidityChecker::new(world, 1.25, 6.0);
        let pair = |x: f64| [Vec2::new(5.0, 5.0), Vec2::new(5.0 + x, 5.0)];
        assert!(checker.proximity_ok(&pair(3.0)));
        assert!(!checker.proximity_ok(&pair(1.25)));
        assert!(!checker.proximity_ok(&pair(6.0)));
        assert!(!checker.proximity_ok(&pair(f64::NAN)));
        let mut trio = [
            Vec2::new(5.0, 5.0),
            Vec2::new(7.0, 5.0),
            Vec2::new(6.0, 7.0),
        ];
        assert!(checker.proximity_ok(&trio));
        trio[2].y = f64::NAN;
        assert!(!checker.proximity_ok(&trio));
    }
}
