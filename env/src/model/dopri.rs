//! Adaptive Dormand–Prince 5(4) on agent positions, with Hairer's fourth-order dense output.
//!
//! A motion is solved by error-controlled steps whose sequence depends only on the start and the
//! velocity field, never on the duration asked for: the last step may reach past the duration,
//! and every sample — the visits and the end — is read from the dense output of the step that
//! contains it. So the state at a time `t` is the same bits whether the motion was asked to end
//! at `t` or visited `t` on its way further, which planners rely on when they stop a motion at a
//! control period boundary they saw while visiting.
//!
//! Samples are visited at the same instants as the fixed-step integrator visits its step ends
//! (every `dt` and the end; [`super::step_schedule`]), so a continuous check sweeps chords
//! between the same instants as at the fixed step.
//!
//! Tolerance: [`TOLERANCE_BL`] on every agent position, end and samples, over motions up to
//! [`REFERENCE_DURATION_S`]. A team under a constant field contracts or spreads along unstable
//! directions: a position error made while the team moves at relative speed `v_k` grows, by the
//! time it moves at `v`, by about `v / v_k` (the error is a shift along the motion). So each
//! step's local error estimate is held below a fixed fraction of the step's own relative
//! displacement ([`ErrorBudget`]): summed and grown, the errors stay below `v · t` times that
//! fraction, a shift in time; with the fraction `TOLERANCE_BL / (v_max · REFERENCE_DURATION_S)`
//! and `v_max` the fastest relative speed a valid team can have, below the tolerance.
//!
//! No crate is used: `ode_solvers`' `Dopri5` owns its system and stores its output in vectors
//! and `diffsol` is built for large heap-allocated systems; both end a motion exactly at its
//! duration, which breaks the sampling rule above. This solver keeps every stage on the stack.

use crate::math::{MAX_AGENTS, Vec2};

/// The integration tolerance on every agent position (BL): a tenth of the bound the project
/// holds the fixed step to (halving `dt` moves an RK4 edge's end by less than 1e-3 BL,
/// `env/tests/integration_step.rs`), a two-hundredth of the camera's position noise
/// (σ = 0.02 BL in the `realistic` and `hardware` presets) and 1/7500 of the built-in goal
/// tolerance (0.75 BL). The accuracy test (`env/tests/adaptive_flow.rs`) checks every sample
/// against it and, team size by team size, the largest deviation from a fine reference against
/// fixed-step RK4's at `dt`: the adaptive flow must be at least as accurate.
pub const TOLERANCE_BL: f64 = 1e-4;

/// The longest motion the tolerance budget is spread over (s): the planners' default longest
/// edge (`max_duration = 2`).
pub const REFERENCE_DURATION_S: f64 = 2.0;

/// How much local error a step may make: [`ErrorBudget::per_bl`] per BL that the team moves
/// relative to its mean motion in the step, counting at least `min_speed · h`. Steps from a
/// state with two agents closer than `r_min` are not error-controlled below the fixed step `dt`:
/// the proximity check rejects every motion at such a sample, so only determinism matters there
/// (and the velocity field's singularity at contact would otherwise shrink steps without end).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorBudget {
    /// Local error allowed per BL of relative displacement.
    pub per_bl: f64,
    /// The slowest relative speed a step is charged for (BL/s).
    pub min_speed: f64,
    /// The separation below which a team is invalid (BL).
    pub r_min: f64,
}

impl ErrorBudget {
    /// The budget that keeps a motion up to [`REFERENCE_DURATION_S`] within [`TOLERANCE_BL`]
    /// for a team whose relative speed (any agent, against the team's mean) never exceeds
    /// `max_speed` (BL/s); steps slower than `min_speed` are charged as if at `min_speed`.
    /// Teams with two agents closer than `r_min` are not error-controlled below `dt`.
    pub fn new(max_speed: f64, min_speed: f64, r_min: f64) -> Self {
        Self {
            per_bl: TOLERANCE_BL / (max_speed * REFERENCE_DURATION_S),
            min_speed,
            r_min,
        }
    }
}

/// The first trial step, in fixed steps `dt` (one 60 fps frame at the default `dt`).
const FIRST_STEP_DTS: f64 = 6.0;

/// The smallest step, in fixed steps `dt`: a step this short is accepted whatever its error
/// estimate, which bounds the work of any motion.
const SMALLEST_STEP_DTS: f64 = 1.0 / 64.0;

const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

type Agents = [Vec2; MAX_AGENTS];

/// The sample spacing `dt` (s) and the error budget of an adaptive motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dp5Grid {
    /// Spacing of the visited samples (s), the fixed-step integrator's step.
    pub dt: f64,
    /// The local error each step may make.
    pub budget: ErrorBudget,
}

/// Work counters of one adaptive motion (for tests and measurements).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Dp5Stats {
    /// Accepted steps.
    pub accepted: usize,
    /// Rejected steps.
    pub rejected: usize,
}

/// The dense output of one accepted step: `y(t0 + θh) = r1 + θ(r2 + (1−θ)(r3 + θ(r4 + (1−θ)r5)))`.
struct Dense {
    r: [Agents; 5],
}

impl Dense {
    #[inline]
    fn at(&self, n: usize, theta: f64, out: &mut [Vec2]) {
        let t1 = 1.0 - theta;
        let [r1, r2, r3, r4, r5] = &self.r;
        for i in 0..n {
            out[i] = r1[i] + (r2[i] + (r3[i] + (r4[i] + r5[i] * t1) * theta) * t1) * theta;
        }
    }
}

/// Solves `ṗ = f(p)` from `start` for `duration` seconds by adaptive Dormand–Prince 5(4) within
/// `budget` and writes the end into `out`. With `visits`, calls `visit` on the sample at every
/// whole `dt` after the start and at the end (the fixed-step integrator's sample instants);
/// stops early and returns false as soon as `visit` returns false (`out` then holds that
/// sample). Without `visits`, only the end is evaluated, bit for bit equal to the last sample
/// with them. Returns the verdict and the work done. Every step is at least `dt / 64` long (`dt`
/// inside `r_min`), so the work is bounded by the duration whatever the velocity field does.
#[inline]
#[allow(clippy::needless_range_loop)] // the stage formulas index every array by agent alike
pub fn dp5_solve(
    f: &impl Fn(&[Vec2], &mut [Vec2]),
    start: &[Vec2],
    duration: f64,
    grid: Dp5Grid,
    out: &mut [Vec2],
    visits: bool,
    mut visit: impl FnMut(&[Vec2]) -> bool,
) -> (bool, Dp5Stats) {
    let Dp5Grid { dt, budget } = grid;
    let mut stats = Dp5Stats::default();
    let n = start.len();
    assert!(
        n <= MAX_AGENTS && out.len() == n,
        "at most {MAX_AGENTS} agents"
    );
    let (steps, rest) = super::step_schedule(duration, dt);
    let samples = steps + usize::from(rest > 0.0);
    if samples == 0 {
        out.copy_from_slice(start);
        return (true, stats);
    }
    let sample_time = |k: usize| {
        if k >= samples {
            duration
        } else {
            k as f64 * dt
        }
    };
    let mut next = if visits { 1 } else { samples };
    let mut next_t = sample_time(next);

    let z = Vec2::zeros();
    let mut y: Agents = [z; MAX_AGENTS];
    y[..n].copy_from_slice(start);
    let mut k = [[z; MAX_AGENTS]; 7];
    let mut s: Agents = [z; MAX_AGENTS];
    let mut y_new: Agents = [z; MAX_AGENTS];
    f(&y[..n], &mut k[0][..n]);
    let h_max = REFERENCE_DURATION_S;
    let h_floor = |y: &[Vec2]| {
        let r2 = budget.r_min * budget.r_min;
        let close = (0..n).any(|i| ((i + 1)..n).any(|j| (y[i] - y[j]).norm_squared() < r2));
        if close { dt } else { dt * SMALLEST_STEP_DTS }
    };
    let mut h_min = h_floor(&y[..n]);
    let mut h = dt * FIRST_STEP_DTS;
    let mut t = 0.0;
    let mut rejected_last = false;
    let mut last_accepted: Option<(f64, f64)> = None;
    loop {
        for i in 0..n {
            s[i] = y[i] + k[0][i] * (h * A21);
        }
        f(&s[..n], &mut k[1][..n]);
        for i in 0..n {
            s[i] = y[i] + (k[0][i] * A31 + k[1][i] * A32) * h;
        }
        f(&s[..n], &mut k[2][..n]);
        for i in 0..n {
            s[i] = y[i] + (k[0][i] * A41 + k[1][i] * A42 + k[2][i] * A43) * h;
        }
        f(&s[..n], &mut k[3][..n]);
        for i in 0..n {
            s[i] = y[i] + (k[0][i] * A51 + k[1][i] * A52 + k[2][i] * A53 + k[3][i] * A54) * h;
        }
        f(&s[..n], &mut k[4][..n]);
        for i in 0..n {
            s[i] = y[i]
                + (k[0][i] * A61 + k[1][i] * A62 + k[2][i] * A63 + k[3][i] * A64 + k[4][i] * A65)
                    * h;
        }
        f(&s[..n], &mut k[5][..n]);
        for i in 0..n {
            y_new[i] = y[i]
                + (k[0][i] * B1 + k[2][i] * B3 + k[3][i] * B4 + k[4][i] * B5 + k[5][i] * B6) * h;
        }
        f(&y_new[..n], &mut k[6][..n]);
        let mut err: f64 = 0.0;
        for i in 0..n {
            let e = (k[0][i] * E1
                + k[2][i] * E3
                + k[3][i] * E4
                + k[4][i] * E5
                + k[5][i] * E6
                + k[6][i] * E7)
                * h;
            let e = e.norm();
            err = if e.is_nan() || e > err { e } else { err };
        }
        let mut mean = Vec2::zeros();
        for i in 0..n {
            mean += y_new[i] - y[i];
        }
        mean /= n as f64;
        let mut moved = budget.min_speed * h;
        for i in 0..n {
            moved = moved.max((y_new[i] - y[i] - mean).norm());
        }
        let ratio = err / (budget.per_bl * moved);
        if (ratio.is_nan() || ratio > 1.0) && h > h_min {
            stats.rejected += 1;
            let shrink = if ratio.is_finite() {
                (0.9 / ratio.sqrt().sqrt()).clamp(0.2, 0.9)
            } else {
                0.2
            };
            h = (h * shrink).max(h_min);
            rejected_last = true;
            continue;
        }
        stats.accepted += 1;
        let t_new = t + h;
        if next_t <= t_new {
            let dense = dense_output(n, &y, &y_new, &k, h);
            while next_t <= t_new {
                dense.at(n, (next_t - t) / h, out);
                if visits && !visit(out) {
                    return (false, stats);
                }
                if next >= samples {
                    return (true, stats);
                }
                next += 1;
                next_t = sample_time(next);
            }
        }
        y[..n].copy_from_slice(&y_new[..n]);
        k[0] = k[6];
        t = t_new;
        // Gustafsson's predictive controller: the trend of the last two accepted steps'
        // errors and sizes anticipates a team that speeds up (a contraction), so that the next
        // step is not tried at a size the trend already rules out
        let ratio = ratio.max(1e-12);
        let mut grow = 0.9 / ratio.sqrt().sqrt();
        if let Some((h_prev, ratio_prev)) = last_accepted {
            grow *= (h / h_prev) * (ratio_prev / ratio).sqrt().sqrt();
        }
        let grow = if grow.is_nan() {
            1.0
        } else {
            grow.clamp(0.2, if rejected_last { 1.0 } else { 10.0 })
        };
        last_accepted = Some((h, ratio));
        rejected_last = false;
        h_min = h_floor(&y[..n]);
        h = (h * grow).clamp(h_min, h_max);
    }
}

/// Hairer's dense output coefficients of the step `y → y_new` of size `h`.
#[inline]
fn dense_output(n: usize, y: &Agents, y_new: &Agents, k: &[Agents; 7], h: f64) -> Dense {
    let z = Vec2::zeros();
    let mut r = [[z; MAX_AGENTS]; 5];
    for i in 0..n {
        let diff = y_new[i] - y[i];
        let bspl = k[0][i] * h - diff;
        r[0][i] = y[i];
        r[1][i] = diff;
        r[2][i] = bspl;
        r[3][i] = diff - k[6][i] * h - bspl;
        r[4][i] = (k[0][i] * D1
            + k[2][i] * D3
            + k[3][i] * D4
            + k[4][i] * D5
            + k[5][i] * D6
            + k[6][i] * D7)
            * h;
    }
    Dense { r }
}
