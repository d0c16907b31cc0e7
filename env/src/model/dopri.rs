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
/// `env/tests/integration/integration_step.rs`), a two-hundredth of the camera's position noise
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
struct Dense<const N: usize> {
    r: [[Vec2; N]; 5],
}

impl<const N: usize> Dense<N> {
    #[inline]
    fn at(&self, theta: f64, out: &mut [Vec2]) {
        let t1 = 1.0 - theta;
        let [r1, r2, r3, r4, r5] = &self.r;
        let out = &mut out[..N];
        for i in 0..N {
            out[i] = r1[i] + (r2[i] + (r3[i] + (r4[i] + r5[i] * t1) * theta) * t1) * theta;
        }
    }
}

/// Calls `$f::<N>($args)` with `N` the team size `$n` as a constant, so that every loop over
/// the agents has a known length; `$n` is at most [`MAX_AGENTS`].
macro_rules! for_team_size {
    ($n:expr, $f:ident $args:tt) => {
        for_team_size!(@ $n, $f $args, 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
    };
    (@ $n:expr, $f:ident $args:tt, $($k:literal)*) => {
        match $n {
            $($k => $f::<$k> $args,)*
            _ => unreachable!("at most {MAX_AGENTS} agents"),
        }
    };
}

const _: () = assert!(MAX_AGENTS == 16, "for_team_size! lists the sizes 0 to 16");

/// Solves `ṗ = f(p)` from `start` for `duration` seconds by adaptive Dormand–Prince 5(4) within
/// `budget` and writes the end into `out`. With `visits`, calls `visit` on the sample at every
/// whole `dt` after the start and at the end (the fixed-step integrator's sample instants);
/// stops early and returns false as soon as `visit` returns false (`out` then holds that
/// sample). Without `visits`, only the end is evaluated, bit for bit equal to the last sample
/// with them. Returns the verdict and the work done. Every step is at least `dt / 64` long (`dt`
/// inside `r_min`), so the work is bounded by the duration whatever the velocity field does.
#[inline]
pub fn dp5_solve(
    f: &impl Fn(&[Vec2], &mut [Vec2]),
    start: &[Vec2],
    duration: f64,
    grid: Dp5Grid,
    out: &mut [Vec2],
    visits: bool,
    mut visit: impl FnMut(&[Vec2]) -> bool,
) -> (bool, Dp5Stats) {
    assert!(
        start.len() <= MAX_AGENTS && out.len() == start.len(),
        "at most {MAX_AGENTS} agents"
    );
    for_team_size!(
        start.len(),
        solve_n(f, start, duration, grid, out, visits, &mut visit)
    )
}

/// [`dp5_solve`] for a team of `N`: every loop over the agents has a known length.
#[inline]
fn solve_n<const N: usize>(
    f: &impl Fn(&[Vec2], &mut [Vec2]),
    start: &[Vec2],
    duration: f64,
    grid: Dp5Grid,
    out: &mut [Vec2],
    visits: bool,
    visit: &mut impl FnMut(&[Vec2]) -> bool,
) -> (bool, Dp5Stats) {
    let mut lane = Dp5Lane::<N>::idle();
    if !lane.start(f, start, duration, grid, visits) {
        out.copy_from_slice(start);
        return (true, lane.stats);
    }
    loop {
        for stage in 1..=6 {
            lane.stage(stage, f);
        }
        if let Some(verdict) = lane.conclude(out, visits, visit) {
            return (verdict, lane.stats);
        }
    }
}

/// Motions solved side by side by [`dp5_solve_many`]: two overlap one motion's square roots and
/// divisions with the other's, and keep few motions in flight, since a caller that orders the
/// motions by promise drops the later ones as the first ends come in. Measured on whole trio
/// plans (`benches/examples/trio_plans.rs`, 60 seeds): 1, 2, 3, 4, 6 and 8 lanes gave about
/// 16.2k, 19.4k, 19.2k, 18.6k, 17.5k and 17.1k iterations/s; on quad-square and the five- and
/// six-agent teams (6 seeds) two lanes were 1–3% faster than four.
const LANES: usize = 2;

/// The ends of many motions from one `start`, motion `i` under `fields[i]` for `durations[i]`
/// seconds: the motions are started in the order `order` yields them, each end goes to
/// `done(i, end)` as soon as it is known, and a motion for which `wanted(i)` is false — asked
/// before it starts and after each of its steps — is dropped unfinished. Each end equals
/// [`dp5_solve`]'s without visits bit for bit. Up to [`LANES`] motions advance together, stage
/// by stage (each with its own steps), and a finished or dropped motion's place goes to the
/// next, so the processor overlaps their arithmetic. `order` is pulled only when a lane frees,
/// so `wanted` may change its answers as ends come in. Allocates nothing.
pub fn dp5_solve_many<F: Fn(&[Vec2], &mut [Vec2])>(
    fields: &[F],
    start: &[Vec2],
    durations: &[f64],
    grid: Dp5Grid,
    order: impl IntoIterator<Item = usize>,
    wanted: impl Fn(usize) -> bool,
    mut done: impl FnMut(usize, &[Vec2]),
) {
    assert!(
        start.len() <= MAX_AGENTS && durations.len() == fields.len(),
        "at most {MAX_AGENTS} agents, one duration per field"
    );
    let order = order.into_iter();
    for_team_size!(
        start.len(),
        many_n(fields, start, durations, grid, order, &wanted, &mut done)
    )
}

/// [`dp5_solve_many`] for a team of `N`.
#[inline]
fn many_n<const N: usize>(
    fields: &[impl Fn(&[Vec2], &mut [Vec2])],
    start: &[Vec2],
    durations: &[f64],
    grid: Dp5Grid,
    mut order: impl Iterator<Item = usize>,
    wanted: &impl Fn(usize) -> bool,
    done: &mut impl FnMut(usize, &[Vec2]),
) {
    let mut lanes = [Dp5Lane::<N>::idle(); LANES];
    let mut motion = [0usize; LANES];
    // fills a free lane with the next wanted motion that needs steps; false when none is left
    let mut fill =
        |lane: &mut Dp5Lane<N>, slot: &mut usize, done: &mut dyn FnMut(usize, &[Vec2])| {
            for i in order.by_ref() {
                if !wanted(i) {
                    continue;
                }
                if lane.start(&fields[i], start, durations[i], grid, false) {
                    *slot = i;
                    return true;
                }
                done(i, start);
            }
            false
        };
    let mut busy = 0;
    for l in 0..LANES {
        if fill(&mut lanes[l], &mut motion[l], done) {
            busy = l + 1;
        } else {
            break;
        }
    }
    let mut end = [Vec2::zeros(); N];
    while busy > 0 {
        for stage in 1..=6 {
            for (lane, &i) in lanes[..busy].iter_mut().zip(&motion[..busy]) {
                lane.stage(stage, &fields[i]);
            }
        }
        let mut l = 0;
        while l < busy {
            let i = motion[l];
            let finished = lanes[l].conclude(&mut end, false, &mut |_| true).is_some();
            if finished {
                done(i, &end);
            }
            if (!finished && wanted(i)) || fill(&mut lanes[l], &mut motion[l], done) {
                l += 1;
            } else {
                busy -= 1;
                lanes.swap(l, busy);
                motion.swap(l, busy);
            }
        }
    }
}

/// One adaptive motion in progress: its state, its stages and its step control.
#[derive(Clone, Copy)]
struct Dp5Lane<const N: usize> {
    dt: f64,
    budget: ErrorBudget,
    duration: f64,
    samples: usize,
    next: usize,
    next_t: f64,
    y: [Vec2; N],
    k: [[Vec2; N]; 7],
    s: [Vec2; N],
    y_new: [Vec2; N],
    h: f64,
    h_min: f64,
    t: f64,
    rejected_last: bool,
    last_accepted: Option<(f64, f64)>,
    stats: Dp5Stats,
}

impl<const N: usize> Dp5Lane<N> {
    /// A lane holding no motion.
    fn idle() -> Self {
        let z = [Vec2::zeros(); N];
        Self {
            dt: 0.0,
            budget: ErrorBudget {
                per_bl: 0.0,
                min_speed: 0.0,
                r_min: 0.0,
            },
            duration: 0.0,
            samples: 0,
            next: 0,
            next_t: 0.0,
            y: z,
            k: [z; 7],
            s: z,
            y_new: z,
            h: 0.0,
            h_min: 0.0,
            t: 0.0,
            rejected_last: false,
            last_accepted: None,
            stats: Dp5Stats::default(),
        }
    }

    /// Starts the motion from `start` for `duration`; false (and nothing to solve) when it has
    /// no sample.
    #[inline]
    fn start(
        &mut self,
        f: &impl Fn(&[Vec2], &mut [Vec2]),
        start: &[Vec2],
        duration: f64,
        grid: Dp5Grid,
        visits: bool,
    ) -> bool {
        let (steps, rest) = super::step_schedule(duration, grid.dt);
        let samples = steps + usize::from(rest > 0.0);
        self.stats = Dp5Stats::default();
        if samples == 0 {
            return false;
        }
        self.dt = grid.dt;
        self.budget = grid.budget;
        self.duration = duration;
        self.samples = samples;
        self.next = if visits { 1 } else { samples };
        self.next_t = self.sample_time(self.next);
        self.y.copy_from_slice(start);
        f(&self.y, &mut self.k[0]);
        self.h_min = self.h_floor();
        self.h = grid.dt * FIRST_STEP_DTS;
        self.t = 0.0;
        self.rejected_last = false;
        self.last_accepted = None;
        true
    }

    /// The time of sample `k` (1-based; the last is the end).
    #[inline]
    fn sample_time(&self, k: usize) -> f64 {
        if k >= self.samples {
            self.duration
        } else {
            k as f64 * self.dt
        }
    }

    /// The smallest step from the state `y`: `dt` when two agents are closer than `r_min`.
    #[inline]
    fn h_floor(&self) -> f64 {
        let (y, n) = (&self.y, N);
        let r2 = self.budget.r_min * self.budget.r_min;
        let close = (0..n).any(|i| ((i + 1)..n).any(|j| (y[i] - y[j]).norm_squared() < r2));
        if close {
            self.dt
        } else {
            self.dt * SMALLEST_STEP_DTS
        }
    }

    /// Forms the input of stage `stage` (1–6; the sixth is the fifth-order solution) of the
    /// step of size `h` and evaluates `f` there.
    #[inline]
    #[allow(clippy::needless_range_loop)] // the stage formulas index every array by agent alike
    fn stage(&mut self, stage: usize, f: &impl Fn(&[Vec2], &mut [Vec2])) {
        let (n, h, y) = (N, self.h, &self.y);
        let k = &self.k;
        let s = &mut self.s;
        match stage {
            1 => {
                for i in 0..n {
                    s[i] = y[i] + k[0][i] * (h * A21);
                }
            }
            2 => {
                for i in 0..n {
                    s[i] = y[i] + (k[0][i] * A31 + k[1][i] * A32) * h;
                }
            }
            3 => {
                for i in 0..n {
                    s[i] = y[i] + (k[0][i] * A41 + k[1][i] * A42 + k[2][i] * A43) * h;
                }
            }
            4 => {
                for i in 0..n {
                    s[i] =
                        y[i] + (k[0][i] * A51 + k[1][i] * A52 + k[2][i] * A53 + k[3][i] * A54) * h;
                }
            }
            5 => {
                for i in 0..n {
                    s[i] = y[i]
                        + (k[0][i] * A61
                            + k[1][i] * A62
                            + k[2][i] * A63
                            + k[3][i] * A64
                            + k[4][i] * A65)
                            * h;
                }
            }
            _ => {
                for i in 0..n {
                    self.y_new[i] = y[i]
                        + (k[0][i] * B1
                            + k[2][i] * B3
                            + k[3][i] * B4
                            + k[4][i] * B5
                            + k[5][i] * B6)
                            * h;
                }
                f(&self.y_new, &mut self.k[6]);
                return;
            }
        }
        f(&self.s, &mut self.k[stage]);
    }

    /// Ends the attempted step once its six stages are evaluated: rejects it (and shrinks `h`)
    /// or accepts it, visits the samples it contains and picks the next step. Returns the
    /// motion's verdict once it ends (the end or the stopping sample in `out`), else `None`.
    #[inline]
    #[allow(clippy::needless_range_loop)] // the error formulas index every array by agent alike
    fn conclude(
        &mut self,
        out: &mut [Vec2],
        visits: bool,
        visit: &mut impl FnMut(&[Vec2]) -> bool,
    ) -> Option<bool> {
        let (n, h) = (N, self.h);
        let (k, y, y_new) = (&self.k, &self.y, &self.y_new);
        // squared norms, one square root for the ratio
        let mut err2: f64 = 0.0;
        for i in 0..n {
            let e = (k[0][i] * E1
                + k[2][i] * E3
                + k[3][i] * E4
                + k[4][i] * E5
                + k[5][i] * E6
                + k[6][i] * E7)
                * h;
            let e2 = e.norm_squared();
            err2 = if e2.is_nan() || e2 > err2 { e2 } else { err2 };
        }
        let mut mean = Vec2::zeros();
        for i in 0..n {
            mean += y_new[i] - y[i];
        }
        mean /= n as f64;
        let slowest = self.budget.min_speed * h;
        let mut moved2 = slowest * slowest;
        for i in 0..n {
            moved2 = moved2.max((y_new[i] - y[i] - mean).norm_squared());
        }
        let ratio = (err2 / moved2).sqrt() / self.budget.per_bl;
        if (ratio.is_nan() || ratio > 1.0) && h > self.h_min {
            self.stats.rejected += 1;
            let shrink = if ratio.is_finite() {
                (0.9 / ratio.sqrt().sqrt()).clamp(0.2, 0.9)
            } else {
                0.2
            };
            self.h = (h * shrink).max(self.h_min);
            self.rejected_last = true;
            return None;
        }
        self.stats.accepted += 1;
        let t_new = self.t + h;
        if self.next_t <= t_new {
            let dense = dense_output(y, y_new, k, h);
            while self.next_t <= t_new {
                dense.at((self.next_t - self.t) / h, out);
                if visits && !visit(out) {
                    return Some(false);
                }
                if self.next >= self.samples {
                    return Some(true);
                }
                self.next += 1;
                self.next_t = self.sample_time(self.next);
            }
        }
        self.y = self.y_new;
        self.k[0] = self.k[6];
        self.t = t_new;
        // Gustafsson's predictive controller: the trend of the last two accepted steps'
        // errors and sizes anticipates a team that speeds up (a contraction), so that the next
        // step is not tried at a size the trend already rules out
        let ratio = ratio.max(1e-12);
        let mut grow = 0.9 / ratio.sqrt().sqrt();
        if let Some((h_prev, ratio_prev)) = self.last_accepted {
            grow *= (h / h_prev) * (ratio_prev / ratio).sqrt().sqrt();
        }
        let grow = if grow.is_nan() {
            1.0
        } else {
            grow.clamp(0.2, if self.rejected_last { 1.0 } else { 10.0 })
        };
        self.last_accepted = Some((h, ratio));
        self.rejected_last = false;
        self.h_min = self.h_floor();
        self.h = (h * grow).clamp(self.h_min, REFERENCE_DURATION_S);
        None
    }
}

/// Hairer's dense output coefficients of the step `y → y_new` of size `h`.
#[inline]
fn dense_output<const N: usize>(
    y: &[Vec2; N],
    y_new: &[Vec2; N],
    k: &[[Vec2; N]; 7],
    h: f64,
) -> Dense<N> {
    let mut r = [[Vec2::zeros(); N]; 5];
    for i in 0..N {
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
