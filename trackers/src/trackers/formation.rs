//! `formation`: a tracker for teams that corrects the shape and the centroid apart.
//!
//! Every agent feels the same pull, so the field decides the team's shape and the gradients
//! its centroid. Each tick the tracker predicts one control period of the planning model from
//! the estimate under the plan's own field and under a fixed set of fields (in-plane angles at
//! the elevation whose three angles 120° apart cancel every pair force on average and at
//! `alpha_max`, and in the plane itself where the field must stay there or `in_plane` allows),
//! each with the gradients that carry the centroid onto the reference's next sample; it commands
//! the one whose predicted shape is closest to the reference's, among those that keep every pair
//! at least `keep_apart` beyond the proximity range's inner edge, or as far apart as the
//! reference's sample does where that is less, for `horizon` periods under the field held (all
//! of them when none does). The plan's own field wins ties and is preferred by `prefer`.
//!
//! Why the fixed set leaves the plane out when it may, and why the pairs are checked over two
//! periods: a pair at angle `φ` to a field of elevation `α` is pulled together in proportion to
//! `3 cos²α cos²φ − 1`, which reaches 2 in the plane but only 1 at the cancelling elevation
//! (`cos²α = 2/3`). In the plane, a pair 1.5 BL apart along the field closes within a frame, so a
//! command that the estimate shows safe ends in contact whenever the true state is a little
//! nearer, and a tracker works from an estimate one frame late. Measured on the team-tracking
//! rings under the `realistic` preset, `docs/planners.md` ("What brings a team into contact").
//!
//! ```text
//! FORMATION(x̂, t)
//!   x_ref ← reference sample one period after t
//!   for u in {plan's field at t} ∪ hold set:
//!     u ← u with the gradients that move centroid(x̂) to centroid(x_ref) in one period
//!     x ← f(x̂, u, one period)                        the planning model
//!     score(u) ← ‖shape(x) − shape(x_ref)‖²  (× prefer for the plan's field)
//!                last if within `horizon` periods of u a pair is nearer than
//!                min(r_min + keep_apart, the sample's)
//!   return argmin score
//! ```

use std::f64::consts::{PI, TAU};

use magbench_env::coil::{DEFAULT_ALPHA_MAX_DEG, Planar};
use magbench_env::math::{centroid, shape_distance};
use magbench_env::params::Reals;
use magbench_env::physics::sweep_cancelling_elevation;
use magbench_env::{Actuation, Control, MAX_AGENTS, Vec2, declare_params};

use crate::tracker::{Tick, Tracker, TrackerContext, TrackerStatus};

declare_params! {
    /// Shape and centroid corrected apart, one period ahead.
    #[derive(Debug, Clone)]
    pub struct Formation {
        /// Least predicted distance beyond the proximity range's inner edge `r_min` that every
        /// pair keeps (BL).
        #[param("keep_apart", Reals::closed(0.0, 10.0))]
        pub keep_apart: f64 = 0.1,
        /// Factor on the plan's own field's score (below 1 prefers it).
        #[param("prefer", Reals::closed(0.0, 1.0))]
        pub prefer: f64 = 0.9,
        /// In-plane angles of the fixed field set.
        #[param("angles", 3..=360)]
        pub angles: usize = 12,
        /// Whether the field stays in the plane: `auto` (two agents yes; three or more no where
        /// the medium carries the out-of-plane force, yes in bulk), `true` or `false`.
        #[param("planar")]
        pub planar: Planar = Planar::Auto,
        /// The largest elevation commanded (degrees) when the field may leave the plane.
        #[param("alpha_max", Reals::closed(0.0, 90.0))]
        pub alpha_max: f64 = DEFAULT_ALPHA_MAX_DEG,
        /// Whether the fixed field set holds in-plane fields when the field may leave the plane
        /// (where it must stay in the plane, they are the whole set).
        #[param("in_plane")]
        pub in_plane: bool = false,
        /// Control periods over which a candidate field, held, must keep the pairs apart: the
        /// period commanded and the one the estimate may lag by.
        #[param("horizon", 1..=10)]
        pub horizon: usize = 2,
        progress: usize = 0,
        targets: Vec<Vec2> = Vec::new(),
    }
}

/// The least separation of any pair of `s`.
fn least_separation(s: &[Vec2]) -> f64 {
    let mut least = f64::INFINITY;
    for i in 0..s.len() {
        for j in (i + 1)..s.len() {
            least = least.min((s[i] - s[j]).norm());
        }
    }
    least
}

impl Formation {
    /// The fields tried besides the plan's: `angles` in-plane angles at each elevation.
    fn field_set(&self, elevated: bool, coil_alpha_max: f64) -> Vec<Control> {
        let mut alphas = vec![];
        if !elevated || self.in_plane {
            alphas.push(0.0);
        }
        if elevated {
            let top = self.alpha_max.to_radians().min(coil_alpha_max);
            let hold = sweep_cancelling_elevation();
            alphas.extend([hold.min(top), top]);
            alphas.dedup();
        }
        let mut set = Vec::with_capacity(alphas.len() * self.angles);
        for &alpha in &alphas {
            for k in 0..self.angles {
                set.push(Control {
                    theta: -PI + TAU * k as f64 / self.angles as f64,
                    alpha,
                    grad: [0.0, 0.0],
                });
            }
        }
        set
    }
}

/// `u` with gradient commands, each within the coil's limit, that move the centroid of a team
/// of `n` by `shift` in `period` seconds under `u`'s field (per axis, clamped); `u` unchanged
/// when the agents' mobilities differ.
fn aim(ctx: &TrackerContext, u: Control, n: usize, shift: Vec2, period: f64) -> Control {
    let coil = &ctx.model.coil;
    let limit = coil.gradient_limit();
    let (zero, [px, py]) = coil.pull_map(&u);
    let velocity = |pull| {
        ctx.model
            .kinematics
            .centroid_velocity(&Actuation { pull, ..zero }, n)
    };
    let (Some(v0), Some(vx), Some(vy)) = (
        velocity(zero.pull),
        velocity(zero.pull + px * limit),
        velocity(zero.pull + py * limit),
    ) else {
        return u;
    };
    let want = shift / period - v0;
    let fraction = |want: f64, reach: f64| {
        let s = want / reach;
        if s.is_finite() {
            s.clamp(-1.0, 1.0)
        } else {
            0.0
        }
    };
    let (ax, ay) = (vx - v0, vy - v0);
    Control {
        grad: [
            fraction(want.x, ax.x) * limit,
            fraction(want.y, ay.y) * limit,
        ],
        ..u
    }
}

impl Tracker for Formation {
    fn name(&self) -> &str {
        "formation"
    }

    fn reset(&mut self, _ctx: &TrackerContext) {
        self.progress = 0;
        self.targets.clear();
    }

    fn command(&mut self, ctx: &TrackerContext, tick: &Tick) -> Control {
        let r = ctx.reference;
        let n = r.agents();
        let est = tick.estimate;
        self.progress = r.index_at(tick.t);
        let next = r.index_at(tick.t + ctx.period).min(r.last());
        let target = r.state(next);
        self.targets = target.to_vec();
        let shift = centroid(target) - centroid(est);
        let elevated = !self.planar.is_planar(n, ctx.model.carries_fz);
        let own = r.control(self.progress).copied().map(|u| Control {
            alpha: if elevated { u.alpha } else { 0.0 },
            ..u
        });
        // the plan itself may pass a pair closer than that: then as close as the plan
        let floor = (ctx.checker.r_min + self.keep_apart).min(least_separation(target) - 1e-9);
        let mut best: Option<(bool, f64, Control)> = None;
        let mut out = [Vec2::zeros(); MAX_AGENTS];
        let mut later = [Vec2::zeros(); MAX_AGENTS];
        let candidates = own.into_iter().map(|u| (true, u)).chain(
            self.field_set(elevated, ctx.model.coil.alpha_max())
                .into_iter()
                .map(|u| (false, u)),
        );
        for (is_own, u) in candidates {
            let u = aim(ctx, u, n, shift, ctx.period);
            ctx.model.propagate(est, &u, ctx.period, &mut out[..n]);
            let mut apart = least_separation(&out[..n]) >= floor;
            let mut from = out;
            for _ in 1..self.horizon {
                if !apart {
                    break;
                }
                ctx.model
                    .propagate(&from[..n], &u, ctx.period, &mut later[..n]);
                apart = least_separation(&later[..n]) >= floor;
                from = later;
            }
            let mut score = shape_distance(&out[..n], target);
            if is_own {
                score *= self.prefer;
            }
            if !score.is_finite() {
                continue;
            }
            // a field that keeps the pairs apart beats any that does not
            let better = match best {
                None => true,
                Some((b_apart, b_score, _)) => (apart, -score) > (b_apart, -b_score),
            };
            if better {
                best = Some((apart, score, u));
            }
        }
        best.map(|(_, _, u)| u).unwrap_or_default()
    }

    fn status(&self) -> TrackerStatus {
        TrackerStatus {
            mode: "follow",
            progress: self.progress,
            targets: Some(self.targets.clone()),
        }
    }
}
