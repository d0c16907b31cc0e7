//! `mppi`: model predictive path integral control (Williams et al.), a receding-horizon tracker.
//!
//! The tracker keeps a nominal sequence of `horizon` controls, one per control period. Each
//! tick it shifts the sequence by one period, makes `samples` candidate sequences (the nominal,
//! the plan's own controls, fields held round the circle and noisy copies of the nominal), rolls
//! every candidate out from the estimate with the planning model, scores each rollout and sends
//! the first control of the exponentially weighted average:
//!
//! ```text
//! MPPI(x̂, t)
//!   k ← nearest reference sample to x̂ in [progress, progress + window]
//!   x_ref(h) ← reference sample k + h·(one period), h = 1..H     (clamped to the end)
//!   U ← U shifted by one period; its last control is the plan's there (else repeated)
//!   V_0 ← U, V_1 ← the plan's own controls ahead (feedforward),
//!   V_2.. ← U with its field angle held at θ_U(1) + 2π·a/(angles + 1), a = 1..angles,
//!   V_j ← clamp(U + ε_j), ε_j ~ N(0, diag(noise_angle², noise_angle², (noise_grad·G)²))
//!   for each j (in parallel when samples ≥ parallel_from):
//!     x ← x̂
//!     for h in 1..H:  x ← f(x, V_j(h), period)                   the planning model
//!       S_j += mean_i |x_i − x_ref,i(h)|²
//!              + control_weight · |V_j(h) − V_j(h−1)|²          V_j(0): the last command sent
//!              + PENALTY if the checker rejects x                (the rest of the rollout too)
//!   w_j ← exp(−(S_j − min S) / temperature),  V_b the best candidate
//!   U ← clamp(V_b + Σ w_j (V_j − V_b) / Σ w_j)     each V_j(h) in the polarity nearer V_b(h)
//!   U(h) ← the polarity of U(h) nearer U(h−1)      U(0): the last command sent
//!   return U(1)
//! ```
//!
//! A control's change is measured with the field angle wrapped to (−π, π] and the gradients as
//! fractions of the coil's limit. The elevation is sampled only when the team needs it
//! (`planar`, as for `formation`), within `alpha_max` and the coil's own limit; every sampled
//! control is brought within the coil's limits by the coil's own clamp. The noise comes from a
//! ChaCha8 stream of the run's seed, one stream per reference followed (first plan, new legs,
//! replans), so a run is the same for the same seed; the rollouts are scored in parallel but
//! into their own slots, so the average does not depend on the threads.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use magbench_env::coil::{DEFAULT_ALPHA_MAX_DEG, Planar};
use magbench_env::input::Rejection;
use magbench_env::math::wrap_angle;
use magbench_env::params::Reals;
use magbench_env::{Control, MAX_AGENTS, Vec2, declare_params};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use rayon::prelude::*;

use crate::tracker::{Tick, Tracker, TrackerContext, TrackerStatus};

declare_params! {
    /// The MPPI tracker.
    #[derive(Debug, Clone)]
    pub struct Mppi {
        /// Control sequences sampled per tick (K).
        #[param("samples", 2..=100_000)]
        pub samples: usize = 128,
        /// Control periods (camera frames) each sequence covers (H).
        #[param("horizon", 1..=600)]
        pub horizon: usize = 10,
        /// Temperature λ of the exponential weights (cost units; lower follows the best
        /// rollout more closely).
        #[param("temperature", Reals { min: 0.0, max: 1e9, above: true })]
        pub temperature: f64 = 1e-3,
        /// Standard deviation of the field angle's (and the elevation's) noise (rad).
        #[param("noise_angle", Reals::closed(0.0, 3.2))]
        pub noise_angle: f64 = 0.15,
        /// Standard deviation of each gradient command's noise, as a fraction of the coil's
        /// gradient limit.
        #[param("noise_grad", Reals::closed(0.0, 2.0))]
        pub noise_grad: f64 = 0.25,
        /// Weight of a control's change from one period to the next (per rad², per squared
        /// fraction of the gradient limit).
        #[param("control_weight", Reals::closed(0.0, 1e9))]
        pub control_weight: f64 = 1e-5,
        /// Candidates whose field angle is held over the horizon at evenly spread angles away
        /// from the nominal's (the nominal's gradients and elevation), among the `samples`.
        #[param("angles", 0..=360)]
        pub angles: usize = 11,
        /// How far ahead of its progress the nearest reference sample is sought (s).
        #[param("window", Reals::closed(0.0, 1e4))]
        pub window: f64 = 1.0,
        /// Samples from which the rollouts are scored in parallel (rayon).
        #[param("parallel_from", 1..=1_000_000)]
        pub parallel_from: usize = 64,
        /// Whether the field stays in the plane: `auto` (two agents yes; three or more no where
        /// the medium carries the out-of-plane force, yes in bulk), `true` or `false`.
        #[param("planar")]
        pub planar: Planar = Planar::Auto,
        /// The largest elevation sampled (degrees) when the field may leave the plane.
        #[param("alpha_max", Reals::closed(0.0, 90.0))]
        pub alpha_max: f64 = DEFAULT_ALPHA_MAX_DEG,
        nominal: Vec<Control> = Vec::new(),
        last: Option<Control> = None,
        progress: usize = 0,
        targets: Vec<Vec2> = Vec::new(),
        rng: Option<ChaCha8Rng> = None,
        references: u64 = 0,
    }
    check(check_work);
}

/// Cost added for every period a rollout spends in a configuration the validity checker
/// rejects (a contact, a pair outside the proximity range).
pub const PENALTY: f64 = 1e6;

/// Most predicted periods per tick (`samples × horizon`), so that one tick stays well under a
/// second.
pub const MAX_ROLLOUT_PERIODS: usize = 2_000_000;

/// Mixed into the run's seed, so that the tracker's noise is not the stream a planner seeded
/// with the run's seed draws.
const SEED_MIX: u64 = 0x4D50_5049_0000_0001;

/// Refuses settings whose one tick predicts more than [`MAX_ROLLOUT_PERIODS`] periods.
fn check_work(m: &Mppi) -> Result<(), Rejection> {
    let work = m.samples.saturating_mul(m.horizon);
    if work > MAX_ROLLOUT_PERIODS {
        return Err(Rejection::new(
            "samples",
            format!(
                "samples × horizon = {} × {} = {work} predicted periods per tick; at most {MAX_ROLLOUT_PERIODS} (so that one tick is computed in well under a second): lower samples or horizon",
                m.samples, m.horizon
            ),
        ));
    }
    Ok(())
}

/// What every rollout of one tick shares.
struct Rollouts<'a> {
    ctx: &'a TrackerContext<'a>,
    /// The estimate the rollouts start from.
    x: &'a [Vec2],
    /// The reference one to `horizon` periods ahead, period-major.
    refs: &'a [Vec2],
    /// The command sent last (the first control's change is measured from it).
    last: Option<Control>,
    /// The coil's gradient limit.
    g_max: f64,
    control_weight: f64,
}

impl Rollouts<'_> {
    /// The cost of the sequence `v`: tracking, control change and validity penalties.
    fn cost(&self, v: &[Control]) -> f64 {
        let n = self.x.len();
        let model = self.ctx.model;
        let mut a = [Vec2::zeros(); MAX_AGENTS];
        let mut b = [Vec2::zeros(); MAX_AGENTS];
        a[..n].copy_from_slice(self.x);
        let mut prev = self.last;
        let mut cost = 0.0;
        for (h, u) in v.iter().enumerate() {
            if let Some(p) = prev {
                cost += self.control_weight * self.change(&p, u);
            }
            prev = Some(*u);
            model.propagate(&a[..n], u, self.ctx.period, &mut b[..n]);
            if !self.ctx.checker.is_valid(&b[..n]) {
                // the rest of the rollout is no better: every period left is penalised
                return cost + PENALTY * (v.len() - h) as f64;
            }
            let target = &self.refs[h * n..(h + 1) * n];
            let err: f64 = b[..n]
                .iter()
                .zip(target)
                .map(|(p, q)| (p - q).norm_squared())
                .sum();
            cost += err / n as f64;
            std::mem::swap(&mut a, &mut b);
        }
        cost
    }

    /// The squared change from `p` to `u`: the angles in radians, the gradients as fractions of
    /// the coil's limit.
    fn change(&self, p: &Control, u: &Control) -> f64 {
        let dt = wrap_angle(u.theta - p.theta);
        let da = u.alpha - p.alpha;
        let gx = (u.grad[0] - p.grad[0]) / self.g_max;
        let gy = (u.grad[1] - p.grad[1]) / self.g_max;
        dt * dt + da * da + gx * gx + gy * gy
    }
}

impl Mppi {
    /// `u` within the coil's limits, in the plane unless `elevated`, its elevation at most the
    /// tracker's `alpha_max` and the coil's.
    fn clamp(&self, ctx: &TrackerContext, u: &Control, elevated: bool) -> Control {
        let (u, _) = ctx.model.coil.clamp(u);
        let top = self.alpha_max.to_radians().min(ctx.model.coil.alpha_max());
        let alpha = if elevated {
            u.alpha.clamp(-top, top)
        } else {
            0.0
        };
        Control { alpha, ..u }
    }

    /// The plan's control in force at reference sample `k`, if the plan has one there.
    fn planned(ctx: &TrackerContext, k: usize) -> Option<Control> {
        ctx.reference.control(k).copied()
    }

    /// The perturbation `v − u`, the angle wrapped to (−π, π].
    fn offset(v: &Control, u: &Control) -> [f64; 4] {
        [
            wrap_angle(v.theta - u.theta),
            v.alpha - u.alpha,
            v.grad[0] - u.grad[0],
            v.grad[1] - u.grad[1],
        ]
    }

    /// `u` moved by the perturbation `e`.
    fn moved(u: &Control, e: &[f64; 4]) -> Control {
        Control {
            theta: wrap_angle(u.theta + e[0]),
            alpha: u.alpha + e[1],
            grad: [u.grad[0] + e[2], u.grad[1] + e[3]],
        }
    }
}

impl Tracker for Mppi {
    fn name(&self) -> &str {
        "mppi"
    }

    fn reset(&mut self, ctx: &TrackerContext) {
        self.rng = Some(noise_stream(ctx.seed, self.references));
        self.references += 1;
        self.progress = 0;
        self.targets.clear();
        // the plan's own controls over the first horizon
        let lead = lead(ctx);
        let mut u = Self::planned(ctx, 0).unwrap_or_default();
        self.nominal = (0..self.horizon)
            .map(|h| {
                u = Self::planned(ctx, h * lead).unwrap_or(u);
                u
            })
            .collect();
    }

    fn command(&mut self, ctx: &TrackerContext, tick: &Tick) -> Control {
        let r = ctx.reference;
        let x = tick.estimate;
        let n = x.len();
        let h_len = self.horizon;
        let lead = lead(ctx);
        let elevated = !self.planar.is_planar(n, ctx.model.carries_fz);
        let window = ((self.window / ctx.model.dt).round() as usize).max(lead);
        let (k, _) = r.nearest_sample(x, self.progress..self.progress + window + 1);
        self.progress = k;
        let refs: Vec<Vec2> = (1..=h_len)
            .flat_map(|h| r.state(k + h * lead).iter().copied())
            .collect();
        self.targets = refs[..n].to_vec();

        // the last tick's optimum, one period on
        if self.nominal.len() != h_len {
            self.nominal.resize(h_len, Control::default());
        }
        self.nominal.rotate_left(1);
        let tail = Self::planned(ctx, k + (h_len - 1) * lead)
            .unwrap_or(self.nominal[h_len.saturating_sub(2)]);
        self.nominal[h_len - 1] = tail;
        let nominal: Vec<Control> = self
            .nominal
            .iter()
            .map(|u| self.clamp(ctx, u, elevated))
            .collect();

        // the candidates: the nominal, the plan's own controls, and noisy nominals
        let g_max = ctx.model.coil.gradient_limit();
        let sd = [
            self.noise_angle,
            if elevated { self.noise_angle } else { 0.0 },
            self.noise_grad * g_max,
            self.noise_grad * g_max,
        ];
        let mut feedforward = nominal.clone();
        for (h, u) in feedforward.iter_mut().enumerate() {
            if let Some(p) = Self::planned(ctx, k + h * lead) {
                *u = self.clamp(ctx, &p, elevated);
            }
        }
        let rng = self.rng.get_or_insert_with(|| noise_stream(ctx.seed, 0));
        let mut sequences: Vec<Vec<Control>> = Vec::with_capacity(self.samples);
        sequences.push(nominal.clone());
        sequences.push(feedforward);
        // fields far from the nominal's, held over the horizon: local noise alone cannot turn
        // the field round in time when the pair closes in
        for j in 0..self.angles {
            let theta =
                wrap_angle(nominal[0].theta + TAU * (j + 1) as f64 / (self.angles + 1) as f64);
            sequences.push(nominal.iter().map(|u| Control { theta, ..*u }).collect());
        }
        while sequences.len() < self.samples {
            let v: Vec<Control> = nominal
                .iter()
                .map(|u| {
                    let e = sd.map(|s| s * normal(rng));
                    Mppi::moved(u, &e)
                })
                .collect();
            sequences.push(v);
        }
        let sequences: Vec<Vec<Control>> = sequences
            .into_iter()
            .map(|v| v.iter().map(|u| self.clamp(ctx, u, elevated)).collect())
            .collect();

        // roll every candidate out and score it
        let rollouts = Rollouts {
            ctx,
            x,
            refs: &refs,
            last: self.last,
            g_max,
            control_weight: self.control_weight,
        };
        let costs: Vec<f64> = if sequences.len() >= self.parallel_from {
            sequences.par_iter().map(|v| rollouts.cost(v)).collect()
        } else {
            sequences.iter().map(|v| rollouts.cost(v)).collect()
        };

        // the exponentially weighted average, taken about the best candidate: each control in
        // the polarity nearer the best's field angle (a field turned by π with its elevation and
        // gradients negated moves the team the same), so that two fields a half turn apart,
        // which act alike, are not averaged into one that does not; a rollout whose cost is not
        // a number weighs nothing
        let (best_j, best) = costs
            .iter()
            .copied()
            .enumerate()
            .filter(|(_, c)| c.is_finite())
            .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
        let base = sequences[best_j].clone();
        let weights: Vec<f64> = costs
            .iter()
            .map(|&c| {
                if c.is_finite() {
                    (-(c - best) / self.temperature).exp()
                } else {
                    0.0
                }
            })
            .collect();
        let total: f64 = weights.iter().sum();
        let mut mean = vec![[0.0; 4]; h_len];
        for (v, w) in sequences.iter().zip(&weights) {
            if *w == 0.0 || !total.is_finite() || total == 0.0 {
                continue;
            }
            for (m, (vu, b)) in mean.iter_mut().zip(v.iter().zip(&base)) {
                let e = Mppi::offset(&nearest_polarity(ctx, vu, b.theta), b);
                for (mi, ei) in m.iter_mut().zip(e) {
                    *mi += w * ei / total;
                }
            }
        }
        // the new nominal, each control in the polarity nearer the one before it (the first,
        // nearer the last command sent): the coil's field does not reverse between frames
        let mut before = self.last.map(|u| u.theta);
        self.nominal = base
            .iter()
            .zip(&mean)
            .map(|(b, e)| {
                let u = self.clamp(ctx, &Mppi::moved(b, e), elevated);
                let u = match before {
                    Some(theta) => nearest_polarity(ctx, &u, theta),
                    None => u,
                };
                before = Some(u.theta);
                u
            })
            .collect();
        let u = self.nominal[0];
        self.last = Some(u);
        u
    }

    fn status(&self) -> TrackerStatus {
        TrackerStatus {
            mode: "follow",
            progress: self.progress,
            targets: Some(self.targets.clone()),
        }
    }
}

/// `u`, or its twin — the field turned by π with the elevation and the gradients negated — when
/// the twin's field angle is nearer `theta` and the coil makes the opposite field direction and
/// the same pull of it (true of the tri-axial set, whose pull is linear in both): every moment
/// reverses, so the pair forces and the pull, and with them the motion, are the same.
fn nearest_polarity(ctx: &TrackerContext, u: &Control, theta: f64) -> Control {
    if wrap_angle(u.theta - theta).abs() <= FRAC_PI_2 {
        return *u;
    }
    let twin = Control {
        theta: wrap_angle(u.theta + PI),
        alpha: -u.alpha,
        grad: [-u.grad[0], -u.grad[1]],
    };
    let coil = &ctx.model.coil;
    let (a, b) = (coil.actuation(u), coil.actuation(&twin));
    let same = (a.b_hat + b.b_hat).norm() <= 1e-12
        && (a.pull - b.pull).norm() <= 1e-12 * (1.0 + a.pull.norm());
    if same { twin } else { *u }
}

/// Reference samples per control period (at least one).
fn lead(ctx: &TrackerContext) -> usize {
    ((ctx.period / ctx.model.dt).round() as usize).max(1)
}

/// The noise of the `reference`-th reference a run with `seed` follows: its own ChaCha8 stream.
fn noise_stream(seed: u64, reference: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ SEED_MIX);
    rng.set_stream(reference);
    rng
}

/// One standard normal draw.
fn normal(rng: &mut ChaCha8Rng) -> f64 {
    StandardNormal.sample(rng)
}
