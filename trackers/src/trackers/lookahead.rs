//! `lookahead`: pure pursuit after the seed's eq. (6), Sec. V-C.
//!
//! Both agents share one segment index `k` into the reference: segments are traversed in
//! order, for both agents together, and `k` moves on only as far as the agent that is further
//! behind (each agent is projected onto its own planned polyline, ahead of `k`). When the
//! projections have not moved on for `stall` seconds (a path that doubles back on itself, as
//! RRT paths do, or a pair that cannot do both pursuits at once) while the team is within
//! `lookahead` of the path, `k` moves on at the plan's pace by itself: the targets keep moving
//! along the path. For agent `i`
//! at `P_i`:
//!
//! - `d1` is the unit direction from `P_i` back to its projection on the path (zero on the
//!   path);
//! - `d2` is the unit direction from `P_i` to its lookahead point: agent `i`'s reference at the
//!   first sample at least `lookahead` BL of path beyond `k` — the targets move along the path
//!   as the team progresses;
//! - `d_l = L·d1 + (1 − L)·d2` (eq. 6).
//!
//! The target of agent `i` one horizon ahead is `P_i + m_i·d_l`, where `m_i` is how far the
//! plan moves agent `i` over one horizon at `k` plus `L` times its distance from the path (so
//! an agent that has fallen off the path is asked to come back, not only to keep pace). Near the
//! end of the reference (every agent within `lookahead` of its final point) the targets become
//! the final state. The [`ObcOptimizer`] turns the targets into the coil command.

use magbench_env::params::Reals;
use magbench_env::{Control, Vec2, declare_params};

use super::obc_drive::ObcDrive;
use crate::tracker::{Tick, Tracker, TrackerContext, TrackerStatus};

declare_params! {
    /// The lookahead (pure pursuit) tracker.
    #[derive(Debug, Clone)]
    pub struct Lookahead {
        /// Gain L of eq. (6): weight of the direction back to the path (0 = pure pursuit of
        /// the lookahead point, 1 = back to the path only).
        #[param("gain", Reals::closed(0.0, 1.0))]
        pub gain: f64 = 0.5,
        /// Lookahead distance along the path (BL).
        #[param("lookahead", Reals::closed(0.0, 1e3))]
        pub lookahead: f64 = 0.3,
        /// How far ahead agents are projected onto their paths (s of reference).
        #[param("window", Reals::closed(0.0, 1e4))]
        pub window: f64 = 1.0,
        /// Seconds without progress after which the targets move on along the path at the
        /// plan's pace by themselves (while the team is within `lookahead` of the path).
        #[param("stall", Reals::closed(0.0, 1e3))]
        pub stall: f64 = 0.1,
        /// The optimizer that turns the targets into the command, and its weights.
        #[params]
        pub drive: ObcDrive,
        k: usize = 0,
        stalled: f64 = 0.0,
        holding: bool = false,
    }
}

fn unit(v: Vec2) -> Vec2 {
    let n = v.norm();
    if n > 1e-9 { v / n } else { Vec2::zeros() }
}

impl Tracker for Lookahead {
    fn name(&self) -> &str {
        "lookahead"
    }

    fn reset(&mut self, ctx: &TrackerContext) {
        self.drive.reset(ctx);
        self.k = 0;
        self.stalled = 0.0;
        self.holding = false;
    }

    fn command(&mut self, ctx: &TrackerContext, tick: &Tick) -> Control {
        let r = ctx.reference;
        let x = tick.estimate;
        let n = x.len();
        let dt = ctx.model.dt;
        let lead = ((self.drive.optimizer().horizon() / dt).round() as usize).max(1);
        let window = self.k..self.k + ((self.window / dt).round() as usize).max(lead) + 1;
        // project each agent on its own path ahead of k; the team moves on with the slowest
        let proj: Vec<(f64, f64)> = (0..n)
            .map(|i| r.distance_to_path_in(i, x[i], window.clone()))
            .collect();
        let slowest = proj.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
        let moved_to = self.k.max(slowest.floor() as usize).min(r.last());
        self.stalled = if moved_to > self.k {
            0.0
        } else {
            self.stalled + ctx.period
        };
        self.k = moved_to;
        if self.stalled >= self.stall && r.distance_to_sample(x, self.k) < self.lookahead {
            // the projections are stuck (a path that doubles back, a pair that cannot do both
            // pursuits at once): the targets move on along the path by themselves
            self.k = (self.k + lead).min(r.last());
        }
        let k = self.k;
        let end = r.end();
        let near_end = (0..n).all(|i| (x[i] - end[i]).norm() <= self.lookahead)
            || r.index_ahead(k, self.lookahead) >= r.last()
                && (0..n).all(|i| proj[i].1 >= (r.last() - 1) as f64);
        self.holding = near_end;
        // each agent's projection on its own path
        let on_path: Vec<Vec2> = (0..n)
            .map(|i| {
                let (s0, f) = (proj[i].1.floor() as usize, proj[i].1.fract());
                r.point(s0, i) + (r.point(s0 + 1, i) - r.point(s0, i)) * f
            })
            .collect();
        let target: Vec<Vec2> = if near_end {
            end.to_vec()
        } else {
            let j = r.index_ahead(k, self.lookahead);
            let l = self.gain;
            (0..n)
                .map(|i| {
                    let d1 = unit(on_path[i] - x[i]);
                    let d2 = unit(r.point(j, i) - x[i]);
                    let dl = d1 * l + d2 * (1.0 - l);
                    let pace = (r.point(k + lead, i) - r.point(k, i)).norm();
                    x[i] + dl * (pace + l * proj[i].0)
                })
                .collect()
        };
        let path = if near_end { &target } else { &on_path };
        self.drive.command(x, &target, path, None)
    }

    fn status(&self) -> TrackerStatus {
        TrackerStatus {
            mode: if self.holding { "hold" } else { "pursue" },
            progress: self.k,
            targets: Some(self.drive.targets()),
        }
    }
}
