//! One edge of a nominal pair: its exact motion, and what a checker needs to know about it.

use super::orbit::{Orbit, OrbitPoint};
use crate::math::Vec2;

/// What bounds the agents' speed at one time of a [`PairEdge`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedSummary {
    /// `√(1 − 2cos²ψ + 5cos⁴ψ)`: the relative speed in units of `κ/r⁴`.
    pub shape: f64,
    /// The separation (BL).
    pub separation: f64,
}

/// What every edge from one start shares, whatever the command: the positions, their centre
/// and the separation (for evaluating many commands from one state, as the OBC does).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairStart {
    start: [Vec2; 2],
    centre: Vec2,
    rel: Vec2,
    r0: f64,
    heading: Vec2,
}

impl PairStart {
    /// The start of two agents; `None` when they coincide or a coordinate is not finite.
    pub fn new(start: &[Vec2]) -> Option<Self> {
        let rel = start[1] - start[0];
        let r0 = rel.norm();
        if !(r0 > 0.0 && r0.is_finite()) {
            return None;
        }
        Some(PairStart {
            start: [start[0], start[1]],
            centre: (start[0] + start[1]) * 0.5,
            rel,
            r0,
            heading: Vec2::new(rel.x / r0, rel.y / r0),
        })
    }

    /// The centre of mass of the start.
    #[inline]
    pub fn centre(&self) -> Vec2 {
        self.centre
    }

    /// The edge from this start under in-plane unit field direction `field`, with
    /// relative-motion constant `kappa` and centre-of-mass velocity `velocity`; `None` when a
    /// number is not finite or `kappa` not positive.
    #[inline]
    pub fn edge(&self, kappa: f64, velocity: Vec2, field: Vec2) -> Option<PairEdge> {
        let finite = velocity.x.is_finite() && velocity.y.is_finite();
        if !(finite && kappa > 0.0 && field.x.is_finite() && field.y.is_finite()) {
            return None;
        }
        let (rx, ry) = (self.heading.x, self.heading.y);
        // ψ = θ_B − φ: cos ψ = b̂·r̂, sin ψ = r̂ × b̂
        let cos_psi = field.x * rx + field.y * ry;
        let sin_psi = rx * field.y - ry * field.x;
        Some(PairEdge {
            start: self.start,
            centre: self.centre,
            velocity,
            rel: self.rel,
            orbit: Orbit::new(kappa, self.r0, sin_psi, cos_psi),
        })
    }
}

/// The exact motion of two identical agents under one constant planar command.
///
/// The pair forces are equal and opposite, so the centre of mass moves at the constant pull
/// velocity, `c(t) = c₀ + v t`, and the separation `r⃗ = P₁ − P₀` follows its [`Orbit`]. Every
/// query depends only on the start, the command and its own time argument.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairEdge {
    start: [Vec2; 2],
    centre: Vec2,
    velocity: Vec2,
    rel: Vec2,
    orbit: Orbit,
}

impl PairEdge {
    /// The edge from `start` (two agents) under in-plane unit field direction `field`, with
    /// relative-motion constant `kappa` and centre-of-mass velocity `velocity`. `None` when the
    /// agents coincide or a number is not finite (no closed form applies).
    pub fn new(kappa: f64, velocity: Vec2, start: &[Vec2], field: Vec2) -> Option<Self> {
        PairStart::new(start)?.edge(kappa, velocity, field)
    }

    /// The orbit of the separation.
    pub fn orbit(&self) -> &Orbit {
        &self.orbit
    }

    /// The two agents' positions at time `t` (s) into `out`; the start itself at `t ≤ 0`.
    #[inline]
    pub fn at(&self, t: f64, out: &mut [Vec2]) {
        if t <= 0.0 {
            out[..2].copy_from_slice(&self.start);
            return;
        }
        let p = self.orbit.at(t);
        self.place(t, &p, out);
    }

    /// The positions at `t` for orbit point `p` (the orbit at `t`).
    #[inline]
    fn place(&self, t: f64, p: &OrbitPoint, out: &mut [Vec2]) {
        let (c, s) = self.orbit.turn(p);
        let perp = Vec2::new(-self.rel.y, self.rel.x);
        let half = (self.rel * c + perp * s) * (0.5 * p.ratio);
        let centre = self.centre + self.velocity * t;
        out[0] = centre - half;
        out[1] = centre + half;
    }

    /// The centre of mass at time `t` (s): it moves at the constant pull velocity.
    #[inline]
    pub fn centre_at(&self, t: f64) -> Vec2 {
        self.centre + self.velocity * t
    }

    /// The separation at time `t` (BL).
    pub fn separation_at(&self, t: f64) -> f64 {
        if t <= 0.0 {
            return self.orbit.r0();
        }
        self.orbit.separation(&self.orbit.at(t))
    }

    /// The smallest and largest separation over `[0, duration]`. The separation along an orbit
    /// rises to one peak (at `cos²ψ̂ = ⅓`) and then falls, so both come from the ends and the
    /// peak, if the edge passes it.
    pub fn separation_range(&self, duration: f64) -> (f64, f64) {
        let mut out = [Vec2::zeros(); 2];
        self.end_and_range(duration, &mut out)
    }

    /// [`PairEdge::at`] the end of the edge into `out`, and [`PairEdge::separation_range`], from
    /// one evaluation of the orbit.
    pub fn end_and_range(&self, duration: f64, out: &mut [Vec2]) -> (f64, f64) {
        let r0 = self.orbit.r0();
        if duration <= 0.0 {
            out[..2].copy_from_slice(&self.start);
            return (r0, r0);
        }
        let end = self.orbit.at(duration);
        self.place(duration, &end, out);
        self.range_to(&end)
    }

    /// [`PairEdge::end_and_range`] with the [`SpeedSummary`] at the end (that of
    /// [`PairEdge::at_with_speed`] there, bit for bit), from one evaluation of the orbit.
    pub fn end_range_and_speed(
        &self,
        duration: f64,
        out: &mut [Vec2],
    ) -> ((f64, f64), SpeedSummary) {
        if duration <= 0.0 {
            let r0 = self.orbit.r0();
            return ((r0, r0), self.at_with_speed(duration, out));
        }
        let end = self.orbit.at(duration);
        self.place(duration, &end, out);
        (self.range_to(&end), self.summary(&end))
    }

    /// The smallest and largest separation from the start to orbit point `end`.
    #[inline]
    fn range_to(&self, end: &OrbitPoint) -> (f64, f64) {
        let r0 = self.orbit.r0();
        let r1 = self.orbit.separation(end);
        let mut hi = r0.max(r1);
        if let Some(peak) = self.orbit.peak()
            && 3.0 * end.cos * end.cos >= 1.0
        {
            hi = hi.max(peak);
        }
        (r0.min(r1), hi)
    }

    /// The first time in `[0, duration]` at which the separation reaches `r_lo` or `r_hi`
    /// (`Some(0)` if it starts outside `(r_lo, r_hi)`), found to machine precision; `None` if it
    /// stays strictly inside.
    pub fn exit_time(&self, duration: f64, r_lo: f64, r_hi: f64) -> Option<f64> {
        let r0 = self.orbit.r0();
        if r0 <= r_lo || r0 >= r_hi {
            return Some(0.0);
        }
        let (lo, hi) = self.separation_range(duration);
        if lo > r_lo && hi < r_hi {
            return None;
        }
        // r rises to the peak, then falls: r_hi can only be reached on the rise and r_lo only
        // on the fall, and on each part r is monotone, so bisection finds the first crossing
        let crossed = |t: f64| {
            let r = self.separation_at(t);
            r <= r_lo || r >= r_hi
        };
        let rise_end = self.orbit.peak_time().unwrap_or(0.0).min(duration);
        if self.separation_at(rise_end) >= r_hi {
            return Some(bisect(0.0, rise_end, crossed));
        }
        Some(bisect(rise_end, duration, crossed))
    }

    /// [`PairEdge::at`] time `t`, with what bounds the agents' speed there.
    #[inline]
    pub fn at_with_speed(&self, t: f64, out: &mut [Vec2]) -> SpeedSummary {
        let p = if t <= 0.0 {
            out[..2].copy_from_slice(&self.start);
            self.orbit.at(0.0)
        } else {
            let p = self.orbit.at(t);
            self.place(t, &p, out);
            p
        };
        self.summary(&p)
    }

    /// What bounds the agents' speed at orbit point `p`.
    #[inline]
    fn summary(&self, p: &OrbitPoint) -> SpeedSummary {
        let c2 = p.cos * p.cos;
        SpeedSummary {
            shape: (1.0 - 2.0 * c2 + 5.0 * c2 * c2).sqrt(),
            separation: self.orbit.separation(p),
        }
    }

    /// A bound on every agent's speed over an interval (BL/s), from [`SpeedSummary`]s at its
    /// ends: `|v| + |ṙ⃗|/2` with `|ṙ⃗| = κ √(1 − 2cos²ψ + 5cos⁴ψ)/r⁴`. Along an orbit the
    /// separation is smallest at an end of any interval (it rises to one peak, then falls), and
    /// `cos²ψ̂` changes monotonically with the root convex in it, so the ends bound both.
    #[inline]
    pub fn speed_bound(&self, a: &SpeedSummary, b: &SpeedSummary) -> f64 {
        let r = a.separation.min(b.separation);
        let r2 = r * r;
        self.velocity.norm() + 0.5 * self.orbit.kappa() * a.shape.max(b.shape) / (r2 * r2)
    }

    /// Both agents' velocities at time `t` (BL/s).
    pub fn velocities_at(&self, t: f64) -> [Vec2; 2] {
        let p = self.orbit.at(t.max(0.0));
        self.velocities(&p)
    }

    fn velocities(&self, p: &OrbitPoint) -> [Vec2; 2] {
        let (c, s) = self.orbit.turn(p);
        let r0 = self.orbit.r0();
        let rh = (self.rel * c + Vec2::new(-self.rel.y, self.rel.x) * s) / r0;
        let eh = Vec2::new(-rh.y, rh.x);
        let (radial, transverse) = self.orbit.rates(p);
        let half = (rh * radial + eh * transverse) * 0.5;
        [self.velocity - half, self.velocity + half]
    }

    /// The two agents' summed path length over `[0, duration]` (BL): ∫ |Ṗ₀| + |Ṗ₁| dt, taken
    /// over the orbit's own variable (where every point is in closed form, with no time
    /// equation to solve) by adaptive Simpson to [`PATH_TOLERANCE`]. Infinite if the pair
    /// collapses within the edge.
    pub fn path_length(&self, duration: f64) -> f64 {
        self.orbit.integrate(duration, PATH_TOLERANCE, |p| {
            let [a, b] = self.velocities(p);
            a.norm() + b.norm()
        })
    }
}

/// Relative tolerance of [`PairEdge::path_length`].
pub const PATH_TOLERANCE: f64 = 1e-6;

/// The first `t` in `(a, b]` where `crossed` holds, given `crossed(b)` and not `crossed(a)`.
fn bisect(mut a: f64, mut b: f64, crossed: impl Fn(f64) -> bool) -> f64 {
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        if crossed(m) {
            b = m;
        } else {
            a = m;
        }
    }
    b
}
