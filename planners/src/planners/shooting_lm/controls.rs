//! The decision variables of `shooting-lm`: piecewise-constant controls over whole control
//! periods, each bounded by a sine transformation, and the straight-line guess they start from.
//!
//! Segment k holds one control for `periods` control periods. Its variables are the field's
//! angle θ_k (free: the model is 2π-periodic in it), the elevation's a_k when the elevation is
//! free, and the gradients' s_x,k, s_y,k. Bounded controls are sines of free variables
//! (MINUIT's transformation for bounded parameters, James & Roos 1975):
//! α = α_max (1 + sin a) / 2 ∈ [0, α_max] and g = G sin s ∈ [−G, G], so every iterate of an
//! unconstrained solver is a command within the coil's limits.

use std::f64::consts::{PI, TAU};

use magbench_env::math::centroid;
use magbench_env::physics::sweep_cancelling_elevation;
use magbench_env::{Control, MAX_AGENTS, Vec2};
use rand::RngExt;

use crate::motion::{aimed, centroid_map, propagate};
use crate::{Problem, Rng};

/// The largest |sin| of a guess's transformed control: a guess on a bound (sin = ±1) sits where
/// the sine's slope is zero, and a gradient-based solver could never move it off.
const OFF_BOUND: f64 = 0.95;

/// The shape of the decision vector.
#[derive(Debug, Clone, Copy)]
pub struct Layout {
    /// Agents.
    pub agents: usize,
    /// Segments (piecewise-constant controls).
    pub segments: usize,
    /// Control periods per segment.
    pub periods: u32,
    /// The largest elevation (rad) when the elevation is free; `None` in the plane.
    pub alpha_max: Option<f64>,
    /// The coil's gradient limit G (T/m).
    pub gradient_limit: f64,
}

impl Layout {
    /// Variables per segment: θ, (a,) s_x, s_y.
    pub fn per_segment(&self) -> usize {
        if self.alpha_max.is_some() { 4 } else { 3 }
    }

    /// Length of the decision vector.
    pub fn len(&self) -> usize {
        self.segments * self.per_segment()
    }

    /// The control of segment `k` under decision vector `z` (θ wrapped into [−π, π)).
    pub fn control(&self, z: &[f64], k: usize) -> Control {
        let v = &z[k * self.per_segment()..(k + 1) * self.per_segment()];
        let theta = (v[0] + PI).rem_euclid(TAU) - PI;
        let (alpha, sx, sy) = match self.alpha_max {
            Some(max) => (max * 0.5 * (1.0 + v[1].sin()), v[2], v[3]),
            None => (0.0, v[1], v[2]),
        };
        Control {
            theta,
            alpha,
            grad: [
                self.gradient_limit * sx.sin(),
                self.gradient_limit * sy.sin(),
            ],
        }
    }

    /// The gradient commands of segment `k` in units of the limit (sin s_x, sin s_y).
    pub fn effort(&self, z: &[f64], k: usize) -> [f64; 2] {
        let v = &z[k * self.per_segment()..(k + 1) * self.per_segment()];
        let p = self.per_segment();
        [v[p - 2].sin(), v[p - 1].sin()]
    }

    /// Writes control `u` as segment `k`'s variables (each transformed control kept within
    /// [`OFF_BOUND`] of its bounds).
    fn set(&self, z: &mut [f64], k: usize, u: &Control) {
        let p = self.per_segment();
        let v = &mut z[k * p..(k + 1) * p];
        let inverse = |fraction: f64| fraction.clamp(-OFF_BOUND, OFF_BOUND).asin();
        v[0] = u.theta;
        if let Some(max) = self.alpha_max {
            v[1] = if max > 0.0 {
                inverse(2.0 * u.alpha / max - 1.0)
            } else {
                0.0
            };
        }
        v[p - 2] = inverse(u.grad[0] / self.gradient_limit);
        v[p - 1] = inverse(u.grad[1] / self.gradient_limit);
    }
}

/// The field of segment `k` in the straight-line guess from `from`: with the elevation free,
/// the sweep that cancels every pair's force on average (three in-plane angles 120° apart at
/// α_h, cos²α_h = 2/3, env's `sweep_cancelling_elevation`); in the plane, the field alternating
/// between ±ψ_m about the axis of agents 0 and 1, where ψ_m = arccos(1/√3) (54.7°) is the local
/// angle at which a pair's radial force vanishes (1 − 3cos²ψ = 0) and the alternation cancels
/// the transverse force (sin 2ψ changes sign).
fn guess_field(from: &[Vec2], alpha_max: Option<f64>, k: usize) -> Control {
    let axis = if from.len() >= 2 {
        let d = from[1] - from[0];
        d.y.atan2(d.x)
    } else {
        0.0
    };
    let (theta, alpha) = match alpha_max {
        Some(max) => (
            axis + TAU * (k % 3) as f64 / 3.0,
            sweep_cancelling_elevation().min(max),
        ),
        None => {
            let psi_m = (1.0f64 / 3.0).sqrt().acos();
            (axis + if k.is_multiple_of(2) { psi_m } else { -psi_m }, 0.0)
        }
    };
    Control {
        theta: (theta + PI).rem_euclid(TAU) - PI,
        alpha,
        grad: [0.0, 0.0],
    }
}

/// The slowest centroid speed (BL/s) along the line from `from`'s centroid to `to`'s that the
/// coil reaches at full gradient under the guess's fields (each coil axis pulls on its own).
pub fn reach(problem: &Problem, alpha_max: Option<f64>, from: &[Vec2], to: &[Vec2]) -> f64 {
    let n = from.len();
    let left = centroid(to) - centroid(from);
    let d = left
        .try_normalize(1e-12)
        .unwrap_or_else(|| Vec2::new(1.0, 0.0));
    let along = |reach: f64, part: f64| {
        if part.abs() < 1e-12 {
            f64::INFINITY
        } else {
            reach.abs() / part.abs()
        }
    };
    (0..3)
        .filter_map(|k| centroid_map(problem, &guess_field(from, alpha_max, k), n))
        .map(|(_, ax, ay)| along(ax.x, d.x).min(along(ay.y, d.y)))
        .fold(f64::INFINITY, f64::min)
}

/// The waypoint `length` BL from `from` toward `goal`: every agent moved along its straight
/// line to its goal by the same fraction, the one that moves the farthest agent `length` (the
/// goal itself when that is at most `length` away).
pub fn waypoint(from: &[Vec2], goal: &[Vec2], length: f64) -> Vec<Vec2> {
    let far = from
        .iter()
        .zip(goal)
        .map(|(p, q)| (q - p).norm())
        .fold(0.0, f64::max);
    if far <= length {
        return goal.to_vec();
    }
    let f = length / far;
    from.iter()
        .zip(goal)
        .map(|(p, q)| p + (q - p) * f)
        .collect()
}

/// The initial decision vector of a window from `from` to `target` whose first segment is the
/// plan's `k0`-th: each segment's field from [`guess_field`] (or, with `rng`, a uniformly random
/// in-plane angle at the same elevation: a restart), and the gradients that carry the centroid,
/// rolled out through the model, to the point of the straight line from `from`'s centroid to
/// `target`'s that it should reach at the segment's end.
pub fn guess(
    problem: &Problem,
    layout: &Layout,
    from: &[Vec2],
    target: &[Vec2],
    k0: usize,
    mut rng: Option<&mut Rng>,
) -> Vec<f64> {
    let n = layout.agents;
    let (c0, c1) = (centroid(from), centroid(target));
    let d = problem.periods(layout.periods);
    let mut z = vec![0.0; layout.len()];
    let mut at = [Vec2::zeros(); MAX_AGENTS];
    at[..n].copy_from_slice(from);
    let mut next = at;
    for k in 0..layout.segments {
        let mut u = guess_field(from, layout.alpha_max, k0 + k);
        if let Some(rng) = rng.as_deref_mut() {
            u.theta = rng.random_range(-PI..PI);
        }
        let to = c0 + (c1 - c0) * ((k + 1) as f64 / layout.segments as f64);
        let u = aimed(problem, u, n, centroid(&at[..n]), to, d);
        layout.set(&mut z, k, &u);
        let u = layout.control(&z, k);
        propagate(problem, &at[..n], &u, d, &mut next[..n]);
        at = next;
    }
    z
}
