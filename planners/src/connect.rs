//! CONNECT, the shooting connection of RRT*: EXTEND's random tries seed a damped Gauss–Newton
//! refinement of the control, with finite-difference Jacobians through env's propagation.
//!
//! No exact steering function exists for this system. CONNECT looks for one constant control
//! `(θ_B, G_x, G_y)` and a whole number of control periods `T` whose end lies within a
//! tolerance of the target under the problem's metric:
//!
//! 1. `seeds` random (control, duration) tries, as in EXTEND; keep the closest end, and give up
//!    unless it is within `basin` of the target;
//! 2. up to `iterations` Levenberg–Marquardt steps on the residual `E(x(u, T)) − E(target)`
//!    (E the metric's embedding) over the control `u`, the Jacobian by forward differences
//!    (three extra propagations, integrated together); gradients stay within the coil's
//!    limits. After each step, `T` moves to the period, within `window` periods of the current
//!    one, whose state along the trajectory is closest to the target.
//!
//! Every end comes from env's propagation of the returned (control, periods), so the result
//! replays exactly; CONNECT does not check collisions (the caller does).

use magbench_env::math::wrap_angle;
use magbench_env::{Control, MAX_AGENTS, Vec2};

use crate::distance::MAX_DIMS;
use crate::extend::{Extend, Extension};
use crate::{Problem, Rng};

/// The shooting connection's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Connect {
    /// The seeding EXTEND (its tries and duration range).
    pub seed: Extend,
    /// Gauss–Newton iterations at most.
    pub iterations: usize,
    /// Periods around the current duration searched along each trajectory.
    pub window: u32,
    /// Accept when the end is within this metric distance of the target (BL).
    pub tolerance: f64,
    /// Refine only when the best seed ends within this distance of the target (BL): the
    /// refinement is local and rarely recovers a far miss.
    pub basin: f64,
}

impl Connect {
    /// CONNECT(from, target): an extension ending within the tolerance of `target`, if found.
    pub fn run(
        &self,
        problem: &Problem,
        rng: &mut Rng,
        from: &[Vec2],
        target: &[Vec2],
    ) -> Option<Extension> {
        let mut best = self.seed.run(problem, rng, from, target);
        if best.periods == 0 || best.distance > self.basin {
            return None;
        }
        let n = from.len();
        let dims = 2 * n;
        let metric = problem.metric;
        let g_max = problem.model.coil.gradient_limit();
        let mut e_target = [0.0; MAX_DIMS];
        metric.embed(target, &mut e_target);
        let mut lambda = 1e-3;
        let steps = [1e-6, 1e-6 * g_max, 1e-6 * g_max];
        let mut ends = [[Vec2::zeros(); MAX_AGENTS]; 3];
        for _ in 0..self.iterations {
            if best.distance <= self.tolerance {
                break;
            }
            // residual and forward-difference Jacobian at (u, T)
            let u = best.control;
            let d = problem.periods(best.periods);
            let mut e0 = [0.0; MAX_DIMS];
            metric.embed(best.end(n), &mut e0);
            let mut r = [0.0; MAX_DIMS];
            for j in 0..dims {
                r[j] = e0[j] - e_target[j];
            }
            let perturbed = [
                Control {
                    theta: u.theta + steps[0],
                    ..u
                },
                Control {
                    grad: [u.grad[0] + steps[1], u.grad[1]],
                    ..u
                },
                Control {
                    grad: [u.grad[0], u.grad[1] + steps[2]],
                    ..u
                },
            ];
            problem
                .model
                .propagate_many(from, &perturbed, &[d; 3], &mut ends);
            let mut jac = [[0.0; 3]; MAX_DIMS];
            for (c, end) in ends.iter().enumerate() {
                let mut e = [0.0; MAX_DIMS];
                metric.embed(&end[..n], &mut e);
                for j in 0..dims {
                    jac[j][c] = (e[j] - e0[j]) / steps[c];
                }
            }
            // (JᵀJ + λ diag JᵀJ) δ = −Jᵀ r
            let mut a = [[0.0; 3]; 3];
            let mut b = [0.0; 3];
            for j in 0..dims {
                for p in 0..3 {
                    b[p] -= jac[j][p] * r[j];
                    for q in 0..3 {
                        a[p][q] += jac[j][p] * jac[j][q];
                    }
                }
            }
            let mut improved = false;
            for _ in 0..4 {
                let mut m = a;
                for p in 0..3 {
                    m[p][p] += lambda * a[p][p].max(1e-12);
                }
                let Some(delta) = solve3(m, b) else { break };
                let candidate = Control {
                    theta: wrap_angle(u.theta + delta[0]),
                    grad: [
                        (u.grad[0] + delta[1]).clamp(-g_max, g_max),
                        (u.grad[1] + delta[2]).clamp(-g_max, g_max),
                    ],
                    ..u
                };
                if let Some(ext) = self.along(problem, from, target, candidate, best.periods)
                    && ext.distance < best.distance
                {
                    best = ext;
                    lambda = (lambda / 3.0).max(1e-9);
                    improved = true;
                    break;
                }
                lambda *= 4.0;
            }
            if !improved {
                break;
            }
        }
        (best.distance <= self.tolerance).then_some(best)
    }

    /// Propagates `u` up to `periods + window` and returns the closest period boundary to
    /// `target` within `periods ± window` (and the seed's duration range).
    fn along(
        &self,
        problem: &Problem,
        from: &[Vec2],
        target: &[Vec2],
        u: Control,
        periods: u32,
    ) -> Option<Extension> {
        let n = from.len();
        let lo = periods
            .saturating_sub(self.window)
            .max(self.seed.min_periods);
        let hi = (periods + self.window).min(self.seed.max_periods);
        if lo > hi {
            return None;
        }
        let mut best = Extension {
            control: u,
            periods: 0,
            end: [Vec2::zeros(); MAX_AGENTS],
            distance: f64::INFINITY,
        };
        let mut out = [Vec2::zeros(); MAX_AGENTS];
        let keep = |p: u32, s: &[Vec2], best: &mut Extension| {
            let d2 = problem.metric.distance_squared(s, target);
            if d2 < best.distance {
                best.distance = d2;
                best.periods = p;
                best.end[..n].copy_from_slice(s);
            }
        };
        if let Some(edge) = problem.model.pair_edge(from, &u) {
            // the exact flow at each period boundary, as `propagate` would end there
            for p in lo..=hi {
                edge.at(problem.periods(p), &mut out[..n]);
                keep(p, &out[..n], &mut best);
            }
            best.distance = best.distance.sqrt();
            return (best.periods > 0).then_some(best);
        }
        let steps_per_period = (problem.control_period / problem.model.dt).round() as u64;
        let mut step = 0u64;
        problem
            .model
            .propagate_with(from, &u, problem.periods(hi), &mut out[..n], |s| {
                step += 1;
                if step.is_multiple_of(steps_per_period) {
                    let p = (step / steps_per_period) as u32;
                    if p >= lo {
                        keep(p, s, &mut best);
                    }
                }
                true
            });
        best.distance = best.distance.sqrt();
        (best.periods > 0).then_some(best)
    }
}

/// Solves a 3×3 linear system by Cramer's rule; `None` when singular.
fn solve3(m: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: &[[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(&m);
    if !d.is_finite() || d.abs() < 1e-300 {
        return None;
    }
    let mut x = [0.0; 3];
    for (c, xc) in x.iter_mut().enumerate() {
        let mut mc = m;
        for r in 0..3 {
            mc[r][c] = b[r];
        }
        *xc = det(&mc) / d;
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}
