//! `obc`: the optimization-based controller with the seed's two modes (Sec. III-B).
//!
//! Each tick the team's distance to the reference is measured against the reference samples
//! near its progress (RMS over agents of the agent distances). When it exceeds `eps`, the
//! proximity controller drives the team to the nearest reference sample (mode `recover`)
//! until it is within `eps/2` of it; otherwise the tracker follows the path forward (mode
//! `follow`): its progress moves to the nearest sample ahead and the target is the reference
//! one prediction horizon later, with the plan's own control offered as an extra candidate.
//! Behind the plan's schedule the target may be up to `catchup` horizons further ahead; when
//! the progress has not moved for `stall` seconds while following (an RRT path that doubles
//! back, a target the pair cannot quite reach), it moves on at the plan's pace by itself.
//! Either way the [`ObcOptimizer`] turns the target into the command.

use magbench_env::params::Reals;
use magbench_env::{Control, declare_params};

use super::obc_drive::ObcDrive;
use crate::tracker::{Tick, Tracker, TrackerContext, TrackerStatus};

declare_params! {
    /// The OBC tracker.
    #[derive(Debug, Clone)]
    pub struct Obc {
        /// Error (BL, RMS over agents) above which the proximity controller takes over.
        #[param("eps", Reals::closed(0.0, 1e3))]
        pub eps: f64 = 0.15,
        /// How far ahead of its progress the nearest reference sample is sought (s).
        #[param("window", Reals::closed(0.0, 1e4))]
        pub window: f64 = 1.0,
        /// How far back the proximity controller seeks the nearest sample (s).
        #[param("back", Reals::closed(0.0, 1e4))]
        pub back: f64 = 1.0,
        /// Offer the plan's own control to the optimizer as a candidate (feedforward); false
        /// = the grid only.
        #[param("feedforward")]
        pub feedforward: bool = true,
        /// Behind the plan's schedule, how many extra horizons ahead the target may be.
        #[param("catchup", Reals::closed(0.0, 100.0))]
        pub catchup: f64 = 2.0,
        /// Seconds without progress (while following) after which the progress moves on at
        /// the plan's pace by itself.
        #[param("stall", Reals::closed(0.0, 1e3))]
        pub stall: f64 = 0.25,
        /// The optimizer that turns the target into the command, and its weights.
        #[params]
        pub drive: ObcDrive,
        progress: usize = 0,
        recovering: bool = false,
        stalled: f64 = 0.0,
    }
}

impl Tracker for Obc {
    fn name(&self) -> &str {
        "obc"
    }

    fn reset(&mut self, ctx: &TrackerContext) {
        self.drive.reset(ctx);
        self.progress = 0;
        self.recovering = false;
        self.stalled = 0.0;
    }

    fn command(&mut self, ctx: &TrackerContext, tick: &Tick) -> Control {
        let r = ctx.reference;
        let dt = ctx.model.dt;
        let per_s = |s: f64| (s / dt).round().max(0.0) as usize;
        let lead = per_s(self.drive.optimizer().horizon()).max(1);
        let x = tick.estimate;
        let lo = if self.recovering {
            self.progress.saturating_sub(per_s(self.back))
        } else {
            self.progress
        };
        let (mut k, d) = r.nearest_sample(x, lo..self.progress + per_s(self.window) + 1);
        let eps = self.eps;
        self.recovering = if self.recovering {
            d > 0.5 * eps
        } else {
            d > eps
        };
        self.stalled = if k > self.progress || self.recovering {
            0.0
        } else {
            self.stalled + ctx.period
        };
        if self.stalled >= self.stall && k < r.last() {
            // on the path but not getting on along it (a path that doubles back, a target the
            // pair cannot quite reach): the progress moves on at the plan's pace by itself
            k = (self.progress + lead).min(r.last());
        }
        self.progress = k;
        let (target, hint) = if self.recovering {
            (r.state(k).to_vec(), None)
        } else {
            // behind schedule, aim up to `catchup` horizons further ahead to win time back
            let behind = r.index_at(tick.t).saturating_sub(k);
            let extra = behind.min((self.catchup * lead as f64).round() as usize);
            let j = (k + lead + extra).min(r.last());
            // the plan's control is exact only while one edge covers the whole horizon
            let hint = match (r.edge(k), r.edge(j.saturating_sub(1))) {
                (Some(a), Some(b)) if self.feedforward && a == b && j == k + lead => {
                    r.control(k).copied()
                }
                _ => None,
            };
            (r.state(j).to_vec(), hint)
        };
        self.drive.command(x, &target, &target, hint.as_ref())
    }

    fn status(&self) -> TrackerStatus {
        TrackerStatus {
            mode: if self.recovering { "recover" } else { "follow" },
            progress: self.progress,
            targets: Some(self.drive.targets()),
        }
    }
}
