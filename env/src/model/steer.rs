//! Steering a nominal pair: constant commands, each held a whole number of control periods,
//! that carry two agents exactly onto a target state (docs/steering.md).
//!
//! Along one orbit of the exact flow ([`super::pair_flow::Orbit`]) the folded field angle `ψ̂`
//! falls from `ψ̂₀` to `ψ̂₁`, the pair turns by `Δφ = σ(ψ̂₀ − ψ̂₁)`, the separation keeps
//! `r / (sin ψ̂ √cos ψ̂)` and the time is `t = C⁵ (G(ψ̂₀) − G(ψ̂₁)) / 2κ`. So one orbit reaches a
//! relative target `(r₁, φ₀ + Δφ)` with `|Δφ| < π/2` from `(r₀, φ₀)` for exactly one `ψ̂₀`:
//! `ln f(ψ̂₀ − |Δφ|) − ln f(ψ̂₀) = ln(r₁/r₀)` with `f = sin √cos`, strictly increasing in
//! `ψ̂₀` ([`orbit_steer`], a safeguarded Newton solve). Its time is a real number, but an edge
//! lasts whole control periods, so [`steer_pair`] splits the relative move into `n ≥ 2` orbits
//! through waypoints, rounds each duration, and makes the last two exact: the field angle of
//! the second-to-last edge is found (a bracketed 1-D root find) so that the last orbit's time
//! from where it ends is a whole number of periods. When the centre of mass needs longer for its
//! shift than the relative move takes, the waypoints make a radial detour out and back (or in
//! and back) that lasts as long as the shift. The centre of mass moves at the pull
//! velocity, affine in the gradient command for a given field angle, so the gradients that
//! carry it onto the target's centre over the edges' total time follow in closed form, within
//! the coil's limits or not at all.

use std::f64::consts::{FRAC_PI_2, PI, SQRT_2, TAU};

use super::PlanningModel;
use super::pair_flow::{g, g_complement};
use crate::coil::Control;
use crate::math::{Vec2, wrap_angle};

/// One orbit that reaches a relative target: the field angle from the separation and the time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitSteer {
    /// Field angle from the separation at the start, `ψ₀ = θ_B − φ₀` (rad, in `[−π/2, π/2]`).
    pub psi: f64,
    /// The time the orbit takes to reach the target (s).
    pub time: f64,
}

/// The one orbit from separation `r0` to separation `r1` with the separation turning by
/// `dphi` (rad), under relative-motion constant `kappa`: `None` unless `|dphi| < π/2` and the
/// numbers are finite and positive. The field angle `θ_B = φ₀ + psi` and `θ_B + π` both follow
/// it.
pub fn orbit_steer(kappa: f64, r0: f64, r1: f64, dphi: f64) -> Option<OrbitSteer> {
    let finite = kappa.is_finite() && r0.is_finite() && r1.is_finite() && dphi.is_finite();
    if !(finite && kappa > 0.0 && r0 > 0.0 && r1 > 0.0) {
        return None;
    }
    let d = dphi.abs();
    if d >= FRAC_PI_2 {
        return None;
    }
    let (r05, r15) = (r0.powi(5), r1.powi(5));
    if d < RADIAL_TURN {
        // along the separation: collapse at ψ = 0 (r⁵ = r₀⁵ − 10κt), repulsion at ψ = π/2
        // (r⁵ = r₀⁵ + 5κt)
        return Some(if r1 <= r0 {
            OrbitSteer {
                psi: 0.0,
                time: (r05 - r15) / (10.0 * kappa),
            }
        } else {
            OrbitSteer {
                psi: FRAC_PI_2,
                time: (r15 - r05) / (5.0 * kappa),
            }
        });
    }
    let target = (r1 / r0).ln();
    let residual = |a: f64| {
        let (sb, cb) = (a - d).sin_cos();
        let (sa, ca) = a.sin_cos();
        // ln f(b) − ln f(a) as one logarithm; the slope of ln f is cot − ½ tan
        let ratio = (sb / sa) * (cb / ca).sqrt();
        let slope = |s: f64, c: f64| c / s - 0.5 * s / c;
        (ratio.ln() - target, slope(sb, cb) - slope(sa, ca))
    };
    // small-turn guess: (ln f)'(ψ̂₀ − d/2) = −ln(r₁/r₀)/d, i.e. tan² + 2k tan − 2 = 0
    let k = -target / d;
    let guess = (((k * k + 2.0).sqrt() - k).atan() + 0.5 * d).clamp(d, FRAC_PI_2);
    let a = newton_in(residual, d, FRAC_PI_2, guess);
    let b = a - d;
    let (sa, ca, sb, cb) = (a.sin(), a.cos(), b.sin(), b.cos());
    let dg = if a <= FRAC_PI_2 / 2.0 {
        g(sa, ca) - g(sb, cb)
    } else {
        g_complement(sb, cb) - g_complement(sa, ca)
    };
    let c = r0 / (sa * ca.sqrt());
    let time = c.powi(5) * dg / (2.0 * kappa);
    time.is_finite().then_some(OrbitSteer {
        psi: dphi.signum() * a,
        time,
    })
}

/// A turn below this (rad) is steered along the separation itself.
const RADIAL_TURN: f64 = 1e-12;

/// The root in `(lo, hi)` of an increasing function given with its derivative, negative near
/// `lo` and positive near `hi`: Newton steps from `guess`, bisection whenever a step leaves the
/// bracket.
fn newton_in(f: impl Fn(f64) -> (f64, f64), mut lo: f64, mut hi: f64, guess: f64) -> f64 {
    let mut x = if guess > lo && guess < hi {
        guess
    } else {
        0.5 * (lo + hi)
    };
    for _ in 0..100 {
        let (v, dv) = f(x);
        if v == 0.0 {
            return x;
        }
        if v < 0.0 || v.is_nan() && x - lo < hi - x {
            lo = x;
        } else {
            hi = x;
        }
        let step = v / dv;
        if step.abs() <= 4.0 * f64::EPSILON * x.abs() {
            return x - step;
        }
        let newton = x - step;
        x = if newton > lo && newton < hi && newton.is_finite() {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if hi - lo <= 4.0 * f64::EPSILON * hi {
            return x;
        }
    }
    x
}

/// The root of `f` between `a` and `b`, where `f` changes sign (`fa`, `fb` its values there),
/// by the Illinois variant of regula falsi, to `xtol`.
fn illinois(
    mut f: impl FnMut(f64) -> Option<f64>,
    mut a: f64,
    mut b: f64,
    mut fa: f64,
    mut fb: f64,
    xtol: f64,
) -> Option<f64> {
    let mut side = 0i8;
    for _ in 0..100 {
        let x = if fa != fb {
            (a * fb - b * fa) / (fb - fa)
        } else {
            0.5 * (a + b)
        };
        let fx = f(x)?;
        if fx == 0.0 || (b - a).abs() <= xtol {
            return Some(x);
        }
        if fx.signum() == fb.signum() {
            b = x;
            fb = fx;
            if side == -1 {
                fa *= 0.5;
            }
            side = -1;
        } else {
            a = x;
            fa = fx;
            if side == 1 {
                fb *= 0.5;
            }
            side = 1;
        }
        if (b - a).abs() <= xtol {
            return Some(0.5 * (a + b));
        }
    }
    Some(0.5 * (a + b))
}

/// The bounds a steer must keep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteerLimits {
    /// Every edge lasts a whole number of these (s): the control period.
    pub period: f64,
    /// The longest edge, in periods (at least 1).
    pub max_periods: u32,
    /// The open proximity range `(r_min, r_max)` the separation keeps throughout (BL).
    pub separation: [f64; 2],
    /// The largest miss accepted: every agent ends within this of its target (BL).
    pub tolerance: f64,
}

/// One edge of a steer: a constant command held for whole control periods.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteerEdge {
    /// The command (planar, gradients within the coil's limits).
    pub control: Control,
    /// Its duration in control periods (≥ 1).
    pub periods: u32,
}

/// A pair's state by its centre, separation and heading.
#[derive(Debug, Clone, Copy)]
struct Shape {
    rel: Vec2,
    r: f64,
    phi: f64,
}

impl Shape {
    fn of(rel: Vec2) -> Self {
        Shape {
            rel,
            r: rel.norm(),
            phi: rel.y.atan2(rel.x),
        }
    }

    fn polar(r: f64, phi: f64) -> Self {
        Shape::of(Vec2::new(r * phi.cos(), r * phi.sin()))
    }
}

/// The relative motion of the steer under construction.
struct Relative<'a> {
    model: &'a PlanningModel,
    limits: &'a SteerLimits,
    kappa: f64,
    /// The centre of mass's shift over the steer (BL).
    shift: Vec2,
    /// [`PullBound`], when the coil has its form.
    pull: Option<PullBound>,
}

/// Why [`Relative::solve`] has no edges.
enum Unsolved {
    /// No edges within the limits.
    Failed,
    /// The edges would last this many periods in all, too short for the pull to carry the
    /// centre of mass its shift whatever their field angles: no gradients exist.
    TooSlow(u32),
}

/// The centre of mass's velocity at zero gradient and its largest change per axis under the
/// largest gradient along that axis, at any field angle, for a coil whose pull per gradient
/// is `(G_x cos θ_B, G_y sin θ_B)` (the tri-axial coil): the drift is the same at every angle and
/// axis `x` moves fastest at `θ_B = 0`, axis `y` at `θ_B = π/2`.
#[derive(Debug, Clone, Copy)]
struct PullBound {
    drift: Vec2,
    reach: [f64; 2],
}

impl PullBound {
    /// The bound at `from`; `None` unless the coil's pull, sampled at a third angle, has the
    /// tri-axial form.
    fn of(model: &PlanningModel, from: &[Vec2]) -> Option<Self> {
        let limit = model.coil.gradient_limit();
        let mut v = [Vec2::zeros(); 2];
        let mut centre = |theta: f64, gx: f64, gy: f64| {
            model.velocities(from, &Control::planar(theta, gx, gy), &mut v);
            (v[0] + v[1]) * 0.5
        };
        let drift = centre(0.0, 0.0, 0.0);
        let x = centre(0.0, limit, 0.0) - drift;
        let y = centre(FRAC_PI_2, 0.0, limit) - centre(FRAC_PI_2, 0.0, 0.0);
        const PROBE: f64 = 0.3;
        let (sp, cp) = PROBE.sin_cos();
        let d = centre(PROBE, 0.0, 0.0);
        let px = centre(PROBE, limit, 0.0) - d;
        let py = centre(PROBE, 0.0, limit) - d;
        let near = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs().max(f64::MIN_POSITIVE);
        let shaped = (d - drift).norm() <= 1e-9 * drift.norm().max(x.norm())
            && near(px.x, x.x * cp)
            && near(py.y, y.y * sp)
            && px.y.abs() <= 1e-9 * x.norm()
            && py.x.abs() <= 1e-9 * y.norm();
        (shaped && x.x.is_finite() && y.y.is_finite()).then_some(PullBound {
            drift,
            reach: [x.x.abs(), y.y.abs()],
        })
    }

    /// Whether no gradients within the limits carry the centre by `shift` over `periods`
    /// periods of `period` seconds, at any field angles (with a margin of 1e-6 for rounding).
    fn too_slow(&self, shift: Vec2, periods: u32, period: f64) -> bool {
        let t = periods as f64 * period;
        let rest = shift - self.drift * t;
        let margin = 1.0 + 1e-6;
        rest.x.abs() > t * self.reach[0] * margin || rest.y.abs() > t * self.reach[1] * margin
    }
}

impl Relative<'_> {
    /// Where the separation `from` goes under field angle `theta` for `periods`, if it stays in
    /// the proximity range.
    fn end(&self, from: &Shape, theta: f64, periods: u32) -> Option<Shape> {
        let half = from.rel * 0.5;
        let edge = self
            .model
            .pair_edge(&[-half, half], &Control::planar(theta, 0.0, 0.0))?;
        let mut out = [Vec2::zeros(); 2];
        let (lo, hi) = edge.end_and_range(periods as f64 * self.limits.period, &mut out);
        let [r_min, r_max] = self.limits.separation;
        (lo > r_min && hi < r_max).then(|| Shape::of(out[1] - out[0]))
    }

    /// The orbit from `from` to `to`.
    fn orbit(&self, from: &Shape, to: &Shape) -> Option<OrbitSteer> {
        orbit_steer(self.kappa, from.r, to.r, wrap_angle(to.phi - from.phi))
    }

    /// The orbit from `from` toward `to`, its time rounded to whole periods: (θ_B, periods).
    fn rounded(&self, from: &Shape, to: &Shape) -> Option<(f64, u32)> {
        let o = self.orbit(from, to)?;
        let periods = self.periods(o.time)?;
        Some((from.phi + o.psi, periods))
    }

    /// A time in whole periods (at least one), if within the longest edge.
    fn periods(&self, time: f64) -> Option<u32> {
        let p = (time / self.limits.period).round().max(1.0);
        (p <= self.limits.max_periods as f64).then_some(p as u32)
    }

    /// The waypoint at fraction `f` of a relative move from `from` to `to` turning by `turn`:
    /// the separation interpolated linearly in `r⁵` and scaled by `scale`, or by `scale` raised
    /// to the tent of `detour`, kept 5% of the proximity range inside it.
    fn waypoint(
        &self,
        from: &Shape,
        to: &Shape,
        turn: f64,
        f: f64,
        (scale, detour): (f64, Option<Detour>),
    ) -> Shape {
        let [r_min, r_max] = self.limits.separation;
        let (r0, r1) = (from.r.powi(5), to.r.powi(5));
        let lift = detour.map_or(1.0, |d| d.tent(f));
        let r = ((r0 + f * (r1 - r0)).powf(0.2) * scale.powf(lift)).clamp(
            r_min + 0.05 * (r_max - r_min),
            r_max - 0.05 * (r_max - r_min),
        );
        Shape::polar(r, from.phi + turn * f)
    }

    /// At least `n`, and enough edges that the orbits through `n` waypoints, which last `T` in
    /// all, fit in edges of 80% of the longest edge: `max(n, ⌈T / 0.8 t_max⌉)`, or `n` when an
    /// orbit has no solution. The time of turning grows with `r⁵`, so a wide pair turning even
    /// a little needs more edges than its turn alone asks for.
    fn timed_edges(
        &self,
        from: &Shape,
        to: &Shape,
        turn: f64,
        n: usize,
        start: (f64, Option<Detour>),
    ) -> usize {
        let mut time = 0.0;
        let mut at = *from;
        for k in 1..=n {
            let next = self.waypoint(from, to, turn, k as f64 / n as f64, start);
            let Some(o) = self.orbit(&at, &next) else {
                return n;
            };
            time += o.time;
            at = next;
        }
        let edge_time = self.limits.max_periods as f64 * self.limits.period;
        n.max((time / (0.8 * edge_time)).ceil() as usize)
    }

    /// The relative part of a steer through `n ≥ 2` orbits turning by `turn` in all: the field
    /// angles and periods of every edge. The waypoints' separations are interpolated linearly
    /// in `r⁵` (a radial orbit's time is proportional to the change of `r⁵`, so each edge gets
    /// an equal share of it) and scaled by `scale`, or by `scale` raised to the tent of
    /// `detour` when one is given. `final_try`: no wider steer is tried after this one, so edges too
    /// quick for the pull are [`Unsolved::Failed`] without a bracket.
    fn solve(
        &self,
        from: &Shape,
        to: &Shape,
        turn: f64,
        n: usize,
        (scale, detour): (f64, Option<Detour>),
        final_try: bool,
    ) -> Result<Vec<(f64, u32)>, Unsolved> {
        let waypoint =
            |k: usize| self.waypoint(from, to, turn, k as f64 / n as f64, (scale, detour));
        let mut edges = Vec::with_capacity(n);
        let mut at = *from;
        for k in 1..n - 1 {
            let (theta, periods) = self.rounded(&at, &waypoint(k)).ok_or(Unsolved::Failed)?;
            at = self.end(&at, theta, periods).ok_or(Unsolved::Failed)?;
            edges.push((theta, periods));
        }
        let mid = waypoint(n - 1);
        let (theta0, first) = self.rounded(&at, &mid).ok_or(Unsolved::Failed)?;
        let nominal = self.orbit(&mid, to).ok_or(Unsolved::Failed)?.time / self.limits.period;
        let base = nominal.round().max(1.0) as u32;
        // every edge's duration is known but the last's
        let before: u32 = edges.iter().map(|e| e.1).sum::<u32>() + first;
        let too_slow = |last: u32| {
            self.pull
                .is_some_and(|p| p.too_slow(self.shift, before + last, self.limits.period))
        };
        let within = |last: u32| last <= self.limits.max_periods;
        if final_try
            && [base, base + 1]
                .into_iter()
                .all(|l| !within(l) || too_slow(l))
        {
            // whatever the brackets find, the gradients fail and nothing is tried after this
            return Err(Unsolved::Failed);
        }
        // by the field angle of the second-to-last edge: where it ends and the last orbit from
        // there (both brackets step through the same angles, and the root was evaluated last)
        let mut seen: Vec<(u64, Option<(Shape, OrbitSteer)>)> = Vec::with_capacity(64);
        let mut last_orbit = |theta: f64| {
            let key = theta.to_bits();
            if let Some(&(_, known)) = seen.iter().find(|e| e.0 == key) {
                return known;
            }
            let found = self
                .end(&at, theta, first)
                .and_then(|m| Some((m, self.orbit(&m, to)?)));
            seen.push((key, found));
            found
        };
        for last in [base, base + 1] {
            if last == 0 || last > self.limits.max_periods {
                continue;
            }
            let time = last as f64 * self.limits.period;
            let miss = |theta: f64| Some(last_orbit(theta)?.1.time - time);
            // when the pull cannot carry the centre its shift in this time, no field angles
            // give gradients: whether a root exists is all that matters, not where it is
            let slow = too_slow(last);
            let Some(theta) = bracket_root(miss, theta0, !slow) else {
                continue;
            };
            if slow {
                return Err(Unsolved::TooSlow(before + last));
            }
            let (m, o) = last_orbit(theta).ok_or(Unsolved::Failed)?;
            let theta_last = m.phi + o.psi;
            self.end(&m, theta_last, last).ok_or(Unsolved::Failed)?;
            edges.push((theta, first));
            edges.push((theta_last, last));
            return Ok(edges);
        }
        Err(Unsolved::Failed)
    }
}

/// A root of `f` near `x0`: the nearest sign change on a grid stepping outward from `x0`,
/// refined by [`illinois`] if `refine` (otherwise the grid point that closes the bracket).
fn bracket_root(mut f: impl FnMut(f64) -> Option<f64>, x0: f64, refine: bool) -> Option<f64> {
    const STEP: f64 = 0.025;
    const STEPS: usize = 10;
    let f0 = f(x0);
    if f0 == Some(0.0) {
        return Some(x0);
    }
    let mut prev = [(x0, f0), (x0, f0)];
    for k in 1..=STEPS {
        for (side, dir) in [(0, 1.0), (1, -1.0)] {
            let x = x0 + dir * STEP * k as f64;
            let fx = f(x);
            if let ((xp, Some(fp)), Some(v)) = (prev[side], fx)
                && fp.signum() != v.signum()
            {
                if !refine {
                    return Some(x);
                }
                let (a, b, fa, fb) = if xp < x {
                    (xp, x, fp, v)
                } else {
                    (x, xp, v, fp)
                };
                if let Some(root) = illinois(&mut f, a, b, fa, fb, 1e-15) {
                    return Some(root);
                }
            }
            prev[side] = (x, fx);
        }
    }
    None
}

/// Gradient commands for edges with field angles and periods `rel`, so that the centre of
/// mass of the pair at `from` moves by `shift` over them; `None` beyond the coil's limits.
fn gradients(
    model: &PlanningModel,
    from: &[Vec2],
    rel: &[(f64, u32)],
    period: f64,
    shift: Vec2,
) -> Option<Vec<Control>> {
    let limit = model.coil.gradient_limit();
    let mut v = [Vec2::zeros(); 2];
    let mut centre = |u: Control| {
        model.velocities(from, &u, &mut v);
        (v[0] + v[1]) * 0.5
    };
    // per edge: drift (zero gradient) and the velocity per full gradient along each axis
    let maps: Vec<(Vec2, Vec2, Vec2, f64)> = rel
        .iter()
        .map(|&(theta, p)| {
            let base = centre(Control::planar(theta, 0.0, 0.0));
            let x = centre(Control::planar(theta, limit, 0.0)) - base;
            let y = centre(Control::planar(theta, 0.0, limit)) - base;
            (base, x, y, p as f64 * period)
        })
        .collect();
    let mut rest = shift;
    for &(base, _, _, t) in &maps {
        rest -= base * t;
    }
    let diagonal = maps
        .iter()
        .all(|(_, x, y, _)| x.y.abs() <= 1e-12 * x.norm() && y.x.abs() <= 1e-12 * y.norm());
    let grads: Vec<[f64; 2]> = if diagonal {
        // each axis: the same fraction of the largest displacement on every edge
        let reach = |axis: usize| -> f64 {
            maps.iter()
                .map(|(_, x, y, t)| t * if axis == 0 { x.x.abs() } else { y.y.abs() })
                .sum()
        };
        let fraction = |axis: usize| {
            let want = rest[axis];
            let can = reach(axis);
            if want == 0.0 {
                Some(0.0)
            } else {
                let s = want / can;
                (s.is_finite() && s.abs() <= 1.0).then_some(s)
            }
        };
        let (sx, sy) = (fraction(0)?, fraction(1)?);
        maps.iter()
            .map(|(_, x, y, _)| [sx * limit * x.x.signum(), sy * limit * y.y.signum()])
            .collect()
    } else {
        // one velocity throughout, each edge's gradients from its 2×2 map
        let total: f64 = maps.iter().map(|m| m.3).sum();
        let want = rest / total;
        let mut out = Vec::with_capacity(maps.len());
        for (_, x, y, _) in &maps {
            let det = x.x * y.y - x.y * y.x;
            let gx = (want.x * y.y - want.y * y.x) / det;
            let gy = (x.x * want.y - x.y * want.x) / det;
            if !(gx.is_finite() && gy.is_finite() && gx.abs() <= 1.0 && gy.abs() <= 1.0) {
                return None;
            }
            out.push([gx * limit, gy * limit]);
        }
        out
    };
    Some(
        rel.iter()
            .zip(grads)
            .map(|(&(theta, _), [gx, gy])| Control::planar(wrap_angle(theta), gx, gy))
            .collect(),
    )
}

/// Constant planar commands, each held whole control periods, that carry the pair `from`
/// onto `to` (two agents each, matched in order) within `limits`; `accept` is asked about each
/// solution found (in order of fewer edges and closer waypoints) and the first it accepts is returned. `None` when no solution it tries
/// exists within the limits, or `accept` refuses them all, or the model has no exact flow for
/// the pair. Every returned steer, propagated by `model` from `from`, ends within
/// `limits.tolerance` of `to` and keeps the separation in range.
pub fn steer_pair(
    model: &PlanningModel,
    from: &[Vec2],
    to: &[Vec2],
    limits: &SteerLimits,
    mut accept: impl FnMut(&[SteerEdge]) -> bool,
) -> Option<Vec<SteerEdge>> {
    if from.len() != 2
        || to.len() != 2
        || limits.max_periods == 0
        || limits.period.is_nan()
        || limits.period <= 0.0
    {
        return None;
    }
    let kappa = model
        .pair_edge(from, &Control::planar(0.0, 0.0, 0.0))?
        .orbit()
        .kappa();
    let (a, b) = (Shape::of(from[1] - from[0]), Shape::of(to[1] - to[0]));
    let [r_min, r_max] = limits.separation;
    if !(a.r > r_min && a.r < r_max && b.r > r_min && b.r < r_max) {
        return None;
    }
    let shift = (to[0] + to[1] - from[0] - from[1]) * 0.5;
    let rel = Relative {
        model,
        limits,
        kappa,
        shift,
        pull: PullBound::of(model, from),
    };
    let needed = shift.norm() / pull_speed(model, from);
    // the slowest axis's time at its fastest pull: what a detour must last
    let axis_needed = rel.pull.map_or(needed * SQRT_2, |p| {
        (shift.x.abs() / p.reach[0]).max(shift.y.abs() / p.reach[1])
    });
    // too fast for the pull: slow the orbits by widening the pair (t ∝ r⁵), or lengthen
    // a detour's excursion in proportion
    let widen = |scale: f64, detour: Option<Detour>, periods: u32| {
        let time = periods as f64 * limits.period;
        let factor = (needed / time).max(1.0);
        match detour {
            None => scale * factor.powf(0.2) * 1.05,
            Some(_) => Detour::stretch(scale, factor * 1.1),
        }
    };
    // a radial orbit's time per unit change of r⁵: 1/10κ inward, 1/5κ outward
    let radial_time = |r0: f64, r1: f64| {
        let rate = if r1 > r0 { 5.0 } else { 10.0 } * kappa;
        (r1.powi(5) - r0.powi(5)).abs() / rate
    };
    let turn = wrap_angle(b.phi - a.phi);
    let mut turns = vec![turn];
    if turn.abs() > 2.0 * PI / 3.0 {
        turns.push(turn - TAU * turn.signum());
    }
    for &turn in &turns {
        // enough edges to turn in short orbits, and to give the pull time for the shift
        let edge_time = limits.max_periods as f64 * limits.period;
        let fewest = ((turn.abs() / EDGE_TURN).ceil() as usize)
            .max((needed / (0.8 * edge_time)).ceil() as usize)
            .max((radial_time(a.r, b.r) / (0.8 * edge_time)).ceil() as usize + 1)
            .max(2);
        if fewest > MAX_EDGES {
            continue;
        }
        // detours for a shift that outlasts the relative move: out and back (the pull acts
        // along the separation's normal while the pair repels) or in and back
        let r5 = a.r.min(b.r).powi(5);
        let mut starts: Vec<(f64, Option<Detour>)> = SCALES.map(|s| (s, None)).to_vec();
        starts.push((
            Detour::Out.start(axis_needed * kappa / r5),
            Some(Detour::Out),
        ));
        let dip = Detour::In.start(needed * kappa / r5);
        if dip > 0.0 {
            starts.push((dip, Some(Detour::In)));
        }
        let timed: Vec<usize> = starts
            .iter()
            .map(|&start| rel.timed_edges(&a, &b, turn, fewest, start))
            .collect();
        for extra in [0, 2] {
            for (&(first_scale, detour), &timed) in starts.iter().zip(&timed) {
                let n = timed + extra;
                if n > MAX_EDGES {
                    continue;
                }
                let mut scale = first_scale;
                for attempt in 0..WIDENINGS {
                    let final_try = attempt + 1 == WIDENINGS;
                    let edges = match rel.solve(&a, &b, turn, n, (scale, detour), final_try) {
                        Ok(edges) => edges,
                        Err(Unsolved::TooSlow(periods)) => {
                            scale = widen(scale, detour, periods);
                            continue;
                        }
                        Err(Unsolved::Failed) => break,
                    };
                    let Some(controls) = gradients(model, from, &edges, limits.period, shift)
                    else {
                        scale = match detour {
                            None => widen(scale, None, edges.iter().map(|e| e.1).sum()),
                            Some(_) => Detour::stretch(scale, DETOUR_STRETCH),
                        };
                        continue;
                    };
                    let steer: Vec<SteerEdge> = controls
                        .into_iter()
                        .zip(&edges)
                        .map(|(control, &(_, periods))| SteerEdge { control, periods })
                        .collect();
                    if lands(model, from, to, limits, &steer) && accept(&steer) {
                        return Some(steer);
                    }
                    break;
                }
            }
        }
    }
    None
}

/// A radial excursion of the waypoints for a shift that outlasts the relative move: the
/// separations rise to `scale` times their interpolated value ([`Detour::Out`]) or fall to it
/// ([`Detour::In`]) at a peak and come back, linearly in the waypoints' fraction. The peak sits
/// where the outward and inward legs take equal shares of time: a radial orbit outward takes
/// twice as long as inward for the same change of `r⁵`.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Detour {
    /// Repel first, then attract: the peak at 2/3 of the waypoints.
    Out,
    /// Attract first, then repel: the peak at 1/3.
    In,
}

/// How much longer a detour's excursion gets when its gradients fail.
const DETOUR_STRETCH: f64 = 1.5;

impl Detour {
    /// The waypoints' fraction at the peak.
    fn peak(self) -> f64 {
        match self {
            Detour::Out => 2.0 / 3.0,
            Detour::In => 1.0 / 3.0,
        }
    }

    /// The exponent of the scale at waypoint fraction `f`: 0 at the ends, 1 at the peak.
    fn tent(self, f: f64) -> f64 {
        let p = self.peak();
        if f <= p { f / p } else { (1.0 - f) / (1.0 - p) }
    }

    /// The first scale of this detour for a shift that needs `time · κ / r⁵` (with `r` the
    /// smaller end separation): an out-and-back radial excursion lasts `0.3 |s⁵ − 1| r⁵ / κ`
    /// (1/5κ out, 1/10κ back per unit of `r⁵`), so `s⁵ = 1 ± time κ / (0.3 r⁵)`, with a 50%
    /// margin outward (`time` is then the slowest axis's, and only the repelling legs pull
    /// along the separation's normal) and 10% inward.
    fn start(self, time_kappa_r5: f64) -> f64 {
        let excursion = time_kappa_r5 / 0.3;
        let s5 = match self {
            Detour::Out => 1.0 + 1.5 * excursion,
            Detour::In => 1.0 - 1.1 * excursion,
        };
        s5.max(0.0).powf(0.2)
    }

    /// A peak scale whose excursion `|scale⁵ − 1|` is `factor` times longer.
    fn stretch(scale: f64, factor: f64) -> f64 {
        (1.0 + (scale.powi(5) - 1.0) * factor).max(0.0).powf(0.2)
    }
}

/// The turn planned for one orbit at most (rad). An orbit's time grows steeply with its turn
/// (at 2 BL, 60° takes 14 s and 36° 1.7 s under the default preset), so several short turns
/// are faster than one long one.
const EDGE_TURN: f64 = 0.4;

/// Steers solved per candidate: the first and up to two with the waypoints widened.
const WIDENINGS: usize = 3;

/// The most edges a steer plans.
const MAX_EDGES: usize = 24;

/// Scales of the waypoints' separations tried in turn: turning is fastest with the pair close
/// (`t ∝ r⁵`); the waypoints stay 5% of the proximity range inside it.
const SCALES: [f64; 2] = [0.7, 1.0];

/// The centre of mass's speed (BL/s) under the largest gradient along both axes at 45°: a
/// scale for how long a shift takes.
fn pull_speed(model: &PlanningModel, from: &[Vec2]) -> f64 {
    let limit = model.coil.gradient_limit();
    let mut v = [Vec2::zeros(); 2];
    model.velocities(from, &Control::planar(PI / 4.0, limit, limit), &mut v);
    ((v[0] + v[1]) * 0.5).norm().max(f64::MIN_POSITIVE)
}

/// Whether `steer`, propagated from `from`, keeps the separation in range and ends within the
/// tolerance of `to`.
fn lands(
    model: &PlanningModel,
    from: &[Vec2],
    to: &[Vec2],
    limits: &SteerLimits,
    steer: &[SteerEdge],
) -> bool {
    let [r_min, r_max] = limits.separation;
    let mut at = [from[0], from[1]];
    for e in steer {
        let Some(edge) = model.pair_edge(&at, &e.control) else {
            return false;
        };
        let mut out = [Vec2::zeros(); 2];
        let (lo, hi) = edge.end_and_range(e.periods as f64 * limits.period, &mut out);
        if !(lo > r_min && hi < r_max) {
            return false;
        }
        at = out;
    }
    at.iter()
        .zip(to)
        .all(|(p, q)| (p - q).norm() <= limits.tolerance)
}

#[cfg(test)]
#[path = "steer_tests.rs"]
mod tests;
