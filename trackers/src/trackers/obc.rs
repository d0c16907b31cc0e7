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

use magbench_env::{Control, Vec2};

use crate::optimizer::{ObcOptimizer, ObcWeights};
use crate::tracker::{Tick, Tracker, TrackerContext, TrackerStatus};

/// Parameters of the OBC tracker.
#[derive(Debug, Clone, PartialEq)]
pub struct ObcParams {
    /// Distance to the path (BL, RMS over agents) above which the proximity controller takes
    /// over.
    pub eps: f64,
    /// How far ahead of its progress the tracker looks for the nearest sample (s).
    pub window: f64,
    /// How far back the proximity controller looks for the nearest sample (s).
    pub back: f64,
    /// Offer the plan's own control to the optimizer as an extra candidate (feedforward).
    pub feedforward: bool,
    /// When behind the plan's schedule, how many extra horizons ahead the target may be.
    pub catchup: f64,
    /// Seconds without progress (while following) after which the progress moves on at the
    /// plan's pace by itself.
    pub stall: f64,
    /// The optimizer's weights.
    pub weights: ObcWeights,
}

impl Default for ObcParams {
    fn default() -> Self {
        ObcParams {
            eps: 0.15,
            window: 1.0,
            back: 1.0,
            feedforward: true,
            catchup: 2.0,
            stall: 0.25,
            weights: ObcWeights::default(),
        }
    }
}

/// The OBC tracker.
#[derive(Debug, Clone)]
pub struct Obc {
    params: ObcParams,
    opt: Option<ObcOptimizer>,
    progress: usize,
    recovering: bool,
    stalled: f64,
    last: Option<Control>,
    targets: Vec<Vec2>,
}

impl Obc {
    /// An OBC tracker with `params`.
    pub fn new(params: ObcParams) -> Self {
        Obc {
            params,
            opt: None,
            progress: 0,
            recovering: false,
            stalled: 0.0,
            last: None,
            targets: vec![],
        }
    }
}

impl Tracker for Obc {
    fn name(&self) -> &str {
        "obc"
    }

    fn reset(&mut self, ctx: &TrackerContext) {
        self.opt = Some(ObcOptimizer::new(
            ctx.model.clone(),
            ctx.checker.clone(),
            ctx.period,
            self.params.weights.clone(),
        ));
        self.progress = 0;
        self.recovering = false;
        self.stalled = 0.0;
    }

    fn command(&mut self, ctx: &TrackerContext, tick: &Tick) -> Control {
        let opt = self.opt.as_ref().expect("reset before command");
        let r = ctx.reference;
        let dt = ctx.model.dt;
        let per_s = |s: f64| (s / dt).round().max(0.0) as usize;
        let lead = per_s(opt.horizon()).max(1);
        let x = tick.estimate;
        let lo = if self.recovering {
            self.progress.saturating_sub(per_s(self.params.back))
        } else {
            self.progress
        };
        let (mut k, d) = r.nearest_sample(x, lo..self.progress + per_s(self.params.window) + 1);
        let eps = self.params.eps;
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
        if self.stalled >= self.params.stall && k < r.last() {
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
            let extra = behind.min((self.params.catchup * lead as f64).round() as usize);
            let j = (k + lead + extra).min(r.last());
            // the plan's control is exact only while one edge covers the whole horizon
            let hint = match (r.edge(k), r.edge(j.saturating_sub(1))) {
                (Some(a), Some(b)) if self.params.feedforward && a == b && j == k + lead => {
                    r.control(k).copied()
                }
                _ => None,
            };
            (r.state(j).to_vec(), hint)
        };
        let sol = opt.solve(x, &target, self.last.as_ref(), hint.as_ref());
        self.targets = target;
        self.last = Some(sol.control);
        sol.control
    }

    fn status(&self) -> TrackerStatus {
        TrackerStatus {
            mode: if self.recovering { "recover" } else { "follow" },
            progress: self.progress,
            targets: Some(self.targets.clone()),
        }
    }
}
